//! The bouncing ball on a vibrating table (Holmes 1982) through the public API, against closed
//! forms.
//!
//! # The closed forms
//! In table coordinates (`examples/vibrating_table/model.rs`) the ball's height obeys
//! $\ddot z = -g + a\omega^2 \sin(\theta_0 + \omega t)$ between impacts. A period-1 orbit has one
//! impact per forcing period $T = 2\pi/\omega$, at phase $\theta_0$, with relative velocities
//! $w^+ = -e\,w^-$ after and $w^-$ before it. Over a period the forcing's velocity contribution
//! integrates to zero, so $w^- = w^+ - gT$, hence
//! $$w^- = -\frac{gT}{1+e}, \qquad w^+ = \frac{e\,gT}{1+e};$$
//! and $z(T) = w^+ T - gT^2/2 + a\omega T \cos\theta_0 = 0$ gives
//! $$a\omega^2 \cos\theta_0 = \frac{\pi g (1-e)}{1+e}.$$
//! Orbits exist for $a\omega^2 \ge \pi g(1-e)/(1+e)$: the existence fold (SN) is at
//! $\cos\theta_0 = 1$. Linearising the impact map $(\theta, w^+) \mapsto (\theta', w^{+\prime})$
//! (implicit next impact time, $\partial_\tau z = w^-$) gives $\det = e^2$ and trace
//! $1 + e^2 - \kappa(1 + e)$ with $\kappa = a\omega^2 \sin\theta_0 (1+e)/g$; a multiplier is $-1$
//! (PD) where $1 + \mathrm{tr} + e^2 = 0$, i.e. $a\omega^2\sin\theta_0 = 2g(1+e^2)/(1+e)^2$, so
//! $$a_\mathrm{PD}\,\omega^2 = g\sqrt{\frac{4(1+e^2)^2}{(1+e)^4} + \frac{\pi^2(1-e)^2}{(1+e)^2}},
//! \qquad a_\mathrm{SN}\,\omega^2 = \frac{\pi g(1-e)}{1+e},$$
//! and the orbits with $\sin\theta_0 > 0$ are stable between them. The monodromy adds the flow
//! direction's multiplier 1.

use crate::model_vibrating_table as model;

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{
    CurveCondition, CurveSpec, Diagram, DiagramBranchId, DiagramSettings, Error as ContError,
    Label, OrbitBranch, OrbitRun, RunDirection, SpecialKind, SwitchOutcome,
};
use hycont::orbit::{
    CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentValue, ShootingSettings,
    solve_shooting,
};
use hycont::problem::NewtonSettings;
use hycont::{HybridJacobians, ParamId, SimulationSettings, check_derivatives};
use model::{A, FLIGHT, IMPACT, OMEGA, Table, WRAP};
use proptest::prelude::*;
use std::f64::consts::PI;

const E: f64 = 0.5;
const G: f64 = 1.0;

fn a_fold(omega: f64) -> f64 {
    PI * G * (1.0 - E) / ((1.0 + E) * omega * omega)
}

fn a_pd(omega: f64) -> f64 {
    let s = 4.0 * (1.0 + E * E).powi(2) / (1.0 + E).powi(4)
        + PI * PI * (1.0 - E).powi(2) / (1.0 + E).powi(2);
    G * s.sqrt() / (omega * omega)
}

