//! Basin stability: Monte-Carlo trials over initial conditions and parameters, classified, with
//! class counts aggregated per grid cell (streaming: memory independent of the number of
//! trials), in parallel, reproducible from a seed whatever the number of threads, and shardable.

use crate::error::{Error, Result};
use crate::rng::SplitMix64;
pub use crate::split::{shard_range, share};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// How one trial variable is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Distribution {
    /// Always this value.
    Fixed(f64),
    /// Uniform on $[lo, hi)$.
    Uniform {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
}

impl Distribution {
    pub(crate) fn draw(self, rng: &mut SplitMix64) -> f64 {
        match self {
            Distribution::Fixed(v) => v,
            Distribution::Uniform { lo, hi } => rng.uniform(lo, hi),
        }
    }
}

/// Binning of one trial variable into cells.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Index of the variable.
    pub variable: usize,
    /// Lower end of the binned range.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Number of bins.
    pub bins: usize,
}

impl Axis {
    fn bin(&self, v: f64) -> usize {
        let x = ((v - self.lo) / (self.hi - self.lo) * self.bins as f64).floor();
        (x.max(0.0) as usize).min(self.bins.saturating_sub(1))
    }
}

/// A basin-stability study: the variables drawn per trial, and how trials are binned (no axes:
/// one cell; one or two axes: a 1-D or 2-D grid).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Study {
    /// Names of the variables (e.g. `omega`, `alpha`, `beta`, `phi0`, `psi0`).
    pub names: Vec<String>,
    /// Their distributions.
    pub variables: Vec<Distribution>,
    /// Binning axes (at most two).
    pub axes: Vec<Axis>,
    /// Seed of the study.
    pub seed: u64,
}

impl Study {
    /// Checks the study's invariants.
    ///
    /// # Errors
    /// [`Error::InvalidStudy`] naming the problem.
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: String| Err(Error::InvalidStudy { reason });
        if self.names.len() != self.variables.len() {
            return bad(format!(
                "{} names for {} variables",
                self.names.len(),
                self.variables.len()
            ));
        }
        if self.axes.len() > 2 {
            return bad("at most two binning axes".into());
        }
        for (i, d) in self.variables.iter().enumerate() {
            match *d {
                Distribution::Fixed(v) if !v.is_finite() => {
                    return bad(format!("{} = {v} is not finite", self.names[i]));
                }
                Distribution::Uniform { lo, hi }
                    if !(lo < hi && lo.is_finite() && hi.is_finite()) =>
                {
                    return bad(format!(
                        "{} range [{lo}, {hi}) is empty or not finite",
                        self.names[i]
                    ));
                }
                _ => {}
            }
        }
        for a in &self.axes {
            if a.variable >= self.variables.len()
                || a.bins == 0
                || !(a.lo < a.hi && a.lo.is_finite() && a.hi.is_finite())
            {
                return bad(format!("invalid axis {a:?}"));
            }
        }
        let cells = self
            .axes
            .iter()
            .try_fold(1usize, |c, a| c.checked_mul(a.bins));
        if cells.is_none_or(|c| c > MAX_CELLS) {
            return bad(format!(
                "the axes have more than {MAX_CELLS} cells (count tables would not fit in memory)"
            ));
        }
        Ok(())
    }

    /// Number of cells.
    #[must_use]
    pub fn cells(&self) -> usize {
        self.axes.iter().map(|a| a.bins).product()
    }

    /// The variables of trial `index` (deterministic in `(seed, index)`).
    #[must_use]
    pub fn trial(&self, index: u64) -> Vec<f64> {
        let mut rng = SplitMix64::for_trial(self.seed, index);
        self.variables.iter().map(|d| d.draw(&mut rng)).collect()
    }

    /// The cell of a trial with these variables; `None` if `values` lacks a binned variable
    /// (values outside an axis's range fall in its first or last bin).
    #[must_use]
    pub fn cell(&self, values: &[f64]) -> Option<usize> {
        let mut cell = 0usize;
        for a in &self.axes {
            let bin = a.bin(*values.get(a.variable)?);
            cell = cell.checked_mul(a.bins)?.checked_add(bin)?;
        }
        Some(cell)
    }
}

/// The most cells a [`Study`]'s axes may have ($2^{24}$; each cell holds one count per class).
pub const MAX_CELLS: usize = 1 << 24;

/// Classifies a trial's variables into one of a fixed set of classes.
pub trait Classifier: Sync {
    /// Names of the classes; [`Classifier::classify`] returns an index into them.
    fn classes(&self) -> Vec<String>;

