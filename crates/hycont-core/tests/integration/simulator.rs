//! The event-driven simulator against closed-form hybrid problems.

use crate::common;
use approx::assert_abs_diff_eq;

use common::{Ball, ImpactOscillator};
use hycont_core::{
    Direction, Error, EventAction, EventId, EventSpec, FiniteDifferences, HybridSystem, Mode,
    SampleTimes, Sensitivities, SimulationSettings, Simulator, StopReason,
};
use std::f64::consts::PI;

fn sim() -> Simulator {
    Simulator::new(SimulationSettings::default()).unwrap()
}

#[test]
fn impact_oscillator_impact_times_are_exact() {
    // x'' = -4 x (w = 2): impacts at (j + 1) pi / 2, pre-impact velocity -v0 e^j.
    let (k, e, v0): (f64, f64, f64) = (4.0, 0.8, 1.5);
    let w: f64 = k.sqrt();
    let traj = sim()
        .run(
            &ImpactOscillator { cap: None },
            Mode(0),
            0.0,
            &[0.0, v0],
            &[k, e],
            60.0,
        )
        .unwrap();
    assert_eq!(traj.stop, StopReason::EndReached);
    let n = traj.events.len();
    assert_eq!(n, (60.0 * w / PI).floor() as usize, "number of impacts");
    for (j, ev) in traj.events.iter().enumerate() {
        let t_exact = (j + 1) as f64 * PI / w;
        assert_abs_diff_eq!(ev.t, t_exact, epsilon = 1e-10 * t_exact.max(1.0));
        let v_exact = -v0 * e.powi(j as i32);
        assert_abs_diff_eq!(ev.state_before[1], v_exact, epsilon = 1e-9 * v0);
        assert!((ev.state_after[1] + e * ev.state_before[1]).abs() < 1e-15);
    }
}

#[test]
fn event_location_meets_the_stated_tolerance() {
    // Location error is measured on the numerical solution: at the located time the event
    // function h = x must satisfy |x| <= |x'| * dt with dt = 1e-13 * max(1, t) (the default
    // tolerance, well inside the required 1e-12 relative). The global error against the closed
    // form is the integrator's (rtol 1e-10 over ~130 impacts), checked separately.
    let (k, e, v0) = (1.0, 0.999, 1.0);
    let traj = sim()
        .run(
            &ImpactOscillator { cap: None },
            Mode(0),
            0.0,
            &[0.0, v0],
            &[k, e],
            400.0,
        )
        .unwrap();
    assert_eq!(traj.events.len(), 127);
    for ev in &traj.events {
        let dt_implied = ev.state_before[0].abs() / ev.state_before[1].abs();
        assert!(
            dt_implied <= 1e-13 * ev.t.max(1.0),
            "impact at t = {}: x = {:e} implies a location error of {dt_implied:e}",
            ev.t,
            ev.state_before[0]
        );
        // Located on the post-crossing side (x <= 0), as documented.
        assert!(ev.state_before[0] <= 0.0);
    }
    let worst_global = traj
        .events
        .iter()
        .enumerate()
        .map(|(j, ev)| (ev.t - (j + 1) as f64 * PI).abs() / ev.t)
        .fold(0.0, f64::max);
    assert!(
        worst_global <= 1e-10,
        "global relative impact-time error {worst_global:e}"
    );
}

#[test]
fn bouncing_ball_impacts_and_zeno_rest_time() {
    let (g, e, v0) = (9.81, 0.7, 2.0);
    let traj = sim()
        .run(
            &Ball { zeno_rest: true },
            Mode(0),
            0.0,
            &[0.0, v0],
            &[g, e],
            5.0,
        )
        .unwrap();
    assert_eq!(traj.stop, StopReason::EndReached);
    assert_eq!(traj.mode_final, Mode(1));
    for (k, ev) in traj.events.iter().enumerate() {
        let t_exact = 2.0 * v0 / g * (1.0 - e.powi(k as i32 + 1)) / (1.0 - e);
        // The ball is polynomial, so DOP853 is exact and only the location errors (1e-13 each,
        // carried from impact to impact) remain.
        assert_abs_diff_eq!(ev.t, t_exact, epsilon = 1e-11);
    }
    let t_rest = 2.0 * v0 / (g * (1.0 - e));
    let z = &traj.zeno[0];
    // Switched within the horizon (1e-9) of the accumulation point, which is predicted exactly.
    assert!(
        t_rest - z.t <= 1.1e-9 && z.t < t_rest,
        "switch at {} vs {t_rest}",
        z.t
    );
    assert_abs_diff_eq!(z.t_accumulation, t_rest, epsilon = 1e-10);
    assert_eq!(traj.state_final, vec![0.0, 0.0]);
}

