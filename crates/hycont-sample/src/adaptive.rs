//! Adaptive, stratified basin stability: trials drawn cell by cell until every class's 95 %
//! Wilson interval in every cell is narrow enough.
//!
//! A [`Study`] with binning axes divides its binned variables into cells. Here each cell has
//! its own stream of trials: trial $j$ of cell $c$ draws the binned variables uniformly inside
//! the cell (the conditional distribution of a uniform variable given the cell) and the others
//! from their distributions, from a generator seeded by $(\text{seed}, c, j)$
//! ([`Study::cell_trial`]). A cell runs batches of [`Adaptive::batch`] trials, in order, until
//! the largest Wilson half-width over its classes,
//! $$ h = \max_k \frac{z}{1 + z^2/n}\sqrt{\frac{\hat p_k(1-\hat p_k)}{n} + \frac{z^2}{4n^2}}, \quad z = 1.96, $$
//! is at most [`Adaptive::halfwidth`] or it has [`Adaptive::max_trials`] trials. Whether a
//! cell goes on depends only on its own counts, so the trials each cell runs, and the counts,
//! are a pure function of the seed: independent of threads, of how cells are split among
//! processes, and of interruptions (a cell stops between batches and resumes where it
//! stopped). A cell's record with more trials therefore contains one with fewer
//! ([`CellCounts::merge`] keeps the longer), which is how shards and processes combine.
//!
//! ```
//! use hycont_sample::adaptive::{run_cells, Adaptive, CellCounts};
//! use hycont_sample::basin::{Axis, Classifier, Distribution, Progress, Study};
//! /// "low" when x < 0.3.
//! struct Threshold;
//! impl Classifier for Threshold {
//!     fn classes(&self) -> Vec<String> { vec!["low".into(), "high".into()] }
//!     fn classify(&self, v: &[f64]) -> Result<usize, String> { Ok(usize::from(v[0] >= 0.3)) }
//! }
//! let study = Study {
//!     names: vec!["x".into()],
//!     variables: vec![Distribution::Uniform { lo: 0.0, hi: 1.0 }],
//!     axes: vec![Axis { variable: 0, lo: 0.0, hi: 1.0, bins: 4 }],
//!     seed: 3,
//! };
//! let mut counts = CellCounts::new(Threshold.classes(), 4);
//! let rule = Adaptive { halfwidth: 0.05, ..Adaptive::default() };
//! run_cells(&study, &Threshold, &rule, &mut counts, &[0, 1, 2, 3], &Progress::default()).unwrap();
//! // Cell 1 (x in [0.25, 0.5)) is "low" with probability 1/5 and needs hundreds of trials; the
//! // pure cells stop at the first batch boundary past z^2 / (2 H) - z^2 = 34.6 trials: 64.
//! assert!(counts.trials[1] > 200 && counts.halfwidth(1) <= 0.05);
//! assert_eq!(counts.trials[2], 64);
//! assert!((0..4).all(|c| counts.settled[c]));
//! ```

use crate::basin::{Classifier, Distribution, Progress, Study, wilson};
use crate::error::{Error, Result};
use crate::rng::SplitMix64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::Ordering;

/// The stopping rule of an adaptive run (validated; defaults as documented per field).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Adaptive {
    /// Target: the largest 95 % Wilson half-width of any class in a cell (default 0.1).
    pub halfwidth: f64,
    /// Trials per cell and round; the rule is tested after each batch (default 32).
    pub batch: u64,
    /// Most trials per cell (default 4096).
    pub max_trials: u64,
}

impl Default for Adaptive {
    fn default() -> Self {
        Self {
            halfwidth: 0.1,
            batch: 32,
            max_trials: 4096,
        }
    }
}