    /// The class of the trial with these variables.
    ///
    /// # Errors
    /// If the trial cannot be classified (counted separately as a failure).
    fn classify(&self, values: &[f64]) -> std::result::Result<usize, String>;
}

/// Class counts per cell; merges exactly (shards add up).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Counts {
    /// Class names.
    pub classes: Vec<String>,
    /// `counts[cell][class]`.
    pub counts: Vec<Vec<u64>>,
    /// Trials that could not be classified, per cell.
    pub failures: Vec<u64>,
    /// Which trial indices were run: `[start, end)` ranges (for merging shards).
    pub ranges: Vec<(u64, u64)>,
}

impl Counts {
    /// Zeroes the counts and forgets the ranges (keeps the allocation).
    fn clear(&mut self) {
        for c in &mut self.counts {
            c.fill(0);
        }
        self.failures.fill(0);
        self.ranges.clear();
    }

    /// An empty table: no trials, `cells` cells of `classes` (e.g. to [`Counts::merge`] runs
    /// into, or to resume a study from nothing).
    #[must_use]
    pub fn new(classes: Vec<String>, cells: usize) -> Self {
        let k = classes.len();
        Self {
            classes,
            counts: vec![vec![0; k]; cells],
            failures: vec![0; cells],
            ranges: Vec::new(),
        }
    }

    /// Checks the table's consistency: one count per class in every cell, one failure count
    /// per cell, trial ranges non-empty, sorted and disjoint, and the trials counted (over all
    /// cells) equal to the trials the ranges cover, without overflow.
    ///
    /// # Errors
    /// [`Error::IncompatibleCounts`] naming the inconsistency (e.g. a table read from a file
    /// that was cut or edited).
    ///
    /// ```
    /// use hycont_sample::basin::Counts;
    /// let mut c = Counts { classes: vec!["a".into()], counts: vec![vec![2]], failures: vec![1],
    ///                      ranges: vec![(0, 3)] };
    /// assert!(c.validate().is_ok());
    /// c.ranges = vec![(0, 300)]; // claims 300 trials, counts 3
    /// assert!(c.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: String| Err(Error::IncompatibleCounts { reason });
        if self.failures.len() != self.counts.len() {
            return bad(format!(
                "{} failure counts for {} cells",
                self.failures.len(),
                self.counts.len()
            ));
        }
        if let Some((cell, row)) = self
            .counts
            .iter()
            .enumerate()
            .find(|(_, r)| r.len() != self.classes.len())
        {
            return bad(format!(
                "cell {cell} has {} counts for {} classes",
                row.len(),
                self.classes.len()
            ));
        }
        let mut covered: u64 = 0;
        let mut end = 0u64;
        for (k, &(a, b)) in self.ranges.iter().enumerate() {
            if a >= b || (k > 0 && a < end) {
                return bad(format!(
                    "trial range {a}..{b} is empty, out of order or overlaps the one before"
                ));
            }
            end = b;
            covered = covered
                .checked_add(b - a)
                .ok_or_else(|| Error::IncompatibleCounts {
                    reason: "the trial ranges cover more than 2^64 trials".into(),
                })?;
        }
        let mut counted: u64 = 0;
        for v in self.counts.iter().flatten().chain(&self.failures) {
            counted = counted
                .checked_add(*v)
                .ok_or_else(|| Error::IncompatibleCounts {
                    reason: "the counts add up to more than 2^64 trials".into(),
                })?;
        }
        if counted != covered {
            return bad(format!(
                "the cells count {counted} trials but the trial ranges cover {covered}"
            ));
        }
        Ok(())
    }

    /// Adds another count table of the same study (e.g. another shard).
    ///
    /// # Errors
    /// [`Error::IncompatibleCounts`] if the class names or cells differ, the trial ranges
    /// overlap, either table is inconsistent ([`Counts::validate`]) or a count would overflow;
    /// `self` is then unchanged.
    pub fn merge(&mut self, other: &Counts) -> Result<()> {
        if self.classes != other.classes || self.counts.len() != other.counts.len() {
            return Err(Error::IncompatibleCounts {
                reason: "different classes or cells".into(),
            });
        }
        self.validate()?;
        other.validate()?;
        for &(a, b) in &other.ranges {
            if self.ranges.iter().any(|&(c, d)| a < d && c < b) {
                return Err(Error::IncompatibleCounts {
                    reason: format!("trials {a}..{b} are counted twice"),
                });
            }
        }
        let overflow = || Error::IncompatibleCounts {
            reason: "a merged count exceeds 2^64".into(),
        };
        let mut counts = self.counts.clone();
        for (x, y) in counts.iter_mut().zip(&other.counts) {
            for (u, v) in x.iter_mut().zip(y) {
                *u = u.checked_add(*v).ok_or_else(overflow)?;
            }
        }
        let mut failures = self.failures.clone();
        for (u, v) in failures.iter_mut().zip(&other.failures) {
            *u = u.checked_add(*v).ok_or_else(overflow)?;
        }
        self.counts = counts;
        self.failures = failures;
        self.ranges.extend_from_slice(&other.ranges);
        self.ranges.sort_unstable();
        // Adjacent ranges coalesce: the table does not remember how its trials were split.
        let mut merged: Vec<(u64, u64)> = Vec::with_capacity(self.ranges.len());
        for &(a, b) in &self.ranges {
            match merged.last_mut() {
                Some(last) if last.1 == a => last.1 = b,
                _ => merged.push((a, b)),
            }
        }
        self.ranges = merged;
        Ok(())
    }

    /// The trials of `range` the table has not counted, as `[start, end)` ranges in order (what
    /// an interrupted run still has to do).
    ///
    /// ```
    /// use hycont_sample::basin::Counts;
    /// let mut c = Counts::new(vec!["a".into()], 1);
    /// c.ranges = vec![(10, 20), (30, 40)];
    /// assert_eq!(c.missing(0..50), vec![0..10, 20..30, 40..50]);
    /// ```
    #[must_use]
    pub fn missing(&self, range: std::ops::Range<u64>) -> Vec<std::ops::Range<u64>> {
        let mut out = Vec::new();
        let mut at = range.start;
        for &(a, b) in &self.ranges {
            if b <= at || a >= range.end {
                continue;
            }
            if a > at {
                out.push(at..a);
            }
            at = at.max(b);
        }
        if at < range.end {
            out.push(at..range.end);
        }
        out
    }

    /// Trials in a cell (classified or not); 0 for a cell the table does not have.
    #[must_use]
    pub fn trials(&self, cell: usize) -> u64 {
        let counted = self
            .counts
            .get(cell)
            .map_or(0, |row| row.iter().fold(0u64, |s, v| s.saturating_add(*v)));
        counted.saturating_add(self.failures.get(cell).copied().unwrap_or(0))
    }

    /// Fraction of class `class` in `cell` with its 95 % Wilson score interval
    /// $\hat p \pm$ (Wilson), as `(p, lo, hi)`; `(0, 0, 1)` for an empty cell (or one, or a
    /// class, the table does not have).
    #[must_use]
    pub fn fraction(&self, cell: usize, class: usize) -> (f64, f64, f64) {
        let n = self.trials(cell) as f64;
        let k = self.counts.get(cell).and_then(|row| row.get(class));
        let (Some(&k), true) = (k, n > 0.0) else {
            return (0.0, 0.0, 1.0);
        };
        let (lo, hi) = wilson(k, self.trials(cell));
        (k as f64 / n, lo, hi)
    }
}