#[test]
fn zeno_without_transition_stops() {
    let (g, e, v0) = (9.81, 0.5, 1.0);
    let traj = sim()
        .run(
            &Ball { zeno_rest: false },
            Mode(0),
            0.0,
            &[0.0, v0],
            &[g, e],
            5.0,
        )
        .unwrap();
    assert!(
        matches!(traj.stop, StopReason::ZenoAccumulation { .. }),
        "{:?}",
        traj.stop
    );
    assert!(traj.t_final < 2.0 * v0 / (g * (1.0 - e)));
}

#[test]
fn terminal_event_stops_at_the_right_time() {
    // x = (v0 / w) sin(w t) reaches cap at t = asin(cap w / v0) / w.
    let (k, v0, cap) = (1.0, 1.0, 0.5);
    let mut s = Simulator::new(SimulationSettings::default().rtol(1e-13).atol(1e-14)).unwrap();
    let traj = s
        .run(
            &ImpactOscillator { cap: Some(cap) },
            Mode(0),
            0.0,
            &[0.0, v0],
            &[k, 0.5],
            10.0,
        )
        .unwrap();
    let t_exact = (cap / v0).asin();
    match traj.stop {
        StopReason::TerminalEvent { event, t } => {
            assert_eq!(event, EventId(1));
            assert_abs_diff_eq!(t, t_exact, epsilon = 1e-12);
        }
        other => panic!("expected a terminal event, got {other:?}"),
    }
    assert_abs_diff_eq!(traj.state_final[0], cap, epsilon = 1e-12);
}

#[test]
fn stroboscopic_samples_use_dense_output() {
    // Harmonic oscillator sampled every 0.7: compare to sin/cos, and check that sampling does not
    // change the step sequence (same number of accepted steps as without samples).
    let settings = SimulationSettings::default()
        .rtol(1e-13)
        .atol(1e-14)
        .samples(SampleTimes::new(0.0, 0.7));
    let mut s = Simulator::new(settings).unwrap();
    let sys = ImpactOscillator { cap: None };
    // Start at x = 1, v = 0: x = cos t never reaches the wall before t = pi/2; integrate to 1.5.
    let traj = s
        .run(&sys, Mode(0), 0.0, &[1.0, 0.0], &[1.0, 0.5], 1.5)
        .unwrap();
    assert_eq!(traj.samples.len(), 3); // t = 0, 0.7, 1.4
    for (t, _, x) in traj.samples.iter() {
        assert_abs_diff_eq!(x[0], t.cos(), epsilon = 1e-12);
        assert_abs_diff_eq!(x[1], -t.sin(), epsilon = 1e-12);
    }
    let mut plain_sim =
        Simulator::new(SimulationSettings::default().rtol(1e-13).atol(1e-14)).unwrap();
    let plain = plain_sim
        .run(&sys, Mode(0), 0.0, &[1.0, 0.0], &[1.0, 0.5], 1.5)
        .unwrap();
    assert_eq!(plain.stats.steps, traj.stats.steps);
}

/// A system with two events inside one long step: x' = 1, identity jumps at x = 0.3 and 0.6
/// (the second listed first), to check time ordering.
struct Ramp;
impl HybridSystem for Ramp {
    fn state_dim(&self) -> usize {
        1
    }
    fn parameter_names(&self) -> &[&'static str] {
        &[]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "ramp"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[EventId(1), EventId(0)]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "level",
            direction: Direction::Rising,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, _: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = 1.0;
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[0] - [0.3, 0.6][e.0]
    }
}

#[test]
fn several_events_in_one_step_are_handled_in_time_order() {
    let settings = SimulationSettings::default().h_initial(1.0);
    let mut s = Simulator::new(settings).unwrap();
    let traj = s.run(&Ramp, Mode(0), 0.0, &[0.0], &[], 1.0).unwrap();
    let times: Vec<f64> = traj.events.iter().map(|e| e.t).collect();
    assert_eq!(traj.events.len(), 2, "{times:?}");
    assert_eq!(traj.events[0].event, EventId(0));
    assert!((times[0] - 0.3).abs() < 1e-13 && (times[1] - 0.6).abs() < 1e-13);
}

