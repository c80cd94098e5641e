//! Sample-based figures: Fig. 5 (brute-force diagram), Figs. 7, 9, 10 (basin stability,
//! rendered from the count tables of [`super::tables`]) and Fig. 8 (final classes).

pub use super::fig5::figure5;
pub use super::fig7::{FIG7_OMEGAS, RASTER, fig7_study, figure7, raster, render7_cells};
pub use super::tables::{counts_for, empty_tables, fill, missing, tables_share_trials};

use super::fig9_files::{probabilities_json, write_fig9};
use super::{FigureFiles, write_json};
use crate::block::Block;
use crate::classes::{Class, base_class};
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use hycont_sample::basin::{Axis, Counts, Distribution, Progress, Study};
use serde_json::{Value, json};

/// The default trial count of sampling figure `n` (7, 9 or 10): enough to show the study's
/// trends (Fig. 10's marginals are noise at 2,000 trials and clear at 100,000).
#[must_use]
pub fn default_trials(n: u32) -> u64 {
    if n == 10 { 100_000 } else { 2_000 }
}

/// Options of the sampling figures.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SampleOptions {
    /// Trials per basin (Fig. 7: per omega).
    pub trials: u64,
    /// Seed.
    pub seed: u64,
    /// The block.
    pub block: Block,
}

pub(crate) fn sample_err(e: hycont_sample::Error) -> Error {
    Error::InvalidArgument {
        name: "study",
        value: e.to_string(),
        reason: "invalid sampling study",
    }
}

/// Fractions per study class (rest-phase variants folded in) with 95 % intervals over all cells,
/// and the fractions of rest-phase motions.
#[must_use]
pub fn fractions_json(counts: &Counts) -> (Value, Value, Value) {
    let total: u64 = (0..counts.counts.len()).map(|c| counts.trials(c)).sum();
    let mut per = vec![0u64; Class::ALL.len()];
    let mut rest = vec![0u64; Class::ALL.len()];
    for cell in &counts.counts {
        for (i, n) in cell.iter().enumerate() {
            let (c, with_rest) = base_class(i);
            per[c.index()] += n;
            if with_rest {
                rest[c.index()] += n;
            }
        }
    }
    let frac = |n: u64| {
        if total == 0 {
            0.0
        } else {
            n as f64 / total as f64
        }
    };
    // Wilson interval on the pooled counts.
    let wilson = |n: u64| {
        let (lo, hi) = hycont_sample::basin::wilson(n, total);
        [lo, hi]
    };
    let mut fr = serde_json::Map::new();
    let mut ci = serde_json::Map::new();
    let mut wr = serde_json::Map::new();
    for c in Class::ALL {
        fr.insert(c.name().into(), json!(frac(per[c.index()])));
        ci.insert(c.name().into(), json!(wilson(per[c.index()])));
        if rest[c.index()] > 0 {
            wr.insert(c.name().into(), json!(frac(rest[c.index()])));
        }
    }
    (Value::Object(fr), Value::Object(ci), Value::Object(wr))
}

/// Writes sampling figure `n` (7, 9 or 10) from its count tables (e.g. merged shards).
///
/// # Errors
/// [`Error::InvalidArgument`] for another figure or tables that do not fit; I/O failures.
pub fn render(
    n: u32,
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    counts: &[Counts],
) -> Result<FigureFiles> {
    let provenance = &provenance
        .clone()
        .with_block(options.block)
        .with_seed(options.seed)
        .with_trials(options.trials);
    match n {
        7 => super::fig7::render7(out, options, provenance, counts, None),
        9 => render9(out, options, provenance, counts),
        10 => render10(out, options, provenance, counts),
        _ => Err(Error::InvalidArgument {
            name: "figure",
            value: n.to_string(),
            reason: "only the sampling figures 7, 9 and 10 are rendered from counts",
        }),
    }
}

/// The classes shown by Figs. 9 and 10 (the study's groups): each a list of study classes.
pub const GROUPS: [(&str, &[Class]); 5] = [
    ("symmetric_p1", &[Class::SymmetricP1]),
    (
        "asymmetric_p1",
        &[Class::AsymmetricP1Pos, Class::AsymmetricP1Neg],
    ),
    ("overturn", &[Class::OverturnPos, Class::OverturnNeg]),
    ("equilibrium", &[Class::Equilibrium]),
    ("other", &[Class::Period2, Class::Other]),
];

/// Probability of each group per cell of a count table.
#[must_use]
pub fn group_probabilities(counts: &Counts) -> Vec<(&'static str, Vec<f64>)> {
    group_probabilities_of(&counts.counts, |cell| counts.trials(cell))
}

