//! The continuation problem of a hybrid periodic orbit: its discretised boundary-value problem
//! with one parameter released, analysed at every point (Floquet multipliers, period, measures).
//!
//! A $\mathbb{Z}_2$-symmetric orbit can be continued on its half orbit
//! ([`PeriodicOrbit::half_of_symmetric`], closure $x_K = S x_0$): half the segments, so about
//! half the work per point, for the same orbits. The analysis then reports the full orbit's
//! multipliers ($\lambda = \mu^2$ from the half map's $\mu$) and period, and adds the
//! symmetry-breaking factor $\prod (1 + \mu)$ to the branch-point test (see
//! [`crate::PointInfo::branch_point_factor`]), so that a branch of half orbits has the special
//! points of the same branch continued on the full orbit. Its points convert to the full
//! problem's unknowns with [`OrbitContinuation::full_branch`]; branches are switched on the
//! full problem ([`OrbitContinuation::full_orbit_problem`]).

use crate::branch::{Branch, BranchPoint, SpecialKind};
use crate::error::{Error, Result};
use crate::quantity::{MeasureId, Quantity};
use crate::switch::branch_switch_direction;
use crate::{ContinuationProblem, MonitorEvent, PointInfo};
use hycont_core::orbit::{
    Closure, Discretisation, Floquet, LinearizationCache, MeasureSet, OrbitEquations, OrbitMethod,
    PeriodicOrbit, check_admissible_collapsed, orbit_problem, symmetric_floquet,
};
use hycont_core::problem::{Activity, Problem, ZeroFunction};
use hycont_core::{HybridJacobians, ParamId, Z2Symmetry};
use std::rc::Rc;

/// Measures shared by the problems of a run (one branch's problem, its full-orbit problem, its
/// curves).
pub type SharedMeasures<'a, S> = Rc<MeasureSet<'a, S>>;

/// Turns the orbit equations into the problem's part (e.g. adds a defining equation).
pub(crate) type WrapPart<'a> =
    Box<dyn FnOnce(Box<dyn OrbitEquations + 'a>) -> Result<Box<dyn ZeroFunction + 'a>> + 'a>;

/// A hybrid periodic orbit to be continued in one parameter.
///
/// Monitors reported at each point: [`MeasureId::PERIOD`], [`MeasureId::SHORTEST_SEGMENT`],
/// then the [`MeasureSet`]'s measures. Admissibility is built in: when a segment's duration
/// reaches zero the orbit's signature no longer describes it (for impacting systems: a flight
/// that touches the impact surface, a grazing), so a terminal [`SpecialKind::Grazing`] event on
/// the shortest segment ends the branch there, located.
///
/// Started from a half orbit ([`Closure::Symmetric`]) it continues symmetric orbits on the
/// half-orbit problem: half the segments, the full orbit's multipliers ($\lambda = \mu^2$ from
/// the half map's $\mu$) and period, and the symmetry-breaking factor $\prod (1 + \mu)$ in the
/// branch-point test ([`crate::PointInfo::branch_point_factor`]), so that its branch has the
/// special points of the same branch on the full orbit.
pub struct OrbitContinuation<'a, S: ?Sized> {
    pub(super) system: &'a S,
    pub(super) like: PeriodicOrbit,
    pub(super) disc: Discretisation,
    pub(super) cache: Option<LinearizationCache>,
    pub(super) problem: Problem<'a>,
    pub(super) param: usize,
    /// Position from the end of the unknowns of the continuation parameter's slot (0: last).
    pub(super) slot_from_end: usize,
    /// A segment left out of the shortest-segment monitor (held at zero on a grazing curve).
    pub(super) collapsed: Option<usize>,
    pub(super) measures: SharedMeasures<'a, S>,
    pub(super) events: Vec<MonitorEvent>,
    /// The symmetry, on a half-orbit problem.
    pub(super) half_of: Option<Z2Symmetry>,
    /// Every discretisation the problem has been on (the revisions of
    /// [`ContinuationProblem::discretisation_revision`]); `disc` is `revisions[current]`.
    pub(super) revisions: Vec<Discretisation>,
    pub(super) current: usize,
    /// Whether the problem is the plain orbit problem, which can be rebuilt on another mesh
    /// (not one wrapped or extended for a two-parameter curve).
    pub(super) adaptable: bool,
    /// Whether a run's start must be admissible ([`OrbitContinuation::require_admissible`]).
    pub(super) admissible_start: bool,
}