#[test]
fn sensitivities_match_finite_differences_across_impacts() {
    let sys = ImpactOscillator { cap: None };
    let (p, x0, t1) = ([2.0, 0.7], [0.3, 1.1], 12.3);
    let traj = sim()
        .run_with_sensitivities(
            &sys,
            Mode(0),
            0.0,
            &x0,
            &p,
            t1,
            Sensitivities::StateAndParameters,
        )
        .unwrap();
    assert!(traj.events.len() >= 4, "crosses several impacts");
    let sens = traj.sensitivities.unwrap();
    let flow = |x0: &[f64], p: &[f64]| {
        sim()
            .run(&sys, Mode(0), 0.0, x0, p, t1)
            .unwrap()
            .state_final
    };
    let h = 1e-6;
    for j in 0..2 {
        let (mut xp, mut xm) = (x0, x0);
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (flow(&xp, &p), flow(&xm, &p));
        for i in 0..2 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            assert_abs_diff_eq!(
                sens.state_entry(i, j),
                fd,
                epsilon = 1e-6 * (1.0 + fd.abs())
            );
        }
    }
    let params = sens.params.unwrap();
    for q in 0..2 {
        let (mut pp, mut pm) = (p, p);
        pp[q] += h;
        pm[q] -= h;
        let (fp, fm) = (flow(&x0, &pp), flow(&x0, &pm));
        for i in 0..2 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            let an = params[i + 2 * q];
            assert_abs_diff_eq!(an, fd, epsilon = 1e-6 * (1.0 + fd.abs()));
        }
    }
}

#[test]
fn finite_difference_wrapper_gives_the_same_sensitivities() {
    let sys = ImpactOscillator { cap: None };
    let (p, x0, t1) = ([2.0, 0.7], [0.3, 1.1], 5.0);
    let exact = sim()
        .run_with_sensitivities(&sys, Mode(0), 0.0, &x0, &p, t1, Sensitivities::State)
        .unwrap()
        .sensitivities
        .unwrap();
    let fd = sim()
        .run_with_sensitivities(
            &FiniteDifferences::new(ImpactOscillator { cap: None }),
            Mode(0),
            0.0,
            &x0,
            &p,
            t1,
            Sensitivities::State,
        )
        .unwrap()
        .sensitivities
        .unwrap();
    for (a, b) in exact.state.iter().zip(&fd.state) {
        assert_abs_diff_eq!(a, b, epsilon = 1e-7 * (1.0 + a.abs()));
    }
}

#[test]
fn bad_input_is_an_error_naming_the_value() {
    let sys = ImpactOscillator { cap: None };
    let mut s = sim();
    let e = s
        .run(&sys, Mode(0), 0.0, &[f64::NAN, 1.0], &[1.0, 0.5], 1.0)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::NonFinite {
                what: "initial state",
                index: 0,
                ..
            }
        ),
        "{e}"
    );
    let e = s
        .run(&sys, Mode(0), 0.0, &[0.0], &[1.0, 0.5], 1.0)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::DimensionMismatch {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{e}"
    );
    let e = s
        .run(&sys, Mode(0), 0.0, &[0.0, 1.0], &[1.0], 1.0)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::DimensionMismatch {
                what: "parameters",
                ..
            }
        ),
        "{e}"
    );
    let e = s
        .run(&sys, Mode(0), 2.0, &[0.0, 1.0], &[1.0, 0.5], 1.0)
        .unwrap_err();
    assert!(matches!(e, Error::InvalidTimeSpan { .. }), "{e}");
    let e = s
        .run(&sys, Mode(3), 0.0, &[0.0, 1.0], &[1.0, 0.5], 1.0)
        .unwrap_err();
    assert!(matches!(e, Error::InvalidMode { .. }), "{e}");
    for settings in [
        SimulationSettings::default().rtol(0.0),
        SimulationSettings::default().atol(-1.0),
        SimulationSettings::default().h_max(0.0),
        SimulationSettings::default().samples(SampleTimes::new(0.0, -1.0)),
    ] {
        let e = Simulator::new(settings).unwrap_err();
        assert!(matches!(e, Error::InvalidSetting { .. }), "{e}");
    }
}

/// x' = -1 with a vector field that is NaN for x < 0 (sqrt).
struct Sqrt;
impl HybridSystem for Sqrt {
    fn state_dim(&self) -> usize {
        1
    }
    fn parameter_names(&self) -> &[&'static str] {
        &[]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "m"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        unreachable!()
    }
    fn vector_field(&self, _: Mode, x: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = -1.0 + 0.0 * x[0].sqrt();
    }
    fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
        unreachable!()
    }
}

#[test]
fn nan_mid_run_ends_with_an_error_saying_when_and_where() {
    let e = sim()
        .run(&Sqrt, Mode(0), 0.0, &[1.0], &[], 5.0)
        .unwrap_err();
    match &e {
        Error::NonFiniteVectorField { t, state, mode, .. } => {
            assert!(*t > 0.9 && *t < 5.0, "t = {t}");
            assert!(state[0] < 0.0);
            assert_eq!(*mode, Mode(0));
        }
        other => panic!("unexpected error {other}"),
    }
    assert!(e.to_string().contains("at t ="), "{e}");
}

