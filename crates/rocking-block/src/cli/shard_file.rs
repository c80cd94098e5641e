//! The count tables of a sampling figure on disk (and how `figure`, `merge` and `--resume`
//! count into them, [`CountFile`]): a shard (`figN.shard-I-of-N.json`), a
//! partial run (`*.partial.json`, written on an interrupt or by an incomplete merge) or both.
//! Every file read is checked against the figure's tables before it is used.

use super::driver::{CountFile, Todo, count_paths, covers, write_count_file};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::sampling::empty_tables;
use crate::figures::sampling::{fill, render};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::{Counts, Progress};
use std::path::{Path, PathBuf};

/// The sampling figures that have count tables.
pub const SAMPLING: [u32; 3] = [7, 9, 10];

/// The most trials per study a run may ask for (10^12: about 30 CPU-years at the study's rate;
/// shard larger studies into separate runs of this size).
pub const MAX_TRIALS: u64 = 1_000_000_000_000;

/// Count tables of a sampling figure over the trials of one shard, complete or not.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub struct ShardFile {
    /// The figure (7, 9 or 10).
    pub figure: u32,
    /// Trials of the whole study (per table).
    pub trials: u64,
    /// Seed of the study.
    pub seed: u64,
    /// `(i, n)`: shard `i` of `n` (a whole run is `(0, 1)`).
    pub shard: (u64, u64),
    /// One table per study of the figure.
    pub counts: Vec<Counts>,
    /// The block the trials are classified for (the study's in files written before it was
    /// recorded).
    #[serde(default)]
    pub block: Block,
    /// The invocation that started the run (kept when it is resumed or merged).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<Provenance>,
}

/// The trials a table has counted (the lengths of its ranges).
fn covered(c: &Counts) -> u64 {
    c.ranges.iter().map(|(a, b)| b.saturating_sub(*a)).sum()
}

fn bad(path: &Path, reason: String) -> Error {
    Error::InvalidFile {
        path: path.to_path_buf(),
        reason,
    }
}

impl ShardFile {
    /// Reads and checks a file.
    ///
    /// # Errors
    /// [`Error::InvalidFile`] naming the file and what is wrong with it.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text).map_err(|reason| bad(path, reason))
    }

    /// Parses and checks the text of a file.
    ///
    /// # Errors
    /// What is wrong with it, in one line.
    pub fn parse(text: &str) -> std::result::Result<Self, String> {
        let file: ShardFile = serde_json::from_str(text)
            .map_err(|e| format!("not a shard file written by `figure N --shard I/N` ({e})"))?;
        file.check()?;
        Ok(file)
    }

    /// The file's consistency: a sampling figure, a valid shard and trial count, the figure's
    /// table shapes and classes, and counts that agree with their trial ranges, all inside the
    /// shard's trials.
    fn check(&self) -> std::result::Result<(), String> {
        if !SAMPLING.contains(&self.figure) {
            return Err(format!("figure {} has no count tables", self.figure));
        }
        if self.trials == 0 || self.trials > MAX_TRIALS {
            return Err(format!(
                "trials = {} is not in 1..={MAX_TRIALS}",
                self.trials
            ));
        }
        let (i, n) = self.shard;
        if n == 0 || i >= n {
            return Err(format!("shard {i}/{n} is not I/N with 0 <= I < N"));
        }
        self.block.validate().map_err(|e| e.to_string())?;
        let expected = empty_tables(self.figure).map_err(|e| e.to_string())?;
        if self.counts.len() != expected.len() {
            return Err(format!(
                "{} count tables; figure {} has {}",
                self.counts.len(),
                self.figure,
                expected.len()
            ));
        }
        let range = self.range();
        let shared = crate::figures::sampling::tables_share_trials(self.figure);
        for (k, (c, e)) in self.counts.iter().zip(&expected).enumerate() {
            if c.classes != e.classes || c.counts.len() != e.counts.len() {
                return Err(format!(
                    "table {k} has {} cells of classes {:?}; figure {} has {} cells of {:?}",
                    c.counts.len(),
                    c.classes,
                    self.figure,
                    e.counts.len(),
                    e.classes
                ));
            }
            c.validate().map_err(|e| format!("table {k}: {e}"))?;
            if let Some(&(a, b)) = c
                .ranges
                .iter()
                .find(|&&(a, b)| a < range.start || b > range.end)
            {
                return Err(format!(
                    "table {k} counts trials {a}..{b}, outside the shard's trials {}..{}",
                    range.start, range.end
                ));
            }
            // Tables that bin the same trials must have counted the same ones.
            if shared && k > 0 && c.missing(range.clone()) != self.counts[0].missing(range.clone())
            {
                return Err(format!(
                    "table {k} counts {} trials, table 0 {} (or others): the figure's tables \
                     bin the same trials",
                    covered(c),
                    covered(&self.counts[0])
                ));
            }
        }
        Ok(())
    }

    /// The sampling options of the run.
    pub fn options(&self) -> crate::figures::sampling::SampleOptions {
        crate::figures::sampling::SampleOptions {
            trials: self.trials,
            seed: self.seed,
            block: self.block,
        }
    }

    /// The trials of the shard.
    pub fn range(&self) -> std::ops::Range<u64> {
        let (i, n) = self.shard;
        hycont_sample::basin::shard_range(self.trials, i, n).unwrap_or(0..0)
    }

    /// Trials counted and trials of the shard, over the figure's studies (Fig. 10's tables
    /// bin the same trials: they count once).
    pub fn progress(&self) -> (u64, u64) {
        let range = self.range();
        let per = range.end - range.start;
        let studies = if crate::figures::sampling::tables_share_trials(self.figure) {
            &self.counts[..self.counts.len().min(1)]
        } else {
            &self.counts[..]
        };
        let done = studies
            .iter()
            .map(|c| {
                per - c
                    .missing(range.clone())
                    .iter()
                    .map(|r| r.end - r.start)
                    .sum::<u64>()
            })
            .sum();
        (done, per * studies.len() as u64)
    }

    /// Whether every table has counted every trial of the shard.
    pub fn is_complete(&self) -> bool {
        let (done, total) = self.progress();
        done == total
    }

    /// Where a complete shard or figure of this file goes in `dir`, and where a partial one.
    pub fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        count_paths(dir, &format!("fig{}", self.figure), self.shard)
    }

    /// Writes the file (atomically).
    ///
    /// # Errors
    /// [`Error::Io`] naming the file.
    pub fn write(&self, path: &Path) -> Result<()> {
        debug_assert!(self.block.validate().is_ok());
        write_count_file(self, path)
    }
}

