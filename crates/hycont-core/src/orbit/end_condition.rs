//! The conditions closing each segment at its end, shared by shooting and collocation.
//!
//! Segment $k$ ends at $y_k$ (of its mode's dimension $n_k$) and must reach the next segment's
//! start $x_{k+1}$ (of dimension $n_{k+1}$; after the last segment: $x_0$, or $S x_0$ for a
//! symmetric closure). At an event $e$ the conditions are $g_e(y_k) - x_{k+1} = 0$ and
//! $h_e(y_k) = 0$; at an interior point $x_c = v$ they are $y_k - x_{k+1} = 0$ and
//! $y_{k,c} - v = 0$: $n_{k+1} + 1$ rows per segment.

use super::signature::{Closure, SegmentEnd, Signature};
use crate::error::{Error, Result, finite_derivative};
use crate::system::{HybridJacobians, Mode};

/// Evaluation and linearisation of the end conditions, with their work space (sized for the
/// largest mode; each segment uses its own $n_{k+1} \times n_k$ part).
pub(crate) struct EndConditions {
    n: usize,
    /// $S$ for a symmetric closure (column-major), else `None`.
    closure: Option<Vec<f64>>,
    /// The dimensions $(n_k, n_{k+1})$ of the last linearisation.
    dims: (usize, usize),
    gx: Vec<f64>,
    gp: Vec<f64>,
    hx: Vec<f64>,
    hp: Vec<f64>,
    gy: Vec<f64>,
    /// Work space: the state a segment must reach (see [`EndConditions::residual`]).
    target: Vec<f64>,
}

impl EndConditions {
    pub(crate) fn new<S: HybridJacobians + ?Sized>(system: &S, signature: &Signature) -> Self {
        let (n, np) = (system.state_dim(), system.parameter_count());
        let closure = match signature.closure() {
            Closure::Periodic => None,
            Closure::Symmetric => system.symmetry().map(|s| s.matrix),
        };
        Self {
            n,
            closure,
            dims: (n, n),
            gx: vec![0.0; n * n],
            gp: vec![0.0; n * np],
            hx: vec![0.0; n],
            hp: vec![0.0; np],
            gy: vec![0.0; n],
            target: vec![0.0; n],
        }
    }

    /// Whether the last segment closes through the symmetry ($x_0$ enters as $S x_0$).
    pub(crate) fn symmetric(&self) -> bool {
        self.closure.is_some()
    }

    /// Writes the state a segment must reach into `out`: the next segment's start, through
    /// the symmetry ($S x_0$) when `wrap` closes a symmetric orbit.
    fn target(
        closure: Option<&[f64]>,
        stride: usize,
        wrap: bool,
        next_start: &[f64],
        out: &mut [f64],
    ) {
        // S's leading block on a first segment of fewer states than the system's largest.
        let n = next_start.len();
        match (closure, wrap) {
            (Some(sm), true) => {
                for (i, o) in out.iter_mut().enumerate() {
                    *o = (0..n).map(|j| sm[i + j * stride] * next_start[j]).sum();
                }
            }
            _ => out.copy_from_slice(next_start),
        }
    }

    /// The $n_{k+1} + 1$ residual rows of a segment in `mode` ending in `y` with `end`,
    /// reaching the next segment's start `next_start` (of its dimension $n_{k+1}$; through the
    /// symmetry when `wrap` closes a symmetric orbit).
    ///
    /// # Errors
    /// [`Error::NonFiniteReset`] or [`Error::NonFiniteEvent`] (at the segment's end, `t` 0)
    /// where the end's reset or event function is not finite at `y`.
    pub(crate) fn residual<S: HybridJacobians + ?Sized>(
        &mut self,
        system: &S,
        (mode, end): (Mode, SegmentEnd),
        y: &[f64],
        p: &[f64],
        (wrap, next_start): (bool, &[f64]),
        out: &mut [f64],
    ) -> Result<()> {
        let n = next_start.len();
        let target = &mut self.target[..n];
        Self::target(self.closure.as_deref(), self.n, wrap, next_start, target);
        let target = &self.target[..n];
        match end {
            SegmentEnd::Event(e) => {
                // NaN marks a component the reset leaves unwritten.
                let gy = &mut self.gy[..n];
                gy.fill(f64::NAN);
                system.reset(e, y, p, gy);
                if let Some(index) = gy.iter().position(|v| !v.is_finite()) {
                    return Err(Error::NonFiniteReset {
                        event: e,
                        index,
                        value: gy[index],
                        state: y.to_vec(),
                    });
                }
                for i in 0..n {
                    out[i] = gy[i] - target[i];
                }
                out[n] = system.event(e, y, p);
                if !out[n].is_finite() {
                    return Err(Error::NonFiniteEvent {
                        event: e,
                        mode,
                        t: 0.0,
                        value: out[n],
                        state: y.to_vec(),
                    });
                }
            }
            SegmentEnd::Interior { component, value } => {
                for i in 0..n {
                    out[i] = y[i] - target[i];
                }
                out[n] = y[component] - value;
            }
        }
        Ok(())
    }