/// The stable period-1 orbit at amplitude `a` (impact phase in (0, pi/2)), from its closed-form
/// post-impact state, integrated along the signature [flight to the phase wrap, flight to the
/// impact].
fn orbit(a: f64, omega: f64) -> PeriodicOrbit {
    model::period_one(&Table, [a, omega, E, G]).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The model written once (`TableModel`) differentiated automatically: every Jacobian
    /// equal to the hand-coded ones below to rounding.
    #[test]
    fn automatic_jacobians_equal_the_hand_coded_ones(z in 0.0f64..2.0, w in -3.0f64..3.0,
                                                     th in -3.0f64..3.0, a in 0.5f64..2.0) {
        let (x, p) = ([z, w, th], [a, 1.1, E, G]);
        let ad = hycont::AutoDiff::new(model::TableModel);
        let (mut j1, mut j2, mut p1, mut p2) = ([0.0; 9], [0.0; 9], [0.0; 12], [0.0; 12]);
        ad.vector_field_jacobian(FLIGHT, &x, &p, &mut j1, Some(&mut p1));
        Table.vector_field_jacobian(FLIGHT, &x, &p, &mut j2, Some(&mut p2));
        let same = |u: &[f64], v: &[f64]| u.iter().zip(v).all(|(a, b)| (a - b).abs() <= 1e-15 * (1.0 + b.abs()));
        prop_assert!(same(&j1, &j2) && same(&p1, &p2));
        for e in [IMPACT, WRAP] {
            ad.reset_jacobian(e, &x, &p, &mut j1, Some(&mut p1));
            Table.reset_jacobian(e, &x, &p, &mut j2, Some(&mut p2));
            prop_assert!(same(&j1, &j2) && same(&p1, &p2));
            let (mut g1, mut g2, mut q1, mut q2) = ([0.0; 3], [0.0; 3], [0.0; 4], [0.0; 4]);
            ad.event_gradient(e, &x, &p, &mut g1, Some(&mut q1));
            Table.event_gradient(e, &x, &p, &mut g2, Some(&mut q2));
            prop_assert!(same(&g1, &g2) && same(&q1, &q2));
        }
    }

    /// The analytic Jacobians against central differences.
    #[test]
    fn jacobians_match_differences(z in 0.0f64..2.0, w in -3.0f64..3.0, th in -3.0f64..3.0,
                                   a in 0.5f64..2.0, om in 0.5f64..2.0) {
        let check = check_derivatives(&Table, FLIGHT, &[z, w, th], &[a, om, E, G]).unwrap();
        prop_assert!(check.max_error() < 1e-7, "{check:?}");
    }
}

