//! Damped Newton's method on a square [`Problem`], with the sparse LU's symbolic analysis reused
//! across iterations and, optionally, the numeric factorisation too (chord steps) while the
//! residual contracts fast.

use super::Problem;
use crate::error::{Error, Result};
use crate::linalg::max_norm;

/// Settings of [`newton`]: a validated builder with `Default`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NewtonSettings {
    /// Converged when $\|\Delta u\|_\infty \le$ `tol` $\cdot (1 + \|u\|_\infty)$ and
    /// $\|F\|_\infty \le$ `residual_tol` (defaults `1e-10`, `1e-10`).
    pub tol: f64,
    /// See `tol`.
    pub residual_tol: f64,
    /// Iteration limit (default 20).
    pub max_iterations: usize,
    /// Smallest damping factor tried before giving up on a step (default `1/64`).
    pub min_damping: f64,
    /// Reuse the last Jacobian factorisation (a chord step) while each step reduces the residual
    /// by at least this factor; `0` always refactorises (default `0.1`).
    pub chord_contraction: f64,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tol: 1e-10,
            residual_tol: 1e-10,
            max_iterations: 20,
            min_damping: 1.0 / 64.0,
            chord_contraction: 0.1,
        }
    }
}

impl NewtonSettings {
    /// The resolution of a solution `u` converged under these settings: the step tolerance
    /// $\text{tol}\,(1 + \|u\|_\infty)$ within which the last step left it.
    ///
    /// ```
    /// use hycont_core::problem::NewtonSettings;
    /// let s = NewtonSettings::default();
    /// assert!((s.resolution(&[-3.0, 1.0]) - 4e-10).abs() < 1e-24);
    /// ```
    #[must_use]
    pub fn resolution(&self, u: &[f64]) -> f64 {
        self.tol * (1.0 + max_norm(u))
    }

    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the first invalid setting.
    ///
    /// ```
    /// use hycont_core::problem::NewtonSettings;
    /// assert!(NewtonSettings::default().validate().is_ok());
    /// assert!(NewtonSettings { tol: 0.0, ..NewtonSettings::default() }.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(Error::InvalidSetting {
                name,
                value,
                reason,
            })
        };
        if !(self.tol > 0.0 && self.tol < 1.0) {
            return bad("newton.tol", self.tol, "must be in (0, 1)");
        }
        if !(self.residual_tol > 0.0 && self.residual_tol.is_finite()) {
            return bad(
                "newton.residual_tol",
                self.residual_tol,
                "must be > 0 and finite",
            );
        }
        if self.max_iterations == 0 {
            return bad("newton.max_iterations", 0.0, "must be >= 1");
        }
        if !(self.min_damping > 0.0 && self.min_damping <= 1.0) {
            return bad("newton.min_damping", self.min_damping, "must be in (0, 1]");
        }
        if !(0.0..1.0).contains(&self.chord_contraction) {
            return bad(
                "newton.chord_contraction",
                self.chord_contraction,
                "must be in [0, 1)",
            );
        }
        Ok(())
    }
}

/// Why Newton's method failed ([`crate::Error::NewtonFailed`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum NewtonFailure {
    /// No damped step (down to the smallest damping) reduces the residual: the Newton
    /// direction does not descend. The start is too far from a solution or there is none
    /// nearby, the Jacobian does not match the residual, or the residual cannot be evaluated at
    /// the trial points (the message gives the evaluation's error).
    NoDescent,
    /// The residual is below its tolerance but the steps do not fall below theirs: the
    /// Jacobian is singular or nearly so at the solution, which is not isolated (e.g. a
    /// segment of zero duration, an orbit that is not one, a degenerate start).
    StepsNotConverging,
    /// The residual fell, but slowly (linear contraction): an inaccurate or nearly singular
    /// Jacobian.
    SlowContraction,
    /// The steps grew without bound.
    Diverging,
    /// The iteration limit was reached otherwise (the residual stagnates or oscillates).
    IterationLimit,
}

impl std::fmt::Display for NewtonFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NewtonFailure::NoDescent => "no descent",
            NewtonFailure::StepsNotConverging => "steps not converging",
            NewtonFailure::SlowContraction => "slow contraction",
            NewtonFailure::Diverging => "diverging",
            NewtonFailure::IterationLimit => "iteration limit",
        })
    }
}