/// Probability of each group per cell of class counts `rows[cell][class]` with `trials(cell)`
/// trials (`NaN` for a cell without any).
pub fn group_probabilities_of(
    rows: &[Vec<u64>],
    trials: impl Fn(usize) -> u64,
) -> Vec<(&'static str, Vec<f64>)> {
    GROUPS
        .iter()
        .map(|(name, members)| {
            let p = rows
                .iter()
                .enumerate()
                .map(|(cell, row)| {
                    let n = trials(cell);
                    if n == 0 {
                        return f64::NAN;
                    }
                    let k: u64 = row
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| members.contains(&base_class(*i).0))
                        .map(|(_, c)| *c)
                        .sum();
                    k as f64 / n as f64
                })
                .collect();
            (*name, p)
        })
        .collect()
}

/// Grid resolution of Fig. 8 (omega x alpha).
pub const FIG8_GRID: (usize, usize) = (70, 40);

/// Fig. 8: the final class on a grid over omega in (0.5, 4.0), alpha in (0.1, 0.9) from
/// phi0 = 0.01, psi0 = 0, for beta = 0 and beta = pi/2, with the SN, BP and PD curves of Fig. 6.
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure8(out: &OutDir, provenance: &Provenance) -> Result<FigureFiles> {
    let block = provenance.block;
    use rayon::prelude::*;
    let (nw, na) = FIG8_GRID;
    let omegas: Vec<f64> = (0..nw)
        .map(|i| 0.5 + 3.5 * (i as f64 + 0.5) / nw as f64)
        .collect();
    let alphas: Vec<f64> = (0..na)
        .map(|j| 0.1 + 0.8 * (j as f64 + 0.5) / na as f64)
        .collect();
    let settings = crate::classes::ClassifierSettings::default();
    let mut grids = Vec::new();
    for beta in [0.0, std::f64::consts::FRAC_PI_2] {
        let cells: Vec<(usize, usize)> =
            (0..nw).flat_map(|i| (0..na).map(move |j| (i, j))).collect();
        let classes: Vec<&'static str> = cells
            .par_iter()
            .map(|&(i, j)| {
                crate::classes::classify(
                    &block.at(omegas[i], alphas[j]),
                    beta,
                    0.01,
                    0.0,
                    &settings,
                )
                .map_or("error", |c| c.class.name())
            })
            .collect();
        let grid: Vec<Vec<&str>> = (0..nw)
            .map(|i| classes[i * na..(i + 1) * na].to_vec())
            .collect();
        grids.push((beta, grid));
    }
    let curves =
        crate::continuation::study_curves(&block, &mut hycont_continuation::observe::Silent)?;
    let json = json!({
        "figure": 8,
        "initial": {"phi0": 0.01, "psi0": 0.0},
        "omega": omegas,
        "alpha": alphas,
        "grids": grids.iter().map(|(b, g)| json!({"beta": b, "classes": g})).collect::<Vec<_>>(),
        "curves": curves_json(&curves),
    });
    let json_path = out.join("fig8.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let title = format!(
        "Fig. 8: final class from phi0 = 0.01, psi0 = 0 on the (omega, alpha) grid{}",
        provenance.block.note()
    );
    let pictures = out.picture("fig8", |p| {
        plot::class_grid_svg(p, &title, &omegas, &alphas, &grids, &curves)
    })?;
    Ok(FigureFiles {
        figure: 8,
        files: [vec![json_path], pictures].concat(),
    })
}

pub(super) fn curves_json(curves: &[crate::continuation::Curve]) -> Value {
    Value::Array(
        curves
            .iter()
            .map(|c| {
                json!({
                    "kind": c.kind.label(),
                    "points": c.points().iter().map(|(w, a)| json!({"omega": w, "alpha": a})).collect::<Vec<_>>(),
                })
            })
            .collect(),
    )
}

/// The random variables of Figs. 9 and 10: omega, alpha, beta, phi0, psi0.
fn plane_study(beta: Distribution, seed: u64, block: &Block) -> Study {
    let b = block.static_boundary();
    Study {
        names: ["omega", "alpha", "beta", "phi0", "psi0"]
            .iter()
            .map(ToString::to_string)
            .collect(),
        variables: vec![
            Distribution::Uniform { lo: 0.5, hi: 4.0 },
            Distribution::Uniform { lo: 0.1, hi: 0.9 },
            beta,
            Distribution::Uniform { lo: -b, hi: b },
            Distribution::Uniform { lo: -1.0, hi: 1.0 },
        ],
        axes: vec![],
        seed,
    }
}

/// Fig. 9: class probabilities on a 30 x 30 (omega, alpha) grid from random phi0, psi0, for
/// beta = 0 and beta = pi/2 (`trials` per beta; the study: 1,000,000).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure9(
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    progress: &Progress,
) -> Result<FigureFiles> {
    let counts = counts_for(9, options, 0..options.trials, progress)?;
    render(9, out, options, provenance, &counts)
}

