//! `figure` and `merge`: the study's figures, sampling shards, interrupts, resuming and merging.
//!
//! A sampling run (Figs. 7, 9, 10, whole or one shard) that is interrupted (SIGINT, SIGTERM,
//! SIGHUP) writes the exact trials it counted to a `*.partial.json` file, which never replaces
//! a complete result; `figure --resume FILE` runs the missing trials and writes the complete
//! result. `merge` checks every file, merges them and writes the figure when the trials are
//! complete, a partial file otherwise.

use super::basin_cells::BasinCellFile;
use super::basin_file::BasinFile;
use super::cell_file::{CellFile, cells_rule};
use super::driver::{
    CountFile, merge_paths, parse_shard, sample, set_threads, stop_on_signals, use_up,
};
use super::ranks::Ranks;
use super::shard_file::{MAX_TRIALS, SAMPLING, ShardFile};
use super::{FigureArgs, MergeArgs, print_written};
use crate::error::{Error, Result};
use crate::figures::cells::BY_CELLS;
use crate::figures::sampling::{SampleOptions, empty_tables};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::Progress;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::Ordering;

/// The figures `figure` draws: those named (a number or `all`), or the figure of the file
/// resumed (which a name must then agree with).
fn figures_to_draw(which: Option<&str>, resume: Option<u32>) -> Result<Vec<u32>> {
    match (resume, which) {
        (Some(figure), Some(w)) if crate::figures::parse(w)? != [figure] => {
            Err(Error::InvalidArgument {
                name: "figure",
                value: w.to_string(),
                reason: "differs from the figure of the --resume file",
            })
        }
        (Some(figure), _) => Ok(vec![figure]),
        (None, Some(w)) => crate::figures::parse(w),
        (None, None) => Err(Error::InvalidArgument {
            name: "figure",
            value: String::new(),
            reason: "name a figure (2 to 10, `atlas` or `all`), or --resume a partial file",
        }),
    }
}

/// A file `figure --resume` completes: trials of a sampling figure, or cells of Fig. 9
/// sampled adaptively.
enum Resumed {
    Trials(ShardFile),
    Cells(CellFile),
}

impl Resumed {
    fn read(path: &Path) -> Result<Self> {
        Ok(if super::cell_file::is_cell_file(path) {
            Resumed::Cells(CellFile::read(path)?)
        } else {
            Resumed::Trials(ShardFile::read(path)?)
        })
    }
    fn figure(&self) -> u32 {
        match self {
            Resumed::Trials(f) => f.figure,
            Resumed::Cells(f) => f.figure,
        }
    }
}

pub(super) fn run_figure(
    args: &FigureArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    let resume = args.resume.as_deref().map(Resumed::read).transpose()?;
    if resume.is_some() && args.block.given() {
        return Err(Error::InvalidArgument {
            name: "block options",
            value: "given with --resume".into(),
            reason: "a resumed run keeps the block it was started for",
        });
    }
    let block = args.block.block()?;
    let invocation = &invocation
        .clone()
        .with_block(block)
        .with_dimensional(super::block_args::figure_dimensional(&args.block)?)
        .with_recipe(args.recipe.recipe()?);
    let which = figures_to_draw(args.which.as_deref(), resume.as_ref().map(Resumed::figure))?;
    let shard = checked_options(args, &which, invocation)?;
    let trials = |n: u32| {
        args.trials
            .unwrap_or_else(|| crate::figures::sampling::default_trials(n))
    };
    set_threads(args.threads)?;
    crate::output::check_dir(&args.out)?;
    let dir = OutDir::new(&args.out).with_format(args.format);
    let progress = Arc::new(Progress {
        budget: args.stop_after,
        ..Progress::default()
    });
    stop_on_signals(&progress);
    if let Some(file) = resume {
        let from = args.resume.clone().unwrap_or_default();
        let files = match file {
            Resumed::Trials(f) => sample(f, &dir, args.force, &progress)?,
            Resumed::Cells(f) => sample(f, &dir, args.force, &progress)?,
        };
        use_up(&from, &files);
        return print_written(out, &files, args.json);
    }
    let mut written: Vec<PathBuf> = Vec::new();
    for n in which {
        if BY_CELLS.contains(&n) && args.trials.is_none() {
            let shard = shard.unwrap_or((0, 1));
            let mut file = CellFile::new(n, cells_rule(args)?, args.seed, shard, block)?;
            file.provenance = Some(invocation.clone());
            written.extend(sample(file, &dir, args.force, &progress)?);
        } else if SAMPLING.contains(&n) {
            let file = ShardFile {
                figure: n,
                trials: trials(n),
                seed: args.seed,
                shard: shard.unwrap_or((0, 1)),
                counts: empty_tables(n)?,
                block,
                provenance: Some(invocation.clone()),
            };
            written.extend(sample(file, &dir, args.force, &progress)?);
        } else if n == crate::figures::ATLAS && Ranks::current().is_root() {
            written.extend(super::diagram_cmd::figure_atlas(&dir, invocation, block)?);
        } else if Ranks::current().is_root() {
            // In an MPI job, rank 0 alone draws the figures that are not sampled.
            let options = SampleOptions {
                trials: trials(n),
                seed: args.seed,
                block,
            };
            match crate::figures::figure_with(n, &dir, options, invocation, &progress) {
                Ok(files) => written.extend(files.files),
                Err(e @ Error::Interrupted { .. }) => {
                    // Stopped inside the figure: the ones before it are complete.
                    print_written(out, &written, args.json)?;
                    return Err(e);
                }
                Err(e) => return Err(e),
            }
        }
        if progress.stop.load(Ordering::Relaxed) {
            // Rank 0 reports an interrupt for the job (the other ranks wrote nothing).
            if !Ranks::current().is_root() {
                return Ok(());
            }
            print_written(out, &written, args.json)?;
            return Err(Error::Interrupted {
                detail: format!("after figure {n}; the figures written above are complete"),
            });
        }
    }
    print_written(out, &written, args.json)
}

