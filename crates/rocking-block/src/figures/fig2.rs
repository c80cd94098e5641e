//! Fig. 2: the symmetric period-1 orbit at (omega, alpha) = (1.3, 0.66), with the two asymmetric
//! orbits at the same parameters.

use super::{FigureFiles, write_json};
use crate::error::{Error, Result};
use crate::orbits::{OrbitKind, orbit};
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use serde_json::json;

/// Writes `fig2.json` (`"orbits"`: name, omega, alpha, amp, period, stable, multipliers,
/// segments) and `fig2.svg` (phase portraits coloured by mode with impacts as jumps, and the time
/// series over one period).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure2(out: &OutDir, provenance: &Provenance) -> Result<FigureFiles> {
    let params = provenance.block.at(1.3, 0.66);
    let mut reports = Vec::new();
    let mut orbits = Vec::new();
    let mut missing = Vec::new();
    for (name, kind) in [
        ("symmetric", OrbitKind::Symmetric),
        ("asymmetric-pos", OrbitKind::AsymmetricPos),
        ("asymmetric-neg", OrbitKind::AsymmetricNeg),
    ] {
        match orbit(&params, kind, None) {
            Ok(o) => {
                reports.push(o.report(name)?);
                orbits.push((name, o.solution.orbit));
            }
            // Another block may have no asymmetric pair at the study's forcing: say so.
            Err(Error::NoOrbit(reason)) if kind != OrbitKind::Symmetric => {
                missing.push(json!({"name": name, "reason": reason}));
            }
            Err(e) => return Err(e),
        }
    }
    let stability = |stable: bool| if stable { "stable" } else { "unstable" };
    let mut title = format!(
        "Fig. 2: omega = 1.3, alpha = 0.66; thick: symmetric orbit ({})",
        stability(reports[0].stable)
    );
    if let Some(r) = reports.get(1) {
        title += &format!(", thin: asymmetric pair ({})", stability(r.stable));
    } else {
        title += ", no asymmetric orbits";
    }
    title += &provenance.block.note();
    let json = json!({
        "figure": 2,
        "parameters": {
            "omega": params.omega,
            "alpha": params.alpha,
            "xi": params.xi,
            "theta_b": params.theta_b,
        },
        "orbits": reports,
        "not_found": missing,
    });
    let json_path = out.join("fig2.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let pictures = out.picture("fig2", |p| plot::orbits_svg(p, &title, &orbits, &params))?;
    Ok(FigureFiles {
        figure: 2,
        files: [vec![json_path], pictures].concat(),
    })
}
