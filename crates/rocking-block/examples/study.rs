//! The rocking block's symmetric orbits continued in omega on their half orbit, and the
//! asymmetric branch switched on at the first symmetry-breaking branch point (BP1, Fig. 3 of
//! the study), with the library API: `OrbitContinuation` on a half orbit, `full_branch` and
//! `full_orbit_problem`, `branch_switch_direction`, `continue_along`.
//!
//! Run with `cargo run --release --example symmetric_branch`.

use hycont::hycont_continuation::observe::Silent;
use hycont::hycont_continuation::{
    ContinuationSettings, OrbitContinuation, SpecialKind, branch_switch_direction, continue_along,
    continue_branch,
};
use hycont::rocking_block::continuation::{default_method, events, measures};
use hycont::rocking_block::orbits::{OrbitKind, orbit};
use hycont::rocking_block::{OMEGA, Parameters, RockingBlock};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let params = Parameters::new(1.3, 0.66);
    let full = orbit(&params, OrbitKind::Symmetric, None)?.solution.orbit;
    // The half orbit: the first half of the segments, closed by x_K = S x_0.
    let half = full.half_of_symmetric(&RockingBlock, 1e-8)?;
    let (mut cp, u0) = OrbitContinuation::new(
        &RockingBlock,
        &half,
        &default_method(),
        OMEGA,
        measures(),
        events(&params),
    )?;
    let settings = ContinuationSettings::default()
        .parameter_bounds(0.5, 4.0)
        .steps(0.02, 1e-8, 0.1);
    // Down in omega from 1.3: BP1 (the half map's multiplier through -1), then SN1 and GR1.
    let t = std::time::Instant::now();
    let down = continue_branch(&mut cp, "symmetric", &u0, -1.0, &settings, &mut Silent)?;
    println!(
        "symmetric branch (half orbit): {} points in {:?}, ended {:?}",
        down.points.len(),
        t.elapsed(),
        down.end
    );
    for s in &down.special_points {
        println!(
            "  {} at omega = {:.10} (located {}), unstable multipliers {}",
            s.kind.label(),
            s.point.params[0],
            s.located,
            s.point.unstable
        );
    }
    // Branch switching at BP1 on the full orbit's problem.
    let down = cp.full_branch(&down);
    let bp = down
        .special(SpecialKind::BranchPoint)
        .next()
        .ok_or("no branch point")?;
    let mut full_cp = cp.full_orbit_problem(measures())?;
    let phi = branch_switch_direction(&mut full_cp, &bp.point.u, &bp.point.tangent)?;
    let asym = continue_along(
        &mut full_cp,
        "asymmetric",
        &bp.point.u,
        &phi,
        1.0,
        &settings.clone().stop_at(SpecialKind::BranchPoint),
        &mut Silent,
    )?;
    println!(
        "asymmetric branch from BP1: {} points, ended {:?}",
        asym.points.len(),
        asym.end
    );
    for s in &asym.special_points {
        println!("  {} at omega = {:.10}", s.kind.label(), s.point.params[0]);
    }
    Ok(())
}
