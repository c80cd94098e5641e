//! The bookkeeping every count file of one table does, over trials or cells: what it has
//! counted, what it lacks, and counting it. [`super::StudyFile`] is built from these, and a
//! driver's own count files (other layouts on disk) can be too.

use super::count_file::Todo;
use crate::Result;
use crate::adaptive::{Adaptive, CellCounts, run_cells};
use crate::basin::{Classifier, Counts, Progress, Study, run, share};
use std::ops::Range;

/// Trials of `range` that `counts` has counted, and `range`'s trials.
#[must_use]
pub fn trials_progress(counts: &Counts, range: Range<u64>) -> (u64, u64) {
    let per = range.end - range.start;
    let missing: u64 = counts.missing(range).iter().map(|r| r.end - r.start).sum();
    (per - missing, per)
}

/// The trials of `range` that `counts` lacks, share `part = (i, k)` of them, as one list.
///
/// # Errors
/// An invalid `part`.
pub fn trials_todo(counts: &Counts, range: Range<u64>, part: (u64, u64)) -> Result<Todo> {
    Ok(vec![share(&counts.missing(range), part.0, part.1)?])
}

/// Counts the trials `todo` lists into `counts` (stopping when `progress` says so).
///
/// # Errors
/// A trial's classification failure or counts that do not merge.
pub fn fill_trials<C: Classifier>(
    (study, classifier): (&Study, &C),
    counts: &mut Counts,
    todo: &[Vec<Range<u64>>],
    progress: &Progress,
) -> Result<()> {
    for r in todo.iter().flatten() {
        if progress.stopping() {
            break;
        }
        counts.merge(&run(study, classifier, r.clone(), progress)?)?;
    }
    Ok(())
}

/// Cells of `cells` that `counts` has settled, and `cells`' number.
#[must_use]
pub fn cells_progress(counts: &CellCounts, cells: Range<usize>) -> (u64, u64) {
    let open = counts.unsettled(cells.clone()).len();
    ((cells.len() - open) as u64, cells.len() as u64)
}

/// The cells of `cells` that `counts` has not settled, share `part` of them, as one list of
/// ranges of cell indices.
///
/// # Errors
/// An invalid `part`.
pub fn cells_todo(counts: &CellCounts, cells: Range<usize>, part: (u64, u64)) -> Result<Todo> {
    Ok(vec![share(
        &runs(&counts.unsettled(cells)),
        part.0,
        part.1,
    )?])
}

/// Trials `counts` ran in `cells`.
#[must_use]
pub fn cells_counted(counts: &CellCounts, cells: Range<usize>) -> u64 {
    counts.trials[cells].iter().sum()
}

/// Samples the cells `todo` lists (ranges of cell indices) to `rule` into `counts`.
///
/// # Errors
/// As [`run_cells`].
pub fn fill_cells<C: Classifier>(
    (study, classifier): (&Study, &C),
    rule: &Adaptive,
    counts: &mut CellCounts,
    todo: &[Vec<Range<u64>>],
    progress: &Progress,
) -> Result<()> {
    let cells: Vec<usize> = todo
        .iter()
        .flatten()
        .flat_map(|r| r.start as usize..r.end as usize)
        .collect();
    run_cells(study, classifier, rule, counts, &cells, progress)
}

/// Whether `a` has run every trial `b` has in every cell (a cell's record is a prefix of its
/// stream: the longer holds the shorter).
#[must_use]
pub fn cells_cover(a: &CellCounts, b: &CellCounts) -> bool {
    a.trials.len() == b.trials.len() && a.trials.iter().zip(&b.trials).all(|(x, y)| x >= y)
}

/// Ranges of consecutive cells.
///
/// ```
/// assert_eq!(hycont_sample::study::runs(&[0, 1, 2, 5, 7, 8]), vec![0..3, 5..6, 7..9]);
/// ```
#[must_use]
pub fn runs(cells: &[usize]) -> Vec<Range<u64>> {
    let mut out: Vec<Range<u64>> = Vec::new();
    for &c in cells {
        let c = c as u64;
        match out.last_mut() {
            Some(r) if r.end == c => r.end = c + 1,
            _ => out.push(c..c + 1),
        }
    }
    out
}
