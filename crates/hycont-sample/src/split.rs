//! Splitting a study's trials among shards and processes: contiguous ranges of trial indices
//! (or of cells), sized within one of each other, so that the parts are disjoint and together
//! the whole (re-exported from [`crate::basin`]).

use crate::error::{Error, Result};

/// The trial range of shard `i` of `n` (0-based) of a study with `trials` trials.
///
/// # Errors
/// [`Error::InvalidStudy`] for `n == 0` or `i >= n`.
pub fn shard_range(trials: u64, i: u64, n: u64) -> Result<std::ops::Range<u64>> {
    if n == 0 || i >= n {
        return Err(Error::InvalidStudy {
            reason: format!("shard {i}/{n}: need 0 <= i < n"),
        });
    }
    let at = |k: u64| (u128::from(trials) * u128::from(k) / u128::from(n)) as u64;
    Ok(at(i)..at(i + 1))
}

/// Share `i` of `n` (0-based) of the trials in `ranges` (disjoint, in increasing order, as
/// [`crate::basin::Counts::missing`] gives them): the trials split in order into `n` contiguous shares whose
/// sizes differ by at most one (as [`shard_range`] splits a whole study), returned as ranges.
/// How processes (e.g. MPI ranks) divide the trials a run still lacks: the shares are disjoint
/// and together are `ranges`.
///
/// ```
/// use hycont_sample::basin::share;
/// let missing = vec![0..10, 20..30, 40..50];
/// assert_eq!(share(&missing, 0, 2).unwrap(), vec![0..10, 20..25]);
/// assert_eq!(share(&missing, 1, 2).unwrap(), vec![25..30, 40..50]);
/// assert!(share(&missing, 2, 2).is_err());
/// ```
///
/// # Errors
/// [`Error::InvalidStudy`] for `n == 0` or `i >= n`.
pub fn share(ranges: &[std::ops::Range<u64>], i: u64, n: u64) -> Result<Vec<std::ops::Range<u64>>> {
    let total: u64 = ranges.iter().map(|r| r.end.saturating_sub(r.start)).sum();
    let mine = shard_range(total, i, n)?;
    // Walk the ranges with the offset of each one's first trial among all of them.
    let mut out = Vec::new();
    let mut offset = 0u64;
    for r in ranges {
        let len = r.end.saturating_sub(r.start);
        let (a, b) = (mine.start.max(offset), mine.end.min(offset + len));
        if a < b {
            out.push(r.start + (a - offset)..r.start + (b - offset));
        }
        offset += len;
    }
    Ok(out)
}
