//! The study through hycont's public API, with the same calls as any other system (compare
//! `examples/vibrating_table` in the `hycont` package): the symmetric orbit at
//! (omega, alpha) = (1.3, 0.66), its branch in omega (continued on the half orbit), the
//! asymmetric branch switched on at the first symmetry-breaking branch point BP1, and the fold
//! curve from SN1 in (omega, alpha) with a user point where it crosses omega = 1.3 (Fig. 4's
//! fold).
//!
//! Run with `cargo run --release -p rocking-block --example study`.

use hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont_core::orbit::{Extremum, GrazingMargin, OrbitMethod, ShootingSettings};
use rocking_block::orbits::symmetric_orbit;
use rocking_block::{ALPHA, IMPACT_MINUS, IMPACT_PLUS, OMEGA, Parameters, RockingBlock};
use std::f64::consts::FRAC_PI_2;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let params = Parameters::new(1.3, 0.66);
    let start = symmetric_orbit(&params)?.solution.orbit;

    let mut run = OrbitRun::new(&RockingBlock, OMEGA)?;
    run.method(OrbitMethod::Shooting(ShootingSettings {
        rtol: 1e-10,
        atol: 1e-12,
    }))
    .bounds(0.5, 4.0)
    .steps(0.02, 1e-8, 0.1);
    let amp = run.add_measure("amp", Extremum::max_abs(0))?;
    let margin = run.add_measure(
        "grazing_margin",
        GrazingMargin::new([IMPACT_PLUS, IMPACT_MINUS]).cap(FRAC_PI_2),
    )?;
    run.bound(amp, -FRAC_PI_2, FRAC_PI_2)?
        .add_event(amp, params.static_boundary(), SpecialKind::BoundaryTouch)?
        .add_terminal_event(margin, 0.0, SpecialKind::Grazing)?;

    let t = std::time::Instant::now();
    let symmetric = run.run("symmetric", &start, RunDirection::Both)?;
    println!(
        "symmetric branch: {} points in {:?}",
        symmetric.branch.points.len(),
        t.elapsed()
    );
    for s in &symmetric.branch.special_points {
        println!(
            "  {} at omega = {:.10} (amp {:.6})",
            s.kind, s.point[OMEGA], s.point[amp]
        );
    }

    let bp1 = symmetric
        .special(SpecialKind::BranchPoint)
        .next()
        .ok_or("no BP")?;
    run.stop_at(SpecialKind::BranchPoint);
    let asymmetric = run.switch_at("asymmetric", &symmetric, bp1.point.label, RunDirection::Up)?;
    println!(
        "asymmetric branch: {} points, ended {:?}",
        asymmetric.branch.points.len(),
        asymmetric.branch.end
    );
    for s in &asymmetric.branch.special_points {
        println!("  {} at omega = {:.10}", s.kind, s.point[OMEGA]);
    }

    let sn1 = symmetric.special(SpecialKind::Fold).next().ok_or("no SN")?;
    let spec = CurveSpec::new(ALPHA)
        .bounds(0.01, 1.06)
        .user_points(OMEGA, [1.3]);
    let fold = run.curve_at("SN", &symmetric, sn1.point.label, &spec)?;
    for s in fold.special(SpecialKind::UserPoint) {
        println!(
            "fold curve at omega = 1.3: alpha = {:.10} (Fig. 4: 0.3664648694)",
            s.point[ALPHA]
        );
    }
    Ok(())
}