    /// Linearises the conditions at `y` (of the segment's dimension $n_k$) towards a next
    /// start of dimension `n_to` (then read with [`Self::state_derivative`] and
    /// [`Self::parameter_derivative`]).
    ///
    /// # Errors
    /// [`Error::NonFiniteDerivative`] naming the first entry of the reset's Jacobian or the
    /// event's gradient that is not finite.
    pub(crate) fn linearise<S: HybridJacobians + ?Sized>(
        &mut self,
        system: &S,
        end: SegmentEnd,
        (y, n_to): (&[f64], usize),
        p: &[f64],
    ) -> Result<()> {
        let (n, np) = (y.len(), p.len());
        self.dims = (n, n_to);
        let (gx, gp) = (&mut self.gx[..n_to * n], &mut self.gp[..n_to * np]);
        let hx = &mut self.hx[..n];
        match end {
            SegmentEnd::Event(e) => {
                // NaN marks an entry the system leaves unwritten (a Jacobian or gradient of
                // the wrong size): an error naming it below, not a stale value.
                for buffer in [&mut *gx, &mut *gp, &mut *hx, &mut self.hp[..]] {
                    buffer.fill(f64::NAN);
                }
                system.reset_jacobian(e, y, p, gx, Some(gp));
                system.event_gradient(e, y, p, hx, Some(&mut self.hp));
                let reset = || format!("reset of event {e}");
                finite_derivative(gx, n_to, ("state", 0), reset, y)?;
                finite_derivative(gp, n_to, ("parameter", 0), reset, y)?;
                let event = || format!("event function {e}");
                finite_derivative(hx, 1, ("state", 0), event, y)?;
                finite_derivative(&self.hp, 1, ("parameter", 0), event, y)?;
            }
            SegmentEnd::Interior { component, .. } => {
                // The signature keeps the mode at interior points: n_to = n.
                gx.fill(0.0);
                for i in 0..n {
                    gx[i + i * n_to] = 1.0;
                }
                gp.fill(0.0);
                hx.fill(0.0);
                hx[component] = 1.0;
                self.hp.fill(0.0);
            }
        }
        Ok(())
    }

    /// $\partial\,\mathrm{row}_i / \partial y_j$ ($g_x$ for $i < n_{k+1}$, $h_x$ for
    /// $i = n_{k+1}$), of the last linearisation.
    pub(crate) fn state_derivative(&self, i: usize, j: usize) -> f64 {
        let n_to = self.dims.1;
        if i < n_to {
            self.gx[i + j * n_to]
        } else {
            self.hx[j]
        }
    }

    /// $\partial\,\mathrm{row}_i / \partial p_q$ at fixed $y$.
    pub(crate) fn parameter_derivative(&self, i: usize, q: usize) -> f64 {
        let n_to = self.dims.1;
        if i < n_to {
            self.gp[i + q * n_to]
        } else {
            self.hp[q]
        }
    }

    /// Writes row `i`'s (`i < n`) entries in the target's columns at `jac[*pos..]`: $-1$ (the
    /// next start's component $i$), or row $i$ of $-S$ (all of $x_0$) after a symmetric wrap.
    pub(crate) fn write_target_entries(
        &self,
        i: usize,
        wrap: bool,
        jac: &mut [f64],
        pos: &mut usize,
    ) {
        match (&self.closure, wrap) {
            (Some(sm), true) => {
                // Over the first segment's start (of the last linearisation's target size).
                for j in 0..self.dims.1 {
                    jac[*pos] = -sm[i + j * self.n];
                    *pos += 1;
                }
            }
            _ => {
                jac[*pos] = -1.0;
                *pos += 1;
            }
        }
    }
}

/// Positions in a Jacobian pattern of the closure's target entries: the last `per_row` entries
/// of each row in `rows` (the last segment's continuity rows write their target entries last).
pub(crate) fn closure_positions(
    pattern: &[(usize, usize)],
    rows: std::ops::Range<usize>,
    per_row: usize,
) -> Vec<usize> {
    let mut out = Vec::with_capacity(rows.len() * per_row);
    for r in rows {
        let positions: Vec<usize> = pattern
            .iter()
            .enumerate()
            .filter(|(_, e)| e.0 == r)
            .map(|(i, _)| i)
            .collect();
        out.extend_from_slice(&positions[positions.len().saturating_sub(per_row)..]);
    }
    out
}
