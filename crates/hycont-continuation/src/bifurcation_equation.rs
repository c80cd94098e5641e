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
use crate::switch::inverse_iteration_on;
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
    // Where the augmented matrix is singular to the last bit (a branch point located exactly),
    // a hair along the known branch (1e-9 of the point's scale), as for the right null vector.
    let psi = match left_null_vector(p, u, known) {
        Ok(psi) => psi,
        Err(_) => {
            let hair = 1e-9 * (1.0 + max_norm(u));
            let moved: Vec<f64> = u.iter().zip(known).map(|(a, b)| a + hair * b).collect();
            left_null_vector(p, &moved, known)?
        }
    };
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
    let m = problem.equations();
    let mut y = inverse_iteration_on(problem, u, row, true)?;
    y.truncate(m);
    Ok(y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PointInfo;
    use hycont_core::problem::{Problem, ZeroFunction};

    /// One scalar equation $F(x, \lambda)$, given with its partial derivatives as
    /// `(F, F_x, F_lambda)`.
    struct Scalar(Box<dyn Fn(f64, f64) -> (f64, f64, f64)>);

    impl ZeroFunction for Scalar {
        fn unknowns(&self) -> usize {
            2
        }
        fn equations(&self) -> usize {
            1
        }
        fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
            vec![(0, 0), (0, 1)]
        }
        fn evaluate(
            &mut self,
            u: &[f64],
            r: &mut [f64],
            j: Option<&mut [f64]>,
        ) -> hycont_core::Result<()> {
            let (f, fx, fl) = (self.0)(u[0], u[1]);
            r[0] = f;
            if let Some(j) = j {
                j[0] = fx;
                j[1] = fl;
            }
            Ok(())
        }
    }

    /// The continuation problem of `f` (unknowns $x$, $\lambda$).
    fn toy(f: impl Fn(f64, f64) -> (f64, f64, f64) + 'static) -> Toy<'static> {
        let mut problem = Problem::new(2);
        problem
            .add_part(Box::new(Scalar(Box::new(f))), vec![0, 1])
            .unwrap();
        Toy(problem)
    }

    struct Toy<'a>(Problem<'a>);

    impl<'a> ContinuationProblem<'a> for Toy<'a> {
        fn problem(&mut self) -> &mut Problem<'a> {
            &mut self.0
        }
        fn parameter_index(&self) -> usize {
            1
        }
        fn parameter_position(&self) -> usize {
            0
        }
        fn parameter_name(&self) -> String {
            "lambda".into()
        }
        fn parameter_names(&self) -> Vec<String> {
            vec!["lambda".into()]
        }
        fn monitor_names(&self) -> Vec<String> {
            Vec::new()
        }
        fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
            Ok(PointInfo {
                params: vec![u[1]],
                monitors: Vec::new(),
                multipliers: Vec::new(),
                trivial: Vec::new(),
                branch_point_factor: None,
                discretisation_error: None,
            })
        }
    }

    /// $F(x, \lambda) = x (x - c \lambda)$: the branches $x = 0$ and $x = c \lambda$ cross at
    /// the origin at the angle $\arctan c$ (not a right angle for $c \ne 0$). $J(0) = 0$, so
    /// the null space is the plane and $\psi = 1$; $F_{xx} = 2$, $F_{x\lambda} = -c$,
    /// $F_{\lambda\lambda} = 0$. With the known tangent $(0, 1)$ (the branch $x = 0$) and
    /// $\varphi_2 = (1, 0)$: $a_{12} = -c$, $a_{22} = 2$, and the second tangent is
    /// $\propto -2 (0, 1) - 2c (1, 0)$, i.e. $(c, 1) / \sqrt{1 + c^2}$ oriented along
    /// $\varphi_2$.
    #[test]
    fn the_second_tangent_of_a_crossing_at_any_angle() {
        for c in [0.3, -2.0, 5.0] {
            let mut toy = toy(move |x, l| (x * (x - c * l), 2.0 * x - c * l, -c * x));
            let t = second_branch_tangent(&mut toy, &[0.0, 0.0], &[0.0, 1.0], &[1.0, 0.0]).unwrap();
            let norm = (1.0 + c * c).sqrt();
            let expected = [c.abs() / norm, c.signum() / norm];
            assert!(
                (t[0] - expected[0]).abs() < 1e-9 && (t[1] - expected[1]).abs() < 1e-9,
                "c = {c}: {t:?} vs {expected:?}"
            );
        }
    }

    /// $F = x (x^2 - \lambda)$ or $F = x^2$ (`double`): at a
    /// pitchfork the second tangent of the known branch $x^2 = \lambda$ (tangent $(1, 0)$) is
    /// the trivial branch's $(0, 1)$ ($a_{12} = F_{x\lambda} = -1$, $a_{22} = F_{\lambda\lambda}
    /// = 0$); for $F = x^2$ the line $x = 0$ is a double root ($a_{12} = 0$, $a_{22} = 2$): no
    /// transversal crossing, a typed error.
    #[test]
    fn a_pitchfork_and_a_double_root() {
        let fork = || toy(|x, l| (x * (x * x - l), 3.0 * x * x - l, -x));
        let double = || toy(|x, _| (x * x, 2.0 * x, 0.0));
        let t = second_branch_tangent(&mut fork(), &[0.0, 0.0], &[1.0, 0.0], &[0.0, 1.0]).unwrap();
        assert!(t[0].abs() < 1e-9 && (t[1] - 1.0).abs() < 1e-9, "{t:?}");
        // Singular along the whole line: no left null vector either.
        let e = second_branch_tangent(&mut double(), &[0.0, 0.0], &[0.0, 1.0], &[1.0, 0.0]);
        assert!(
            matches!(e, Err(Error::SwitchFailed { .. } | Error::Core(_))),
            "{e:?}"
        );
        // Off the line's singular point the left null vector exists and the quadratic is
        // degenerate: a12 = 0, a22 = 2.
        let e = second_branch_tangent(&mut double(), &[1e-3, 0.0], &[0.0, 1.0], &[1.0, 0.0]);
        assert!(matches!(e, Err(Error::SwitchFailed { .. })), "{e:?}");
    }
}
