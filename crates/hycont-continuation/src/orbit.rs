//! Continuation of hybrid periodic orbits: the shooting or collocation problem of a
//! [`PeriodicOrbit`] with one parameter released, analysed at every point (Floquet multipliers,
//! period, user measures), with branch switching at period doublings.
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
use crate::switch::branch_switch_direction;
use crate::{ContinuationProblem, MonitorEvent, PointInfo};
use hycont_core::orbit::{
    Closure, CollocationSettings, LinearizationCache, Mesh, PeriodicOrbit, ShootingSettings,
    collocation_floquet, collocation_problem, collocation_unpack, monodromy_by_shooting,
    monodromy_from_cache, pack, shooting_problem_cached, solve_collocation, symmetric_floquet,
    unpack,
};
use hycont_core::problem::{Activity, NewtonSettings, Problem};
use hycont_core::{HybridJacobians, ParamId, Z2Symmetry};

/// How the orbit's boundary-value problem is discretised.
#[derive(Debug, Clone, PartialEq)]
pub enum OrbitMethod {
    /// Multiple shooting.
    Shooting(ShootingSettings),
    /// Orthogonal collocation (the mesh is adapted once at the start and then kept).
    Collocation(CollocationSettings),
}

#[derive(Debug, Clone)]
enum Layout {
    Shooting(ShootingSettings, LinearizationCache),
    Collocation { meshes: Vec<Mesh>, ncol: usize },
}

/// A function computing measures of an orbit (of the half orbit, on a half-orbit problem).
pub type MeasureFn<'a> = Box<dyn FnMut(&PeriodicOrbit) -> Vec<f64> + 'a>;

/// Measures recorded at every point: a function of the orbit, with names.
///
/// On a half-orbit problem the function receives the half orbit ([`Closure::Symmetric`]): a
/// measure invariant under the symmetry (an amplitude, a margin to an impact surface that
/// the symmetry maps to another) has the full orbit's value there; others can unfold it
/// ([`PeriodicOrbit::unfold_symmetric`]).
pub struct Measures<'a> {
    /// Names of the values, in order.
    pub names: Vec<String>,
    /// The values.
    pub compute: MeasureFn<'a>,
}

impl std::fmt::Debug for Measures<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Measures")
            .field("names", &self.names)
            .finish_non_exhaustive()
    }
}

impl Default for Measures<'_> {
    fn default() -> Self {
        Self {
            names: Vec::new(),
            compute: Box::new(|_| Vec::new()),
        }
    }
}

/// A hybrid periodic orbit to be continued in one parameter.
///
/// Monitors reported at each point: `period` (index 0), `min_duration` (index 1, the shortest
/// segment's duration), then the [`Measures`] (from index 2). Events passed to
/// [`OrbitContinuation::new`] index this list. Admissibility is built in: when a segment's
/// duration reaches zero the orbit's signature no longer describes it (for impacting systems:
/// an extremum or a flight touches the impact surface, a grazing), so a terminal
/// [`SpecialKind::Grazing`] event on `min_duration` ends the branch there, located.
///
/// Started from a half orbit ([`Closure::Symmetric`]) it continues symmetric orbits on the
/// half-orbit problem (see the [module documentation](self)); `period` is the full period.
pub struct OrbitContinuation<'a, S: ?Sized> {
    system: &'a S,
    like: PeriodicOrbit,
    layout: Layout,
    problem: Problem<'a>,
    param: usize,
    /// Position from the end of the unknowns of the continuation parameter's slot (0: last).
    slot_from_end: usize,
    /// A segment left out of `min_duration` (held at zero on a grazing curve).
    collapsed: Option<usize>,
    measures: Measures<'a>,
    events: Vec<MonitorEvent>,
    /// The symmetry, on a half-orbit problem.
    half_of: Option<Z2Symmetry>,
}

impl<S: ?Sized> std::fmt::Debug for OrbitContinuation<'_, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OrbitContinuation")
            .field("problem", &self.problem)
            .field("param", &self.param)
            .finish_non_exhaustive()
    }
}

