//! The command line's glue to the library's study runner ([`hycont_sample::study`]): the
//! progress bar, signals, threads, shard arguments, the paths and reading and writing of
//! count files, and the [`Render`] of each count file's result. The count files themselves
//! (`shard_file`, `cell_file`, `basin_file`, `basin_cells`: [`hycont_sample::study::TableFile`]s)
//! and the commands (`sampling`: `figure` and `merge`; `basin_cmd`) build on it.

use super::ranks::Ranks;
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::provenance::Provenance;
use hycont_sample::adaptive::Adaptive;
use hycont_sample::basin::Progress;
use hycont_sample::study::Outcome;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A library error of text that does not parse as the argument `name` (`--name`), as the
/// command line's own.
pub(super) fn spec_err(name: &'static str) -> impl Fn(hycont_sample::Error) -> Error {
    move |e| match e {
        hycont_sample::Error::InvalidSpec { spec, reason } => Error::InvalidArgument {
            name,
            value: spec,
            reason,
        },
        other => other.into(),
    }
}

/// `--shard I/N`.
pub(super) fn parse_shard(text: &str) -> Result<(u64, u64)> {
    hycont_sample::study::parse_shard(text).map_err(spec_err("shard"))
}

/// Sizes rayon's pool (only the first call of a process does; results do not depend on it).
///
/// # Errors
/// [`Error::InvalidArgument`] for zero threads.
pub(super) fn set_threads(threads: Option<usize>) -> Result<()> {
    hycont_sample::study::set_threads(threads).map_err(spec_err("threads"))
}

pub(super) use hycont_sample::study::use_up;

/// Stops sampling runs on SIGINT, SIGTERM and SIGHUP (their counts so far are kept).
pub(super) fn stop_on_signals(progress: &Arc<Progress>) {
    let p = Arc::clone(progress);
    // Only the first handler of the process is installed (tests call `run` repeatedly).
    let _ = ctrlc::set_handler(move || p.stop.store(true, Ordering::Relaxed));
}

pub(super) use hycont_sample::study::CountFile;

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
            "{done} of {total} trials counted, kept in {}; complete them with {}",
            partial.display(),
            resume_hint(&file, &partial)
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
            "the files hold {done} of {total} trials: wrote {} (the result needs them all); run the missing trials with {}",
            partial.display(),
            resume_hint(&m, &partial)
        ),
    })
}

/// The command that completes `file`'s partial file `partial`.
fn resume_hint<F: CountFile>(file: &F, partial: &Path) -> String {
    let command = if file.what() == "basin" {
        "basin"
    } else {
        "figure"
    };
    format!("`rocking-block {command} --resume {}`", partial.display())
}

/// Reads each of `paths` as a count file of kind `F` and merges them ([`merge_files`]).
pub(super) fn merge_paths<F: CountFile<Error = Error> + Render>(
    paths: &[PathBuf],
    out: &OutDir,
    invocation: &Provenance,
    set_invocation: impl FnOnce(&mut F, Provenance),
) -> Result<Vec<PathBuf>> {
    let files = (paths.iter())
        .map(|p| Ok((p.clone(), F::read(p)?)))
        .collect::<Result<Vec<_>>>()?;
    merge_files(files, out, invocation, set_invocation)
}

/// Trials per cell and round of the runs sampled cell by cell (Fig. 9, `basin --halfwidth`):
/// a cell of one class meets the default half-width 0.1 after one batch (the Wilson
/// half-width of 0 of 16 is 0.097).
pub(super) const CELL_BATCH: u64 = 16;

/// The stopping rule of `--halfwidth H --max-per-cell N` (Fig. 9, `basin`), in batches of
/// [`CELL_BATCH`].
///
/// # Errors
/// [`Error::InvalidArgument`] naming the flag out of range.
pub(super) fn cell_rule(halfwidth: f64, max_per_cell: u64) -> Result<Adaptive> {
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
