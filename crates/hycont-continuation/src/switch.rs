//! Branch switching at branch points: the second null direction of the Jacobian.

use crate::ContinuationProblem;
use crate::error::{Error, Result};
use hycont_core::linalg::SparsePattern;
use hycont_core::problem::Problem;

/// The sparsity pattern of the augmented Jacobian $[J; r^\top]$ of a problem with one more
/// unknown than equations (a dense last row), and the number of entries of $J$ (which come
/// first in its values). The problem's local blocks are condensed (the last row borders them).
///
/// # Errors
/// [`Error::NotOneDimensional`] if the problem does not have one more unknown than equations.
pub(crate) fn augmented_pattern(problem: &Problem<'_>) -> Result<(SparsePattern, usize)> {
    let (n, m) = (problem.unknowns(), problem.equations());
    if n != m + 1 {
        return Err(Error::NotOneDimensional {
            unknowns: n,
            equations: m,
        });
    }
    let mut entries = problem.jacobian_entries();
    let k = entries.len();
    entries.reserve_exact(n);
    entries.extend((0..n).map(|j| (m, j)));
    let blocks = problem.elimination_blocks();
    Ok((SparsePattern::with_blocks_owned(n, n, entries, &blocks)?, k))
}

/// At a (located) branch point `u` of a branch with tangent `t`, the direction of the other
/// branch: the null vector $\varphi$ of the augmented Jacobian $[J(u); t^\top]$ (so that
/// $J \varphi = 0$, $\varphi \perp t$), by inverse iteration on its LU factorisation.
///
/// # Errors
/// [`Error::SwitchFailed`] if the iteration does not produce a direction in the null space of
/// $J$ (the point is not a branch point).
pub fn branch_switch_direction<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &mut P,
    u: &[f64],
    t: &[f64],
) -> Result<Vec<f64>> {
    let problem = p.problem();
    // Where the augmented Jacobian is singular to the last bit (a branch point located exactly,
    // e.g. a symmetry breaking at a parameter of exactly 0), the iteration runs a hair along
    // the branch (1e-9 of the point's scale: far below a located point's accuracy).
    let mut x = match inverse_iteration(problem, u, t) {
        Ok(x) => x,
        Err(_) => {
            let scale = 1e-9 * (1.0 + hycont_core::linalg::max_norm(u));
            let moved: Vec<f64> = u.iter().zip(t).map(|(a, b)| a + scale * b).collect();
            inverse_iteration(problem, &moved, t)?
        }
    };
    // Remove the tangent component and check that J x is small.
    let tx: f64 = t.iter().zip(&x).map(|(a, b)| a * b).sum();
    for (xi, ti) in x.iter_mut().zip(t) {
        *xi -= tx * ti;
    }
    let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    x.iter_mut().for_each(|v| *v /= norm);
    let jac = problem.dense_jacobian(u)?;
    let jx = jac
        .iter()
        .map(|row| row.iter().zip(&x).map(|(a, b)| a * b).sum::<f64>().abs())
        .fold(0.0f64, f64::max);
    let scale = jac
        .iter()
        .flat_map(|r| r.iter())
        .fold(0.0f64, |acc, v| acc.max(v.abs()));
    if jx > 1e-4 * scale.max(1.0) {
        return Err(Error::SwitchFailed {
            reason: format!("no second null direction: |J phi| = {jx:e}"),
        });
    }
    Ok(x)
}

/// Four steps of inverse iteration on $[J(u); t^\top]$ from a fixed, generic start vector:
/// the direction of its smallest singular value, normalised.
fn inverse_iteration(problem: &mut Problem<'_>, u: &[f64], t: &[f64]) -> Result<Vec<f64>> {
    inverse_iteration_on(problem, u, t, false)
}

/// [`inverse_iteration`] on $[J(u); t^\top]$ or, with `transposed`, on its transpose (toward
/// its left null vector).
pub(crate) fn inverse_iteration_on(
    problem: &mut Problem<'_>,
    u: &[f64],
    t: &[f64],
    transposed: bool,
) -> Result<Vec<f64>> {
    let (mut pattern, k) = augmented_pattern(problem)?;
    let (n, m) = (problem.unknowns(), problem.equations());
    let mut values = Vec::new();
    let mut res = vec![0.0; m];
    problem.evaluate(u, &mut res, Some(&mut values))?;
    values.truncate(k);
    values.reserve_exact(t.len());
    values.extend_from_slice(t);
    pattern.factorize(&values)?;
    let mut x: Vec<f64> = (0..n)
        .map(|i| ((i as f64 + 1.0) * 0.754_877_666).fract() - 0.5)
        .collect();
    for _ in 0..4 {
        if transposed {
            pattern.solve_transpose_in_place(&mut x)?;
        } else {
            pattern.solve_in_place(&mut x)?;
        }
        let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(Error::SwitchFailed {
                reason: "inverse iteration broke down".into(),
            });
        }
        x.iter_mut().for_each(|v| *v /= norm);
    }
    Ok(x)
}

