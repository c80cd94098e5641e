// The model of the `symmetric_branch` example (shared with the library tests): a harmonically
// forced, damped oscillator between two walls at x = -d and x = +d, with Newtonian impacts
// v -> -e v (a symmetric two-sided impact oscillator).
//
// State `(x, v, r, s)`: displacement, velocity, and the forcing oscillator
// `r' = r + omega s - r (r^2 + s^2)`, `s' = s - omega r - s (r^2 + s^2)` whose limit cycle is
// `(r, s) = (sin(omega t + beta), cos(omega t + beta))`; `v' = -k x - c v + a r`. One mode;
// events RIGHT (`d - x` falls through 0: x reaches +d) and LEFT (`x + d` falls through 0).
// Parameters `(a, omega, k, c, d, e)`.
//
// The Z2 symmetry `(x, v, r, s) -> -(x, v, r, s)` (the walls swapped) is linear because the
// forcing's phase is carried by the oscillator pair (r, s), which the symmetry maps to
// `(-r, -s)`, a half period later: a forced system written with its phase as a wrapped angle
// `theta` would need `theta -> theta + pi`, which is not linear.

use hycont::orbit::{
    Closure, SegmentEnd, SegmentSpec, Signature, SymmetricSearch, SymmetricSolution,
    find_symmetric_orbit,
};
use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId,
    Z2Symmetry,
};
use std::f64::consts::{PI, TAU};

pub const A: ParamId = ParamId(0);
pub const OMEGA: ParamId = ParamId(1);
pub const FREE: Mode = Mode(0);
pub const RIGHT: EventId = EventId(0);
pub const LEFT: EventId = EventId(1);

pub struct ImpactPair;

impl HybridSystem for ImpactPair {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "omega", "k", "c", "d", "e"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[RIGHT, LEFT]
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: if e == RIGHT {
                "right wall"
            } else {
                "left wall"
            },
            direction: Direction::Falling,
            action: EventAction::Jump { to: FREE },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let rho = x[2] * x[2] + x[3] * x[3];
        f[0] = x[1];
        f[1] = -p[2] * x[0] - p[3] * x[1] + p[0] * x[2];
        f[2] = x[2] + p[1] * x[3] - x[2] * rho;
        f[3] = x[3] - p[1] * x[2] - x[3] * rho;
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        if e == RIGHT { p[4] - x[0] } else { x[0] + p[4] }
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        out[1] = -p[5] * x[1];
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        let mut matrix = vec![0.0; 16];
        for i in 0..4 {
            matrix[i + 4 * i] = -1.0;
        }
        Some(Z2Symmetry {
            matrix,
            modes: vec![FREE],
            events: vec![LEFT, RIGHT],
        })
    }
    /// The forcing oscillator's multipliers: 1 (its phase) and `exp(-2 T)` (its radius).
    fn trivial_multipliers(&self, _: &[f64], period: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0), ((-2.0 * period).exp(), 0.0)]
    }
}

impl HybridJacobians for ImpactPair {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let (r, s) = (x[2], x[3]);
        let rho = r * r + s * s;
        // Column-major 4 x 4.
        dx.fill(0.0);
        dx[1] = -p[2]; // d f1 / d x
        dx[4] = 1.0; // d f0 / d v
        dx[5] = -p[3];
        dx[9] = p[0]; // d f1 / d r
        dx[10] = 1.0 - rho - 2.0 * r * r;
        dx[11] = -p[1] - 2.0 * r * s;
        dx[14] = p[1] - 2.0 * r * s;
        dx[15] = 1.0 - rho - 2.0 * s * s;
        if let Some(dp) = dp {
            // Column-major 4 x 6: a, omega, k, c, d, e.
            dp.fill(0.0);
            dp[1] = r;
            dp[6] = s;
            dp[7] = -r;
            dp[9] = -x[0];
            dp[13] = -x[1];
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
        dx[0] = if e == RIGHT { -1.0 } else { 1.0 };
        if let Some(dp) = dp {
            dp.fill(0.0);
            dp[4] = 1.0;
        }
    }
    fn reset_jacobian(
        &self,
        _: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        for i in 0..4 {
            dx[i + 4 * i] = 1.0;
        }
        dx[1 + 4] = -p[5];
        if let Some(dp) = dp {
            dp.fill(0.0);
            dp[1 + 4 * 5] = -x[1];
        }
    }
}

/// The symmetric orbit with one impact on each wall at parameters `p` (`(a, omega, k, c, d, e)`):
/// its half orbit is one free flight from just after a left impact to a right impact, closed
/// through the symmetry (which maps its end, after the right impact's reset, onto its start),
/// searched from seeds on the left wall (12 speeds, 24 forcing phases) with half period
/// `pi / omega`.
pub fn find_symmetric(p: &[f64; 6]) -> hycont::Result<SymmetricSolution> {
    let (omega, d) = (p[1], p[4]);
    let half = Signature::with_closure(
        &ImpactPair,
        vec![SegmentSpec {
            mode: FREE,
            end: SegmentEnd::Event(RIGHT),
        }],
        Closure::Symmetric,
    )?;
    let seeds = (0..12)
        .flat_map(|i| {
            (0..24).map(move |j| {
                let beta = TAU * f64::from(j) / 24.0;
                vec![-d, 0.1 + 0.25 * f64::from(i), beta.sin(), beta.cos()]
            })
        })
        .collect();
    let search = SymmetricSearch::new(seeds).half_period(PI / omega);
    find_symmetric_orbit(&ImpactPair, &half, p, &search)
}
