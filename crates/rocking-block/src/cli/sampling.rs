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
use hycont_sample::study::Outcome;
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

pub(super) use hycont_sample::study::{CountFile, Todo};

/// What a count file of the command line draws once complete (or, with `--force`, partial):
/// its figure or basin.
pub(super) trait Render {
    /// Writes the result of the counted trials into `out`.
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>>;
}

/// Counts the trials `file` lacks (with a progress bar on stderr) and writes the result: the
/// figure or the shard when complete; otherwise the partial file (and, with `force`, the result
/// of the trials counted so far) and [`Error::Interrupted`]. In an MPI job every rank counts
/// its share and rank 0 alone writes (the other ranks return no files): the library's runner
/// ([`hycont_sample::study::sample`]) with a progress bar.
pub(super) fn sample<F: CountFile<Error = Error> + Render>(
    file: F,
    out: &OutDir,
    force: bool,
    progress: &Progress,
) -> Result<Vec<PathBuf>> {
    let ranks = Ranks::current();
    let bar = progress_bar(&file, ranks)?;
    let finished = AtomicBool::new(false);
    let outcome = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !finished.load(Ordering::Relaxed) {
                bar.set_position(progress.done.load(Ordering::Relaxed));
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
        });
        let r = hycont_sample::study::sample(file, &out.dir, progress, ranks);
        finished.store(true, Ordering::Relaxed);
        r
    });
    bar.finish_and_clear();
    let (file, partial) = match outcome? {
        Outcome::Elsewhere => return Ok(Vec::new()),
        Outcome::Complete {
            written: Some(path),
            ..
        } => return Ok(vec![path]),
        Outcome::Complete {
            file,
            written: None,
        } => return file.render(out),
        Outcome::Partial { file, path } => (file, path),
        _ => return Ok(Vec::new()),
    };
    if force && file.shard().1 == 1 {
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

/// The progress bar of a run of `file`'s missing trials on stderr (hidden on ranks other than
/// 0).
fn progress_bar<F: CountFile<Error = Error>>(
    file: &F,
    ranks: Ranks,
) -> Result<indicatif::ProgressBar> {
    let done = file.counted_trials();
    let planned = file.planned_trials(&file.todo(ranks.part())?);
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
    Ok(bar)
}

/// Merges count files of one run: the result when complete, a partial file otherwise.
pub(super) fn merge_files<F: CountFile<Error = Error> + Render>(
    files: Vec<(PathBuf, F)>,
    out: &OutDir,
    invocation: &Provenance,
    set_invocation: impl FnOnce(&mut F, Provenance),
) -> Result<Vec<PathBuf>> {
    if files.is_empty() {
        return Err(Error::InvalidArgument {
            name: "shards",
            value: String::new(),
            reason: "name at least one shard file",
        });
    }
    let mut m = hycont_sample::study::merge(files)?;
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