impl Adaptive {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidStudy`] naming the bad setting.
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: String| Err(Error::InvalidStudy { reason });
        if !(self.halfwidth > 0.0 && self.halfwidth < 0.5) {
            return bad(format!(
                "halfwidth = {} must be in (0, 0.5): a 95 % interval of half-width 0.5 says nothing",
                self.halfwidth
            ));
        }
        if self.batch == 0 || self.max_trials < self.batch {
            return bad(format!(
                "batch = {} must be >= 1 and max_trials = {} at least one batch",
                self.batch, self.max_trials
            ));
        }
        Ok(())
    }
}

/// Class counts per cell of an adaptive run: how many trials each cell ran (its first
/// `trials[c]`) and whether it met the rule.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CellCounts {
    /// Class names.
    pub classes: Vec<String>,
    /// `counts[cell][class]`.
    pub counts: Vec<Vec<u64>>,
    /// Trials that could not be classified, per cell.
    pub failures: Vec<u64>,
    /// Trials run per cell: the cell's trials `0..trials[c]`.
    pub trials: Vec<u64>,
    /// Whether the cell met the rule (half-width or cap).
    pub settled: Vec<bool>,
}

impl CellCounts {
    /// An empty table of `cells` cells of `classes`.
    #[must_use]
    pub fn new(classes: Vec<String>, cells: usize) -> Self {
        let k = classes.len();
        Self {
            classes,
            counts: vec![vec![0; k]; cells],
            failures: vec![0; cells],
            trials: vec![0; cells],
            settled: vec![false; cells],
        }
    }

    /// Checks the table: its shape, and every cell's classified trials and failures adding up
    /// to its trials.
    ///
    /// # Errors
    /// [`Error::IncompatibleCounts`] naming the first problem.
    pub fn validate(&self) -> Result<()> {
        let n = self.counts.len();
        let bad = |reason: String| Err(Error::IncompatibleCounts { reason });
        if self.failures.len() != n || self.trials.len() != n || self.settled.len() != n {
            return bad(format!("per-cell lists of different lengths for {n} cells"));
        }
        for (c, row) in self.counts.iter().enumerate() {
            if row.len() != self.classes.len() {
                return bad(format!("cell {c} has {} counts", row.len()));
            }
            let sum = row
                .iter()
                .try_fold(self.failures[c], |s, v| s.checked_add(*v));
            if sum != Some(self.trials[c]) {
                return bad(format!(
                    "cell {c}: counts and failures do not add up to its {} trials",
                    self.trials[c]
                ));
            }
        }
        Ok(())
    }

    /// Checks the table against the rule and study that made it (e.g. one read from a file,
    /// before it is merged, resumed or drawn): every cell ran whole batches, at most up to the
    /// batch that reached the cap; a cell is settled exactly when it meets the rule (its
    /// half-width at most the target, or the cap reached), or, without trials, when it has
    /// none to run (it lies outside a binned variable's range); the cells outside `cells`
    /// (another shard's) ran none.
    ///
    /// # Errors
    /// [`Error::IncompatibleCounts`] naming the first cell that breaks the rule;
    /// as [`CellCounts::validate`] and [`Study::cell_trial`].
    pub fn check_rule(
        &self,
        rule: &Adaptive,
        study: &Study,
        cells: std::ops::Range<usize>,
    ) -> Result<()> {
        self.validate()?;
        rule.validate()?;
        let bad = |c: usize, reason: String| {
            Err(Error::IncompatibleCounts {
                reason: format!("cell {c}: {reason}"),
            })
        };
        if self.counts.len() != study.cells() {
            return Err(Error::IncompatibleCounts {
                reason: format!(
                    "{} cells for a study of {}",
                    self.counts.len(),
                    study.cells()
                ),
            });
        }
        let cap = rule.max_trials.div_ceil(rule.batch) * rule.batch;
        for c in 0..self.counts.len() {
            let (trials, settled) = (self.trials[c], self.settled[c]);
            if !cells.contains(&c) {
                if trials > 0 || settled {
                    return bad(c, "another shard's cell has trials here".into());
                }
                continue;
            }
            if trials % rule.batch != 0 || trials > cap {
                return bad(
                    c,
                    format!(
                        "{trials} trials: not whole batches of {} up to the cap of {}",
                        rule.batch, rule.max_trials
                    ),
                );
            }
            let record = CellRecord::of(self, c);
            let meets = if trials == 0 {
                study.cell_trial(c, 0)?.is_none()
            } else {
                record.meets(rule)
            };
            if settled != meets {
                return bad(
                    c,
                    format!(
                        "it says it is{} settled, with {trials} trials and a half-width of {:.4} (rule: {} or {} trials)",
                        if settled { "" } else { " not" },
                        self.halfwidth(c),
                        rule.halfwidth,
                        rule.max_trials
                    ),
                );
            }
        }
        Ok(())
    }

    /// The largest 95 % Wilson half-width over the classes of `cell` (1 for a cell without
    /// classified trials).
    #[must_use]
    pub fn halfwidth(&self, cell: usize) -> f64 {
        let Some(row) = self.counts.get(cell) else {
            return 1.0;
        };
        let n: u64 = row.iter().sum();
        if n == 0 {
            return 1.0;
        }
        row.iter()
            .map(|&k| {
                let (lo, hi) = wilson(k, n);
                0.5 * (hi - lo)
            })
            .fold(0.0, f64::max)
    }

    /// The fraction of class `class` in `cell` among its classified trials, with its 95 %
    /// Wilson interval (`NaN` and `(0, 1)` for a cell without any).
    #[must_use]
    pub fn fraction(&self, cell: usize, class: usize) -> (f64, f64, f64) {
        let row = &self.counts[cell];
        let n: u64 = row.iter().sum();
        if n == 0 {
            return (f64::NAN, 0.0, 1.0);
        }
        let (lo, hi) = wilson(row[class], n);
        (row[class] as f64 / n as f64, lo, hi)
    }

    /// The cells of `cells` that have not met the rule.
    #[must_use]
    pub fn unsettled(&self, cells: std::ops::Range<usize>) -> Vec<usize> {
        cells
            .filter(|&c| !self.settled.get(c).copied().unwrap_or(true))
            .collect()
    }

    /// Merges another record of the same run in: per cell the one with more trials (a cell's
    /// trials are a prefix of its stream, so the longer record contains the shorter).
    ///
    /// # Errors
    /// [`Error::IncompatibleCounts`] for another shape or classes, or two records of a cell
    /// with the same number of trials and different counts (not the same run).
    pub fn merge(&mut self, other: &CellCounts) -> Result<()> {
        other.validate()?;
        if other.classes != self.classes || other.counts.len() != self.counts.len() {
            return Err(Error::IncompatibleCounts {
                reason: "different classes or cells".into(),
            });
        }
        for c in 0..self.counts.len() {
            let same = other.trials[c] == self.trials[c];
            if same && (&other.counts[c], other.failures[c]) != (&self.counts[c], self.failures[c])
            {
                return Err(Error::IncompatibleCounts {
                    reason: format!(
                        "cell {c}: two records of {} trials that differ (another run?)",
                        self.trials[c]
                    ),
                });
            }
            if other.trials[c] > self.trials[c] || (same && other.settled[c]) {
                self.counts[c].clone_from(&other.counts[c]);
                self.failures[c] = other.failures[c];
                self.trials[c] = other.trials[c];
                self.settled[c] = other.settled[c];
            }
        }
        Ok(())
    }
}

impl Study {
    /// Trial `j` of cell `cell`: the binned variables uniform inside the cell (on the part of
    /// their range the cell covers), the others from their distributions; deterministic in
    /// `(seed, cell, j)`. `None` when the cell and a binned variable's range do not overlap
    /// (the cell has no trials).
    ///
    /// # Errors
    /// [`Error::InvalidStudy`] for an invalid study, a cell out of range, or a binned variable
    /// that is not uniform (stratifying a fixed value means nothing).
    pub fn cell_trial(&self, cell: usize, j: u64) -> Result<Option<Vec<f64>>> {
        self.validate()?;
        if cell >= self.cells() {
            return Err(Error::InvalidStudy {
                reason: format!("cell {cell} of a study with {} cells", self.cells()),
            });
        }
        // One stream per cell: the study's seed hashed with the cell.
        let stream = SplitMix64::for_trial(self.seed, u64::MAX - cell as u64).next_u64();
        let mut rng = SplitMix64::for_trial(stream, j);
        let mut values: Vec<f64> = self.variables.iter().map(|d| d.draw(&mut rng)).collect();
        // Bins from the last axis (fastest) to the first, as `Study::cell` numbers them.
        let mut rest = cell;
        for a in self.axes.iter().rev() {
            let bin = rest % a.bins;
            rest /= a.bins;
            let width = (a.hi - a.lo) / a.bins as f64;
            let (blo, bhi) = (a.lo + width * bin as f64, a.lo + width * (bin + 1) as f64);
            let Distribution::Uniform { lo, hi } = self.variables[a.variable] else {
                return Err(Error::InvalidStudy {
                    reason: format!(
                        "{} is binned but not uniform: stratified sampling needs uniform binned variables",
                        self.names[a.variable]
                    ),
                });
            };
            let (l, h) = (blo.max(lo), bhi.min(hi));
            if l >= h {
                return Ok(None);
            }
            values[a.variable] = rng.uniform(l, h);
        }
        Ok(Some(values))
    }
}

/// Runs the cells `cells` of `study` (in parallel; each cell's batches in order) until each
/// meets `rule` or `progress` says stop (between batches), from where `counts` left them.
///
/// # Errors
/// Invalid settings or study, counts of another shape, a binned variable that is not uniform.
pub fn run_cells<C: Classifier>(
    study: &Study,
    classifier: &C,
    rule: &Adaptive,
    counts: &mut CellCounts,
    cells: &[usize],
    progress: &Progress,
) -> Result<()> {
    rule.validate()?;
    study.validate()?;
    counts.validate()?;
    if counts.counts.len() != study.cells() || counts.classes != classifier.classes() {
        return Err(Error::IncompatibleCounts {
            reason: format!(
                "a table of {} cells for a study of {}, or other classes",
                counts.counts.len(),
                study.cells()
            ),
        });
    }
    if let Some(&c) = cells.iter().find(|&&c| c >= study.cells()) {
        return Err(Error::InvalidStudy {
            reason: format!("cell {c} of a study with {} cells", study.cells()),
        });
    }
    let done: Vec<(usize, CellRecord)> = cells
        .par_iter()
        .map(|&c| {
            let record = CellRecord::of(counts, c);
            run_cell(study, classifier, rule, c, record, progress).map(|r| (c, r))
        })
        .collect::<Result<_>>()?;
    for (c, r) in done {
        counts.counts[c] = r.counts;
        counts.failures[c] = r.failures;
        counts.trials[c] = r.trials;
        counts.settled[c] = r.settled;
    }
    Ok(())
}

/// One cell's record while it runs.
struct CellRecord {
    counts: Vec<u64>,
    failures: u64,
    trials: u64,
    settled: bool,
}

impl CellRecord {
    fn of(counts: &CellCounts, c: usize) -> Self {
        Self {
            counts: counts.counts[c].clone(),
            failures: counts.failures[c],
            trials: counts.trials[c],
            settled: counts.settled[c],
        }
    }

    /// Whether the record meets the rule: the half-width, the cap, or no trials possible.
    fn meets(&self, rule: &Adaptive) -> bool {
        let table = CellCounts {
            classes: Vec::new(),
            counts: vec![self.counts.clone()],
            failures: vec![self.failures],
            trials: vec![self.trials],
            settled: vec![false],
        };
        self.trials >= rule.max_trials || (self.trials > 0 && table.halfwidth(0) <= rule.halfwidth)
    }
}

fn run_cell<C: Classifier>(
    study: &Study,
    classifier: &C,
    rule: &Adaptive,
    cell: usize,
    mut r: CellRecord,
    progress: &Progress,
) -> Result<CellRecord> {
    while !r.settled {
        if progress.stopping() {
            break;
        }
        let batch: Vec<u64> = (r.trials..r.trials + rule.batch).collect();
        let classes: Vec<Option<std::result::Result<usize, String>>> = batch
            .par_iter()
            .map(|&j| {
                let v = study.cell_trial(cell, j)?;
                Ok(v.map(|v| classifier.classify(&v)))
            })
            .collect::<Result<_>>()?;
        if classes.iter().any(Option::is_none) {
            // The cell lies outside a binned variable's range: no trials.
            r.settled = true;
            break;
        }
        for c in classes.into_iter().flatten() {
            match c {
                Ok(k) if k < r.counts.len() => r.counts[k] += 1,
                _ => r.failures += 1,
            }
        }
        r.trials += rule.batch;
        progress.done.fetch_add(rule.batch, Ordering::Relaxed);
        r.settled = r.meets(rule);
    }
    Ok(r)
}