impl<S: ?Sized> std::fmt::Debug for OrbitContinuation<'_, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OrbitContinuation")
            .field("problem", &self.problem)
            .field("param", &self.param)
            .field("half_orbit", &self.half_of.is_some())
            .finish_non_exhaustive()
    }
}

/// Checks a parameter handle against the system.
pub(crate) fn check_parameter<S: hycont_core::HybridSystem + ?Sized>(
    system: &S,
    p: ParamId,
) -> Result<()> {
    let count = system.parameter_count();
    if p.index() < count {
        Ok(())
    } else {
        Err(Error::NoSuchQuantity {
            quantity: Quantity::Parameter(p),
            count,
        })
    }
}

impl<'a, S: HybridJacobians + ?Sized> OrbitContinuation<'a, S> {
    /// The continuation problem of `orbit` (a solution, or a good guess: shooting solves it in
    /// the first step, collocation solves it first and adapts its mesh) in `parameter`, and the
    /// starting unknowns. A half orbit ([`PeriodicOrbit::half_of_symmetric`]) gives the
    /// half-orbit problem of its symmetric orbits.
    ///
    /// # Errors
    /// A parameter the system does not have; an orbit that is not finite or does not match the
    /// system; a collocation solve that fails; a half orbit of a system without a symmetry.
    pub fn new(
        system: &'a S,
        orbit: &PeriodicOrbit,
        method: &OrbitMethod,
        parameter: ParamId,
        measures: SharedMeasures<'a, S>,
        events: Vec<MonitorEvent>,
    ) -> Result<(Self, Vec<f64>)> {
        check_parameter(system, parameter)?;
        let (disc, like, base) = Discretisation::prepare(method, system, orbit)?;
        let cp = Self::on_discretisation(system, like, disc, parameter, measures, events)?;
        let u0 = cp.problem.initial_unknowns(&base);
        Ok((cp, u0))
    }

    /// The problem on an existing discretisation (no solve): orbits like `like` (its
    /// signature; a half orbit gives the half-orbit problem), e.g. to restart from or switch at
    /// a point of a saved branch.
    ///
    /// # Errors
    /// As [`OrbitContinuation::new`].
    pub fn on_discretisation(
        system: &'a S,
        like: PeriodicOrbit,
        disc: Discretisation,
        parameter: ParamId,
        measures: SharedMeasures<'a, S>,
        events: Vec<MonitorEvent>,
    ) -> Result<Self> {
        let mut cp = Self::build(
            system,
            like,
            disc,
            parameter,
            measures,
            events,
            Box::new(|eq| Ok(eq)),
        )?;
        cp.adaptable = true;
        Ok(cp)
    }

