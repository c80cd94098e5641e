//! Switching signature at a grazing (`OrbitRun::switch_at` at a GR point, and whole diagrams
//! through it), on the symmetric two-sided impact oscillator (`examples/symmetric_branch`):
//! its symmetric branch in the forcing amplitude `a` ends (at `a ~ 1.36`) where the flight
//! between the impacts dips to the other wall, an interior turning point of the flight
//! touching that wall. Beyond, the orbits impact there too: the switch splits the flight at
//! the turning point and inserts the impact (the wall's reset leads back into the one mode,
//! so no zero-length segment).
//!
//! References: each orbit of the new branch, simulated from inside its first segment for one
//! period, returns to itself (1e-8 where the new impact's speed is at least 0.1; nearer the
//! grazing the return is ill-conditioned, 5e-6 at speed 0.003, so 1e-4 there: the simulator
//! finds the impacts on its own), with one impact more per half period than the old
//! signature's; at the switch point the new impact's
//! velocity is zero (the grazing) and grows along the branch; the branch's orbits are
//! physical (the suites re-check every point, `invariants`). The other way, a tangential
//! impact removed (`join_at_grazing`): back from the family beyond, and below the branch's
//! other grazing, where the orbits miss the walls and follow the closed form of the harmonic
//! response.

use crate::model_symmetric_branch as pair;

use hycont::Error as CoreError;
use hycont::hycont_continuation::{
    DiagramSettings, EndReason, OrbitBranch, OrbitRun, RunDirection, SpecialKind, SwitchOutcome,
};
use hycont::orbit::{CollocationSettings, JoinAt, OrbitMethod, join_at_grazing};
use hycont::orbit::{PeriodicOrbit, SegmentEnd};
use hycont::{HybridSystem, SimulationSettings, Simulator};
use pair::{A, FREE, ImpactPair};

/// The symmetric orbit at a = 1 (omega 0.6, k 1, c 0.1, d 1, e 0.8), one impact per wall.
fn symmetric_orbit() -> PeriodicOrbit {
    pair::find_symmetric(&[1.0, 0.6, 1.0, 0.1, 1.0, 0.8])
        .unwrap()
        .full
        .orbit
}

fn run() -> OrbitRun<'static, ImpactPair> {
    let mut run = OrbitRun::new(&ImpactPair, A).unwrap();
    run.bounds(0.05, 3.0);
    run
}

/// How far the orbit, simulated for a period from the middle of its first segment, is from
/// where it started, and the impacts on the way ([`PeriodicOrbit::simulated_return`]).
fn returns(orbit: &PeriodicOrbit) -> (f64, usize) {
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let back = orbit.simulated_return(&ImpactPair, &settings).unwrap();
    (back.gap, back.events)
}

/// Impacts per period by `orbit`'s signature (segments that end at an event: both of the
/// pair's events are wall impacts). At a grazing orbit this is the reference: a simulation of
/// it may or may not register the tangential touch of the wall as impacts (it did, or did not,
/// for grazing points located 1e-11 apart).
fn impacts(orbit: &PeriodicOrbit) -> usize {
    orbit
        .signature
        .segments()
        .iter()
        .filter(|s| matches!(s.end, SegmentEnd::Event(_)))
        .count()
}

/// The state just before the new impact (the end of segment `k` of `orbit`), simulated.
fn impact_state(orbit: &PeriodicOrbit, k: usize) -> Vec<f64> {
    let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-12).atol(1e-13)).unwrap();
    sim.run(
        &ImpactPair,
        FREE,
        0.0,
        &orbit.starts[k],
        &orbit.params,
        orbit.durations[k] * (1.0 - 1e-9),
    )
    .unwrap()
    .state_final
}

/// The wall velocity of the new impact (the end of segment `k` of `orbit`).
fn impact_speed(orbit: &PeriodicOrbit, k: usize) -> f64 {
    impact_state(orbit, k)[1].abs()
}

/// How far past the wall the flight would turn without the new impact (at the end of segment
/// `k`): meeting it at speed $v$ while decelerating at $|\ddot x|$, it turns $v^2 / (2
/// |\ddot x|)$ beyond it. Zero at the grazing; about the distance past it in the amplitude.
fn penetration(orbit: &PeriodicOrbit, k: usize) -> f64 {
    let x = impact_state(orbit, k);
    let mut f = [0.0; 4];
    ImpactPair.vector_field(FREE, &x, &orbit.params, &mut f);
    x[1] * x[1] / (2.0 * f[1].abs())
}

