//! COCO's stick-slip oscillator (`examples/stick_slip`): modes of their own state dimension
//! (STICK 3 states, SLIP 4), a grazing switch into a signature with a zero-length SLIP
//! segment, by both discretisations.
//!
//! References:
//! - The period of every orbit of both families is the forcing's, $\pi / w$ (the phase
//!   advances at rate $w$ and PHASE shifts it by $\pi$ once per period): to 1e-10.
//! - Each orbit's own simulation for one period (the simulator's event detection, across
//!   the 3 -> 4 -> 3 state jumps) returns to its start: to 1e-8 away from the grazing, with
//!   the signature's number of events (2 for sustained stick, 3 for stick-slip).
//! - Shooting and collocation (40 intervals of degree 4) locate the fold, the grazing and
//!   the stick-slip orbits at the same parameters to 1e-8.
//! - At the grazing orbit the position's maximum is the stop's `x1 = 0.5` (1e-10), and the
//!   new family starts there with a SLIP segment of zero duration that grows with `V`.

#[path = "../../examples/stick_slip/model.rs"]
mod model;

use hycont::hycont_continuation::{OrbitBranch, OrbitMethod, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{CollocationSettings, PeriodicOrbit, ShootingSettings};
use hycont::{Error, EventId, HybridModel, Mode, Scalar, SimulationSettings, check_derivatives};
use model::{SLIP, STICK, StickSlip, V};

fn period() -> f64 {
    std::f64::consts::PI / model::P0[3]
}

fn slip_duration(o: &PeriodicOrbit) -> Option<f64> {
    (o.signature.segments().iter())
        .position(|s| s.mode == SLIP)
        .map(|k| o.durations[k])
}

/// The two families by `method`: sustained stick up from `V = 0.5`, and stick-slip switched
/// at its grazing; with the fold's and the grazing's `V`.
fn families(method: OrbitMethod) -> (OrbitBranch, OrbitBranch, f64, f64) {
    let system = StickSlip::default();
    let orbit = model::sustained_stick_orbit().unwrap();
    let mut run = OrbitRun::new(&system, V).unwrap();
    run.method(method).bounds(0.5, 0.7);
    let two = run.run("sustained", &orbit, RunDirection::Up).unwrap();
    let fold = two.first(SpecialKind::Fold).unwrap().point.params[0];
    let db = two.first(SpecialKind::DOMAIN_BOUNDARY).unwrap().clone();
    let three = run
        .switch_at("stick-slip", &two, db.point.label, RunDirection::Up)
        .unwrap();
    (two, three, fold, db.point.params[0])
}

fn collocation() -> OrbitMethod {
    OrbitMethod::Collocation(CollocationSettings {
        ntst: 40,
        ..CollocationSettings::default()
    })
}

/// The model's dual-number Jacobians (rectangular at the bounce, 4 x 3, and at rest, 3 x 4)
/// agree with central differences in both modes.
#[test]
fn jacobians_across_dimensions_match_differences() {
    let system = StickSlip::default();
    let p = model::P0;
    for (mode, x) in [
        (STICK, vec![0.3, 0.2, 0.7]),
        (STICK, vec![0.49, -0.1, -1.2]),
        (SLIP, vec![0.05, 0.45, -0.3, 0.4]),
    ] {
        let check = check_derivatives(&system, mode, &x, &p).unwrap();
        assert!(check.max_error() < 1e-7, "{mode}: {check:?}");
    }
}

/// Shooting: the sustained-stick family folds just before its grazing; the stick-slip family
/// starts at the grazing orbit with a zero-length SLIP segment and goes on up to the bound,
/// every orbit of period pi/w, those away from the grazing returning to themselves.
#[test]
fn the_stick_slip_family_goes_on_from_the_grazing_by_shooting() {
    let system = StickSlip::default();
    let (two, three, fold, grazing) = families(OrbitMethod::Shooting(ShootingSettings::default()));
    assert!(fold > grazing && fold - grazing < 1e-4, "{fold} {grazing}");
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    for q in &two.branch.points {
        let o = two.orbit_of(q).unwrap();
        assert!((o.period() - period()).abs() < 1e-10);
        assert_eq!(o.starts[0].len(), 3);
    }
    // The grazing orbit: its maximum (the start after MINSEP) at the stop.
    let last = two.orbit_of(two.branch.points.last().unwrap()).unwrap();
    assert!(
        (last.starts[0][0] - 0.5).abs() < 1e-10,
        "{:?}",
        last.starts[0]
    );
    let points = &three.branch.points;
    assert!((points[0].params[0] - grazing).abs() < 1e-10);
    assert!(points.len() > 5, "{:?}", three.branch.end);
    assert!((points.last().unwrap().params[0] - 0.7).abs() < 1e-10);
    let first = three.orbit_of(&points[0]).unwrap();
    assert_eq!(first.segment_count(), 3);
    assert!(slip_duration(&first).unwrap().abs() < 1e-12);
    let mut previous = 0.0;
    for q in &points[1..] {
        let o = three.orbit_of(q).unwrap();
        assert!((o.period() - period()).abs() < 1e-10);
        let slip = slip_duration(&o).unwrap();
        assert!(slip > previous, "{slip} after {previous}");
        previous = slip;
        let lens: Vec<usize> = o.starts.iter().map(Vec::len).collect();
        assert!(lens.contains(&4) && lens.contains(&3), "{lens:?}");
        if q.params[0] > 0.6 {
            let back = o.simulated_return(&system, &settings).unwrap();
            assert!(back.gap < 1e-8, "V = {}: {back:?}", q.params[0]);
            assert_eq!(back.events, 3);
        }
    }
}

/// The domain margin along the sustained-stick family is the stop's distance from the
/// position's maximum, $0.5 - x_1$ where MINSEP ends the second segment (the first segment's
/// start, MINSEP's reset being the identity), at every point by both discretisations (1e-8:
/// the margin is read off the scan's integration of each segment from its start, the
/// reference off the discretised orbit's next start; they differ by the discretisation's
/// error, as collocation and shooting do in the test below). The other conditions are larger (COLLISION at PHASE's end about 0.3-0.4, the durations
/// about 1.7). The position is extremal exactly where that segment ends, so the scan finds
/// the turn a rounding error before or after the end; the margin takes it as the end's value
/// either way (as an interior turn it would have gone to the grazing margin instead, and the
/// domain margin jumped to the next condition from one point to the next).
#[test]
fn the_domain_margin_is_the_stop_distance_at_the_flights_turn() {
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        collocation(),
    ] {
        let (two, ..) = families(method);
        let names = &two.branch.monitor_names;
        let domain = names.iter().position(|n| n == "admissible_domain").unwrap();
        for q in &two.branch.points {
            let reference = 0.5 - two.orbit_of(q).unwrap().starts[0][0];
            let margin = q.monitors[domain];
            assert!(
                (margin - reference).abs() < 1e-8,
                "V = {}: {margin} against {reference}",
                q.params[0]
            );
        }
    }
}

