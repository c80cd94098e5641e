//! The rocking block against the study's and independently computed reference behaviour.

use approx::assert_abs_diff_eq;
use hycont_core::{
    HybridSystem, SampleTimes, Sensitivities, SimulationSettings, Simulator, StopReason,
};
use rocking_block::{
    IMPACT_MINUS, IMPACT_PLUS, LIFT_OFF_PLUS, MINUS, OVERTURN_NEG, Outcome, PLUS, Parameters, REST,
    RockingBlock, SimulationRequest, initial_mode, initial_state, restitution, simulate,
};
use std::f64::consts::{FRAC_PI_2, PI};

/// Flight durations of the stable asymmetric period-1 orbit at (omega, alpha) = (1.3, 0.66), as
/// given in the orbits issue (study + independent computation, 5 digits).
const ASYM_FLIGHTS: [f64; 2] = [3.14569, 1.68753];

#[test]
fn settles_on_the_asymmetric_period_one_orbit() {
    // From phi0 = 0.01, psi0 = 0 with forcing phase beta = pi/2 ((r, s) = (1, 0)).
    let req = SimulationRequest {
        phi0: 0.01,
        beta: FRAC_PI_2,
        periods: 300.0,
        points_per_period: 200,
        ..SimulationRequest::default()
    };
    let (report, traj) = simulate(&req).unwrap();
    assert_eq!(report.outcome, Outcome::Running);
    // Stroboscopic samples converge (period 1). The residual drift, ~2e-11 per period, is the
    // phase error of the neutral forcing oscillator at rtol 1e-10.
    let n = report.strobe.len();
    for k in n - 5..n - 1 {
        let d = (report.strobe[k + 1][0] - report.strobe[k][0]).abs()
            + (report.strobe[k + 1][1] - report.strobe[k][1]).abs();
        assert!(d < 1e-8, "strobe not converged: {d:e}");
    }
    // Two flights per period with the published durations.
    let ev = &traj.events;
    let mut flights = [
        ev[ev.len() - 1].t - ev[ev.len() - 2].t,
        ev[ev.len() - 2].t - ev[ev.len() - 3].t,
    ];
    flights.sort_by(|a, b| b.total_cmp(a));
    for (f, r) in flights.iter().zip(ASYM_FLIGHTS) {
        assert_abs_diff_eq!(*f, r, epsilon = 1e-5);
    }
    // Asymmetric: the mean of phi over the last period is far from 0.
    let per = req.points_per_period;
    let last: Vec<f64> = traj
        .samples
        .x
        .chunks(4)
        .rev()
        .take(per)
        .map(|x| x[0])
        .collect();
    let mean = last.iter().sum::<f64>() / per as f64;
    assert!(mean.abs() > 0.1, "mean phi over a period = {mean}");
    // Amp = max |phi| over a period (sampled, so a slight underestimate of 0.62605).
    let amp = last.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert_abs_diff_eq!(amp, 0.62605, epsilon = 1e-4);
}

