//! Two-dimensional atlases of periodic orbits: [`OrbitRun::atlas`] covers the family of
//! orbits through a start with the run's parameter and a second one free, and
//! [`OrbitRun::extend_atlas`] grows a saved one further.

use super::problem::{OrbitContinuation, check_parameter};
use super::run::OrbitRun;
use crate::ContinuationProblem;
use crate::atlas::{Atlas, AtlasChart, AtlasSettings};
use crate::error::{Error, Result};
use hycont_core::orbit::{Closure, Discretisation, PeriodicOrbit};
use hycont_core::problem::Activity;
use hycont_core::{HybridJacobians, HybridSystem, ParamId};
use serde::{Deserialize, Serialize};

/// An atlas of periodic orbits with its layout (serialisable: save it, read its charts as
/// orbits, grow it further with [`OrbitRun::extend_atlas`]). Charts' unknowns are those of
/// `discretisation` for orbits like `template` (the half orbits of a symmetric family, whose
/// charts [`OrbitAtlas::orbit_of`] unfolds), followed by the two free parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrbitAtlas {
    /// The charts.
    pub atlas: Atlas,
    /// The free parameters: the run's and the second.
    pub free: [ParamId; 2],
    /// An orbit with the charts' signature.
    pub template: PeriodicOrbit,
    /// The discretisation of the charts' orbits.
    pub discretisation: Discretisation,
}

