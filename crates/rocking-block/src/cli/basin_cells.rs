//! `basin --halfwidth`: a basin run sampled cell by cell ([`hycont_sample::adaptive`]) until
//! every class's 95 % Wilson half-width in every cell is at most the target, or the cell has
//! `--max-per-cell` trials; `BasinCellFile` is its count file (shards split cells; partial
//! files, `--resume`, `merge` and MPI as the other sampling runs).

use crate::basin::{classifier, write_basin};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::sampling::sample_err;
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts};
use hycont_sample::basin::{Counts, Progress, Study, shard_range};
use hycont_sample::study::{TableFile, fill_cells};
use std::path::PathBuf;

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
}

impl TableFile for BasinCellFile {
    type Table = CellCounts;
    type Error = Error;
    const WRITER: &'static str = "basin --halfwidth";
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
        self.table.counts.len() as u64
    }
    fn tables(&self) -> &[CellCounts] {
        std::slice::from_ref(&self.table)
    }
    fn tables_mut(&mut self) -> &mut [CellCounts] {
        std::slice::from_mut(&mut self.table)
    }
    fn same_run(&self, other: &Self) -> std::result::Result<(), String> {
        if (&self.study, self.rule, self.block) != (&other.study, other.rule, other.block) {
            return Err("study, rule or block differ from the files before".into());
        }
        Ok(())
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let c = classifier(&self.block);
        let study = (&self.study, &c);
        fill_cells(study, &self.rule, &mut self.table, todo, progress).map_err(sample_err)
    }
    /// A valid rule, study and block; the table of the study's cells and classes, every cell
    /// as the rule leaves it.
    fn check(&self) -> std::result::Result<(), String> {
        self.rule.validate().map_err(|e| e.to_string())?;
        crate::basin::validate(&self.study, &self.block).map_err(|e| e.to_string())?;
        let expected = hycont_sample::basin::Classifier::classes(&classifier(&self.block));
        if self.table.classes != expected || self.table.counts.len() != self.study.cells() {
            return Err("the table does not fit the study's cells and classes".into());
        }
        let (i, n) = self.shard;
        let span = shard_range(self.extent(), i, n).map_err(|e| e.to_string())?;
        (self.table)
            .check_rule(
                &self.rule,
                &self.study,
                span.start as usize..span.end as usize,
            )
            .map_err(|e| e.to_string())
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