/// Checks the options of `figure` against the figures drawn: a recipe other than the study's
/// only for the branch figures, trials in range, a shard of one sampling figure (returned).
fn checked_options(
    args: &FigureArgs,
    which: &[u32],
    invocation: &Provenance,
) -> Result<Option<(u64, u64)>> {
    if !invocation.recipe().is_study() && !which.iter().any(|n| (3..=5).contains(n)) {
        return Err(Error::InvalidArgument {
            name: "continuation options",
            value: format!("figures {}", crate::figures::names(which)),
            reason: "--method, --h0, --h-min, --h-max, --max-points, --ntst, --ncol, --tol, --adapt-every and --mesh-tol apply to the branch figures 3, 4 and 5",
        });
    }
    if let Some(t) = args.trials.filter(|t| !(1..=MAX_TRIALS).contains(t)) {
        return Err(Error::InvalidArgument {
            name: "trials",
            value: t.to_string(),
            reason: "must be in 1..=10^12 (shard larger studies into separate runs)",
        });
    }
    if args.halfwidth.is_some() && !which.iter().any(|n| BY_CELLS.contains(n)) {
        return Err(Error::InvalidArgument {
            name: "halfwidth",
            value: format!("figures {}", crate::figures::names(which)),
            reason: "applies to Figs. 7 and 9 (sampled cell by cell)",
        });
    }
    let shard = args.shard.as_deref().map(parse_shard).transpose()?;
    if shard.is_some() && !matches!(which, [n] if SAMPLING.contains(n)) {
        return Err(Error::InvalidArgument {
            name: "shard",
            value: args.which.clone().unwrap_or_default(),
            reason: "shard one sampling figure (7, 9 or 10) at a time",
        });
    }
    Ok(shard)
}

pub(super) fn run_merge(
    args: &MergeArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    crate::output::check_dir(&args.out)?;
    let dir = OutDir::new(&args.out).with_format(args.format);
    let basins = args
        .shards
        .first()
        .is_some_and(|p| super::basin_file::is_basin_file(p));
    let cells = args
        .shards
        .first()
        .is_some_and(|p| super::cell_file::is_cell_file(p));
    let (shards, invocation) = (&args.shards, invocation);
    let with_block = |p: Provenance, b| Some(p.with_block(b));
    let files = match (cells, basins) {
        (true, true) => merge_paths(shards, &dir, invocation, |f: &mut BasinCellFile, p| {
            f.provenance = Some(p);
        })?,
        (true, false) => merge_paths(shards, &dir, invocation, |f: &mut CellFile, p| {
            f.provenance = with_block(p, f.block);
        })?,
        (false, true) => merge_paths(shards, &dir, invocation, |f: &mut BasinFile, p| {
            f.provenance = Some(p);
        })?,
        (false, false) => merge_paths(shards, &dir, invocation, |f: &mut ShardFile, p| {
            f.provenance = with_block(p, f.block);
        })?,
    };
    print_written(out, &files, args.json)
}