/// Collocation locates the same fold, grazing and stick-slip orbits as shooting (1e-8).
#[test]
fn collocation_agrees_with_shooting_across_the_grazing() {
    let (_, three_s, fold_s, graze_s) =
        families(OrbitMethod::Shooting(ShootingSettings::default()));
    let (_, three_c, fold_c, graze_c) = families(collocation());
    assert!((fold_s - fold_c).abs() < 1e-8, "{fold_s} {fold_c}");
    assert!((graze_s - graze_c).abs() < 1e-8, "{graze_s} {graze_c}");
    let end = |b: &OrbitBranch| b.orbit_of(b.branch.points.last().unwrap()).unwrap();
    let (s, c) = (end(&three_s), end(&three_c));
    assert_eq!(s.signature, c.signature);
    for (a, b) in s.durations.iter().zip(&c.durations) {
        assert!((a - b).abs() < 1e-8, "{:?} {:?}", s.durations, c.durations);
    }
    for (a, b) in s.starts.iter().flatten().zip(c.starts.iter().flatten()) {
        assert!((a - b).abs() < 1e-8, "{:?} {:?}", s.starts, c.starts);
    }
}

/// The stick-slip model whose bounce forgets the SLIP state's last component.
struct ForgetfulBounce;

impl HybridModel for ForgetfulBounce {
    fn state_dim(&self) -> usize {
        model::Model.state_dim()
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        model::Model.mode_dim(mode)
    }
    fn parameter_names(&self) -> &[&'static str] {
        model::Model.parameter_names()
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        model::Model.mode_name(mode)
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        model::Model.events(mode)
    }
    fn event_spec(&self, e: EventId) -> hycont::EventSpec {
        model::Model.event_spec(e)
    }
    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], f: &mut [T]) {
        model::Model.vector_field(mode, x, p, f);
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], p: &[T]) -> T {
        model::Model.event(e, x, p)
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        if e == model::COLLISION {
            out[..3].copy_from_slice(&[x[1], x[0], x[1]]);
        } else {
            model::Model.reset(e, x, p, out);
        }
    }
}