impl OrbitAtlas {
    /// The orbit of a chart (the full orbit also for a symmetric family continued on half
    /// orbits).
    ///
    /// # Errors
    /// A system that is not the atlas's (other parameter names, or a template that does not
    /// fit it: [`Error::InvalidSaved`], [`Error::Core`]), a chart that does not fit the
    /// atlas's layout, or a half orbit that cannot be unfolded.
    pub fn orbit_of<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        chart: &AtlasChart,
    ) -> Result<PeriodicOrbit> {
        let names: Vec<&str> = system.parameter_names().to_vec();
        if self.atlas.parameter_names != names {
            return Err(Error::InvalidSaved {
                what: "atlas",
                reason: format!(
                    "it names the parameters {:?}, the system {names:?}",
                    self.atlas.parameter_names
                ),
            });
        }
        self.template.validate(system)?;
        let base = self.discretisation.segment_values(&self.template)
            + self.template.segment_count()
            + self.template.params.len();
        if chart.point.u.len() != base + 2 {
            return Err(Error::InvalidSetting {
                name: "chart unknowns",
                value: chart.point.u.len() as f64,
                reason: "do not fit the atlas's layout",
            });
        }
        let orbit = self.discretisation.unpack(&self.template, &chart.point.u);
        Ok(match orbit.signature.closure() {
            Closure::Symmetric => orbit.unfold_symmetric(system)?,
            Closure::Periodic => orbit,
        })
    }

    /// The atlas as JSON.
    ///
    /// # Errors
    /// If serialisation fails.
    pub fn to_json(&self) -> std::result::Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// An atlas from JSON (as written by [`OrbitAtlas::to_json`]).
    ///
    /// # Errors
    /// If the text is not an orbit atlas.
    pub fn from_json(text: &str) -> std::result::Result<Self, serde_json::Error> {
        let mut saved: Self = serde_json::from_str(text)?;
        saved.atlas.restore_keys();
        Ok(saved)
    }
}

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// Covers the two-parameter family of orbits through `start` with the run's parameter and
    /// `second` free by an atlas of charts ([`crate::atlas`]), named `name`: on the run's
    /// discretisation, on half orbits for a symmetric start (as [`OrbitRun::run`]), with the
    /// run's measures; its edges are `settings`' bounds and edges and, with the run's
    /// admissibility on, where orbits stop being admissible (GR, DB). The run's observer sees
    /// every chart.
    ///
    /// # Errors
    /// A parameter the system does not have or the run's own; invalid settings; an invalid
    /// start or no solution near it; a start outside the bounds or not admissible.
    pub fn atlas(
        &mut self,
        name: &str,
        start: &PeriodicOrbit,
        second: ParamId,
        settings: &AtlasSettings,
    ) -> Result<OrbitAtlas> {
        self.check_second(second)?;
        let (mut cp, u) = self.problem(start)?;
        let nbase = cp.problem().base_unknowns();
        let (u0, params) = self.release(&mut cp, &u[..nbase], second)?;
        let atlas = crate::atlas::cover(&mut cp, name, &u0, params, settings, &mut *self.observer)?;
        Ok(OrbitAtlas {
            atlas,
            free: [self.free, second],
            template: cp.template().clone(),
            discretisation: cp.discretisation().clone(),
        })
    }

    /// Grows a saved atlas of this run's orbits further, up to `max_charts` charts in all,
    /// once it passes [`OrbitRun::check_atlas`].
    ///
    /// # Errors
    /// An atlas that does not fit the system or the run (another first parameter, other
    /// measures or events), or does not pass [`OrbitRun::check_atlas`].
    pub fn extend_atlas(&mut self, saved: &mut OrbitAtlas, max_charts: usize) -> Result<()> {
        let mut cp = self.saved_problem(saved)?;
        crate::atlas::extend(&mut cp, &mut saved.atlas, max_charts, &mut *self.observer)
    }

    /// Checks a saved atlas (e.g. read from a file) against this run: the system's (its
    /// parameter names, the template), in this run's parameter and a second one with this
    /// run's measures and events, its parameters at the unknowns this run releases, and every
    /// chart a solution with its tangent plane, analysis and test values there
    /// ([`crate::atlas::check`]). [`OrbitRun::extend_atlas`] checks so before it grows it.
    ///
    /// # Errors
    /// As [`OrbitRun::extend_atlas`], without growing anything.
    pub fn check_atlas(&mut self, saved: &OrbitAtlas) -> Result<()> {
        let mut cp = self.saved_problem(saved)?;
        crate::atlas::check(&mut cp, &saved.atlas)
    }

    /// The problem of a saved atlas: this run's, with the atlas's second parameter released
    /// at the unknowns the atlas says.
    fn saved_problem(&mut self, saved: &OrbitAtlas) -> Result<OrbitContinuation<'a, S>> {
        saved.template.validate(self.system)?;
        if saved.free[0] != self.free {
            return Err(Error::InvalidSetting {
                name: "atlas parameter",
                value: saved.free[0].index() as f64,
                reason: "is not this run's parameter",
            });
        }
        self.check_second(saved.free[1])?;
        let mut cp = OrbitContinuation::on_discretisation(
            self.system,
            saved.template.clone(),
            saved.discretisation.clone(),
            self.free,
            self.measures.clone(),
            self.events.clone(),
        )?;
        if cp.monitor_names() != saved.atlas.monitor_names {
            return Err(Error::InvalidSetting {
                name: "atlas measures",
                value: saved.atlas.monitor_names.len() as f64,
                reason: "differ from this run's",
            });
        }
        let nbase = cp.problem().base_unknowns();
        let first = saved.atlas.charts.first().map(|c| c.point.u.clone());
        let base = first.unwrap_or_default();
        if base.len() < nbase {
            return Err(Error::InvalidSetting {
                name: "atlas",
                value: base.len() as f64,
                reason: "has no charts of this layout",
            });
        }
        let (_, params) = self.release(&mut cp, &base[..nbase], saved.free[1])?;
        if params != saved.atlas.unknown_params {
            return Err(Error::InvalidSaved {
                what: "atlas",
                reason: format!(
                    "its parameters are the unknowns {:?}, this run's {params:?}",
                    saved.atlas.unknown_params
                ),
            });
        }
        Ok(cp)
    }

    fn check_second(&self, second: ParamId) -> Result<()> {
        check_parameter(self.system, second)?;
        if second == self.free {
            return Err(Error::InvalidSetting {
                name: "second parameter",
                value: second.index() as f64,
                reason: "must differ from the run's parameter",
            });
        }
        Ok(())
    }

    /// Makes `second` active in `cp` too; the unknowns of `base` with both parameters, and
    /// the parameters' indices in them (the run's first).
    fn release(
        &self,
        cp: &mut OrbitContinuation<'a, S>,
        base: &[f64],
        second: ParamId,
    ) -> Result<(Vec<f64>, [usize; 2])> {
        let like = cp.template().clone();
        let problem = cp.problem_mut();
        let name = self.system.parameter_names()[second.index()];
        let id = problem
            .monitor_id(name)
            .ok_or_else(|| Error::SwitchFailed {
                reason: format!("no monitor for parameter {name}"),
            })?;
        let nbase = base.len();
        let np = like.params.len();
        // The orbit's parameters are the last of the base unknowns.
        let value = |p: ParamId| base[nbase - np + p.index()];
        problem.set_activity(id, Activity::Active(value(second)))?;
        cp.set_second_parameter(self.free.index() > second.index());
        let (lo, hi) = if self.free.index() < second.index() {
            (self.free, second)
        } else {
            (second, self.free)
        };
        let mut u0 = base.to_vec();
        u0.extend([value(lo), value(hi)]);
        let params = if lo == self.free {
            [nbase, nbase + 1]
        } else {
            [nbase + 1, nbase]
        };
        Ok((u0, params))
    }
}