impl NewtonFailure {
    /// Why iterations that reached their limit did not converge, with a message: `history`
    /// holds the residuals before each step and the steps, `last_residual` the residual after
    /// the last step, `residual_tol` its tolerance and `tol` the step tolerance (scaled).
    #[must_use]
    pub fn diagnose(
        history: &[NewtonIteration],
        last_residual: f64,
        residual_tol: f64,
        tol: f64,
    ) -> (Self, String) {
        diagnose(history, last_residual, residual_tol, tol)
    }
}

fn diagnose(
    history: &[NewtonIteration],
    last_residual: f64,
    residual_tol: f64,
    tol: f64,
) -> (NewtonFailure, String) {
    let last_step = history.last().map_or(f64::NAN, |h| h.step);
    if last_residual <= residual_tol {
        return (
            NewtonFailure::StepsNotConverging,
            format!(
                "the residual {last_residual:e} is below its tolerance but the steps stay at \
                 {last_step:e} (tolerance {tol:e}): the Jacobian is (nearly) singular there, so \
                 the solution is not isolated (a zero-duration segment, a degenerate orbit?)"
            ),
        );
    }
    if !last_step.is_finite() || last_step > 1e6 * (1.0 + tol) {
        return (
            NewtonFailure::Diverging,
            format!("the steps diverge (last {last_step:e}, residual {last_residual:e})"),
        );
    }
    // Residuals over the last iterations, with the final one.
    let mut r: Vec<f64> = history.iter().map(|h| h.residual).collect();
    r.push(last_residual);
    let tail = &r[r.len().saturating_sub(4)..];
    let falling = tail.windows(2).all(|w| w[1] < w[0]);
    if falling && tail.len() >= 3 {
        let q = (tail[tail.len() - 1] / tail[0]).powf(1.0 / (tail.len() - 1) as f64);
        if q >= 0.5 {
            return (
                NewtonFailure::SlowContraction,
                format!(
                    "the residual falls only by a factor {q:.3} per iteration (now \
                     {last_residual:e}): an inaccurate or nearly singular Jacobian"
                ),
            );
        }
        return (
            NewtonFailure::IterationLimit,
            format!(
                "the residual still falls by a factor {q:.3} per iteration (now {last_residual:e}): \
                 too few iterations, or a start too far away"
            ),
        );
    }
    (
        NewtonFailure::IterationLimit,
        format!("no convergence: the residual stagnates at {last_residual:e}"),
    )
}

/// One Newton iteration, for the history kept in results and errors.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NewtonIteration {
    /// $\|F(u_k)\|_\infty$ before the step.
    pub residual: f64,
    /// $\|\Delta u\|_\infty$ of the full Newton step.
    pub step: f64,
    /// Damping factor used.
    pub damping: f64,
    /// Whether the Jacobian was factorised for this step (false: chord step).
    pub factorized: bool,
}

/// A converged Newton solve.
#[derive(Debug, Clone, PartialEq)]
pub struct NewtonSolution {
    /// The solution.
    pub u: Vec<f64>,
    /// $\|F(u)\|_\infty$ at the solution.
    pub residual: f64,
    /// The iterations.
    pub history: Vec<NewtonIteration>,
}

impl NewtonSolution {
    /// Number of Jacobian factorisations done.
    #[must_use]
    pub fn factorizations(&self) -> usize {
        self.history.iter().filter(|h| h.factorized).count()
    }
}