#[test]
fn period_one_orbits_match_the_closed_form() {
    let (a, omega) = (1.3, 1.0);
    let sol = solve_shooting(
        &Table,
        &orbit(a, omega),
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    let theta0 = (a_fold(omega) / a).acos();
    let o = &sol.orbit;
    assert_abs_diff_eq!(o.starts[0][2], theta0, epsilon = 1e-10);
    assert_abs_diff_eq!(
        o.starts[0][1],
        E * G * 2.0 * PI / (1.0 + E),
        epsilon = 1e-10
    );
    assert_abs_diff_eq!(o.period(), 2.0 * PI / omega, epsilon = 1e-10);
    // Multipliers: 1 (trivial), and the roots of l^2 - tr l + e^2.
    let kappa = a * omega * omega * theta0.sin() * (1.0 + E) / G;
    let tr = 1.0 + E * E - kappa * (1.0 + E);
    let disc = tr * tr - 4.0 * E * E;
    let nontrivial: Vec<(f64, f64)> = sol.floquet.nontrivial().collect();
    assert_eq!(nontrivial.len(), 2);
    let (sum, product) = if disc < 0.0 {
        (
            2.0 * nontrivial[0].0,
            nontrivial[0].0.hypot(nontrivial[0].1).powi(2),
        )
    } else {
        (
            nontrivial[0].0 + nontrivial[1].0,
            nontrivial[0].0 * nontrivial[1].0,
        )
    };
    assert_abs_diff_eq!(sum, tr, epsilon = 1e-9);
    assert_abs_diff_eq!(product, E * E, epsilon = 1e-9);
}

/// The amplitude branch through `a = 1.3` at `omega = 1`, both ways over `[0.9, 1.8]`.
fn amplitude_run(method: OrbitMethod) -> (OrbitRun<'static, Table>, OrbitBranch) {
    let mut run = OrbitRun::new(&Table, A).unwrap();
    run.method(method).bounds(0.9, 1.8);
    let v_impact = run
        .add_measure("impact_velocity", SegmentValue::end(1, 1))
        .unwrap();
    run.add_user_points(A, [1.2]).unwrap();
    let phase = run
        .add_measure("impact_phase", SegmentValue::start(0, 2))
        .unwrap();
    run.add_event(phase, 0.5, SpecialKind::Custom(Label::new("PH").unwrap()))
        .unwrap();
    let branch = run
        .run("period-1", &orbit(1.3, 1.0), RunDirection::Both)
        .unwrap();
    // The impact velocity is -g T / (1 + e) on every orbit of the branch.
    for p in &branch.branch.points {
        assert_abs_diff_eq!(p[v_impact], -2.0 * PI / 1.5, epsilon = 1e-8);
    }
    (run, branch)
}

#[test]
fn the_fold_and_the_period_doubling_are_at_their_closed_form_amplitudes() {
    let (_, b) = amplitude_run(OrbitMethod::Shooting(ShootingSettings::default()));
    let sn = b.special(SpecialKind::Fold).next().expect("a fold");
    let pd = b.special(SpecialKind::PeriodDoubling).next().expect("a PD");
    assert!(sn.located && pd.located);
    assert_abs_diff_eq!(sn.point[A], a_fold(1.0), epsilon = 1e-8);
    assert_abs_diff_eq!(pd.point[A], a_pd(1.0), epsilon = 1e-8);
    // UZ at a = 1.2 on both sheets (stable, impact phase > 0, and unstable), at the closed
    // form's phases.
    let uz: Vec<f64> = b
        .special(SpecialKind::UserPoint)
        .map(|s| b.orbit_of(&s.point).unwrap().starts[0][2])
        .collect();
    let theta = (a_fold(1.0) / 1.2).acos();
    assert_eq!(uz.len(), 2, "{uz:?}");
    assert!(uz.iter().any(|t| (t - theta).abs() < 1e-8));
    assert!(uz.iter().any(|t| (t + theta).abs() < 1e-8));
    // The user event where the impact phase is 0.5: a = a_SN / cos(0.5).
    let ph = b
        .special(SpecialKind::Custom(Label::new("PH").unwrap()))
        .next()
        .expect("PH");
    assert_abs_diff_eq!(ph.point[A], a_fold(1.0) / 0.5f64.cos(), epsilon = 1e-8);
    // Stable exactly between SN and PD on the sheet with phase > 0.
    for p in &b.branch.points {
        let phase = b.orbit_of(p).unwrap().starts[0][2];
        let inside = phase > 1e-6 && p[A] < a_pd(1.0) - 1e-6;
        if inside || p[A] > a_pd(1.0) + 1e-6 || phase < -1e-6 {
            assert_eq!(p.stable(), inside, "a = {}, phase {phase}", p[A]);
        }
    }
}

/// The example's configuration: derivatives by central differences (`FiniteDifferences`)
/// instead of the analytic ones; the located points are as accurate.
#[test]
fn finite_difference_derivatives_reach_the_closed_forms() {
    let fd = hycont::FiniteDifferences::new(Table);
    let mut run = OrbitRun::new(&fd, A).unwrap();
    run.bounds(0.9, 1.8);
    let b = run.run("fd", &orbit(1.3, 1.0), RunDirection::Both).unwrap();
    let at = |k| b.special(k).next().unwrap().point[A];
    assert_abs_diff_eq!(at(SpecialKind::Fold), a_fold(1.0), epsilon = 1e-8);
    assert_abs_diff_eq!(at(SpecialKind::PeriodDoubling), a_pd(1.0), epsilon = 1e-8);
}

#[test]
fn collocation_agrees_with_the_closed_form() {
    let (_, b) = amplitude_run(OrbitMethod::Collocation(CollocationSettings::default()));
    let sn = b.special(SpecialKind::Fold).next().unwrap();
    let pd = b.special(SpecialKind::PeriodDoubling).next().unwrap();
    // Collocation's discretisation error at NTST 20, NCOL 4 is below 1e-9 here (the located
    // points are exact for the discretised problem).
    assert_abs_diff_eq!(sn.point[A], a_fold(1.0), epsilon = 1e-8);
    assert_abs_diff_eq!(pd.point[A], a_pd(1.0), epsilon = 1e-8);
}

#[test]
fn switching_at_the_period_doubling_gives_period_two_orbits() {
    let (mut run, b) = amplitude_run(OrbitMethod::Shooting(ShootingSettings::default()));
    let pd = b
        .special(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .point
        .label;
    let p2 = run.switch_at("period-2", &b, pd, RunDirection::Up).unwrap();
    assert!(p2.branch.ended_cleanly(), "{:?}", p2.branch.end);
    // It starts at the doubled PD orbit and its orbits last two forcing periods with two
    // impacts at different phases.
    assert_abs_diff_eq!(p2.branch.points[0][A], a_pd(1.0), epsilon = 1e-8);
    let far = p2.branch.points.last().unwrap();
    let o = p2.orbit_of(far).unwrap();
    assert_abs_diff_eq!(o.period(), 4.0 * PI, epsilon = 1e-8);
    let impacts: Vec<f64> = o.starts.iter().step_by(2).map(|x| x[2]).collect();
    assert!((impacts[0] - impacts[1]).abs() > 1e-3, "{impacts:?}");
    assert!(far[A] > a_pd(1.0) + 0.01);
}

#[test]
fn fold_and_period_doubling_curves_follow_a_omega_squared() {
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let (mut run, b) = amplitude_run(method);
        for (kind, closed_form) in [
            (SpecialKind::PeriodDoubling, a_pd as fn(f64) -> f64),
            (SpecialKind::Fold, a_fold),
        ] {
            let label = b.special(kind).next().unwrap().point.label;
            let spec = CurveSpec::new(OMEGA)
                .bounds(0.8, 1.25)
                .user_points(OMEGA, [0.95, 1.05]);
            let c = run.curve_at("curve", &b, label, &spec).unwrap();
            assert_eq!(c.second, Some(OMEGA));
            let uz: Vec<_> = c.special(SpecialKind::UserPoint).collect();
            assert_eq!(uz.len(), 2, "{kind}: {:?}", c.branch.special_points);
            for s in uz {
                assert_abs_diff_eq!(s.point[A], closed_form(s.point[OMEGA]), epsilon = 1e-8);
            }
            for p in &c.branch.points {
                assert_abs_diff_eq!(p[A], closed_form(p[OMEGA]), epsilon = 1e-8);
            }
        }
    }
}

/// A curve saved (and read back from JSON) continues from its end point with wider bounds,
/// on the same closed form `a = c / omega^2`, with its condition recorded; a branch, or another
/// second parameter, is refused.
#[test]
fn a_saved_curve_continues_from_its_end() {
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let (mut run, b) = amplitude_run(method);
        let pd = b
            .special(SpecialKind::PeriodDoubling)
            .next()
            .unwrap()
            .point
            .label;
        let short = run
            .curve_at("pd", &b, pd, &CurveSpec::new(OMEGA).bounds(0.9, 1.1))
            .unwrap();
        let short = OrbitBranch::from_json(&short.to_json().unwrap()).unwrap();
        assert_eq!(short.condition, Some(CurveCondition::PeriodDoubling));
        let top = short
            .special(SpecialKind::EndPoint)
            .max_by(|x, y| x.point[OMEGA].total_cmp(&y.point[OMEGA]))
            .unwrap();
        assert_abs_diff_eq!(top.point[OMEGA], 1.1, epsilon = 1e-9);
        let spec = CurveSpec::new(OMEGA).bounds(0.8, 1.25);
        let longer = run
            .curve_from("pd", &short, top.point.label, &spec)
            .unwrap();
        assert_eq!(longer.condition, Some(CurveCondition::PeriodDoubling));
        let reach = longer
            .branch
            .points
            .iter()
            .map(|p| p[OMEGA])
            .fold(f64::NEG_INFINITY, f64::max);
        assert_abs_diff_eq!(reach, 1.25, epsilon = 1e-9);
        for p in &longer.branch.points {
            assert_abs_diff_eq!(p[A], a_pd(p[OMEGA]), epsilon = 1e-8);
        }
        assert!(run.curve_from("x", &b, pd, &spec).is_err(), "a branch");
        let other = CurveSpec::new(ParamId(2));
        assert!(
            run.curve_from("x", &short, top.point.label, &other)
                .is_err()
        );
    }
}

