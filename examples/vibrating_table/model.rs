// The model of the `vibrating_table` example (shared with the library tests): a ball bouncing
// on a table that vibrates as `s(t) = a sin(omega t)`, in coordinates relative to the table.
//
// State `(z, w, theta)`: height and velocity of the ball above the table, forcing phase.
// Between impacts `z' = w`, `w' = -g + a omega^2 sin(theta)`, `theta' = omega`; at an impact
// (`z` falls through 0) `w -> -e w`; the phase wraps from `pi` to `-pi` (an event that only
// resets `theta`). Parameters `(a, omega, e, g)`. Derivatives come from `FiniteDifferences`
// (the library tests supply and check analytic ones), or exactly by automatic differentiation
// from `TableModel`, the same equations written once for any scalar (`AutoDiff::new(TableModel)`).

use hycont::ParamId;
use hycont::{Direction, EventAction, EventId, EventSpec, HybridModel, HybridSystem, Mode, Scalar};
use std::f64::consts::PI;

pub const A: ParamId = ParamId(0);
pub const OMEGA: ParamId = ParamId(1);
pub const IMPACT: EventId = EventId(0);
pub const WRAP: EventId = EventId(1);
pub const FLIGHT: Mode = Mode(0);

pub struct Table;

impl HybridSystem for Table {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "omega", "e", "g"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "flight"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[IMPACT, WRAP]
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        let (name, direction) = if e == IMPACT {
            ("impact", Direction::Falling)
        } else {
            ("phase wrap", Direction::Rising)
        };
        EventSpec {
            name,
            direction,
            action: EventAction::Jump { to: FLIGHT },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        f[0] = x[1];
        f[1] = -p[3] + p[0] * p[1] * p[1] * x[2].sin();
        f[2] = p[1];
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        if e == IMPACT { x[0] } else { x[2] - PI }
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        if e == IMPACT {
            out[1] = -p[2] * x[1];
        } else {
            out[2] = x[2] - 2.0 * PI;
        }
    }
}

/// The table's equations for any scalar (events and modes are `Table`'s).
#[allow(dead_code)] // not every includer differentiates automatically
pub struct TableModel;

impl HybridModel for TableModel {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        Table.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        Table.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        Table.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        Table.event_spec(e)
    }
    fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
        f[0] = x[1];
        f[1] = -p[3] + p[0] * p[1] * p[1] * x[2].sin();
        f[2] = p[1];
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], _: &[T]) -> T {
        if e == IMPACT { x[0] } else { x[2] - PI }
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        out.copy_from_slice(x);
        if e == IMPACT {
            out[1] = -p[2] * x[1];
        } else {
            out[2] = x[2] - 2.0 * PI;
        }
    }
}
