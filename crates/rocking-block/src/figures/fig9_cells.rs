//! Fig. 9 sampled adaptively ([`hycont_sample::adaptive`]): trials drawn cell by cell of the
//! 30 x 30 (omega, alpha) grid, omega and alpha uniform inside the cell, until every class's
//! 95 % Wilson half-width in the cell is at most the target (or the per-cell cap is reached),
//! for each beta. The figure reports the trials and the largest half-width of every cell.

use super::FigureFiles;
use super::fig9_files::{probabilities_json, write_fig9};
use super::sampling::{SampleOptions, fig9_study, group_probabilities_of};
use crate::classes::RockingClassifier;
use crate::error::Result;
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts, run_cells};
use hycont_sample::basin::{Classifier, Progress, Study};
use serde_json::json;

/// The half-width Fig. 9 is sampled to by default: every class's 95 % interval in every cell
/// within +-0.1.
pub const DEFAULT_HALFWIDTH: f64 = 0.1;

/// Fig. 9's two betas.
const BETAS: [f64; 2] = [0.0, std::f64::consts::FRAC_PI_2];

/// The studies of the two panels (beta = 0 and pi/2; seeds `seed` and `seed + 1`).
#[must_use]
pub fn fig9_cell_studies(options: &SampleOptions) -> Vec<Study> {
    BETAS
        .iter()
        .enumerate()
        .map(|(k, &beta)| fig9_study(beta, options.seed.wrapping_add(k as u64), &options.block))
        .collect()
}

/// Empty per-cell tables of the two panels.
#[must_use]
pub fn empty_cell_tables() -> Vec<CellCounts> {
    let classes = RockingClassifier::default().classes();
    let cells = fig9_study(0.0, 0, &crate::block::Block::default()).cells();
    BETAS
        .iter()
        .map(|_| CellCounts::new(classes.clone(), cells))
        .collect()
}

/// Runs the cells `cells[k]` of panel `k` until they meet `rule` (or `progress` stops them).
///
/// # Errors
/// Tables of another shape; numerical failures.
pub fn fill_cells(
    options: &SampleOptions,
    rule: &Adaptive,
    tables: &mut [CellCounts],
    cells: &[Vec<usize>],
    progress: &Progress,
) -> Result<()> {
    let classifier = RockingClassifier {
        block: options.block,
        ..RockingClassifier::default()
    };
    for ((study, table), cells) in fig9_cell_studies(options).iter().zip(tables).zip(cells) {
        run_cells(study, &classifier, rule, table, cells, progress)
            .map_err(super::sampling::sample_err)?;
    }
    Ok(())
}

/// Writes `fig9.json` (per panel and cell: the group probabilities, the trials and the largest
/// 95 % half-width) and the picture.
///
/// # Errors
/// Tables of another shape; numerical or I/O failures.
pub fn render9_cells(
    out: &OutDir,
    options: &SampleOptions,
    rule: &Adaptive,
    provenance: &Provenance,
    tables: &[CellCounts],
) -> Result<FigureFiles> {
    let provenance = provenance
        .clone()
        .with_block(options.block)
        .with_seed(options.seed);
    let mut panels = Vec::new();
    let mut entries = Vec::new();
    let mut total = 0u64;
    let mut widest = 0.0f64;
    for (k, (&beta, t)) in BETAS.iter().zip(tables).enumerate() {
        let probs = group_probabilities_of(&t.counts, |c| t.trials[c]);
        let widths: Vec<f64> = (0..t.counts.len()).map(|c| t.halfwidth(c)).collect();
        let trials: u64 = t.trials.iter().sum();
        total += trials;
        widest = widths.iter().copied().fold(widest, f64::max);
        entries.push(json!({
            "beta": beta,
            "trials": trials,
            "seed": options.seed.wrapping_add(k as u64),
            "trials_per_cell": t.trials,
            "largest_halfwidth_per_cell": widths,
            "probabilities": probabilities_json(&probs),
        }));
        panels.push((beta, probs));
    }
    let sampling = json!({
        "adaptive": true,
        "halfwidth": rule.halfwidth,
        "batch": rule.batch,
        "max_trials_per_cell": rule.max_trials,
        "largest_halfwidth": widest,
    });
    let title = format!(
        "Fig. 9: group probabilities, 30 x 30 cells, {total} trials (95 % half-width <= {widest:.2}){}",
        options.block.note()
    );
    write_fig9(
        out,
        &options.block,
        &provenance,
        &panels,
        entries,
        Some(sampling),
        &title,
    )
}
