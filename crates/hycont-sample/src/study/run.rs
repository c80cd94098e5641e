//! Running a study's missing trials to completion or to a stop, and merging shards.

use super::checkpoint::{checkpoint_path, fill_in_rounds, remove_checkpoints};
use super::count_file::CountFile;
use super::ranks::Ranks;
use crate::Error;
use crate::basin::Progress;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// How a [`sample`] run ended.
#[derive(Debug)]
#[non_exhaustive]
pub enum Outcome<F> {
    /// Every trial of the shard is counted. A shard of several was written to `written` (its
    /// complete path); a whole run's file is the result, which the driver renders.
    Complete {
        /// The counts.
        file: F,
        /// Where the complete shard was written (`None` for a whole run).
        written: Option<PathBuf>,
    },
    /// Stopped before every trial was counted: the exact trials counted are kept in the
    /// partial file `path`.
    Partial {
        /// The counts.
        file: F,
        /// Where they are kept.
        path: PathBuf,
    },
    /// This process is a rank other than 0 of an MPI job: its counts went to rank 0, which
    /// writes.
    Elsewhere,
}

/// Counts the trials `file` lacks and writes what the run has: the complete shard (a whole
/// run's complete file is left to the driver, which renders it), or the partial file when
/// `progress` stops it first (never over a complete result or a partial file holding trials
/// this run lacks: [`partial_path`]). In an MPI job (`ranks`, e.g. [`Ranks::current`]) every
/// rank counts its share, checkpointing it in rounds into `dir`
/// ([`super::checkpoint_path`]), and rank 0 gathers and writes; the checkpoints are removed
/// once rank 0 has written.
///
/// # Errors
/// A trial's failure (the file's [`CountFile::fill`]), a rank's ([`Error::Rank`]), a file that
/// cannot be written.
pub fn sample<F: CountFile>(
    file: F,
    dir: &Path,
    progress: &Progress,
    ranks: Ranks,
) -> Result<Outcome<F>, F::Error>
where
    F::Error: std::fmt::Display,
{
    let todo = file.todo(ranks.part())?;
    progress
        .done
        .store(file.counted_trials(), Ordering::Relaxed);
    let (complete, partial) = file.paths(dir);
    let checkpoint = (ranks.part().1 > 1).then(|| checkpoint_path(&complete, ranks.part()));
    let mut counted = if ranks.is_root() {
        file
    } else {
        file.cleared()
    };
    // Several ranks: each checkpoints its counts after every round of its share.
    let mine = match &checkpoint {
        Some(path) => fill_in_rounds(&mut counted, &todo, progress, (path, ranks)),
        None => counted.fill(&todo, progress),
    }
    .map(|()| counted);
    let Some(file) = ranks.gather(mine)? else {
        return Ok(Outcome::Elsewhere);
    };
    // Once rank 0 has written what every rank counted, their checkpoints are not needed.
    let drop_checkpoints = || {
        if let Some(path) = &checkpoint {
            remove_checkpoints(path, ranks.part().1);
        }
    };
    if file.is_complete() {
        let written = if file.shard().1 == 1 {
            None
        } else {
            file.write(&complete)?;
            Some(complete)
        };
        drop_checkpoints();
        return Ok(Outcome::Complete { file, written });
    }
    let (path, write) = partial_path(&file, partial);
    if write {
        file.write(&path)?;
    }
    drop_checkpoints();
    Ok(Outcome::Partial { file, path })
}

/// Where an interrupted run keeps its counts, and whether it must write them: at `partial`,
/// replacing what is there only if this run has counted every trial of it; where a partial
/// file of the same run there has counted every trial this one has, that file keeps them
/// (nothing to write); otherwise (another study's file, or counts neither holds all of) beside
/// it, with this process's id in the name, so that no counted trial is lost.
#[must_use]
pub fn partial_path<F: CountFile>(file: &F, partial: PathBuf) -> (PathBuf, bool) {
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

/// Merges count files of one study (shards, partial files, ranks' checkpoints; each read and
/// checked by [`CountFile::read`]) into the whole run's: complete when they hold every trial.
///
/// # Errors
/// [`Error::InvalidFile`] naming the first file that does not merge and why (another study,
/// trials counted twice, counts that overflow); [`Error::InvalidStudy`] for no files.
pub fn merge<F: CountFile>(files: Vec<(PathBuf, F)>) -> Result<F, F::Error> {
    let mut merged: Option<F> = None;
    for (path, file) in files {
        let Some(m) = merged.as_mut() else {
            merged = Some(file.whole());
            continue;
        };
        m.merge(&file)
            .map_err(|reason| Error::InvalidFile { path, reason })?;
    }
    merged.ok_or_else(|| {
        Error::InvalidStudy {
            reason: "no count files to merge".into(),
        }
        .into()
    })
}
