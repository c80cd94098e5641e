//! Fig. 9's files, whatever the sampling (a fixed number of trials per beta, or cell by cell
//! to a half-width): `fig9.json` with its grid, panels, sampling rule and curves, and the picture.

use super::sampling::curves_json;
use super::{FigureFiles, write_json};
use crate::block::Block;
use crate::error::Result;
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use serde_json::{Value, json};

/// One Fig. 9 panel: its beta and each group's probability per cell.
pub type Panel = (f64, Vec<(&'static str, Vec<f64>)>);

/// Group probabilities per cell as JSON (`null` for a cell without trials).
pub(super) fn probabilities_json(probs: &[(&str, Vec<f64>)]) -> Value {
    probs
        .iter()
        .map(|(n, p)| {
            let cells: Vec<Value> = p
                .iter()
                .map(|v| if v.is_nan() { Value::Null } else { json!(v) })
                .collect();
            (n.to_string(), json!(cells))
        })
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// Writes `fig9.json` (the grid, the panels' `entries`, the sampling rule if any, the curves)
/// and the picture of the `panels` under `title`.
pub(super) fn write_fig9(
    out: &OutDir,
    block: &Block,
    provenance: &Provenance,
    panels: &[Panel],
    entries: Vec<Value>,
    sampling: Option<Value>,
    title: &str,
) -> Result<FigureFiles> {
    let curves =
        crate::continuation::study_curves(block, &mut hycont_continuation::observe::Silent)?;
    let mut json = json!({
        "figure": 9,
        "grid": {"omega": [0.5, 4.0, 30], "alpha": [0.1, 0.9, 30], "cell_order": "omega-major"},
        "basins": entries,
        "curves": curves_json(&curves),
    });
    if let (Some(obj), Some(sampling)) = (json.as_object_mut(), sampling) {
        obj.insert("sampling".into(), sampling);
    }
    let json_path = out.join("fig9.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let pictures = out.picture("fig9", |p| {
        plot::probability_grid_svg(p, title, panels, &curves)
    })?;
    Ok(FigureFiles {
        figure: 9,
        files: [vec![json_path], pictures].concat(),
    })
}
