//! Two-parameter continuation of codimension-one points of hybrid periodic orbits: folds (SN),
//! period doublings (PD), symmetry-breaking branch points (BP), and events on measures such as
//! boundary touch (SB) and grazing (GR), on either discretisation.
//!
//! Each curve is the orbit's discretised problem with both parameters released and one defining
//! scalar equation added:
//! - SN, PD, and SN and BP of a $\mathbb{Z}_2$-symmetric orbit (on its half orbit): the
//!   problem's Jacobian with its closure scaled by $+1$ (fold) or $-1$ (period doubling;
//!   symmetry breaking on a half orbit, where the half map $S \circ \phi_{T/2}$ has the
//!   multiplier $-1$) is singular, as a minimally augmented system (see `singular.rs`): the
//!   full-period map has a multiplier $+1$ at both a symmetric fold and a symmetry-breaking
//!   point, the half map tells them apart;
//! - events: a measure of the orbit held at its level (SB: an amplitude at a boundary; GR: a
//!   grazing margin at zero), or a segment's duration held at zero (GR: the segment has
//!   collapsed).
//!
//! Built by [`crate::OrbitRun::curve_at`] from a labelled special point of a branch, or by hand
//! with [`Codim2::new`].

mod measured;
mod singular;

use crate::error::{Error, Result};
use crate::orbit::{OrbitContinuation, SharedMeasures};
use crate::quantity::{MeasureId, Quantity};
use crate::{ContinuationProblem, MonitorEvent, PointInfo};
use hycont_core::orbit::{Closure, Discretisation, PeriodicOrbit, Touch};
use hycont_core::problem::Activity;
use hycont_core::{HybridJacobians, ParamId};
use measured::{Held, MeasuredCondition};
use serde::{Deserialize, Serialize};
use singular::SingularClosure;

/// The defining condition of a two-parameter curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum CurveCondition {
    /// A non-trivial multiplier at $+1$: a fold (on a half orbit: of the half map, a fold of
    /// symmetric orbits).
    Fold,
    /// A non-trivial multiplier at $-1$ (a full orbit).
    PeriodDoubling,
    /// On a half orbit: a half-map multiplier at $-1$, a symmetry-breaking branch point.
    SymmetryBreaking,
    /// A measure held at a level (user measures only: from index 2 on).
    Measure {
        /// The measure.
        measure: MeasureId,
        /// Its level.
        level: f64,
    },
    /// The duration of segment `segment` held at zero (the segment has collapsed: a grazing).
    Collapse {
        /// The segment.
        segment: usize,
    },
    /// One grazing or boundary condition held at zero ([`Touch`]: a turning point on an
    /// event surface, a tangential impact, a segment ending on a surface): where a margin
    /// measure vanished at the curve's start, the condition that attained it, smooth where
    /// the margin is not.
    Touch {
        /// The condition.
        touch: Touch,
        /// The margin it attained at the curve's start (zero along the curve: its events are
        /// not detected there).
        measure: Option<MeasureId>,
        /// The kind of the special point the curve started at (e.g. GR, or DB for a domain
        /// boundary).
        kind: crate::SpecialKind,
    },
}

impl CurveCondition {
    /// The special-point kind whose curve this is (an event curve's kind is its event's).
    #[must_use]
    pub fn kind(self) -> crate::SpecialKind {
        use crate::SpecialKind as K;
        match self {
            CurveCondition::PeriodDoubling => K::PeriodDoubling,
            CurveCondition::Fold => K::Fold,
            CurveCondition::SymmetryBreaking => K::BranchPoint,
            CurveCondition::Measure { .. } => K::BoundaryTouch,
            CurveCondition::Collapse { .. } => K::Grazing,
            CurveCondition::Touch { kind, .. } => kind,
        }
    }

    /// The measure whose value the condition holds (an event on it would mark every point):
    /// the held measure, or the margin a touch attained at the start.
    #[must_use]
    pub fn defining_measure(self) -> Option<MeasureId> {
        match self {
            CurveCondition::Measure { measure, .. } => Some(measure),
            CurveCondition::Touch { measure, .. } => measure,
            _ => None,
        }
    }
}

/// A two-parameter curve problem: the orbit's problem with `first` and `second` released and
/// the defining equation of its [`CurveCondition`] added; continued in `first` (both parameters
/// are in every point's [`crate::BranchPoint::params`]).
pub struct Codim2<'a, S: ?Sized> {
    inner: OrbitContinuation<'a, S>,
    condition: CurveCondition,
    second: ParamId,
}

impl<S: ?Sized> std::fmt::Debug for Codim2<'_, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Codim2")
            .field("inner", &self.inner)
            .field("condition", &self.condition)
            .field("second", &self.second)
            .finish()
    }
}

