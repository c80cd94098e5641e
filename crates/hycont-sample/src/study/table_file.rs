//! [`TableFile`]: a file of one or more count [`Table`]s over one shard and what they count,
//! in the driver's own layout on disk. Every `TableFile` is a [`CountFile`]: the bookkeeping
//! (progress, what is missing, checks, merging, which file holds more) comes from its tables,
//! and the driver says only what is its own: its study, how it counts, how it is named.

use super::count_file::{CountFile, Todo};
use super::files::write_atomic;
use super::tally::Table;
use crate::Error;
use crate::basin::{Progress, shard_range};
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A file of count tables over one shard of a study (trials, or cells sampled to a rule),
/// complete or not. Implement it for a driver's own file (its fields, its serde layout) and
/// the runner ([`super::sample`], [`super::merge`]) drives it as a [`CountFile`].
pub trait TableFile: Clone + serde::Serialize + serde::de::DeserializeOwned {
    /// Its tables' type ([`crate::basin::Counts`] or [`crate::adaptive::CellCounts`]).
    type Table: Table;
    /// The driver's error, into which this crate's errors convert.
    type Error: From<Error>;
    /// What wrote a file of this kind, for the message naming a file that is not one (e.g.
    /// `figure N --shard I/N`).
    const WRITER: &'static str;
    /// What is sampled, for messages (e.g. `figure 7`, `basin`).
    fn what(&self) -> String;
    /// The stem of its file names: `STEM.json` (a whole run), `STEM.shard-I-of-N.json`,
    /// `*.partial.json` ([`shard_paths`]); by default [`TableFile::what`].
    fn stem(&self) -> String {
        self.what()
    }
    /// `(i, n)`: shard `i` of `n` (a whole run is `(0, 1)`).
    fn shard(&self) -> (u64, u64);
    /// Sets the shard (a merge makes the whole run, `(0, 1)`).
    fn set_shard(&mut self, shard: (u64, u64));
    /// What the shards split: the study's trials (tables over trials) or cells.
    fn extent(&self) -> u64;
    /// The tables.
    fn tables(&self) -> &[Self::Table];
    /// The tables, to merge into.
    fn tables_mut(&mut self) -> &mut [Self::Table];
    /// Whether the tables bin the same trials (one run fills them all; their to-do is one
    /// list, and they must have counted the same trials), rather than count separate studies.
    fn shares_trials(&self) -> bool {
        false
    }
    /// Why `other` is not of the same study and run as this file (anything but its counts,
    /// shard and provenance differs), in one line naming what differs.
    ///
    /// # Errors
    /// That line.
    fn same_run(&self, other: &Self) -> std::result::Result<(), String>;
    /// Counts what `todo` lists (one list per table, or one for tables that share trials).
    ///
    /// # Errors
    /// A trial that fails.
    fn fill(&mut self, todo: &[Vec<Range<u64>>], progress: &Progress) -> Result<(), Self::Error>;
    /// The driver's own checks of a file read (its study, the tables' number, shapes and
    /// classes; a stopping rule), before the tables' own ([`Table::check`]).
    ///
    /// # Errors
    /// What is wrong, in one line.
    fn check(&self) -> std::result::Result<(), String>;

    /// Parses the text of a file of this kind and checks it: a valid shard, the driver's
    /// [`TableFile::check`], every table's ([`Table::check`]), and tables that share trials
    /// having counted the same ones.
    ///
    /// # Errors
    /// What is wrong with it, in one line.
    fn parse(text: &str) -> std::result::Result<Self, String> {
        let file: Self = serde_json::from_str(text)
            .map_err(|e| format!("not a file written by `{}` ({e})", Self::WRITER))?;
        check_file(&file)?;
        Ok(file)
    }
}

/// Where a file of stem `stem` (`fig9`, `basin`) of shard `(i, n)` goes in `dir`, complete and
/// partial: `stem.json` for a whole run, `stem.shard-I-of-N.json` for a shard.
///
/// ```
/// use std::path::Path;
/// let (done, partial) = hycont_sample::study::shard_paths(Path::new("out"), "fig9", (1, 4));
/// assert_eq!(done, Path::new("out/fig9.shard-1-of-4.json"));
/// assert_eq!(partial, Path::new("out/fig9.shard-1-of-4.partial.json"));
/// ```
#[must_use]
pub fn shard_paths(dir: &Path, stem: &str, (i, n): (u64, u64)) -> (PathBuf, PathBuf) {
    let name = if n == 1 {
        stem.to_string()
    } else {
        format!("{stem}.shard-{i}-of-{n}")
    };
    (
        dir.join(format!("{name}.json")),
        dir.join(format!("{name}.partial.json")),
    )
}

