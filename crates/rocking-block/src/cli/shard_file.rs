//! The count tables of a sampling figure on disk (and how `figure`, `merge` and `--resume`
//! count into them, [`TableFile`]): a shard (`figN.shard-I-of-N.json`), a
//! partial run (`*.partial.json`, written on an interrupt or by an incomplete merge) or both.
//! Every file read is checked against the figure's tables before it is used.

use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::sampling::{empty_tables, fill, render, tables_share_trials};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::{Counts, Progress};
use hycont_sample::study::{CountFile, TableFile};
use std::path::PathBuf;

/// The sampling figures that have count tables.
pub const SAMPLING: [u32; 3] = [7, 9, 10];

/// The most trials per study a run may ask for (10^12: about 30 CPU-years at the study's rate;
/// shard larger studies into separate runs of this size).
pub const MAX_TRIALS: u64 = 1_000_000_000_000;

/// Count tables of a sampling figure over the trials of one shard, complete or not.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
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

impl ShardFile {
    /// Parses and checks the text of a file ([`TableFile::parse`]).
    ///
    /// # Errors
    /// What is wrong with it, in one line.
    pub fn parse(text: &str) -> std::result::Result<Self, String> {
        <Self as TableFile>::parse(text)
    }

    /// Trials counted and trials of the shard ([`CountFile::progress`]).
    pub fn progress(&self) -> (u64, u64) {
        CountFile::progress(self)
    }

    /// Whether every table has counted every trial of the shard.
    pub fn is_complete(&self) -> bool {
        CountFile::is_complete(self)
    }

    /// The sampling options of the run.
    pub fn options(&self) -> crate::figures::sampling::SampleOptions {
        crate::figures::sampling::SampleOptions {
            trials: self.trials,
            seed: self.seed,
            block: self.block,
        }
    }
}

impl TableFile for ShardFile {
    type Table = Counts;
    type Error = Error;
    const WRITER: &'static str = "figure N --shard I/N";
    fn what(&self) -> String {
        format!("figure {}", self.figure)
    }
    fn stem(&self) -> String {
        format!("fig{}", self.figure)
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn set_shard(&mut self, shard: (u64, u64)) {
        self.shard = shard;
    }
    fn extent(&self) -> u64 {
        self.trials
    }
    fn tables(&self) -> &[Counts] {
        &self.counts
    }
    fn tables_mut(&mut self) -> &mut [Counts] {
        &mut self.counts
    }
    /// Fig. 10's tables bin the same trials.
    fn shares_trials(&self) -> bool {
        tables_share_trials(self.figure)
    }
    fn same_run(&self, other: &Self) -> std::result::Result<(), String> {
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
        Ok(())
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let options = self.options();
        fill(self.figure, options, &mut self.counts, todo, progress)
    }
    /// A sampling figure, a trial count in range, a valid block, the figure's table shapes
    /// and classes.
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
        match (self.counts.iter().zip(&expected).enumerate())
            .find(|(_, (c, e))| c.classes != e.classes || c.counts.len() != e.counts.len())
        {
            Some((k, (c, e))) => Err(format!(
                "table {k} has {} cells of classes {:?}; figure {} has {} cells of {:?}",
                c.counts.len(),
                c.classes,
                self.figure,
                e.counts.len(),
                e.classes
            )),
            None => Ok(()),
        }
    }
}

impl super::driver::Render for ShardFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let invocation = self.provenance.clone().unwrap_or_default();
        Ok(render(self.figure, out, self.options(), &invocation, &self.counts)?.files)
    }
}
