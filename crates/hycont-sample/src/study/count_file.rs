//! What a study has counted over its shard of the trials: the interface [`super::sample`] and
//! [`super::merge`] drive.

use crate::basin::{Counts, Progress};
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Trial ranges to run: one list per table, or one for tables that bin the same trials (or,
/// for a study sampled cell by cell, cells).
pub type Todo = Vec<Vec<Range<u64>>>;

/// A file of count tables over one shard of a study's trials, complete or not: what a study
/// driver counts into, writes, resumes and merges. `Error` is the driver's error type, into
/// which this crate's errors convert.
pub trait CountFile: Sized + serde::Serialize + serde::de::DeserializeOwned {
    /// The driver's error.
    type Error: From<crate::Error>;
    /// What is sampled, for messages (e.g. `figure 7`, `basin`).
    fn what(&self) -> String;
    /// Trials counted and trials of the shard (for studies sampled cell by cell: cells
    /// settled and cells of the shard).
    fn progress(&self) -> (u64, u64);
    /// `(i, n)`: shard `i` of `n`.
    fn shard(&self) -> (u64, u64);
    /// Where the complete shard (or, for a whole run, the result's count file) goes, and the
    /// partial file.
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf);
    /// The trials of the shard not counted yet, share `part = (i, k)` of them (`(0, 1)`: all):
    /// what [`CountFile::fill`] runs.
    ///
    /// # Errors
    /// The driver's, e.g. a shard that does not fit the study.
    fn todo(&self, part: (u64, u64)) -> Result<Todo, Self::Error>;
    /// How many trials `todo` runs, where that is known before they run (for a progress bar;
    /// default: the trials its ranges hold).
    fn planned_trials(&self, todo: &Todo) -> Option<u64> {
        Some(todo.iter().flatten().map(|r| r.end - r.start).sum())
    }
    /// Trials counted so far (default: as [`CountFile::progress`] counts).
    fn counted_trials(&self) -> u64 {
        self.progress().0
    }
    /// Counts the trials `todo` lists (from [`CountFile::todo`]).
    ///
    /// # Errors
    /// A trial that fails (the driver's classifier).
    fn fill(&mut self, todo: &[Vec<Range<u64>>], progress: &Progress) -> Result<(), Self::Error>;
    /// What another process (an MPI rank) fills its share of the trials into, to be merged
    /// into this file: the same study and shard with nothing counted, or the file itself
    /// where a merge keeps the longer record (cells sampled to a half-width).
    #[must_use]
    fn cleared(&self) -> Self;
    /// Writes the file itself (atomically, e.g. with [`super::write_atomic`]).
    ///
    /// # Errors
    /// The file cannot be written.
    fn write(&self, path: &Path) -> Result<(), Self::Error>;
    /// Merges another shard's counts of the same study in (the same study, trials and seed).
    ///
    /// # Errors
    /// Why they do not merge, in one line.
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String>;
    /// The file as a whole run (shard 0 of 1), for a merge.
    #[must_use]
    fn whole(self) -> Self;
    /// Reads and checks a file of this kind.
    ///
    /// # Errors
    /// The file cannot be read or is not a valid count file of this kind.
    fn read(path: &Path) -> Result<Self, Self::Error>;
    /// Whether this file is of the same study and shard as `other` and has counted every
    /// trial `other` has (writing it over `other` loses nothing).
    fn subsumes(&self, other: &Self) -> bool;
    /// Whether every table has counted every trial of the shard.
    fn is_complete(&self) -> bool {
        let (done, total) = self.progress();
        done == total
    }
}

/// Whether table `a` has counted every trial of `range` that table `b` has (every trial `a`
/// lacks, `b` lacks too): what [`CountFile::subsumes`] asks of each table.
///
/// ```
/// use hycont_sample::basin::Counts;
/// use hycont_sample::study::covers;
/// let (mut a, mut b) = (Counts::new(vec!["x".into()], 1), Counts::new(vec!["x".into()], 1));
/// a.ranges = vec![(0, 10)];
/// a.counts = vec![vec![10]];
/// b.ranges = vec![(2, 5)];
/// b.counts = vec![vec![3]];
/// assert!(covers(&a, &b, &(0..10)) && !covers(&b, &a, &(0..10)));
/// ```
#[must_use]
pub fn covers(a: &Counts, b: &Counts, range: &Range<u64>) -> bool {
    let b_missing = b.missing(range.clone());
    a.missing(range.clone()).iter().all(|m| {
        // [m.start, m.end) lies in the union of b's missing intervals (sorted, disjoint).
        let mut at = m.start;
        for g in &b_missing {
            if g.start <= at && at < g.end {
                at = g.end;
            }
        }
        at >= m.end
    })
}
