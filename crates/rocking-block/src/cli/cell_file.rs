//! `CellFile`: an adaptively sampled Fig. 9 on disk (its per-cell tables, stopping rule, seed,
//! block and shard of cells), complete or not: what `figure 9 --halfwidth`, its shards, its
//! partial files, `--resume` and `merge` read and write. A shard `I/N` runs the cells of
//! [`hycont_sample::basin::shard_range`]`(cells, I, N)`; a cell's record with more trials
//! contains one with fewer, so merging keeps the longer.

use super::FigureArgs;
use super::driver::{CELL_BATCH, count_paths, read_count_file, runs, write_count_file};
use super::driver::{CountFile, Todo};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::figures::fig9_cells::{DEFAULT_HALFWIDTH, empty_cell_tables, fill_cells, render9_cells};
use crate::figures::sampling::{SampleOptions, sample_err};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::{Adaptive, CellCounts};
use hycont_sample::basin::{Progress, shard_range, share};
use hycont_sample::study::{cells_counted, cells_cover, cells_progress};
use std::path::{Path, PathBuf};

/// An adaptively sampled Fig. 9, whole or one shard of its cells.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct CellFile {
    /// The figure (9).
    pub figure: u32,
    /// The stopping rule.
    pub rule: Adaptive,
    /// Seed of the study.
    pub seed: u64,
    /// `(i, n)`: shard `i` of `n` of the cells (a whole run is `(0, 1)`).
    pub shard: (u64, u64),
    /// One table per beta.
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
    /// A run of Fig. 9 to `rule` with nothing counted.
    pub(super) fn new(rule: Adaptive, seed: u64, shard: (u64, u64), block: Block) -> Self {
        CellFile {
            figure: 9,
            rule,
            seed,
            shard,
            tables: empty_cell_tables(),
            block,
            provenance: None,
        }
    }

    fn options(&self) -> SampleOptions {
        SampleOptions {
            trials: 0,
            seed: self.seed,
            block: self.block,
        }
    }

    /// The cells of the shard.
    fn cells(&self) -> std::ops::Range<usize> {
        let n = self.tables.first().map_or(0, |t| t.counts.len()) as u64;
        let r = shard_range(n, self.shard.0, self.shard.1).unwrap_or(0..0);
        r.start as usize..r.end as usize
    }

    fn check(&self) -> std::result::Result<(), String> {
        if self.figure != 9 {
            return Err(format!("figure {} is not sampled by cells", self.figure));
        }
        self.rule.validate().map_err(|e| e.to_string())?;
        let (i, n) = self.shard;
        if n == 0 || i >= n {
            return Err(format!("shard {i}/{n} is not I/N with 0 <= I < N"));
        }
        self.block.validate().map_err(|e| e.to_string())?;
        let expected = empty_cell_tables();
        if self.tables.len() != expected.len() {
            return Err(format!("{} tables; Fig. 9 has 2", self.tables.len()));
        }
        let studies = crate::figures::fig9_cells::fig9_cell_studies(&self.options());
        for (k, ((t, e), study)) in self.tables.iter().zip(&expected).zip(&studies).enumerate() {
            if t.classes != e.classes || t.counts.len() != e.counts.len() {
                return Err(format!("table {k} is not a Fig. 9 table"));
            }
            // Every cell as the rule leaves it: whole batches, settled exactly when it meets
            // the rule, nothing in another shard's cells.
            (t.check_rule(&self.rule, study, self.cells()))
                .map_err(|e| format!("table {k}: {e}"))?;
        }
        Ok(())
    }
}

impl CountFile for CellFile {
    type Error = crate::error::Error;
    fn what(&self) -> String {
        "figure 9".into()
    }
    /// Settled cells and cells of the shard, over both tables.
    fn progress(&self) -> (u64, u64) {
        let cells = self.cells();
        (self.tables.iter())
            .map(|t| cells_progress(t, cells.clone()))
            .fold((0, 0), |(a, b), (c, d)| (a + c, b + d))
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        count_paths(dir, "fig9", self.shard)
    }
    /// Cells (as ranges of cell indices) not settled yet, share `part` of them per table.
    fn todo(&self, part: (u64, u64)) -> Result<Todo> {
        self.tables
            .iter()
            .map(|t| share(&runs(&t.unsettled(self.cells())), part.0, part.1).map_err(sample_err))
            .collect()
    }
    fn planned_trials(&self, _: &Todo) -> Option<u64> {
        None
    }
    fn counted_trials(&self) -> u64 {
        let cells = self.cells();
        (self.tables.iter())
            .map(|t| cells_counted(t, cells.clone()))
            .sum()
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
        fill_cells(&options, &rule, &mut self.tables, &cells, progress)
    }
    /// The same file: a cell's longer record wins a merge, so other processes continue from it.
    fn cleared(&self) -> Self {
        self.clone()
    }
    fn write(&self, path: &Path) -> Result<()> {
        write_count_file(self, path)
    }
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String> {
        if (self.figure, self.rule, self.seed, self.block)
            != (other.figure, other.rule, other.seed, other.block)
        {
            return Err(format!(
                "rule {:?}, seed {} or block differ from the files before (rule {:?}, seed {})",
                other.rule, other.seed, self.rule, self.seed
            ));
        }
        for (a, b) in self.tables.iter_mut().zip(&other.tables) {
            a.merge(b).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
    fn whole(self) -> Self {
        CellFile {
            shard: (0, 1),
            ..self
        }
    }
    fn read(path: &Path) -> Result<Self> {
        read_count_file(path, "figure 9 --halfwidth", CellFile::check)
    }
    fn subsumes(&self, other: &Self) -> bool {
        (self.figure, self.rule, self.seed, self.shard, self.block)
            == (
                other.figure,
                other.rule,
                other.seed,
                other.shard,
                other.block,
            )
            && (self.tables.iter())
                .zip(&other.tables)
                .all(|(a, b)| cells_cover(a, b))
    }
}

/// The stopping rule of Fig. 9 sampled adaptively (`--halfwidth`, `--max-per-cell`), in
/// batches of [`CELL_BATCH`].
pub(super) fn fig9_rule(args: &FigureArgs) -> Result<Adaptive> {
    let rule = Adaptive {
        halfwidth: args.halfwidth.unwrap_or(DEFAULT_HALFWIDTH),
        max_trials: args.max_per_cell,
        batch: CELL_BATCH,
    };
    rule.validate().map_err(|e| Error::InvalidArgument {
        name: "halfwidth",
        value: format!("{} (--max-per-cell {})", rule.halfwidth, rule.max_trials),
        reason: if e.to_string().contains("max_trials") {
            "--max-per-cell must be at least one batch of 16 trials"
        } else {
            "must be in (0, 0.5)"
        },
    })?;
    Ok(rule)
}

impl super::driver::Render for CellFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let invocation = self
            .provenance
            .clone()
            .unwrap_or_default()
            .with_block(self.block);
        Ok(render9_cells(out, &self.options(), &self.rule, &invocation, &self.tables)?.files)
    }
}
