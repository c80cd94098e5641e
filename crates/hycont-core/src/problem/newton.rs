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
            Damped::Failed { damping } => {
                history.push(NewtonIteration {
                    residual: res,
                    step,
                    damping,
                    factorized: true,
                });
                return Err(Error::NewtonFailed {
                    reason: format!(
                        "no damped step reduces the residual {res:e} (smallest damping {damping}) at iteration {}",
                        history.len()
                    ),
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
    Err(Error::NewtonFailed {
        reason: format!(
            "no convergence in {} iterations (residual {:e})",
            settings.max_iterations,
            max_norm(&f)
        ),
        history,
    })
}

/// Outcome of [`damped_step`].
enum Damped {
    /// The step `damping * du` reduces the residual (to `residual`).
    Accepted { residual: f64, damping: f64 },
    /// A chord step that does not reduce the residual enough (refactorise, do not damp).
    PoorChord,
    /// No damping down to the smallest reduces the residual.
    Failed { damping: f64 },
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
    loop {
        for ((t, x), d) in trial.iter_mut().zip(u).zip(du) {
            *t = x + damping * d;
        }
        let ok =
            problem.evaluate(trial, trial_f, None).is_ok() && trial_f.iter().all(|v| v.is_finite());
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
            return Damped::Failed { damping };
        }
        damping *= 0.5;
    }
}