#[test]
fn the_family_beyond_an_interior_grazing_impacts_there() {
    let mut run = run();
    let symmetric = run
        .run("symmetric", &symmetric_orbit(), RunDirection::Both)
        .unwrap();
    let grazings: Vec<f64> = symmetric
        .special(SpecialKind::Grazing)
        .map(|s| s.point[A])
        .collect();
    assert_eq!(grazings.len(), 2, "{grazings:?}");
    let dip = symmetric
        .special(SpecialKind::Grazing)
        .max_by(|a, b| a.point[A].total_cmp(&b.point[A]))
        .unwrap();
    let beyond: OrbitBranch = run
        .switch_at("beyond", &symmetric, dip.point.label, RunDirection::Up)
        .unwrap();
    let points = &beyond.branch.points;
    assert!(points.len() > 20, "{:?}", beyond.branch.end);
    // It starts at the grazing orbit, in the signature with one more impact per half.
    assert!((points[0][A] - dip.point[A]).abs() < 1e-10);
    let old = symmetric.orbit_of(&dip.point).unwrap();
    let first = beyond.orbit_of(&points[0]).unwrap();
    assert_eq!(first.segment_count(), old.segment_count() + 2);
    // The new impact (the end of each half's first segment) starts at zero speed and grows:
    // at the grazing to the location's tolerance (1e-10 in arclength), the flight's turning
    // point at most about that past the wall (its speed grows as the square root of that
    // distance: a few 1e-6 at 1e-11).
    let k = 0;
    assert!(penetration(&first, k) < 1e-10, "{}", penetration(&first, k));
    let later = beyond.orbit_of(&points[10]).unwrap();
    assert!(impact_speed(&later, k) > 1e-3);
    // Every orbit beyond the start returns to itself with its impacts found by simulation.
    let old_impacts = impacts(&old);
    for p in &points[1..] {
        let orbit = beyond.orbit_of(p).unwrap();
        let (gap, impacts) = returns(&orbit);
        // Near the grazing the return is ill-conditioned (a slow impact's time moves with the
        // rounding of its approach): checked to 1e-8 where the new impact is no longer slow.
        let tol = if impact_speed(&orbit, k) >= 0.1 {
            1e-8
        } else {
            1e-4
        };
        assert!(gap < tol, "a = {}: gap {gap:e}", p[A]);
        assert_eq!(impacts, old_impacts + 2, "a = {}", p[A]);
    }
}

/// The amplitude of the harmonic response of `x'' + c x' + k x = a sin(omega t)`, the
/// oscillator between the walls while it does not reach them: `x = X sin(omega t + phi)` with
/// `X = a / sqrt((k - omega^2)^2 + (c omega)^2)` (substitute; the transient decays for
/// `c > 0`), so that `x^2 + (v / omega)^2 = X^2` at every point of the orbit. It grazes the
/// walls where `X = d`: `a_g = d sqrt((k - omega^2)^2 + (c omega)^2)`.
fn harmonic_amplitude(p: &[f64]) -> f64 {
    let (a, omega, k, c) = (p[0], p[1], p[2], p[3]);
    a / ((k - omega * omega).powi(2) + (c * omega).powi(2)).sqrt()
}

/// The symmetric branch's other grazing, at small forcing, is a tangential impact: the
/// impacts' speed falls to zero as the amplitude falls to `d`. Switched there
/// (`join_at_grazing`: the orbit's only events removed, the orbit closed through a section),
/// the branch beyond is the harmonic response that misses the walls, down to the bound: its
/// start at the closed form's `a_g`, every orbit on the closed form's circle
/// `x^2 + (v / omega)^2 = X^2` (1e-9) and returning to itself by simulation with no impact;
/// by shooting and by collocation.
#[test]
fn below_a_tangential_impact_the_orbits_miss_the_walls() {
    for method in [
        OrbitMethod::default(),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        below_a_tangential_impact_by(method);
    }
}

fn below_a_tangential_impact_by(method: OrbitMethod) {
    let mut run = run();
    run.method(method);
    let symmetric = run
        .run("symmetric", &symmetric_orbit(), RunDirection::Both)
        .unwrap();
    let vanishing = symmetric
        .special(SpecialKind::Grazing)
        .min_by(|a, b| a.point[A].total_cmp(&b.point[A]))
        .unwrap();
    let free = run
        .switch_at("free", &symmetric, vanishing.point.label, RunDirection::Up)
        .unwrap();
    let points = &free.branch.points;
    let a_g = vanishing.point[A] / harmonic_amplitude(&vanishing.point.params);
    assert!((vanishing.point[A] - a_g).abs() < 1e-9, "{a_g}");
    assert!((points[0][A] - a_g).abs() < 1e-9);
    assert!(points.len() > 10, "{:?}", free.branch.end);
    assert!(points[1..].iter().all(|p| p[A] < a_g));
    assert!((points.last().unwrap()[A] - 0.05).abs() < 1e-9);
    for p in &points[1..] {
        let orbit = free.orbit_of(p).unwrap();
        let omega = p.params[1];
        for x in &orbit.starts {
            let radius = (x[0] * x[0] + (x[1] / omega).powi(2)).sqrt();
            assert!(
                (radius - harmonic_amplitude(&p.params)).abs() < 1e-9,
                "a = {}: {radius}",
                p[A]
            );
        }
        let (gap, impacts) = returns(&orbit);
        assert!(gap < 1e-8, "a = {}: gap {gap:e}", p[A]);
        assert_eq!(impacts, 0, "a = {}", p[A]);
    }
}