    /// [`OrbitContinuation::on_discretisation`] with the orbit equations wrapped by `wrap`.
    pub(crate) fn build(
        system: &'a S,
        like: PeriodicOrbit,
        disc: Discretisation,
        parameter: ParamId,
        measures: SharedMeasures<'a, S>,
        events: Vec<MonitorEvent>,
        wrap: WrapPart<'a>,
    ) -> Result<Self> {
        check_parameter(system, parameter)?;
        like.validate(system)?;
        let half_of = match like.signature.closure() {
            Closure::Periodic => None,
            // A half orbit's symmetry is checked at its segment starts before it is used.
            Closure::Symmetric => Some(like.symmetry_at_starts(system)?),
        };
        let cache = matches!(disc, Discretisation::Shooting(_)).then(LinearizationCache::default);
        let eq = disc.equations(system, &like, cache.clone())?;
        let first = eq.first_parameter();
        let mut problem = orbit_problem(system, wrap(eq)?, first, &like.params)?;
        let q = parameter.index();
        let id = problem
            .monitor_id(system.parameter_names()[q])
            .ok_or_else(|| Error::SwitchFailed {
                reason: format!("no monitor for parameter #{q}"),
            })?;
        problem.set_activity(id, Activity::Active(like.params[q]))?;
        Ok(Self {
            system,
            like,
            revisions: vec![disc.clone()],
            current: 0,
            adaptable: false,
            disc,
            cache,
            problem,
            param: q,
            slot_from_end: 0,
            collapsed: None,
            measures,
            events,
            half_of,
            admissible_start: false,
        })
    }

    /// Whether runs of this problem refuse a start whose orbit is not admissible (default: no;
    /// [`crate::OrbitRun`] turns it on with its admissibility): the corrected start is checked
    /// by [`hycont_core::orbit::check_admissible`] (a segment held collapsed on a grazing curve
    /// may have zero duration), and a violation is [`Error::InadmissibleStart`].
    pub fn require_admissible(&mut self, on: bool) -> &mut Self {
        self.admissible_start = on;
        self
    }

    /// Whether the problem's orbits are checked at a run's start
    /// ([`OrbitContinuation::require_admissible`]).
    #[must_use]
    pub fn requires_admissible(&self) -> bool {
        self.admissible_start
    }

    /// The number of unknowns of the problem (with its active parameters).
    #[must_use]
    pub(crate) fn unknowns(&self) -> usize {
        self.problem.unknowns()
    }