/// The span of a file's shard ([`Table`]'s).
fn span<F: TableFile>(file: &F) -> Range<u64> {
    let (i, n) = file.shard();
    shard_range(file.extent(), i, n).unwrap_or(0..0)
}

/// The tables that count separate trials: all, or the first where they share trials.
fn counting<F: TableFile>(file: &F) -> &[F::Table] {
    let t = file.tables();
    if file.shares_trials() {
        &t[..t.len().min(1)]
    } else {
        t
    }
}

/// A file read: a valid shard, the driver's checks, every table's, and tables that share
/// trials having counted the same.
pub(super) fn check_file<F: TableFile>(file: &F) -> std::result::Result<(), String> {
    let (i, n) = file.shard();
    if n == 0 || i >= n {
        return Err(format!("shard {i}/{n} is not I/N with 0 <= I < N"));
    }
    file.check()?;
    let span = span(file);
    let tables = file.tables();
    for (k, t) in tables.iter().enumerate() {
        t.check(span.clone())
            .map_err(|e| format!("table {k}: {e}"))?;
        if file.shares_trials()
            && k > 0
            && !(t.covers(&tables[0], span.clone()) && tables[0].covers(t, span.clone()))
        {
            return Err(format!(
                "table {k} counts {} trials, table 0 {} (or others): the tables bin the same trials",
                t.counted(span.clone()),
                tables[0].counted(span.clone())
            ));
        }
    }
    Ok(())
}

impl<F: TableFile> CountFile for F {
    type Error = F::Error;
    fn what(&self) -> String {
        TableFile::what(self)
    }
    /// Summed over the tables that count separate trials.
    fn progress(&self) -> (u64, u64) {
        let span = span(self);
        (counting(self).iter())
            .map(|t| t.progress(span.clone()))
            .fold((0, 0), |(a, b), (c, d)| (a + c, b + d))
    }
    fn shard(&self) -> (u64, u64) {
        TableFile::shard(self)
    }
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        shard_paths(dir, &self.stem(), TableFile::shard(self))
    }
    fn todo(&self, part: (u64, u64)) -> Result<Todo, F::Error> {
        let span = span(self);
        Ok((counting(self).iter())
            .map(|t| t.todo(span.clone(), part))
            .collect::<crate::Result<_>>()?)
    }
    fn planned_trials(&self, todo: &Todo) -> Option<u64> {
        (self.tables().iter().all(Table::planned))
            .then(|| todo.iter().flatten().map(|r| r.end - r.start).sum())
    }
    fn counted_trials(&self) -> u64 {
        let span = span(self);
        counting(self).iter().map(|t| t.counted(span.clone())).sum()
    }
    fn fill(&mut self, todo: &[Vec<Range<u64>>], progress: &Progress) -> Result<(), F::Error> {
        TableFile::fill(self, todo, progress)
    }
    fn cleared(&self) -> Self {
        let mut out = self.clone();
        for t in out.tables_mut() {
            *t = t.cleared();
        }
        out
    }
    fn write(&self, path: &Path) -> Result<(), F::Error> {
        let text = serde_json::to_string(self).map_err(|e| Error::Io {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Ok(write_atomic(path, text)?)
    }
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String> {
        self.same_run(other)?;
        if self.tables().len() != other.tables().len() {
            return Err(format!(
                "{} count tables; the files before have {}",
                other.tables().len(),
                self.tables().len()
            ));
        }
        for (a, b) in self.tables_mut().iter_mut().zip(other.tables()) {
            a.merge(b).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
    fn whole(mut self) -> Self {
        self.set_shard((0, 1));
        self
    }
    fn read(path: &Path) -> Result<Self, F::Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::Read {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        F::parse(&text).map_err(|reason| {
            Error::InvalidFile {
                path: path.to_path_buf(),
                reason,
            }
            .into()
        })
    }
    fn subsumes(&self, other: &Self) -> bool {
        let span = span(self);
        self.same_run(other).is_ok()
            && TableFile::shard(self) == TableFile::shard(other)
            && self.tables().len() == other.tables().len()
            && (self.tables().iter())
                .zip(other.tables())
                .all(|(a, b)| a.covers(b, span.clone()))
    }
}