impl CountFile for ShardFile {
    type Error = crate::error::Error;
    fn what(&self) -> String {
        format!("figure {}", self.figure)
    }
    fn progress(&self) -> (u64, u64) {
        ShardFile::progress(self)
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        ShardFile::paths(self, dir)
    }
    fn todo(&self, part: (u64, u64)) -> Result<Todo> {
        crate::figures::sampling::missing(self.figure, &self.counts, self.range(), part)
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let options = self.options();
        fill(self.figure, options, &mut self.counts, todo, progress)
    }
    fn cleared(&self) -> Self {
        ShardFile {
            counts: self
                .counts
                .iter()
                .map(|c| Counts::new(c.classes.clone(), c.counts.len()))
                .collect(),
            provenance: self.provenance.clone(),
            ..*self
        }
    }
    fn write(&self, path: &Path) -> Result<()> {
        ShardFile::write(self, path)
    }
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String> {
        if self.block != other.block {
            return Err(format!(
                "block {:?} differs from the files before ({:?})",
                other.block, self.block
            ));
        }
        if (self.figure, self.trials, self.seed) != (other.figure, other.trials, other.seed) {
            return Err(format!(
                "figure {}, {} trials, seed {} differ from the files before (figure {}, {} trials, seed {})",
                other.figure, other.trials, other.seed, self.figure, self.trials, self.seed
            ));
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            a.merge(b).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
    fn whole(self) -> Self {
        ShardFile {
            shard: (0, 1),
            ..self
        }
    }
    fn read(path: &Path) -> Result<Self> {
        ShardFile::read(path)
    }
    fn subsumes(&self, other: &Self) -> bool {
        let range = self.range();
        (self.figure, self.trials, self.seed, self.shard, self.block)
            == (
                other.figure,
                other.trials,
                other.seed,
                other.shard,
                other.block,
            )
            && self
                .counts
                .iter()
                .zip(&other.counts)
                .all(|(a, b)| covers(a, b, &range))
    }
}

impl super::driver::Render for ShardFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let invocation = self.provenance.clone().unwrap_or_default();
        Ok(render(self.figure, out, self.options(), &invocation, &self.counts)?.files)
    }
}
