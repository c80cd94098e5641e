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
//! physical (the suites re-check every point, `invariants`).

#[path = "../examples/symmetric_branch/model.rs"]
#[allow(dead_code)] // the model is shared with the example, which uses all of it
mod pair;

use hycont::hycont_continuation::{
    DiagramSettings, Error, OrbitBranch, OrbitRun, RunDirection, SpecialKind, SwitchOutcome,
};
use hycont::orbit::{
    Closure, PeriodicOrbit, SegmentEnd, SegmentSpec, Signature, SymmetricSearch,
    find_symmetric_orbit,
};
use hycont::{SampleTimes, SimulationSettings, Simulator};
use pair::{A, FREE, ImpactPair, RIGHT};
use std::f64::consts::{PI, TAU};

/// The symmetric orbit at a = 1 (omega 0.6, k 1, c 0.1, d 1, e 0.8), one impact per wall.
fn symmetric_orbit() -> PeriodicOrbit {
    let d = 1.0;
    let p = [1.0, 0.6, 1.0, 0.1, d, 0.8];
    let half = Signature::with_closure(
        &ImpactPair,
        vec![SegmentSpec {
            mode: FREE,
            end: SegmentEnd::Event(RIGHT),
        }],
        Closure::Symmetric,
    )
    .unwrap();
    let seeds = (0..12)
        .flat_map(|i| {
            (0..24).map(move |j| {
                let beta = TAU * f64::from(j) / 24.0;
                vec![-d, 0.1 + 0.25 * f64::from(i), beta.sin(), beta.cos()]
            })
        })
        .collect();
    let search = SymmetricSearch::new(seeds).half_period(PI / 0.6);
    find_symmetric_orbit(&ImpactPair, &half, &p, &search)
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
/// where it started, and the impacts on the way.
fn returns(orbit: &PeriodicOrbit) -> (f64, usize) {
    let period: f64 = orbit.durations.iter().sum();
    let t0 = 0.5 * orbit.durations[0];
    let settings = SimulationSettings::default()
        .rtol(1e-12)
        .atol(1e-13)
        .samples(SampleTimes::new(t0, period));
    let mut sim = Simulator::new(settings).unwrap();
    let x0 = &orbit.starts[0];
    let traj = sim
        .run(
            &ImpactPair,
            FREE,
            0.0,
            x0,
            &orbit.params,
            t0 + period * 1.000_001,
        )
        .unwrap();
    let states: Vec<&[f64]> = traj.samples.iter().map(|(_, _, x)| x).collect();
    let gap = states[0]
        .iter()
        .zip(states[1])
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let impacts = traj
        .events
        .iter()
        .filter(|e| e.t > t0 && e.t <= t0 + period)
        .count();
    (gap, impacts)
}

/// The wall velocity of the new impact (the end of segment `k` of `orbit`).
fn impact_speed(orbit: &PeriodicOrbit, k: usize) -> f64 {
    let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-12).atol(1e-13)).unwrap();
    let traj = sim
        .run(
            &ImpactPair,
            FREE,
            0.0,
            &orbit.starts[k],
            &orbit.params,
            orbit.durations[k] * (1.0 - 1e-9),
        )
        .unwrap();
    traj.state_final[1].abs()
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
    // The new impact (the end of each half's first segment) starts at zero speed and grows.
    let k = 0;
    assert!(
        impact_speed(&first, k) < 1e-6,
        "{}",
        impact_speed(&first, k)
    );
    let later = beyond.orbit_of(&points[10]).unwrap();
    assert!(impact_speed(&later, k) > 1e-3);
    // Every orbit beyond the start returns to itself with its impacts found by simulation.
    let (_, old_impacts) = returns(&old);
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
    // The tangential impact at the other end is not (yet) switched at: a typed error.
    let vanishing = symmetric
        .special(SpecialKind::Grazing)
        .min_by(|a, b| a.point[A].total_cmp(&b.point[A]))
        .unwrap();
    let e = run
        .switch_at("other", &symmetric, vanishing.point.label, RunDirection::Up)
        .unwrap_err();
    assert!(
        matches!(e, Error::Core(_) | Error::SwitchFailed { .. }),
        "{e}"
    );
}

/// A whole diagram goes on through the grazing (GR is switched at by default): the branch
/// beyond is in it, switched on at the symmetric branch's dip; the tangential impact's GR is
/// recorded as a failed switch, and the diagram goes on.
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
            .any(|r| matches!(r.outcome, SwitchOutcome::Followed(_))),
        "{at_grazing:?}"
    );
    assert!(
        at_grazing
            .iter()
            .any(|r| matches!(r.outcome, SwitchOutcome::Failed(_))),
        "{at_grazing:?}"
    );
    run().check_diagram(&diagram).unwrap();
}
