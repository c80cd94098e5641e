//! Two-parameter curves in one call (BifurcationKit's `continuation(br, ind, lens2, opts)`,
//! COCO's `ode_hspo2SN`, `ode_PD2hspo`, `coco_add_event` curves): from a labelled fold,
//! period doubling, branch point or event point of a branch, on the branch's discretisation;
//! and the other curve through a fold-flip point of a curve.

use super::run::{OrbitRun, RunDirection};
use super::saved::OrbitBranch;
use crate::MonitorEvent;
use crate::branch::SpecialKind;
use crate::codim2::{Codim2, CurveCondition};
use crate::error::{Error, Result};
use crate::quantity::{MeasureId, Quantity};
use hycont_core::orbit::Discretisation;
use hycont_core::{HybridJacobians, ParamId};
use serde::{Deserialize, Serialize};

/// What a two-parameter curve is continued in besides the branch's parameter: the second
/// parameter, its bounds, user points, and the direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurveSpec {
    /// The second parameter, released along the curve.
    pub second: ParamId,
    /// Bounds of the second parameter (the branch parameter's bounds are the run's).
    pub bounds: Option<(f64, f64)>,
    /// User points (UZ) where a parameter or measure takes a value.
    pub user_points: Vec<(Quantity, f64)>,
    /// Which way(s) from the special point (default both).
    pub direction: RunDirection,
}

impl CurveSpec {
    /// A curve releasing `second`, both ways, unbounded in `second`, no user points.
    #[must_use]
    pub fn new(second: ParamId) -> Self {
        Self {
            second,
            bounds: None,
            user_points: Vec::new(),
            direction: RunDirection::Both,
        }
    }

    /// Bounds the second parameter to `[min, max]`.
    #[must_use]
    pub fn bounds(mut self, min: f64, max: f64) -> Self {
        self.bounds = Some((min, max));
        self
    }

    /// User points (UZ) where `on` (e.g. either parameter) takes each of `values`.
    #[must_use]
    pub fn user_points(
        mut self,
        on: impl Into<Quantity>,
        values: impl IntoIterator<Item = f64>,
    ) -> Self {
        let on = on.into();
        self.user_points.extend(values.into_iter().map(|v| (on, v)));
        self
    }

