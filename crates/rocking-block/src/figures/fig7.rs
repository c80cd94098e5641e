//! Fig. 7: the basins of attraction over initial (phi0, psi0) at alpha = 0.66, beta = 0 for
//! six omegas, the dominant class per cell; sampled with a number of trials per omega, or
//! cell by cell to a half-width ([`super::cells`]).

use super::sampling::{SampleOptions, counts_for, fractions_json, render};
use super::{FigureFiles, write_json};
use crate::block::Block;
use crate::classes::{Class, base_class};
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts};
use hycont_sample::basin::{Axis, Counts, Distribution, Progress, Study};
use serde_json::json;

/// The omega values of Fig. 7.
pub const FIG7_OMEGAS: [f64; 6] = [1.0, 1.16, 1.5, 2.0, 3.0, 4.0];

/// Raster bins per axis of Fig. 7's basins.
pub const RASTER: usize = 40;

/// The basin study of Fig. 7 at one omega.
#[must_use]
pub fn fig7_study(omega: f64, seed: u64, block: &Block) -> Study {
    let b = block.static_boundary();
    Study {
        names: ["omega", "alpha", "beta", "phi0", "psi0"]
            .iter()
            .map(ToString::to_string)
            .collect(),
        variables: vec![
            Distribution::Fixed(omega),
            Distribution::Fixed(0.66),
            Distribution::Fixed(0.0),
            Distribution::Uniform { lo: -b, hi: b },
            Distribution::Uniform { lo: -1.0, hi: 1.0 },
        ],
        axes: vec![
            Axis {
                variable: 3,
                lo: -b,
                hi: b,
                bins: RASTER,
            },
            Axis {
                variable: 4,
                lo: -1.0,
                hi: 1.0,
                bins: RASTER,
            },
        ],
        seed,
    }
}

/// The dominant study class per raster cell (`null` for empty cells).
#[must_use]
pub fn raster(counts: &Counts) -> Vec<Vec<Option<&'static str>>> {
    (0..RASTER)
        .map(|i| {
            (0..RASTER)
                .map(|j| {
                    let cell = &counts.counts[i * RASTER + j];
                    let mut per = [0u64; 8];
                    for (k, n) in cell.iter().enumerate() {
                        per[base_class(k).0.index()] += n;
                    }
                    let (best, n) = per
                        .iter()
                        .enumerate()
                        .max_by_key(|(_, n)| **n)
                        .expect("8 classes");
                    (*n > 0).then(|| Class::ALL[best].name())
                })
                .collect()
        })
        .collect()
}

/// Fig. 7: basins at alpha = 0.66, beta = 0 for the omega values of [`FIG7_OMEGAS`], `trials`
/// each (the study: 20,000), phi0 uniform in the static boundary, psi0 in (-1, 1).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure7(
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    progress: &Progress,
) -> Result<FigureFiles> {
    let counts = counts_for(7, options, 0..options.trials, progress)?;
    render(7, out, options, provenance, &counts)
}

