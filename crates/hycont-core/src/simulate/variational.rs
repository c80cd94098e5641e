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
use crate::system::{EventId, HybridJacobians, HybridSystem, Mode, ParamId, Tangents};

/// How the simulator extends the state: plain, or with variational equations.
pub(crate) trait Extension<S: HybridSystem + ?Sized> {
    /// Dimension of the augmented state.
    fn dim(&self) -> usize;
    /// The state's dimension in the mode the run continues in (after a jump between modes of
    /// different dimensions; only plain runs cross them).
    fn set_state_dim(&mut self, n: usize);
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
    fn set_state_dim(&mut self, n: usize) {
        self.n = n;
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
    selected: Vec<ParamId>,
    /// Work space of [`HybridJacobians::vector_field_with_tangents`]: $n (n + n_p)$ values.
    work: Vec<f64>,
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
    pub(crate) fn new(n: usize, np: usize, selected: Vec<ParamId>) -> Self {
        Self {
            n,
            selected,
            work: vec![0.0; n * (n + np)],
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
    pub(crate) fn select(&mut self, selected: impl Iterator<Item = ParamId>) {
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

    fn set_state_dim(&mut self, n: usize) {
        // Sensitivity runs are refused for systems whose modes differ in dimension.
        debug_assert_eq!(n, self.n, "a sensitivity run across state dimensions");
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
        let cols = self.columns();
        let (f, out) = dy[..n * (1 + cols)].split_at_mut(n);
        let tangents = Tangents {
            x: &y[n..n * (1 + cols)],
            params: &self.selected,
            out,
            work: &mut self.work,
        };
        system.vector_field_with_tangents(mode, &y[..n], p, f, tangents);
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
                    let q = self.selected[j - n].index();
                    acc += self.gp[i + q * n] + self.v[i] * self.hp[q] / denom;
                }
                y_plus[n + j * n + i] = acc;
            }
        }
        Ok(())
    }
}
