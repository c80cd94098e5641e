//! Continuation of hybrid periodic orbits: the shooting or collocation problem of a
//! [`PeriodicOrbit`] with one parameter released, analysed at every point (Floquet multipliers,
//! period, user measures), with branch switching at period doublings.

use crate::branch::{BranchPoint, SpecialKind};
use crate::error::{Error, Result};
use crate::switch::branch_switch_direction;
use crate::{ContinuationProblem, MonitorEvent, PointInfo};
use hycont_core::orbit::{
    CollocationSettings, LinearizationCache, Mesh, PeriodicOrbit, ShootingSettings,
    collocation_floquet, collocation_problem, collocation_unpack, monodromy_by_shooting,
    monodromy_from_cache, pack, shooting_problem_cached, solve_collocation, unpack,
};
use hycont_core::problem::{Activity, NewtonSettings, Problem};
use hycont_core::{HybridJacobians, ParamId};

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

/// A function computing measures of an orbit.
pub type MeasureFn<'a> = Box<dyn FnMut(&PeriodicOrbit) -> Vec<f64> + 'a>;

/// Measures recorded at every point: a function of the orbit, with names.
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
    /// in parameter `parameter`, and the starting unknowns.
    ///
    /// # Errors
    /// If the orbit cannot be solved or the problem cannot be built.
    pub fn new(
        system: &'a S,
        orbit: &PeriodicOrbit,
        method: &OrbitMethod,
        parameter: ParamId,
        measures: Measures<'a>,
        events: Vec<MonitorEvent>,
    ) -> Result<(Self, Vec<f64>)> {
        let q = parameter.index();
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

    /// The orbit at unknowns `u`.
    #[must_use]
    pub fn orbit(&self, u: &[f64]) -> PeriodicOrbit {
        match &self.layout {
            Layout::Shooting(..) => unpack(&self.like, u),
            Layout::Collocation { meshes, ncol } => {
                collocation_unpack(&self.like, meshes, *ncol, u).1
            }
        }
    }

    /// The continuation problem of the period-doubled orbit at a located period-doubling point
    /// of a branch of this problem: the starting unknowns (the orbit traversed twice) and the
    /// direction of the period-2 branch (the doubled problem has a branch point there).
    ///
    /// # Errors
    /// [`Error::SwitchFailed`] if `point` is not a period doubling of this problem.
    pub fn from_period_doubling(
        &self,
        point: &BranchPoint,
        measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>, Vec<f64>)> {
        let kk = self.like.segment_count();
        let double = |v: &[f64]| -> Vec<f64> {
            // [segment blocks..., durations (K), params..., active slot] -> doubled.
            let n_seg_vals = match &self.layout {
                Layout::Shooting(..) => kk * self.like.starts[0].len(),
                Layout::Collocation { meshes, ncol } => meshes
                    .iter()
                    .map(|m| ((m.len() - 1) * ncol + 1) * self.like.starts[0].len())
                    .sum(),
            };
            let mut out = v[..n_seg_vals].to_vec();
            out.extend_from_slice(&v[..n_seg_vals]);
            out.extend_from_slice(&v[n_seg_vals..n_seg_vals + kk]);
            out.extend_from_slice(&v[n_seg_vals..n_seg_vals + kk]);
            out.extend_from_slice(&v[n_seg_vals + kk..]);
            out
        };
        let orbit = self.orbit(&point.u).doubled();
        let (problem, layout) = match &self.layout {
            Layout::Shooting(s, _) => {
                let cache = LinearizationCache::default();
                (
                    shooting_problem_cached(self.system, &orbit, *s, cache.clone())?,
                    Layout::Shooting(*s, cache),
                )
            }
            Layout::Collocation { meshes, ncol } => {
                let mut m2 = meshes.clone();
                m2.extend(meshes.iter().cloned());
                (
                    collocation_problem(self.system, &orbit, m2.clone(), *ncol)?,
                    Layout::Collocation {
                        meshes: m2,
                        ncol: *ncol,
                    },
                )
            }
        };
        let mut doubled = Self {
            system: self.system,
            like: orbit.clone(),
            layout,
            problem,
            param: self.param,
            slot_from_end: 0,
            collapsed: None,
            measures,
            events: self.events.clone(),
        };
        let name = self.system.parameter_names()[self.param];
        let id = doubled
            .problem
            .monitor_id(name)
            .expect("parameter monitor exists");
        doubled
            .problem
            .set_activity(id, Activity::Active(orbit.params[self.param]));
        let u0 = double(&point.u);
        let mut t = double(&point.tangent);
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
        let mut monitors = vec![orbit.period(), min_duration];
        monitors.extend((self.measures.compute)(&orbit));
        Ok(PointInfo {
            params: orbit.params.clone(),
            monitors,
            multipliers: floquet.multipliers,
            trivial: floquet.trivial,
        })
    }
    /// Collocation: each segment's node values weigh `1 / nodes` (the segment's mean square,
    /// as AUTO's $L_2$ norm, independent of the mesh); shooting's few segment starts, the
    /// durations and the parameters weigh 1.
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        let Layout::Collocation { meshes, ncol } = &self.layout else {
            return None;
        };
        let n = self.like.starts[0].len();
        let mut w = Vec::with_capacity(self.problem.unknowns());
        for m in meshes {
            let nodes = (m.len() - 1) * ncol + 1;
            w.extend(std::iter::repeat_n(1.0 / nodes as f64, nodes * n));
        }
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
