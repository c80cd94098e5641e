// The model of the `piecewise_linear` example (shared with the library tests): a harmonically
// forced, damped oscillator whose stiffness grows from 1 to 1 + k at x = d (a spring engages;
// the restoring force stays continuous, so the state does not jump at the switch).
//
// State `(x, v, r, s)`: displacement, velocity, and the forcing oscillator
// `r' = r + omega s - r (r^2 + s^2)`, `s' = s - omega r - s (r^2 + s^2)`, whose limit cycle is
// `(r, s) = (sin(omega t + beta), cos(omega t + beta))`. Modes SOFT (x < d):
// `v' = -x - 2 zeta v + f r`; STIFF (x > d): `v' = -x - k (x - d) - 2 zeta v + f r`. Events UP
// (x rises through d) and DOWN (falls through it) switch modes without a reset. Parameters
// `(f, omega, zeta, k, d)`. Derivatives come from `FiniteDifferences`, or exactly by automatic
// differentiation from `OscillatorModel`, the equations written once for any scalar.

use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridModel, HybridSystem, Mode, ParamId, Scalar,
};

pub const F: ParamId = ParamId(0);
pub const OMEGA: ParamId = ParamId(1);
pub const SOFT: Mode = Mode(0);
pub const STIFF: Mode = Mode(1);
pub const UP: EventId = EventId(0);
pub const DOWN: EventId = EventId(1);

pub struct Oscillator;

impl HybridSystem for Oscillator {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["f", "omega", "zeta", "k", "d"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        ["soft", "stiff"][m.0]
    }
    fn events(&self, m: Mode) -> &[EventId] {
        if m == SOFT { &[UP] } else { &[DOWN] }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        let (name, direction, to) = if e == UP {
            ("engage", Direction::Rising, STIFF)
        } else {
            ("release", Direction::Falling, SOFT)
        };
        EventSpec {
            name,
            direction,
            action: EventAction::Jump { to },
        }
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        let spring = if m == STIFF {
            p[3] * (x[0] - p[4])
        } else {
            0.0
        };
        let rho = x[2] * x[2] + x[3] * x[3];
        out[0] = x[1];
        out[1] = -x[0] - spring - 2.0 * p[2] * x[1] + p[0] * x[2];
        out[2] = x[2] + p[1] * x[3] - x[2] * rho;
        out[3] = x[3] - p[1] * x[2] - x[3] * rho;
    }
    fn event(&self, _: EventId, x: &[f64], p: &[f64]) -> f64 {
        x[0] - p[4]
    }
    /// The forcing oscillator's multipliers: 1 (its phase) and `exp(-2 T)` (its radius).
    fn trivial_multipliers(&self, _: &[f64], period: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0), ((-2.0 * period).exp(), 0.0)]
    }
}

/// The oscillator's equations for any scalar (modes and events are `Oscillator`'s).
#[allow(dead_code)] // not every includer differentiates automatically
pub struct OscillatorModel;

impl HybridModel for OscillatorModel {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        Oscillator.parameter_names()
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        Oscillator.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        Oscillator.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        Oscillator.event_spec(e)
    }
    fn vector_field<T: Scalar>(&self, m: Mode, x: &[T], p: &[T], out: &mut [T]) {
        let spring = if m == STIFF {
            p[3] * (x[0] - p[4])
        } else {
            T::from(0.0)
        };
        let rho = x[2] * x[2] + x[3] * x[3];
        out[0] = x[1];
        out[1] = -x[0] - spring - p[2] * x[1] * 2.0 + p[0] * x[2];
        out[2] = x[2] + p[1] * x[3] - x[2] * rho;
        out[3] = x[3] - p[1] * x[2] - x[3] * rho;
    }
    fn event<T: Scalar>(&self, _: EventId, x: &[T], p: &[T]) -> T {
        x[0] - p[4]
    }
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        Oscillator.trivial_multipliers(p, period)
    }
}
