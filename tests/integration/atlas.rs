//! Two-dimensional atlases ([`OrbitRun::atlas`]) of the vibrating table's period-one orbits
//! over the forcing amplitude and frequency $(a, \omega)$, against the closed forms of
//! `tests/integration/vibrating_table.rs`: with $C = \pi g (1-e)/(1+e)$, the period-one orbit impacts at
//! phase $\theta_0$ with $a\omega^2\cos\theta_0 = C$, at the velocity $-gT/(1+e)$
//! ($T = 2\pi/\omega$), and the family folds (SN) where $\cos\theta_0 = 1$, on $a\omega^2 = C$.
//! Started on the stable sheet ($\sin\theta_0 > 0$) with the fold as an edge, the atlas covers
//! that sheet inside the bounds: every chart's orbit is the closed form's (to the integrator's
//! and collocation's accuracy), the fold's boundary charts lie on $a\omega^2 = C$, and the
//! bound charts on the bounds.

use crate::model_vibrating_table as model;

use approx::assert_abs_diff_eq;
use hycont::AutoDiff;
use hycont::hycont_continuation::OrbitMethod;
use hycont::hycont_continuation::atlas::{AtlasEnd, AtlasSettings, Edge};
use hycont::hycont_continuation::{MeasureId, OrbitAtlas, OrbitRun, SpecialKind};
use hycont::hycont_core::orbit::{CollocationSettings, PeriodicOrbit, SegmentValue};
use model::{A, OMEGA, TableModel};
use std::f64::consts::PI;

const E: f64 = 0.5;
const G: f64 = 1.0;
const C: f64 = PI * G * (1.0 - E) / (1.0 + E);
const OMEGA_RANGE: (f64, f64) = (0.8, 1.25);
const A_MAX: f64 = 1.6;

/// The stable period-one orbit at `(a, omega)`, from its closed-form post-impact state.
fn orbit(a: f64, omega: f64) -> PeriodicOrbit {
    model::period_one(&AutoDiff::new(TableModel), [a, omega, E, G]).unwrap()
}

/// The atlas of the period-one family through `(1.3, 1.0)` over `omega` in [0.8, 1.25] and
/// `a <= 1.6`, by `method`; the impact phase and velocity are measured.
fn table_atlas(method: OrbitMethod, settings: AtlasSettings) -> (OrbitAtlas, [MeasureId; 2]) {
    let table: &'static _ = Box::leak(Box::new(AutoDiff::new(TableModel)));
    let mut run = OrbitRun::new(table, A).unwrap();
    run.method(method);
    let phase = run
        .add_measure("impact_phase", SegmentValue::start(0, 2))
        .unwrap();
    let velocity = run
        .add_measure("impact_velocity", SegmentValue::end(1, 1))
        .unwrap();
    let settings = settings
        .bound(OMEGA, OMEGA_RANGE.0, OMEGA_RANGE.1)
        .bound(A, 0.0, A_MAX);
    let atlas = run
        .atlas("period-1", &orbit(1.3, 1.0), OMEGA, &settings)
        .unwrap();
    (atlas, [phase, velocity])
}

/// Every chart against the closed forms; the fold's and the bounds' boundary charts on their
/// curves; the covered region reaches every edge.
fn check_against_closed_forms((saved, [phase, velocity]): &(OrbitAtlas, [MeasureId; 2]), tol: f64) {
    let atlas = &saved.atlas;
    assert_eq!(atlas.end, AtlasEnd::Covered, "{:?}", atlas.stats);
    let (mut folds, mut bounds) = (0, 0);
    for c in &atlas.charts {
        let (a, omega) = (c.point[A], c.point[OMEGA]);
        let theta0 = c.point.value(*phase).unwrap();
        let t = 2.0 * PI / omega;
        assert_abs_diff_eq!(
            c.point.value(*velocity).unwrap(),
            -G * t / (1.0 + E),
            epsilon = tol
        );
        assert_abs_diff_eq!(a * omega * omega * theta0.cos(), C, epsilon = tol);
        // The stable sheet: the impact phase is non-negative up to the fold.
        assert!(
            theta0 > -tol,
            "chart at a = {a}, omega = {omega}: theta0 = {theta0}"
        );
        assert!(a <= A_MAX + tol && omega >= OMEGA_RANGE.0 - tol && omega <= OMEGA_RANGE.1 + tol);
        match c.edge {
            Some(Edge::Special {
                kind: SpecialKind::Fold,
            }) => {
                folds += 1;
                // On the fold: theta0 = 0, a omega^2 = C (within the location tolerance).
                assert_abs_diff_eq!(a * omega * omega, C, epsilon = 1e-6);
                assert!(theta0.abs() < 1e-3, "fold chart theta0 = {theta0}");
            }
            Some(Edge::Bound { level, .. }) => {
                bounds += 1;
                let on_bound = [(a - level).abs(), (omega - level).abs()];
                assert!(on_bound.iter().any(|d| *d < 1e-6), "{a} {omega} {level}");
            }
            Some(other) => panic!("unexpected edge {other:?}"),
            None => {}
        }
    }
    assert!(
        folds >= 5 && bounds >= 5,
        "{folds} fold and {bounds} bound charts"
    );
    // The fold's charts span the omega range between the bounds (a omega^2 = C meets a = 1.6
    // at omega = sqrt(C / 1.6) = 0.809).
    let fold_omegas: Vec<f64> = atlas
        .edge_charts(SpecialKind::Fold)
        .map(|c| c.point[OMEGA])
        .collect();
    let lo = fold_omegas.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = fold_omegas
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        lo < (C / A_MAX).sqrt() + 0.05 && hi > OMEGA_RANGE.1 - 0.05,
        "{lo} {hi}"
    );
}

