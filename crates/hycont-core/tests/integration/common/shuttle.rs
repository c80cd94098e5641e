//! The shuttle: a system whose modes have states of different dimensions, with its closed
//! form.
//!
//! In mode A (one state, x' = 1) x climbs from 0 to 1, where event UP (h = 1 - x, falling)
//! jumps into mode B with the state (x) -> (x, -v0); in mode B (two states, x' = y, y' = a) x
//! falls back, x(t) = 1 - v0 t + a t^2 / 2, to 0, where event DOWN (h = x, falling) jumps back
//! into A with (x, y) -> (x). Closed form: A lasts 1, B lasts
//! t_B = (v0 - sqrt(v0^2 - 2 a)) / a (the first root of x(t) = 0) and ends with
//! y = -sqrt(v0^2 - 2 a); the motion repeats with period 1 + t_B.

use hycont_core::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode,
};

pub const A: Mode = Mode(0);
pub const B: Mode = Mode(1);
pub const UP: EventId = EventId(0);
pub const DOWN: EventId = EventId(1);
/// v0 and a.
pub const P: [f64; 2] = [1.0, 0.2];

/// The shuttle; `clash` also watches UP in mode B (of another dimension): an invalid system;
/// `short_gradient` writes DOWN's gradient as if mode B had one state (a gradient of the
/// wrong length).
#[derive(Default)]
pub struct Shuttle {
    pub clash: bool,
    pub short_gradient: bool,
}

impl HybridSystem for Shuttle {
    fn state_dim(&self) -> usize {
        2
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        if mode == A { 1 } else { 2 }
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["v0", "a"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        if mode == A { "climb" } else { "fall" }
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        match (mode == A, self.clash) {
            (true, _) => &[UP],
            (false, false) => &[DOWN],
            (false, true) => &[DOWN, UP],
        }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: if e == UP { "up" } else { "down" },
            direction: Direction::Falling,
            action: EventAction::Jump {
                to: if e == UP { B } else { A },
            },
        }
    }
    fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        if mode == A {
            f[0] = 1.0;
        } else {
            f[0] = x[1];
            f[1] = p[1];
        }
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        if e == UP { 1.0 - x[0] } else { x[0] }
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        if e == UP {
            out[0] = x[0];
            out[1] = -p[0];
        } else {
            out[0] = x[0];
        }
    }
}

impl HybridJacobians for Shuttle {
    fn vector_field_jacobian(
        &self,
        m: Mode,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        if m == B {
            dx[2] = 1.0;
        }
        if let Some(dp) = dp {
            dp.fill(0.0);
            if m == B {
                dp[3] = 1.0;
            }
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
        if self.short_gradient {
            dx[0] = if e == UP { -1.0 } else { 1.0 };
        } else {
            dx.fill(0.0);
            dx[0] = if e == UP { -1.0 } else { 1.0 };
        }
        if let Some(dp) = dp {
            dp.fill(0.0);
        }
    }
    /// Rectangular: UP is 2 x 1 ((x) -> (x, -v0)), DOWN 1 x 2 ((x, y) -> (x)).
    fn reset_jacobian(
        &self,
        e: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx[..2].copy_from_slice(&[1.0, 0.0]);
        if let Some(dp) = dp {
            if e == UP {
                // Columns v0 and a of the 2 x 2 parameter Jacobian.
                dp[..4].copy_from_slice(&[0.0, -1.0, 0.0, 0.0]);
            } else {
                dp[..2].fill(0.0);
            }
        }
    }
}
