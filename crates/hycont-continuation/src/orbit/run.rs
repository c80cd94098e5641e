//! Orbit runs (COCO's `ode_isol2hspo` and `coco` in one typed builder): the system, the
//! continued parameter, the discretisation, step settings and bounds, named measures, events
//! with labels and user points, and the calls that produce branches: [`OrbitRun::run`] from an
//! orbit, [`OrbitRun::restart`] from a labelled point of a saved branch,
//! [`OrbitRun::switch_at`] a branch point or period doubling, and [`OrbitRun::curve_at`] a
//! special point for a two-parameter curve.

use super::problem::{OrbitContinuation, SharedMeasures, check_parameter};
use super::saved::OrbitBranch;
use crate::branch::{Branch, SpecialKind};
use crate::error::{Error, Result};
use crate::observe::{Observer, Silent};
use crate::quantity::{MeasureId, Quantity};
use crate::settings::{BoundOn, ContinuationSettings};
use crate::{ContinuationProblem, MonitorEvent};
use hycont_core::orbit::{
    AdmissibilityMargin, Discretisation, Margin, Measure, MeasureSet, OrbitMethod, PeriodicOrbit,
};
use hycont_core::{HybridJacobians, ParamId};
use serde::{Deserialize, Serialize};
use std::rc::Rc;

/// Which way(s) to continue from a start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunDirection {
    /// Both ways (decreasing first), joined into one branch in increasing order.
    #[default]
    Both,
    /// Increasing continued parameter (or along a switching direction).
    Up,
    /// Decreasing continued parameter (or against a switching direction).
    Down,
}

/// A continuation run of hybrid periodic orbits in one parameter: a builder with validated
/// settings and `Default`-like defaults (shooting, [`ContinuationSettings::default`], no
/// bounds, no measures), whose calls produce [`OrbitBranch`]es.
///
/// ```
/// # use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId};
/// # use hycont_core::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature, Extremum};
/// use hycont_continuation::{OrbitRun, RunDirection, SpecialKind};
/// # /// x' = y + x (a - x^2 - y^2), y' = -x + y (a - x^2 - y^2): circles of radius sqrt(a).
/// # struct Hopf;
/// # impl HybridSystem for Hopf {
/// #     fn state_dim(&self) -> usize { 2 }
/// #     fn parameter_names(&self) -> &[&'static str] { &["a"] }
/// #     fn mode_count(&self) -> usize { 1 }
/// #     fn mode_name(&self, _: Mode) -> &'static str { "m" }
/// #     fn events(&self, _: Mode) -> &[EventId] { &[] }
/// #     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
/// #     fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
/// #         let r = p[0] - x[0] * x[0] - x[1] * x[1];
/// #         f[0] = x[1] + x[0] * r; f[1] = -x[0] + x[1] * r;
/// #     }
/// #     fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 { 0.0 }
/// # }
/// # impl HybridJacobians for Hopf {
/// #     fn vector_field_jacobian(&self, _: Mode, x: &[f64], p: &[f64], dx: &mut [f64], dp: Option<&mut [f64]>) {
/// #         let r = p[0] - x[0] * x[0] - x[1] * x[1];
/// #         dx[0] = r - 2.0 * x[0] * x[0]; dx[1] = -1.0 - 2.0 * x[0] * x[1];
/// #         dx[2] = 1.0 - 2.0 * x[0] * x[1]; dx[3] = r - 2.0 * x[1] * x[1];
/// #         if let Some(dp) = dp { dp[0] = x[0]; dp[1] = x[1]; }
/// #     }
/// #     fn event_gradient(&self, _: EventId, _: &[f64], _: &[f64], _: &mut [f64], _: Option<&mut [f64]>) {}
/// # }
/// // The circle of radius 1 (a = 1), one turn from y = 0 back to y = 0.
/// let sig = Signature::new(&Hopf, vec![SegmentSpec {
///     mode: Mode(0), end: SegmentEnd::Interior { component: 1, value: 0.0 } }]).unwrap();
/// let start = PeriodicOrbit::new(&Hopf, sig, vec![vec![1.0, 0.0]],
///                                vec![2.0 * std::f64::consts::PI], vec![1.0]).unwrap();
/// let mut run = OrbitRun::new(&Hopf, ParamId(0)).unwrap();
/// run.bounds(0.5, 2.0);
/// let radius = run.add_measure("radius", Extremum::max(0)).unwrap();
/// run.add_user_points(radius, [1.2]).unwrap();   // UZ where the radius is 1.2
/// let branch = run.run("circles", &start, RunDirection::Both).unwrap();
/// let uz = branch.special(SpecialKind::UserPoint).next().unwrap();
/// // The radius is sqrt(a): a = 1.44 there.
/// assert!((uz.point[ParamId(0)] - 1.44).abs() < 1e-8);
/// ```
pub struct OrbitRun<'a, S: ?Sized> {
    pub(super) system: &'a S,
    pub(super) free: ParamId,
    pub(super) method: OrbitMethod,
    pub(super) settings: ContinuationSettings,
    pub(super) curve_settings: ContinuationSettings,
    pub(super) measures: SharedMeasures<'a, S>,
    pub(super) events: Vec<MonitorEvent>,
    pub(super) half_orbits: bool,
    pub(super) symmetry_tol: f64,
    pub(super) observer: Box<dyn Observer + 'a>,
    /// The admissibility measures, once added.
    pub(super) admissibility: Option<(MeasureId, MeasureId)>,
}

