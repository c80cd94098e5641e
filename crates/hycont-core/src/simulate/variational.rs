//! Variational equations integrated alongside the state, and their update at jumps.
//!
//! The augmented state is $y = (x, \Phi, \Phi_p)$ with $\Phi = \partial x / \partial x_0$
//! ($n \times n$, column-major) and $\Phi_p = \partial x / \partial p$ ($n \times n_p$, or only
//! the columns of selected parameters):
//! $$\dot\Phi = f_x \Phi, \qquad \dot\Phi_p = f_x \Phi_p + f_p.$$
//! At a jump through event $h$ with reset $g$, from vector field $f^-$ to $f^+$, the saltation
//! matrix
//! $$S = g_x + \frac{(f^+ - g_x f^-)\, h_x^\top}{h_x f^-}$$
//! maps $\Phi^+ = S \Phi^-$ and
//! $\Phi_p^+ = S \Phi_p^- + g_p + (f^+ - g_x f^-)\, h_p^\top / (h_x f^-)$
//! (the event time moves with the initial state and the parameters).

use crate::error::{Error, Result};
use crate::system::{EventId, HybridJacobians, HybridSystem, Mode};

/// How the simulator extends the state: plain, or with variational equations.
pub(crate) trait Extension<S: HybridSystem + ?Sized> {
    /// Dimension of the augmented state.
    fn dim(&self) -> usize;
    /// Writes the initial augmented state (the state followed by the identity and zeros).
    fn initial(&self, x0: &[f64], y: &mut [f64]);
    /// Right-hand side of the augmented system.
    fn rhs(&mut self, system: &S, mode: Mode, p: &[f64], y: &[f64], dy: &mut [f64]);
    /// Applies the reset of `event` (and the saltation update) to the augmented state.
    #[allow(clippy::too_many_arguments)]
    fn jump(
        &mut self,
        system: &S,
        event: EventId,
        from: Mode,
        to: Mode,
        t: f64,
        p: &[f64],
        y_minus: &[f64],
        y_plus: &mut [f64],
    ) -> Result<()>;
}

/// The state only.
pub(crate) struct Plain {
    pub n: usize,
}

impl<S: HybridSystem + ?Sized> Extension<S> for Plain {
    fn dim(&self) -> usize {
        self.n
    }
    fn initial(&self, x0: &[f64], y: &mut [f64]) {
        y.copy_from_slice(x0);
    }
    #[inline]
    fn rhs(&mut self, system: &S, mode: Mode, p: &[f64], y: &[f64], dy: &mut [f64]) {
        system.vector_field(mode, y, p, dy);
    }
    fn jump(
        &mut self,
        system: &S,
        event: EventId,
        _from: Mode,
        _to: Mode,
        _t: f64,
        p: &[f64],
        y_minus: &[f64],
        y_plus: &mut [f64],
    ) -> Result<()> {
        system.reset(event, y_minus, p, y_plus);
        Ok(())
    }
}

/// The state with $\Phi$ and the columns of $\Phi_p$ of the selected parameters.
#[derive(Debug, Clone)]
pub(crate) struct Variational {
    n: usize,
    /// Parameters whose columns of $\Phi_p$ are integrated, in increasing order.
    selected: Vec<usize>,
    a: Vec<f64>,
    b: Vec<f64>,
    // Jump work space.
    fm: Vec<f64>,
    fp: Vec<f64>,
    hx: Vec<f64>,
    hp: Vec<f64>,
    gx: Vec<f64>,
    gp: Vec<f64>,
    salt: Vec<f64>,
    v: Vec<f64>,
}

impl Variational {
    pub(crate) fn new(n: usize, np: usize, selected: Vec<usize>) -> Self {
        Self {
            n,
            selected,
            a: vec![0.0; n * n],
            b: vec![0.0; n * np],
            fm: vec![0.0; n],
            fp: vec![0.0; n],
            hx: vec![0.0; n],
            hp: vec![0.0; np],
            gx: vec![0.0; n * n],
            gp: vec![0.0; n * np],
            salt: vec![0.0; n * n],
            v: vec![0.0; n],
        }
    }

    /// Whether the work space is for state dimension `n` and `np` parameters.
    pub(crate) fn fits(&self, n: usize, np: usize) -> bool {
        self.n == n && self.hp.len() == np
    }

