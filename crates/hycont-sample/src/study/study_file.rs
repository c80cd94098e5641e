//! [`StudyFile`]: a basin-stability study of any [`Classifier`] on disk, counted over trials or
//! cell by cell to a stopping rule, whole or one shard: the [`CountFile`] a user's study
//! hands the runner without writing one of its own.

use super::table_file::{TableFile, check_file};
use super::tally::{Table, fill_cells, fill_trials};
use crate::adaptive::{Adaptive, CellCounts};
use crate::basin::{Classifier, Counts, Progress, Study, shard_range};
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// The `format` every [`StudyFile`] carries, and its `version`.
pub const FORMAT: &str = "hycont-sample study";
/// The version of [`FORMAT`] this crate writes and reads.
pub const VERSION: u32 = 1;

/// The most trials a study may ask for (10^12; shard larger studies).
pub const MAX_TRIALS: u64 = 1_000_000_000_000;

/// How a study is counted: a number of trials (binned as the study's axes say), or cell by
/// cell until a stopping rule is met.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Plan {
    /// Trials `0..trials` (a shard: its part, [`shard_range`]), counted in `counts`.
    Trials {
        /// Trials of the whole study.
        trials: u64,
        /// The counts so far.
        counts: Counts,
    },
    /// Each cell (a shard: its part of the cells) sampled in batches until `rule` is met.
    Cells {
        /// The stopping rule.
        rule: Adaptive,
        /// The counts so far.
        counts: CellCounts,
    },
}

/// A study of any classifier `C` (which the file records: `C`'s serde form says what the
/// trials are classified by, e.g. a system's fixed parameters), over one shard, complete or
/// not. JSON: `{"format": "hycont-sample study", "version": 1, "name": ..., "study":
/// <Study>, "classifier": <C>, "shard": [i, n], "plan": {"trials": {"trials": N, "counts":
/// <Counts>}} | {"cells": {"rule": <Adaptive>, "counts": <CellCounts>}}}`. Files are named
/// `NAME.json` (a whole run), `NAME.shard-I-of-N.json` (a shard) and `*.partial.json` (an
/// interrupted run).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyFile<C> {
    /// [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The study's name: the stem of its files.
    pub name: String,
    /// The study (variables, axes, seed).
    pub study: Study,
    /// What classifies its trials.
    pub classifier: C,
    /// `(i, n)`: shard `i` of `n` (a whole run is `(0, 1)`).
    pub shard: (u64, u64),
    /// How it is counted, and the counts.
    pub plan: Plan,
}