impl<'a, S: HybridJacobians + ?Sized> Codim2<'a, S> {
    /// The curve problem through `orbit` (a point of the curve, e.g. a located special point's
    /// orbit; for [`CurveCondition::SymmetryBreaking`] and the fold of a symmetric orbit, its
    /// half orbit) on `disc`, continued in `first` with `second` released, and the starting
    /// unknowns. `events` are detected along the curve.
    ///
    /// # Errors
    /// Parameters the system does not have or that coincide; a condition that does not apply
    /// to the orbit (symmetry breaking needs a half orbit, period doubling a full one, a
    /// measure index out of range); a problem that cannot be built.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        system: &'a S,
        orbit: &PeriodicOrbit,
        disc: &Discretisation,
        first: ParamId,
        second: ParamId,
        condition: CurveCondition,
        measures: SharedMeasures<'a, S>,
        events: Vec<MonitorEvent>,
    ) -> Result<(Self, Vec<f64>)> {
        crate::orbit::check_parameter(system, first)?;
        crate::orbit::check_parameter(system, second)?;
        if first == second {
            return Err(Error::InvalidSetting {
                name: "second parameter",
                value: second.index() as f64,
                reason: "must differ from the continued one",
            });
        }
        let base = disc.pack(system, orbit)?;
        let factor = closure_factor(system, condition, orbit, measures.len())?;
        let u_base = base.clone();
        let mut inner = OrbitContinuation::build(
            system,
            orbit.clone(),
            disc.clone(),
            first,
            measures.clone(),
            events,
            Box::new(move |eq| match factor {
                Some(c) => Ok(Box::new(SingularClosure::new(eq, c, &u_base)?) as _),
                None => Ok(eq as _),
            }),
        )?;
        let problem = inner.problem_mut();
        let id = problem
            .monitor_id(system.parameter_names()[second.index()])
            .ok_or_else(|| Error::SwitchFailed {
                reason: format!("no monitor for parameter #{}", second.index()),
            })?;
        problem.set_activity(id, Activity::Active(orbit.params[second.index()]))?;
        let nbase = problem.base_unknowns();
        let held = match condition {
            CurveCondition::Measure { measure, level } => Some(Held::Measure {
                index: measure.index() - 2,
                level,
            }),
            CurveCondition::Collapse { segment } => Some(Held::Duration {
                column: disc.segment_values(orbit) + segment,
            }),
            CurveCondition::Touch { touch, .. } => Some(Held::Touch(touch)),
            _ => None,
        };
        if let Some(held) = held {
            let part = MeasuredCondition {
                system,
                like: orbit.clone(),
                disc: disc.clone(),
                measures,
                held,
                unknowns: nbase,
                columns: disc.orbit_columns(orbit),
            };
            problem.add_part(Box::new(part), (0..nbase).collect())?;
        }
        // Unknowns: base, then the active monitors' values in monitor (parameter) order.
        let (p1, p2) = (orbit.params[first.index()], orbit.params[second.index()]);
        let mut u0 = base;
        if first.index() < second.index() {
            u0.extend([p1, p2]);
        } else {
            u0.extend([p2, p1]);
        }
        inner.set_second_parameter(first.index() > second.index());
        if let CurveCondition::Collapse { segment } = condition {
            inner.set_collapsed(segment);
        }
        Ok((
            Self {
                inner,
                condition,
                second,
            },
            u0,
        ))
    }

    /// The underlying orbit problem (with both parameters active).
    #[must_use]
    pub fn orbit_problem(&self) -> &OrbitContinuation<'a, S> {
        &self.inner
    }

    /// Whether runs refuse a start whose orbit is not admissible (see
    /// [`OrbitContinuation::require_admissible`]).
    pub fn require_admissible(&mut self, on: bool) -> &mut Self {
        self.inner.require_admissible(on);
        self
    }

    /// The condition.
    #[must_use]
    pub fn condition(&self) -> CurveCondition {
        self.condition
    }

    /// The second parameter.
    #[must_use]
    pub fn second(&self) -> ParamId {
        self.second
    }
}