/// Writes Fig. 7 from one count table per omega; `cells` gives the rule and per-cell tables
/// of a run sampled cell by cell (whose `all` are the same counts as tables over trials).
pub(super) fn render7(
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    all: &[Counts],
    cells: Option<(&Adaptive, &[CellCounts])>,
) -> Result<FigureFiles> {
    if all.len() != FIG7_OMEGAS.len() {
        return Err(Error::InvalidArgument {
            name: "counts",
            value: all.len().to_string(),
            reason: "Fig. 7 needs one table per omega",
        });
    }
    let mut basins = Vec::new();
    let mut rasters = Vec::new();
    let mut widest = 0.0f64;
    for (k, (&omega, counts)) in FIG7_OMEGAS.iter().zip(all).enumerate() {
        let table = cells.and_then(|(_, t)| t.get(k));
        let (basin, r, w) = basin_json(k, omega, counts, table, &options);
        widest = widest.max(w);
        basins.push(basin);
        rasters.push((omega, r));
    }
    let mut json = json!({
        "figure": 7,
        "parameters": {"alpha": 0.66, "beta": 0.0, "xi": options.block.xi, "theta_b": options.block.theta_b},
        "classifier": crate::classes::ClassifierSettings::default(),
        "basins": basins,
    });
    let total: u64 = all
        .iter()
        .map(|c| (0..c.counts.len()).map(|i| c.trials(i)).sum::<u64>())
        .sum();
    let sampled = match cells {
        Some((rule, _)) => {
            json["sampling"] = json!({
                "adaptive": true,
                "halfwidth": rule.halfwidth,
                "batch": rule.batch,
                "max_trials_per_cell": rule.max_trials,
                "largest_halfwidth": widest,
            });
            format!("{total} trials cell by cell (95 % half-width <= {widest:.2})")
        }
        None => format!("{} trials per omega", total / FIG7_OMEGAS.len() as u64),
    };
    let json_path = out.join("fig7.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let title = format!(
        "Fig. 7: dominant class per cell of initial (phi0, psi0), alpha = 0.66, beta = 0, {sampled}{}",
        options.block.note()
    );
    let pictures = out.picture("fig7", |p| {
        plot::basins_svg(p, &title, &rasters, options.block.static_boundary())
    })?;
    Ok(FigureFiles {
        figure: 7,
        files: [vec![json_path], pictures].concat(),
    })
}

/// Panel `k`'s entry of `fig7.json` (at `omega`, from `counts`, and its per-cell `table` when
/// sampled cell by cell), its raster and its largest half-width (0 without cells).
fn basin_json(
    k: usize,
    omega: f64,
    counts: &Counts,
    table: Option<&CellCounts>,
    options: &SampleOptions,
) -> (serde_json::Value, Vec<Vec<Option<&'static str>>>, f64) {
    let study = fig7_study(omega, options.seed.wrapping_add(k as u64), &options.block);
    let (fractions, intervals, with_rest) = fractions_json(counts);
    let trials: u64 = (0..counts.counts.len()).map(|c| counts.trials(c)).sum();
    let r = raster(counts);
    let mut basin = json!({
        "omega": omega,
        "alpha": 0.66,
        "beta": 0.0,
        "trials": trials,
        "seed": study.seed,
        "fractions": fractions,
        "intervals_95": intervals,
        "with_rest_phases": with_rest,
        "failures": counts.failures.iter().sum::<u64>(),
        "raster": {"phi0": [study.axes[0].lo, study.axes[0].hi, RASTER], "psi0": [-1.0, 1.0, RASTER], "dominant": r},
    });
    let mut widest = 0.0f64;
    match table {
        Some(t) => {
            let widths: Vec<f64> = (0..t.counts.len()).map(|c| t.halfwidth(c)).collect();
            widest = widths.iter().copied().fold(widest, f64::max);
            basin["largest_halfwidth_per_cell"] = json!(widths);
            basin["trials_per_cell"] = json!(t.trials);
        }
        None => basin["trial_ranges"] = json!(counts.ranges),
    }
    (basin, r, widest)
}

/// Writes Fig. 7 from its per-cell tables (one per omega), sampled cell by cell to `rule`.
///
/// # Errors
/// Tables of another shape; I/O failures.
pub fn render7_cells(
    out: &OutDir,
    options: &SampleOptions,
    rule: &Adaptive,
    provenance: &Provenance,
    tables: &[CellCounts],
) -> Result<FigureFiles> {
    let counts: Vec<Counts> = (tables.iter())
        .map(|t| Counts {
            classes: t.classes.clone(),
            counts: t.counts.clone(),
            failures: t.failures.clone(),
            ranges: Vec::new(),
        })
        .collect();
    let provenance = provenance
        .clone()
        .with_block(options.block)
        .with_seed(options.seed);
    render7(out, *options, &provenance, &counts, Some((rule, tables)))
}