#[test]
fn from_phi_001_with_beta_zero_the_block_chatters_lifts_off_and_overturns() {
    // The foundation issue expects an asymmetric orbit from here; integrating the study's
    // equations gives: chatter to rest, lift-off at r = 1 / (alpha omega^2 tan theta_b), one
    // impact at t = 3.2547125, overturn to the left at t = 8.5701874. The post-lift-off part was
    // cross-checked with scipy's DOP853 (rtol 1e-11): impact 3.254712508578, overturn 8.57018741.
    let params = Parameters::new(1.3, 0.66);
    let req = SimulationRequest {
        params,
        periods: 400.0,
        ..SimulationRequest::default()
    };
    let (report, traj) = simulate(&req).unwrap();
    assert_eq!(report.outcome, Outcome::OverturnNeg);
    match traj.stop {
        StopReason::TerminalEvent { event, t } => {
            assert_eq!(event, OVERTURN_NEG);
            assert_abs_diff_eq!(t, 8.570_187_4, epsilon = 1e-6);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(traj.zeno.len(), 1);
    let lift = traj
        .events
        .iter()
        .find(|e| e.event == LIFT_OFF_PLUS)
        .unwrap();
    let r_lift = 1.0 / (params.alpha * params.omega.powi(2) * params.theta_b.tan());
    assert_abs_diff_eq!(lift.state_before[2], r_lift, epsilon = 1e-10);
    let impact = traj
        .events
        .iter()
        .rfind(|e| e.event == IMPACT_PLUS)
        .unwrap();
    assert_abs_diff_eq!(impact.t, 3.254_712_508_6, epsilon = 1e-8);
}

#[test]
fn weak_forcing_never_lifts_off() {
    // alpha omega^2 tan(theta_b) = 0.3 * 1.69 * 1.21 = 0.61 < 1.
    let params = Parameters::new(1.3, 0.3);
    assert!(!params.lift_off_possible());
    let from_rest = SimulationRequest {
        params,
        phi0: 0.0,
        periods: 50.0,
        ..SimulationRequest::default()
    };
    let (report, traj) = simulate(&from_rest).unwrap();
    assert_eq!(report.outcome, Outcome::Rest);
    assert!(traj.events.is_empty());
    assert_eq!(report.final_state[..2], [0.0, 0.0]);
    // Tilted slightly, it chatters down to rest and stays there.
    let tilted = SimulationRequest {
        phi0: 0.01,
        ..from_rest
    };
    let (report, traj) = simulate(&tilted).unwrap();
    assert_eq!(report.outcome, Outcome::Rest);
    assert_eq!(traj.zeno.len(), 1);
    assert!(
        traj.events
            .iter()
            .all(|e| e.event == IMPACT_PLUS || e.event == IMPACT_MINUS)
    );
}

#[test]
fn figure_3d_initial_condition_comes_to_rest_instead_of_overturning() {
    // The study's Fig. 3(d) caption says this overturns; the equations say it chatters to rest at
    // t ~ 16.66 (max |phi| ~ 0.333), and alpha omega^2 tan(theta_b) = 0.65 < 1 keeps it there.
    let req = SimulationRequest {
        params: Parameters::new(0.902, 0.66),
        phi0: -0.2254,
        psi0: -0.1597,
        forcing_state: Some([-0.7778, 0.6284]),
        periods: 20.0,
        points_per_period: 400,
        ..SimulationRequest::default()
    };
    let (report, _) = simulate(&req).unwrap();
    assert_eq!(report.outcome, Outcome::Rest);
    assert_eq!(report.rest_times.len(), 1);
    assert_abs_diff_eq!(report.rest_times[0], 16.66, epsilon = 0.01);
    let amp = report.max_abs_phi.unwrap();
    assert_abs_diff_eq!(amp, 0.333, epsilon = 1e-3);
}

#[test]
fn symmetry_maps_solutions_to_solutions() {
    // S(phi, psi, r, s) = -(phi, psi, r, s); beta -> beta + pi flips (r, s).
    let params = Parameters::new(1.3, 0.66);
    let p = params.to_vec();
    let settings = SimulationSettings::default().samples(SampleTimes::new(0.0, 0.05));
    let run = |x0: [f64; 4]| {
        Simulator::new(settings.clone())
            .unwrap()
            .run(
                &RockingBlock,
                initial_mode(&x0, &params),
                0.0,
                &x0,
                &p,
                60.0,
            )
            .unwrap()
    };
    let x0 = initial_state(0.01, 0.0, FRAC_PI_2);
    let a = run(x0);
    let b = run(x0.map(|v| -v));
    assert!(a.events.len() > 10);
    assert_eq!(a.samples.len(), b.samples.len());
    for ((_, ma, xa), (_, mb, xb)) in a.samples.iter().zip(b.samples.iter()) {
        let expected_mode = match ma {
            PLUS => MINUS,
            MINUS => PLUS,
            m => m,
        };
        assert_eq!(mb, expected_mode);
        for (u, v) in xa.iter().zip(xb) {
            assert!((u + v).abs() <= 1e-10, "{xa:?} vs {xb:?}");
        }
    }
}

#[test]
fn every_impact_obeys_the_restitution_law() {
    let params = Parameters::new(1.3, 0.66);
    let e = restitution(params.theta_b);
    let req = SimulationRequest {
        beta: FRAC_PI_2,
        periods: 20.0,
        ..SimulationRequest::default()
    };
    let (_, traj) = simulate(&req).unwrap();
    for ev in traj
        .events
        .iter()
        .filter(|e| e.event == IMPACT_PLUS || e.event == IMPACT_MINUS)
    {
        // On the surface to the location tolerance: |phi| <= |psi| * 1e-13 * max(1, t).
        assert!(ev.state_before[0].abs() <= ev.state_before[1].abs() * 1e-13 * ev.t.max(1.0));
        assert_eq!(ev.state_after[1], e * ev.state_before[1]);
        let (before, after) = (ev.mode_before, ev.mode_after.unwrap());
        assert!((before == PLUS && after == MINUS) || (before == MINUS && after == PLUS));
    }
}

#[test]
fn monodromy_with_saltation_matches_finite_differences() {
    // Two forcing periods along the asymmetric orbit (four impacts), state and parameter
    // sensitivities against central differences of the flow.
    let params = Parameters::new(1.3, 0.66);
    let p = params.to_vec();
    let req = SimulationRequest {
        beta: FRAC_PI_2,
        periods: 50.0,
        ..SimulationRequest::default()
    };
    let (_, settled) = simulate(&req).unwrap();
    let x0: [f64; 4] = settled.state_final.clone().try_into().unwrap();
    let mode = settled.mode_final;
    let t1 = 2.0 * 2.0 * PI / params.omega;
    let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-12).atol(1e-14)).unwrap();
    let traj = sim
        .run_with_sensitivities(
            &RockingBlock,
            mode,
            0.0,
            &x0,
            &p,
            t1,
            Sensitivities::StateAndParameters,
        )
        .unwrap();
    assert_eq!(traj.stop, StopReason::EndReached);
    assert!(
        traj.stats.jumps >= 3,
        "crosses impacts: {}",
        traj.stats.jumps
    );
    let sens = traj.sensitivities.unwrap();
    let mut flow = |x: &[f64], p: &[f64]| {
        sim.run(&RockingBlock, mode, 0.0, x, p, t1)
            .unwrap()
            .state_final
    };
    let h = 1e-6;
    for j in 0..4 {
        let (mut xp, mut xm) = (x0, x0);
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (flow(&xp, &p), flow(&xm, &p));
        for i in 0..4 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            let an = sens.state_entry(i, j);
            assert_abs_diff_eq!(an, fd, epsilon = 1e-6 * (1.0 + fd.abs()));
        }
    }
    let dp = sens.params.unwrap();
    for q in 0..4 {
        let hq = h * p[q].abs().max(1e-2);
        let (mut pp, mut pm) = (p.clone(), p.clone());
        pp[q] += hq;
        pm[q] -= hq;
        let (fp, fm) = (flow(&x0, &pp), flow(&x0, &pm));
        for i in 0..4 {
            let fd = (fp[i] - fm[i]) / (2.0 * hq);
            let an = dp[i + 4 * q];
            assert_abs_diff_eq!(an, fd, epsilon = 1e-5 * (1.0 + fd.abs()));
        }
    }
}

