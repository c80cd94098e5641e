//! The corrector: chord Newton on the augmented system, its factorisation (left for the
//! tangent, the determinant and the analysis) and the charts built from it.

use super::predict::{add_with_max, dot, max_abs};
use super::{Chart, Palc};
use crate::error::{Error, Result};
use crate::{ContinuationProblem, PointInfo};
use hycont_core::problem::JacobianUse;

/// Corrector iterations kept for the diagnosis of a failure (the last ones).
const RECENT: usize = 4;

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// Assembles and factorises $[J(u); r^\top]$ and writes $[F(u); r \cdot u - r_0 - s]$,
    /// `r0` $= r \cdot u_0$ (the same through a correction: taken once).
    ///
    /// `purpose` tells the problem whether the Jacobian must be exact (at a solution: tangent,
    /// determinant, multipliers) or only gives chord directions (it may then be computed more
    /// cheaply; the residual is exact either way).
    pub(super) fn factor(
        &mut self,
        u: &[f64],
        row: &[f64],
        r0: f64,
        s: f64,
        purpose: JacobianUse,
    ) -> Result<()> {
        let n = self.n;
        self.generation += 1;
        if self.locating {
            self.stats.location_jacobians += 1;
        } else {
            self.stats.jacobians += 1;
        }
        let mut values = std::mem::take(&mut self.values);
        self.p
            .problem()
            .evaluate_for(u, &mut self.res[..n - 1], &mut values, purpose)?;
        values.truncate(self.k);
        // Exactly the row's room (the problem sized the values for its own entries: a vector
        // grown by doubling would hold twice a large system's millions).
        values.reserve_exact(row.len());
        values.extend_from_slice(row);
        self.res[n - 1] = dot(row, u) - r0 - s;
        let out = self.pattern.factorize(&values);
        self.values = values;
        Ok(out?)
    }

    /// Newton on the augmented system from `u_pred` (taken: it becomes the solution); returns
    /// the solution and the iterations, and leaves the augmented Jacobian at the solution
    /// factorised (with `row` as last row).
    ///
    /// Converged when the residual is below the tolerance after at least one step, or the step
    /// is below the tolerance with a residual of the same order. The residual criterion matters
    /// near branch points, where the augmented Jacobian is nearly singular and evaluation noise
    /// is amplified along the (parameter-free) null direction.
    ///
    /// With `accurate_predictor` (location, where the predictor interpolates two nearby
    /// solutions to high order and is mostly a solution already) the exact factorisation is
    /// done at the predictor and its residual checked first: a predictor that solves the
    /// equations is accepted with that one factorisation; otherwise it starts the iterations.
    /// Otherwise, with chord steps armed by [`Palc::step`] (the previous chart's factorisation,
    /// see [`super::chord`]), the iterations start from that factorisation without a new one,
    /// until the contraction is slow or a solution is expected.
    pub(super) fn correct(
        &mut self,
        u_pred: Vec<f64>,
        row: &[f64],
        u0: &[f64],
        s: f64,
        accurate_predictor: bool,
    ) -> Result<(Vec<f64>, usize)> {
        let ns = self.settings.newton;
        let max_it = 2 * self.settings.target_iterations;
        let n = self.n;
        let r0 = dot(row, u0);
        let mut u = u_pred;
        let mut u_max = max_abs(&u);
        // The step's work space (an error returns without it: the next correction makes one).
        let mut du = std::mem::take(&mut self.du);
        du.resize(n, 0.0);
        let mut last_step = f64::INFINITY;
        let mut last_res = f64::INFINITY;
        // Chord iterations: the Jacobian is factorised at the predictor (and again only if the
        // residual stops contracting fast); the other iterations evaluate the residual only,
        // except where the contraction so far says the step lands on a solution: the exact
        // factorisation the solution needs is done there directly (its residual decides
        // convergence as any other; if it does not converge, it serves the next steps).
        let mut exact = accurate_predictor;
        // Chord steps armed by the step (see `chord`): the held factorisation serves until
        // a factorisation replaces it.
        let mut chord = if exact { None } else { self.chord.take() };
        let chord_start = chord.is_some();
        self.chord_converged = false;
        // Whether the last factorisation was the exact one that chord steps led to.
        let mut via_chord = false;
        if exact {
            self.factor(&u, row, r0, s, JacobianUse::Exact)?;
            if max_abs(&self.res) <= ns.residual_tol {
                self.du = du;
                return Ok((u, 0));
            }
        } else if chord.is_some() {
            self.residual(&u, row, r0, s)?;
        } else {
            self.factor(&u, row, r0, s, JacobianUse::NewtonDirection)?;
        }
        let mut fresh = true;
        let mut expect_solution = false;
        // The last iterations, for a diagnosis if the corrector fails (fixed storage: no
        // allocation on the corrector's path).
        let mut recent = [hycont_core::problem::NewtonIteration {
            residual: 0.0,
            step: 0.0,
            damping: 1.0,
            factorized: false,
        }; RECENT];
        let mut done = 0usize;
        for it in 0..=max_it {
            if !fresh {
                if expect_solution {
                    self.factor(&u, row, r0, s, JacobianUse::Exact)?;
                    via_chord = chord.take().is_some();
                } else {
                    self.residual(&u, row, r0, s)?;
                }
                exact = expect_solution;
            }
            let res = max_abs(&self.res);
            let scale = 1.0 + u_max;
            if it > 0
                && (res <= ns.residual_tol
                    || (last_step <= ns.tol * scale && res <= 1e3 * last_step.max(ns.residual_tol)))
            {
                // Converged: the tangent and the determinant need the factorisation there.
                if !exact {
                    via_chord = chord.take().is_some();
                    self.factor(&u, row, r0, s, JacobianUse::Exact)?;
                }
                self.chord_converged = via_chord;
                self.du = du;
                return Ok((u, it));
            }
            via_chord = false;
            if it == max_it || !res.is_finite() {
                break;
            }
            if !fresh && !exact && res > 0.2 * last_res {
                // Slow contraction: refresh the Jacobian.
                self.factor(&u, row, r0, s, JacobianUse::NewtonDirection)?;
                chord = None;
            }
            // A chord iteration contracts the residual by about the same factor each step.
            expect_solution = it > 0 && res * (res / last_res) <= 0.1 * ns.residual_tol;
            for (d, r) in du.iter_mut().zip(&self.res) {
                *d = -r;
            }
            self.pattern.solve_in_place(&mut du)?;
            if let Some(c) = &chord {
                c.correct(&mut du);
            }
            last_step = max_abs(&du);
            last_res = res;
            recent[done % RECENT] = hycont_core::problem::NewtonIteration {
                residual: res,
                step: last_step,
                damping: 1.0,
                factorized: (fresh && !chord_start) || exact,
            };
            done += 1;
            if last_step > 1e3 * scale {
                break;
            }
            u_max = add_with_max(&mut u, &du);
            fresh = false;
        }
        let history: Vec<_> = (done.saturating_sub(RECENT)..done)
            .map(|i| recent[i % RECENT])
            .collect();
        let tol = ns.tol * (1.0 + max_abs(&u));
        let last = max_abs(&self.res);
        let (failure, why) = if last_step > 1e3 * (1.0 + max_abs(&u)) {
            (
                hycont_core::problem::NewtonFailure::Diverging,
                format!(
                    "the corrector's step {last_step:e} left the chart (residual {last_res:e})"
                ),
            )
        } else {
            hycont_core::problem::NewtonFailure::diagnose(&history, last, ns.residual_tol, tol)
        };
        Err(Error::Core(hycont_core::Error::NewtonFailed {
            reason: format!("the corrector did not converge in {done} iterations: {why}"),
            failure,
            history,
        }))
    }

    /// Writes $[F(u); r \cdot u - r_0 - s]$ (see [`Palc::factor`]).
    fn residual(&mut self, u: &[f64], row: &[f64], r0: f64, s: f64) -> Result<()> {
        let n = self.n;
        self.count_residual();
        self.p.problem().evaluate(u, &mut self.res[..n - 1], None)?;
        self.res[n - 1] = dot(row, u) - r0 - s;
        Ok(())
    }

    pub(super) fn count_residual(&mut self) {
        if self.locating {
            self.stats.location_residuals += 1;
        } else {
            self.stats.residuals += 1;
        }
    }

    pub(super) fn analyse(&mut self, u: &[f64]) -> Result<PointInfo> {
        self.stats.analyses += 1;
        Ok(self.p.analyse(u)?)
    }

    /// Tangent at `u` with the current factorisation of $[J(u); row]$ (left by
    /// [`Palc::correct`]), and the determinant of that matrix.
    pub(super) fn tangent_from_factorization(&mut self) -> Result<(Vec<f64>, (f64, f64))> {
        let det = self.pattern.determinant()?;
        let mut x = vec![0.0; self.n];
        x[self.n - 1] = 1.0;
        self.pattern.solve_in_place(&mut x)?;
        self.z.clone_from(&x);
        self.wnormalize(&mut x);
        Ok((x, det))
    }

    /// The determinant of $[J; r]$ from `det` $= \det [J; q]$, the matrix left factorised with
    /// [`Palc::tangent_from_factorization`] run on it: a change of the last row only, so
    /// $\det [J; r] = \det [J; q]\,(r \cdot z)$ with $z = [J; q]^{-1} e_n$ (the matrix determinant
    /// lemma; $q \cdot z = 1$). As (sign, log of the magnitude).
    pub(super) fn det_with_row(&self, (sign, log): (f64, f64), r: &[f64]) -> (f64, f64) {
        let rz = dot(r, &self.z);
        (sign * rz.signum(), log + rz.abs().ln())
    }

    /// The chart at a corrected `u`, using the factorisation the corrector left (also for the
    /// analysis, see [`ContinuationProblem::analyse_factorised`]).
    pub(super) fn chart(&mut self, u: Vec<f64>, _row: &[f64], iterations: usize) -> Result<Chart> {
        let (t, det) = self.tangent_from_factorization()?;
        self.stats.analyses += 1;
        let info = self.p.analyse_factorised(&u, &self.pattern)?;
        Ok(Chart {
            u,
            t,
            info,
            iterations,
            det,
        })
    }
}