#[test]
fn a_saved_branch_restarts_at_a_label() {
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let (mut run, b) = amplitude_run(method);
        let text = b.to_json().unwrap();
        let saved = OrbitBranch::from_json(&text).unwrap();
        assert_eq!(saved, b);
        let uz = saved
            .special(SpecialKind::UserPoint)
            .find(|s| saved.orbit_of(&s.point).unwrap().starts[0][2] > 0.0)
            .unwrap()
            .point
            .label;
        // Fresh runs (as in another process): by the same method the saved discretisation (a
        // collocation mesh) is kept; by the other the point's orbit is discretised afresh.
        let other = match method {
            OrbitMethod::Shooting(_) => OrbitMethod::Collocation(CollocationSettings::default()),
            OrbitMethod::Collocation(_) => OrbitMethod::Shooting(ShootingSettings::default()),
        };
        for (by, same) in [(method, true), (other, false)] {
            let mut fresh = OrbitRun::new(&Table, A).unwrap();
            fresh.method(by).bounds(0.9, 1.8);
            let again = fresh
                .restart("again", &saved, uz, Some(RunDirection::Up))
                .unwrap();
            let pd = again.first(SpecialKind::PeriodDoubling).unwrap();
            assert_abs_diff_eq!(pd.point[A], a_pd(1.0), epsilon = 1e-8);
            let kept = again.discretisation == saved.discretisation;
            assert_eq!(kept, same, "{method:?} restarted by {by:?}");
        }
        let again = run
            .restart("again", &saved, uz, Some(RunDirection::Up))
            .unwrap();
        assert_eq!(again.discretisation, saved.discretisation);
    }
}