/// Solves the square problem $F(u) = 0$ from `u0` by damped Newton: full steps while the residual
/// decreases sufficiently, halved (down to `min_damping`) otherwise. Converged when a step is
/// below `tol` and the residual at the new point below `residual_tol`.
///
/// # Errors
/// [`Error::NewtonFailed`] (with the iteration history) on divergence or the iteration limit;
/// [`Error::SingularMatrix`] if the Jacobian is singular; [`Error::DimensionMismatch`] if the
/// problem is not square or `u0` has the wrong length.
pub fn newton(
    problem: &mut Problem<'_>,
    u0: &[f64],
    settings: &NewtonSettings,
) -> Result<NewtonSolution> {
    settings.validate()?;
    let (m, n) = (problem.equations(), problem.unknowns());
    if m != n {
        return Err(Error::DimensionMismatch {
            what: "equations (Newton needs a square problem)",
            expected: n,
            found: m,
        });
    }
    crate::error::check_len("initial unknowns", u0, n)?;
    crate::error::check_finite("initial unknowns", u0)?;
    let mut u = u0.to_vec();
    let mut f = vec![0.0; m];
    let mut trial = (vec![0.0; n], vec![0.0; m]);
    let mut du = vec![0.0; n];
    let mut history = Vec::new();
    // Residual at u, if already known from the previous accepted step.
    let mut known_residual = false;
    let mut chord = false;
    for _ in 0..settings.max_iterations {
        if chord {
            if !known_residual {
                problem.evaluate(&u, &mut f, None)?;
            }
        } else {
            problem.factorize(&u, &mut f)?;
        }
        let res = max_norm(&f);
        for (d, v) in du.iter_mut().zip(&f) {
            *d = -v;
        }
        problem.solve_in_place(&mut du)?;
        let step = max_norm(&du);
        let scale = 1.0 + max_norm(&u);
        let (trial_res, damping) = match damped_step(
            problem,
            (&u, &du),
            &mut trial,
            res,
            chord,
            settings,
        ) {
            Damped::Accepted { residual, damping } => (residual, damping),
            Damped::PoorChord => {
                // A poor chord step: refactorise instead of damping.
                chord = false;
                known_residual = false;
                continue;
            }
            Damped::Failed { damping, error } => {
                history.push(NewtonIteration {
                    residual: res,
                    step,
                    damping,
                    factorized: true,
                });
                let why = error.map_or_else(String::new, |e| {
                    format!("; the residual could not be evaluated at a trial point: {e}")
                });
                return Err(Error::NewtonFailed {
                    reason: format!(
                        "no damped step reduces the residual {res:e} (smallest damping {damping}) at iteration {}{why}",
                        history.len()
                    ),
                    failure: NewtonFailure::NoDescent,
                    history,
                });
            }
        };
        history.push(NewtonIteration {
            residual: res,
            step,
            damping,
            factorized: !chord,
        });
        std::mem::swap(&mut u, &mut trial.0);
        std::mem::swap(&mut f, &mut trial.1);
        known_residual = true;
        if damping == 1.0 && step <= settings.tol * scale && trial_res <= settings.residual_tol {
            return Ok(NewtonSolution {
                u,
                residual: trial_res,
                history,
            });
        }
        chord = damping == 1.0
            && settings.chord_contraction > 0.0
            && trial_res <= settings.chord_contraction * res;
    }
    let tol = settings.resolution(&u);
    let (failure, why) = diagnose(&history, max_norm(&f), settings.residual_tol, tol);
    Err(Error::NewtonFailed {
        reason: format!(
            "did not converge in {} iterations: {why}",
            settings.max_iterations
        ),
        failure,
        history,
    })
}

/// Outcome of [`damped_step`].
enum Damped {
    /// The step `damping * du` reduces the residual (to `residual`).
    Accepted { residual: f64, damping: f64 },
    /// A chord step that does not reduce the residual enough (refactorise, do not damp).
    PoorChord,
    /// No damping down to the smallest reduces the residual (`error`: the last evaluation
    /// that failed, if one did).
    Failed { damping: f64, error: Option<Error> },
}

/// The first of the damped steps `u + damping du`, `damping` = 1, 1/2, 1/4, ... down to
/// [`NewtonSettings::min_damping`], that reduces the residual `res` sufficiently (Armijo with
/// `1e-4`) or below the tolerance; the trial point and its residual are left in `trial`.
fn damped_step(
    problem: &mut Problem<'_>,
    (u, du): (&[f64], &[f64]),
    (trial, trial_f): &mut (Vec<f64>, Vec<f64>),
    res: f64,
    chord: bool,
    settings: &NewtonSettings,
) -> Damped {
    let mut damping = 1.0;
    let mut error = None;
    loop {
        for ((t, x), d) in trial.iter_mut().zip(u).zip(du) {
            *t = x + damping * d;
        }
        let ok = match problem.evaluate(trial, trial_f, None) {
            Ok(()) => trial_f.iter().all(|v| v.is_finite()),
            Err(e) => {
                error = Some(e);
                false
            }
        };
        let trial_res = if ok { max_norm(trial_f) } else { f64::INFINITY };
        if trial_res <= (1.0 - 1e-4 * damping) * res || trial_res <= settings.residual_tol {
            return Damped::Accepted {
                residual: trial_res,
                damping,
            };
        }
        if chord {
            return Damped::PoorChord;
        }
        if damping <= settings.min_damping {
            return Damped::Failed { damping, error };
        }
        damping *= 0.5;
    }
}
