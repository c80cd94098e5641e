// The model of the `table_basins` example (shared with `tests/integration/table_basins.rs`): the ball on
// a vibrating table of `vibrating_table`, plus sticking. State `(z, w, theta)`: height and
// velocity of the ball relative to the table `s(t) = a sin(omega t)`, forcing phase. In flight
// `z' = w`, `w' = -g + a omega^2 sin(theta)`, `theta' = omega`; an impact (`z` falls through 0)
// sets `w -> -e w`. Impacts that accumulate (complete chattering, detected by the simulator)
// leave the ball riding on the table, mode `STUCK` (`z = w = 0`), while the table's downward
// acceleration is below gravity; it lifts off when `a omega^2 sin(theta)` exceeds `g`. The
// phase wraps from `pi` to `-pi` in both modes. Parameters `(a, omega, e, g)`.

use hycont::hycont_sample::classify::PeriodicallyForced;
use hycont::{Direction, EventAction, EventId, EventSpec, HybridSystem, Mode};
use std::f64::consts::PI;

pub const FLIGHT: Mode = Mode(0);
pub const STUCK: Mode = Mode(1);
pub const IMPACT: EventId = EventId(0);
pub const WRAP_FLIGHT: EventId = EventId(1);
pub const LIFT_OFF: EventId = EventId(2);
pub const WRAP_STUCK: EventId = EventId(3);

pub struct StickyTable;

/// The ball's acceleration relative to the table at rest on it: `a omega^2 sin(theta) - g`.
fn pull(theta: f64, p: &[f64]) -> f64 {
    p[0] * p[1] * p[1] * theta.sin() - p[3]
}

impl HybridSystem for StickyTable {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "omega", "e", "g"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        if m == FLIGHT { "flight" } else { "stuck" }
    }
    fn events(&self, m: Mode) -> &[EventId] {
        if m == FLIGHT {
            &[IMPACT, WRAP_FLIGHT]
        } else {
            &[LIFT_OFF, WRAP_STUCK]
        }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        let (name, direction, to) = match e {
            IMPACT => ("impact", Direction::Falling, FLIGHT),
            WRAP_FLIGHT => ("phase wrap", Direction::Rising, FLIGHT),
            LIFT_OFF => ("lift-off", Direction::Rising, FLIGHT),
            _ => ("phase wrap (stuck)", Direction::Rising, STUCK),
        };
        EventSpec {
            name,
            direction,
            action: EventAction::Jump { to },
        }
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        if m == FLIGHT {
            f[0] = x[1];
            f[1] = pull(x[2], p);
        } else {
            f[0] = 0.0;
            f[1] = 0.0;
        }
        f[2] = p[1];
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        match e {
            IMPACT => x[0],
            LIFT_OFF => pull(x[2], p),
            _ => x[2] - PI,
        }
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        if e == IMPACT {
            out[1] = -p[2] * x[1];
        } else if e != LIFT_OFF {
            out[2] = x[2] - 2.0 * PI;
        }
    }
    fn zeno_transition(
        &self,
        _: Mode,
        _: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        out.copy_from_slice(x);
        out[0] = 0.0;
        out[1] = 0.0;
        Some(if pull(x[2], p) > 0.0 { FLIGHT } else { STUCK })
    }
}

/// Forced with period `2 pi / omega`; the strobes compare `(z, w)`; stuck for good where the
/// table cannot lift the ball (`a omega^2 <= g`).
impl PeriodicallyForced for StickyTable {
    fn forcing_period(&self, p: &[f64]) -> f64 {
        2.0 * PI / p[1]
    }
    fn strobe_components(&self) -> &[usize] {
        &[0, 1]
    }
    fn mode_at(&self, x: &[f64], p: &[f64]) -> Mode {
        if x[0] <= 0.0 && x[1] == 0.0 && pull(x[2], p) <= 0.0 {
            STUCK
        } else {
            FLIGHT
        }
    }
    fn absorbed(&self, m: Mode, _: &[f64], p: &[f64]) -> bool {
        m == STUCK && p[0] * p[1] * p[1] <= p[3]
    }
}

/// The table's attractors, classified by hycont's stroboscopic classifier. A trial's variables
/// are `[a, z0, w0, theta0]`; `omega`, `e`, `g` are fixed (and recorded in a study's files).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TableClassifier {
    pub omega: f64,
    pub e: f64,
    pub g: f64,
    pub settings: hycont::hycont_sample::classify::StrobeSettings,
}

/// The classes, in [`TableClassifier`]'s order.
pub const CLASSES: [&str; 6] = [
    "stuck",
    "chattering",
    "period-1",
    "period-2",
    "higher period",
    "undecided",
];

