//! Basin stability of a block for user ranges: the study's five trial variables (omega, alpha,
//! beta, phi0, psi0) each fixed or uniform, binned on up to two of them, classified into the
//! study's classes; results as JSON (pooled fractions and per-cell counts with 95 % Wilson
//! intervals), CSV and a picture.

use crate::block::Block;
use crate::classes::{Class, RockingClassifier, base_class};
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::{Axis, Counts, Distribution, Study};
use serde_json::{Value, json};
use std::f64::consts::FRAC_PI_2;
use std::path::PathBuf;

/// The trial variables in the order the classifier reads them.
pub const VARIABLES: [&str; 5] = ["omega", "alpha", "beta", "phi0", "psi0"];

/// Checks a user's study: the five variables in order, valid distributions and axes, and a
/// block that lets every drawn trial be classified (omega > 0, alpha >= 0 over the ranges).
///
/// # Errors
/// [`Error::InvalidArgument`] naming the problem.
pub fn validate(study: &Study, block: &Block) -> Result<()> {
    let bad = |value: String, reason: &'static str| Error::InvalidArgument {
        name: "basin",
        value,
        reason,
    };
    if study.names != VARIABLES {
        return Err(bad(
            format!("{:?}", study.names),
            "the variables must be omega, alpha, beta, phi0, psi0",
        ));
    }
    study
        .validate()
        .map_err(|e| bad(e.to_string(), "invalid basin study"))?;
    block.validate()?;
    let range = |d: &Distribution| match *d {
        Distribution::Fixed(v) => (v, v),
        Distribution::Uniform { lo, hi } => (lo, hi),
    };
    let (w, a) = (range(&study.variables[0]), range(&study.variables[1]));
    block.at(w.0, a.0).validate()?;
    block.at(w.1, a.1).validate()?;
    // Every start must be a standing block, as `simulate` requires of its start.
    let (lo, hi) = range(&study.variables[3]);
    if !(lo.abs() < FRAC_PI_2 && hi.abs() < FRAC_PI_2) {
        return Err(Error::InvalidArgument {
            name: "phi0",
            value: if lo == hi {
                format!("{lo:?}")
            } else {
                format!("{lo:?}:{hi:?}")
            },
            reason: "must lie within |phi0| < pi/2 (at |phi0| >= pi/2 the block has overturned)",
        });
    }
    Ok(())
}

/// The classifier of a basin of `block`.
#[must_use]
pub fn classifier(block: &Block) -> RockingClassifier {
    RockingClassifier {
        block: *block,
        ..RockingClassifier::default()
    }
}

/// The counts folded onto the study's eight classes (rest-phase variants counted with their
/// class).
#[must_use]
pub fn folded(counts: &Counts) -> Counts {
    let names = Class::ALL.iter().map(|c| c.name().to_string()).collect();
    let mut out = Counts::new(names, counts.counts.len());
    for (cell, row) in counts.counts.iter().enumerate() {
        for (i, n) in row.iter().enumerate() {
            out.counts[cell][base_class(i).0.index()] += n;
        }
    }
    out.failures.clone_from(&counts.failures);
    out.ranges.clone_from(&counts.ranges);
    out
}

/// `[lo, hi]` of bin `i` of `axis`.
fn bin_range(axis: &Axis, i: usize) -> [f64; 2] {
    let w = (axis.hi - axis.lo) / axis.bins as f64;
    [axis.lo + w * i as f64, axis.lo + w * (i + 1) as f64]
}

/// The bins of every axis of cell `cell` (the first axis varies slowest).
fn cell_bins(study: &Study, cell: usize) -> Vec<[f64; 2]> {
    let mut rest = cell;
    let mut out = Vec::new();
    for (k, axis) in study.axes.iter().enumerate() {
        let inner: usize = study.axes[k + 1..].iter().map(|a| a.bins).product();
        out.push(bin_range(axis, rest / inner));
        rest %= inner;
    }
    out
}

