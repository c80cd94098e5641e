//! Boundary (DB) points and curves: a branch ends where a segment collapses onto another
//! event's surface, and the curve from that DB point follows the boundary in two parameters,
//! by either discretisation, against a closed form.
//!
//! # The model and its closed form
//! The ball on a vibrating table (`examples/vibrating_table/model.rs`) with its forcing phase
//! wrapped at $\theta = \varphi_w$ (a parameter) instead of $\pi$: the phase lives in
//! $[\varphi_w - 2\pi, \varphi_w)$. The period-1 orbit impacts at the phase $\theta_0$ with
//! $$a\omega^2\cos\theta_0 = \frac{\pi g(1-e)}{1+e}$$
//! (derived in `tests/integration/vibrating_table.rs`); between impacts the phase passes $\varphi_w$ once,
//! so the orbit has two segments, impact to wrap and wrap to impact, the first lasting
//! $(\varphi_w - \theta_0)/\omega$. It collapses where the impact happens at the wrap,
//! $\theta_0 = \varphi_w$: there the segment ends on the other event's surface (the domain
//! margin's zero, DB), at
//! $$a_{DB}(\varphi_w) = \frac{\pi g (1-e)}{(1+e)\,\omega^2\cos\varphi_w}.$$

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{
    CurveCondition, CurveSpec, EndReason, Label, OrbitRun, RunDirection, SpecialKind,
};
use hycont::orbit::{
    CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings,
    Signature,
};
use hycont::{
    Direction, EventAction, EventId, EventSpec, FiniteDifferences, HybridSystem, Mode, ParamId,
    SimulationSettings,
};
use std::f64::consts::PI;

const A: ParamId = ParamId(0);
const PHASE: ParamId = ParamId(4);
const IMPACT: EventId = EventId(0);
const WRAP: EventId = EventId(1);
const FLIGHT: Mode = Mode(0);
/// `(a, omega, e, g, phase_w)`.
const P: [f64; 5] = [1.3, 1.0, 0.5, 1.0, 0.7];

/// Height and velocity above the table, forcing phase; parameters `(a, omega, e, g, phase_w)`.
struct PhasedTable;

impl HybridSystem for PhasedTable {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "omega", "e", "g", "phase_w"]
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
        EventSpec {
            name: if e == IMPACT { "impact" } else { "wrap" },
            direction: if e == IMPACT {
                Direction::Falling
            } else {
                Direction::Rising
            },
            action: EventAction::Jump { to: FLIGHT },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        f[0] = x[1];
        f[1] = -p[3] + p[0] * p[1] * p[1] * x[2].sin();
        f[2] = p[1];
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        if e == IMPACT { x[0] } else { x[2] - p[4] }
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

fn a_db(phase: f64) -> f64 {
    let (omega, e, g) = (P[1], P[2], P[3]);
    PI * g * (1.0 - e) / ((1.0 + e) * omega * omega * phase.cos())
}

/// The stable period-1 orbit at `a = 1.3` from its closed-form post-impact state.
fn start(sys: &FiniteDifferences<PhasedTable>) -> PeriodicOrbit {
    let (a, omega, e, g) = (P[0], P[1], P[2], P[3]);
    let theta0 = (PI * g * (1.0 - e) / ((1.0 + e) * a * omega * omega)).acos();
    let w_plus = e * g * 2.0 * PI / omega / (1.0 + e);
    let segment = |end| SegmentSpec { mode: FLIGHT, end };
    let signature = Signature::new(
        sys,
        vec![
            segment(SegmentEnd::Event(WRAP)),
            segment(SegmentEnd::Event(IMPACT)),
        ],
    )
    .unwrap();
    PeriodicOrbit::from_initial_state(
        sys,
        signature,
        &[0.0, w_plus, theta0],
        &P,
        20.0,
        &SimulationSettings::default(),
    )
    .unwrap()
}

/// Continued up in `a`, the branch ends where the impact meets the wrap, at the closed form;
/// the curve from that DB point in `(a, phase_w)` holds the collapsed segment at zero duration
/// and follows the closed form over phase_w in [0.2, 1.2].
#[test]
fn the_boundary_curve_follows_the_closed_form() {
    let sys = FiniteDifferences::new(PhasedTable);
    let orbit = start(&sys);
    let db = SpecialKind::Custom(Label::new("DB").unwrap());
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let mut run = OrbitRun::new(&sys, A).unwrap();
        run.method(method).bounds(1.1, 1.5);
        let branch = run.run("period-1", &orbit, RunDirection::Up).unwrap();
        assert!(
            matches!(branch.branch.end, EndReason::Inadmissible(_)),
            "{:?}",
            branch.branch.end
        );
        let end = branch.branch.special_points.last().unwrap();
        assert_abs_diff_eq!(end.point[A], a_db(P[4]), epsilon = 1e-8);
        // The DB point of the admissibility's domain margin: the collapse's GR comes with it,
        // and the orbit problem names DB (the impact crosses the wrap's surface at a finite
        // rate: not a grazing).
        assert_eq!(end.kind, db);
        assert_eq!(
            crate::collapse_ends::end_at_collapse(&sys, &branch, &end.point),
            0
        );
        let label = end.point.label;
        run.bounds(1.0, 3.0);
        let spec = CurveSpec::new(PHASE).bounds(0.2, 1.2);
        let curve = run.curve_at("DB", &branch, label, &spec).unwrap();
        assert!(
            matches!(
                curve.condition,
                Some(CurveCondition::Collapse { segment: 0 })
            ),
            "{:?}",
            curve.condition
        );
        assert_eq!(curve.branch.end, EndReason::Bound);
        let phases: Vec<f64> = curve.branch.points.iter().map(|p| p[PHASE]).collect();
        let lo = phases.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = phases.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(lo < 0.2 + 1e-9 && hi > 1.2 - 1e-9, "[{lo}, {hi}]");
        for p in &curve.branch.points {
            assert_abs_diff_eq!(p[A], a_db(p[PHASE]), epsilon = 1e-8);
        }
    }
}
