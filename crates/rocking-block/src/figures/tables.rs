//! The count tables of the sampling figures (7, 9, 10): their shapes, and filling them with
//! the trials they lack (a fresh run, or the rest of an interrupted one).

use super::sampling::{
    FIG7_OMEGAS, SampleOptions, fig7_study, fig9_study, fig10_study, sample_err,
};
use crate::block::Block;
use crate::classes::RockingClassifier;
use crate::error::{Error, Result};
use hycont_sample::basin::{Axis, Counts, Progress, Study, run, share};

/// The count tables of sampling figure `n` (7, 9 or 10) over trials `range`: one per study
/// (Fig. 7: one per omega; Fig. 9: one per beta; Fig. 10: one per binned variable).
///
/// # Errors
/// [`Error::InvalidArgument`] for another figure; numerical failures.
pub fn counts_for(
    n: u32,
    options: SampleOptions,
    range: std::ops::Range<u64>,
    progress: &Progress,
) -> Result<Vec<Counts>> {
    let mut tables = empty_tables(n)?;
    let todo = missing(n, &tables, range, (0, 1))?;
    fill(n, options, &mut tables, &todo, progress)?;
    Ok(tables)
}

/// The studies of sampling figure `n` and how their trials are binned (Fig. 10: one study,
/// three binnings; Figs. 7 and 9: one study per table).
fn studies(n: u32, seed: u64, block: &Block) -> Result<(Vec<Study>, Vec<Vec<Axis>>)> {
    match n {
        7 => Ok((
            FIG7_OMEGAS
                .iter()
                .enumerate()
                .map(|(k, &omega)| fig7_study(omega, seed.wrapping_add(k as u64), block))
                .collect(),
            Vec::new(),
        )),
        9 => Ok((
            [0.0, std::f64::consts::FRAC_PI_2]
                .into_iter()
                .enumerate()
                .map(|(k, beta)| fig9_study(beta, seed.wrapping_add(k as u64), block))
                .collect(),
            Vec::new(),
        )),
        10 => {
            let (study, binnings) = fig10_study(seed, block);
            Ok((vec![study], binnings))
        }
        _ => Err(Error::InvalidArgument {
            name: "figure",
            value: n.to_string(),
            reason: "only the sampling figures 7, 9 and 10 have count tables",
        }),
    }
}

/// Whether the count tables of sampling figure `n` bin the same trials (Fig. 10: one study,
/// three binnings) rather than count separate studies (Figs. 7 and 9).
#[must_use]
pub fn tables_share_trials(n: u32) -> bool {
    n == 10
}

/// Empty count tables of sampling figure `n` (the shapes [`counts_for`] returns).
///
/// # Errors
/// [`Error::InvalidArgument`] for another figure.
pub fn empty_tables(n: u32) -> Result<Vec<Counts>> {
    let classes = hycont_sample::basin::Classifier::classes(&RockingClassifier::default());
    let (studies, binnings) = studies(n, 0, &Block::default())?;
    let cells: Vec<usize> = if binnings.is_empty() {
        studies.iter().map(Study::cells).collect()
    } else {
        binnings
            .iter()
            .map(|axes| axes.iter().map(|a| a.bins).product())
            .collect()
    };
    Ok(cells
        .into_iter()
        .map(|c| Counts::new(classes.clone(), c))
        .collect())
}

/// The trials of `range` that `tables` (of sampling figure `n`) have not counted yet, share
/// `part = (i, k)` of them ([`hycont_sample::basin::share`]; `(0, 1)`: all): one list of ranges
/// per table, or one for all tables where they bin the same trials (Fig. 10). What [`fill`]
/// runs; processes that divide a run (MPI ranks) each take their share.
///
/// # Errors
/// An invalid share.
pub fn missing(
    n: u32,
    tables: &[Counts],
    range: std::ops::Range<u64>,
    part: (u64, u64),
) -> Result<Vec<Vec<std::ops::Range<u64>>>> {
    let counted = if tables_share_trials(n) {
        &tables[..tables.len().min(1)]
    } else {
        tables
    };
    counted
        .iter()
        .map(|t| share(&t.missing(range.clone()), part.0, part.1).map_err(sample_err))
        .collect()
}

/// Runs the trials `todo` lists (from [`missing`]: per table, or one list for tables that bin
/// the same trials) and merges them into `tables` (of sampling figure `n`): a fresh run from
/// [`empty_tables`], or the rest of an interrupted one. Stops early when `progress` says so,
/// with exact ranges.
///
/// # Errors
/// Tables or lists of another shape; numerical failures.
pub fn fill(
    n: u32,
    options: SampleOptions,
    tables: &mut [Counts],
    todo: &[Vec<std::ops::Range<u64>>],
    progress: &Progress,
) -> Result<()> {
    let classifier = RockingClassifier {
        block: options.block,
        ..RockingClassifier::default()
    };
    let (studies, binnings) = studies(n, options.seed, &options.block)?;
    let merge = |t: &mut Counts, c: &Counts| t.merge(c).map_err(sample_err);
    let shape = |what: String| {
        Err(sample_err(hycont_sample::Error::IncompatibleCounts {
            reason: what,
        }))
    };
    if binnings.is_empty() {
        if tables.len() != studies.len() || todo.len() != studies.len() {
            return shape(format!(
                "{} tables and {} lists for {} studies",
                tables.len(),
                todo.len(),
                studies.len()
            ));
        }
        for ((t, study), ranges) in tables.iter_mut().zip(&studies).zip(todo) {
            for r in ranges {
                let c = run(study, &classifier, r.clone(), progress).map_err(sample_err)?;
                merge(t, &c)?;
            }
        }
        return Ok(());
    }
    // One run fills every binning: the tables share their ranges.
    if todo.len() != 1 {
        return shape(format!("{} lists for tables that share trials", todo.len()));
    }
    for r in &todo[0] {
        let cs = hycont_sample::basin::run_binned(
            &studies[0],
            &binnings,
            &classifier,
            r.clone(),
            progress,
        )
        .map_err(sample_err)?;
        if cs.len() != tables.len() {
            return shape(format!("{} tables for {} binnings", tables.len(), cs.len()));
        }
        for (t, c) in tables.iter_mut().zip(&cs) {
            merge(t, c)?;
        }
    }
    Ok(())
}