/// Back along the branch beyond the dip's grazing, the new impact's speed falls to zero at
/// the grazing parameter (a tangential impact, GR, located where the symmetric branch
/// grazed, 1e-8); switched there, the impact is removed and the branch is the symmetric
/// branch again: its first orbit is the symmetric branch's grazing orbit (1e-8) and it ends
/// at the other grazing, the closed form's `a_g` (1e-9), every orbit returning to itself
/// with the old signature's impacts (1e-8 where the impacts' speed is at least 0.1).
#[test]
fn back_through_the_grazing_the_impact_is_removed() {
    let mut run = run();
    let symmetric = run
        .run("symmetric", &symmetric_orbit(), RunDirection::Both)
        .unwrap();
    let dip = symmetric
        .special(SpecialKind::Grazing)
        .max_by(|a, b| a.point[A].total_cmp(&b.point[A]))
        .unwrap();
    let beyond = run
        .switch_at("beyond", &symmetric, dip.point.label, RunDirection::Up)
        .unwrap();
    let p10 = &beyond.branch.points[10];
    let toward = if p10[A] > dip.point[A] {
        RunDirection::Down
    } else {
        RunDirection::Up
    };
    let back = run
        .restart("back", &beyond, p10.label, Some(toward))
        .unwrap();
    let gr = back.special(SpecialKind::Grazing).last().unwrap();
    assert!((gr.point[A] - dip.point[A]).abs() < 1e-8);
    let again = run
        .switch_at("again", &back, gr.point.label, RunDirection::Up)
        .unwrap();
    let first = again.orbit_of(&again.branch.points[0]).unwrap();
    let old = symmetric.orbit_of(&dip.point).unwrap();
    assert_eq!(first.signature, old.signature);
    for (x, y) in first
        .starts
        .iter()
        .flatten()
        .zip(old.starts.iter().flatten())
    {
        assert!((x - y).abs() < 1e-8, "{x} {y}");
    }
    for (x, y) in first.durations.iter().zip(&old.durations) {
        assert!((x - y).abs() < 1e-8, "{x} {y}");
    }
    let end = again.branch.points.last().unwrap();
    let a_g = end[A] / harmonic_amplitude(&end.params);
    assert_eq!(
        again.branch.end,
        EndReason::Inadmissible(SpecialKind::Grazing)
    );
    assert!((end[A] - a_g).abs() < 1e-9, "{} {a_g}", end[A]);
    let old_impacts = impacts(&old);
    // The last point is the tangential grazing itself, where a simulation may miss the
    // impacts of zero speed.
    let inner = &again.branch.points[1..again.branch.points.len() - 1];
    for p in inner {
        let orbit = again.orbit_of(p).unwrap();
        let (gap, impacts) = returns(&orbit);
        // Ill-conditioned near the tangential impact at the end, as beyond the dip.
        let tol = if impact_speed(&orbit, 0) >= 0.1 {
            1e-8
        } else {
            1e-4
        };
        assert!(gap < tol, "a = {}: gap {gap:e}", p[A]);
        assert_eq!(impacts, old_impacts, "a = {}", p[A]);
    }
}

/// A whole diagram goes on through both grazings (GR is switched at by default): the
/// symmetric branch's dip (an impact inserted) and its tangential impacts (removed: the
/// harmonic response); both switches are followed, and the saved diagram passes its check.
#[test]
fn a_diagram_crosses_the_grazing() {
    let diagram = run()
        .diagram("symmetric", &symmetric_orbit(), &DiagramSettings::default())
        .unwrap();
    let at_grazing: Vec<_> = diagram
        .switches
        .iter()
        .filter(|r| r.kind == SpecialKind::Grazing && r.branch.0 == 0)
        .collect();
    assert_eq!(at_grazing.len(), 2, "{:?}", diagram.switches);
    assert!(
        at_grazing
            .iter()
            .all(|r| matches!(r.outcome, SwitchOutcome::Followed(_))),
        "{at_grazing:?}"
    );
    run().check_diagram(&diagram).unwrap();
}