#[test]
fn step_limit_stops_gracefully() {
    let settings = SimulationSettings::default().max_steps(10);
    let traj = Simulator::new(settings)
        .unwrap()
        .run(
            &ImpactOscillator { cap: None },
            Mode(0),
            0.0,
            &[0.0, 1.0],
            &[1.0, 0.5],
            100.0,
        )
        .unwrap();
    assert!(matches!(traj.stop, StopReason::StepLimit { .. }));
    assert!(traj.t_final < 100.0);
}

#[test]
fn sensitivities_of_some_parameters_equal_those_columns_of_all() {
    use hycont_core::ParamSet;
    let sys = ImpactOscillator { cap: None };
    let (p, x0, t1) = ([2.0, 0.7], [0.3, 1.1], 12.3);
    // With the error controlled on the state only, the step sequence does not depend on which
    // sensitivities are carried, so the columns must agree exactly.
    let run = |which| {
        Simulator::new(SimulationSettings::default().sensitivities_in_error(false))
            .unwrap()
            .run_with_sensitivities(&sys, Mode(0), 0.0, &x0, &p, t1, which)
            .unwrap()
    };
    let all = run(Sensitivities::StateAndParameters);
    let all_sens = all.sensitivities.unwrap();
    let all_params = all_sens.params.unwrap();
    for q in 0..2 {
        let set = ParamSet::EMPTY.with(q).unwrap();
        let some = run(Sensitivities::StateAndSomeParameters(set));
        // Same steps (the error is controlled on the state), so the same numbers.
        assert_eq!(some.state_final, all.state_final);
        let sens = some.sensitivities.unwrap();
        assert_eq!(sens.state, all_sens.state);
        let params = sens.params.unwrap();
        for k in 0..2 {
            for i in 0..2 {
                let expected = if k == q { all_params[i + 2 * k] } else { 0.0 };
                assert_eq!(params[i + 2 * k], expected, "column {k} with {set:?}");
            }
        }
    }
    // No parameters: the state sensitivities and zero parameter columns.
    let none = run(Sensitivities::StateAndSomeParameters(ParamSet::EMPTY));
    let sens = none.sensitivities.unwrap();
    assert_eq!(sens.state, all_sens.state);
    assert!(sens.params.unwrap().iter().all(|&v| v == 0.0));
}

/// A run split into pieces by [`Simulator::resume`] is the same motion (the impact oscillator's
/// closed form: impacts at $t_j = (j + 1)\pi/w$, flight $j$ is $x = (v_0 e^j / w)
/// \sin(w (t - t_j))$), and each piece starts with the step size the last one proposed rather
/// than a new estimate (which costs right-hand side evaluations).
#[test]
fn resumed_pieces_continue_the_motion_without_new_step_estimates() {
    let (k, e, v0): (f64, f64, f64) = (4.0, 0.8, 1.5);
    let w = k.sqrt();
    let system = ImpactOscillator { cap: None };
    let (pieces, t_end) = (20, 6.0);
    let (mut resumer, mut fresh) = (sim(), sim());
    let first = resumer
        .run(
            &system,
            Mode(0),
            0.0,
            &[0.0, v0],
            &[k, e],
            t_end / pieces as f64,
        )
        .unwrap();
    let (mut traj, mut fresh_traj) = (first.clone(), first);
    let (mut resumed_evals, mut fresh_evals) = (0, 0);
    for i in 2..=pieces {
        let t_i = t_end * i as f64 / pieces as f64;
        assert!(traj.next_step > 0.0);
        traj = resumer.resume(&system, &traj, &[k, e], t_i).unwrap();
        fresh_traj = fresh
            .run(
                &system,
                fresh_traj.mode_final,
                fresh_traj.t_final,
                &fresh_traj.state_final,
                &[k, e],
                t_i,
            )
            .unwrap();
        resumed_evals += traj.stats.rhs_evaluations;
        fresh_evals += fresh_traj.stats.rhs_evaluations;
    }
    assert_eq!(traj.t_final, t_end);
    // Closed form at t_end: the flight after the last impact before it.
    let j = (t_end * w / PI).floor() as i32 - 1;
    let t_j = f64::from(j + 1) * PI / w;
    let x = v0 * e.powi(j + 1) / w * (w * (t_end - t_j)).sin();
    let v = v0 * e.powi(j + 1) * (w * (t_end - t_j)).cos();
    assert_abs_diff_eq!(traj.state_final[0], x, epsilon = 1e-8);
    assert_abs_diff_eq!(traj.state_final[1], v, epsilon = 1e-8);
    assert!(
        resumed_evals < fresh_evals,
        "resumed pieces {resumed_evals} evaluations, fresh runs {fresh_evals}"
    );
}