impl<'a, S: HybridJacobians + ?Sized> OrbitContinuation<'a, S> {
    /// The continuation problem of `orbit` (a solution, or a good guess: it is solved first)
    /// in parameter `parameter`, and the starting unknowns. A half orbit
    /// ([`PeriodicOrbit::half_of_symmetric`]) gives the half-orbit problem of its symmetric
    /// orbits.
    ///
    /// # Errors
    /// If the orbit cannot be solved or the problem cannot be built; a half orbit of a system
    /// without a symmetry.
    pub fn new(
        system: &'a S,
        orbit: &PeriodicOrbit,
        method: &OrbitMethod,
        parameter: ParamId,
        measures: Measures<'a>,
        events: Vec<MonitorEvent>,
    ) -> Result<(Self, Vec<f64>)> {
        let q = parameter.index();
        let half_of = match orbit.signature.closure() {
            Closure::Periodic => None,
            Closure::Symmetric => {
                Some(
                    system
                        .symmetry()
                        .ok_or_else(|| hycont_core::Error::InvalidSignature {
                            segment: 0,
                            reason:
                                "a half orbit (symmetric closure) needs a system with a symmetry"
                                    .into(),
                        })?,
                )
            }
        };
        let (mut problem, base, layout, like) = match method {
            OrbitMethod::Shooting(settings) => {
                let cache = LinearizationCache::default();
                let problem = shooting_problem_cached(system, orbit, *settings, cache.clone())?;
                (
                    problem,
                    pack(orbit),
                    Layout::Shooting(*settings, cache),
                    orbit.clone(),
                )
            }
            OrbitMethod::Collocation(settings) => {
                let sol = solve_collocation(system, orbit, *settings, &NewtonSettings::default())?;
                let problem = collocation_problem(
                    system,
                    &sol.solution.orbit,
                    sol.meshes.clone(),
                    settings.ncol,
                )?;
                let base = sol.unknowns();
                (
                    problem,
                    base,
                    Layout::Collocation {
                        meshes: sol.meshes,
                        ncol: settings.ncol,
                    },
                    sol.solution.orbit,
                )
            }
        };
        let name = system.parameter_names()[q];
        let id = problem
            .monitor_id(name)
            .ok_or_else(|| Error::SwitchFailed {
                reason: format!("no monitor for parameter {name}"),
            })?;
        problem.set_activity(id, Activity::Active(like.params[q]));
        let u0 = problem.initial_unknowns(&base);
        Ok((
            Self {
                system,
                like,
                layout,
                problem,
                param: q,
                slot_from_end: 0,
                collapsed: None,
                measures,
                events,
                half_of,
            },
            u0,
        ))
    }

