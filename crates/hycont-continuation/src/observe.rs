//! Observers: get every accepted point and special point (the CLI's progress bar is one).

use crate::atlas::AtlasChart;
use crate::branch::{Branch, BranchPoint, SpecialPoint};

/// Receives progress along a branch.
pub trait Observer {
    /// A point was accepted.
    fn point(&mut self, point: &BranchPoint, parameter: f64) {
        let _ = (point, parameter);
    }
    /// A special point was located.
    fn special(&mut self, special: &SpecialPoint) {
        let _ = special;
    }
    /// A branch of a diagram is finished ([`crate::OrbitRun::diagram`]).
    fn branch(&mut self, branch: &Branch) {
        let _ = branch;
    }
    /// A chart was added to an atlas ([`crate::atlas::cover`]); `count` charts so far.
    fn chart(&mut self, chart: &AtlasChart, count: usize) {
        let _ = (chart, count);
    }
    /// Whether the run should stop now (default: never), e.g. on an interrupt. Asked after
    /// every point of a branch or curve, every chart of an atlas and before every switch of a
    /// diagram: a stopped run ends cleanly with what it has (a branch ending with
    /// [`crate::EndReason::Stopped`], an atlas with [`crate::atlas::AtlasEnd::Stopped`], a
    /// diagram with the branches so far, whose points not yet switched at
    /// [`crate::OrbitRun::extend_diagram`] switches at later).
    fn stop(&mut self) -> bool {
        false
    }
}

impl<O: Observer + ?Sized> Observer for &mut O {
    fn point(&mut self, point: &BranchPoint, parameter: f64) {
        (**self).point(point, parameter);
    }
    fn special(&mut self, special: &SpecialPoint) {
        (**self).special(special);
    }
    fn branch(&mut self, branch: &Branch) {
        (**self).branch(branch);
    }
    fn chart(&mut self, chart: &AtlasChart, count: usize) {
        (**self).chart(chart, count);
    }
    fn stop(&mut self) -> bool {
        (**self).stop()
    }
}

/// Stops a run once a flag is set (e.g. by a signal handler), and tells nothing else.
///
/// ```
/// use hycont_continuation::observe::{Observer, StopFlag};
/// use std::sync::atomic::{AtomicBool, Ordering};
/// let flag = AtomicBool::new(false);
/// let mut observer = StopFlag(&flag);
/// assert!(!observer.stop());
/// flag.store(true, Ordering::Relaxed);
/// assert!(observer.stop());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct StopFlag<'f>(pub &'f std::sync::atomic::AtomicBool);

impl Observer for StopFlag<'_> {
    fn stop(&mut self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Ignores everything.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Observer for Silent {}

/// Counts points (handy in tests and benchmarks).
#[derive(Debug, Clone, Copy, Default)]
pub struct Counter {
    /// Points seen.
    pub points: usize,
    /// Special points seen.
    pub specials: usize,
}

impl Observer for Counter {
    fn point(&mut self, _: &BranchPoint, _: f64) {
        self.points += 1;
    }
    fn special(&mut self, _: &SpecialPoint) {
        self.specials += 1;
    }
}