impl<S: ?Sized> std::fmt::Debug for OrbitRun<'_, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OrbitRun")
            .field("free", &self.free)
            .field("method", &self.method)
            .field("settings", &self.settings)
            .field("measures", &self.measures)
            .field("events", &self.events)
            .field("half_orbits", &self.half_orbits)
            .finish_non_exhaustive()
    }
}

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// A run of `system`'s periodic orbits continued in `free`.
    ///
    /// # Errors
    /// [`Error::NoSuchQuantity`] if the system has no parameter `free`.
    pub fn new(system: &'a S, free: ParamId) -> Result<Self> {
        check_parameter(system, free)?;
        let mut run = Self {
            system,
            free,
            method: OrbitMethod::default(),
            settings: ContinuationSettings::default(),
            curve_settings: crate::curve_settings(),
            measures: Rc::new(MeasureSet::new()),
            events: Vec::new(),
            half_orbits: true,
            symmetry_tol: 1e-6,
            observer: Box::new(Silent),
            admissibility: None,
        };
        run.admissibility(true)?;
        Ok(run)
    }

    /// Whether branches end where their orbits stop being admissible (default: on). On, the
    /// run records two measures, `admissible_grazing` and `admissible_domain`
    /// ([`AdmissibilityMargin`]), and ends the branch where the first reaches zero with a
    /// located GR point (an interior touch of an event surface or a tangential impact) and
    /// where the second does with a located `DB` point (a segment collapses or ends on another
    /// event's surface). Off, the events are dropped (the measures, once added, stay
    /// recorded).
    ///
    /// # Errors
    /// As [`OrbitRun::add_measure`] when the measures are first added.
    pub fn admissibility(&mut self, on: bool) -> Result<&mut Self> {
        let kinds = [SpecialKind::Grazing, SpecialKind::DOMAIN_BOUNDARY];
        if on {
            let ids = match self.admissibility {
                Some(ids) => ids,
                None => {
                    let graze = AdmissibilityMargin::new(self.system, Margin::Grazing);
                    let domain = AdmissibilityMargin::new(self.system, Margin::Domain);
                    let ids = (
                        self.add_measure("admissible_grazing", graze)?,
                        self.add_measure("admissible_domain", domain)?,
                    );
                    self.admissibility = Some(ids);
                    ids
                }
            };
            let ons = [Quantity::from(ids.0), Quantity::from(ids.1)];
            if !self.events.iter().any(|e| ons.contains(&e.on)) {
                for (on, kind) in ons.into_iter().zip(kinds) {
                    self.push_event(on, 0.0, kind, true)?;
                }
            }
        } else if let Some(ids) = self.admissibility {
            let ons = [Quantity::from(ids.0), Quantity::from(ids.1)];
            self.events.retain(|e| !ons.contains(&e.on));
        }
        Ok(self)
    }

    /// The discretisation (default: shooting with its default settings).
    pub fn method(&mut self, method: OrbitMethod) -> &mut Self {
        self.method = method;
        self
    }

    /// The continuation settings of branches (validated when a run starts).
    pub fn settings(&mut self, settings: ContinuationSettings) -> &mut Self {
        self.settings = settings;
        self
    }

    /// The continuation settings of branches, to change in place (e.g. `stop_at` between
    /// calls).
    pub fn settings_mut(&mut self) -> &mut ContinuationSettings {
        &mut self.settings
    }

    /// The continuation settings of two-parameter curves (default [`crate::curve_settings`]);
    /// the branch settings' bounds apply to curves as well.
    pub fn curve_settings(&mut self, settings: ContinuationSettings) -> &mut Self {
        self.curve_settings = settings;
        self
    }

    /// Bounds the continued parameter to `[min, max]` (replacing earlier bounds on it).
    pub fn bounds(&mut self, min: f64, max: f64) -> &mut Self {
        self.settings
            .bounds
            .retain(|b| b.on != BoundOn::ContinuationParameter);
        self.settings = std::mem::take(&mut self.settings).parameter_bounds(min, max);
        self
    }

    /// Bounds a parameter or measure to `[min, max]`.
    ///
    /// # Errors
    /// [`Error::NoSuchQuantity`] for a handle the run does not have.
    pub fn bound(&mut self, on: impl Into<Quantity>, min: f64, max: f64) -> Result<&mut Self> {
        let on = on.into();
        self.check_quantity(on)?;
        self.settings = std::mem::take(&mut self.settings).bounds(on, min, max);
        Ok(self)
    }

    /// The first, smallest and largest arclength steps.
    pub fn steps(&mut self, h0: f64, h_min: f64, h_max: f64) -> &mut Self {
        self.settings = std::mem::take(&mut self.settings).steps(h0, h_min, h_max);
        self
    }

    /// The largest number of points of a branch.
    pub fn max_points(&mut self, n: usize) -> &mut Self {
        self.settings.max_points = n;
        self
    }

    /// Ends branches at the first located special point of this kind.
    pub fn stop_at(&mut self, kind: SpecialKind) -> &mut Self {
        self.settings.stop_at.push(kind);
        self
    }

    /// Whether symmetric starts of a system with a symmetry are continued on their half orbit
    /// (default `true`: half the work per point, the same orbits and special points).
    pub fn half_orbits(&mut self, on: bool) -> &mut Self {
        self.half_orbits = on;
        self
    }

    /// Receives every point and special point (e.g. a progress bar; default: none).
    pub fn observer(&mut self, observer: Box<dyn Observer + 'a>) -> &mut Self {
        self.observer = observer;
        self
    }

    /// Records a measure at every point (COCO's `coco_add_func` of a monitor); returns its
    /// handle, usable in events, user points, bounds and [`crate::BranchPoint::get`].
    ///
    /// # Errors
    /// A name that is empty or taken; [`Error::InvalidSetting`] if a problem built by this run
    /// is still alive.
    pub fn add_measure(&mut self, name: &str, measure: impl Measure<S> + 'a) -> Result<MeasureId> {
        let set = Rc::get_mut(&mut self.measures).ok_or(Error::InvalidSetting {
            name: "measures",
            value: 0.0,
            reason: "cannot be added while a problem of this run is alive",
        })?;
        let index = set.add(name, measure)?;
        Ok(MeasureId::named(2 + index, name))
    }

    /// A special point of kind `kind` where `on` crosses `level` (COCO's `coco_add_event`):
    /// `kind` is [`SpecialKind::BoundaryTouch`], [`SpecialKind::Grazing`],
    /// [`SpecialKind::UserPoint`] or a [`SpecialKind::Custom`] label.
    ///
    /// # Errors
    /// An unknown quantity, a non-finite level, or a kind that has its own detector.
    pub fn add_event(
        &mut self,
        on: impl Into<Quantity>,
        level: f64,
        kind: SpecialKind,
    ) -> Result<&mut Self> {
        self.push_event(on.into(), level, kind, false)
    }

    /// Like [`OrbitRun::add_event`], and the branch ends there (e.g. beyond it the orbits are
    /// not admissible). Where terminal events are located at one point (within the location
    /// tolerance), the one added first ends the branch, and users' events come before the
    /// run's admissibility margins ([`crate::ContinuationProblem::monitor_events`]).
    ///
    /// # Errors
    /// As [`OrbitRun::add_event`].
    pub fn add_terminal_event(
        &mut self,
        on: impl Into<Quantity>,
        level: f64,
        kind: SpecialKind,
    ) -> Result<&mut Self> {
        self.push_event(on.into(), level, kind, true)
    }

    /// User points (UZ) where `on` takes each of `values`.
    ///
    /// # Errors
    /// As [`OrbitRun::add_event`].
    pub fn add_user_points(
        &mut self,
        on: impl Into<Quantity>,
        values: impl IntoIterator<Item = f64>,
    ) -> Result<&mut Self> {
        let on = on.into();
        for v in values {
            self.push_event(on, v, SpecialKind::UserPoint, false)?;
        }
        Ok(self)
    }

    fn push_event(
        &mut self,
        on: Quantity,
        level: f64,
        kind: SpecialKind,
        terminal: bool,
    ) -> Result<&mut Self> {
        self.check_quantity(on)?;
        if !level.is_finite() {
            return Err(Error::InvalidSetting {
                name: "event level",
                value: level,
                reason: "must be finite",
            });
        }
        if !matches!(
            kind,
            SpecialKind::BoundaryTouch
                | SpecialKind::Grazing
                | SpecialKind::UserPoint
                | SpecialKind::Custom(_)
        ) {
            return Err(Error::InvalidLabel {
                label: kind.label().to_string(),
                reason: "has its own detector; events take SB, GR, UZ or a user label",
            });
        }
        // The run's admissibility events stay last: a user's event located at one point with
        // them ends the run ([`crate::ContinuationProblem::monitor_events`]'s precedence).
        let ons = self
            .admissibility
            .map(|(graze, domain)| [Quantity::from(graze), Quantity::from(domain)]);
        let at = match ons {
            Some(ons) if !ons.contains(&on) => (self.events.iter())
                .position(|e| ons.contains(&e.on))
                .unwrap_or(self.events.len()),
            _ => self.events.len(),
        };
        self.events.insert(
            at,
            MonitorEvent {
                kind,
                on,
                level,
                terminal,
            },
        );
        Ok(self)
    }

    /// Checks a parameter or measure handle against the run (a measure handle of another run,
    /// whose measure at that index has another name, is [`Error::ForeignHandle`]).
    pub(super) fn check_quantity(&self, q: Quantity) -> Result<()> {
        let m = match q {
            Quantity::Parameter(p) => return check_parameter(self.system, p),
            Quantity::Measure(m) => m,
        };
        let count = 2 + self.measures.len();
        let name = match m.index() {
            0 => "period",
            1 => "shortest_segment",
            i if i < count => self.measures.names()[i - 2].as_str(),
            _ => return Err(Error::NoSuchQuantity { quantity: q, count }),
        };
        if m.fits(name) {
            Ok(())
        } else {
            Err(Error::ForeignHandle {
                quantity: q,
                reason: format!("this run's measure #{} is {name:?}", m.index()),
            })
        }
    }

    /// The continuation problem of `start` and its starting unknowns: on the half orbit when the
    /// start is symmetric (to `1e-6`), the system has a symmetry and half orbits are on. A
    /// symmetric orbit is recognised by its signature: $2K$ segments, the last $K$ the images of
    /// the first $K$ ([`PeriodicOrbit::is_symmetric`]); give a symmetric start with a segment
    /// boundary half a period after another (e.g. at both impacts of a symmetric impacting
    /// orbit).
    ///
    /// # Errors
    /// As [`OrbitContinuation::new`].
    pub fn problem(&self, start: &PeriodicOrbit) -> Result<(OrbitContinuation<'a, S>, Vec<f64>)> {
        self.problem_in(start, self.free)
    }

    /// [`OrbitRun::problem`] continued in `free` (a saved branch's parameter, where a switch
    /// continues it).
    pub(super) fn problem_in(
        &self,
        start: &PeriodicOrbit,
        free: ParamId,
    ) -> Result<(OrbitContinuation<'a, S>, Vec<f64>)> {
        start.validate(self.system)?;
        let half;
        let start = if self.half_orbits && start.is_symmetric(self.system, self.symmetry_tol) {
            half = start.half_of_symmetric(self.system, self.symmetry_tol)?;
            &half
        } else {
            start
        };
        let (mut cp, u0) = OrbitContinuation::new(
            self.system,
            start,
            &self.method,
            free,
            self.measures.clone(),
            self.events.clone(),
        )?;
        cp.require_admissible(self.admissibility_on());
        Ok((cp, u0))
    }

    /// Whether the run's admissibility is on ([`OrbitRun::admissibility`]): its branches end
    /// where their orbits stop being admissible, and its starts must be admissible.
    #[must_use]
    pub fn admissibility_on(&self) -> bool {
        self.admissibility.is_some_and(|(graze, domain)| {
            let ons = [Quantity::from(graze), Quantity::from(domain)];
            self.events.iter().any(|e| ons.contains(&e.on))
        })
    }

    /// The branch through `start` (a periodic orbit or a good guess, e.g.
    /// [`PeriodicOrbit::from_simulation`]), named `name`, in `direction`. Both ways, the two
    /// runs are joined into one branch in increasing order with one labelling, unless the first
    /// closes the branch (a closed curve). The branch reaches the located point it ended on (a
    /// bound, an inadmissible orbit, a stop point). A corrector failure in the middle ends the
    /// run and keeps the branch ([`crate::EndReason::CorrectorFailed`]).
    ///
    /// # Errors
    /// An invalid start or settings, or no solution near the start.
    pub fn run(
        &mut self,
        name: &str,
        start: &PeriodicOrbit,
        direction: RunDirection,
    ) -> Result<OrbitBranch> {
        let (mut cp, u0) = self.problem(start)?;
        let settings = self.settings.clone();
        let branch = self.continue_in(&mut cp, name, &u0, None, direction, &settings)?;
        self.saved(&cp, cp.into_full_branch(branch), None)
    }

    /// Continues from the point labelled `label` of a saved branch, in `direction` (`None`: the
    /// way the saved run went there, when the continued parameter is the same; else both
    /// ways). A collocation branch restarted by collocation keeps its mesh and unknowns; other
    /// restarts start from the point's orbit.
    ///
    /// A restart continues the branch through the point's orbit as any run does, from the
    /// orbit with the parameter held: at a point where two branches meet it may follow either.
    /// The first point of a branch switched at a branch point ([`OrbitRun::switch_at`]) is the
    /// branch point itself, where a restart can follow the family switched from; restart a
    /// switched branch from its second point on to stay on it.
    ///
    /// # Errors
    /// A branch that does not fit the system, a two-parameter curve, an unknown label; as
    /// [`OrbitRun::run`].
    pub fn restart(
        &mut self,
        name: &str,
        saved: &OrbitBranch,
        label: usize,
        direction: Option<RunDirection>,
    ) -> Result<OrbitBranch> {
        saved.validate(self.system)?;
        if saved.second.is_some() {
            return Err(Error::InvalidSetting {
                name: "restart",
                value: label as f64,
                reason: "a two-parameter curve cannot be restarted as a branch",
            });
        }
        let point = saved.point(label)?;
        let direction = match direction {
            Some(d) => d,
            None if saved.free == self.free => saved.direction_at(label)?,
            None => RunDirection::Both,
        };
        let disc = saved.discretisation_of(point)?;
        let keep_mesh = matches!(disc, Discretisation::Collocation { .. })
            && matches!(self.method, OrbitMethod::Collocation(_));
        if !keep_mesh {
            let orbit = saved.orbit_of(point)?;
            return self.run(name, &orbit, direction);
        }
        let mut cp = OrbitContinuation::on_discretisation(
            self.system,
            saved.template.clone(),
            disc.clone(),
            self.free,
            self.measures.clone(),
            self.events.clone(),
        )?;
        cp.require_admissible(self.admissibility_on());
        let nbase = cp.problem().base_unknowns();
        let mut u0 = point.u[..nbase].to_vec();
        u0.push(point.u[nbase - saved.template.params.len() + self.free.index()]);
        let settings = self.settings.clone();
        let branch = self.continue_in(&mut cp, name, &u0, None, direction, &settings)?;
        self.saved(&cp, branch, None)
    }

    /// The saved form of a branch of `cp` (in the full orbits' layout).
    pub(super) fn saved(
        &self,
        cp: &OrbitContinuation<'a, S>,
        branch: Branch,
        curve: Option<(ParamId, crate::codim2::CurveCondition)>,
    ) -> Result<OrbitBranch> {
        let (template, _) = cp.full_layout()?;
        let mut revisions = cp.full_revisions().into_iter();
        let discretisation = revisions.next().expect("a problem has a discretisation");
        let saved = OrbitBranch {
            branch,
            free: cp.parameter(),
            second: curve.map(|c| c.0),
            condition: curve.map(|c| c.1),
            template,
            discretisation,
            rediscretised: revisions.collect(),
        };
        // The test suites' invariant: every point of every branch is an orbit, and a physical
        // one where the run's admissibility is on.
        #[cfg(feature = "invariants")]
        if crate::checking_branches()
            && let Err(e) = saved.check_points(self.system, self.admissibility_on())
        {
            panic!("branch invariant violated: {e}");
        }
        Ok(saved)
    }
}
