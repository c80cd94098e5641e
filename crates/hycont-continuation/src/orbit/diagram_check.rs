//! Re-checking a saved [`Diagram`] before it is extended or trusted: its tree (origins,
//! depths, switch records and their outcomes) consistent in itself, and every branch what it
//! says for the run that extends it ([`OrbitRun::check_saved`]).

use super::diagram::{Diagram, DiagramBranchId, SwitchOutcome};
use super::run::OrbitRun;
use crate::branch::{SpecialKind, SpecialPoint};
use crate::error::{Error, Result};
use hycont_core::HybridJacobians;

impl Diagram {
    /// Checks the diagram's tree: the first branch is the root (no origin, depth 0); every
    /// other branch was switched on at a located BP or PD of an earlier branch (its origin)
    /// one level deeper, all in one parameter and none a two-parameter curve; every switch
    /// record names a located special point of its kind on its branch (with that point's
    /// parameter), at most once, and its outcome names branches and points the diagram has
    /// (a followed branch's origin is the record's point, and every switched branch is
    /// followed by exactly one record). The branches' points are checked against a system by
    /// [`OrbitRun::check_diagram`].
    ///
    /// # Errors
    /// [`Error::InvalidSaved`] naming the first inconsistency.
    pub fn check_tree(&self) -> Result<()> {
        let invalid = |reason: String| Error::InvalidSaved {
            what: "diagram",
            reason,
        };
        let Some(root) = self.branches.first() else {
            return Err(invalid("it has no branches".into()));
        };
        if root.origin.is_some() || root.depth != 0 {
            return Err(invalid(
                "its first branch is not the root (origin, depth 0)".into(),
            ));
        }
        for (i, b) in self.branches.iter().enumerate() {
            if b.branch.free != root.branch.free || b.branch.second.is_some() {
                return Err(invalid(format!(
                    "branch {i} is not continued in the root's parameter {}",
                    root.branch.free.index()
                )));
            }
            let Some((parent, label)) = b.origin else {
                if i > 0 {
                    return Err(invalid(format!("branch {i} has no origin")));
                }
                continue;
            };
            if parent.0 >= i {
                return Err(invalid(format!(
                    "branch {i} has its origin on branch {}, not an earlier one",
                    parent.0
                )));
            }
            let s = self
                .switch_point(parent, label, None)
                .map_err(|r| invalid(format!("branch {i} has its origin at {r}")))?;
            if !super::diagram::switchable(&s.kind) {
                return Err(invalid(format!(
                    "branch {i} has its origin at a {} point (branches switch at BP, PD, GR and DB)",
                    s.kind
                )));
            }
            if b.depth != self.branches[parent.0].depth + 1 {
                return Err(invalid(format!(
                    "branch {i} is at depth {}, its origin's branch at {}",
                    b.depth, self.branches[parent.0].depth
                )));
            }
        }
        self.check_switches().map_err(invalid)
    }

    /// The special point labelled `label` of branch `id` (of `kind` when given), located.
    fn switch_point(
        &self,
        id: DiagramBranchId,
        label: usize,
        kind: Option<SpecialKind>,
    ) -> std::result::Result<&SpecialPoint, String> {
        let b = self
            .branches
            .get(id.0)
            .ok_or_else(|| format!("branch {} (the diagram has {})", id.0, self.branches.len()))?;
        let s = b
            .branch
            .branch
            .special_points
            .iter()
            .find(|s| s.point.label == label)
            .ok_or_else(|| format!("label {label} of branch {}: no special point there", id.0))?;
        if !s.located || kind.is_some_and(|k| k != s.kind) {
            return Err(format!(
                "label {label} of branch {}: a {}{} point",
                id.0,
                if s.located { "" } else { "non-located " },
                s.kind
            ));
        }
        Ok(s)
    }

    /// The switch records against the branches.
    fn check_switches(&self) -> std::result::Result<(), String> {
        let mut seen = std::collections::HashSet::new();
        let mut followed = vec![0usize; self.branches.len()];
        for (k, r) in self.switches.iter().enumerate() {
            let at = |reason: String| format!("switch record {k}: {reason}");
            if !seen.insert((r.branch, r.label)) {
                return Err(at(format!(
                    "label {} of branch {} is recorded twice",
                    r.label, r.branch.0
                )));
            }
            let s = self
                .switch_point(r.branch, r.label, Some(r.kind))
                .map_err(at)?;
            let parameter = self.branches[r.branch.0]
                .branch
                .branch
                .parameter_of(&s.point);
            if parameter.to_bits() != r.parameter.to_bits() {
                return Err(at(format!(
                    "parameter {} is not its point's {parameter}",
                    r.parameter
                )));
            }
            match &r.outcome {
                SwitchOutcome::Followed(j) => {
                    let child = self.branches.get(j.0).filter(|_| j.0 > 0);
                    if child.is_none_or(|c| c.origin != Some((r.branch, r.label))) {
                        return Err(at(format!(
                            "branch {} it says it followed does not start there",
                            j.0
                        )));
                    }
                    followed[j.0] += 1;
                }
                SwitchOutcome::Known { branch, label } => {
                    self.switch_point(*branch, *label, Some(r.kind))
                        .map_err(at)?;
                }
                SwitchOutcome::Duplicate(j) if j.0 >= self.branches.len() => {
                    return Err(at(format!(
                        "it leads to branch {}, which does not exist",
                        j.0
                    )));
                }
                SwitchOutcome::Origin if self.branches[r.branch.0].origin.is_none() => {
                    return Err(at("it marks the origin of the root branch".into()));
                }
                _ => {}
            }
        }
        match (1..self.branches.len()).find(|&i| followed[i] != 1) {
            Some(i) => Err(format!(
                "branch {i} is followed by {} switch records, not one",
                followed[i]
            )),
            None => Ok(()),
        }
    }
}

impl<S: HybridJacobians + ?Sized> OrbitRun<'_, S> {
    /// Checks a saved diagram (e.g. read from a file) against this run: its tree
    /// ([`Diagram::check_tree`]) and every branch ([`OrbitRun::check_saved`]: this system's,
    /// in this run's parameter with its measures, every point an orbit whose analysis is what
    /// it says). [`OrbitRun::extend_diagram`] checks so before it switches anywhere.
    ///
    /// # Errors
    /// [`Error::InvalidSaved`] or [`Error::InvalidPoint`] naming what does not fit.
    pub fn check_diagram(&self, diagram: &Diagram) -> Result<()> {
        diagram.check_tree()?;
        for (i, b) in diagram.branches.iter().enumerate() {
            self.check_saved(&b.branch).map_err(|e| match e {
                Error::InvalidSaved { reason, .. } => Error::InvalidSaved {
                    what: "diagram",
                    reason: format!("branch {i}: {reason}"),
                },
                other => other,
            })?;
        }
        Ok(())
    }
}