impl<'a, S: HybridJacobians + ?Sized> ContinuationProblem<'a> for Codim2<'a, S> {
    fn problem(&mut self) -> &mut hycont_core::problem::Problem<'a> {
        self.inner.problem_mut()
    }
    fn parameter_index(&self) -> usize {
        self.inner.parameter_index()
    }
    fn parameter_position(&self) -> usize {
        self.inner.parameter_position()
    }
    fn parameter_name(&self) -> String {
        self.inner.parameter_name()
    }
    fn parameter_names(&self) -> Vec<String> {
        self.inner.parameter_names()
    }
    fn monitor_names(&self) -> Vec<String> {
        self.inner.monitor_names()
    }
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        self.inner.analyse(u)
    }
    fn check_start(&mut self, u: &[f64]) -> Result<()> {
        self.inner.check_start(u)
    }
    fn monitor_events(&self) -> Vec<MonitorEvent> {
        self.inner.monitor_events()
    }
    fn end_among(&mut self, u: &[f64], located: &[MonitorEvent]) -> usize {
        self.inner.end_among(u, located)
    }
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        self.inner.unknown_weights()
    }
    /// The second parameter's unknown on a fold curve (full or half orbits): the active
    /// parameters are the last two unknowns, the continued one and this.
    fn cusp_parameter(&self) -> Option<usize> {
        (self.condition == CurveCondition::Fold).then(|| {
            let n = self.inner.unknowns();
            2 * n - 3 - self.inner.parameter_index()
        })
    }
    /// The full orbit's multiplier the curve holds: $+1$ on a fold curve, $-1$ on a
    /// period-doubling curve. On a half orbit the analysis reports the full orbit's
    /// multipliers $\lambda = \mu^2$ (the full monodromy is the square of the half map
    /// $S \circ \phi_{T/2}$, whose multipliers are $\mu$): a symmetric fold ($\mu = +1$)
    /// and a symmetry-breaking point ($\mu = -1$) both hold $\lambda = +1$, so their curves
    /// report the full orbit's R1 (another $\mu$ at $\pm 1$), LPNS (a complex $\mu$ pair on
    /// the unit circle) and LPPD ($\mu = \pm i$, a double $\lambda = -1$: not generic on
    /// these curves). R2 and PDNS need a full multiplier held at $-1$, which a symmetric
    /// orbit only has doubled ($\mu = \pm i$): period doubling is continued on full orbits.
    fn held_multiplier(&self) -> Option<f64> {
        match self.condition {
            CurveCondition::Fold | CurveCondition::SymmetryBreaking => Some(1.0),
            CurveCondition::PeriodDoubling if !self.inner.is_half_orbit() => Some(-1.0),
            _ => None,
        }
    }
}

/// Continuation settings suited to two-parameter curves: larger steps (the curves are smooth),
/// events (user points, terminal events) and the codimension-two points of fold and
/// period-doubling curves detected ([`crate::Detect::codim2`]): the one-parameter test
/// functions are meaningless on a curve defined by one of them, and a turning point of the
/// curve in the continued parameter is passed by the arclength parameterisation, not a
/// special point.
#[must_use]
pub fn curve_settings() -> crate::ContinuationSettings {
    crate::ContinuationSettings::default()
        .steps(0.02, 1e-8, 0.25)
        .detect(crate::Detect {
            fold: false,
            branch_point: false,
            period_doubling: false,
            torus: false,
            monitor_events: true,
            codim2: true,
        })
}

/// The factor of the singular closure a curve condition continues ($+1$: a multiplier 1, the
/// fold; $-1$: a multiplier $-1$, period doubling on the full orbit or symmetry breaking on
/// the half orbit), `None` for the conditions held by a measured part; an error where the
/// condition does not apply to `orbit` (with `measures` measures besides the two built in).
fn closure_factor<S: hycont_core::HybridSystem + ?Sized>(
    system: &S,
    condition: CurveCondition,
    orbit: &PeriodicOrbit,
    measures: usize,
) -> Result<Option<f64>> {
    let half = orbit.signature.closure() == Closure::Symmetric;
    Ok(match condition {
        CurveCondition::Fold => Some(1.0),
        CurveCondition::PeriodDoubling if half => {
            return Err(Error::InvalidSetting {
                name: "curve condition",
                value: -1.0,
                reason: "period doubling is continued on the full orbit, not a half orbit",
            });
        }
        CurveCondition::SymmetryBreaking if !half => {
            return Err(Error::InvalidSetting {
                name: "curve condition",
                value: -1.0,
                reason: "symmetry breaking is continued on the half orbit of a symmetric orbit",
            });
        }
        CurveCondition::PeriodDoubling | CurveCondition::SymmetryBreaking => Some(-1.0),
        CurveCondition::Measure { measure, level } => {
            if !level.is_finite() {
                return Err(Error::InvalidSetting {
                    name: "measure level",
                    value: level,
                    reason: "must be finite",
                });
            }
            let count = 2 + measures;
            if measure.index() < 2 || measure.index() >= count {
                return Err(Error::NoSuchQuantity {
                    quantity: Quantity::Measure(measure),
                    count,
                });
            }
            None
        }
        CurveCondition::Touch { touch, .. } => {
            touch.validate(system, orbit)?;
            None
        }
        CurveCondition::Collapse { segment } => {
            if segment >= orbit.segment_count() {
                return Err(Error::InvalidSetting {
                    name: "collapsed segment",
                    value: segment as f64,
                    reason: "the orbit has no such segment",
                });
            }
            None
        }
    })
}
