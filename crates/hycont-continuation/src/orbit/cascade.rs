//! Period-doubling cascades read off a [`Diagram`]: chains of branches each switched on at a
//! period doubling of the one before, with the doublings' parameter values and the ratios of
//! successive intervals (which tend to Feigenbaum's $\delta = 4.6692\ldots$ in a cascade of
//! quadratic-map type).

use super::diagram::{Diagram, DiagramBranchId, SwitchOutcome, SwitchRecord};
use crate::branch::SpecialKind;
use serde::{Deserialize, Serialize};

/// A chain of period doublings in a diagram.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cascade {
    /// The branches of the chain: the first, then each switched on at a doubling of the one
    /// before (periods 1, 2, 4, ... times the first's).
    pub branches: Vec<DiagramBranchId>,
    /// The continued parameter at the doublings: on each branch of the chain, the doubling it
    /// was switched on at to the next; on the last, its first doubling not switched at (when
    /// located), so a chain of $n$ branches has $n$ or $n - 1$ doublings.
    pub doublings: Vec<f64>,
}

impl Cascade {
    /// The intervals between successive doublings.
    #[must_use]
    pub fn intervals(&self) -> Vec<f64> {
        self.doublings.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// The ratios $\delta_k = (p_k - p_{k-1}) / (p_{k+1} - p_k)$ of successive intervals.
    #[must_use]
    pub fn ratios(&self) -> Vec<f64> {
        self.intervals().windows(2).map(|w| w[0] / w[1]).collect()
    }
}

impl Diagram {
    /// The period-doubling cascades: from every doubling that was switched at on a branch not
    /// itself born at a doubling, the chain of doubled branches, each followed through the
    /// first doubling switched at on it. Chains of one doubling are included. (Never panics,
    /// also on a diagram that does not pass [`Diagram::check_tree`]; its cascades then say
    /// what its records say.)
    #[must_use]
    pub fn cascades(&self) -> Vec<Cascade> {
        let pd = |r: &&SwitchRecord| r.kind == SpecialKind::PeriodDoubling;
        let born_at_pd = |b: DiagramBranchId| {
            let origin = self.branches.get(b.0).and_then(|b| b.origin);
            origin.is_some_and(|(parent, label)| {
                self.switches.iter().any(|r| {
                    r.branch == parent && r.label == label && r.kind == SpecialKind::PeriodDoubling
                })
            })
        };
        self.switches
            .iter()
            .filter(pd)
            .filter(|r| matches!(r.outcome, SwitchOutcome::Followed(_)) && !born_at_pd(r.branch))
            .map(|first| {
                let mut cascade = Cascade {
                    branches: vec![first.branch],
                    doublings: vec![first.parameter],
                };
                let mut record = first;
                // (A chain that comes back to one of its branches, only in an edited
                // diagram that did not pass `Diagram::check_tree`, ends there.)
                while let SwitchOutcome::Followed(child) = record.outcome {
                    if cascade.branches.contains(&child) {
                        break;
                    }
                    cascade.branches.push(child);
                    // The child's own doublings, not the one it was born at.
                    let mut own = self
                        .switches
                        .iter()
                        .filter(pd)
                        .filter(|r| r.branch == child && r.outcome != SwitchOutcome::Origin);
                    let next = own
                        .clone()
                        .find(|r| matches!(r.outcome, SwitchOutcome::Followed(_)))
                        .or_else(|| {
                            own.find(|r| !matches!(r.outcome, SwitchOutcome::Known { .. }))
                        });
                    let Some(next) = next else { break };
                    cascade.doublings.push(next.parameter);
                    record = next;
                }
                cascade
            })
            .collect()
    }
}
