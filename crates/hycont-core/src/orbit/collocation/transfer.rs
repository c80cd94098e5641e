//! One mesh interval's transfer matrix $Y = -S_1^{-1} S_0$ from its condensed rows
//! $[S_0\ S_1]$ ($n \times 2n$): Gaussian elimination with partial pivoting of $S_1$ and
//! back-substitution, for any $n$ or, where $n \le 8$, with $n$ known at compile time (the
//! whole interval's work in registers and stack arrays: a Floquet analysis does this on every
//! interval of every point). Both run the same elimination and back-substitution
//! (`linalg::dense`; the fixed one's back-substitution is written out with constant sizes,
//! the same operations in the same order), the fixed one without the run-time dispatch, so
//! they give the same numbers (up to the sign of a zero).

use super::condense::singular;
use crate::error::Result;
use crate::linalg::dense::{eliminate, eliminate_inline, reciprocals, solve_upper};

/// Work space for $Y = -S_1^{-1} S_0$ from the rows $[S_0\ S_1]$.
pub(super) struct Transfer {
    n: usize,
    small: Vec<f64>,
    perm: Vec<usize>,
    pivots: Vec<f64>,
    /// The pivots' reciprocals.
    inv: Vec<f64>,
}

impl Transfer {
    pub(super) fn new(n: usize) -> Self {
        Self {
            n,
            small: vec![0.0; 2 * n * n],
            perm: vec![0; n],
            pivots: vec![0.0; n],
            inv: vec![0.0; n],
        }
    }

    /// The work space for $n \times n$ transfers (segments of modes of their own dimension).
    pub(super) fn resize(&mut self, n: usize) {
        if n != self.n {
            *self = Self::new(n);
        }
    }

    /// Writes $Y$ (column-major) into `y`; `s(i, col)` is row `i`, column `col` of
    /// $[S_0\ S_1]$ (`col < 2n`); `k`, `j` (segment, interval) name a singular $S_1$.
    pub(super) fn solve(
        &mut self,
        s: impl Fn(usize, usize) -> f64,
        k: usize,
        j: usize,
        y: &mut [f64],
    ) -> Result<()> {
        let solved = match self.n {
            1 => solve_fixed::<1>(&s, y),
            2 => solve_fixed::<2>(&s, y),
            3 => solve_fixed::<3>(&s, y),
            4 => solve_fixed::<4>(&s, y),
            5 => solve_fixed::<5>(&s, y),
            6 => solve_fixed::<6>(&s, y),
            7 => solve_fixed::<7>(&s, y),
            8 => solve_fixed::<8>(&s, y),
            _ => self.solve_any(&s, y),
        };
        solved.ok_or_else(|| singular(k, j))
    }

    /// [`Transfer::solve`] for any $n$, in the work space.
    fn solve_any(&mut self, s: &impl Fn(usize, usize) -> f64, y: &mut [f64]) -> Option<()> {
        let n = self.n;
        // [S_1 | -S_0], then U Y = L^{-1} P (-S_0).
        for i in 0..n {
            for col in 0..n {
                self.small[i + col * n] = s(i, n + col);
                self.small[i + (n + col) * n] = -s(i, col);
            }
        }
        eliminate(
            &mut self.small,
            (n, n, 2 * n),
            &mut self.perm,
            &mut self.pivots,
        )?;
        reciprocals(&self.pivots, &mut self.inv);
        let (u, rhs) = self.small.split_at_mut(n * n);
        for col in rhs.chunks_exact_mut(n) {
            solve_upper(u, n, &self.inv, col);
        }
        y.copy_from_slice(rhs);
        Some(())
    }
}