    /// Which way(s) to continue.
    #[must_use]
    pub fn direction(mut self, direction: RunDirection) -> Self {
        self.direction = direction;
        self
    }
}

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// The two-parameter curve through the special point labelled `label` of `branch`, named
    /// `name`, in the branch's parameter and `spec.second`, on the branch's discretisation:
    /// - a fold (SN): of a symmetric orbit on its half orbit (a half-map multiplier $+1$),
    ///   else of the full orbit;
    /// - a branch point (BP) of a symmetric orbit: the symmetry-breaking curve on its half orbit
    ///   (a half-map multiplier $-1$);
    /// - a period doubling (PD): on the full orbit;
    /// - an event on a measure (SB, GR, DB, a user label): the measure held at its level (a
    ///   grazing or a domain boundary by a collapsing segment: that segment's duration held at
    ///   zero); symmetric orbits on their half orbit. A margin held at zero (the admissibility
    ///   events GR and DB, a [`hycont_core::orbit::GrazingMargin`]) is the smallest of several
    ///   conditions and not smooth where two meet (e.g. a turning point reaching a segment's
    ///   end): the curve holds the one condition that attains it at the start instead
    ///   ([`hycont_core::orbit::Touch`]: a turning point on the surface, a tangential impact's
    ///   approach rate, a segment's end on the surface; [`CurveCondition::Touch`]), a smooth
    ///   function of the orbit with an exact gradient, so the curve is followed with ordinary
    ///   steps.
    ///
    /// Along the curve: folds, `spec`'s user points, and the run's terminal events (other than
    /// the one defining the curve) are detected; the run's bounds and `spec`'s bound on the
    /// second parameter apply; steps follow [`OrbitRun::curve_settings`].
    ///
    /// # Errors
    /// A branch that does not fit the system, an unknown label or parameter, a special point
    /// that has no curve (e.g. an end point, a branch point of an orbit that is not symmetric:
    /// [`Error::WrongSpecialPoint`]); no solution near the start.
    pub fn curve_at(
        &mut self,
        name: &str,
        branch: &OrbitBranch,
        label: usize,
        spec: &CurveSpec,
    ) -> Result<OrbitBranch> {
        branch.validate(self.system)?;
        let special = branch.special_at(label)?;
        let wrong = |reason| Error::WrongSpecialPoint {
            operation: "continue a curve",
            label,
            branch: branch.branch.name.clone(),
            kind: special.kind.label().to_string(),
            reason,
        };
        if branch.second.is_some() {
            return Err(wrong("the branch is already a two-parameter curve"));
        }
        let mut orbit = branch.orbit_of(&special.point)?;
        let symmetric = self.half_orbits && orbit.is_symmetric(self.system, self.symmetry_tol);
        let measure = match special.on {
            Some(Quantity::Measure(m)) => Some(m),
            _ => None,
        };
        let condition = match (special.kind, measure) {
            (SpecialKind::Fold, _) => CurveCondition::Fold,
            (SpecialKind::BranchPoint, _) if symmetric => CurveCondition::SymmetryBreaking,
            (SpecialKind::BranchPoint, _) => {
                return Err(wrong(
                    "only symmetry-breaking branch points (of symmetric orbits) have curves",
                ));
            }
            (SpecialKind::PeriodDoubling, _) => CurveCondition::PeriodDoubling,
            (
                SpecialKind::BoundaryTouch | SpecialKind::Grazing | SpecialKind::Custom(_),
                Some(m),
            ) if m == MeasureId::SHORTEST_SEGMENT
                || (self.admissibility.is_some_and(|(_, domain)| domain == m)
                    && orbit.durations.iter().any(|d| d.abs() < 1e-8)) =>
            {
                // A collapsed segment (the domain margin's duration condition, too): its
                // (located) duration is zero up to rounding.
                for d in &mut orbit.durations {
                    if d.abs() < 1e-8 {
                        *d = 0.0;
                    }
                }
                CurveCondition::Collapse { segment: 0 }
            }
            (
                SpecialKind::BoundaryTouch | SpecialKind::Grazing | SpecialKind::Custom(_),
                Some(m),
            ) if m.index() >= 2 => CurveCondition::Measure {
                measure: m,
                level: special.level.unwrap_or(0.0),
            },
            _ => return Err(wrong("curves start at SN, BP, PD and events on measures")),
        };
        let at = (branch, branch.discretisation_of(&special.point)?);
        self.continue_curve(name, at, orbit, condition, special.kind, spec, &wrong)
    }

    /// Continues the curve saved as `curve` (by [`OrbitRun::curve_at`] or this) further from its
    /// point labelled `label` (e.g. one of its ends, with wider bounds), in the same parameters
    /// and with the same defining condition; `spec.second` must be the curve's.
    ///
    /// # Errors
    /// A curve that does not fit the system, a branch or a curve saved without its condition,
    /// another second parameter, an unknown label; as [`OrbitRun::curve_at`].
    pub fn curve_from(
        &mut self,
        name: &str,
        curve: &OrbitBranch,
        label: usize,
        spec: &CurveSpec,
    ) -> Result<OrbitBranch> {
        curve.validate(self.system)?;
        let point = curve.point(label)?;
        let (Some(second), Some(condition)) = (curve.second, curve.condition) else {
            return Err(Error::InvalidSetting {
                name: "curve",
                value: label as f64,
                reason: "not a two-parameter curve saved with its condition",
            });
        };
        if spec.second != second {
            return Err(Error::InvalidSetting {
                name: "second parameter",
                value: spec.second.index() as f64,
                reason: "a curve continues in its own second parameter",
            });
        }
        let mut orbit = curve.orbit_of(point)?;
        if matches!(condition, CurveCondition::Collapse { .. }) {
            for d in &mut orbit.durations {
                if d.abs() < 1e-8 {
                    *d = 0.0;
                }
            }
        }
        let wrong = |reason| Error::WrongSpecialPoint {
            operation: "continue a curve",
            label,
            branch: curve.branch.name.clone(),
            kind: condition.kind().label().to_string(),
            reason,
        };
        let kind = condition.kind();
        let at = (curve, curve.discretisation_of(point)?);
        self.continue_curve(name, at, orbit, condition, kind, spec, &wrong)
    }

    /// The other curve through the fold-flip point (LPPD) labelled `label` of the fold or
    /// period-doubling curve `curve`, in the same two parameters (`spec.second` must be the
    /// curve's): from a fold curve the period-doubling curve through it, and the other way;
    /// on the curve's discretisation, as [`OrbitRun::curve_at`] continues curves.
    ///
    /// # Errors
    /// A curve that does not fit the system, a branch or a curve saved without its condition,
    /// another second parameter, an unknown label, a point that is not LPPD
    /// ([`Error::WrongSpecialPoint`]); no solution near the start.
    pub fn curve_through(
        &mut self,
        name: &str,
        curve: &OrbitBranch,
        label: usize,
        spec: &CurveSpec,
    ) -> Result<OrbitBranch> {
        curve.validate(self.system)?;
        let special = curve.special_at(label)?;
        let wrong = |reason| Error::WrongSpecialPoint {
            operation: "continue the other curve",
            label,
            branch: curve.branch.name.clone(),
            kind: special.kind.label().to_string(),
            reason,
        };
        if special.kind != SpecialKind::FoldFlip {
            return Err(wrong("the other curve starts at a fold-flip point (LPPD)"));
        }
        let other = match curve.condition {
            Some(CurveCondition::Fold) => CurveCondition::PeriodDoubling,
            Some(CurveCondition::PeriodDoubling) => CurveCondition::Fold,
            _ => {
                return Err(wrong(
                    "not a fold or period-doubling curve saved with its condition",
                ));
            }
        };
        if curve.second != Some(spec.second) {
            return Err(Error::InvalidSetting {
                name: "second parameter",
                value: spec.second.index() as f64,
                reason: "the other curve is in the curve's own two parameters",
            });
        }
        let orbit = curve.orbit_of(&special.point)?;
        let at = (curve, curve.discretisation_of(&special.point)?);
        self.continue_curve(name, at, orbit, other, other.kind(), spec, &wrong)
    }

    /// The curve with `condition` through `orbit` (a point of `branch` on its discretisation
    /// `disc`, which the curve keeps).
    #[allow(clippy::too_many_arguments)]
    fn continue_curve(
        &mut self,
        name: &str,
        (branch, disc): (&OrbitBranch, &Discretisation),
        orbit: hycont_core::orbit::PeriodicOrbit,
        condition: CurveCondition,
        kind: SpecialKind,
        spec: &CurveSpec,
        wrong: &dyn Fn(&'static str) -> Error,
    ) -> Result<OrbitBranch> {
        let symmetric = self.half_orbits && orbit.is_symmetric(self.system, self.symmetry_tol);
        let half = symmetric && condition != CurveCondition::PeriodDoubling;
        let (start, disc) = if half {
            let h = orbit.half_of_symmetric(self.system, self.symmetry_tol)?;
            let disc = match disc {
                Discretisation::Collocation { meshes, ncol } => Discretisation::Collocation {
                    meshes: meshes[..h.segment_count()].to_vec(),
                    ncol: *ncol,
                },
                d => d.clone(),
            };
            (h, disc)
        } else {
            (orbit, disc.clone())
        };
        let condition = match condition {
            // A grazing found by a margin at an orbit whose segment has collapsed onto the
            // surface it touches: as singular as the collapse itself.
            CurveCondition::Measure { .. }
                if start.durations.iter().enumerate().any(|(k, d)| {
                    d.abs() < 1e-8
                        && super::collapse::collapses_tangentially(self.system, &start, k)
                }) =>
            {
                return Err(wrong(
                    "a segment has collapsed onto an event surface the flow touches \
                     tangentially, where the curve's condition is singular; continue the \
                     grazing curve from the other side (the margin's event on longer segments)",
                ));
            }
            // A margin held at zero: the condition that attains it, smooth where the margin is
            // not (where another condition meets it, e.g. a turning point reaching a segment's
            // end).
            CurveCondition::Measure {
                measure,
                level: 0.0,
            } => {
                match self
                    .measures
                    .touch(self.system, &start, measure.index() - 2)?
                {
                    Some(touch) => CurveCondition::Touch {
                        touch,
                        measure: Some(measure),
                        kind,
                    },
                    None => condition,
                }
            }
            CurveCondition::Collapse { .. } => {
                let segment = start
                    .durations
                    .iter()
                    .enumerate()
                    .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                    .map_or(0, |(k, _)| k);
                if super::collapse::collapses_tangentially(self.system, &start, segment) {
                    return Err(wrong(
                        "its segment collapses onto an event surface the flow touches \
                         tangentially, where a zero duration is not a regular condition; \
                         continue the grazing curve from an event on a GrazingMargin measure",
                    ));
                }
                CurveCondition::Collapse { segment }
            }
            c => c,
        };
        let (mut cp, u0) = Codim2::new(
            self.system,
            &start,
            &disc,
            branch.free,
            spec.second,
            condition,
            self.measures.clone(),
            self.curve_events(
                condition.defining_measure().map(Quantity::Measure),
                kind,
                spec,
            )?,
        )?;
        cp.require_admissible(self.admissibility_on());
        let mut settings = self.curve_settings.clone();
        settings.bounds.extend(self.settings.bounds.iter().copied());
        if let Some((lo, hi)) = spec.bounds {
            settings = settings.bounds(spec.second, lo, hi);
        }
        let b = self.continue_in(&mut cp, name, &u0, None, spec.direction, &settings)?;
        let inner = cp.orbit_problem();
        self.saved(
            inner,
            inner.into_full_branch(b),
            Some((spec.second, condition)),
        )
    }

    /// The events along a curve: `spec`'s user points and the run's terminal events except
    /// those on the measure `defining` the curve and, on a curve of a `kind` point, the
    /// admissibility event of that kind (its margin vanishes along the curve).
    fn curve_events(
        &self,
        defining: Option<Quantity>,
        kind: SpecialKind,
        spec: &CurveSpec,
    ) -> Result<Vec<MonitorEvent>> {
        let same_kind_admissibility = |e: &MonitorEvent| {
            self.admissibility.is_some_and(|(graze, domain)| {
                e.kind == kind
                    && (e.on == Quantity::Measure(graze) || e.on == Quantity::Measure(domain))
            })
        };
        let mut events: Vec<MonitorEvent> = self
            .events
            .iter()
            .filter(|e| e.terminal && Some(e.on) != defining && !same_kind_admissibility(e))
            .copied()
            .collect();
        for &(on, level) in &spec.user_points {
            self.check_quantity(on)?;
            if !level.is_finite() {
                return Err(Error::InvalidSetting {
                    name: "user point",
                    value: level,
                    reason: "must be finite",
                });
            }
            events.push(MonitorEvent {
                kind: SpecialKind::UserPoint,
                on,
                level,
                terminal: false,
            });
        }
        Ok(events)
    }
}