/// The 95 % Wilson score interval of a fraction `k` of `n` trials,
/// $\frac{\hat p + z^2/2n \pm z\sqrt{\hat p(1-\hat p)/n + z^2/4n^2}}{1 + z^2/n}$ with
/// $z = 1.96$; exactly 0 (1) at its lower (upper) end when `k = 0` (`k = n`); `(0, 1)` for
/// no trials.
///
/// ```
/// let (lo, hi) = hycont_sample::basin::wilson(0, 2000);
/// assert_eq!(lo, 0.0);
/// assert!((hi - 0.001917).abs() < 1e-6);
/// ```
#[must_use]
pub fn wilson(k: u64, n: u64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (kf, nf) = (k as f64, n as f64);
    let p = kf / nf;
    let z: f64 = 1.959_963_984_540_054;
    let denom = 1.0 + z * z / nf;
    let centre = (p + z * z / (2.0 * nf)) / denom;
    let half = z * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt() / denom;
    let lo = if k == 0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if k >= n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// Progress and interruption of a running study.
#[derive(Debug, Default)]
pub struct Progress {
    /// Trials done.
    pub done: AtomicU64,
    /// Set to stop early (e.g. on Ctrl-C): trials not yet started are skipped and the counts so
    /// far are returned, with their exact trial ranges.
    pub stop: AtomicBool,
    /// A budget: the run stops as on [`Progress::stop`] once `done` reaches it (checked before
    /// each chunk of trials, so a run counts whole chunks: with one thread exactly the chunks
    /// up to the first that reaches it). `None`: no budget.
    pub budget: Option<u64>,
}

impl Progress {
    /// A progress that stops once `budget` trials are done (see [`Progress::budget`]).
    #[must_use]
    pub fn with_budget(budget: u64) -> Self {
        Self {
            budget: Some(budget),
            ..Self::default()
        }
    }

    /// Whether the run is asked to stop: by [`Progress::stop`], or its budget is spent.
    pub fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
            || self
                .budget
                .is_some_and(|b| self.done.load(Ordering::Relaxed) >= b)
    }
}