/// [`Transfer::solve`] with `N` known at compile time: $[S_1\ {-S_0}]$ in a stack array,
/// eliminated by [`eliminate_inline`] (the same pivoting and steps as the general path, with
/// the sizes constant), then the back-substitution of each column of $-S_0$.
#[inline(always)]
fn solve_fixed<const N: usize>(s: &impl Fn(usize, usize) -> f64, y: &mut [f64]) -> Option<()> {
    let mut buf = [0.0f64; 2 * 8 * 8];
    let a = &mut buf[..2 * N * N];
    for col in 0..N {
        for i in 0..N {
            a[i + col * N] = s(i, N + col);
            a[i + (N + col) * N] = -s(i, col);
        }
    }
    let (mut perm, mut pivots) = ([0usize; N], [0.0f64; N]);
    eliminate_inline(a, (N, N, 2 * N), &mut perm, &mut pivots)?;
    let inv = pivots.map(|p| 1.0 / p);
    let (u, rhs) = a.split_at_mut(N * N);
    for col in rhs.chunks_exact_mut(N) {
        upper_fixed::<N>(u, &inv, col);
    }
    y.copy_from_slice(rhs);
    Some(())
}

/// `dense::solve_upper` with `N` known at compile time (the same operations in the same
/// order; inlined into [`solve_fixed`], where the general one is a call per column).
#[inline(always)]
fn upper_fixed<const N: usize>(u: &[f64], inv: &[f64; N], t: &mut [f64]) {
    for k in (0..N).rev() {
        let xk = t[k] * inv[k];
        t[k] = xk;
        if xk != 0.0 {
            for i in 0..k {
                t[i] -= u[k * N + i] * xk;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Transfer;
    use proptest::prelude::*;

    proptest! {
        /// The compile-time kernels (every `n` up to 8) give the general path's transfer
        /// matrix to the last bit, on rows with a third of their entries zero (skipped
        /// updates), and refuse the same singular $S_1$ (a zero column).
        #[test]
        fn fixed_sizes_give_the_general_numbers(
            n in 1usize..=8,
            entries in proptest::collection::vec(
                prop_oneof![2 => -10.0f64..10.0, 1 => Just(0.0)], 128),
            singular_column in proptest::option::of(0usize..8),
        ) {
            let mut rows = entries[..2 * n * n].to_vec();
            if let Some(c) = singular_column.filter(|&c| c < n) {
                for i in 0..n {
                    rows[i + (n + c) * n] = 0.0;
                }
            }
            // Row i, column col of [S_0 S_1], column-major n x 2n.
            let s = |i: usize, col: usize| rows[i + col * n];
            let mut fixed = vec![f64::NAN; n * n];
            let mut any = vec![f64::NAN; n * n];
            let mut t = Transfer::new(n);
            let fixed_ok = t.solve(s, 0, 0, &mut fixed).is_ok();
            let any_ok = t.solve_any(&s, &mut any).is_some();
            prop_assert_eq!(fixed_ok, any_ok);
            if fixed_ok {
                // Equal values; a zero's sign may differ (the general kernel updates the rows
                // above the pivot with zero multipliers: -0 - 0 * a is +0 for a < 0).
                prop_assert_eq!(&fixed, &any);
            }
        }
    }

    /// $Y = -S_1^{-1} S_0$ for a small case by hand: $S_1 = \mathrm{diag}(2, 4)$ after a row
    /// swap ($S_1 = [[0, 4], [2, 0]]$), $S_0 = [[1, 2], [3, 4]]$; then
    /// $S_1^{-1} = [[0, 1/2], [1/4, 0]]$ and $Y = -[[3/2, 2], [1/4, 1/2]]$.
    #[test]
    fn transfer_of_a_swapped_block_by_hand() {
        // Column-major [S_0 S_1]: S_0 = [[1, 2], [3, 4]], S_1 = [[0, 4], [2, 0]].
        let rows = [1.0, 3.0, 2.0, 4.0, 0.0, 2.0, 4.0, 0.0];
        let mut y = [0.0; 4];
        Transfer::new(2)
            .solve(|i, col| rows[i + 2 * col], 0, 0, &mut y)
            .unwrap();
        assert_eq!(y, [-1.5, -0.25, -2.0, -0.5]);
    }
}
