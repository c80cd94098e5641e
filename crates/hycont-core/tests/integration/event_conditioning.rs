//! Recorded events report their conditioning: the estimated errors of the crossing time and of
//! the approach rate bound the actual errors against a closed form, and grow as the crossing
//! becomes tangential.
//!
//! The model: $\dot x = v$, $\dot v = -x$ from $(0, 1)$, so $x = \sin t$, with a wall at
//! $x = d < 1$ (event $h = d - x$, falling). The first crossing is at $t^* = \arcsin d$ with
//! velocity $v^* = \cos t^* = \sqrt{1 - d^2}$, so $d = \sqrt{1 - v_a^2}$ gives the approach
//! velocity $v_a$; the rate of $h$ there is $-v^*$ and its second derivative
//! $\ddot h = \sin t^* = d \approx 1$. The conditioning analysis (`EventConditioning`) predicts
//! rate errors of about $\delta h / v_a$ with
//! $\delta h \approx \mathrm{rtol}$.

use hycont_core::{
    Direction, EventAction, EventId, EventSpec, HybridSystem, Mode, SimulationSettings, Simulator,
};

struct Wall;

impl HybridSystem for Wall {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["d"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[EventId(0)]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "wall",
            direction: Direction::Falling,
            action: EventAction::Terminal,
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], _: &[f64], f: &mut [f64]) {
        f[0] = x[1];
        f[1] = -x[0];
    }
    fn event(&self, _: EventId, x: &[f64], p: &[f64]) -> f64 {
        p[0] - x[0]
    }
}

/// The located crossing for approach velocity `va` and its errors against the closed form:
/// (estimated and actual time error, estimated and actual velocity error).
fn crossing(va: f64, settings: SimulationSettings) -> (f64, f64, f64, f64, bool) {
    let d = (1.0 - va * va).sqrt();
    let mut sim = Simulator::new(settings).unwrap();
    let traj = sim
        .run(&Wall, Mode(0), 0.0, &[0.0, 1.0], &[d], 3.0)
        .unwrap();
    let e = traj.events.first().expect("the wall is reached");
    let c = e.conditioning;
    let (t_star, v_star) = (d.asin(), (1.0 - d * d).sqrt());
    // The rate of h = d - x is -v.
    assert!(
        (c.rate + e.state_before[1]).abs() <= 1e-6 * v_star + c.rate_error,
        "rate {} against -v {}",
        c.rate,
        -e.state_before[1]
    );
    (
        c.t_error,
        (e.t - t_star).abs(),
        c.rate_error,
        (e.state_before[1] - v_star).abs(),
        c.rate_resolved(0.01),
    )
}

#[test]
fn the_estimates_bound_the_errors_and_grow_near_tangency() {
    let mut last_rate_error = 0.0;
    for va in [1e-1, 1e-2, 1e-3, 1e-4] {
        let (t_est, t_err, v_est, v_err, resolved) = crossing(va, SimulationSettings::default());
        assert!(
            t_err <= t_est,
            "va {va}: time error {t_err:e} > estimate {t_est:e}"
        );
        assert!(
            v_err <= v_est,
            "va {va}: velocity error {v_err:e} > estimate {v_est:e}"
        );
        // Relative to the velocity the estimate grows as the crossing turns tangential.
        assert!(v_est / va > last_rate_error, "va {va}");
        last_rate_error = v_est / va;
        // Resolved to 1 % except at the most tangential crossing.
        assert_eq!(resolved, va > 1e-4 + 1e-12, "va {va}: {v_est:e}");
    }
    // Tighter tolerances resolve it (the errors scale with them).
    let tight = SimulationSettings::default().rtol(1e-13).atol(1e-15);
    let (_, _, v_est, v_err, resolved) = crossing(1e-4, tight);
    assert!(v_err <= v_est && resolved, "{v_est:e}");
}
