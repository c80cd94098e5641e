//! The defining equation of fold, period-doubling and symmetry-breaking curves as a minimally
//! augmented system on the discretised boundary-value problem itself (Govaerts 2000; as in
//! MatCont and BifurcationKit), so that it is exact for either discretisation.
//!
//! Let $J_c(u)$ be the Jacobian of the orbit equations with respect to the segment states and
//! durations (parameters held) with the closure's coupling scaled by $c$: the linearised
//! problem closed by $\delta x_K = c\,\delta x_0$ ($c\,S\,\delta x_0$ on a half orbit). Solving
//! the event conditions for the duration changes reduces it to $\det(c^{-1} P - I)$ with $P$ the
//! Poincaré map's Jacobian (the monodromy with its flow-direction multiplier replaced by 0), so
//! $J_c$ is singular exactly where a non-trivial multiplier equals $c$: $c = 1$ a fold, $c = -1$
//! a period doubling (on a half orbit: a symmetric fold and a symmetry-breaking branch point).
//! With borders $b$, $d$ the bordered matrix
//! $$B = \begin{pmatrix} J_c & b \\ d^\top & 0 \end{pmatrix}, \qquad
//!   B \begin{pmatrix} v \\ g \end{pmatrix} = \begin{pmatrix} 0 \\ 1 \end{pmatrix}$$
//! is regular near the curve and defines $g(u)$, which vanishes exactly where $J_c$ is singular.
//! Its gradient is $g_u = -w^\top (\partial_u J_c)\, v$ with $B^\top (w, g) = e$, computed as a
//! central difference of $J(u \pm \varepsilon v)^\top w$: two more Jacobian evaluations, no
//! second derivatives of the system. The borders are refreshed to the current null vectors at
//! every exact evaluation (a converged point), which leaves the curve unchanged.

use hycont_core::linalg::{EliminationBlock, SparsePattern};
use hycont_core::orbit::OrbitEquations;
use hycont_core::problem::{JacobianHints, JacobianUse, LocalBlock, ZeroFunction};
use hycont_core::{Error, Result};

/// The orbit equations plus the singularity condition of the closure-scaled Jacobian.
pub(crate) struct SingularClosure<'a> {
    inner: Box<dyn OrbitEquations + 'a>,
    factor: f64,
    /// Equations of the inner part (= its state and duration unknowns).
    m: usize,
    /// Unknowns of the inner part.
    nu: usize,
    pattern: Vec<(usize, usize)>,
    closure: Vec<usize>,
    /// Positions of the inner entries in the state and duration columns.
    keep: Vec<usize>,
    bordered: SparsePattern,
    b: Vec<f64>,
    d: Vec<f64>,
    jv: Vec<f64>,
    jp: Vec<f64>,
    res: Vec<f64>,
    vals: Vec<f64>,
    held: Vec<bool>,
}

/// A fixed, generic unit vector (for the first borders).
fn generic(n: usize, seed: f64) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n)
        .map(|i| ((i as f64 + 1.0) * seed).fract() - 0.5)
        .collect();
    normalize(&mut v);
    v
}

fn normalize(v: &mut [f64]) {
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm > 0.0 {
        v.iter_mut().for_each(|x| *x /= norm);
    }
}

impl<'a> SingularClosure<'a> {
    /// The condition for closure factor `factor` (`1.0` fold, `-1.0` period doubling or
    /// symmetry breaking), with borders fitted at `u0` (a point on or near the curve).
    pub(crate) fn new(
        inner: Box<dyn OrbitEquations + 'a>,
        factor: f64,
        u0: &[f64],
    ) -> Result<Self> {
        let m = inner.equations();
        let nu = inner.unknowns();
        let ns = inner.first_parameter();
        if ns != m {
            return Err(Error::DimensionMismatch {
                what: "orbit equations (states and durations)",
                expected: m,
                found: ns,
            });
        }
        let pattern = inner.jacobian_pattern();
        let closure = inner.closure_entries();
        let keep: Vec<usize> = (0..pattern.len()).filter(|&e| pattern[e].1 < m).collect();
        let mut entries: Vec<(usize, usize)> = keep.iter().map(|&e| pattern[e]).collect();
        entries.extend((0..m).map(|i| (i, m)));
        entries.extend((0..m).map(|j| (m, j)));
        entries.push((m, m));
        // The inner part's local blocks, bordered by the last row and column.
        let blocks: Vec<EliminationBlock> = inner
            .local_blocks()
            .into_iter()
            .map(|b| EliminationBlock {
                rows: b.equations.collect(),
                cols: b.unknowns.collect(),
            })
            .collect();
        let bordered = SparsePattern::with_blocks(m + 1, m + 1, &entries, &blocks)?;
        let mut me = Self {
            inner,
            factor,
            m,
            nu,
            pattern,
            closure,
            keep,
            bordered,
            b: generic(m, 0.754_877_666),
            d: generic(m, 0.569_840_291),
            jv: Vec::new(),
            jp: Vec::new(),
            res: vec![0.0; m],
            vals: Vec::new(),
            held: vec![false; nu],
        };
        // Inverse iteration with the bordered matrix: the borders approach the null vectors.
        me.jacobian_at(u0, &me.held.clone(), true)?;
        for _ in 0..3 {
            let (v, w, _) = me.null_vectors()?;
            me.d = v;
            me.b = w;
            normalize(&mut me.d);
            normalize(&mut me.b);
        }
        Ok(me)
    }

