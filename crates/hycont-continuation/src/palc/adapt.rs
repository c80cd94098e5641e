//! Mesh (discretisation) adaptation along a run: when it is due, and the chart carried to the
//! new discretisation and corrected there.

use super::{Chart, Palc};
use crate::ContinuationProblem;
use crate::error::Result;

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// Whether the discretisation is due for adaptation at chart `b`, `since` points after the
    /// last one: where the error estimate exceeds the tolerance, and every
    /// [`ContinuationSettings::adapt_every`] points unless the estimate is below a hundredth of
    /// the tolerance (a mesh that good is not worth moving).
    pub(super) fn adaptation_due(&self, b: &Chart, since: usize) -> bool {
        let every = self.settings.adapt_every;
        let tol = self.settings.discretisation_tolerance;
        let error = b.info.discretisation_error;
        error.is_some_and(|e| e > tol)
            || (every > 0 && since >= every && error.is_none_or(|e| e > 0.01 * tol))
    }

    /// Chart `b` on a new discretisation ([`ContinuationProblem::rediscretise`]), corrected on
    /// the hyperplane through the carried point normal to the carried tangent; `None` when the
    /// problem keeps its discretisation, or when the carried point does not correct (the
    /// problem then returns to the discretisation of `b`).
    pub(super) fn rediscretised(&mut self, b: &Chart) -> Result<Option<Chart>> {
        let before = self.p.discretisation_revision();
        let tolerance = self.settings.discretisation_tolerance;
        let Some(carried) = self.p.rediscretise(&b.u, &b.t, tolerance)? else {
            return Ok(None);
        };
        let (u, mut t) = (carried.u, carried.t);
        if carried.layout_changed {
            self.relayout()?;
        }
        self.wnormalize(&mut t);
        let row = self.row_of(&t);
        let corrected = self
            .correct(u.clone(), &row, &u, 0.0, false)
            .and_then(|(u, it)| self.chart(u, &row, it));
        match corrected {
            Ok(mut c) => {
                if self.wdot(&c.t, &t) < 0.0 {
                    c.t.iter_mut().for_each(|x| *x = -*x);
                }
                self.stats.rediscretisations += 1;
                Ok(Some(c))
            }
            Err(_) => {
                self.restore(before)?;
                Ok(None)
            }
        }
    }
}