#[test]
fn shooting_atlas_of_the_table_matches_the_closed_forms() {
    let saved = table_atlas(
        OrbitMethod::default(),
        AtlasSettings::default().radii(0.1, 1e-3, 0.2),
    );
    eprintln!(
        "{} charts, {:?}",
        saved.0.atlas.charts.len(),
        saved.0.atlas.stats
    );
    check_against_closed_forms(&saved, 1e-8);
}

/// Collocation (NTST 20, NCOL 4: discretisation error below 1e-9 on this family, see
/// `tests/integration/vibrating_table.rs`) covers the same sheet with the same edges.
#[test]
fn collocation_atlas_of_the_table_matches_the_closed_forms() {
    let method = OrbitMethod::Collocation(CollocationSettings::default());
    let saved = table_atlas(method, AtlasSettings::default().radii(0.1, 1e-3, 0.2));
    check_against_closed_forms(&saved, 1e-8);
}

/// An atlas stopped at a chart limit, saved as JSON, read back and grown by
/// [`OrbitRun::extend_atlas`] is the atlas grown in one go; a run with other measures, or
/// another first parameter, refuses it.
#[test]
fn a_saved_atlas_grows_to_the_uninterrupted_one() {
    let settings = AtlasSettings::default().radii(0.1, 1e-3, 0.2);
    let (whole, _) = table_atlas(OrbitMethod::default(), settings.clone());
    let (part, _) = table_atlas(OrbitMethod::default(), settings.max_charts(60));
    assert_eq!(part.atlas.end, AtlasEnd::ChartLimit);
    assert_eq!(part.atlas.charts.len(), 60);
    let mut read = OrbitAtlas::from_json(&part.to_json().unwrap()).unwrap();
    assert_eq!(read, part);
    let table: &'static _ = Box::leak(Box::new(AutoDiff::new(TableModel)));
    let mut run = OrbitRun::new(table, A).unwrap();
    run.add_measure("impact_phase", SegmentValue::start(0, 2))
        .unwrap();
    run.add_measure("impact_velocity", SegmentValue::end(1, 1))
        .unwrap();
    run.extend_atlas(&mut read, 2000).unwrap();
    assert_eq!(read.atlas.end, AtlasEnd::Covered);
    assert_eq!(read.atlas.charts.len(), whole.atlas.charts.len());
    for (a, b) in read.atlas.charts.iter().zip(&whole.atlas.charts) {
        assert_eq!(a.point.u, b.point.u);
        assert_eq!(a.edge, b.edge);
    }
    let mut other = OrbitRun::new(table, A).unwrap();
    assert!(other.extend_atlas(&mut read.clone(), 3000).is_err());
    let mut by_omega = OrbitRun::new(table, OMEGA).unwrap();
    assert!(by_omega.extend_atlas(&mut read, 3000).is_err());
}

/// The table with a stronger gravity in its vector field (`g + 0.05`): the same names, sizes
/// and events, other orbits.
struct Heavier;

impl hycont::HybridSystem for Heavier {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        model::Table.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, m: hycont::Mode) -> &'static str {
        model::Table.mode_name(m)
    }
    fn events(&self, m: hycont::Mode) -> &[hycont::EventId] {
        model::Table.events(m)
    }
    fn event_spec(&self, e: hycont::EventId) -> hycont::EventSpec {
        model::Table.event_spec(e)
    }
    fn vector_field(&self, m: hycont::Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        model::Table.vector_field(m, x, p, f);
        f[1] -= 0.05;
    }
    fn event(&self, e: hycont::EventId, x: &[f64], p: &[f64]) -> f64 {
        model::Table.event(e, x, p)
    }
    fn reset(&self, e: hycont::EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        model::Table.reset(e, x, p, out);
    }
}

