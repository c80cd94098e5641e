// The model of the `impact_oscillator` example (shared with the library tests): COCO's impact
// oscillator (Recipes for Continuation, Example 15.2), a harmonically forced, damped linear
// oscillator with a wall at x = d and Newtonian impacts v -> -e v.
//
// State `(x, v, r, s)`: displacement, velocity, and the forcing oscillator
// `r' = r + w s - r (r^2 + s^2)`, `s' = s - w r - s (r^2 + s^2)` whose limit cycle is
// `(r, s) = (sin(w t + beta), cos(w t + beta))`; `v' = -k x - c v + A r`. One mode; the event
// IMPACT (`d - x` falls through 0). Parameters `(k, c, A, w, d, e)`, COCO's names and order.

use hycont::orbit::PeriodicOrbit;
use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId,
    SimulationSettings, Simulator,
};

pub const AMP: ParamId = ParamId(2);
pub const W: ParamId = ParamId(3);
pub const FREE: Mode = Mode(0);
pub const IMPACT: EventId = EventId(0);

pub struct ImpactOscillator;

/// COCO's starting parameters `p0 = (k, c, A, w, d, e) = (1, 0.1, 1, 1, 1, 0.8)`.
pub const P0: [f64; 6] = [1.0, 0.1, 1.0, 1.0, 1.0, 0.8];

/// The impacting period-1 orbit at [`P0`], read off a simulation from rest (300 time units,
/// its transient gone), starting right after its impact.
pub fn impacting_orbit() -> Result<PeriodicOrbit, hycont::Error> {
    let mut sim = Simulator::new(SimulationSettings::default())?;
    let traj = sim.run(
        &ImpactOscillator,
        FREE,
        0.0,
        &[0.0, 0.0, 0.0, 1.0],
        &P0,
        300.0,
    )?;
    PeriodicOrbit::from_simulation(&ImpactOscillator, &traj, &P0, 1e-8)?
        .starting_after(&ImpactOscillator, IMPACT)
}

impl HybridSystem for ImpactOscillator {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["k", "c", "A", "w", "d", "e"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[IMPACT]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "impact",
            direction: Direction::Falling,
            action: EventAction::Jump { to: FREE },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let rho = x[2] * x[2] + x[3] * x[3];
        f[0] = x[1];
        f[1] = -p[0] * x[0] - p[1] * x[1] + p[2] * x[2];
        f[2] = x[2] + p[3] * x[3] - x[2] * rho;
        f[3] = x[3] - p[3] * x[2] - x[3] * rho;
    }
    fn event(&self, _: EventId, x: &[f64], p: &[f64]) -> f64 {
        p[4] - x[0]
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        out[1] = -p[5] * x[1];
    }
    /// The forcing oscillator's multipliers: 1 (its phase) and `exp(-2 T)` (its radius).
    fn trivial_multipliers(&self, _: &[f64], period: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0), ((-2.0 * period).exp(), 0.0)]
    }
}

impl HybridJacobians for ImpactOscillator {
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
        dx[1] = -p[0];
        dx[4] = 1.0;
        dx[5] = -p[1];
        dx[9] = p[2];
        dx[10] = 1.0 - rho - 2.0 * r * r;
        dx[11] = -p[3] - 2.0 * r * s;
        dx[14] = p[3] - 2.0 * r * s;
        dx[15] = 1.0 - rho - 2.0 * s * s;
        if let Some(dp) = dp {
            // Column-major 4 x 6: k, c, A, w, d, e.
            dp.fill(0.0);
            dp[1] = -x[0];
            dp[5] = -x[1];
            dp[9] = r;
            dp[14] = s;
            dp[15] = -r;
        }
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        dx[0] = -1.0;
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