/// An orbit read off a simulation, rotated to start after the impact: its last segment ends at
/// the impact, its values are the closed form's, and the impact velocity is `-g T / (1 + e)`.
#[test]
fn a_simulated_orbit_starts_after_a_chosen_event() {
    use hycont::orbit::Measure;
    let p = [1.3, 1.0, E, G];
    let mut sim = hycont::Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(&Table, FLIGHT, 0.0, &[0.0, 2.0, 0.0], &p, 300.0)
        .unwrap();
    let read = PeriodicOrbit::from_simulation(&Table, &traj, &p, 1e-8).unwrap();
    let orbit = read.starting_after(&Table, IMPACT).unwrap();
    let ends: Vec<_> = orbit.signature.segments().iter().map(|s| s.end).collect();
    assert_eq!(ends, [SegmentEnd::Event(WRAP), SegmentEnd::Event(IMPACT)]);
    assert_abs_diff_eq!(orbit.period(), read.period(), epsilon = 1e-12);
    assert_abs_diff_eq!(
        orbit.starts[0][2],
        (a_fold(1.0) / 1.3).acos(),
        epsilon = 1e-6
    );
    let v = SegmentValue::end(1, 1).evaluate(&Table, &orbit).unwrap();
    assert_abs_diff_eq!(v, -2.0 * PI * G / (1.0 + E), epsilon = 1e-6);
    // The orbit started after the wrap instead, and an event no segment ends at.
    let other = orbit.starting_after(&Table, WRAP).unwrap();
    assert_eq!(other.signature.segments()[1].end, SegmentEnd::Event(WRAP));
    assert!(orbit.starting_after(&Table, hycont::EventId(5)).is_err());
}