    /// Evaluates the inner residual and exact Jacobian at `u` into `self.res` and `self.jv`
    /// (or `self.jp` when `into_main` is false).
    fn jacobian_at(&mut self, u: &[f64], held: &[bool], into_main: bool) -> Result<()> {
        let mut jac = std::mem::take(if into_main {
            &mut self.jv
        } else {
            &mut self.jp
        });
        jac.resize(self.pattern.len(), 0.0);
        let hints = JacobianHints {
            held,
            purpose: JacobianUse::Exact,
        };
        let out = self
            .inner
            .evaluate_hinted(u, &mut self.res, Some(&mut jac), hints);
        if into_main {
            self.jv = jac;
        } else {
            self.jp = jac;
        }
        out
    }

    /// Factorises the bordered matrix of `self.jv` and returns $v$, $w$ and $g$.
    fn null_vectors(&mut self) -> Result<(Vec<f64>, Vec<f64>, f64)> {
        let m = self.m;
        let mut jc = self.jv.clone();
        for &e in &self.closure {
            jc[e] *= self.factor;
        }
        self.vals.clear();
        self.vals.extend(self.keep.iter().map(|&e| jc[e]));
        self.vals.extend_from_slice(&self.b);
        self.vals.extend_from_slice(&self.d);
        self.vals.push(0.0);
        self.bordered.factorize(&self.vals)?;
        let mut x = vec![0.0; m + 1];
        x[m] = 1.0;
        let mut y = x.clone();
        self.bordered.solve_in_place(&mut x)?;
        self.bordered.solve_transpose_in_place(&mut y)?;
        let g = x[m];
        x.truncate(m);
        y.truncate(m);
        Ok((x, y, g))
    }
}

impl ZeroFunction for SingularClosure<'_> {
    fn unknowns(&self) -> usize {
        self.nu
    }
    fn equations(&self) -> usize {
        self.m + 1
    }
    fn local_blocks(&self) -> Vec<LocalBlock> {
        self.inner.local_blocks()
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let mut p = self.pattern.clone();
        p.extend((0..self.nu).map(|j| (self.m, j)));
        p
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<()> {
        let held = vec![false; self.nu];
        let hints = JacobianHints {
            held: &held,
            purpose: JacobianUse::Exact,
        };
        self.evaluate_hinted(u, residual, jacobian, hints)
    }
    fn evaluate_hinted(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
        hints: JacobianHints<'_>,
    ) -> Result<()> {
        self.held.clear();
        self.held.extend_from_slice(hints.held);
        let held = self.held.clone();
        self.jacobian_at(u, &held, true)?;
        residual[..self.m].copy_from_slice(&self.res);
        let (v, w, g) = self.null_vectors()?;
        residual[self.m] = g;
        let Some(jac) = jacobian else {
            return Ok(());
        };
        let k = self.pattern.len();
        jac[..k].copy_from_slice(&self.jv);
        // g_u = -w^T (dJ/du) v by central differences of J along v.
        let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let umax = u.iter().fold(1.0f64, |a, x| a.max(x.abs()));
        let eps = 1e-6 * umax / vmax.max(f64::MIN_POSITIVE);
        let mut shifted = u.to_vec();
        let mut diff = vec![0.0; k];
        for sign in [1.0, -1.0] {
            for j in 0..self.m {
                shifted[j] = u[j] + sign * eps * v[j];
            }
            self.jacobian_at(&shifted, &held, false)?;
            for (dv, jp) in diff.iter_mut().zip(&self.jp) {
                *dv += sign * jp;
            }
        }
        let row = &mut jac[k..];
        row.fill(0.0);
        for (e, &(i, j)) in self.pattern.iter().enumerate() {
            row[j] -= w[i] * diff[e] / (2.0 * eps);
        }
        // Refresh the borders at points the continuation keeps (exact evaluations).
        if hints.purpose == JacobianUse::Exact {
            self.d = v;
            self.b = w;
            normalize(&mut self.d);
            normalize(&mut self.b);
        }
        Ok(())
    }
}
