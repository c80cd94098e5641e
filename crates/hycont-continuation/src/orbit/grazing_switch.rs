//! Switching signature at a grazing (GR) point of a branch: where an interior turning point
//! of a segment's flow touches an event surface, the family beyond has an impact there (and,
//! where that impact leads into another mode, a flight of zero length at the grazing in it:
//! [`split_at_grazing`]). The grazing orbit, written in the new signature, starts the new
//! family's branch. Where the impact leads into another mode, the grazing orbit is also a
//! point of a family whose zero-length flight stays of zero length (two impacts at one
//! instant, not physical: after them the flow leaves its mode's domain), so the new
//! signature's problem has a branch point there; the new family is the other branch through
//! it, the one along which the flight's duration changes. The branch goes the way in which
//! its orbits are physical (admissible), which may be past the grazing parameter or back from
//! it (both families then on one side: a nonsmooth fold).
//!
//! The other way, at a tangential impact or a collapsed segment, the impacts there are removed
//! ([`join_at_grazing`]); the joined orbit is exact only to the grazing's location, so it is
//! solved again at the grazing's parameters, and its problem is regular there: its tangent
//! starts the branch.

use super::problem::OrbitContinuation;
use super::run::{OrbitRun, RunDirection};
use super::saved::OrbitBranch;
use crate::ContinuationProblem;
use crate::bifurcation_equation::second_branch_tangent;
use crate::branch::{BranchPoint, SpecialPoint};
use crate::error::{Error, Result};
use crate::quantity::MeasureId;
use crate::quantity::Quantity;
use crate::switch::null_directions;
use hycont_core::HybridJacobians;
use hycont_core::orbit::{
    GrazingJoin, GrazingSplit, JoinAt, PeriodicOrbit, Touch, check_admissible, join_at_grazing,
    solve_orbit, split_at_grazing,
};

/// The least component along a zero-length segment's duration of a unit tangent that moves it
/// (far below any family's that leaves duration zero at a finite rate, far above rounding).
const MOVES_DURATION: f64 = 1e-8;

