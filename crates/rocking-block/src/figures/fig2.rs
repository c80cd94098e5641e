//! Fig. 2: the symmetric period-1 orbit at (omega, alpha) = (1.3, 0.66), with the two asymmetric
//! orbits at the same parameters.

use super::{FigureFiles, write_json};
use crate::error::Result;
use crate::model::Parameters;
use crate::orbits::{OrbitKind, orbit};
use crate::plot;
use serde_json::json;
use std::path::Path;

/// Writes `fig2.json` (`"orbits"`: name, omega, alpha, amp, period, stable, multipliers,
/// segments) and `fig2.svg` (phase portraits coloured by mode with impacts as jumps, and the time
/// series over one period).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure2(out: &Path) -> Result<FigureFiles> {
    let params = Parameters::new(1.3, 0.66);
    let mut reports = Vec::new();
    let mut orbits = Vec::new();
    for (name, kind) in [
        ("symmetric", OrbitKind::Symmetric),
        ("asymmetric-pos", OrbitKind::AsymmetricPos),
        ("asymmetric-neg", OrbitKind::AsymmetricNeg),
    ] {
        let o = orbit(&params, kind, None)?;
        reports.push(o.report(name)?);
        orbits.push((name, o.solution.orbit));
    }
    let json = json!({
        "figure": 2,
        "parameters": {
            "omega": params.omega,
            "alpha": params.alpha,
            "xi": params.xi,
            "theta_b": params.theta_b,
        },
        "orbits": reports,
    });
    let json_path = out.join("fig2.json");
    write_json(&json_path, &json)?;
    let svg_path = out.join("fig2.svg");
    crate::output::write_with(&svg_path, |p| {
        plot::orbits_svg(
            p,
            "Fig. 2: omega = 1.3, alpha = 0.66; thick: symmetric orbit (unstable), thin: asymmetric pair (stable)",
            &orbits,
            &params,
        )
    })?;
    Ok(FigureFiles {
        figure: 2,
        files: vec![json_path, svg_path],
    })
}
