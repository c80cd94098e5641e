//! The rocking block across grazing: where the lower symmetric orbit's interior dip touches
//! phi = 0 (GR1 in omega at alpha = 0.66, GR2 in alpha at omega = 1.3), Figs. 3 and 4 switch
//! to the family with the dip's extra impacts ([`GRAZED`]).
//!
//! References: each orbit of the new family, simulated by the event-driven simulator from
//! inside its first segment for one period (impacts found by the simulator on its own),
//! returns to itself, with two impacts more per half period than the grazing orbit: the dip
//! reaches phi = 0, the block rocks briefly on its other corner (the zero-length flight at the
//! grazing) and impacts back. Where the new impacts' speed is at least 1e-2 the return is
//! checked to 1e-8 (relative to the state's size, about 1); nearer the grazing a slow
//! impact's time moves with the rounding of its approach, and the return to 1e-5.
//! `continue --switch` at the GR of a saved run finds the same branch.

use crate::common;

use common::{RunOk, bin, fails, scratch};
use hycont_continuation::SpecialKind;
use hycont_continuation::observe::Silent;
use hycont_continuation::{BranchPoint, EndReason, OrbitBranch, RunDirection};
use hycont_core::SimulationSettings;
use hycont_core::orbit::{PeriodicOrbit, SegmentEnd};
use rocking_block::block::Block;
use rocking_block::continuation::{AMP, Free, GRAZED, default_method, study_branches, study_run};
use rocking_block::{IMPACT_MINUS, IMPACT_PLUS, RockingBlock};

/// How far the orbit, simulated for a period from the middle of its first segment, is from
/// where it started, and the impacts on the way ([`PeriodicOrbit::simulated_return`]).
fn returns(orbit: &PeriodicOrbit) -> (f64, usize) {
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let back = orbit.simulated_return(&RockingBlock, &settings).unwrap();
    (back.gap, back.events)
}

/// Impacts per period by `orbit`'s signature (its segments that end at an impact). At the
/// grazing orbit itself this is the reference: a simulation of it may or may not register the
/// dip's tangential touch of phi = 0 as two impacts more (it did, or did not, for grazing
/// points located 1e-11 apart).
fn impacts(orbit: &PeriodicOrbit) -> usize {
    orbit
        .signature
        .segments()
        .iter()
        .filter(|s| matches!(s.end, SegmentEnd::Event(e) if e == IMPACT_PLUS || e == IMPACT_MINUS))
        .count()
}

/// The zero-length segments of the grazing orbit (the flights on the other corner).
fn zero_length(orbit: &PeriodicOrbit) -> Vec<usize> {
    (0..orbit.durations.len())
        .filter(|&k| orbit.durations[k] == 0.0)
        .collect()
}

/// Checks that every orbit of `branch` at `points` returns to itself by simulation with
/// `impacts` impacts per period: to 1e-8 where the new impacts (the starts of the zero-length
/// segments `zeros` of its first orbit: after the first, the flight on the other corner starts
/// with the restituted speed) are at least 1e-2 fast, else to 1e-5 (see the module docs).
/// Returns how many were checked to 1e-8.
fn check_returns(
    branch: &OrbitBranch,
    points: &[BranchPoint],
    zeros: &[usize],
    impacts: usize,
) -> usize {
    let q = branch.free;
    let mut checked = 0;
    for p in points {
        let orbit = branch.orbit_of(p).unwrap();
        let speed = zeros
            .iter()
            .map(|&k| orbit.starts[k][1].abs())
            .fold(f64::INFINITY, f64::min);
        let (gap, found) = returns(&orbit);
        let tol = if speed >= 1e-2 { 1e-8 } else { 1e-5 };
        assert!(gap < tol, "{}: gap {gap:e} (speed {speed:e})", p[q]);
        assert_eq!(found, impacts, "{}", p[q]);
        checked += usize::from(speed >= 1e-2);
    }
    checked
}