/// Bad input: an orbit through a reset that leaves a component of the larger state unwritten
/// is refused with a typed error naming the event and the component, by both
/// discretisations; a start of the wrong mode's dimension names the segment.
#[test]
fn a_reset_that_does_not_fill_the_next_state_is_an_error() {
    let (_, three, ..) = families(OrbitMethod::Shooting(ShootingSettings::default()));
    let orbit = three.orbit_of(three.branch.points.last().unwrap()).unwrap();
    let bad = hycont::AutoDiff::new(ForgetfulBounce);
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        collocation(),
    ] {
        let e = hycont::orbit::solve_orbit(
            &bad,
            &orbit,
            &method,
            &hycont::problem::NewtonSettings::default(),
            1e-9,
        )
        .unwrap_err();
        assert!(
            matches!(&e, Error::NonFiniteReset { event, index: 3, .. } if *event == model::COLLISION),
            "{e}"
        );
    }
    let mut wrong = orbit.clone();
    let k = slip_duration_index(&orbit);
    wrong.starts[k].pop();
    let e = wrong.validate(&StickSlip::default()).unwrap_err();
    assert!(e.to_string().contains(&format!("segment {k}")), "{e}");
}

fn slip_duration_index(o: &PeriodicOrbit) -> usize {
    (o.signature.segments().iter())
        .position(|s| s.mode == SLIP)
        .unwrap()
}

/// A saved stick-slip branch (segments of 3 and 4 states) reads back equal, validates, and
/// restarts from a middle point by either discretisation to the same end orbit (1e-8).
#[test]
fn a_saved_branch_of_mixed_dimensions_restarts() {
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        collocation(),
    ] {
        let (_, three, ..) = families(method);
        let text = three.to_json().unwrap();
        let back = OrbitBranch::from_json(&text).unwrap();
        assert_eq!(back.to_json().unwrap(), text);
        let system = StickSlip::default();
        back.validate(&system).unwrap();
        let middle = &back.branch.points[back.branch.points.len() / 2];
        let mut run = OrbitRun::new(&system, V).unwrap();
        run.method(method).bounds(0.5, 0.7);
        let again = run
            .restart("again", &back, middle.label, Some(RunDirection::Up))
            .unwrap();
        let end = |b: &OrbitBranch| b.orbit_of(b.branch.points.last().unwrap()).unwrap();
        let (a, b) = (end(&three), end(&again));
        for (x, y) in a.starts.iter().flatten().zip(b.starts.iter().flatten()) {
            assert!((x - y).abs() < 1e-8, "{:?} {:?}", a.starts, b.starts);
        }
    }
}

