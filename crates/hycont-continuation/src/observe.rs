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