#[test]
fn figures_3_and_4_go_on_past_grazing_with_the_dips_impacts() {
    let block = Block::default();
    for free in [Free::Omega, Free::Alpha] {
        let branches = study_branches(free, &block, &mut Silent).unwrap();
        let grazed = branches.last().unwrap();
        assert_eq!(grazed.branch.name, GRAZED);
        let parent = &branches[0];
        let gr = parent.special(SpecialKind::Grazing).next().unwrap();
        let q = free.id();
        let points = &grazed.branch.points;
        assert!(points.len() > 10, "{free:?}: {:?}", grazed.branch.end);
        // It starts at the grazing orbit.
        assert!((points[0][q] - gr.point[q]).abs() < 1e-12);
        assert!((points[0][AMP] - gr.point[AMP]).abs() < 1e-12);
        let old = parent.orbit_of(&gr.point).unwrap();
        let first = grazed.orbit_of(&points[0]).unwrap();
        let zeros = zero_length(&first);
        assert_eq!(zeros.len(), 2, "{free:?}: {:?}", first.durations);
        assert_eq!(first.segment_count(), old.segment_count() + 4);
        let old_impacts = impacts(&old);
        // Up to the family's own grazing, where it ends: there another dip touches phi = 0,
        // which the simulation of the located orbit may or may not meet.
        let inner = match grazed.branch.end {
            EndReason::Inadmissible(SpecialKind::Grazing) => &points[1..points.len() - 1],
            _ => &points[1..],
        };
        let checked = check_returns(grazed, inner, &zeros, old_impacts + 4);
        assert!(checked > 5, "{free:?}: {checked} points checked to 1e-8");
        // The family turns back from the grazing (a nonsmooth fold: both families on the side
        // below it), with a branch point, a fold, and a grazing of its own.
        assert!(points[1..].iter().all(|p| p[q] < gr.point[q]));
        for kind in [
            SpecialKind::BranchPoint,
            SpecialKind::Fold,
            SpecialKind::Grazing,
        ] {
            assert!(
                grazed.special(kind).next().is_some(),
                "{free:?}: no {kind:?}"
            );
        }
    }
}