#[test]
fn invalid_parameters_are_rejected_with_their_name() {
    for (params, name) in [
        (Parameters::new(0.0, 0.66), "omega"),
        (Parameters::new(1.3, -0.1), "alpha"),
        (
            Parameters {
                xi: -1.0,
                ..Parameters::default()
            },
            "xi",
        ),
        (
            Parameters {
                theta_b: 1.6,
                ..Parameters::default()
            },
            "theta_b",
        ),
        (
            Parameters {
                theta_b: 0.3,
                ..Parameters::default()
            },
            "theta_b",
        ),
        (Parameters::new(f64::NAN, 0.66), "omega"),
    ] {
        let err = params.validate().unwrap_err().to_string();
        assert!(err.contains(name), "{err}");
    }
    let bad = SimulationRequest {
        phi0: f64::INFINITY,
        ..SimulationRequest::default()
    };
    assert!(simulate(&bad).unwrap_err().to_string().contains("phi0"));
}

#[test]
fn rest_mode_is_entered_at_the_accumulation_of_chatter() {
    let params = Parameters::new(1.3, 0.66);
    let req = SimulationRequest {
        params,
        periods: 0.2,
        ..SimulationRequest::default()
    };
    let (_, traj) = simulate(&req).unwrap();
    let z = &traj.zeno[0];
    assert_eq!(z.mode_after, REST);
    assert_eq!(RockingBlock.mode_name(z.mode_after), "rest");
    // Many impacts with geometrically shrinking flights (ratio ~ e) before the switch.
    assert!(traj.events.len() > 10);
}
