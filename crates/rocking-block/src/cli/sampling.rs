//! `figure` and `merge`: the study's figures, sampling shards, interrupts, resuming and merging.
//!
//! A sampling run (Figs. 7, 9, 10, whole or one shard) that is interrupted (SIGINT, SIGTERM,
//! SIGHUP) writes the exact trials it counted to a `*.partial.json` file, which never replaces
//! a complete result; `figure --resume FILE` runs the missing trials and writes the complete
//! result. `merge` checks every file, merges them and writes the figure when the trials are
//! complete, a partial file otherwise.

use super::cell_file::{CellFile, fig9_rule};
use super::ranks::Ranks;
use super::shard_file::{MAX_TRIALS, SAMPLING, ShardFile};
use super::{FigureArgs, MergeArgs, print_written};
use crate::error::{Error, Result};
use crate::figures::sampling::{SampleOptions, empty_tables};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::basin::Progress;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

pub(super) fn parse_shard(text: &str) -> Result<(u64, u64)> {
    let bad = || Error::InvalidArgument {
        name: "shard",
        value: text.to_string(),
        reason: "expected I/N with 0 <= I < N",
    };
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Sizes rayon's pool (only the first call of a process does; results do not depend on it).
///
/// # Errors
/// [`Error::InvalidArgument`] for zero threads.
pub(super) fn set_threads(threads: Option<usize>) -> Result<()> {
    if let Some(n) = threads {
        if n == 0 {
            return Err(Error::InvalidArgument {
                name: "threads",
                value: "0".into(),
                reason: "must be at least 1",
            });
        }
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global();
    }
    Ok(())
}

/// Removes the partial file a resumed run completed (unless it was rewritten).
pub(super) fn use_up(from: &Path, written: &[PathBuf]) {
    if from.to_string_lossy().ends_with(".partial.json") && !written.iter().any(|w| w == from) {
        let _ = std::fs::remove_file(from);
    }
}

/// Stops sampling runs on SIGINT, SIGTERM and SIGHUP (their counts so far are kept).
pub(super) fn stop_on_signals(progress: &Arc<Progress>) {
    let p = Arc::clone(progress);
    // Only the first handler of the process is installed (tests call `run` repeatedly).
    let _ = ctrlc::set_handler(move || p.stop.store(true, Ordering::Relaxed));
}

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
        if n == 9 && args.trials.is_none() {
            let mut file =
                CellFile::new(fig9_rule(args)?, args.seed, shard.unwrap_or((0, 1)), block);
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
    if args.halfwidth.is_some() && !which.contains(&9) {
        return Err(Error::InvalidArgument {
            name: "halfwidth",
            value: format!("figures {}", crate::figures::names(which)),
            reason: "applies to Fig. 9 (sampled cell by cell)",
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

/// Trial ranges to run: one list per table, or one for tables that bin the same trials.
pub(super) type Todo = Vec<Vec<std::ops::Range<u64>>>;

/// A file of count tables over one shard of a sampling run's trials (a sampling figure's, or a
/// basin's), complete or not: what `sample` and `merge` need of it.
pub(super) trait CountFile: Sized + serde::Serialize + serde::de::DeserializeOwned {
    /// What is sampled, for messages (`figure 7`, `basin`).
    fn what(&self) -> String;
    /// Trials counted and trials of the shard (for runs sampled cell by cell: cells settled and
    /// cells of the shard).
    fn progress(&self) -> (u64, u64);
    /// `(i, n)`: shard `i` of `n`.
    fn shard(&self) -> (u64, u64);
    /// Where the complete shard (or, for a whole run, the result) goes, and the partial file.
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf);
    /// The trials of the shard not counted yet, share `part = (i, k)` of them (`(0, 1)`: all):
    /// what [`CountFile::fill`] runs.
    fn todo(&self, part: (u64, u64)) -> Result<Todo>;
    /// How many trials `todo` runs, where that is known before they run (for the progress
    /// bar; default: the trials its ranges hold).
    fn planned_trials(&self, todo: &Todo) -> Option<u64> {
        Some(todo.iter().flatten().map(|r| r.end - r.start).sum())
    }
    /// Trials counted so far (default: as [`CountFile::progress`] counts).
    fn counted_trials(&self) -> u64 {
        self.progress().0
    }
    /// Counts the trials `todo` lists (from [`CountFile::todo`]).
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()>;
    /// What another process (an MPI rank) fills its share of the trials into, to be merged
    /// into this file: the same run and shard with nothing counted, or the file itself where
    /// a merge keeps the longer record (cells sampled to a half-width).
    fn cleared(&self) -> Self;
    /// Writes the result of the counted trials into `out`.
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>>;
    /// Writes the file itself.
    fn write(&self, path: &Path) -> Result<()>;
    /// Merges another shard's counts of the same run in (the same study, trials and seed).
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String>;
    /// The file as a whole run (shard 0 of 1), for a merge.
    fn whole(self) -> Self;
    /// Reads and checks a file of this kind.
    fn read(path: &Path) -> Result<Self>;
    /// Whether this file is of the same run and shard as `other` and has counted every trial
    /// `other` has (writing it over `other` loses nothing).
    fn subsumes(&self, other: &Self) -> bool;
    /// Whether every table has counted every trial of the shard.
    fn is_complete(&self) -> bool {
        let (done, total) = self.progress();
        done == total
    }
}

/// Counts the trials `file` lacks (with a progress bar on stderr) and writes the result: the
/// figure or the shard when complete; otherwise the partial file (and, with `force`, the result
/// of the trials counted so far) and [`Error::Interrupted`]. In an MPI job every rank counts
/// its share and rank 0 alone writes (the other ranks return no files).
pub(super) fn sample<F: CountFile>(
    file: F,
    out: &OutDir,
    force: bool,
    progress: &Progress,
) -> Result<Vec<PathBuf>> {
    // The processes of an MPI job each count their share of the trials left; rank 0 merges
    // them and goes on as a single process would (one process: the whole share).
    let ranks = Ranks::current();
    let todo = file.todo(ranks.part())?;
    let done = file.counted_trials();
    progress.done.store(done, Ordering::Relaxed);
    let planned = file.planned_trials(&todo);
    let (bar, template) = match planned {
        _ if !ranks.is_root() => (indicatif::ProgressBar::hidden(), ""),
        Some(mine) => (
            indicatif::ProgressBar::new(done + mine),
            "{msg} [{bar:40}] {pos}/{len} trials ({per_sec}, eta {eta})",
        ),
        // Adaptive runs do not know their trials in advance.
        None => (
            indicatif::ProgressBar::no_length(),
            "{msg} {spinner} {pos} trials ({per_sec})",
        ),
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(file.what());
    let finished = AtomicBool::new(false);
    let checkpoint = (ranks.part().1 > 1)
        .then(|| super::checkpoint::checkpoint_path(&file.paths(&out.dir).0, ranks.part()));
    let result = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !finished.load(Ordering::Relaxed) {
                bar.set_position(progress.done.load(Ordering::Relaxed));
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
        });
        let mut counted = if ranks.is_root() {
            file
        } else {
            file.cleared()
        };
        // Several ranks: each checkpoints its counts after every round of its share.
        let r = match &checkpoint {
            Some(path) => super::checkpoint::fill_in_rounds(&mut counted, &todo, progress, path),
            None => counted.fill(&todo, progress),
        }
        .map(|()| counted);
        finished.store(true, Ordering::Relaxed);
        r
    });
    bar.finish_and_clear();
    let Some(file) = ranks.gather(result)? else {
        return Ok(Vec::new());
    };
    // Once rank 0 has written what every rank counted, their checkpoints are not needed (it
    // removes them from the output directory, shared by the ranks on a cluster).
    let drop_checkpoint = || {
        if let Some(path) = &checkpoint {
            super::checkpoint::remove_all(path, ranks.part().1);
        }
    };
    let (complete, partial) = file.paths(&out.dir);
    let whole = file.shard().1 == 1;
    if file.is_complete() {
        let written = if whole {
            file.render(out)?
        } else {
            file.write(&complete)?;
            vec![complete]
        };
        drop_checkpoint();
        return Ok(written);
    }
    let (partial, write) = partial_path(&file, partial);
    if write {
        file.write(&partial)?;
    }
    drop_checkpoint();
    if force && whole {
        file.render(out)?;
    }
    let (done, total) = file.progress();
    Err(Error::Interrupted {
        detail: format!(
            "{done} of {total} trials counted, kept in {}; complete them with `rocking-block {} --resume {}`",
            partial.display(),
            if file.what() == "basin" {
                "basin"
            } else {
                "figure"
            },
            partial.display()
        ),
    })
}

/// Where an interrupted run keeps its counts, and whether it must write them: at `partial`,
/// replacing what is there only if this run has counted every trial of it; where a partial
/// file of the same run there has counted every trial this one has, that file keeps them
/// (nothing to write); otherwise (another study's file, or counts neither holds all of) beside
/// it, with this process's id in the name, so that no counted trial is lost.
fn partial_path<F: CountFile>(file: &F, partial: PathBuf) -> (PathBuf, bool) {
    match F::read(&partial) {
        Err(_) if !partial.exists() => return (partial, true),
        Ok(existing) if file.subsumes(&existing) => return (partial, true),
        Ok(existing) if existing.subsumes(file) => return (partial, false),
        // Another study's counts, a file that is not a count file of this kind, or counts
        // that overlap this run's only in part: not replaced.
        _ => {}
    }
    let name = partial
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let stem = name.strip_suffix(".partial.json").unwrap_or(&name);
    let beside = partial.with_file_name(format!("{stem}.{}.partial.json", std::process::id()));
    (beside, true)
}

/// Merges count files of one run: the result when complete, a partial file otherwise.
pub(super) fn merge_files<F: CountFile>(
    files: Vec<(PathBuf, F)>,
    out: &OutDir,
    invocation: &Provenance,
    set_invocation: impl FnOnce(&mut F, Provenance),
) -> Result<Vec<PathBuf>> {
    let mut merged: Option<F> = None;
    for (path, file) in files {
        let Some(m) = merged.as_mut() else {
            merged = Some(file.whole());
            continue;
        };
        m.merge(&file)
            .map_err(|reason| Error::InvalidFile { path, reason })?;
    }
    let Some(mut m) = merged else {
        return Err(Error::InvalidArgument {
            name: "shards",
            value: String::new(),
            reason: "name at least one shard file",
        });
    };
    set_invocation(&mut m, invocation.clone());
    if m.is_complete() {
        return m.render(out);
    }
    let (_, partial) = m.paths(&out.dir);
    m.write(&partial)?;
    let (done, total) = m.progress();
    Err(Error::Incomplete {
        detail: format!(
            "the files hold {done} of {total} trials: wrote {} (the result needs them all); run the missing trials with `rocking-block {} --resume {}`",
            partial.display(),
            if m.what() == "basin" {
                "basin"
            } else {
                "figure"
            },
            partial.display()
        ),
    })
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
        .is_some_and(|p| super::basin_cmd::is_basin_file(p));
    let cells = args
        .shards
        .first()
        .is_some_and(|p| super::cell_file::is_cell_file(p));
    let files = if cells && basins {
        let files = args
            .shards
            .iter()
            .map(|p| Ok((p.clone(), super::basin_cells::BasinCellFile::read(p)?)))
            .collect::<Result<Vec<_>>>()?;
        merge_files(files, &dir, invocation, |f, p| f.provenance = Some(p))?
    } else if cells {
        let files = args
            .shards
            .iter()
            .map(|p| Ok((p.clone(), CellFile::read(p)?)))
            .collect::<Result<Vec<_>>>()?;
        merge_files(files, &dir, invocation, |f, p| {
            f.provenance = Some(p.with_block(f.block));
        })?
    } else if basins {
        let files = args
            .shards
            .iter()
            .map(|p| Ok((p.clone(), super::basin_cmd::BasinFile::read(p)?)))
            .collect::<Result<Vec<_>>>()?;
        merge_files(files, &dir, invocation, |f, p| f.provenance = Some(p))?
    } else {
        let files = args
            .shards
            .iter()
            .map(|p| Ok((p.clone(), ShardFile::read(p)?)))
            .collect::<Result<Vec<_>>>()?;
        merge_files(files, &dir, invocation, |f, p| {
            f.provenance = Some(p.with_block(f.block));
        })?
    };
    print_written(out, &files, args.json)
}
