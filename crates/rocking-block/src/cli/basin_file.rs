//! `BasinFile`: the count table of a `basin` run on disk (its study, trials, shard and block),
//! complete or not.

use super::driver::Render;
use super::shard_file::MAX_TRIALS;
use crate::basin::{classifier, validate, write_basin};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::sampling::sample_err;
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::{Counts, Progress, Study};
use hycont_sample::study::{TableFile, fill_trials};
use std::path::{Path, PathBuf};

/// The counts of a basin run over one shard of its trials, complete or not.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct BasinFile {
    /// The study (variables, axes, seed).
    pub study: Study,
    /// The block.
    pub block: Block,
    /// Trials of the whole run.
    pub trials: u64,
    /// `(i, n)`: shard `i` of `n` (a whole run is `(0, 1)`).
    pub shard: (u64, u64),
    /// The counts (classes as [`crate::classes::RockingClassifier`]'s).
    pub counts: Counts,
    /// The invocation that started the run (for a merge: the merge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<Provenance>,
}

/// Whether `path` holds a basin file (rather than a sampling figure's shard).
pub(super) fn is_basin_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("study").is_some())
}

impl TableFile for BasinFile {
    type Table = Counts;
    type Error = Error;
    const WRITER: &'static str = "basin";
    fn what(&self) -> String {
        "basin".into()
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
        std::slice::from_ref(&self.counts)
    }
    fn tables_mut(&mut self) -> &mut [Counts] {
        std::slice::from_mut(&mut self.counts)
    }
    fn same_run(&self, other: &Self) -> std::result::Result<(), String> {
        if (&self.study, self.block, self.trials) != (&other.study, other.block, other.trials) {
            return Err("another study, block or trial count than the files before".into());
        }
        Ok(())
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let c = classifier(&self.block);
        fill_trials((&self.study, &c), &mut self.counts, todo, progress).map_err(sample_err)
    }
    /// A valid study and block, trials in range, the classes and cells of the study.
    fn check(&self) -> std::result::Result<(), String> {
        validate(&self.study, &self.block).map_err(|e| e.to_string())?;
        if self.trials == 0 || self.trials > MAX_TRIALS {
            return Err(format!("{} trials: need 1..=10^12", self.trials));
        }
        let classes = hycont_sample::basin::Classifier::classes(&classifier(&self.block));
        if self.counts.classes != classes || self.counts.counts.len() != self.study.cells() {
            return Err(format!(
                "{} cells of classes {:?}; the study has {} cells of {:?}",
                self.counts.counts.len(),
                self.counts.classes,
                self.study.cells(),
                classes
            ));
        }
        Ok(())
    }
}

impl Render for BasinFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let provenance = self
            .provenance
            .clone()
            .unwrap_or_default()
            .with_trials(self.trials);
        write_basin(
            out,
            &self.study,
            &self.block,
            &self.counts,
            provenance,
            |_| {},
        )
    }
}
