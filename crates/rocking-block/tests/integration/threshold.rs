//! At the lift-off threshold $\alpha\omega^2\tan\theta_b = 1$ the block behaves as just below
//! it: once at rest it stays at rest (the forcing's peak reaches the threshold without
//! exceeding it). Computed in floating point the product exceeds 1 by rounding, and the block
//! used to lift off with no excess acceleration, fall back at once, come to rest by a Zeno
//! transition that lifted it off again at the same instant, and so on: `simulate --omega
//! 1.1197387404777615 --periods 400 --phi0 0.01` ran 180 s and 12.5 GB to the 50M-step limit
//! and reported `running`. Pinned here by the work the simulation does (its steps), not by
//! time.

use rocking_block::classes::{Class, classify};
use rocking_block::{Outcome, Parameters, SimulationRequest, simulate};

/// The study's block at alpha = 0.66: omega with alpha omega^2 tan(theta_b) = 1 to rounding.
const OMEGA_THRESHOLD: f64 = 1.1197387404777615;

fn rest_at(omega: f64) -> (Outcome, u64) {
    let req = SimulationRequest {
        params: Parameters::new(omega, 0.66),
        phi0: 0.01,
        periods: 400.0,
        ..SimulationRequest::default()
    };
    let (report, _) = simulate(&req).expect("the simulation ends");
    (report.outcome, report.stats.steps)
}

#[test]
fn at_the_lift_off_threshold_the_block_rests_as_just_below() {
    let p = Parameters::new(OMEGA_THRESHOLD, 0.66);
    let product = p.alpha * p.omega * p.omega * p.theta_b.tan();
    assert!((product - 1.0).abs() < 4.0 * f64::EPSILON, "{product}");
    assert!(!p.lift_off_possible());
    let (below, below_steps) = rest_at(OMEGA_THRESHOLD * (1.0 - 1e-9));
    let (at, at_steps) = rest_at(OMEGA_THRESHOLD);
    assert_eq!(below, Outcome::Rest);
    assert_eq!(at, Outcome::Rest);
    // About the same work as just below (thousands of steps, not millions).
    assert!(
        at_steps < 10 * below_steps.max(1000),
        "{at_steps} vs {below_steps}"
    );
    // Classified alike (the same start, forcing phase 0).
    let settings = rocking_block::classes::ClassifierSettings::default();
    for omega in [OMEGA_THRESHOLD * (1.0 - 1e-9), OMEGA_THRESHOLD] {
        let c = classify(&Parameters::new(omega, 0.66), 0.0, 0.01, 0.0, &settings).unwrap();
        assert_eq!(c.class, Class::Equilibrium, "omega {omega}");
    }
}
