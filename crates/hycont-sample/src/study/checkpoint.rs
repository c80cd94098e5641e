//! Checkpoints of the ranks of an MPI run: each rank counts its share of the trials in
//! [`ROUNDS`] rounds and writes what it has counted after every round to its own checkpoint
//! file, so that a rank killed outright (SIGKILL, a node lost: `mpirun` then ends every rank,
//! and the gather at rank 0 never happens) loses at most one round. Merging the ranks'
//! checkpoints ([`super::merge`]) gives the run's partial file, which a resumed run completes;
//! a run that ends normally (complete or interrupted, its counts gathered and written by rank
//! 0) has rank 0 remove them ([`remove_checkpoints`]; they are written where the run's results
//! go, which the ranks share on a cluster).

use super::count_file::{CountFile, Todo};
use super::ranks::Ranks;
use crate::basin::Progress;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Rounds a rank's share is counted in: at most this fraction of it is lost to a kill.
pub const ROUNDS: u64 = 20;

/// Rank `rank` of `size`'s checkpoint file beside the run's result `complete` (e.g.
/// `fig10.json` gives `fig10.rank-1-of-4.checkpoint.json`).
///
/// ```
/// use std::path::Path;
/// assert_eq!(
///     hycont_sample::study::checkpoint_path(Path::new("out/fig10.shard-0-of-2.json"), (1, 4)),
///     Path::new("out/fig10.shard-0-of-2.rank-1-of-4.checkpoint.json")
/// );
/// ```
#[must_use]
pub fn checkpoint_path(complete: &Path, (rank, size): (u64, u64)) -> PathBuf {
    let name = complete
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let stem = name.strip_suffix(".json").unwrap_or(&name);
    complete.with_file_name(format!("{stem}.rank-{rank}-of-{size}.checkpoint.json"))
}

/// Removes the checkpoints of every rank of a job of `size` ranks (`own` is one of them).
pub fn remove_checkpoints(own: &Path, size: u64) {
    let name = own
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let Some((stem, _)) = name.split_once(".rank-") else {
        return;
    };
    for rank in 0..size {
        let path = own.with_file_name(format!("{stem}.rank-{rank}-of-{size}.checkpoint.json"));
        let _ = std::fs::remove_file(path);
    }
}

/// Counts `todo` (this rank's share) into `file` in [`ROUNDS`] rounds, writing `file` to
/// `checkpoint` after each. After every round the ranks agree whether any of them stops (its
/// `progress` says so, or its round failed): then all stop there, so that a stop (a signal
/// that reaches one rank, a trial budget, a failure) ends the whole job at the same round,
/// each rank keeping what it counted. Every rank runs exactly [`ROUNDS`] rounds (some
/// perhaps empty) so that their agreements pair up.
///
/// # Errors
/// As [`CountFile::fill`] and [`CountFile::write`] (this rank's).
pub fn fill_in_rounds<F: CountFile>(
    file: &mut F,
    todo: &Todo,
    progress: &Progress,
    (checkpoint, ranks): (&Path, Ranks),
) -> Result<(), F::Error> {
    let mut failure = None;
    for round in rounds_of(todo, ROUNDS) {
        if failure.is_none() && round.iter().any(|list| !list.is_empty()) {
            failure = file
                .fill(&round, progress)
                .and_then(|()| file.write(checkpoint))
                .err();
        }
        if ranks.any(progress.stopping() || failure.is_some()) {
            progress
                .stop
                .store(true, std::sync::atomic::Ordering::Relaxed);
            break;
        }
    }
    failure.map_or(Ok(()), Err)
}

/// `todo` cut into `rounds` rounds: round `k` of each list holds its trials (or cells) from
/// the `k`-th `rounds`-th of its total on, in order (empty rounds are left out).
///
/// ```
/// let todo = vec![vec![0..10, 20..23]];
/// let parts = hycont_sample::study::rounds(&todo, 2);
/// assert_eq!(parts, vec![vec![vec![0..6]], vec![vec![6..10, 20..23]]]);
/// ```
#[must_use]
pub fn rounds(todo: &Todo, rounds: u64) -> Vec<Todo> {
    rounds_of(todo, rounds)
        .into_iter()
        .filter(|round| round.iter().any(|list| !list.is_empty()))
        .collect()
}

/// [`rounds`] with the empty rounds kept: exactly `rounds` of them.
fn rounds_of(todo: &Todo, rounds: u64) -> Vec<Todo> {
    let rounds = rounds.max(1);
    let totals: Vec<u64> = todo
        .iter()
        .map(|list| list.iter().map(|r| r.end - r.start).sum())
        .collect();
    (0..rounds)
        .map(|k| {
            todo.iter()
                .zip(&totals)
                .map(|(list, &total)| {
                    let (from, to) = (total * k / rounds, total * (k + 1) / rounds);
                    slice(list, from..to)
                })
                .collect::<Todo>()
        })
        .collect()
}

/// The part of the ranges `list` (in order) from its `positions.start`-th trial up to (not
/// including) its `positions.end`-th.
fn slice(list: &[Range<u64>], positions: Range<u64>) -> Vec<Range<u64>> {
    let mut out = Vec::new();
    let mut at = 0;
    for r in list {
        let len = r.end - r.start;
        let (lo, hi) = (positions.start.max(at), positions.end.min(at + len));
        if lo < hi {
            out.push(r.start + (lo - at)..r.start + (hi - at));
        }
        at += len;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rounds hold every trial of `todo` once, in order, and no more.
    #[test]
    fn rounds_cover_the_trials_once_in_order() {
        let todo: Todo = vec![vec![0..10, 20..23, 40..41], vec![], vec![5..6]];
        for n in [1, 2, 3, 7, 20, 100] {
            let parts = rounds(&todo, n);
            for (t, list) in todo.iter().enumerate() {
                let trials: Vec<u64> = list.iter().flat_map(Clone::clone).collect();
                let got: Vec<u64> = parts
                    .iter()
                    .flat_map(|p| p[t].iter().flat_map(Clone::clone))
                    .collect();
                assert_eq!(got, trials, "{n} rounds, list {t}");
            }
            assert!(parts.len() as u64 <= n);
        }
    }
}
