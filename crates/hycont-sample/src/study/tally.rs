//! [`Table`]: one count table's bookkeeping over a shard, for tables over trials
//! ([`Counts`]) and tables sampled cell by cell ([`CellCounts`]): what it has counted, what it
//! lacks, whether it holds another's trials, merging. Counting into them: [`fill_trials`],
//! [`fill_cells`].

use crate::Result;
use crate::adaptive::{Adaptive, CellCounts, run_cells};
use crate::basin::{Classifier, Counts, Progress, Study, run, share};
use std::ops::Range;

/// One count table of a study. A shard's `span` is what it splits: the indices of its trials
/// for a table over trials, of its cells for a table sampled cell by cell.
pub trait Table: Clone {
    /// Whether the trials a to-do list runs are known before they run (over trials: the
    /// lengths of its ranges; cell by cell: no, a cell runs until its rule is met).
    fn planned(&self) -> bool;
    /// What the table has done of `span`, and `span`'s size: trials counted (over trials) or
    /// cells settled (cell by cell).
    fn progress(&self, span: Range<u64>) -> (u64, u64);
    /// What of `span` the table lacks (trials, or cells not settled), share `part = (i, k)`
    /// of it ([`share`]), as ranges of indices.
    ///
    /// # Errors
    /// An invalid `part`.
    fn todo(&self, span: Range<u64>, part: (u64, u64)) -> Result<Vec<Range<u64>>>;
    /// Trials the table ran in `span`.
    fn counted(&self, span: Range<u64>) -> u64;
    /// Whether the table has every trial of `span` that `other` has (writing it over `other`
    /// loses nothing).
    fn covers(&self, other: &Self, span: Range<u64>) -> bool;
    /// Merges another process's or shard's counts of the same table in.
    ///
    /// # Errors
    /// Counts that do not merge (another shape, trials counted twice, overflow).
    fn merge(&mut self, other: &Self) -> Result<()>;
    /// What another process fills its share into, to be merged into this table: the table
    /// with nothing counted (over trials), or the table itself (cell by cell: a cell's
    /// longer record wins a merge, so others continue from it).
    #[must_use]
    fn cleared(&self) -> Self;
    /// The table's own consistency, and nothing counted outside `span`.
    ///
    /// # Errors
    /// What is wrong, in one line.
    fn check(&self, span: Range<u64>) -> std::result::Result<(), String>;
}

impl Table for Counts {
    fn planned(&self) -> bool {
        true
    }
    fn progress(&self, span: Range<u64>) -> (u64, u64) {
        let per = span.end - span.start;
        let missing: u64 = self.missing(span).iter().map(|r| r.end - r.start).sum();
        (per - missing, per)
    }
    fn todo(&self, span: Range<u64>, part: (u64, u64)) -> Result<Vec<Range<u64>>> {
        share(&self.missing(span), part.0, part.1)
    }
    fn counted(&self, span: Range<u64>) -> u64 {
        self.progress(span).0
    }
    fn covers(&self, other: &Self, span: Range<u64>) -> bool {
        super::covers(self, other, &span)
    }
    fn merge(&mut self, other: &Self) -> Result<()> {
        Counts::merge(self, other)
    }
    fn cleared(&self) -> Self {
        Counts::new(self.classes.clone(), self.counts.len())
    }
    fn check(&self, span: Range<u64>) -> std::result::Result<(), String> {
        self.validate().map_err(|e| e.to_string())?;
        match (self.ranges.iter()).find(|&&(a, b)| a < span.start || b > span.end) {
            Some(&(a, b)) => Err(format!(
                "counts trials {a}..{b}, outside the shard's trials {}..{}",
                span.start, span.end
            )),
            None => Ok(()),
        }
    }
}

impl Table for CellCounts {
    fn planned(&self) -> bool {
        false
    }
    fn progress(&self, span: Range<u64>) -> (u64, u64) {
        let cells = span.start as usize..span.end as usize;
        let open = self.unsettled(cells.clone()).len();
        ((cells.len() - open) as u64, cells.len() as u64)
    }
    fn todo(&self, span: Range<u64>, part: (u64, u64)) -> Result<Vec<Range<u64>>> {
        let cells = span.start as usize..span.end as usize;
        share(&runs(&self.unsettled(cells)), part.0, part.1)
    }
    fn counted(&self, span: Range<u64>) -> u64 {
        self.trials[span.start as usize..span.end as usize]
            .iter()
            .sum()
    }
    /// A cell's record is a prefix of its stream: the longer holds the shorter.
    fn covers(&self, other: &Self, _: Range<u64>) -> bool {
        self.trials.len() == other.trials.len()
            && (self.trials.iter()).zip(&other.trials).all(|(x, y)| x >= y)
    }
    fn merge(&mut self, other: &Self) -> Result<()> {
        CellCounts::merge(self, other)
    }
    fn cleared(&self) -> Self {
        self.clone()
    }
    /// Its shape and sums, and no trials in another shard's cells (the stopping rule is the
    /// file's to check, with [`CellCounts::check_rule`]).
    fn check(&self, span: Range<u64>) -> std::result::Result<(), String> {
        self.validate().map_err(|e| e.to_string())?;
        let outside = (0..self.trials.len() as u64).find(|c| {
            !span.contains(c) && (self.trials[*c as usize] > 0 || self.settled[*c as usize])
        });
        match outside {
            Some(c) => Err(format!("cell {c}: another shard's cell has trials here")),
            None => Ok(()),
        }
    }
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