    /// The zero problem (e.g. to add parts for two-parameter curves; the problem then keeps
    /// its discretisation along a run).
    pub fn problem_mut(&mut self) -> &mut Problem<'a> {
        self.adaptable = false;
        &mut self.problem
    }

    /// Records that a second parameter's monitor was made active; `continued_is_last` is true
    /// when the continued parameter's slot comes last (its index is the higher one).
    pub(crate) fn set_second_parameter(&mut self, continued_is_last: bool) {
        self.adaptable = false;
        self.slot_from_end = usize::from(!continued_is_last);
    }

    /// Leaves segment `k` out of the shortest-segment monitor (its duration is held at zero).
    pub(crate) fn set_collapsed(&mut self, k: usize) {
        self.adaptable = false;
        self.collapsed = Some(k);
    }

    /// The orbit at unknowns `u` (on a half-orbit problem, the half orbit).
    #[must_use]
    pub fn orbit(&self, u: &[f64]) -> PeriodicOrbit {
        self.disc.unpack(&self.like, u)
    }

    /// Whether this is a half-orbit problem (started from a [`Closure::Symmetric`] orbit).
    #[must_use]
    pub fn is_half_orbit(&self) -> bool {
        self.half_of.is_some()
    }

    /// The continued parameter.
    #[must_use]
    pub fn parameter(&self) -> ParamId {
        ParamId(self.param)
    }

    /// The discretisation (of the half orbit, on a half-orbit problem).
    #[must_use]
    pub fn discretisation(&self) -> &Discretisation {
        &self.disc
    }

    /// The orbit whose signature the problem's orbits have (its values are the start's).
    #[must_use]
    pub fn template(&self) -> &PeriodicOrbit {
        &self.like
    }

    /// The measures.
    #[must_use]
    pub fn measures(&self) -> &SharedMeasures<'a, S> {
        &self.measures
    }

    /// The template and discretisation of the full orbits of this problem's orbits (this
    /// problem's own when it is not a half-orbit problem).
    ///
    /// # Errors
    /// If the half orbit cannot be unfolded.
    pub fn full_layout(&self) -> Result<(PeriodicOrbit, Discretisation)> {
        if self.half_of.is_some() {
            Ok((
                self.like.unfold_symmetric(self.system)?,
                self.disc.repeated(2),
            ))
        } else {
            Ok((self.like.clone(), self.disc.clone()))
        }
    }

    /// The problem of the full orbits of this half-orbit problem, with the same parameter,
    /// measures, events and discretisation (each segment's mesh twice); its points are those
    /// of [`OrbitContinuation::full_branch`]. Branches are switched on it (at a branch point
    /// where the symmetry breaks, [`crate::branch_switch_direction`]). For a problem that is
    /// not a half-orbit problem: a fresh one-parameter copy.
    ///
    /// # Errors
    /// If the problem cannot be built.
    pub fn full_orbit_problem(&self) -> Result<Self> {
        self.full_orbit_problem_at(self.current)
    }

    /// [`OrbitContinuation::full_orbit_problem`] on the discretisation of `point` (a point of
    /// a branch of this problem; a run that adapted its mesh has points on several), whose
    /// [`OrbitContinuation::full_point`] solves it.
    ///
    /// # Errors
    /// As [`OrbitContinuation::full_orbit_problem`]; a point of another problem (a revision
    /// this one does not have).
    pub fn full_orbit_problem_of(&self, point: &BranchPoint) -> Result<Self> {
        self.full_orbit_problem_at(point.discretisation)
    }

    /// A point of a branch of this problem with the unknowns and tangent of the full orbit's
    /// problem ([`OrbitContinuation::full_orbit_problem`]): on a half-orbit problem the
    /// segments followed by their images (the tangent renormalised); otherwise a copy.
    #[must_use]
    pub fn full_point(&self, point: &BranchPoint) -> BranchPoint {
        let mut p = point.clone();
        self.to_full(&mut p);
        p
    }

    /// [`OrbitContinuation::full_point`] in place.
    fn to_full(&self, point: &mut BranchPoint) {
        let Some(sym) = &self.half_of else {
            return;
        };
        let disc = self.revision(point.discretisation);
        let mut t = disc.repeat_unknowns(&self.like, &point.tangent, Some(sym));
        normalize(&mut t);
        point.tangent = t;
        point.u = disc.repeat_unknowns(&self.like, &point.u, Some(sym));
    }

    /// A branch of this problem with every point (special points included) in the unknowns of
    /// the full orbit's problem (see [`OrbitContinuation::full_point`]).
    #[must_use]
    pub fn full_branch(&self, branch: &Branch) -> Branch {
        self.into_full_branch(branch.clone())
    }

    /// [`OrbitContinuation::full_branch`] of a branch given away (its points converted in
    /// place, without copies).
    #[must_use]
    pub fn into_full_branch(&self, mut branch: Branch) -> Branch {
        for p in &mut branch.points {
            self.to_full(p);
        }
        for s in &mut branch.special_points {
            self.to_full(&mut s.point);
        }
        branch
    }

    /// The continuation problem of the period-doubled orbit at a located period-doubling point
    /// of a branch of this problem: the starting unknowns (the orbit traversed twice) and the
    /// direction of the period-2 branch (the doubled problem has a branch point there).
    ///
    /// # Errors
    /// [`Error::SwitchFailed`] if `point` is not a period doubling of this problem, or this is a
    /// half-orbit problem (switch on [`OrbitContinuation::full_orbit_problem`]).
    pub fn from_period_doubling(&self, point: &BranchPoint) -> Result<(Self, Vec<f64>, Vec<f64>)> {
        if self.half_of.is_some() {
            return Err(Error::SwitchFailed {
                reason: "period doubling on a half-orbit problem: switch on its full_orbit_problem"
                    .into(),
            });
        }
        let disc = self.revision(point.discretisation);
        let mut doubled = Self::on_discretisation(
            self.system,
            disc.unpack(&self.like, &point.u).doubled(),
            disc.repeated(2),
            ParamId(self.param),
            self.measures.clone(),
            self.events.clone(),
        )?;
        doubled.admissible_start = self.admissible_start;
        let u0 = disc.repeat_unknowns(&self.like, &point.u, None);
        let mut t = disc.repeat_unknowns(&self.like, &point.tangent, None);
        normalize(&mut t);
        let phi = branch_switch_direction(&mut doubled, &u0, &t)?;
        Ok((doubled, u0, phi))
    }

    /// The point's parameters, monitors and multipliers (the full orbit's on a half orbit).
    fn info(&mut self, orbit: &PeriodicOrbit, floquet: Floquet) -> hycont_core::Result<PointInfo> {
        let shortest = orbit
            .durations
            .iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != self.collapsed)
            .map(|(_, d)| *d)
            .fold(f64::INFINITY, f64::min);
        // On a half orbit: the full orbit's multipliers and period, and the half map's
        // symmetry-breaking factor.
        let (floquet, period, branch_point_factor) = if self.half_of.is_some() {
            let (half, full) = symmetric_floquet(self.system, orbit, &floquet.monodromy)?;
            let factor = crate::shifted_product(&half.multipliers, &half.trivial, 1.0);
            (full, 2.0 * orbit.period(), Some(factor))
        } else {
            (floquet, orbit.period(), None)
        };
        let mut monitors = vec![period, shortest];
        monitors.extend(self.measures.evaluate(self.system, orbit)?);
        Ok(PointInfo {
            params: orbit.params.clone(),
            monitors,
            multipliers: floquet.multipliers,
            trivial: floquet.trivial,
            branch_point_factor,
            discretisation_error: None,
        })
    }
}

