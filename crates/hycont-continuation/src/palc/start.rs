//! A run's start: its checks and its first chart (shared by the two directions of a run from
//! the same start).

use super::chord::Held;
use super::predict::{generic, orientation};
use super::slots::{Slot, Source};
use super::{Chart, Palc};
use crate::ContinuationProblem;
use crate::error::{Error, Result};

/// The smallest parameter component of the (weighted unit) tangent at a start corrected with
/// the parameter fixed: below it the correction was nearly singular and is redone on a
/// generic hyperplane.
const PARAMETER_FIXED_MIN_SLOPE: f64 = 1e-3;

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// The first chart. Without a given direction: `u0` corrected with the parameter fixed
    /// (where that fails, on a generic hyperplane through it: a branch that does not move in the
    /// parameter there), its tangent oriented by `direction`. With one (branch switching,
    /// restarts): a predictor step `h0` along it first, so that a start at a branch point leaves
    /// it along the requested branch.
    pub(super) fn first_chart(
        &mut self,
        u0: &[f64],
        initial_tangent: Option<&[f64]>,
        direction: f64,
    ) -> Result<Chart> {
        let pi = self.p.parameter_index();
        // The chart, and the last row of the augmented Jacobian its correction left factorised.
        let (mut a, factorised_row) = if let Some(t) = initial_tangent {
            let mut dir = t.to_vec();
            self.wnormalize(&mut dir);
            if direction < 0.0 {
                dir.iter_mut().for_each(|x| *x = -*x);
            }
            let h0 = self.settings.first_step();
            let pred: Vec<f64> = u0.iter().zip(&dir).map(|(x, t)| x + h0 * t).collect();
            let row = self.row_of(&dir);
            let (u, it) = self.correct(pred, &row, u0, h0, false)?;
            self.p.check_start(&u)?;
            let mut c = self.chart(u, &row, it)?;
            if self.wdot(&c.t, &dir) < 0.0 {
                c.t.iter_mut().for_each(|x| *x = -*x);
            }
            (c, row)
        } else if let Some(mut c) = self.reusable_first_chart(u0) {
            // The other direction from the same start: the same chart, the tangent reversed.
            if orientation(&c.t, pi) * direction < 0.0 {
                c.t.iter_mut().for_each(|x| *x = -*x);
                // The determinant's last row is the tangent's: reversing it flips the sign.
                c.det.0 = -c.det.0;
            }
            return Ok(c);
        } else {
            let (mut c, row) = self.held_start(u0)?;
            if orientation(&c.t, pi) * direction < 0.0 {
                c.t.iter_mut().for_each(|x| *x = -*x);
            }
            (c, row)
        };
        self.check_start_bounds(&a)?;
        // The determinant with the chart's own oriented tangent as the last row, consistent with
        // the following charts (each uses its predecessor's tangent), from the factorisation
        // left (see `Palc::det_with_row`); and that factorisation held for the first step's
        // chords, as a step's chart leaves its own.
        let own = self.row_of(&a.t);
        a.det = self.det_with_row(a.det, &own);
        self.held = Some(Held {
            generation: self.generation,
            row: factorised_row,
            z: self.z.clone(),
        });
        if initial_tangent.is_none() {
            let revision = self.p.discretisation_revision();
            self.first = Some((u0.to_vec(), revision, a.clone()));
        }
        Ok(a)
    }

    /// The chart of a directed start `u0` (a branch point or period doubling switched at),
    /// for testing the step to the first chart `a`: its own analysis, the direction `t`
    /// oriented as `a`'s tangent, and `a`'s determinant (the augmented Jacobian is singular
    /// at the start; the branch-point test is not watched on that step).
    pub(super) fn directed_start(&mut self, u0: &[f64], t: &[f64], a: &Chart) -> Result<Chart> {
        let mut dir = t.to_vec();
        self.wnormalize(&mut dir);
        if self.wdot(&dir, &a.t) < 0.0 {
            dir.iter_mut().for_each(|x| *x = -*x);
        }
        let info = self.analyse(u0)?;
        Ok(Chart {
            u: u0.to_vec(),
            t: dir,
            info,
            iterations: 0,
            det: a.det,
        })
    }

    /// The first chart from `u0` without a direction: corrected with the continued parameter
    /// held, or on a generic hyperplane where it cannot be held; with the row it was corrected
    /// on. A start is usually a solution already (a problem's own solve): its first
    /// factorisation is then the chart's (see [`Palc::correct`]'s accurate predictor).
    fn held_start(&mut self, u0: &[f64]) -> Result<(Chart, Vec<f64>)> {
        let pi = self.p.parameter_index();
        let mut row = vec![0.0; self.n];
        row[pi] = 1.0;
        // With the parameter fixed, the correction is singular where the branch does not
        // move in the parameter (e.g. a curve along which the continued parameter stays
        // put): Newton then fails, or lands on a point the problem refuses, or where the
        // branch is (nearly) orthogonal to the parameter. Then on a generic hyperplane
        // through `u0`.
        let fixed = self
            .correct(u0.to_vec(), &row, u0, 0.0, true)
            .and_then(|(u, it)| {
                let c = self.chart(u, &row, it)?;
                if c.t[pi].abs() < PARAMETER_FIXED_MIN_SLOPE {
                    return Err(Error::InvalidSetting {
                        name: "start",
                        value: c.t[pi],
                        reason: "the branch does not move in the parameter at the start",
                    });
                }
                self.p.check_start(&c.u)?;
                Ok(c)
            });
        if let Ok(c) = fixed {
            return Ok((c, row));
        }
        let g = generic(self.n);
        let (u, it) = self.correct(u0.to_vec(), &g, u0, 0.0, false)?;
        self.p.check_start(&u)?;
        Ok((self.chart(u, &g, it)?, g))
    }

    /// Checks that the first chart lies inside every bound (of the continued parameter, other
    /// parameters and measures; to $10^{-9}$ relative): a run from outside would return points
    /// outside the window asked for.
    fn check_start_bounds(&self, c: &Chart) -> Result<()> {
        let pi = self.p.parameter_index();
        let bounds: Vec<(Source, f64)> = self
            .slots
            .iter()
            .filter_map(|s| match *s {
                Slot::Bound { source, level, .. } => Some((source, level)),
                _ => None,
            })
            .collect();
        // Each bound is two slots: its minimum, then its maximum.
        for pair in bounds.chunks_exact(2) {
            let ((source, min), max) = (pair[0], pair[1].1);
            let value = source.value(c, pi);
            let tol = 1e-9 * (1.0 + value.abs());
            if !(value >= min - tol && value <= max + tol) {
                let name = match source {
                    Source::Continued => self.p.parameter_name(),
                    Source::Param(i) => self.p.parameter_names()[i].clone(),
                    Source::Monitor(i) => self.p.monitor_names()[i].clone(),
                };
                return Err(Error::StartOutsideBounds {
                    parameter: name,
                    value,
                    min,
                    max,
                });
            }
        }
        Ok(())
    }

    /// The first chart of the last run from `u0` without a direction, if it was on the current
    /// discretisation.
    fn reusable_first_chart(&self, u0: &[f64]) -> Option<Chart> {
        let (start, revision, chart) = self.first.as_ref()?;
        (start == u0 && *revision == self.p.discretisation_revision()).then(|| chart.clone())
    }

    /// Checks a run's start: a usable direction, a finite start (and tangent) of the right
    /// length, inside the continuation bounds.
    pub(super) fn check_start(
        &self,
        u0: &[f64],
        initial_tangent: Option<&[f64]>,
        direction: f64,
    ) -> Result<()> {
        if !(direction.is_finite() && direction != 0.0) {
            return Err(Error::InvalidSetting {
                name: "direction",
                value: direction,
                reason: "must be finite and non-zero: > 0 continues with increasing parameter (or along the tangent), < 0 against it",
            });
        }
        hycont_core::error::check_len("initial point", u0, self.n)?;
        hycont_core::error::check_finite("initial point", u0)?;
        if let Some(t) = initial_tangent {
            hycont_core::error::check_len("initial tangent", t, self.n)?;
            hycont_core::error::check_finite("initial tangent", t)?;
        }
        let (min, max) = self.settings.continuation_bounds();
        let value = u0[self.p.parameter_index()];
        // A located end point lies on its bound to the locator's accuracy: the same 1e-9
        // (relative) as the first chart's check.
        let tol = 1e-9 * (1.0 + value.abs());
        if !(min - tol <= value && value <= max + tol) {
            return Err(Error::StartOutsideBounds {
                parameter: self.p.parameter_name(),
                value,
                min,
                max,
            });
        }
        Ok(())
    }
}