/// The directions of the solution set through a solution `u`: unit null vectors of the
/// Jacobian $J$ (one more unknown than equations): one where `u` is a regular point (the
/// tangent), two (orthonormal) where the rank of $J$ drops by one, at a branch point where two
/// families cross (e.g. at a grazing, the family of the new signature and a family whose new
/// segment stays of zero length).
///
/// # Errors
/// [`Error::SwitchFailed`] when no null direction is found (`u` is not a solution), or the
/// problem is not one-dimensional.
pub fn null_directions<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &mut P,
    u: &[f64],
) -> Result<Vec<Vec<f64>>> {
    let problem = p.problem();
    let n = problem.unknowns();
    let generic: Vec<f64> = (0..n)
        .map(|i| ((i as f64 + 1.0) * 0.618_033_988_7).fract() - 0.5)
        .collect();
    let first = null_vector(problem, u, &generic)?.ok_or_else(|| Error::SwitchFailed {
        reason: "no null direction of the Jacobian there".into(),
    })?;
    let mut out = vec![first.clone()];
    // A second one orthogonal to the first: the null vector of [J; x1^T] (at a regular point
    // that is x1 itself, removed below).
    if let Some(mut second) = null_vector(problem, u, &first)? {
        let c: f64 = first.iter().zip(&second).map(|(a, b)| a * b).sum();
        second.iter_mut().zip(&first).for_each(|(x, f)| *x -= c * f);
        let norm = second.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > 1e-3 {
            second.iter_mut().for_each(|v| *v /= norm);
            if null_defect(problem, u, &second)? <= NULL_TOL {
                out.push(second);
            }
        }
    }
    Ok(out)
}

/// How small $|J x|$ must be, relative to $\max_i \sum_j |J_{ij} x_j|$, for `x` to be a null
/// direction.
const NULL_TOL: f64 = 1e-6;

/// A unit null vector of $J$ at `u` with the row `row` fixing it: the solution of
/// $[J; r^\top] x = e_N$ (one solve: at a branch point, where that matrix is singular, the
/// solve is a step of inverse iteration toward its null vector), if it is one.
fn null_vector(problem: &mut Problem<'_>, u: &[f64], row: &[f64]) -> Result<Option<Vec<f64>>> {
    let (mut pattern, k) = augmented_pattern(problem)?;
    let (n, m) = (problem.unknowns(), problem.equations());
    let mut values = Vec::new();
    let mut res = vec![0.0; m];
    problem.evaluate(u, &mut res, Some(&mut values))?;
    values.truncate(k);
    values.reserve_exact(row.len());
    values.extend_from_slice(row);
    if pattern.factorize(&values).is_err() {
        return Ok(inverse_iteration(problem, u, row).ok());
    }
    let mut x = vec![0.0; n];
    x[n - 1] = 1.0;
    if pattern.solve_in_place(&mut x).is_err() {
        return Ok(inverse_iteration(problem, u, row).ok());
    }
    let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return Ok(None);
    }
    x.iter_mut().for_each(|v| *v /= norm);
    Ok((null_defect(problem, u, &x)? <= NULL_TOL).then_some(x))
}

/// $\max_i |(J x)_i|$ over $\max_i \sum_j |J_{ij} x_j|$ at `u`.
fn null_defect(problem: &mut Problem<'_>, u: &[f64], x: &[f64]) -> Result<f64> {
    let m = problem.equations();
    let mut values = Vec::new();
    let mut res = vec![0.0; m];
    problem.evaluate(u, &mut res, Some(&mut values))?;
    let (mut jx, mut scale) = (vec![0.0; m], vec![0.0; m]);
    for ((i, j), v) in problem.jacobian_entries().into_iter().zip(&values) {
        jx[i] += v * x[j];
        scale[i] += (v * x[j]).abs();
    }
    let worst = jx.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let scale = scale.iter().fold(0.0f64, |a, v| a.max(*v));
    Ok(if scale > 0.0 {
        worst / scale
    } else {
        f64::INFINITY
    })
}