#[test]
fn bad_input_is_a_typed_error() {
    assert!(matches!(
        OrbitRun::new(&Table, ParamId(9)),
        Err(ContError::NoSuchQuantity { .. })
    ));
    let (mut run, b) = amplitude_run(OrbitMethod::Shooting(ShootingSettings::default()));
    assert!(matches!(
        run.switch_at("x", &b, 100_000, RunDirection::Up),
        Err(ContError::NoSuchLabel { label: 100_000, .. })
    ));
    let sn = b.first(SpecialKind::Fold).unwrap().point.label;
    assert!(matches!(
        b.first(SpecialKind::Torus),
        Err(ContError::NoSuchSpecialPoint { ref kind, .. }) if kind == "TR"
    ));
    assert!(matches!(
        run.switch_at("x", &b, sn, RunDirection::Up),
        Err(ContError::WrongSpecialPoint { .. })
    ));
    assert!(run.add_user_points(ParamId(7), [1.0]).is_err());
    assert!(run.add_event(A, f64::NAN, SpecialKind::UserPoint).is_err());
    assert!(run.add_event(A, 1.0, SpecialKind::Fold).is_err());
    assert!(Label::new("SN").is_err());
    let mut guess = orbit(1.3, 1.0);
    guess.starts[0][1] = f64::NAN;
    let err = run.run("nan", &guess, RunDirection::Up).unwrap_err();
    assert!(err.to_string().contains("NaN"), "{err}");
    let curve = CurveSpec::new(ParamId(11));
    assert!(run.curve_at("c", &b, sn, &curve).is_err());
}

/// The diagram from the period-1 orbit in `a` (one call): the period-1 branch's PD at its
/// closed form, the period-2 branch switched on there, its own period doubling to period 4,
/// then period 8, down the cascade to the depth asked for, each generation's orbits twice as
/// long; every doubling located with a multiplier -1, at the same amplitude by both
/// discretisations (each locates the points of its own discretised problem; their
/// discretisation errors here are below 1e-9).
#[test]
fn a_diagram_follows_the_period_doubling_cascade() {
    let diagram = |method| {
        let mut run = OrbitRun::new(&Table, A).unwrap();
        run.method(method).bounds(0.9, 2.5);
        let settings = DiagramSettings {
            depth: 3,
            ..DiagramSettings::default()
        };
        run.diagram("period-1", &orbit(1.3, 1.0), &settings)
            .unwrap()
    };
    let doublings = |d: &Diagram| -> Vec<f64> {
        d.switches
            .iter()
            .filter(|r| r.kind == SpecialKind::PeriodDoubling)
            .map(|r| r.parameter)
            .collect()
    };
    let d = diagram(OrbitMethod::Shooting(ShootingSettings::default()));
    // A chain: each branch switched on at its parent's doubling, each period twice the last.
    assert_eq!(d.branches.len(), 4);
    for (k, b) in d.branches.iter().enumerate() {
        assert_eq!(b.depth, k);
        assert_eq!(b.origin.map(|o| o.0), k.checked_sub(1).map(DiagramBranchId));
        let period = b
            .branch
            .orbit_of(&b.branch.branch.points[1])
            .unwrap()
            .period();
        assert_abs_diff_eq!(period, 2.0 * PI * f64::from(1 << k), epsilon = 1e-8);
        for s in b.branch.special(SpecialKind::PeriodDoubling) {
            let (re, im) = s.critical.expect("a PD's multiplier");
            assert_abs_diff_eq!(re, -1.0, epsilon = 1e-6);
            assert_abs_diff_eq!(im, 0.0, epsilon = 1e-6);
        }
    }
    let pd = doublings(&d);
    assert_eq!(pd.len(), 4, "{:?}", d.switches);
    assert_abs_diff_eq!(pd[0], a_pd(1.0), epsilon = 1e-8);
    assert!(pd.windows(2).all(|w| w[1] > w[0]), "{pd:?}");
    assert_eq!(d.switches[3].outcome, SwitchOutcome::DepthLimit);
    // One cascade through the four branches; its intervals shrink (by about Feigenbaum's 4.67
    // here).
    let cascades = d.cascades();
    assert_eq!(cascades.len(), 1);
    assert_eq!(cascades[0].doublings, pd);
    assert_eq!(cascades[0].branches.len(), 4);
    let ratios = cascades[0].ratios();
    assert_eq!(ratios.len(), 2);
    assert!(ratios.iter().all(|r| (3.5..6.0).contains(r)), "{ratios:?}");
    let c = diagram(OrbitMethod::Collocation(CollocationSettings::default()));
    for (a, b) in pd.iter().zip(doublings(&c)) {
        assert_abs_diff_eq!(*a, b, epsilon = 1e-8);
    }
}
