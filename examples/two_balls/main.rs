//! Codimension-two points on two-parameter curves through hycont's public API, on two balls
//! bouncing on vibrating tables driven by one forcing (`model.rs`): ball 1's fold (SN) and
//! period doubling (PD) on the branch in the amplitude `a`, their curves in `(a, e2)` with the
//! points where ball 2's multipliers meet them (LPPD, R1, R2, LPNS, PDNS), the other curve
//! through a fold-flip point in one call, and the whole diagram (every PD switched at, the
//! cascade's ratios) in one call. Located points are printed next to their closed forms
//! (derived in `tests/integration/codim2_points.rs`; omega = 1):
//! `a_SN(e, g) = pi g (1 - e) / (1 + e)`, `a_PD(e, g) = g F(e)`,
//! `F(e) = sqrt(4 (1 + e^2)^2 / (1 + e)^4 + pi^2 (1 - e)^2 / (1 + e)^2)`.
//!
//! Run with `cargo run --release --example two_balls`.

mod model;

use hycont::hycont_continuation::{
    CurveSpec, DiagramSettings, OrbitBranch, OrbitRun, RunDirection, SpecialKind,
};
use model::{A, E1, E2, G1, TwoBalls, a_pd, a_sn, bisect, orbit};
use std::f64::consts::PI;

/// Ball 1's special point of `kind` at `a_ref` on the branch in `a` through `a0`.
fn ball_one(
    run: &mut OrbitRun<'_, TwoBalls>,
    (a0, e2, g2): (f64, f64, f64),
    kind: SpecialKind,
    a_ref: f64,
) -> Result<(OrbitBranch, usize), Box<dyn std::error::Error>> {
    let branch = run.run("period-1", &orbit(a0, e2, g2), RunDirection::Both)?;
    let label = branch
        .special(kind)
        .find(|s| (s.point[A] - a_ref).abs() < 1e-6)
        .ok_or("no such point of ball 1")?
        .point
        .label;
    Ok((branch, label))
}

fn print_points(curve: &OrbitBranch) {
    for s in &curve.branch.special_points {
        if !matches!(s.kind, SpecialKind::EndPoint) {
            println!(
                "  {:>4} at e2 = {:.10} (a = {:.10}), multiplier {:?}",
                s.kind.label(),
                s.point[E2],
                s.point[A],
                s.critical
            );
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut run = OrbitRun::new(&TwoBalls, A)?;
    run.bounds(0.3, 3.0);

    // Ball 1's fold curve (the line a = a_SN(e1, g1)) in (a, e2), with g2 = 1.
    let a_fold = a_sn(E1, G1);
    let (branch, sn) = ball_one(
        &mut run,
        (1.1 * a_fold, 0.65, 1.0),
        SpecialKind::Fold,
        a_fold,
    )?;
    let spec = CurveSpec::new(E2).bounds(0.56, 0.95);
    let fold = run.curve_at("SN", &branch, sn, &spec)?;
    println!(
        "fold curve of ball 1 (g2 = 1), {} points:",
        fold.branch.points.len()
    );
    print_points(&fold);
    let lppd = bisect(|e| a_pd(e, 1.0) - a_fold, 0.6, 0.99);
    println!("  closed form: LPPD at e2 = {lppd:.10}");

    // The other curve through the fold-flip point: ball 2's period doubling, a = g2 F(e2).
    let at = fold.first(SpecialKind::FoldFlip)?.point.label;
    let pd2 = run.curve_through("PD", &fold, at, &spec)?;
    let worst = pd2
        .branch
        .points
        .iter()
        .map(|p| (p[A] - a_pd(p[E2], 1.0)).abs())
        .fold(0.0, f64::max);
    println!(
        "ball 2's PD curve through it: {} points, largest |a - g2 F(e2)| = {worst:.1e}",
        pd2.branch.points.len()
    );

    // Ball 1's PD curve (a = a_PD(e1, g1)) with g2 = 1.2: ball 2's period doubling is R2.
    let a_flip = a_pd(E1, G1);
    let (branch, pd) = ball_one(
        &mut run,
        (0.95 * a_flip, 0.75, 1.2),
        SpecialKind::PeriodDoubling,
        a_flip,
    )?;
    let flip = run.curve_at("PD", &branch, pd, &CurveSpec::new(E2).bounds(0.58, 0.9))?;
    println!(
        "period-doubling curve of ball 1 (g2 = 1.2), {} points:",
        flip.branch.points.len()
    );
    print_points(&flip);
    let r2 = bisect(|e| a_pd(e, 1.2) - a_flip, 0.57, 0.9);
    println!("  closed form: R2 at e2 = {r2:.10}");

    // The whole diagram in a at e2 = 0.65, g2 = 1, one call: each ball's cascade.
    let settings = DiagramSettings {
        depth: 3,
        ..DiagramSettings::default()
    };
    let diagram = run.diagram("period-1", &orbit(1.3, 0.65, 1.0), &settings)?;
    println!("diagram: {} branches", diagram.branches.len());
    for c in diagram.cascades() {
        println!(
            "  cascade: PD at a = {:.8?}, ratios {:.3?}",
            c.doublings,
            c.ratios()
        );
    }
    println!(
        "  closed forms of the first doublings: a_PD(e2 = 0.65) = {:.8}, a_PD(e1) = {:.8} \
         (pi/3 = {:.8} is ball 1's fold)",
        a_pd(0.65, 1.0),
        a_flip,
        PI / 3.0
    );
    Ok(())
}
