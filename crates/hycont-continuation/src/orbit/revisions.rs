//! The revisions of an orbit problem's discretisation: collocation meshes adapted along a
//! branch ([`crate::ContinuationProblem::rediscretise`]), the problem rebuilt on any of them,
//! and the full orbits' layout of each.

use super::problem::OrbitContinuation;
use crate::error::Result;
use hycont_core::orbit::Discretisation;
use hycont_core::{HybridJacobians, ParamId};

impl<S: HybridJacobians + ?Sized> OrbitContinuation<'_, S> {
    /// Rebuilds the problem on revision `r` of its discretisation.
    pub(super) fn switch_to(&mut self, r: usize) -> Result<()> {
        let fresh = Self::on_discretisation(
            self.system,
            self.like.clone(),
            self.revisions[r].clone(),
            ParamId(self.param),
            self.measures.clone(),
            self.events.clone(),
        )?;
        self.disc = fresh.disc;
        self.cache = fresh.cache;
        self.problem = fresh.problem;
        self.current = r;
        Ok(())
    }

    /// The discretisation of revision `r` (of the half orbit on a half-orbit problem); the
    /// current one for an unknown revision.
    pub(super) fn revision(&self, r: usize) -> &Discretisation {
        self.revisions.get(r).unwrap_or(&self.disc)
    }

    /// Every revision of the discretisation of the full orbits (see
    /// [`OrbitContinuation::full_layout`]), in order: a point's
    /// [`crate::BranchPoint::discretisation`] indexes it.
    #[must_use]
    pub fn full_revisions(&self) -> Vec<Discretisation> {
        self.revisions
            .iter()
            .map(|d| {
                if self.half_of.is_some() {
                    d.repeated(2)
                } else {
                    d.clone()
                }
            })
            .collect()
    }

    pub(super) fn full_orbit_problem_at(&self, revision: usize) -> Result<Self> {
        let (like, _) = self.full_layout()?;
        let mut revisions = self.full_revisions();
        if revision >= revisions.len() {
            return Err(hycont_core::Error::IndexOutOfRange {
                what: "discretisation revision",
                index: revision,
                count: revisions.len(),
            }
            .into());
        }
        let disc = revisions.swap_remove(revision);
        let mut full = Self::on_discretisation(
            self.system,
            like,
            disc,
            ParamId(self.param),
            self.measures.clone(),
            self.events.clone(),
        )?;
        full.admissible_start = self.admissible_start;
        Ok(full)
    }

    /// Moves a collocation problem (a one-parameter one) to meshes that equidistribute the
    /// error estimate at `u`, with more intervals where it exceeds `tolerance`; kept when the
    /// size is the same and no mesh point would move by more than a tenth of the smallest
    /// interval. Returns `u` and `t` carried over.
    pub(super) fn adapt_mesh(
        &mut self,
        u: &[f64],
        t: &[f64],
        tolerance: f64,
    ) -> Result<Option<crate::Rediscretised>> {
        let Discretisation::Collocation { meshes, .. } = &self.disc else {
            return Ok(None);
        };
        if !self.adaptable {
            return Ok(None);
        }
        let smallest = meshes
            .iter()
            .flat_map(|m| m.windows(2).map(|w| w[1] - w[0]))
            .fold(f64::INFINITY, f64::min);
        let adapted = self.disc.refined(&self.like, u, tolerance);
        if self.disc.distance(&adapted) <= 0.1 * smallest {
            return Ok(None);
        }
        let carried = crate::Rediscretised {
            u: self.disc.transfer(&adapted, &self.like, u)?,
            t: self.disc.transfer(&adapted, &self.like, t)?,
            layout_changed: !self.disc.same_layout(&adapted),
        };
        self.revisions.push(adapted);
        let r = self.revisions.len() - 1;
        self.switch_to(r)?;
        Ok(Some(carried))
    }

    /// Returns to revision `revision` of the discretisation; whether the layout changed.
    pub(super) fn restore(&mut self, revision: usize) -> Result<bool> {
        if revision == self.current {
            return Ok(false);
        }
        if revision >= self.revisions.len() {
            return Err(hycont_core::Error::IndexOutOfRange {
                what: "discretisation revision",
                index: revision,
                count: self.revisions.len(),
            }
            .into());
        }
        let changed = !self.disc.same_layout(&self.revisions[revision]);
        self.switch_to(revision)?;
        Ok(changed)
    }
}