    /// The zero problem (e.g. to add parts for two-parameter curves).
    pub fn problem_mut(&mut self) -> &mut Problem<'a> {
        &mut self.problem
    }

    /// Records that a second parameter's monitor was made active; `after` is true when its slot
    /// comes after the continuation parameter's (it has a lower index, so its monitor is first).
    pub(crate) fn set_second_parameter(&mut self, _second: ParamId, continued_is_last: bool) {
        self.slot_from_end = usize::from(!continued_is_last);
    }

    /// Leaves segment `k` out of the `min_duration` monitor (its duration is held at zero).
    pub(crate) fn set_collapsed(&mut self, k: usize) {
        self.collapsed = Some(k);
    }

    /// The orbit at unknowns `u` (on a half-orbit problem, the half orbit).
    #[must_use]
    pub fn orbit(&self, u: &[f64]) -> PeriodicOrbit {
        match &self.layout {
            Layout::Shooting(..) => unpack(&self.like, u),
            Layout::Collocation { meshes, ncol } => {
                collocation_unpack(&self.like, meshes, *ncol, u).1
            }
        }
    }

    /// Whether this is a half-orbit problem (started from a [`Closure::Symmetric`] orbit).
    #[must_use]
    pub fn is_half_orbit(&self) -> bool {
        self.half_of.is_some()
    }

    /// The number of unknowns holding segment states (shooting: the starts; collocation: the
    /// node values), which come first.
    fn segment_values(&self) -> usize {
        let n = self.like.starts[0].len();
        match &self.layout {
            Layout::Shooting(..) => self.like.segment_count() * n,
            Layout::Collocation { meshes, ncol } => {
                meshes.iter().map(|m| ((m.len() - 1) * ncol + 1) * n).sum()
            }
        }
    }

    /// Unknowns (or a tangent) `v` of this problem with the segments repeated: the segment
    /// states followed by their images under `image` (applied to each state), the durations
    /// twice, then the rest.
    fn repeat_segments(&self, v: &[f64], image: Option<&Z2Symmetry>) -> Vec<f64> {
        let n = self.like.starts[0].len();
        let (nv, kk) = (self.segment_values(), self.like.segment_count());
        let mut out = Vec::with_capacity(v.len() + nv + kk);
        out.extend_from_slice(&v[..nv]);
        match image {
            Some(sym) => {
                let mut y = vec![0.0; n];
                for x in v[..nv].chunks_exact(n) {
                    sym.apply(x, &mut y);
                    out.extend_from_slice(&y);
                }
            }
            None => out.extend_from_slice(&v[..nv]),
        }
        out.extend_from_slice(&v[nv..nv + kk]);
        out.extend_from_slice(&v[nv..nv + kk]);
        out.extend_from_slice(&v[nv + kk..]);
        out
    }

    /// The one-parameter problem of `orbit` in the same parameter, with the same events and
    /// `measures`, on this problem's discretisation with every segment's mesh repeated
    /// `copies` times (`orbit` has this problem's segments that many times).
    fn rebuilt(&self, orbit: PeriodicOrbit, copies: usize, measures: Measures<'a>) -> Result<Self> {
        let (problem, layout) = match &self.layout {
            Layout::Shooting(s, _) => {
                let cache = LinearizationCache::default();
                (
                    shooting_problem_cached(self.system, &orbit, *s, cache.clone())?,
                    Layout::Shooting(*s, cache),
                )
            }
            Layout::Collocation { meshes, ncol } => {
                let all: Vec<Mesh> = (0..copies).flat_map(|_| meshes.iter().cloned()).collect();
                (
                    collocation_problem(self.system, &orbit, all.clone(), *ncol)?,
                    Layout::Collocation {
                        meshes: all,
                        ncol: *ncol,
                    },
                )
            }
        };
        let mut out = Self {
            system: self.system,
            like: orbit,
            layout,
            problem,
            param: self.param,
            slot_from_end: 0,
            collapsed: None,
            measures,
            events: self.events.clone(),
            half_of: None,
        };
        let name = self.system.parameter_names()[self.param];
        let id = out
            .problem
            .monitor_id(name)
            .ok_or_else(|| Error::SwitchFailed {
                reason: format!("no monitor for parameter {name}"),
            })?;
        out.problem
            .set_activity(id, Activity::Active(out.like.params[self.param]));
        Ok(out)
    }

    /// The problem of the full orbits of this half-orbit problem, with `measures`: the same
    /// parameter, events and discretisation (each segment's mesh twice); its points are those
    /// of [`OrbitContinuation::full_branch`]. Branches are switched on it (at a branch point
    /// where the symmetry breaks, [`crate::branch_switch_direction`]). For a problem that is
    /// not a half-orbit problem: a fresh one-parameter copy.
    ///
    /// # Errors
    /// If the problem cannot be built.
    pub fn full_orbit_problem(&self, measures: Measures<'a>) -> Result<Self> {
        if self.half_of.is_some() {
            let full = self.like.unfold_symmetric(self.system)?;
            self.rebuilt(full, 2, measures)
        } else {
            self.rebuilt(self.like.clone(), 1, measures)
        }
    }

    /// A point of a branch of this problem with the unknowns and tangent of the full orbit's
    /// problem ([`OrbitContinuation::full_orbit_problem`]): on a half-orbit problem the
    /// segments followed by their images (the tangent renormalised); otherwise a copy.
    #[must_use]
    pub fn full_point(&self, point: &BranchPoint) -> BranchPoint {
        let Some(sym) = &self.half_of else {
            return point.clone();
        };
        let mut t = self.repeat_segments(&point.tangent, Some(sym));
        let norm = t.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.0 {
            t.iter_mut().for_each(|x| *x /= norm);
        }
        BranchPoint {
            u: self.repeat_segments(&point.u, Some(sym)),
            tangent: t,
            ..point.clone()
        }
    }

    /// A branch of this problem with every point (special points included) in the unknowns of
    /// the full orbit's problem (see [`OrbitContinuation::full_point`]).
    #[must_use]
    pub fn full_branch(&self, branch: &Branch) -> Branch {
        let mut out = branch.clone();
        if self.half_of.is_some() {
            for p in &mut out.points {
                *p = self.full_point(p);
            }
            for s in &mut out.special_points {
                s.point = self.full_point(&s.point);
            }
        }
        out
    }

    /// The continuation problem of the period-doubled orbit at a located period-doubling point
    /// of a branch of this problem: the starting unknowns (the orbit traversed twice) and the
    /// direction of the period-2 branch (the doubled problem has a branch point there).
    ///
    /// # Errors
    /// [`Error::SwitchFailed`] if `point` is not a period doubling of this problem, or this is a
    /// half-orbit problem (switch on [`OrbitContinuation::full_orbit_problem`]).
    pub fn from_period_doubling(
        &self,
        point: &BranchPoint,
        measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>, Vec<f64>)> {
        if self.half_of.is_some() {
            return Err(Error::SwitchFailed {
                reason: "period doubling on a half-orbit problem: switch on its full_orbit_problem"
                    .into(),
            });
        }
        let orbit = self.orbit(&point.u).doubled();
        let mut doubled = self.rebuilt(orbit, 2, measures)?;
        let u0 = self.repeat_segments(&point.u, None);
        let mut t = self.repeat_segments(&point.tangent, None);
        let norm = t.iter().map(|x| x * x).sum::<f64>().sqrt();
        t.iter_mut().for_each(|x| *x /= norm);
        let phi = branch_switch_direction(&mut doubled, &u0, &t)?;
        Ok((doubled, u0, phi))
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
        let mut names = vec!["period".to_string(), "min_duration".to_string()];
        names.extend(self.measures.names.iter().cloned());
        names
    }
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        let (orbit, floquet) = match &self.layout {
            Layout::Shooting(s, cache) => {
                let orbit = unpack(&self.like, u);
                // The corrector's last Jacobian evaluation was at this point: reuse its flows.
                let f = match monodromy_from_cache(self.system, &orbit, cache)? {
                    Some(f) => f,
                    None => monodromy_by_shooting(self.system, &orbit, *s)?,
                };
                (orbit, f)
            }
            Layout::Collocation { meshes, ncol } => {
                let (nodes, orbit) = collocation_unpack(&self.like, meshes, *ncol, u);
                let f = collocation_floquet(self.system, &orbit, meshes, &nodes, *ncol)?;
                (orbit, f)
            }
        };
        let min_duration = orbit
            .durations
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        // On a half orbit: the full orbit's multipliers and period, and the half map's
        // symmetry-breaking factor.
        let (floquet, period, branch_point_factor) = if self.half_of.is_some() {
            let (half, full) = symmetric_floquet(self.system, &orbit, &floquet.monodromy)?;
            let factor = crate::shifted_product(&half.multipliers, &half.trivial, 1.0);
            (full, 2.0 * orbit.period(), Some(factor))
        } else {
            (floquet, orbit.period(), None)
        };
        let mut monitors = vec![period, min_duration];
        monitors.extend((self.measures.compute)(&orbit));
        Ok(PointInfo {
            params: orbit.params.clone(),
            monitors,
            multipliers: floquet.multipliers,
            trivial: floquet.trivial,
            branch_point_factor,
        })
    }
    /// Collocation: each segment's node values weigh `1 / nodes` (the segment's mean square,
    /// as AUTO's $L_2$ norm, independent of the mesh); shooting's few segment starts, the
    /// durations and the parameters weigh 1. On a half-orbit problem the segments' values and
    /// durations weigh twice that (they stand for the full orbit's, which has them twice), so
    /// that arclength, and with it the steps, are those of the full orbit's problem.
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        let copies = if self.half_of.is_some() { 2.0 } else { 1.0 };
        let n = self.like.starts[0].len();
        let mut w = Vec::with_capacity(self.problem.unknowns());
        match &self.layout {
            Layout::Shooting(..) if self.half_of.is_none() => return None,
            Layout::Shooting(..) => w.resize(self.segment_values(), copies),
            Layout::Collocation { meshes, ncol } => {
                for m in meshes {
                    let nodes = (m.len() - 1) * ncol + 1;
                    w.extend(std::iter::repeat_n(copies / nodes as f64, nodes * n));
                }
            }
        }
        w.extend(std::iter::repeat_n(copies, self.like.segment_count()));
        w.resize(self.problem.unknowns(), 1.0);
        Some(w)
    }
    fn monitor_events(&self) -> Vec<MonitorEvent> {
        let mut events = vec![MonitorEvent {
            kind: SpecialKind::Grazing,
            monitor: 1,
            level: 0.0,
            terminal: true,
        }];
        events.extend(self.events.iter().copied());
        events
    }
}

/// Whether a special-point kind is one at which this module can switch branches.
#[must_use]
pub fn can_switch(kind: SpecialKind) -> bool {
    matches!(kind, SpecialKind::BranchPoint | SpecialKind::PeriodDoubling)
}
