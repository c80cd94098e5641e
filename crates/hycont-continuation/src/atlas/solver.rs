//! The linear algebra of a two-dimensional atlas: the projection corrector on
//! $[F(u); (W T)^\top (u - u_p)] = 0$, the tangent plane from the null space of $J$, and the
//! fold test $\det [J; e_{p_1}^\top; e_{p_2}^\top]$.

use crate::error::{Error, Result};
use crate::{ContinuationProblem, PointInfo};
use hycont_core::linalg::SparsePattern;
use hycont_core::problem::{JacobianUse, NewtonFailure, NewtonSettings};

/// A tangent basis: two $W$-orthonormal vectors spanning the null space of $J$.
pub(super) type Basis = [Vec<f64>; 2];

/// The corrector and its factorisation for a problem with two more unknowns than equations.
pub(super) struct Solver<'p, 'a, P: ContinuationProblem<'a> + ?Sized> {
    pub(super) p: &'p mut P,
    /// Unknowns.
    pub(super) n: usize,
    /// Entries of $J$ (the augmented matrix's first values).
    k: usize,
    pattern: SparsePattern,
    values: Vec<f64>,
    res: Vec<f64>,
    /// Arclength weights.
    pub(super) w: Vec<f64>,
    /// The two parameters' indices in the unknowns.
    pub(super) params: [usize; 2],
    newton: NewtonSettings,
    /// Corrector solves and Jacobian factorisations so far.
    pub(super) corrections: usize,
    pub(super) factorisations: usize,
    _marker: std::marker::PhantomData<&'a ()>,
}

