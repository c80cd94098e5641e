//! The figures sampled cell by cell ([`hycont_sample::adaptive`]): Fig. 7 (each omega's
//! 40 x 40 cells of initial (phi0, psi0)) and Fig. 9 (each beta's 30 x 30 (omega, alpha)
//! cells). Trials are drawn uniformly inside a cell until every class's 95 % Wilson
//! half-width in the cell is at most the target (or the per-cell cap is reached). The figures
//! report the trials and the largest half-width of every cell.

use super::FigureFiles;
use super::fig9_files::{probabilities_json, write_fig9};
use super::sampling::{FIG7_OMEGAS, SampleOptions, fig7_study, fig9_study, group_probabilities_of};
use crate::classes::RockingClassifier;
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts, run_cells};
use hycont_sample::basin::{Classifier, Progress, Study};
use serde_json::json;

/// The half-width Figs. 7 and 9 are sampled to by default: every class's 95 % interval in
/// every cell within +-0.1.
pub const DEFAULT_HALFWIDTH: f64 = 0.1;

/// Fig. 9's two betas.
const BETAS: [f64; 2] = [0.0, std::f64::consts::FRAC_PI_2];

/// The figures sampled cell by cell.
pub const BY_CELLS: [u32; 2] = [7, 9];

fn not_by_cells(figure: u32) -> Error {
    Error::InvalidArgument {
        name: "figure",
        value: figure.to_string(),
        reason: "only Figs. 7 and 9 are sampled cell by cell",
    }
}

/// The studies of figure `figure`'s panels: Fig. 7 one per omega of [`FIG7_OMEGAS`], Fig. 9
/// one per beta (0 and pi/2); panel `k` has the seed `seed + k`.
///
/// # Errors
/// [`Error::InvalidArgument`] for a figure not sampled cell by cell.
pub fn cell_studies(figure: u32, options: &SampleOptions) -> Result<Vec<Study>> {
    let seed = |k: usize| options.seed.wrapping_add(k as u64);
    match figure {
        7 => Ok((FIG7_OMEGAS.iter().enumerate())
            .map(|(k, &omega)| fig7_study(omega, seed(k), &options.block))
            .collect()),
        9 => Ok((BETAS.iter().enumerate())
            .map(|(k, &beta)| fig9_study(beta, seed(k), &options.block))
            .collect()),
        _ => Err(not_by_cells(figure)),
    }
}

/// Empty per-cell tables of figure `figure`'s panels.
///
/// # Errors
/// [`Error::InvalidArgument`] for a figure not sampled cell by cell.
pub fn empty_cell_tables(figure: u32) -> Result<Vec<CellCounts>> {
    let classes = RockingClassifier::default().classes();
    let studies = cell_studies(figure, &SampleOptions::default())?;
    Ok((studies.iter())
        .map(|s| CellCounts::new(classes.clone(), s.cells()))
        .collect())
}

/// Runs the cells `cells[k]` of figure `figure`'s panel `k` until they meet `rule` (or
/// `progress` stops them).
///
/// # Errors
/// A figure not sampled cell by cell; tables of another shape; numerical failures.
pub fn fill_cells(
    figure: u32,
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
    for ((study, table), cells) in cell_studies(figure, options)?.iter().zip(tables).zip(cells) {
        run_cells(study, &classifier, rule, table, cells, progress)
            .map_err(super::sampling::sample_err)?;
    }
    Ok(())
}

/// Writes figure `figure` (7 or 9) from its per-cell tables.
///
/// # Errors
/// A figure not sampled cell by cell; tables of another shape; numerical or I/O failures.
pub fn render_cells(
    figure: u32,
    out: &OutDir,
    options: &SampleOptions,
    rule: &Adaptive,
    provenance: &Provenance,
    tables: &[CellCounts],
) -> Result<FigureFiles> {
    match figure {
        7 => super::sampling::render7_cells(out, options, rule, provenance, tables),
        9 => render9_cells(out, options, rule, provenance, tables),
        _ => Err(not_by_cells(figure)),
    }
}

/// Writes `fig9.json` (per panel and cell: the group probabilities, the trials and the largest
/// 95 % half-width) and the picture.
///
/// # Errors
/// Tables of another shape; numerical or I/O failures.
fn render9_cells(
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