/// `join_at_grazing` away from a grazing: typed errors naming the segment (an impact at speed
/// 1.5 is no tangential impact, a segment of positive duration has not collapsed, segments
/// that do not exist, a join across the orbit's closure).
#[test]
fn joins_away_from_a_grazing_are_refused() {
    let full = symmetric_orbit();
    let half = full.half_of_symmetric(&ImpactPair, 1e-6).unwrap();
    let refused =
        |orbit: &PeriodicOrbit, at: JoinAt, segment: usize, words: &str| match join_at_grazing(
            &ImpactPair,
            orbit,
            at,
        ) {
            Err(CoreError::InvalidSignature { segment: s, reason }) => {
                assert_eq!(s, segment, "{reason}");
                assert!(reason.contains(words), "{reason}");
            }
            other => panic!("{at:?}: {other:?}"),
        };
    refused(
        &half,
        JoinAt::TangentialImpact { segment: 0 },
        0,
        "not a grazing",
    );
    refused(
        &full,
        JoinAt::TangentialImpact { segment: 0 },
        0,
        "not a grazing",
    );
    refused(&half, JoinAt::Collapsed { segment: 0 }, 0, "not zero");
    // A half orbit returns only through its symmetry: its simulated return is refused.
    let settings = SimulationSettings::default();
    assert!(matches!(
        half.simulated_return(&ImpactPair, &settings),
        Err(CoreError::InvalidSignature { .. })
    ));
    refused(&half, JoinAt::Collapsed { segment: 3 }, 3, "has 1 segments");
    refused(
        &full,
        JoinAt::TangentialImpact { segment: 1 },
        1,
        "across the orbit's closure",
    );
}

/// Written with interior points at the extrema of x (`with_interior_points`: segments end
/// where v = 0), the symmetric branch's dip is a segment's end that touches the other wall
/// (`Touch::End`), and the switch replaces that end by the impact (`split_at_grazing` at a
/// segment's end). The family beyond is the one the plain signature's switch finds: the same
/// grazing parameter (1e-8) and the same end of the branch and special points along it (1e-7
/// in a, each located to the run's accuracy), every orbit returning to itself by simulation
/// (to 1e-4: near the grazing the return is ill-conditioned, see the module docs).
#[test]
fn a_grazing_at_a_segments_end_is_split_there() {
    let mut run = run();
    let beyond_of = |run: &mut OrbitRun<'static, ImpactPair>, start: &PeriodicOrbit| {
        let symmetric = run.run("symmetric", start, RunDirection::Both).unwrap();
        let dip = symmetric
            .special(SpecialKind::Grazing)
            .max_by(|a, b| a.point[A].total_cmp(&b.point[A]))
            .unwrap()
            .clone();
        let beyond = run
            .switch_at("beyond", &symmetric, dip.point.label, RunDirection::Up)
            .unwrap();
        (dip.point[A], beyond)
    };
    let plain = symmetric_orbit();
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let interior = plain
        .with_interior_points(&ImpactPair, 1, 0.0, &settings)
        .unwrap();
    assert!(interior.segment_count() > plain.segment_count());
    let (a_plain, by_plain) = beyond_of(&mut run, &plain);
    let (a_interior, by_interior) = beyond_of(&mut run, &interior);
    assert!(
        (a_plain - a_interior).abs() < 1e-8,
        "{a_plain} {a_interior}"
    );
    let last = |b: &OrbitBranch| b.branch.points.last().unwrap()[A];
    assert_eq!(by_plain.branch.end, by_interior.branch.end);
    assert!((last(&by_plain) - last(&by_interior)).abs() < 1e-7);
    let specials = |b: &OrbitBranch| -> Vec<(String, f64)> {
        b.branch
            .special_points
            .iter()
            .map(|s| (s.kind.label().to_string(), s.point[A]))
            .collect()
    };
    let (sp, si) = (specials(&by_plain), specials(&by_interior));
    assert!(!sp.is_empty());
    assert_eq!(sp.len(), si.len(), "{sp:?} {si:?}");
    for ((kp, ap), (ki, ai)) in sp.iter().zip(&si) {
        assert_eq!(kp, ki);
        assert!((ap - ai).abs() < 1e-7, "{kp}: {ap} {ai}");
    }
    for p in &by_interior.branch.points[1..by_interior.branch.points.len() - 1] {
        let (gap, _) = returns(&by_interior.orbit_of(p).unwrap());
        assert!(gap < 1e-4, "a = {}: gap {gap:e}", p[A]);
    }
}
