//! The algebraic bifurcation equation at a simple branch point: where two branches of
//! $F(u) = 0$ ($F: \mathbb{R}^{m+1} \to \mathbb{R}^m$) cross, $J = F'(u)$ has rank $m - 1$, a
//! two-dimensional null space spanned by orthonormal $\varphi_1, \varphi_2$ and a left null
//! vector $\psi$ ($\psi^\top J = 0$). Every branch's tangent $t = \alpha \varphi_1 + \beta
//! \varphi_2$ solves $\psi^\top F''(u)[t, t] = 0$ (project $F(u(s)) = 0$ differentiated twice
//! onto $\psi$), a quadratic in $(\alpha, \beta)$ with two real roots, one per branch (Keller;
//! BifurcationKit's and AUTO's branch switching).
//!
//! Where one branch's tangent $\varphi_1$ is known (a root: $a_{11} = 0$), the other's is
//! $t \propto -a_{22} \varphi_1 + 2 a_{12} \varphi_2$, with $a_{ij} = \psi^\top F''[\varphi_i,
//! \varphi_j]$ from central second differences of $F$. Stepping along it, the corrector starts
//! $O(h^2)$ from the new branch; along $\varphi_2$ alone (orthogonal to the known branch) it
//! starts $O(h)$ away, outside the basin of Newton's method near the singular point (which
//! shrinks with the distance to it) when the branches cross at a shallow angle.

use crate::ContinuationProblem;
use crate::error::{Error, Result};
use crate::switch::augmented_pattern;
use hycont_core::linalg::max_norm;

/// The tangent of the second branch through the simple branch point `u`, where `known` is
/// the first branch's tangent and `other` the unit null direction of $J(u)$ orthogonal to it
/// (see the module docs). Unit length, oriented as `other`.
///
/// # Errors
/// [`Error::SwitchFailed`] where no left null vector is found or the quadratic is degenerate
/// ($a_{12} = 0$ with $a_{22} \ne 0$: the branches do not cross transversally); evaluation
/// failures.
pub(crate) fn second_branch_tangent<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &mut P,
    u: &[f64],
    known: &[f64],
    other: &[f64],
) -> Result<Vec<f64>> {
    let psi = left_null_vector(p, u, known)?;
    let problem = p.problem();
    let m = problem.equations();
    // Central second differences: the step balances truncation (eps^2) against the
    // residual's noise (integration to ~1e-12, divided by eps^2).
    let eps = 1e-3 * (1.0 + max_norm(u));
    let mut eval = |a: f64, v: &[f64], b: f64, w: &[f64]| -> Result<f64> {
        let x: Vec<f64> = (0..u.len())
            .map(|i| u[i] + eps * (a * v[i] + b * w[i]))
            .collect();
        let mut r = vec![0.0; m];
        problem.evaluate(&x, &mut r, None)?;
        Ok(psi.iter().zip(&r).map(|(a, b)| a * b).sum())
    };
    let mixed = (eval(1.0, known, 1.0, other)?
        - eval(1.0, known, -1.0, other)?
        - eval(-1.0, known, 1.0, other)?
        + eval(-1.0, known, -1.0, other)?)
        / (4.0 * eps * eps);
    let pure = (eval(0.0, known, 1.0, other)? - 2.0 * eval(0.0, known, 0.0, other)?
        + eval(0.0, known, -1.0, other)?)
        / (eps * eps);
    if mixed.abs() <= 1e-12 * pure.abs() {
        return Err(Error::SwitchFailed {
            reason: format!(
                "the bifurcation equation is degenerate (a12 = {mixed:e}, a22 = {pure:e}): the branches do not cross transversally"
            ),
        });
    }
    let mut t: Vec<f64> = known
        .iter()
        .zip(other)
        .map(|(k, o)| -pure * k + 2.0 * mixed * o)
        .collect();
    let norm = t.iter().map(|v| v * v).sum::<f64>().sqrt();
    let sign = if mixed < 0.0 { -1.0 } else { 1.0 };
    t.iter_mut().for_each(|v| *v *= sign / norm);
    Ok(t)
}

/// The left null vector $\psi$ of $J(u)$ at a branch point: the first $m$ components of the
/// left null vector of the singular augmented matrix $[J; r^\top]$ (whose last component
/// vanishes), by inverse iteration on its transpose.
fn left_null_vector<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &mut P,
    u: &[f64],
    row: &[f64],
) -> Result<Vec<f64>> {
    let problem = p.problem();
    let (mut pattern, k) = augmented_pattern(problem)?;
    let (n, m) = (problem.unknowns(), problem.equations());
    let mut values = Vec::new();
    let mut res = vec![0.0; m];
    problem.evaluate(u, &mut res, Some(&mut values))?;
    values.truncate(k);
    values.extend_from_slice(row);
    pattern.factorize(&values)?;
    let mut y: Vec<f64> = (0..n)
        .map(|i| ((i as f64 + 1.0) * 0.569_840_290_998).fract() - 0.5)
        .collect();
    for _ in 0..4 {
        pattern.solve_transpose_in_place(&mut y)?;
        let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(Error::SwitchFailed {
                reason: "no left null vector: inverse iteration broke down".into(),
            });
        }
        y.iter_mut().for_each(|v| *v /= norm);
    }
    y.truncate(m);
    Ok(y)
}