/// The orbit on the other side of a grazing.
enum Beyond {
    /// With the impact inserted.
    Split(GrazingSplit),
    /// With the impact removed.
    Join(GrazingJoin),
}

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// The branch of the signature beyond the grazing `special` of `branch` (see the module
    /// docs), named `name`.
    pub(super) fn switch_at_grazing(
        &mut self,
        name: &str,
        branch: &OrbitBranch,
        special: &SpecialPoint,
    ) -> Result<OrbitBranch> {
        let full = branch.orbit_of(&special.point)?;
        let orbit = if self.half_orbits && full.is_symmetric(self.system, self.symmetry_tol) {
            full.half_of_symmetric(self.system, self.symmetry_tol)?
        } else {
            full
        };
        let (mut cp, u0, direction) = match self.beyond(&orbit, special)? {
            Beyond::Split(split) => {
                let (mut cp, u0) = OrbitContinuation::new(
                    self.system,
                    &split.orbit,
                    &self.method,
                    branch.free,
                    self.measures.clone(),
                    self.events.clone(),
                )?;
                cp.require_admissible(self.admissibility_on());
                let direction = self.grazing_direction(&mut cp, &u0, split.zero_length)?;
                (cp, u0, direction)
            }
            Beyond::Join(join) => {
                // Exact to the grazing's location only: solved again at its parameters.
                let solved = solve_orbit(
                    self.system,
                    &join.orbit,
                    &self.method,
                    &self.settings.newton,
                    self.symmetry_tol,
                )?;
                let (mut cp, u0) = self.problem_in(&solved.solution.orbit, branch.free)?;
                let direction = null_directions(&mut cp, &u0)?.swap_remove(0);
                (cp, u0, direction)
            }
        };
        self.continue_physical(&mut cp, name, &u0, &direction)
    }

    /// The orbit on the other side of the grazing `special` of a branch through `orbit`: split
    /// at an interior touch of the admissibility margin, joined at a tangential impact or a
    /// collapsed segment (the shortest-segment monitor's grazing).
    fn beyond(&self, orbit: &PeriodicOrbit, special: &SpecialPoint) -> Result<Beyond> {
        let failed = |reason: String| Error::SwitchFailed { reason };
        let margin = match (special.on, self.admissibility) {
            (Some(Quantity::Measure(m)), _) if m == MeasureId::SHORTEST_SEGMENT => {
                let shortest = (0..orbit.segment_count())
                    .min_by(|&a, &b| orbit.durations[a].total_cmp(&orbit.durations[b]))
                    .unwrap_or(0);
                let at = JoinAt::Collapsed { segment: shortest };
                return Ok(Beyond::Join(join_at_grazing(self.system, orbit, at)?));
            }
            (Some(Quantity::Measure(m)), Some((grazing, domain)))
                if m == grazing || m == domain =>
            {
                m
            }
            _ => {
                return Err(failed(
                    "only a zero of the run's admissibility margins (an event surface touched inside a segment or at its end, a tangential impact) or a collapsing segment switches signature".into(),
                ));
            }
        };
        // The measure set's index of the margin (the monitors begin with period and shortest
        // segment).
        let touch = self
            .measures
            .touch(self.system, orbit, margin.index() - 2)?
            .ok_or_else(|| failed("the margin is attained by no touch here".into()))?;
        match touch {
            Touch::Turn { .. } | Touch::End { .. } => {
                Ok(Beyond::Split(split_at_grazing(self.system, orbit, &touch)?))
            }
            Touch::Approach { segment, .. } => Ok(Beyond::Join(join_at_grazing(
                self.system,
                orbit,
                JoinAt::TangentialImpact { segment },
            )?)),
        }
    }

    /// The branch of `cp` from the grazing orbit `u0` along `direction`, the way in which its
    /// orbits are physical.
    fn continue_physical(
        &mut self,
        cp: &mut OrbitContinuation<'a, S>,
        name: &str,
        u0: &[f64],
        direction: &[f64],
    ) -> Result<OrbitBranch> {
        let info = cp.analyse(u0)?;
        let start = BranchPoint::from_info(&info, u0.to_vec(), direction.to_vec(), 0, 0.0);
        let settings = self.settings.clone();
        let mut why = Vec::new();
        for way in [RunDirection::Up, RunDirection::Down] {
            match self.continue_in(cp, name, u0, Some((&start, direction)), way, &settings) {
                Ok(b) => {
                    // Physical beyond its start: its first point after the grazing orbit.
                    let beyond = b.points.get(1).map(|p| cp.orbit(&p.u));
                    let physical = beyond.as_ref().map(|o| {
                        o.unfold_symmetric(self.system)
                            .or_else(|_| Ok(o.clone()))
                            .and_then(|o| check_admissible(self.system, &o))
                    });
                    match physical {
                        Some(Ok(())) => return self.saved(cp, cp.into_full_branch(b), None),
                        Some(Err(e)) => why.push(e.to_string()),
                        None => why.push("no point beyond the grazing".into()),
                    }
                }
                Err(e) => why.push(e.to_string()),
            }
        }
        Err(Error::SwitchFailed {
            reason: format!(
                "the new signature is physical neither way from the grazing ({})",
                why.join("; ")
            ),
        })
    }

    /// The direction of the new family at the grazing orbit `u0`: the tangent where the new
    /// problem is regular there (also with a zero-length segment, where no family keeps it at
    /// zero length); at its branch point (a zero-length segment, unknown
    /// `zero_length`'s duration), the zero-length family's tangent is the null direction that
    /// keeps that duration, and the new family's is the other root of the bifurcation
    /// equation ([`second_branch_tangent`]: the families need not cross at a right angle).
    fn grazing_direction(
        &self,
        cp: &mut OrbitContinuation<'a, S>,
        u0: &[f64],
        zero_length: Option<usize>,
    ) -> Result<Vec<f64>> {
        let dirs = null_directions(cp, u0)?;
        let Some(k) = zero_length else {
            return Ok(dirs[0].clone());
        };
        let z = cp.discretisation().segment_values(cp.template()) + k;
        let x1 = dirs[0].clone();
        let x2 = match dirs.get(1) {
            Some(x2) => x2.clone(),
            None => match crate::switch::branch_switch_direction(cp, u0, &x1) {
                Ok(x2) => x2,
                // Regular at the grazing orbit (where the jumps around the zero-length segment
                // do not compose to the identity, no family keeps it at zero length): the one
                // family through the orbit is the new one if it moves that duration.
                Err(Error::SwitchFailed { .. }) if x1[z].abs() > MOVES_DURATION => {
                    return Ok(x1);
                }
                Err(e) => return Err(e),
            },
        };
        // In the plane of the two: orthogonal to the direction that keeps the duration.
        let (c1, c2) = (x1[z], x2[z]);
        let mut d: Vec<f64> = x1.iter().zip(&x2).map(|(a, b)| c1 * a + c2 * b).collect();
        let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(Error::SwitchFailed {
                reason: "no direction at the grazing changes the zero-length segment's duration"
                    .into(),
            });
        }
        d.iter_mut().for_each(|v| *v /= norm);
        // The zero-length family's tangent (the other unit vector of the plane), and from the
        // bifurcation equation the new family's, which need not be orthogonal to it.
        let mut keep: Vec<f64> = x1.iter().zip(&x2).map(|(a, b)| c2 * a - c1 * b).collect();
        let norm = keep.iter().map(|v| v * v).sum::<f64>().sqrt();
        keep.iter_mut().for_each(|v| *v /= norm);
        second_branch_tangent(cp, u0, &keep, &d)
    }
}