    /// Selects the parameters whose columns of $\Phi_p$ are integrated (increasing order).
    pub(crate) fn select(&mut self, selected: impl Iterator<Item = usize>) {
        self.selected.clear();
        self.selected.extend(selected);
    }

    /// Columns of sensitivities carried: $n$ for $\Phi$ plus one per selected parameter.
    fn columns(&self) -> usize {
        self.n + self.selected.len()
    }

    fn with_params(&self) -> bool {
        !self.selected.is_empty()
    }
}

impl<S: HybridJacobians + ?Sized> Extension<S> for Variational {
    fn dim(&self) -> usize {
        self.n * (1 + self.columns())
    }

    fn initial(&self, x0: &[f64], y: &mut [f64]) {
        let n = self.n;
        y.fill(0.0);
        y[..n].copy_from_slice(x0);
        for i in 0..n {
            y[n + i + i * n] = 1.0;
        }
    }

    fn rhs(&mut self, system: &S, mode: Mode, p: &[f64], y: &[f64], dy: &mut [f64]) {
        let n = self.n;
        let x = &y[..n];
        let bp = if self.with_params() {
            Some(&mut self.b[..])
        } else {
            None
        };
        system.vector_field_with_jacobian(mode, x, p, &mut dy[..n], &mut self.a, bp);
        // Column j of the sensitivities: f_x times column j (plus f_p's column for parameters).
        let cols = self.columns();
        let sens = (&y[n..n * (1 + cols)], &mut dy[n..n * (1 + cols)]);
        let fp = (&self.b[..], &self.selected[..]);
        match n {
            1 => sensitivity_rhs::<1>(&self.a, fp, sens),
            2 => sensitivity_rhs::<2>(&self.a, fp, sens),
            3 => sensitivity_rhs::<3>(&self.a, fp, sens),
            4 => sensitivity_rhs::<4>(&self.a, fp, sens),
            5 => sensitivity_rhs::<5>(&self.a, fp, sens),
            6 => sensitivity_rhs::<6>(&self.a, fp, sens),
            _ => sensitivity_rhs_any(n, &self.a, fp, sens),
        }
    }

    fn jump(
        &mut self,
        system: &S,
        event: EventId,
        from: Mode,
        to: Mode,
        t: f64,
        p: &[f64],
        y_minus: &[f64],
        y_plus: &mut [f64],
    ) -> Result<()> {
        let n = self.n;
        let xm = &y_minus[..n];
        system.vector_field(from, xm, p, &mut self.fm);
        let hp = if self.with_params() {
            Some(&mut self.hp[..])
        } else {
            None
        };
        system.event_gradient(event, xm, p, &mut self.hx, hp);
        system.reset(event, xm, p, &mut y_plus[..n]);
        let gp = if self.with_params() {
            Some(&mut self.gp[..])
        } else {
            None
        };
        system.reset_jacobian(event, xm, p, &mut self.gx, gp);
        system.vector_field(to, &y_plus[..n], p, &mut self.fp);
        let denom: f64 = self.hx.iter().zip(&self.fm).map(|(a, b)| a * b).sum();
        let scale: f64 = self
            .hx
            .iter()
            .zip(&self.fm)
            .map(|(a, b)| (a * b).abs())
            .sum::<f64>()
            .max(f64::MIN_POSITIVE);
        if denom.abs() <= 1e-13 * scale || denom == 0.0 {
            return Err(Error::InvalidTransition {
                t,
                mode: from,
                reason: format!(
                    "{event} is crossed tangentially (grazing: dh/dt = {denom:e}); \
                     the saltation matrix is undefined"
                ),
            });
        }
        // v = f+ - g_x f-
        for i in 0..n {
            let mut acc = self.fp[i];
            for k in 0..n {
                acc -= self.gx[i + k * n] * self.fm[k];
            }
            self.v[i] = acc;
        }
        for j in 0..n {
            for i in 0..n {
                self.salt[i + j * n] = self.gx[i + j * n] + self.v[i] * self.hx[j] / denom;
            }
        }
        for j in 0..self.columns() {
            let col = &y_minus[n + j * n..n + (j + 1) * n];
            for i in 0..n {
                let mut acc = 0.0;
                for (k, c) in col.iter().enumerate() {
                    acc += self.salt[i + k * n] * c;
                }
                if j >= n {
                    let q = self.selected[j - n];
                    acc += self.gp[i + q * n] + self.v[i] * self.hp[q] / denom;
                }
                y_plus[n + j * n + i] = acc;
            }
        }
        Ok(())
    }
}