/// The study of one Fig. 9 panel: omega, alpha, phi0, psi0 uniform, beta fixed, binned on the
/// 30 x 30 (omega, alpha) grid.
#[must_use]
pub fn fig9_study(beta: f64, seed: u64, block: &Block) -> Study {
    Study {
        axes: vec![
            Axis {
                variable: 0,
                lo: 0.5,
                hi: 4.0,
                bins: 30,
            },
            Axis {
                variable: 1,
                lo: 0.1,
                hi: 0.9,
                bins: 30,
            },
        ],
        ..plane_study(Distribution::Fixed(beta), seed, block)
    }
}

fn render9(
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    all: &[Counts],
) -> Result<FigureFiles> {
    if all.len() != 2 {
        return Err(Error::InvalidArgument {
            name: "counts",
            value: all.len().to_string(),
            reason: "Fig. 9 needs one table per beta",
        });
    }
    let mut panels = Vec::new();
    let mut entries = Vec::new();
    for (k, (beta, counts)) in [0.0, std::f64::consts::FRAC_PI_2]
        .into_iter()
        .zip(all)
        .enumerate()
    {
        let probs = group_probabilities(counts);
        entries.push(json!({
            "beta": beta,
            "trials": (0..counts.counts.len()).map(|c| counts.trials(c)).sum::<u64>(),
            "seed": options.seed.wrapping_add(k as u64),
            "trial_ranges": counts.ranges,
            "probabilities": probabilities_json(&probs),
        }));
        panels.push((beta, probs));
    }
    let title = format!(
        "Fig. 9: probability of each solution group on the (omega, alpha) grid, 30 x 30 cells{}",
        options.block.note()
    );
    write_fig9(
        out,
        &options.block,
        provenance,
        &panels,
        entries,
        None,
        &title,
    )
}

/// Fig. 10: probabilities against phi0, psi0 and beta (50 bins each) from trials with random
/// phi0, psi0, alpha, omega and beta (`trials`; the study: 2,000,000).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure10(
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    progress: &Progress,
) -> Result<FigureFiles> {
    let counts = counts_for(10, options, 0..options.trials, progress)?;
    render(10, out, options, provenance, &counts)
}

/// The study of Fig. 10 (every variable uniform, beta over a forcing period) and its three
/// binnings (phi0, psi0, beta in 50 bins each), which bin the same trials.
#[must_use]
pub fn fig10_study(seed: u64, block: &Block) -> (Study, Vec<Vec<Axis>>) {
    let b = block.static_boundary();
    let study = plane_study(
        Distribution::Uniform {
            lo: 0.0,
            hi: std::f64::consts::TAU,
        },
        seed,
        block,
    );
    let binnings = vec![
        vec![Axis {
            variable: 3,
            lo: -b,
            hi: b,
            bins: 50,
        }],
        vec![Axis {
            variable: 4,
            lo: -1.0,
            hi: 1.0,
            bins: 50,
        }],
        vec![Axis {
            variable: 2,
            lo: 0.0,
            hi: std::f64::consts::TAU,
            bins: 50,
        }],
    ];
    (study, binnings)
}

fn render10(
    out: &OutDir,
    options: SampleOptions,
    provenance: &Provenance,
    counts: &[Counts],
) -> Result<FigureFiles> {
    let (_, binnings) = fig10_study(options.seed, &options.block);
    if counts.len() != binnings.len() {
        return Err(Error::InvalidArgument {
            name: "counts",
            value: counts.len().to_string(),
            reason: "Fig. 10 needs one table per binned variable",
        });
    }
    let names = ["phi0", "psi0", "beta"];
    let mut marginals = serde_json::Map::new();
    let mut panels = Vec::new();
    for ((name, c), axis) in names.iter().zip(counts).zip(&binnings) {
        let probs = group_probabilities(c);
        marginals.insert(name.to_string(), json!({
            "range": [axis[0].lo, axis[0].hi],
            "bins": 50,
            "trials_per_bin": (0..50).map(|i| c.trials(i)).collect::<Vec<_>>(),
            "probabilities": probs.iter().map(|(n, p)| (n.to_string(), json!(p))).collect::<serde_json::Map<_, _>>(),
        }));
        let trials: Vec<u64> = (0..c.counts.len()).map(|i| c.trials(i)).collect();
        panels.push(plot::Marginal {
            name,
            range: (axis[0].lo, axis[0].hi),
            probabilities: probs,
            trials,
        });
    }
    let json = json!({
        "figure": 10,
        "trials": (0..counts[0].counts.len()).map(|c| counts[0].trials(c)).sum::<u64>(),
        "seed": options.seed,
        "trial_ranges": counts[0].ranges,
        "marginals": marginals,
    });
    let title = format!(
        "Fig. 10: probability of each solution group against phi0, psi0 and beta, {} trials{}",
        json["trials"],
        options.block.note()
    );
    let json_path = out.join("fig10.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let pictures = out.picture("fig10", |p| plot::marginals_svg(p, &title, &panels))?;
    Ok(FigureFiles {
        figure: 10,
        files: [vec![json_path], pictures].concat(),
    })
}
