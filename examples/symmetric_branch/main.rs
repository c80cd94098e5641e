//! Symmetric orbits through hycont's public API, on a symmetric two-sided impact oscillator
//! (walls at `x = -d` and `x = +d`, `model.rs`): the Z2 symmetry `(x, v, r, s) -> -(x, v, r, s)`
//! swaps the walls and, with the forcing phase carried by the oscillator pair `(r, s)`, shifts
//! the forcing by half a period, so it is linear (a wrapped phase angle would not be).
//!
//! 1. The symmetric orbit with one impact on each wall is found from seeds on the left wall
//!    (`find_symmetric_orbit` on the half orbit's signature, one segment from a left impact to
//!    a right one, closed through the symmetry).
//! 2. Its branch in the forcing amplitude `a` is continued on the half orbit (half the
//!    unknowns; the half map's multiplier -1 marks where the symmetry breaks, BP); both ends
//!    are default GR points: where the impacts vanish (the closed form
//!    `a = d sqrt((k - w^2)^2 + (c w)^2)`) and where the flight between impacts dips to the
//!    other wall (its physical end).
//! 3. At the BP the asymmetric branch is switched on in one call.
//!
//! Run with `cargo run --release --example symmetric_branch`.

mod model;

use hycont::hycont_continuation::{OrbitRun, RunDirection, SpecialKind};
use model::{A, ImpactPair, OMEGA, find_symmetric};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (omega, k, c, d, e) = (0.6_f64, 1.0_f64, 0.1_f64, 1.0_f64, 0.8);
    let graze = d * ((k - omega * omega).powi(2) + (c * omega).powi(2)).sqrt();
    let p = [1.0, omega, k, c, d, e];

    // The half orbit: one free flight from just after a left impact to a right impact; the
    // symmetry maps its end (after the right impact's reset) onto its start (`find_symmetric`
    // in model.rs: the signature, seeds on the left wall, the search).
    let found = find_symmetric(&p)?;
    println!(
        "symmetric orbit at a = 1, omega = {}: impact velocity {:.6}, half-map multipliers {:?}",
        found.half.params[OMEGA.index()],
        found.half.starts[0][1] / e,
        found.half_floquet.multipliers
    );

    // Its branch in a, on the half orbit, both ways to the default GR points.
    let mut run = OrbitRun::new(&ImpactPair, A)?;
    run.bounds(0.05, 3.0);
    let branch = run.run("symmetric", &found.full.orbit, RunDirection::Both)?;
    for s in &branch.branch.special_points {
        println!("{} at a = {:.12}", s.kind, s.point[A]);
    }
    let gr = branch.first(SpecialKind::Grazing)?;
    println!(
        "the impacts vanish at a = {:.12} (closed form {graze:.12})",
        gr.point[A]
    );

    // The asymmetric branch through the symmetry-breaking point.
    let bp = branch.first(SpecialKind::BranchPoint)?;
    let asymmetric = run.switch_at("asymmetric", &branch, bp.point.label, RunDirection::Both)?;
    let asymmetric_orbits = asymmetric
        .branch
        .points
        .iter()
        .filter(|p| !run_orbit_is_symmetric(&asymmetric, p))
        .count();
    println!(
        "asymmetric branch: {} points ({} of them asymmetric orbits), ends {:?}",
        asymmetric.branch.points.len(),
        asymmetric_orbits,
        asymmetric.branch.end
    );
    Ok(())
}

/// Whether the orbit at a point is symmetric (to 1e-6).
fn run_orbit_is_symmetric(
    branch: &hycont::hycont_continuation::OrbitBranch,
    point: &hycont::hycont_continuation::BranchPoint,
) -> bool {
    branch
        .orbit_of(point)
        .is_ok_and(|o| o.is_symmetric(&ImpactPair, 1e-6))
}
