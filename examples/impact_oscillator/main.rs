//! COCO's impact oscillator (Recipes for Continuation, Example 15.2) through hycont's public
//! API: an impacting orbit read off a simulation is continued down in the forcing amplitude
//! `A` to the grazing where its impact velocity vanishes (the GR point that ends the branch by
//! default), and the grazing curve in `(A, w)` is followed from it in one call. Every point
//! is printed next to the closed form `A = d sqrt((k - w^2)^2 + (c w)^2)`: at a grazing the
//! orbit is the free harmonic response whose amplitude `A / sqrt((k - w^2)^2 + (c w)^2)` is
//! the wall's distance `d` (derived in `tests/integration/grazing_curves.rs`).
//!
//! The curve holds the one condition that attains the admissibility margin at the grazing,
//! here the impact's approach rate (a smooth function of the orbit), not the margin itself
//! (the smallest of several conditions, not smooth where they meet).
//!
//! Run with `cargo run --release --example impact_oscillator`.

mod model;

use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use model::{AMP, ImpactOscillator, W};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (k, c, d) = (1.0_f64, 0.1_f64, 1.0_f64);
    let graze = |w: f64| d * ((k - w * w).powi(2) + (c * w).powi(2)).sqrt();
    // At COCO's p0 = (k, c, A, w, d, e) = (1, 0.1, 1, 1, 1, 0.8), read off a simulation.
    let orbit = model::impacting_orbit()?;

    // The impacting orbits, down in A: the branch ends where the impact velocity vanishes.
    let mut run = OrbitRun::new(&ImpactOscillator, AMP)?;
    run.bounds(0.01, 2.0);
    let branch = run.run("impacting", &orbit, RunDirection::Down)?;
    let gr = branch.first(SpecialKind::Grazing)?;
    println!(
        "GR: A = {:.12} (closed form {:.12}) after {} points",
        gr.point[AMP],
        graze(1.0),
        branch.branch.points.len()
    );

    // The grazing curve in (A, w) over w in [0.2, 1.58], with user points.
    let spec = CurveSpec::new(W)
        .bounds(0.2, 1.58)
        .user_points(W, [0.5, 1.5]);
    let curve = run.curve_at("grazing", &branch, gr.point.label, &spec)?;
    for s in curve.special(SpecialKind::UserPoint) {
        let w = s.point[W];
        println!(
            "grazing curve at w = {w:.1}: A = {:.12} (closed form {:.12})",
            s.point[AMP],
            graze(w)
        );
    }
    let worst = curve
        .branch
        .points
        .iter()
        .map(|q| (q[AMP] - graze(q[W])).abs())
        .fold(0.0, f64::max);
    println!(
        "{} points over w in [0.2, 1.58]; largest distance to the closed form {worst:.1e}",
        curve.branch.points.len()
    );
    Ok(())
}