impl<S: HybridJacobians + ?Sized> OrbitContinuation<'_, S> {
    /// `info` with the discretisation's error estimate at `u`.
    fn with_error_estimate(&self, mut info: PointInfo, u: &[f64]) -> PointInfo {
        info.discretisation_error = self.disc.error_estimate(&self.like, u);
        info
    }
}

/// `t` scaled to unit Euclidean norm (the norm in four interleaved partial sums: a full
/// orbit's tangent has thousands of entries).
fn normalize(t: &mut [f64]) {
    let norm = crate::palc::dot(t, t).sqrt();
    if norm > 0.0 {
        t.iter_mut().for_each(|x| *x /= norm);
    }
}

impl<'a, S: HybridJacobians + ?Sized> ContinuationProblem<'a> for OrbitContinuation<'a, S> {
    fn problem(&mut self) -> &mut Problem<'a> {
        &mut self.problem
    }
    fn parameter_index(&self) -> usize {
        // Active monitors' values are the last unknowns, in monitor (parameter) order.
        self.problem.unknowns() - 1 - self.slot_from_end
    }
    fn parameter_position(&self) -> usize {
        self.param
    }
    fn parameter_name(&self) -> String {
        self.system.parameter_names()[self.param].to_string()
    }
    fn parameter_names(&self) -> Vec<String> {
        self.system
            .parameter_names()
            .iter()
            .map(ToString::to_string)
            .collect()
    }
    fn monitor_names(&self) -> Vec<String> {
        let mut names = vec!["period".to_string(), "shortest_segment".to_string()];
        names.extend(self.measures.names().iter().cloned());
        names
    }
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        let (orbit, floquet) =
            self.disc
                .floquet(self.system, &self.like, u, self.cache.as_ref())?;
        let info = self.info(&orbit, floquet)?;
        Ok(self.with_error_estimate(info, u))
    }
    fn analyse_afresh(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        let (orbit, floquet) = self.disc.floquet(self.system, &self.like, u, None)?;
        let info = self.info(&orbit, floquet)?;
        Ok(self.with_error_estimate(info, u))
    }
    /// Collocation reads the multipliers off the factorisation's condensed intervals.
    fn analyse_factorised(
        &mut self,
        u: &[f64],
        jacobian: &hycont_core::linalg::SparsePattern,
    ) -> hycont_core::Result<PointInfo> {
        match self
            .disc
            .floquet_factorised(self.system, &self.like, u, jacobian)?
        {
            Some((orbit, floquet)) => {
                let info = self.info(&orbit, floquet)?;
                Ok(self.with_error_estimate(info, u))
            }
            None => self.analyse(u),
        }
    }
    /// Collocation: each segment's node values weigh `1 / nodes` (the segment's mean square,
    /// as AUTO's $L_2$ norm, independent of the mesh); shooting's few segment starts, the
    /// durations and the parameters weigh 1. On a half-orbit problem the segments' values and
    /// durations weigh twice that (they stand for the full orbit's, which has them twice), so
    /// that arclength, and with it the steps, are those of the full orbit's problem.
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        let copies = if self.half_of.is_some() { 2.0 } else { 1.0 };
        self.disc
            .unknown_weights(&self.like, copies, self.problem.unknowns())
    }
    /// Collocation (a one-parameter problem): meshes equidistributing the error estimate, with
    /// more intervals where it exceeds `tolerance`
    /// ([`hycont_core::orbit::Discretisation::refined`]); kept when their size is the same and
    /// no mesh point would move by more than a tenth of the smallest interval.
    fn rediscretise(
        &mut self,
        u: &[f64],
        t: &[f64],
        tolerance: f64,
    ) -> Result<Option<crate::Rediscretised>> {
        self.adapt_mesh(u, t, tolerance)
    }
    fn discretisation_revision(&self) -> usize {
        self.current
    }
    /// By collocation (see [`ContinuationProblem::chord_steps`]).
    fn chord_steps(&self) -> bool {
        matches!(self.disc, Discretisation::Collocation { .. })
    }
    fn restore_discretisation(&mut self, revision: usize) -> Result<bool> {
        self.restore(revision)
    }
    fn check_start(&mut self, u: &[f64]) -> Result<()> {
        if !self.admissible_start {
            return Ok(());
        }
        let orbit = self.orbit(u);
        let collapsed: Vec<usize> = self.collapsed.into_iter().collect();
        match check_admissible_collapsed(self.system, &orbit, &collapsed) {
            Err(hycont_core::Error::Inadmissible {
                segment,
                event,
                violation,
                t,
                value,
            }) => Err(Error::InadmissibleStart {
                segment,
                event,
                violation,
                t,
                value,
            }),
            other => Ok(other?),
        }
    }
    /// The run's events, then the collapse of any segment (a grazing of the shortest
    /// segment's duration; [`ContinuationProblem::end_among`] says when it ends the run).
    fn monitor_events(&self) -> Vec<MonitorEvent> {
        let mut events = self.events.clone();
        events.push(MonitorEvent {
            kind: SpecialKind::Grazing,
            on: Quantity::Measure(MeasureId::SHORTEST_SEGMENT),
            level: 0.0,
            terminal: true,
        });
        events
    }
    /// At a collapsed segment the run's domain margin vanishes with the collapse (its
    /// conditions include the durations). Where the segment's flow meets its end's surface
    /// tangentially (two events merging at zero speed) the collapse is a grazing and its GR
    /// ends the run; else the run's events by precedence (a segment collapsing across another
    /// event's surface: the domain margin's DB).
    fn end_among(&mut self, u: &[f64], located: &[MonitorEvent]) -> usize {
        let collapse = Quantity::Measure(MeasureId::SHORTEST_SEGMENT);
        let Some(i) = located.iter().position(|e| e.on == collapse) else {
            return 0;
        };
        let orbit = self.orbit(u);
        match super::collapse::collapsed_segment(&orbit) {
            Some(k) if super::collapse::collapses_tangentially(self.system, &orbit, k) => i,
            _ => 0,
        }
    }
}

/// Whether a special-point kind is one at which branches can be switched.
#[must_use]
pub fn can_switch(kind: SpecialKind) -> bool {
    matches!(kind, SpecialKind::BranchPoint | SpecialKind::PeriodDoubling)
}
