// The model of the `two_balls` example (shared with `tests/integration/codim2_points.rs`): two balls
// bouncing on vibrating tables driven by one forcing, ball 2's table a phase `psi` ahead; each
// is the Holmes ball of `examples/vibrating_table`. They do not interact, so a period-1 orbit
// is a pair of the single ball's orbits and its multipliers are the union of theirs: ball 1's
// fold and period-doubling curves in (a, e2) meet ball 2's special points at closed-form
// places (derived in `tests/integration/codim2_points.rs`).
//
// State `(z1, w1, z2, w2, theta)`: heights and velocities of the balls above their tables, the
// forcing phase; parameters `(a, omega, e1, e2, g1, g2, psi)`; analytic Jacobians (`TwoBalls`),
// or exact ones by automatic differentiation (`AutoDiff::new(TwoBallsModel)`).

#![allow(dead_code)] // each includer uses part of the model

use hycont::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridModel, HybridSystem, Mode,
    ParamId, Scalar, SimulationSettings,
};
use std::f64::consts::PI;

pub const A: ParamId = ParamId(0);
pub const E2: ParamId = ParamId(3);
pub const IMPACT1: EventId = EventId(0);
pub const IMPACT2: EventId = EventId(1);
pub const WRAP: EventId = EventId(2);
pub const FLIGHT: Mode = Mode(0);
pub const E1: f64 = 0.5;
pub const G1: f64 = 1.0;
/// Ball 2's table leads by this phase: its impacts come well after ball 1's.
pub const PSI: f64 = -1.5;

/// The two balls.
pub struct TwoBalls;

impl HybridSystem for TwoBalls {
    fn state_dim(&self) -> usize {
        5
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "omega", "e1", "e2", "g1", "g2", "psi"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "flight"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[IMPACT1, IMPACT2, WRAP]
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        let (name, direction) = match e {
            IMPACT1 => ("impact 1", Direction::Falling),
            IMPACT2 => ("impact 2", Direction::Falling),
            _ => ("phase wrap", Direction::Rising),
        };
        EventSpec {
            name,
            direction,
            action: EventAction::Jump { to: FLIGHT },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let aw2 = p[0] * p[1] * p[1];
        f[0] = x[1];
        f[1] = -p[4] + aw2 * x[4].sin();
        f[2] = x[3];
        f[3] = -p[5] + aw2 * (x[4] + p[6]).sin();
        f[4] = p[1];
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        match e {
            IMPACT1 => x[0],
            IMPACT2 => x[2],
            _ => x[4] - PI,
        }
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        match e {
            IMPACT1 => out[1] = -p[2] * x[1],
            IMPACT2 => out[3] = -p[3] * x[3],
            _ => out[4] = x[4] - 2.0 * PI,
        }
    }
}

impl HybridJacobians for TwoBalls {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        // Column-major 5 x 5.
        dx.fill(0.0);
        let aw2 = p[0] * p[1] * p[1];
        let (s1, c1) = x[4].sin_cos();
        let (s2, c2) = (x[4] + p[6]).sin_cos();
        dx[5] = 1.0; // d z1' / d w1
        dx[17] = 1.0; // d z2' / d w2
        dx[21] = aw2 * c1; // d w1' / d theta
        dx[23] = aw2 * c2; // d w2' / d theta
        if let Some(dp) = dp {
            // Column-major 5 x 7: columns a, omega, e1, e2, g1, g2, psi.
            dp.fill(0.0);
            dp[1] = p[1] * p[1] * s1;
            dp[3] = p[1] * p[1] * s2;
            dp[6] = 2.0 * p[0] * p[1] * s1;
            dp[8] = 2.0 * p[0] * p[1] * s2;
            dp[9] = 1.0;
            dp[21] = -1.0;
            dp[28] = -1.0;
            dp[33] = aw2 * c2;
        }
    }
    fn event_gradient(
        &self,
        e: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        dx[match e {
            IMPACT1 => 0,
            IMPACT2 => 2,
            _ => 4,
        }] = 1.0;
        if let Some(dp) = dp {
            dp.fill(0.0);
        }
    }
    fn reset_jacobian(
        &self,
        e: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        for i in 0..5 {
            dx[i + 5 * i] = 1.0;
        }
        match e {
            IMPACT1 => dx[6] = -p[2],
            IMPACT2 => dx[18] = -p[3],
            _ => {}
        }
        if let Some(dp) = dp {
            dp.fill(0.0);
            match e {
                IMPACT1 => dp[11] = -x[1], // d(-e1 w1)/d e1
                IMPACT2 => dp[18] = -x[3], // d(-e2 w2)/d e2
                _ => {}
            }
        }
    }
}