/// A diagram crosses the grazing on its own: from the sustained-stick orbit over V in
/// [0.5, 0.7] (depth 1, the default kinds), the sustained-stick family and, switched at its DB
/// point, the stick-slip family with its SLIP segment, ending at the bound; the saved diagram
/// reads back and re-checks.
#[test]
fn a_diagram_switches_at_the_grazing() {
    use hycont::hycont_continuation::{Diagram, DiagramSettings, SwitchOutcome};
    let system = StickSlip::default();
    let orbit = model::sustained_stick_orbit().unwrap();
    let mut run = OrbitRun::new(&system, V).unwrap();
    run.bounds(0.5, 0.7);
    let settings = DiagramSettings {
        depth: 1,
        ..DiagramSettings::default()
    };
    let diagram = run.diagram("sustained", &orbit, &settings).unwrap();
    assert_eq!(diagram.branches.len(), 2, "{:?}", diagram.switches);
    let db: Vec<_> = (diagram.switches.iter())
        .filter(|s| s.kind == SpecialKind::DOMAIN_BOUNDARY)
        .collect();
    assert_eq!(db.len(), 1);
    assert!(matches!(db[0].outcome, SwitchOutcome::Followed(_)));
    let new = &diagram.branches[1].branch;
    let end = new.orbit_of(new.branch.points.last().unwrap()).unwrap();
    assert!(slip_duration(&end).unwrap() > 0.0);
    assert!((new.branch.points.last().unwrap().params[0] - 0.7).abs() < 1e-10);
    let text = diagram.to_json().unwrap();
    Diagram::from_json(&text).unwrap();
}

/// Back the other way: the stick-slip family, continued down from V = 0.7, ends where its
/// impact becomes tangential and its SLIP segment collapses (the grazing); switching there
/// removes the impact and the zero-length SLIP segment (their jumps compose to the identity
/// at zero impact speed), ends the STICK segment at MINSEP where the impact was (the flow
/// crosses that identity event there), and finds the sustained-stick family again: its orbit
/// at the grazing's V agrees with the sustained-stick branch's grazing orbit (1e-8) and the
/// family runs to V = 0.5.
#[test]
fn switching_back_at_the_grazing_finds_sustained_stick() {
    let system = StickSlip::default();
    let (two, three, _, grazing) = families(OrbitMethod::Shooting(ShootingSettings::default()));
    let mut run = OrbitRun::new(&system, V).unwrap();
    run.bounds(0.5, 0.7);
    let top = three.branch.points.last().unwrap().label;
    let down = run
        .restart("down", &three, top, Some(RunDirection::Down))
        .unwrap();
    let end = down
        .branch
        .special_points
        .iter()
        .find(|s| s.kind == SpecialKind::Grazing || s.kind == SpecialKind::DOMAIN_BOUNDARY)
        .unwrap_or_else(|| panic!("{:?}", down.branch.end));
    assert!(
        (end.point.params[0] - grazing).abs() < 1e-8,
        "{}",
        end.point.params[0]
    );
    let back = run
        .switch_at("back", &down, end.point.label, RunDirection::Down)
        .unwrap();
    let first = back.orbit_of(&back.branch.points[0]).unwrap();
    assert!(first.starts.iter().all(|x| x.len() == 3), "{first:?}");
    let g = two.orbit_of(two.branch.points.last().unwrap()).unwrap();
    let max = |o: &PeriodicOrbit| {
        (o.starts.iter())
            .map(|x| x[0])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    assert!(
        (max(&first) - max(&g)).abs() < 1e-8,
        "{} {}",
        max(&first),
        max(&g)
    );
    assert!(
        (back.branch.points.last().unwrap().params[0] - 0.5).abs() < 1e-9,
        "{:?}",
        back.branch.end
    );
}