/// $\dot\Phi = f_x \Phi$ and $\dot\Phi_p = f_x \Phi_p + f_p$, column by column: `a` is $f_x$
/// (column-major), `b` holds $f_p$'s columns of every parameter and `selected` the parameters of
/// the columns after the first `n`. The state dimension `N` is known at compile time, so the
/// accumulators stay in registers; the sums are [`sensitivity_rhs_any`]'s, term by term in the
/// same order.
fn sensitivity_rhs<const N: usize>(
    a: &[f64],
    (b, selected): (&[f64], &[usize]),
    (y, dy): (&[f64], &mut [f64]),
) {
    let mut fx = [[0.0; N]; N];
    for (to, from) in fx.iter_mut().zip(a.chunks_exact(N)) {
        to.copy_from_slice(from);
    }
    for (j, (col, out)) in y.chunks_exact(N).zip(dy.chunks_exact_mut(N)).enumerate() {
        let mut acc = [0.0; N];
        if j >= N {
            let q = selected[j - N];
            acc.copy_from_slice(&b[q * N..(q + 1) * N]);
        }
        for (fx_k, &c) in fx.iter().zip(col) {
            for (acc_i, &f) in acc.iter_mut().zip(fx_k) {
                *acc_i += f * c;
            }
        }
        out.copy_from_slice(&acc);
    }
}

/// [`sensitivity_rhs`] for any state dimension `n`.
fn sensitivity_rhs_any(
    n: usize,
    a: &[f64],
    (b, selected): (&[f64], &[usize]),
    (y, dy): (&[f64], &mut [f64]),
) {
    for (j, (col, out)) in y.chunks_exact(n).zip(dy.chunks_exact_mut(n)).enumerate() {
        for (i, o) in out.iter_mut().enumerate() {
            let mut acc = if j >= n {
                b[selected[j - n] * n + i]
            } else {
                0.0
            };
            for (k, c) in col.iter().enumerate() {
                acc += a[i + k * n] * c;
            }
            *o = acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{sensitivity_rhs, sensitivity_rhs_any};
    use proptest::prelude::*;

    /// $f_x \Phi + [0\ f_p]$ column by column, from the definition (the direct term first).
    fn reference(n: usize, a: &[f64], b: &[f64], selected: &[usize], y: &[f64]) -> Vec<f64> {
        let cols = y.len() / n;
        let mut out = vec![0.0; y.len()];
        for j in 0..cols {
            for i in 0..n {
                let mut acc = if j >= n {
                    b[selected[j - n] * n + i]
                } else {
                    0.0
                };
                for k in 0..n {
                    acc += a[i + k * n] * y[k + j * n];
                }
                out[i + j * n] = acc;
            }
        }
        out
    }

    proptest! {
        /// The kernel for a dimension known at compile time and the general one give the
        /// definition's sums exactly (the same terms in the same order), with and without
        /// parameter columns.
        #[test]
        fn kernels_match_the_definition(
            values in proptest::collection::vec(-3.0f64..3.0, 4 * 4 + 4 * 3 + 4 * 6),
            with_params in any::<bool>(),
        ) {
            let n = 4;
            let (a, rest) = values.split_at(n * n);
            let (b, y) = rest.split_at(n * 3);
            let selected: &[usize] = if with_params { &[0, 2] } else { &[] };
            let y = &y[..n * (n + selected.len())];
            let want = reference(n, a, b, selected, y);
            let mut fixed = vec![0.0; y.len()];
            sensitivity_rhs::<4>(a, (b, selected), (y, &mut fixed));
            let mut any = vec![0.0; y.len()];
            sensitivity_rhs_any(n, a, (b, selected), (y, &mut any));
            prop_assert_eq!(&fixed, &want);
            prop_assert_eq!(&any, &want);
        }
    }
}