/// $\langle a, b \rangle_W$.
pub(super) fn wdot(w: &[f64], a: &[f64], b: &[f64]) -> f64 {
    w.iter().zip(a).zip(b).map(|((w, a), b)| w * a * b).sum()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

impl<'p, 'a, P: ContinuationProblem<'a> + ?Sized> Solver<'p, 'a, P> {
    pub(super) fn new(p: &'p mut P, params: [usize; 2], newton: NewtonSettings) -> Result<Self> {
        let problem = p.problem();
        let (n, m) = (problem.unknowns(), problem.equations());
        if n != m + 2 {
            return Err(Error::InvalidSetting {
                name: "atlas problem",
                value: n as f64 - m as f64,
                reason: "an atlas needs exactly two more unknowns than equations",
            });
        }
        if params[0] == params[1] || params.iter().any(|&i| i >= n) {
            return Err(Error::InvalidSetting {
                name: "atlas parameter index",
                value: params[1] as f64,
                reason: "needs two different unknowns of the problem",
            });
        }
        let mut entries = problem.jacobian_entries();
        let k = entries.len();
        entries.extend((0..n).map(|j| (m, j)));
        entries.extend((0..n).map(|j| (m + 1, j)));
        let blocks = problem.elimination_blocks();
        let pattern = SparsePattern::with_blocks(n, n, &entries, &blocks)?;
        let w = match p.unknown_weights() {
            Some(w) if w.len() == n && w.iter().all(|&x| x > 0.0 && x.is_finite()) => w,
            Some(w) => {
                return Err(Error::InvalidSetting {
                    name: "unknown_weights",
                    value: w.len() as f64,
                    reason: "need one finite positive weight per unknown",
                });
            }
            None => vec![1.0; n],
        };
        Ok(Self {
            p,
            n,
            k,
            pattern,
            values: Vec::new(),
            res: vec![0.0; n],
            w,
            params,
            newton,
            corrections: 0,
            factorisations: 0,
            _marker: std::marker::PhantomData,
        })
    }

    /// The unit ($W$-norm) directions of the two parameters: the tangent plane a start is
    /// corrected and oriented against.
    pub(super) fn parameter_basis(&self) -> Basis {
        let e = |i: usize| {
            let mut v = vec![0.0; self.n];
            v[i] = 1.0 / self.w[i].sqrt();
            v
        };
        [e(self.params[0]), e(self.params[1])]
    }

    /// Evaluates $F(u)$ into the residual's first rows and factorises $[J(u); r_0; r_1]$.
    fn factor(&mut self, u: &[f64], rows: &[Vec<f64>; 2], purpose: JacobianUse) -> Result<()> {
        let m = self.n - 2;
        self.factorisations += 1;
        let mut values = std::mem::take(&mut self.values);
        self.p
            .problem()
            .evaluate_for(u, &mut self.res[..m], &mut values, purpose)?;
        values.truncate(self.k);
        values.reserve_exact(rows[0].len() + rows[1].len());
        values.extend_from_slice(&rows[0]);
        values.extend_from_slice(&rows[1]);
        let out = self.pattern.factorize(&values);
        self.values = values;
        Ok(out?)
    }

    /// The weighted rows $(W t_0, W t_1)$ of a basis.
    fn rows(&self, basis: &Basis) -> [Vec<f64>; 2] {
        let row = |t: &[f64]| self.w.iter().zip(t).map(|(w, t)| w * t).collect();
        [row(&basis[0]), row(&basis[1])]
    }

    /// Newton on $[F(u); (W T)^\top (u - u_p)] = 0$ from the prediction `u_p` (the solution
    /// in the normal space of `basis` through `u_p`); returns it and the iterations, and
    /// leaves $[J; (WT)^\top]$ factorised exactly at the solution.
    pub(super) fn project(&mut self, u_p: &[f64], basis: &Basis) -> Result<(Vec<f64>, usize)> {
        self.corrections += 1;
        let rows = self.rows(basis);
        let ns = self.newton;
        let mut u = u_p.to_vec();
        let mut last_step = f64::INFINITY;
        for it in 0..=ns.max_iterations {
            self.factor(&u, &rows, JacobianUse::Exact)?;
            let m = self.n - 2;
            for (r, row) in rows.iter().enumerate() {
                self.res[m + r] = row
                    .iter()
                    .zip(&u)
                    .zip(u_p)
                    .map(|((a, x), y)| a * (x - y))
                    .sum();
            }
            let res = max_abs(&self.res);
            let scale = 1.0 + max_abs(&u);
            if !res.is_finite() {
                break;
            }
            if it > 0 && res <= ns.residual_tol && last_step <= ns.tol.sqrt() * scale {
                return Ok((u, it));
            }
            if it == ns.max_iterations {
                break;
            }
            let mut du: Vec<f64> = self.res.iter().map(|r| -r).collect();
            self.pattern.solve_in_place(&mut du)?;
            last_step = max_abs(&du);
            if !(last_step <= 1e3 * scale) {
                break;
            }
            u.iter_mut().zip(&du).for_each(|(x, d)| *x += d);
        }
        Err(Error::Core(hycont_core::Error::NewtonFailed {
            reason: format!(
                "the atlas corrector did not converge in {} iterations (residual {:e})",
                ns.max_iterations,
                max_abs(&self.res)
            ),
            failure: NewtonFailure::Diverging,
            history: Vec::new(),
        }))
    }

    /// Factorises $[J(u); (W T)^\top]$ at `u` (a saved chart with its tangent basis `basis`)
    /// as [`Solver::project`] leaves it at its solution; the largest residual $|F(u)|$.
    pub(super) fn factor_at(&mut self, u: &[f64], basis: &Basis) -> Result<f64> {
        let rows = self.rows(basis);
        self.factor(u, &rows, JacobianUse::Exact)?;
        Ok(max_abs(&self.res[..self.n - 2]))
    }

    /// The tangent plane at the point [`Solver::project`] converged to: the null space of
    /// $J$, from the factorisation of $[J; (W T)^\top]$ ($x_a$ with $J x_a = 0$,
    /// $\langle t_b, x_a \rangle_W = \delta_{ab}$), $W$-orthonormalised.
    pub(super) fn tangent_plane(&mut self) -> Result<Basis> {
        let n = self.n;
        let mut x = vec![0.0; 2 * n];
        x[n - 2] = 1.0;
        x[2 * n - 1] = 1.0;
        self.pattern.solve_many_in_place(&mut x, 2)?;
        let (a, b) = x.split_at(n);
        let mut t0 = a.to_vec();
        let mut t1 = b.to_vec();
        let n0 = wdot(&self.w, &t0, &t0).sqrt();
        t0.iter_mut().for_each(|v| *v /= n0);
        let c = wdot(&self.w, &t0, &t1);
        t1.iter_mut().zip(&t0).for_each(|(v, t)| *v -= c * t);
        let n1 = wdot(&self.w, &t1, &t1).sqrt();
        if !(n0 > 0.0 && n0.is_finite() && n1 > 1e-12 * n0 && n1.is_finite()) {
            return Err(Error::InvalidSetting {
                name: "atlas tangent plane",
                value: n1,
                reason: "the null space of the Jacobian is not two-dimensional here",
            });
        }
        t1.iter_mut().for_each(|v| *v /= n1);
        Ok([t0, t1])
    }

    /// The analysis at the point [`Solver::project`] converged to (reads the factorisation).
    pub(super) fn analyse(&mut self, u: &[f64]) -> Result<PointInfo> {
        Ok(self.p.analyse_factorised(u, &self.pattern)?)
    }

    /// Sign and log-magnitude of $\det [J(u); e_{p_1}^\top; e_{p_2}^\top]$ with the Jacobian
    /// of the last exact factorisation (at `u`): zero where the problem at fixed parameters
    /// is singular, a fold over the parameter plane.
    pub(super) fn fold_determinant(&mut self) -> Result<(f64, f64)> {
        let n = self.n;
        let mut values = std::mem::take(&mut self.values);
        values.truncate(self.k);
        values.resize(self.k + 2 * n, 0.0);
        values[self.k + self.params[0]] = 1.0;
        values[self.k + n + self.params[1]] = 1.0;
        self.factorisations += 1;
        let out = self.pattern.factorize(&values);
        self.values = values;
        out?;
        Ok(self.pattern.determinant()?)
    }
}
