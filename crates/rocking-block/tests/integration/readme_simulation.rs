//! End-to-end: the README's simulation (400 forcing periods at the study's start point)
//! checked against the study's asymmetric period-1 orbit.

use approx::assert_abs_diff_eq;
use rocking_block::{Outcome, SimulationRequest, simulate};
use std::f64::consts::FRAC_PI_2;

#[test]
fn readme_simulation_reaches_the_published_asymmetric_orbit() {
    let req = SimulationRequest {
        phi0: 0.01,
        psi0: 0.0,
        beta: FRAC_PI_2,
        periods: 400.0,
        points_per_period: 200,
        ..SimulationRequest::default()
    };
    let (report, traj) = simulate(&req).unwrap();
    assert_eq!(report.outcome, Outcome::Running);
    assert_eq!(report.strobe.len(), 401);
    // Two impacts per period once settled.
    let late: Vec<_> = traj
        .events
        .iter()
        .filter(|e| e.t > 300.0 * 4.8332)
        .collect();
    let periods_late = (traj.t_final - 300.0 * 4.8332) / (2.0 * std::f64::consts::PI / 1.3);
    assert_eq!(late.len() as f64, (2.0 * periods_late).round());
    // The published Amp of the asymmetric orbit, 0.62605, over the last period (dense samples:
    // within 1e-4). The whole run's max |phi| includes the transient and is larger.
    let amp = traj
        .samples
        .x
        .chunks(4)
        .rev()
        .take(200)
        .fold(0.0f64, |m, x| m.max(x[0].abs()));
    assert!(report.max_abs_phi.unwrap() >= amp);
    assert_abs_diff_eq!(amp, 0.62605, epsilon = 1e-4);
    // The JSON report serialises with the documented fields.
    let json = serde_json::to_value(&report).unwrap();
    for key in [
        "outcome",
        "t_end",
        "impacts",
        "final_state",
        "strobe",
        "stats",
    ] {
        assert!(json.get(key).is_some(), "{key}");
    }
}