/// Runs trials `range` of `study` with `classifier` in parallel (rayon's pool), counting classes
/// per cell of the study's axes. The result is identical for any number of threads; interrupted
/// runs (via [`Progress::stop`]) report exactly which trials they counted.
///
/// # Errors
/// An invalid study.
pub fn run<C: Classifier>(
    study: &Study,
    classifier: &C,
    range: std::ops::Range<u64>,
    progress: &Progress,
) -> Result<Counts> {
    let mut out = run_binned(
        study,
        std::slice::from_ref(&study.axes),
        classifier,
        range,
        progress,
    )?;
    Ok(out.pop().expect("one binning"))
}

/// Like [`run`], counting every trial once per binning (each a list of at most two axes), e.g.
/// the marginal distributions over several variables of the same trials.
///
/// # Errors
/// An invalid study or binning.
pub fn run_binned<C: Classifier>(
    study: &Study,
    binnings: &[Vec<Axis>],
    classifier: &C,
    range: std::ops::Range<u64>,
    progress: &Progress,
) -> Result<Vec<Counts>> {
    let studies: Vec<Study> = binnings
        .iter()
        .map(|axes| Study {
            axes: axes.clone(),
            ..study.clone()
        })
        .collect();
    for s in &studies {
        s.validate()?;
    }
    study.validate()?;
    let classes = classifier.classes();
    // Chunks of consecutive trials: each records whether it ran completely, so an interrupted
    // run reports exact ranges.
    const CHUNK: u64 = 256;
    let chunk_count = (range.end.saturating_sub(range.start)).div_ceil(CHUNK);
    let chunk = |c: u64| {
        let a = range.start + c * CHUNK;
        (a, a.saturating_add(CHUNK).min(range.end))
    };
    let empty = || -> Vec<Counts> {
        studies
            .iter()
            .map(|s| Counts::new(classes.clone(), s.cells()))
            .collect()
    };
    // Streaming aggregation with bounded memory: one accumulator per worker thread, which takes
    // chunks from a shared counter and adds each finished chunk to its tables. Counts are integer
    // sums, so the result does not depend on which thread ran which chunk.
    let next = AtomicU64::new(0);
    let workers = rayon::current_num_threads().max(1);
    let partials: Vec<Vec<Counts>> = (0..workers)
        .into_par_iter()
        .map(|_| {
            let mut acc = empty();
            let mut scratch = empty();
            loop {
                if progress.stopping() {
                    break;
                }
                let c = next.fetch_add(1, Ordering::Relaxed);
                if c >= chunk_count {
                    break;
                }
                let (a, b) = chunk(c);
                for t in &mut scratch {
                    t.clear();
                }
                let mut complete = true;
                for i in a..b {
                    if progress.stop.load(Ordering::Relaxed) {
                        // An unfinished chunk is dropped whole, so the ranges stay exact.
                        complete = false;
                        break;
                    }
                    let values = study.trial(i);
                    let class = classifier
                        .classify(&values)
                        .ok()
                        .filter(|k| *k < classes.len());
                    for (t, s) in scratch.iter_mut().zip(&studies) {
                        // Trials have every variable of the validated study.
                        let cell = s.cell(&values).unwrap_or(0);
                        match class {
                            Some(k) => t.counts[cell][k] += 1,
                            None => t.failures[cell] += 1,
                        }
                    }
                    progress.done.fetch_add(1, Ordering::Relaxed);
                }
                if !complete {
                    break;
                }
                for (t, sc) in acc.iter_mut().zip(&mut scratch) {
                    sc.ranges.push((a, b));
                    t.merge(sc).expect("chunks are disjoint");
                }
            }
            acc
        })
        .collect();
    let mut totals = empty();
    for p in &partials {
        for (t, c) in totals.iter_mut().zip(p) {
            t.merge(c)?;
        }
    }
    Ok(totals)
}