impl hycont::hycont_sample::basin::Classifier for TableClassifier {
    fn classes(&self) -> Vec<String> {
        CLASSES.iter().map(ToString::to_string).collect()
    }
    fn classify(&self, v: &[f64]) -> Result<usize, String> {
        use hycont::hycont_sample::classify::{Attractor, classify};
        let p = [v[0], self.omega, self.e, self.g];
        let table = hycont::FiniteDifferences::new(StickyTable);
        let c =
            classify(&table, &p, FLIGHT, &v[1..4], &self.settings).map_err(|e| e.to_string())?;
        Ok(match c.attractor {
            Attractor::Absorbed => 0,
            // Orbits that stick to the table for part of their period.
            Attractor::Periodic { .. } if c.zeno || c.modes.contains(&STUCK) => 1,
            Attractor::Periodic { period: 1, .. } => 2,
            Attractor::Periodic { period: 2, .. } => 3,
            Attractor::Periodic { .. } => 4,
            Attractor::Undecided => 5,
            Attractor::Terminal { event } => return Err(format!("terminal event {event:?}")),
        })
    }
}

/// The study of the example and its test: the table's amplitude `a` uniform on `[0.5, 2)` in
/// 15 cells, the drop height `z0` on `[0.05, 1)`, velocity `w0` on `[-1, 1)`, phase `theta0` on
/// `[-pi, pi)`.
pub fn amplitude_study(seed: u64) -> hycont::hycont_sample::basin::Study {
    use hycont::hycont_sample::basin::{Axis, Distribution, Study};
    Study {
        names: ["a", "z0", "w0", "theta0"].map(String::from).to_vec(),
        variables: vec![
            Distribution::Uniform { lo: 0.5, hi: 2.0 },
            Distribution::Uniform { lo: 0.05, hi: 1.0 },
            Distribution::Uniform { lo: -1.0, hi: 1.0 },
            Distribution::Uniform { lo: -PI, hi: PI },
        ],
        axes: vec![Axis {
            variable: 0,
            lo: 0.5,
            hi: 2.0,
            bins: 15,
        }],
        seed,
    }
}

/// The bouncing period-1 orbit's state just after its impact at amplitude `a` (closed form,
/// `tests/integration/vibrating_table.rs`): phase `theta0` with `a omega^2 cos(theta0) = pi g (1 - e) /
/// (1 + e)` on the stable branch (`sin(theta0) > 0`), take-off velocity `w+ = e g T / (1 + e)`;
/// `None` below the fold.
pub fn orbit_after_impact(a: f64, omega: f64, e: f64, g: f64) -> Option<[f64; 3]> {
    let t = 2.0 * PI / omega;
    let c = PI * g * (1.0 - e) / (1.0 + e) / (a * omega * omega);
    (c <= 1.0).then(|| [0.0, e * g * t / (1.0 + e), c.acos()])
}

/// The largest modulus of the period-1 orbit's multipliers at `a` (closed form): the impact
/// map's Jacobian has trace `1 + e^2 - kappa (1 + e)`, `kappa = a omega^2 sin(theta0) (1 + e) /
/// g`, and determinant `e^2`.
pub fn orbit_multiplier(a: f64, omega: f64, e: f64, g: f64) -> Option<f64> {
    let theta0 = orbit_after_impact(a, omega, e, g)?[2];
    let kappa = a * omega * omega * theta0.sin() * (1.0 + e) / g;
    let (tr, det) = (1.0 + e * e - kappa * (1.0 + e), e * e);
    let disc = tr * tr - 4.0 * det;
    Some(if disc >= 0.0 {
        0.5 * (tr.abs() + disc.sqrt())
    } else {
        det.sqrt()
    })
}

/// Trials started near the bouncing period-1 orbit: a trial's variables `[a, u, v]` (`u`, `v`
/// in `[-1, 1)`) start the ball just after the orbit's impact with its take-off velocity
/// scaled by `1 + spread u` and its phase moved by `spread v` radians; classified as
/// [`TableClassifier`] does. `NaN` variables below the fold (no orbit) are an error.
pub struct NearOrbit {
    pub table: TableClassifier,
    pub spread: f64,
}

impl hycont::hycont_sample::basin::Classifier for NearOrbit {
    fn classes(&self) -> Vec<String> {
        self.table.classes()
    }
    fn classify(&self, v: &[f64]) -> Result<usize, String> {
        let TableClassifier { omega, e, g, .. } = self.table;
        let [z, w, theta] = orbit_after_impact(v[0], omega, e, g)
            .ok_or_else(|| format!("no period-1 orbit at a = {}", v[0]))?;
        let start = [
            v[0],
            z,
            w * (1.0 + self.spread * v[1]),
            theta + self.spread * v[2],
        ];
        self.table.classify(&start)
    }
}

/// The near-orbit study: `a` uniform on `[lo, hi)` in `bins` cells, `u`, `v` on `[-1, 1)`.
pub fn near_orbit_study(
    lo: f64,
    hi: f64,
    bins: usize,
    seed: u64,
) -> hycont::hycont_sample::basin::Study {
    use hycont::hycont_sample::basin::{Axis, Distribution, Study};
    let unit = Distribution::Uniform { lo: -1.0, hi: 1.0 };
    Study {
        names: ["a", "u", "v"].map(String::from).to_vec(),
        variables: vec![Distribution::Uniform { lo, hi }, unit, unit],
        axes: vec![Axis {
            variable: 0,
            lo,
            hi,
            bins,
        }],
        seed,
    }
}
