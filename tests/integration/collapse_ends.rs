//! Which terminal event ends a run at a collapsed segment, where several are located at one
//! point: the run's domain margin vanishes with every duration, so its DB always comes with
//! the collapse's GR (the shortest-segment monitor). The orbit problem's
//! `ContinuationProblem::end_among` names the collapse's GR where the collapsed segment's
//! flow meets its end's surface tangentially (a grazing: the segment starts on that surface
//! with zero speed into it, two events merging), and leaves the listed order (DB before the
//! collapse) where it crosses that surface at a finite rate. Checked here on the
//! piecewise-linear oscillator, whose stiff segment collapses where the orbit's maximum
//! touches the switching surface (tangential); `boundary_curves` checks a transversal collapse
//! (an impact reaching the wrap of the forcing phase).

use crate::model_piecewise_linear as model;

use hycont::HybridJacobians;
use hycont::hycont_continuation::{
    BranchPoint, ContinuationProblem, MeasureId, MonitorEvent, OrbitBranch, OrbitContinuation,
    OrbitRun, Quantity, RunDirection, SpecialKind,
};
use hycont::orbit::{MeasureSet, OrbitMethod, ShootingSettings};

/// The index `end_among` gives among `[DB, collapse GR]` at `point` of `branch` (0: DB).
pub fn end_at_collapse<S: HybridJacobians>(
    system: &S,
    branch: &OrbitBranch,
    point: &BranchPoint,
) -> usize {
    let orbit = branch.orbit_of(point).unwrap();
    let method = OrbitMethod::Shooting(ShootingSettings::default());
    let measures = std::rc::Rc::new(MeasureSet::new());
    let (mut cp, u) =
        OrbitContinuation::new(system, &orbit, &method, branch.free, measures, Vec::new()).unwrap();
    let collapse = *cp.monitor_events().last().unwrap();
    assert_eq!(collapse.on, Quantity::Measure(MeasureId::SHORTEST_SEGMENT));
    let db = MonitorEvent {
        kind: SpecialKind::DOMAIN_BOUNDARY,
        on: Quantity::Measure(MeasureId::new(3)),
        level: 0.0,
        terminal: true,
    };
    cp.end_among(&u, &[db, collapse])
}

/// Down in the forcing amplitude the two-mode orbits' stiff segment collapses where their
/// maximum reaches the switching surface: a tangential collapse, ended as a grazing (the
/// branch's last special point is a GR), which the problem names over DB; at the branch's
/// start, where no segment has collapsed, the listed order stands.
#[test]
fn a_tangential_collapse_ends_the_run_as_a_grazing() {
    let fd = hycont::FiniteDifferences::new(model::Oscillator);
    let mut run = OrbitRun::new(&fd, model::F).unwrap();
    run.bounds(0.1, 1.0);
    let orbit = crate::piecewise_linear::two_mode_orbit(0.5, 0.8);
    let two = run.run("two-mode", &orbit, RunDirection::Down).unwrap();
    let end = two.branch.special_points.last().unwrap();
    assert_eq!(end.kind, SpecialKind::Grazing);
    let o = two.orbit_of(&end.point).unwrap();
    assert!(
        o.durations.iter().any(|d| d.abs() < 1e-8),
        "{:?}",
        o.durations
    );
    assert_eq!(end_at_collapse(&fd, &two, &end.point), 1);
    assert_eq!(end_at_collapse(&fd, &two, &two.branch.points[0]), 0);
}
