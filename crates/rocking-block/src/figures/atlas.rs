//! The atlas figure: the symmetric period-one orbits over the (omega, alpha) plane as two
//! sheets of charts joined along the fold (SN) curve, Amp as colour, with Fig. 6's curves.

use super::{FigureFiles, write_json};
use crate::continuation::{
    AMP, Recipe, atlas_settings, default_method, study_atlas, study_branches_from, study_curves,
    study_start,
};
use crate::error::{Error, Result};
use crate::model::{ALPHA, OMEGA};
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use hycont_continuation::observe::Observer;
use hycont_continuation::{MeasureId, OrbitAtlas, SpecialKind};
use hycont_core::orbit::PeriodicOrbit;
use serde_json::json;

/// The two sheets of the symmetric family: through the Fig. 2 orbit (up to the fold) and
/// beyond the fold (from the Fig. 3 branch between SN1 and GR1, up to the fold and the
/// grazing curve), each an atlas with the fold as an edge. A block whose Fig. 3 branch has no
/// fold followed by a grazing point has the first sheet only.
///
/// # Errors
/// Numerical failures.
pub fn study_sheets(
    block: &crate::block::Block,
    observer: &mut dyn Observer,
) -> Result<Vec<OrbitAtlas>> {
    let start = study_start(block)?;
    let settings = atlas_settings();
    let upper = study_atlas(
        "through the Fig. 2 orbit",
        &start,
        default_method(),
        &settings,
        observer,
    )?;
    let fig3 = study_branches_from(
        crate::model::Free::Omega,
        block,
        &Recipe::default(),
        &start,
        observer,
    )?;
    let Some(lower) = beyond_fold(&fig3[0])? else {
        return Ok(vec![upper]);
    };
    let lower = study_atlas(
        "beyond the fold (SN)",
        &lower,
        default_method(),
        &settings,
        observer,
    )?;
    Ok(vec![upper, lower])
}

/// An orbit of the symmetric branch beyond its first fold: midway (in points) between the
/// fold SN1 and the grazing point GR1 of Fig. 3 (`None` without both).
fn beyond_fold(branch: &hycont_continuation::OrbitBranch) -> Result<Option<PeriodicOrbit>> {
    let b = &branch.branch;
    if branch.first(SpecialKind::Fold).is_err() || branch.first(SpecialKind::Grazing).is_err() {
        return Ok(None);
    }
    // Special points are numbered apart from the points: find the points nearest to them.
    let nearest = |kind: SpecialKind| -> Result<usize> {
        let s = &branch.first(kind)?.point;
        let gap = |p: &hycont_continuation::BranchPoint| {
            (p[OMEGA] - s[OMEGA]).abs()
                + (p.get(AMP).unwrap_or(0.0) - s.get(AMP).unwrap_or(0.0)).abs()
        };
        (0..b.points.len())
            .min_by(|&i, &j| gap(&b.points[i]).total_cmp(&gap(&b.points[j])))
            .ok_or_else(|| Error::NoOrbit("an empty branch".into()))
    };
    let (sn, gr) = (nearest(SpecialKind::Fold)?, nearest(SpecialKind::Grazing)?);
    if sn.abs_diff(gr) < 2 {
        return Err(Error::NoOrbit("no point between SN1 and GR1".into()));
    }
    Ok(Some(branch.orbit_of(&b.points[(sn + gr) / 2])?))
}

/// A chart's summary for the figure's JSON.
fn chart_json(a: &OrbitAtlas, c: &hycont_continuation::atlas::AtlasChart) -> serde_json::Value {
    let [p, q] = a.atlas.unknown_params;
    let u = &c.point.u;
    let polygon: Vec<[f64; 2]> = c
        .polygon
        .iter()
        .map(|v| {
            let at = |k: usize| u[k] + c.point.tangent[k] * v[0] + c.tangent2[k] * v[1];
            [at(p), at(q)]
        })
        .collect();
    json!({
        "omega": c.point[OMEGA], "alpha": c.point[ALPHA], "amp": c.point.get(AMP),
        "period": c.point.get(MeasureId::PERIOD), "stable": c.point.stable(),
        "unstable_multipliers": c.point.unstable, "edge": c.edge.map(|e| e.label()),
        "radius": c.radius, "polygon": polygon,
    })
}

/// Writes `atlas.json` (`"charts": [{"sheet", "omega", "alpha", "amp", "period", "stable",
/// "edge", "radius", "polygon"}]` over all sheets, `"sheets": [{"name", "end", "stats",
/// "charts"}]` with each sheet's chart count, and Fig. 6's curves) and `atlas.svg`.
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure_atlas(
    out: &OutDir,
    provenance: &Provenance,
    observer: &mut dyn Observer,
) -> Result<FigureFiles> {
    let block = provenance.block;
    let sheets = study_sheets(&block, observer)?;
    let curves = study_curves(&block, observer)?;
    super::stopped_by(observer, crate::figures::ATLAS)?;
    let json = json!({
        "figure": "atlas",
        "window": crate::continuation::ATLAS_WINDOW,
        "settings": sheets[0].atlas.settings,
        "sheets": sheets.iter().map(|a| json!({
            "name": a.atlas.name,
            "end": format!("{:?}", a.atlas.end),
            "stats": a.atlas.stats,
            "charts": a.atlas.charts.len(),
        })).collect::<Vec<_>>(),
        "charts": sheets.iter().enumerate().flat_map(|(k, a)| {
            a.atlas.charts.iter().map(move |c| {
                let mut v = chart_json(a, c);
                v["sheet"] = json!(k);
                v
            })
        }).collect::<Vec<_>>(),
        "curves": curves.iter().map(super::fig6::curve_json).collect::<Vec<_>>(),
    });
    let json_path = out.join("atlas.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let note = block.note();
    let title = format!("Atlas of the symmetric period-one orbits, Amp over (omega, alpha){note}");
    let pictures = out.picture("atlas", |p| plot::atlas_svg(p, &title, &sheets, &curves))?;
    Ok(FigureFiles {
        figure: ATLAS,
        files: [vec![json_path], pictures].concat(),
    })
}

/// The number `figure` files the atlas figure under (`rocking-block figure atlas`).
pub const ATLAS: u32 = 11;