impl hycont::HybridJacobians for Heavier {
    fn vector_field_jacobian(
        &self,
        m: hycont::Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        model::Table.vector_field_jacobian(m, x, p, dx, dp);
    }
    fn event_gradient(
        &self,
        e: hycont::EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        model::Table.event_gradient(e, x, p, dx, dp);
    }
    fn reset_jacobian(
        &self,
        e: hycont::EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        model::Table.reset_jacobian(e, x, p, dx, dp);
    }
}

/// A run that measures what `table_atlas` does, on `system`.
fn measured_run<'a, S: hycont::HybridJacobians>(system: &'a S) -> OrbitRun<'a, S> {
    let mut run = OrbitRun::new(system, A).unwrap();
    run.add_measure("impact_phase", SegmentValue::start(0, 2))
        .unwrap();
    run.add_measure("impact_velocity", SegmentValue::end(1, 1))
        .unwrap();
    run
}

/// A saved atlas is checked against the run that grows it (`OrbitRun::check_atlas`): with
/// its parameters' unknowns swapped, or grown by another system with the same names and
/// sizes, it is refused; `orbit_of` refuses a system of other parameters; an atlas bounded by
/// a measure handle of another run is refused, not bounded by this run's measure of that
/// index.
#[test]
fn saved_atlases_are_checked_against_the_run() {
    let settings = AtlasSettings::default()
        .radii(0.1, 1e-3, 0.2)
        .max_charts(40);
    let (part, _) = table_atlas(OrbitMethod::default(), settings);
    let table: &'static _ = Box::leak(Box::new(AutoDiff::new(TableModel)));
    measured_run(table).check_atlas(&part).unwrap();
    let mut swapped = part.clone();
    swapped.atlas.unknown_params.reverse();
    let e = measured_run(table)
        .extend_atlas(&mut swapped, 100)
        .unwrap_err();
    assert!(e.to_string().contains("unknowns"), "{e}");
    let e = measured_run(&Heavier)
        .extend_atlas(&mut part.clone(), 100)
        .unwrap_err();
    assert!(
        matches!(e, hycont::hycont_continuation::Error::InvalidSaved { .. }),
        "{e}"
    );
    assert!(part.orbit_of(table, &part.atlas.charts[3]).is_ok());
    struct Renamed;
    impl hycont::HybridSystem for Renamed {
        fn state_dim(&self) -> usize {
            3
        }
        fn parameter_names(&self) -> &[&'static str] {
            &["b", "omega", "e", "g"]
        }
        fn mode_count(&self) -> usize {
            1
        }
        fn mode_name(&self, m: hycont::Mode) -> &'static str {
            model::Table.mode_name(m)
        }
        fn events(&self, m: hycont::Mode) -> &[hycont::EventId] {
            model::Table.events(m)
        }
        fn event_spec(&self, e: hycont::EventId) -> hycont::EventSpec {
            model::Table.event_spec(e)
        }
        fn vector_field(&self, m: hycont::Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
            model::Table.vector_field(m, x, p, f);
        }
        fn event(&self, e: hycont::EventId, x: &[f64], p: &[f64]) -> f64 {
            model::Table.event(e, x, p)
        }
    }
    let e = part.orbit_of(&Renamed, &part.atlas.charts[3]).unwrap_err();
    assert!(e.to_string().contains("parameters"), "{e}");
    // A handle of another run's measure at an index where this run has another measure.
    let mut other = OrbitRun::new(table, A).unwrap();
    other
        .add_measure("apex", SegmentValue::start(0, 0))
        .unwrap();
    let apex = other
        .add_measure("apex2", SegmentValue::start(0, 1))
        .unwrap();
    let mut run = measured_run(table);
    let bounded = AtlasSettings::default()
        .radii(0.1, 1e-3, 0.2)
        .bound(OMEGA, OMEGA_RANGE.0, OMEGA_RANGE.1)
        .bound(apex, -10.0, 10.0);
    let e = run
        .atlas("period-1", &orbit(1.3, 1.0), OMEGA, &bounded)
        .unwrap_err();
    assert!(
        matches!(e, hycont::hycont_continuation::Error::ForeignHandle { .. }),
        "{e}"
    );
}