/// The result as JSON: the variables, the axes, trials and failures, pooled fractions of each
/// class with 95 % intervals (and of rest-phase motions), and per cell (when binned) the bins,
/// trials and class counts.
#[must_use]
pub fn result_json(study: &Study, counts: &Counts) -> Value {
    let (fractions, intervals, with_rest) = crate::figures::sampling::fractions_json(counts);
    let variables: serde_json::Map<String, Value> = study
        .names
        .iter()
        .zip(&study.variables)
        .map(|(n, d)| {
            let v = match *d {
                Distribution::Fixed(v) => json!({"fixed": v}),
                Distribution::Uniform { lo, hi } => json!({"uniform": [lo, hi]}),
            };
            (n.clone(), v)
        })
        .collect();
    let f = folded(counts);
    let cells: Vec<Value> = if study.axes.is_empty() {
        Vec::new()
    } else {
        (0..f.counts.len())
            .map(|c| {
                let per: serde_json::Map<String, Value> = f
                    .classes
                    .iter()
                    .zip(&f.counts[c])
                    .map(|(n, k)| (n.clone(), json!(k)))
                    .collect();
                json!({"bins": cell_bins(study, c), "trials": f.trials(c), "counts": per})
            })
            .collect()
    };
    json!({
        "variables": variables,
        "axes": study.axes.iter().map(|a| json!({"variable": study.names[a.variable], "lo": a.lo, "hi": a.hi, "bins": a.bins})).collect::<Vec<_>>(),
        "seed": study.seed,
        "trials": (0..counts.counts.len()).map(|c| counts.trials(c)).sum::<u64>(),
        "failures": counts.failures.iter().sum::<u64>(),
        "trial_ranges": counts.ranges,
        "fractions": fractions,
        "intervals_95": intervals,
        "with_rest_phases": with_rest,
        "cells": cells,
    })
}

/// The counts per cell as CSV: the cell's bins (`NAME_lo`, `NAME_hi` per axis), its trials,
/// and per class the count, the fraction and its 95 % Wilson interval.
#[must_use]
pub fn result_csv(study: &Study, counts: &Counts) -> String {
    let f = folded(counts);
    let mut header = vec!["cell".to_string()];
    for a in &study.axes {
        let n = &study.names[a.variable];
        header.extend([format!("{n}_lo"), format!("{n}_hi")]);
    }
    header.push("trials".into());
    for c in &f.classes {
        header.extend([
            c.clone(),
            format!("{c}_fraction"),
            format!("{c}_lo95"),
            format!("{c}_hi95"),
        ]);
    }
    let mut text = header.join(",") + "\n";
    for cell in 0..f.counts.len() {
        let mut row = vec![cell.to_string()];
        row.extend(
            cell_bins(study, cell)
                .iter()
                .flat_map(|b| [b[0].to_string(), b[1].to_string()]),
        );
        row.push(f.trials(cell).to_string());
        for (k, n) in f.counts[cell].iter().enumerate() {
            let (p, lo, hi) = f.fraction(cell, k);
            row.extend([n.to_string(), p.to_string(), lo.to_string(), hi.to_string()]);
        }
        text += &(row.join(",") + "\n");
    }
    text
}

/// Writes a basin's files: `basin.json` (the result with `provenance`, completed with the
/// block and seed, and amended by `extra`), `basin.csv` and the picture.
///
/// # Errors
/// [`Error::Io`] naming a file that cannot be written.
pub fn write_basin(
    out: &OutDir,
    study: &Study,
    block: &Block,
    counts: &Counts,
    provenance: Provenance,
    extra: impl FnOnce(&mut serde_json::Value),
) -> Result<Vec<PathBuf>> {
    let provenance = provenance.with_block(*block).with_seed(study.seed);
    let json_path = out.join("basin.json");
    let mut value = result_json(study, counts);
    extra(&mut value);
    crate::figures::write_json(&json_path, &provenance.insert_into(value))?;
    let csv_path = out.join("basin.csv");
    crate::output::write_atomic(&csv_path, result_csv(study, counts))?;
    let title = title(study, block, counts);
    let pictures = out.picture("basin", |p| {
        crate::plot::basin_svg(p, &title, study, &folded(counts))
    })?;
    Ok([vec![json_path, csv_path], pictures].concat())
}

/// The picture's title: the fixed variables and the block.
fn title(study: &Study, block: &Block, counts: &Counts) -> String {
    let fixed: Vec<String> = study
        .names
        .iter()
        .zip(&study.variables)
        .filter_map(|(n, d)| match d {
            Distribution::Fixed(v) => Some(format!("{n} = {v}")),
            Distribution::Uniform { .. } => None,
        })
        .collect();
    let trials: u64 = (0..counts.counts.len()).map(|c| counts.trials(c)).sum();
    let at = if fixed.is_empty() {
        String::new()
    } else {
        format!(" at {}", fixed.join(", "))
    };
    format!(
        "basin stability{at}; theta_b = {}, xi = {} ({trials} trials)",
        block.theta_b, block.xi
    )
}
