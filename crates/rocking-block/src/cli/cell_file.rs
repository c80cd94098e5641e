//! `CellFile`: Fig. 7 or 9 sampled cell by cell on disk (its per-cell tables, stopping rule,
//! seed, block and shard of cells), complete or not: what `figure 7` and `figure 9` (without
//! `--trials`), their shards, their partial files, `--resume` and `merge` read and write. A shard `I/N` runs the cells of
//! [`hycont_sample::basin::shard_range`]`(cells, I, N)`; a cell's record with more trials
//! contains one with fewer, so merging keeps the longer.

use super::FigureArgs;
use super::driver::cell_rule;
use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::cells::{
    BY_CELLS, DEFAULT_HALFWIDTH, cell_studies, empty_cell_tables, fill_cells, render_cells,
};
use crate::figures::sampling::SampleOptions;
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts};
use hycont_sample::basin::{Progress, shard_range};
use hycont_sample::study::TableFile;
use std::path::{Path, PathBuf};

/// Fig. 7 or 9 sampled cell by cell, whole or one shard of its cells.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct CellFile {
    /// The figure (7 or 9).
    pub figure: u32,
    /// The stopping rule.
    pub rule: Adaptive,
    /// Seed of the study.
    pub seed: u64,
    /// `(i, n)`: shard `i` of `n` of the cells (a whole run is `(0, 1)`).
    pub shard: (u64, u64),
    /// One table per panel (Fig. 7: per omega, Fig. 9: per beta).
    pub tables: Vec<CellCounts>,
    /// The block.
    pub block: Block,
    /// The invocation that started the run (for a merge: the merge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<Provenance>,
}

/// Whether the text of a count file is a [`CellFile`] (it names its rule).
pub(super) fn is_cell_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("rule").is_some())
}

impl CellFile {
    /// A run of figure `figure` (7 or 9) to `rule` with nothing counted.
    pub(super) fn new(
        figure: u32,
        rule: Adaptive,
        seed: u64,
        shard: (u64, u64),
        block: Block,
    ) -> Result<Self> {
        Ok(CellFile {
            figure,
            rule,
            seed,
            shard,
            tables: empty_cell_tables(figure)?,
            block,
            provenance: None,
        })
    }

    fn options(&self) -> SampleOptions {
        SampleOptions {
            trials: 0,
            seed: self.seed,
            block: self.block,
        }
    }
}

impl TableFile for CellFile {
    type Table = CellCounts;
    type Error = Error;
    const WRITER: &'static str = "figure 7 or 9 sampled cell by cell";
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
        self.tables.first().map_or(0, |t| t.counts.len()) as u64
    }
    fn tables(&self) -> &[CellCounts] {
        &self.tables
    }
    fn tables_mut(&mut self) -> &mut [CellCounts] {
        &mut self.tables
    }
    fn same_run(&self, other: &Self) -> std::result::Result<(), String> {
        if (self.figure, self.rule, self.seed, self.block)
            != (other.figure, other.rule, other.seed, other.block)
        {
            return Err(format!(
                "rule {:?}, seed {} or block differ from the files before (rule {:?}, seed {})",
                other.rule, other.seed, self.rule, self.seed
            ));
        }
        Ok(())
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let cells: Vec<Vec<usize>> = todo
            .iter()
            .map(|rs| {
                rs.iter()
                    .flat_map(|r| r.start as usize..r.end as usize)
                    .collect()
            })
            .collect();
        let (options, rule) = (self.options(), self.rule);
        fill_cells(
            self.figure,
            &options,
            &rule,
            &mut self.tables,
            &cells,
            progress,
        )
    }
    /// The figure's tables (Fig. 7: six, Fig. 9: two), every cell as the rule leaves it: whole
    /// batches, settled exactly when it meets the rule, nothing in another shard's cells.
    fn check(&self) -> std::result::Result<(), String> {
        if !BY_CELLS.contains(&self.figure) {
            return Err(format!("figure {} is not sampled by cells", self.figure));
        }
        self.rule.validate().map_err(|e| e.to_string())?;
        self.block.validate().map_err(|e| e.to_string())?;
        let fig = self.figure;
        let expected = empty_cell_tables(fig).map_err(|e| e.to_string())?;
        if self.tables.len() != expected.len() {
            let (got, want) = (self.tables.len(), expected.len());
            return Err(format!("{got} tables; Fig. {fig} has {want}"));
        }
        let (i, n) = self.shard;
        let span = shard_range(self.extent(), i, n).map_err(|e| e.to_string())?;
        let studies = cell_studies(fig, &self.options()).map_err(|e| e.to_string())?;
        for (k, ((t, e), study)) in self.tables.iter().zip(&expected).zip(&studies).enumerate() {
            if t.classes != e.classes || t.counts.len() != e.counts.len() {
                return Err(format!("table {k} is not a Fig. {fig} table"));
            }
            let cells = span.start as usize..span.end as usize;
            (t.check_rule(&self.rule, study, cells)).map_err(|e| format!("table {k}: {e}"))?;
        }
        Ok(())
    }
}

/// The stopping rule of Figs. 7 and 9 sampled cell by cell (`--halfwidth`, `--max-per-cell`).
pub(super) fn cells_rule(args: &FigureArgs) -> Result<Adaptive> {
    cell_rule(
        args.halfwidth.unwrap_or(DEFAULT_HALFWIDTH),
        args.max_per_cell,
    )
}

impl super::driver::Render for CellFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let invocation = self
            .provenance
            .clone()
            .unwrap_or_default()
            .with_block(self.block);
        let (options, rule) = (self.options(), &self.rule);
        Ok(render_cells(self.figure, out, &options, rule, &invocation, &self.tables)?.files)
    }
}
