// The model of the `stick_slip` example (shared with the library tests): COCO's stick-slip
// oscillator (Dankowicz and Schilder, "Recipes for Continuation", Examples 9.3-9.4), a system
// whose modes have states of different dimensions.
//
// STICK (3 states `(x1, x2, x3)`: position, velocity, forcing phase) and SLIP (4 states
// `(x1, x2, x3, x4)`: a relative displacement, then position, velocity and phase), with
// `F = V^2 sin(phase)^2 / (1 - position)^2 - c velocity - position`:
// - STICK: `x1' = x2`, `x2' = F`, `x3' = w`;
// - SLIP: `x1' = -n - F/5`, `x2' = x3`, `x3' = n + 6F/5`, `x4' = w`.
//
// Events: PHASE (`pi/2 - x3` falls through 0; the phase is shifted back by `pi`, the forcing's
// period), MINSEP (`x2` falls through 0: the position's maximum, an identity "turn"),
// COLLISION (`0.5 - x1` falls through 0: the mass reaches the stop, and the bounce
// `(x1, x2, x3) -> ((1+e)/6 x2, x1, -e x2, x3)` leads into SLIP) in STICK; REST (`x1` falls
// through 0, and `(x1, x2, x3, x4) -> (x2, x3, x4)` leads back into STICK) in SLIP.
// Parameters `(V, c, n, w, e)`, COCO's names and order.

use hycont::{
    AutoDiff, Direction, EventAction, EventId, EventSpec, HybridModel, Mode, ParamId, Scalar,
};

pub const V: ParamId = ParamId(0);
pub const STICK: Mode = Mode(0);
pub const SLIP: Mode = Mode(1);
pub const PHASE: EventId = EventId(0);
pub const MINSEP: EventId = EventId(1);
pub const COLLISION: EventId = EventId(2);
pub const REST: EventId = EventId(3);

/// COCO's parameters `p0 = (V, c, n, w, e) = (0.59, 0.04, 3.17, 0.92, 0.80)`.
pub const P0: [f64; 5] = [0.59, 0.04, 3.17, 0.92, 0.80];

/// The stick-slip oscillator, with exact Jacobians by dual numbers.
pub type StickSlip = AutoDiff<Model>;

/// The stick-slip oscillator written once for any scalar.
#[derive(Debug, Clone, Copy, Default)]
pub struct Model;

/// `V^2 sin(phase)^2 / (1 - position)^2 - c velocity - position`.
fn force<T: Scalar>(position: T, velocity: T, phase: T, p: &[T]) -> T {
    let gap = T::from(1.0) - position;
    p[0] * p[0] * phase.sin().powi(2) / (gap * gap) - p[1] * velocity - position
}

impl HybridModel for Model {
    fn state_dim(&self) -> usize {
        4
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        if mode == STICK { 3 } else { 4 }
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["V", "c", "n", "w", "e"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        if mode == STICK { "stick" } else { "slip" }
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        if mode == STICK {
            &[PHASE, MINSEP, COLLISION]
        } else {
            &[REST]
        }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        let (name, to) = match e {
            PHASE => ("phase", STICK),
            MINSEP => ("minsep", STICK),
            COLLISION => ("collision", SLIP),
            _ => ("rest", STICK),
        };
        EventSpec {
            name,
            direction: Direction::Falling,
            action: EventAction::Jump { to },
        }
    }
    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], f: &mut [T]) {
        if mode == STICK {
            f[0] = x[1];
            f[1] = force(x[0], x[1], x[2], p);
            f[2] = p[3];
        } else {
            let force = force(x[1], x[2], x[3], p);
            f[0] = -p[2] - force / 5.0;
            f[1] = x[2];
            f[2] = p[2] + force * 1.2;
            f[3] = p[3];
        }
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], _: &[T]) -> T {
        match e {
            PHASE => -x[2] + std::f64::consts::FRAC_PI_2,
            MINSEP => x[1],
            COLLISION => -x[0] + 0.5,
            _ => x[0],
        }
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        match e {
            PHASE => {
                out.copy_from_slice(x);
                out[2] = x[2] - std::f64::consts::PI;
            }
            MINSEP => out.copy_from_slice(x),
            COLLISION => {
                // 3 -> 4 states.
                out[0] = (p[4] + 1.0) * x[1] / 6.0;
                out[1] = x[0];
                out[2] = -p[4] * x[1];
                out[3] = x[2];
            }
            _ => out.copy_from_slice(&x[1..4]),
        }
    }
}

/// The sustained-stick orbit at `V = 0.5` (the other parameters [`P0`]'s), read off a
/// simulation from `(0.25, 0, -pi/2)` after its transient (3000 time units), starting right
/// after its position's maximum (MINSEP): two segments in STICK, ended by PHASE and MINSEP.
pub fn sustained_stick_orbit() -> Result<hycont::orbit::PeriodicOrbit, hycont::Error> {
    let system = StickSlip::default();
    let mut p = P0;
    p[V.index()] = 0.5;
    let mut sim = hycont::Simulator::new(hycont::SimulationSettings::default())?;
    let x0 = [0.25, 0.0, -std::f64::consts::FRAC_PI_2];
    let traj = sim.run(&system, STICK, 0.0, &x0, &p, 3000.0)?;
    hycont::orbit::PeriodicOrbit::from_simulation(&system, &traj, &p, 1e-8)?
        .starting_after(&system, MINSEP)
}
