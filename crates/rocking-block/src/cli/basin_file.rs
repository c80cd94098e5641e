//! `BasinFile`: the count table of a `basin` run on disk (its study, trials, shard and block),
//! complete or not, and how a basin's result is written (`basin.json`, `.csv`, `.svg`).

use super::driver::{CountFile, Render, Todo, count_paths, covers, write_count_file};
use super::read_err;
use super::shard_file::MAX_TRIALS;
use crate::basin::{classifier, folded, result_csv, result_json, validate};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::{Counts, Distribution, Progress, Study};
use hycont_sample::study::{fill_trials, trials_progress, trials_todo};
use std::path::{Path, PathBuf};

/// The counts of a basin run over one shard of its trials, complete or not.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
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

impl BasinFile {
    /// Reads and checks a file.
    ///
    /// # Errors
    /// [`Error::Read`], or [`Error::InvalidFile`] naming what is wrong.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(read_err(path))?;
        let invalid = |reason: String| Error::InvalidFile {
            path: path.to_path_buf(),
            reason,
        };
        let file: BasinFile = serde_json::from_str(&text)
            .map_err(|e| invalid(format!("not a basin file written by `basin` ({e})")))?;
        file.check().map_err(invalid)?;
        Ok(file)
    }

    fn check(&self) -> std::result::Result<(), String> {
        validate(&self.study, &self.block).map_err(|e| e.to_string())?;
        let (i, n) = self.shard;
        if self.trials == 0 || self.trials > MAX_TRIALS || n == 0 || i >= n {
            return Err(format!(
                "{} trials, shard {i}/{n}: need 1..=10^12 trials and 0 <= I < N",
                self.trials
            ));
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
        self.counts.validate().map_err(|e| e.to_string())?;
        let range = self.range();
        if let Some(&(a, b)) = self
            .counts
            .ranges
            .iter()
            .find(|&&(a, b)| a < range.start || b > range.end)
        {
            return Err(format!(
                "counts trials {a}..{b}, outside the shard's trials {}..{}",
                range.start, range.end
            ));
        }
        Ok(())
    }

    fn range(&self) -> std::ops::Range<u64> {
        let (i, n) = self.shard;
        hycont_sample::basin::shard_range(self.trials, i, n).unwrap_or(0..0)
    }
}

impl CountFile for BasinFile {
    type Error = crate::error::Error;
    fn what(&self) -> String {
        "basin".into()
    }
    fn progress(&self) -> (u64, u64) {
        trials_progress(&self.counts, self.range())
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        count_paths(dir, "basin", self.shard)
    }
    fn todo(&self, part: (u64, u64)) -> Result<Todo> {
        Ok(trials_todo(&self.counts, self.range(), part)?)
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let c = classifier(&self.block);
        fill_trials((&self.study, &c), &mut self.counts, todo, progress)
            .map_err(crate::figures::sampling::sample_err)
    }
    fn cleared(&self) -> Self {
        BasinFile {
            study: self.study.clone(),
            block: self.block,
            trials: self.trials,
            shard: self.shard,
            counts: Counts::new(self.counts.classes.clone(), self.counts.counts.len()),
            provenance: self.provenance.clone(),
        }
    }
    fn read(path: &Path) -> Result<Self> {
        BasinFile::read(path)
    }
    fn subsumes(&self, other: &Self) -> bool {
        (&self.study, self.block, self.trials, self.shard)
            == (&other.study, other.block, other.trials, other.shard)
            && covers(&self.counts, &other.counts, &self.range())
    }
    fn write(&self, path: &Path) -> Result<()> {
        write_count_file(self, path)
    }
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String> {
        if (&self.study, self.block, self.trials) != (&other.study, other.block, other.trials) {
            return Err("another study, block or trial count than the files before".into());
        }
        self.counts.merge(&other.counts).map_err(|e| e.to_string())
    }
    fn whole(self) -> Self {
        BasinFile {
            shard: (0, 1),
            ..self
        }
    }
}

/// The picture's title: the fixed variables and the block.
/// Writes a basin's files: `basin.json` (the result with `provenance`, completed with the
/// block and seed, and amended by `extra`), `basin.csv` and the picture.
pub(super) fn write_basin(
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
