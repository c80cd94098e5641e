//! Branch switching in one call (BifurcationKit's `continuation(br, ind_bif, opts)`, COCO's
//! `ode_BP2hspo` and `ode_PD2hspo`): at a labelled branch point, along the second null
//! direction of the full orbit's problem; at a labelled period doubling, on the orbit traversed
//! twice; at a labelled grazing, in the signature beyond it (`grazing_switch`).

use super::problem::OrbitContinuation;
use super::run::{OrbitRun, RunDirection};
use super::saved::OrbitBranch;
use crate::ContinuationProblem;
use crate::branch::{BranchPoint, EndReason, SpecialKind};
use crate::error::{Error, Result};
use crate::switch::branch_switch_direction;
use hycont_core::HybridJacobians;

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// The branch through the special point labelled `label` of `branch` other than `branch`
    /// itself, named `name`, in `direction` (`Up` along the switching direction, `Down`
    /// against it, `Both` joined through the point), with this run's settings, measures and
    /// events:
    /// - at a branch point (BP) the direction is the null vector of the full orbit's
    ///   augmented Jacobian orthogonal to the branch ([`branch_switch_direction`]); the new
    ///   branch starts at the branch point. A branch that ends at a branch point of its parent
    ///   (with [`OrbitRun::stop_at`] `BranchPoint`, e.g. where an asymmetric branch rejoins the
    ///   symmetric one) ends at the parent's located point there, the same orbit: located from
    ///   the new branch's side, the corrector can slip onto the parent branch, which crosses the
    ///   chart's hyperplanes there too;
    /// - at a period doubling (PD) the new branch is that of the orbit traversed twice, along
    ///   the null direction of its problem there, starting at the doubled orbit;
    /// - at a grazing (GR) of the run's admissibility margin where an interior turning point
    ///   touches an event surface, the new branch is that of the neighbouring signature: the
    ///   segment split at the turning point with the event's reset there and, where the reset
    ///   leads into another mode, a zero-length segment in it
    ///   ([`hycont_core::orbit::split_at_grazing`]). It starts at the grazing orbit and goes
    ///   the way in which its orbits are physical, past the grazing parameter or back from it
    ///   (`direction` is not used: the physical side decides). At a tangential impact of the
    ///   margin ([`hycont_core::orbit::Touch::Approach`]) or where a segment collapses (the
    ///   shortest-segment monitor's GR), the impacts there are removed
    ///   ([`hycont_core::orbit::join_at_grazing`]): the joined orbit, solved again at the
    ///   grazing's parameters, starts the branch along its tangent, the way it is physical.
    ///   At a segment's end on an event's surface (a GR of the grazing margin, or a DB of the
    ///   domain margin) whose end keeps the state and mode (e.g. an extremum of a signature
    ///   with interior points), the end is replaced by the impact.
    ///
    /// # Errors
    /// A branch that does not fit the system, an unknown label, a special point other than BP,
    /// PD, GR or DB ([`Error::WrongSpecialPoint`]), no second direction there, a segment end
    /// that changes the state there, impacts that cannot be joined, a new signature physical
    /// on neither side
    /// ([`Error::SwitchFailed`]).
    pub fn switch_at(
        &mut self,
        name: &str,
        branch: &OrbitBranch,
        label: usize,
        direction: RunDirection,
    ) -> Result<OrbitBranch> {
        branch.validate(self.system)?;
        let special = branch.special_at(label)?;
        let wrong = |reason| Error::WrongSpecialPoint {
            operation: "switch branches",
            label,
            branch: branch.branch.name.clone(),
            kind: special.kind.label().to_string(),
            reason,
        };
        if branch.second.is_some() {
            return Err(wrong("the branch is a two-parameter curve"));
        }
        let mut full = OrbitContinuation::on_discretisation(
            self.system,
            branch.template.clone(),
            branch.discretisation_of(&special.point)?.clone(),
            branch.free,
            self.measures.clone(),
            self.events.clone(),
        )?;
        full.require_admissible(self.admissibility_on());
        let settings = self.settings.clone();
        match special.kind {
            SpecialKind::BranchPoint => {
                let p = &special.point;
                let phi = branch_switch_direction(&mut full, &p.u, &p.tangent)?;
                let start = BranchPoint {
                    tangent: phi.clone(),
                    discretisation: 0,
                    ..p.clone()
                };
                let b = self.continue_in(
                    &mut full,
                    name,
                    &p.u,
                    Some((&start, &phi)),
                    direction,
                    &settings,
                )?;
                let mut child = self.saved(&full, b, None)?;
                snap_to_parent(&mut child, branch)?;
                Ok(child)
            }
            SpecialKind::PeriodDoubling => {
                let (mut doubled, u0, phi) = full.from_period_doubling(&special.point)?;
                let info = doubled.analyse(&u0)?;
                let start = BranchPoint::from_info(&info, u0.clone(), phi.clone(), 0, 0.0);
                let b = self.continue_in(
                    &mut doubled,
                    name,
                    &u0,
                    Some((&start, &phi)),
                    direction,
                    &settings,
                )?;
                self.saved(&doubled, b, None)
            }
            SpecialKind::Grazing => {
                let special = special.clone();
                self.switch_at_grazing(name, branch, &special)
            }
            SpecialKind::Custom(ref l) if l.as_str() == "DB" => {
                let special = special.clone();
                self.switch_at_grazing(name, branch, &special)
            }
            _ => Err(wrong("branches are switched at BP, PD, GR and DB points")),
        }
    }
}

/// A switched branch that ended on reaching a branch point of its parent ends at the parent's
/// located point there (see [`OrbitRun::switch_at`]): the located branch point of `parent`
/// whose continued parameter lies in the bracket of the end's step (widened by its width).
/// Only on the same discretisation: a point of another mesh does not solve the child's problem.
fn snap_to_parent(child: &mut OrbitBranch, parent_saved: &OrbitBranch) -> Result<()> {
    let parent = &parent_saved.branch;
    let b = &child.branch;
    if b.end != EndReason::Reached(SpecialKind::BranchPoint) {
        return Ok(());
    }
    let Some(end) = b.special_points.last() else {
        return Ok(());
    };
    let (lo, hi) = (
        end.bracket.0.min(end.bracket.1),
        end.bracket.0.max(end.bracket.1),
    );
    let width = (hi - lo).max(1e-12);
    let found = parent
        .special(SpecialKind::BranchPoint)
        .filter(|s| s.located)
        .map(|s| (parent.parameter_of(&s.point), s))
        .filter(|(q, _)| *q >= lo - width && *q <= hi + width)
        .min_by(|a, b| {
            let mid = 0.5 * (lo + hi);
            (a.0 - mid).abs().total_cmp(&(b.0 - mid).abs())
        })
        .map(|(_, s)| s.clone());
    let Some(mut s) = found else {
        return Ok(());
    };
    // On another mesh (the child's or the parent's was adapted on the way) the parent's point
    // would not solve the child's problem: the child keeps its own end.
    if parent_saved.discretisation_of(&s.point)? != child.discretisation_of(&end.point)? {
        return Ok(());
    }
    s.point.discretisation = end.point.discretisation;
    // The run's points end with its own end point when it was located: replace it.
    let b = &mut child.branch;
    let last = b.special_points.len() - 1;
    let was_located = b.special_points[last].located;
    b.special_points[last] = s.clone();
    match b.points.last_mut() {
        Some(p) if was_located => *p = s.point,
        _ => b.points.push(s.point),
    }
    b.relabel();
    Ok(())
}
