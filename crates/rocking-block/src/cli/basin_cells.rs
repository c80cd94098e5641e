//! `basin --halfwidth`: a basin run sampled cell by cell ([`hycont_sample::adaptive`]) until
//! every class's 95 % Wilson half-width in every cell is at most the target, or the cell has
//! `--max-per-cell` trials; `BasinCellFile` is its count file (shards split cells; partial
//! files, `--resume`, `merge` and MPI as the other sampling runs).

use super::basin_file::write_basin;
use super::driver::CELL_BATCH;
use super::driver::{CountFile, Todo};
use super::driver::{count_paths, read_count_file, write_count_file};
use crate::basin::classifier;
use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::sampling::sample_err;
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts};
use hycont_sample::basin::{Counts, Progress, Study, shard_range};
use hycont_sample::study::{cells_counted, cells_cover, cells_progress, cells_todo, fill_cells};
use std::path::{Path, PathBuf};

/// A basin run sampled cell by cell, whole or one shard of its cells.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct BasinCellFile {
    /// The study (variables, axes, seed).
    pub study: Study,
    /// The stopping rule.
    pub rule: Adaptive,
    /// `(i, n)`: shard `i` of `n` of the cells.
    pub shard: (u64, u64),
    /// The counts per cell.
    pub table: CellCounts,
    /// The block.
    pub block: Block,
    /// The invocation that started the run (for a merge: the merge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<Provenance>,
}

/// The stopping rule of `--halfwidth H --max-per-cell N`, in batches of [`CELL_BATCH`].
pub(super) fn basin_rule(halfwidth: f64, max_per_cell: u64) -> Result<Adaptive> {
    let rule = Adaptive {
        halfwidth,
        max_trials: max_per_cell,
        batch: CELL_BATCH,
    };
    rule.validate().map_err(|e| Error::InvalidArgument {
        name: "halfwidth",
        value: format!("{halfwidth} (--max-per-cell {max_per_cell})"),
        reason: if e.to_string().contains("max_trials") {
            "--max-per-cell must be at least one batch of 16 trials"
        } else {
            "must be in (0, 0.5)"
        },
    })?;
    Ok(rule)
}

impl BasinCellFile {
    /// A run of `study` to `rule` with nothing counted.
    pub(super) fn new(study: Study, rule: Adaptive, shard: (u64, u64), block: Block) -> Self {
        let classes = hycont_sample::basin::Classifier::classes(&classifier(&block));
        BasinCellFile {
            table: CellCounts::new(classes, study.cells()),
            study,
            rule,
            shard,
            block,
            provenance: None,
        }
    }

    fn cells(&self) -> std::ops::Range<usize> {
        let r =
            shard_range(self.table.counts.len() as u64, self.shard.0, self.shard.1).unwrap_or(0..0);
        r.start as usize..r.end as usize
    }

    /// The counts as a table of the fixed-trial runs (per-cell counts, no trial ranges), for
    /// the basin's JSON, CSV and picture.
    fn as_counts(&self) -> Counts {
        Counts {
            classes: self.table.classes.clone(),
            counts: self.table.counts.clone(),
            failures: self.table.failures.clone(),
            ranges: Vec::new(),
        }
    }

    fn check(&self) -> std::result::Result<(), String> {
        self.rule.validate().map_err(|e| e.to_string())?;
        crate::basin::validate(&self.study, &self.block).map_err(|e| e.to_string())?;
        let (i, n) = self.shard;
        if n == 0 || i >= n {
            return Err(format!("shard {i}/{n} is not I/N with 0 <= I < N"));
        }
        let expected = hycont_sample::basin::Classifier::classes(&classifier(&self.block));
        if self.table.classes != expected || self.table.counts.len() != self.study.cells() {
            return Err("the table does not fit the study's cells and classes".into());
        }
        (self.table)
            .check_rule(&self.rule, &self.study, self.cells())
            .map_err(|e| e.to_string())
    }
}

impl CountFile for BasinCellFile {
    type Error = crate::error::Error;
    fn what(&self) -> String {
        "basin".into()
    }
    fn progress(&self) -> (u64, u64) {
        cells_progress(&self.table, self.cells())
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        count_paths(dir, "basin", self.shard)
    }
    fn todo(&self, part: (u64, u64)) -> Result<Todo> {
        Ok(cells_todo(&self.table, self.cells(), part)?)
    }
    fn planned_trials(&self, _: &Todo) -> Option<u64> {
        None
    }
    fn counted_trials(&self) -> u64 {
        cells_counted(&self.table, self.cells())
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let c = classifier(&self.block);
        fill_cells(
            (&self.study, &c),
            &self.rule,
            &mut self.table,
            todo,
            progress,
        )
        .map_err(sample_err)
    }
    /// The same file: a cell's longer record wins a merge.
    fn cleared(&self) -> Self {
        self.clone()
    }
    fn write(&self, path: &Path) -> Result<()> {
        write_count_file(self, path)
    }
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String> {
        if (&self.study, self.rule, self.block) != (&other.study, other.rule, other.block) {
            return Err("study, rule or block differ from the files before".into());
        }
        self.table.merge(&other.table).map_err(|e| e.to_string())
    }
    fn whole(self) -> Self {
        BasinCellFile {
            shard: (0, 1),
            ..self
        }
    }
    fn read(path: &Path) -> Result<Self> {
        read_count_file(path, "basin --halfwidth", BasinCellFile::check)
    }
    fn subsumes(&self, other: &Self) -> bool {
        (&self.study, self.rule, self.shard, self.block)
            == (&other.study, other.rule, other.shard, other.block)
            && cells_cover(&self.table, &other.table)
    }
}

impl super::driver::Render for BasinCellFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let provenance = self.provenance.clone().unwrap_or_default();
        let widths: Vec<f64> = (0..self.table.counts.len())
            .map(|c| self.table.halfwidth(c))
            .collect();
        let sampling = serde_json::json!({
            "adaptive": true,
            "halfwidth": self.rule.halfwidth,
            "batch": self.rule.batch,
            "max_trials_per_cell": self.rule.max_trials,
            "largest_halfwidth": widths.iter().copied().fold(0.0, f64::max),
            "trials_per_cell": self.table.trials,
            "largest_halfwidth_per_cell": widths,
        });
        let counts = self.as_counts();
        write_basin(out, &self.study, &self.block, &counts, provenance, |v| {
            if let Some(obj) = v.as_object_mut() {
                // Cells run their own trial streams: no trial ranges.
                obj.remove("trial_ranges");
                obj.insert("sampling".into(), sampling);
            }
        })
    }
}