impl<C> StudyFile<C>
where
    C: Classifier + Clone + PartialEq + Serialize + serde::de::DeserializeOwned,
{
    /// A study of `trials` trials with nothing counted, shard `shard`.
    ///
    /// # Errors
    /// [`Error::InvalidStudy`] for an invalid study, name, shard or trial count.
    pub fn trials(
        name: &str,
        study: Study,
        classifier: C,
        trials: u64,
        shard: (u64, u64),
    ) -> Result<Self> {
        let counts = Counts::new(classifier.classes(), study.cells());
        let plan = Plan::Trials { trials, counts };
        Self::checked(name, study, classifier, shard, plan)
    }

    /// A study sampled cell by cell to `rule` with nothing counted, shard `shard` of its
    /// cells.
    ///
    /// # Errors
    /// As [`StudyFile::trials`]; an invalid rule.
    pub fn cells(
        name: &str,
        study: Study,
        classifier: C,
        rule: Adaptive,
        shard: (u64, u64),
    ) -> Result<Self> {
        let counts = CellCounts::new(classifier.classes(), study.cells());
        let plan = Plan::Cells { rule, counts };
        Self::checked(name, study, classifier, shard, plan)
    }

    fn checked(
        name: &str,
        study: Study,
        classifier: C,
        shard: (u64, u64),
        plan: Plan,
    ) -> Result<Self> {
        let file = Self {
            format: FORMAT.into(),
            version: VERSION,
            name: name.into(),
            study,
            classifier,
            shard,
            plan,
        };
        check_file(&file).map_err(|reason| Error::InvalidStudy { reason })?;
        Ok(file)
    }

    /// The file's consistency: format and version, a name usable as a file stem, a valid
    /// study and shard, and counts of the classifier's classes over the study's cells that
    /// agree with their trials, all inside the shard.
    fn check(&self) -> std::result::Result<(), String> {
        if (self.format.as_str(), self.version) != (FORMAT, VERSION) {
            return Err(format!(
                "format {:?} version {}: this reads {FORMAT:?} version {VERSION}",
                self.format, self.version
            ));
        }
        let stem_ok = |c: char| c.is_ascii_alphanumeric() || "-_.".contains(c);
        if self.name.is_empty() || !self.name.chars().all(stem_ok) {
            return Err(format!(
                "name {:?}: letters, digits, '-', '_' and '.' only",
                self.name
            ));
        }
        self.study.validate().map_err(|e| e.to_string())?;
        let classes = self.classifier.classes();
        match &self.plan {
            Plan::Trials { trials, counts } => {
                if !(1..=MAX_TRIALS).contains(trials) {
                    return Err(format!("trials = {trials} is not in 1..={MAX_TRIALS}"));
                }
                if counts.classes != classes || counts.counts.len() != self.study.cells() {
                    return Err(format!(
                        "counts of {} cells of {:?}; the study has {} cells of {classes:?}",
                        counts.counts.len(),
                        counts.classes,
                        self.study.cells()
                    ));
                }
            }
            Plan::Cells { rule, counts } => {
                if counts.classes != classes {
                    return Err(format!(
                        "classes {:?}; the classifier's are {classes:?}",
                        counts.classes
                    ));
                }
                (counts.check_rule(rule, &self.study, self.cell_range()))
                    .map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    }

    /// The trials of the shard (a study sampled by cells: none).
    #[must_use]
    pub fn range(&self) -> Range<u64> {
        match &self.plan {
            Plan::Trials { trials, .. } => {
                shard_range(*trials, self.shard.0, self.shard.1).unwrap_or(0..0)
            }
            Plan::Cells { .. } => 0..0,
        }
    }

    /// The cells of the shard (a study of trials: every cell).
    #[must_use]
    pub fn cell_range(&self) -> Range<usize> {
        let cells = self.study.cells();
        match &self.plan {
            Plan::Trials { .. } => 0..cells,
            Plan::Cells { .. } => {
                let r = shard_range(cells as u64, self.shard.0, self.shard.1).unwrap_or(0..0);
                r.start as usize..r.end as usize
            }
        }
    }
}

impl Table for Plan {
    fn planned(&self) -> bool {
        matches!(self, Plan::Trials { .. })
    }
    fn progress(&self, span: Range<u64>) -> (u64, u64) {
        match self {
            Plan::Trials { counts, .. } => counts.progress(span),
            Plan::Cells { counts, .. } => counts.progress(span),
        }
    }
    fn todo(&self, span: Range<u64>, part: (u64, u64)) -> Result<Vec<Range<u64>>> {
        match self {
            Plan::Trials { counts, .. } => counts.todo(span, part),
            Plan::Cells { counts, .. } => counts.todo(span, part),
        }
    }
    fn counted(&self, span: Range<u64>) -> u64 {
        match self {
            Plan::Trials { counts, .. } => counts.counted(span),
            Plan::Cells { counts, .. } => counts.counted(span),
        }
    }
    fn covers(&self, other: &Self, span: Range<u64>) -> bool {
        match (self, other) {
            (Plan::Trials { counts: a, .. }, Plan::Trials { counts: b, .. }) => a.covers(b, span),
            (Plan::Cells { counts: a, .. }, Plan::Cells { counts: b, .. }) => a.covers(b, span),
            _ => false,
        }
    }
    fn merge(&mut self, other: &Self) -> Result<()> {
        match (self, other) {
            (Plan::Trials { counts: a, .. }, Plan::Trials { counts: b, .. }) => a.merge(b),
            (Plan::Cells { counts: a, .. }, Plan::Cells { counts: b, .. }) => a.merge(b),
            _ => Err(Error::IncompatibleCounts {
                reason: "a study over trials and one sampled cell by cell".into(),
            }),
        }
    }
    fn cleared(&self) -> Self {
        match self {
            Plan::Trials { trials, counts } => Plan::Trials {
                trials: *trials,
                counts: counts.cleared(),
            },
            Plan::Cells { .. } => self.clone(),
        }
    }
    fn check(&self, span: Range<u64>) -> std::result::Result<(), String> {
        match self {
            Plan::Trials { counts, .. } => counts.check(span),
            Plan::Cells { counts, .. } => counts.check(span),
        }
    }
}

impl<C> TableFile for StudyFile<C>
where
    C: Classifier + Clone + PartialEq + Serialize + serde::de::DeserializeOwned,
{
    type Table = Plan;
    type Error = Error;
    const WRITER: &'static str = "a hycont-sample study";
    fn what(&self) -> String {
        self.name.clone()
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn set_shard(&mut self, shard: (u64, u64)) {
        self.shard = shard;
    }
    fn extent(&self) -> u64 {
        match &self.plan {
            Plan::Trials { trials, .. } => *trials,
            Plan::Cells { .. } => self.study.cells() as u64,
        }
    }
    fn tables(&self) -> &[Plan] {
        std::slice::from_ref(&self.plan)
    }
    fn tables_mut(&mut self) -> &mut [Plan] {
        std::slice::from_mut(&mut self.plan)
    }
    fn same_run(&self, other: &Self) -> std::result::Result<(), String> {
        let rule = |p: &Plan| match p {
            Plan::Trials { trials, .. } => (Some(*trials), None),
            Plan::Cells { rule, .. } => (None, Some(*rule)),
        };
        let key = |f: &Self| {
            (
                f.name.clone(),
                f.study.clone(),
                f.classifier.clone(),
                rule(&f.plan),
            )
        };
        if key(self) == key(other) {
            return Ok(());
        }
        Err(format!(
            "study {:?} differs from the files before (another study, classifier, trial count or rule)",
            other.name
        ))
    }
    fn fill(&mut self, todo: &[Vec<Range<u64>>], progress: &Progress) -> Result<()> {
        let study = (&self.study, &self.classifier);
        match &mut self.plan {
            Plan::Trials { counts, .. } => fill_trials(study, counts, todo, progress),
            Plan::Cells { rule, counts } => fill_cells(study, rule, counts, todo, progress),
        }
    }
    fn check(&self) -> std::result::Result<(), String> {
        StudyFile::check(self)
    }
}