/// `continue --restart RUN --label GR --switch` switches there to the figure's branch past
/// grazing (its special points to 1e-9); at a label that is no BP, PD, GR or DB it exits 2.
#[test]
fn the_cli_switches_at_a_saved_grazing() {
    let dir = scratch("grazing");
    std::fs::create_dir_all(&dir).unwrap();
    let saved = dir.join("symmetric.json");
    bin()
        .args(["continue", "--free", "omega", "--out"])
        .arg(&saved)
        .run_ok();
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&saved).unwrap()).unwrap();
    let specials = run["branch"]["special_points"].as_array().unwrap();
    let label_of = |kind: &str| {
        specials
            .iter()
            .find(|s| s["kind"] == kind)
            .unwrap_or_else(|| panic!("no {kind} in {specials:?}"))["point"]["label"]
            .as_u64()
            .unwrap()
            .to_string()
    };
    let switch = |label: &str| {
        bin()
            .args([
                "continue", "--free", "omega", "--switch", "--json", "--label", label,
            ])
            .arg("--restart")
            .arg(&saved)
            .output()
            .unwrap()
    };
    let out = switch(&label_of("GR"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let fig3 = study_branches(Free::Omega, &Block::default(), &mut Silent).unwrap();
    let grazed = fig3.last().unwrap();
    let mut found = 0;
    for s in &grazed.branch.special_points {
        let near = v["special_points"].as_array().unwrap().iter().any(|o| {
            o["kind"] == s.kind.label()
                && (o["omega"].as_f64().unwrap() - s.point[Free::Omega.id()]).abs() <= 1e-9
        });
        assert!(
            near,
            "{:?} at {} is not in {}",
            s.kind,
            s.point[Free::Omega.id()],
            v["special_points"]
        );
        found += 1;
    }
    assert!(found >= 3);
    fails(&switch(&label_of("SN")), 2, "cannot switch branches");
}

/// Back along the family past GR1 (from its tenth point toward the grazing), the flight on
/// the other corner shrinks to zero length and its two impacts merge into one of zero speed
/// at the grazing parameter (located where the symmetric branch grazed, 1e-8); switched there,
/// the impacts are removed (`join_at_grazing`) and the branch is the lower symmetric branch
/// again: its first orbit is the symmetric branch's grazing orbit (to the two grazings'
/// distance times the orbit's sensitivity to omega), and it finds the
/// symmetric branch's branch point BP1 by continuation from the other side (1e-9).
#[test]
fn back_through_gr1_the_dips_impacts_are_removed() {
    let block = Block::default();
    let free = Free::Omega;
    let branches = study_branches(free, &block, &mut Silent).unwrap();
    let (symmetric, grazed) = (&branches[0], branches.last().unwrap());
    let gr1 = symmetric.special(SpecialKind::Grazing).next().unwrap();
    let bp1 = symmetric.special(SpecialKind::BranchPoint).next().unwrap();
    let q = free.id();
    let mut run = study_run(free, &block.at(1.3, 0.66), free.range(), default_method()).unwrap();
    let p10 = &grazed.branch.points[10];
    let toward = if p10[q] < gr1.point[q] {
        RunDirection::Up
    } else {
        RunDirection::Down
    };
    let back = run
        .restart("back", grazed, p10.label, Some(toward))
        .unwrap();
    let gr = back.special(SpecialKind::Grazing).last().unwrap();
    assert!(
        (gr.point[q] - gr1.point[q]).abs() < 1e-8,
        "{} {}",
        gr.point[q],
        gr1.point[q]
    );
    let again = run
        .switch_at("again", &back, gr.point.label, RunDirection::Up)
        .unwrap();
    let first = again.orbit_of(&again.branch.points[0]).unwrap();
    let old = symmetric.orbit_of(&gr1.point).unwrap();
    assert_eq!(first.signature, old.signature);
    let pairs = first
        .starts
        .iter()
        .flatten()
        .zip(old.starts.iter().flatten());
    let gap = pairs
        .chain(first.durations.iter().zip(&old.durations))
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    // Two grazings, each located to its own accuracy: the orbits differ by the parameters'
    // difference times the orbit's sensitivity to omega (states and durations of order one:
    // a factor below 10).
    let dq = (gr.point[q] - gr1.point[q]).abs();
    assert!(gap <= 10.0 * dq + 1e-10, "{gap:e} for {dq:e}");
    let bp = again.special(SpecialKind::BranchPoint).next().unwrap();
    assert!(
        (bp.point[q] - bp1.point[q]).abs() < 1e-9,
        "{} {}",
        bp.point[q],
        bp1.point[q]
    );
}

/// The family past GR1 grazes in turn (GR1:GR, omega ~ 1.2052): another dip, inside its long
/// flight, touches phi = 0. Switched there, the family with that dip's two impacts as well,
/// up to its own grazing: its orbits return to themselves by simulation (as above; its new
/// impacts stay slow, below 1e-2, so to 1e-5) with four impacts more per period than the
/// family's orbits away from its grazing. There the new family crosses the family whose new flight
/// stays of zero length at a shallow angle: the switch steps along the new family's tangent
/// from the bifurcation equation (stepping orthogonally to the other family, the corrector
/// started outside Newton's basin and the switch failed).
#[test]
fn the_family_past_gr1_grazes_and_goes_on_with_two_more_impacts() {
    let block = Block::default();
    let free = Free::Omega;
    let branches = study_branches(free, &block, &mut Silent).unwrap();
    let grazed = branches.last().unwrap();
    let gr = grazed.special(SpecialKind::Grazing).next().unwrap();
    let q = free.id();
    let mut run = study_run(free, &block.at(1.3, 0.66), free.range(), default_method()).unwrap();
    let beyond = run
        .switch_at("beyond", grazed, gr.point.label, RunDirection::Up)
        .unwrap();
    let points = &beyond.branch.points;
    assert!(points.len() > 5, "{:?}", beyond.branch.end);
    assert!((points[0][q] - gr.point[q]).abs() < 1e-12);
    let old = grazed.orbit_of(&gr.point).unwrap();
    let first = beyond.orbit_of(&points[0]).unwrap();
    assert_eq!(first.segment_count(), old.segment_count() + 4);
    let zeros = zero_length(&first);
    assert_eq!(zeros.len(), 2, "{:?}", first.durations);
    // Counted away from the grazing (at it, the simulator may count the touch as impacts).
    let (_, old_impacts) = returns(&grazed.orbit_of(&grazed.branch.points[5]).unwrap());
    // Up to its own grazing, where it ends (as above).
    assert_eq!(
        beyond.branch.end,
        EndReason::Inadmissible(SpecialKind::Grazing)
    );
    let inner = &points[1..points.len() - 1];
    assert!(inner.len() >= 5, "{} points", inner.len());
    check_returns(&beyond, inner, &zeros, old_impacts + 4);
}