/// The two balls written once for any scalar: with `AutoDiff` a system with exact
/// Jacobians, equal to [`TwoBalls`]' hand-coded ones (`tests/integration/autodiff.rs`).
pub struct TwoBallsModel;

impl HybridModel for TwoBallsModel {
    fn state_dim(&self) -> usize {
        TwoBalls.state_dim()
    }
    fn parameter_names(&self) -> &[&'static str] {
        TwoBalls.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        TwoBalls.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        TwoBalls.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        TwoBalls.event_spec(e)
    }
    fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
        let aw2 = p[0] * p[1] * p[1];
        f[0] = x[1];
        f[1] = -p[4] + aw2 * x[4].sin();
        f[2] = x[3];
        f[3] = -p[5] + aw2 * (x[4] + p[6]).sin();
        f[4] = p[1];
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], _: &[T]) -> T {
        match e {
            IMPACT1 => x[0],
            IMPACT2 => x[2],
            _ => x[4] - PI,
        }
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        out.copy_from_slice(x);
        match e {
            IMPACT1 => out[1] = -p[2] * x[1],
            IMPACT2 => out[3] = -p[3] * x[3],
            _ => out[4] = x[4] - 2.0 * PI,
        }
    }
}

pub fn f(e: f64) -> f64 {
    (4.0 * (1.0 + e * e).powi(2) / (1.0 + e).powi(4)
        + PI * PI * (1.0 - e).powi(2) / (1.0 + e).powi(2))
    .sqrt()
}

pub fn a_sn(e: f64, g: f64) -> f64 {
    PI * g * (1.0 - e) / (1.0 + e)
}

pub fn a_pd(e: f64, g: f64) -> f64 {
    g * f(e)
}

/// The root of `h` in `[lo, hi]` (a sign change) by bisection to rounding.
pub fn bisect(h: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let s = h(lo).signum();
    assert!(h(hi).signum() != s, "no sign change in [{lo}, {hi}]");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if h(mid).signum() == s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A ball's post-impact velocity and impact phase (relative to its table) on its stable
/// period-1 orbit (omega = 1).
pub fn ball(a: f64, e: f64, g: f64) -> (f64, f64) {
    (e * g * 2.0 * PI / (1.0 + e), (a_sn(e, g) / a).acos())
}

/// The period-1 orbit at `a` from just after ball 1's impact: ball 2's state there from its
/// own impact a phase difference earlier, both closed form; segments in the order the events
/// come.
pub fn orbit(a: f64, e2: f64, g2: f64) -> PeriodicOrbit {
    let (w1, th1) = ball(a, E1, G1);
    let (w2, th2) = ball(a, e2, g2);
    // Ball 2 hits at theta = th2 - psi; its flight since then, tau = (th1 - th2 + psi) mod
    // 2 pi: w = w+ - g tau + a (cos th2 - cos(th2 + tau)), z = (w+ + a cos th2) tau
    // - g tau^2 / 2 - a (sin(th2 + tau) - sin th2).
    let tau = (th1 - th2 + PSI).rem_euclid(2.0 * PI);
    let z2 =
        (w2 + a * th2.cos()) * tau - 0.5 * g2 * tau * tau - a * ((th2 + tau).sin() - th2.sin());
    let v2 = w2 - g2 * tau + a * (th2.cos() - (th2 + tau).cos());
    let segment = |e| SegmentSpec {
        mode: FLIGHT,
        end: SegmentEnd::Event(e),
    };
    // Ball 2's impact phase in (-pi, pi], before or after ball 1's.
    let hit2 = PI - (PI - (th2 - PSI)).rem_euclid(2.0 * PI);
    let order = if hit2 > th1 {
        vec![segment(IMPACT2), segment(WRAP), segment(IMPACT1)]
    } else {
        vec![segment(WRAP), segment(IMPACT2), segment(IMPACT1)]
    };
    let signature = Signature::new(&TwoBalls, order).unwrap();
    PeriodicOrbit::from_initial_state(
        &TwoBalls,
        signature,
        &[0.0, w1, z2, v2, th1],
        &[a, 1.0, E1, e2, G1, g2, PSI],
        20.0,
        &SimulationSettings::default(),
    )
    .unwrap()
}
