//! Derivatives of a vector field along many directions at once (Jacobian-matrix products):
//! what variational equations integrate, $\dot\Phi = f_x \Phi$ and
//! $\dot\Phi_p = f_x \Phi_p + f_p$.
//!
//! [`HybridJacobians::vector_field_with_tangents`] forms them from the Jacobians by
//! default; [`super::AutoDiff`] seeds its dual numbers with the directions instead and gets the
//! products from one evaluation as wide as the directions, without forming the Jacobians.

use super::{HybridJacobians, Mode, ParamId};

/// Directions along which [`HybridJacobians::vector_field_with_tangents`]
/// differentiates a vector field $f(x, p)$, and where the derivatives go.
///
/// There are $k$ directions; direction $j$ moves the state along column $j$ of
/// [`Tangents::x`] and, for the last $\ell$ = `params.len()` directions, parameter
/// `params[j - (k - ℓ)]` by one. Its derivative, column $j$ of [`Tangents::out`], is
/// $$f_x\, x_j \quad (j < k - \ell), \qquad f_x\, x_j + \partial f / \partial p_{q_j}
/// \quad (j \ge k - \ell).$$
#[derive(Debug)]
pub struct Tangents<'a> {
    /// The state's parts of the $k$ directions, $n \times k$, column-major.
    pub x: &'a [f64],
    /// The parameters the last `params.len()` directions move by one, in order.
    pub params: &'a [ParamId],
    /// The $k$ derivatives, $n \times k$, column-major.
    pub out: &'a mut [f64],
    /// Work space for implementations that form the Jacobians first (the default does):
    /// at least $n\,(n + n_p)$ values.
    pub work: &'a mut [f64],
}

impl Tangents<'_> {
    /// The number of directions $k$ for state dimension `n`.
    #[must_use]
    pub fn count(&self, n: usize) -> usize {
        self.x.len().checked_div(n).unwrap_or(0)
    }

    /// The same directions and buffers, borrowed for a shorter time: to pass them on to a
    /// wrapped system and still use `out` afterwards (e.g. to change its sign).
    pub fn reborrow(&mut self) -> Tangents<'_> {
        Tangents {
            x: self.x,
            params: self.params,
            out: &mut *self.out,
            work: &mut *self.work,
        }
    }
}

/// [`HybridJacobians::vector_field_with_tangents`] by forming the Jacobians in
/// `tangents.work` and multiplying (the trait's default).
pub(crate) fn by_jacobians<S: HybridJacobians + ?Sized>(
    system: &S,
    mode: Mode,
    x: &[f64],
    p: &[f64],
    f: &mut [f64],
    tangents: Tangents<'_>,
) {
    let n = x.len();
    let Tangents {
        x: dirs,
        params,
        out,
        work,
    } = tangents;
    let (a, b) = work.split_at_mut(n * n);
    let b = &mut b[..n * p.len()];
    let dp = (!params.is_empty()).then_some(&mut *b);
    system.vector_field_with_jacobian(mode, x, p, f, a, dp);
    product(n, a, (b, params), (dirs, out));
}

/// Columns of `out` from the Jacobians: `a` is $f_x$ ($n \times n$, column-major), `b` holds
/// $f_p$'s columns of every parameter and `params` the parameters of the last directions.
pub(crate) fn product(
    n: usize,
    a: &[f64],
    (b, params): (&[f64], &[ParamId]),
    (y, dy): (&[f64], &mut [f64]),
) {
    match n {
        1 => product_n::<1>(a, (b, params), (y, dy)),
        2 => product_n::<2>(a, (b, params), (y, dy)),
        3 => product_n::<3>(a, (b, params), (y, dy)),
        4 => product_n::<4>(a, (b, params), (y, dy)),
        5 => product_n::<5>(a, (b, params), (y, dy)),
        6 => product_n::<6>(a, (b, params), (y, dy)),
        _ => SPARSE.with_borrow_mut(|(cols, diags)| {
            if !cols.fill(n, a) {
                product_any(n, a, (b, params), (y, dy));
            } else if diags.fill(n, cols) {
                diags.product(n, (b, params), (y, dy));
            } else {
                cols.product(n, (b, params), (y, dy));
            }
        }),
    }
}

std::thread_local! {
    /// Each thread's storage for [`Columns`] and [`Diagonals`] (reused: no allocation per
    /// evaluation once it has grown to the Jacobian's nonzeros).
    static SPARSE: std::cell::RefCell<(Columns, Diagonals)> = const {
        std::cell::RefCell::new((
            Columns {
                start: Vec::new(),
                entries: Vec::new(),
            },
            Diagonals {
                range: Vec::new(),
                slot: Vec::new(),
                stretches: Vec::new(),
                values: Vec::new(),
            },
        ))
    };
}

/// A sparse Jacobian stored by the stretches of its diagonals from their first nonzero to
/// their last, when those hold at most twice its nonzeros in all (a banded Jacobian, as a
/// chain's or a discretised beam's, or one made of banded blocks): each stretch's product is
/// one contiguous loop the compiler vectorises, where [`Columns`] scatters a few entries per
/// column.
///
/// Diagonal $d$ holds the entries $(i, i + d)$, entry $(i, j)$ at position $\min(i, j)$.
/// Taken in increasing $d$, the terms of each output entry come by increasing column, as in
/// [`product_any`]: the same values (up to the sign of a zero).
#[derive(Debug, Default)]
struct Diagonals {
    /// Per diagonal `d` (at `d + n - 1`): its first and one past its last nonzero position
    /// (work space of `fill`).
    range: Vec<(usize, usize)>,
    /// Per diagonal `d` (at `d + n - 1`): its place in `stretches` (work space of `fill`).
    slot: Vec<usize>,
    /// The stored stretches, by increasing $d$: `(d, first position, start in values)`;
    /// stretch `s` is `values[stretches[s].2..stretches[s + 1].2]` (a last entry closes).
    stretches: Vec<(isize, usize, usize)>,
    values: Vec<f64>,
}

impl Diagonals {
    /// Stores the nonzeros of `cols` (of an $n \times n$ matrix) by diagonal stretches;
    /// `false` when those hold more than twice the nonzeros.
    fn fill(&mut self, n: usize, cols: &Columns) -> bool {
        const EMPTY: (usize, usize) = (usize::MAX, 0);
        self.range.clear();
        self.range.resize(2 * n - 1, EMPTY);
        for (k, w) in cols.start.windows(2).enumerate() {
            for &(i, _) in &cols.entries[w[0]..w[1]] {
                let r = &mut self.range[k + n - 1 - i];
                let pos = i.min(k);
                *r = (r.0.min(pos), r.1.max(pos + 1));
            }
        }
        self.stretches.clear();
        self.slot.clear();
        self.slot.resize(2 * n - 1, usize::MAX);
        let mut len = 0;
        for (at, &(lo, hi)) in self.range.iter().enumerate() {
            if hi > 0 {
                self.slot[at] = self.stretches.len();
                self.stretches
                    .push((at as isize - (n as isize - 1), lo, len));
                len += hi - lo;
            }
        }
        if len > 2 * cols.entries.len() {
            return false;
        }
        self.stretches.push((0, 0, len));
        self.values.clear();
        self.values.resize(len, 0.0);
        for (k, w) in cols.start.windows(2).enumerate() {
            for &(i, v) in &cols.entries[w[0]..w[1]] {
                let (_, lo, at) = self.stretches[self.slot[k + n - 1 - i]];
                self.values[at + i.min(k) - lo] = v;
            }
        }
        true
    }

    /// [`product_any`]'s sums over the stored stretches.
    fn product(&self, n: usize, (b, params): (&[f64], &[ParamId]), (y, dy): (&[f64], &mut [f64])) {
        let first = y.len() / n - params.len();
        for (j, (col, out)) in y.chunks_exact(n).zip(dy.chunks_exact_mut(n)).enumerate() {
            if j >= first {
                let q = params[j - first].index();
                out.copy_from_slice(&b[q * n..(q + 1) * n]);
            } else {
                out.fill(0.0);
            }
            for w in self.stretches.windows(2) {
                let ((d, lo, at), end) = (w[0], w[1].2);
                let vals = &self.values[at..end];
                let m = vals.len();
                // Rows `lo..lo + m` and columns `lo + d..` (d >= 0), or the other way round.
                let shift = d.unsigned_abs();
                let (o, c) = if d >= 0 {
                    (&mut out[lo..lo + m], &col[lo + shift..lo + shift + m])
                } else {
                    (&mut out[lo + shift..lo + shift + m], &col[lo..lo + m])
                };
                for ((o, v), c) in o.iter_mut().zip(vals).zip(c) {
                    *o += v * c;
                }
            }
        }
    }
}

/// A Jacobian's nonzero entries column by column (compressed columns, rows increasing): large
/// systems' Jacobians are mostly zeros (a chain couples each state to a few neighbours), and
/// a product over the nonzeros costs $k \cdot nnz$ instead of $k n^2$ for $k$ directions.
/// Read from the column-major Jacobian in storage order (one contiguous pass).
#[derive(Debug, Default)]
struct Columns {
    /// Column `k`'s entries are `entries[start[k]..start[k + 1]]`.
    start: Vec<usize>,
    /// `(row, value)`.
    entries: Vec<(usize, f64)>,
}

impl Columns {
    /// Reads the nonzeros of `a` ($n \times n$, column-major); `false` (and stops reading) when
    /// they are more than a quarter of its entries (denser Jacobians are multiplied as dense).
    fn fill(&mut self, n: usize, a: &[f64]) -> bool {
        self.start.clear();
        self.entries.clear();
        let limit = n * n / 4;
        for col in a.chunks_exact(n) {
            self.start.push(self.entries.len());
            // Eight entries at a time: most such runs of a sparse Jacobian are all zeros, and
            // one test of the run skips them (their bits but the signs or-ed together: zero
            // exactly when every entry is +0 or -0; a loop without early exit, vectorised).
            for (r, run) in col.chunks(8).enumerate() {
                if run.iter().fold(0u64, |m, v| m | (v.to_bits() << 1)) == 0 {
                    continue;
                }
                for (i, &v) in run.iter().enumerate() {
                    if v != 0.0 {
                        self.entries.push((8 * r + i, v));
                    }
                }
            }
            if self.entries.len() > limit {
                return false;
            }
        }
        self.start.push(self.entries.len());
        true
    }

    /// [`product_any`]'s sums without the terms of the Jacobian's zero entries: the other terms
    /// in the same order (each output entry's by increasing column), so the same values (up to
    /// the sign of a zero).
    fn product(&self, n: usize, (b, params): (&[f64], &[ParamId]), (y, dy): (&[f64], &mut [f64])) {
        let first = y.len() / n - params.len();
        for (j, (col, out)) in y.chunks_exact(n).zip(dy.chunks_exact_mut(n)).enumerate() {
            if j >= first {
                let q = params[j - first].index();
                out.copy_from_slice(&b[q * n..(q + 1) * n]);
            } else {
                out.fill(0.0);
            }
            for (k, &c) in col.iter().enumerate() {
                for &(i, v) in &self.entries[self.start[k]..self.start[k + 1]] {
                    out[i] += v * c;
                }
            }
        }
    }
}

/// [`product`] for a state dimension `N` known at compile time, so that the accumulators stay
/// in registers; the sums are [`product_any`]'s, term by term in the same order.
fn product_n<const N: usize>(
    a: &[f64],
    (b, params): (&[f64], &[ParamId]),
    (y, dy): (&[f64], &mut [f64]),
) {
    let mut fx = [[0.0; N]; N];
    for (to, from) in fx.iter_mut().zip(a.chunks_exact(N)) {
        to.copy_from_slice(from);
    }
    let first = y.len() / N - params.len();
    for (j, (col, out)) in y.chunks_exact(N).zip(dy.chunks_exact_mut(N)).enumerate() {
        let mut acc = [0.0; N];
        if j >= first {
            let q = params[j - first].index();
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

/// [`product`] for any state dimension `n`.
fn product_any(
    n: usize,
    a: &[f64],
    (b, params): (&[f64], &[ParamId]),
    (y, dy): (&[f64], &mut [f64]),
) {
    let first = y.len() / n - params.len();
    for (j, (col, out)) in y.chunks_exact(n).zip(dy.chunks_exact_mut(n)).enumerate() {
        for (i, o) in out.iter_mut().enumerate() {
            let mut acc = if j >= first {
                b[params[j - first].index() * n + i]
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
    use super::{Columns, Diagonals, product, product_any, product_n};
    use crate::system::ParamId;
    use proptest::prelude::*;

    /// $f_x X + [0\ f_p]$ column by column, from the definition (the direct term first).
    fn reference(n: usize, a: &[f64], b: &[f64], params: &[ParamId], y: &[f64]) -> Vec<f64> {
        let cols = y.len() / n;
        let first = cols - params.len();
        let mut out = vec![0.0; y.len()];
        for j in 0..cols {
            for i in 0..n {
                let mut acc = if j >= first {
                    b[params[j - first].index() * n + i]
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
        /// parameter directions, for as many state directions as the state has and fewer.
        #[test]
        fn kernels_match_the_definition(
            values in proptest::collection::vec(-3.0f64..3.0, 4 * 4 + 4 * 3 + 4 * 6),
            with_params in any::<bool>(),
            state_directions in 1usize..=4,
        ) {
            let n = 4;
            let (a, rest) = values.split_at(n * n);
            let (b, y) = rest.split_at(n * 3);
            let params: &[ParamId] = if with_params { &[ParamId(0), ParamId(2)] } else { &[] };
            let y = &y[..n * (state_directions + params.len())];
            let want = reference(n, a, b, params, y);
            let mut fixed = vec![0.0; y.len()];
            product_n::<4>(a, (b, params), (y, &mut fixed));
            let mut any = vec![0.0; y.len()];
            product_any(n, a, (b, params), (y, &mut any));
            prop_assert_eq!(&fixed, &want);
            prop_assert_eq!(&any, &want);
        }

        /// The sparse kernel gives the definition's sums for Jacobians with few nonzeros, also
        /// along directions with zero entries (the zero terms dropped: the same values), and
        /// declines Jacobians with more than a quarter of their entries nonzero.
        #[test]
        fn the_sparse_kernel_matches_the_definition(
            values in proptest::collection::vec(-3.0f64..3.0, 12 * 12 + 12 * 2 + 12 * 5),
            keep in proptest::collection::vec(0usize..144, 0..36),
            zero_dirs in proptest::collection::vec(proptest::bool::weighted(0.3), 12 * 5),
            with_params in any::<bool>(),
        ) {
            let n = 12;
            let (dense, rest) = values.split_at(n * n);
            let (b, y) = rest.split_at(n * 2);
            // At most 36 of the 144 entries kept: a quarter.
            let mut a = vec![0.0; n * n];
            for &k in &keep {
                a[k] = dense[k];
            }
            let params: &[ParamId] = if with_params { &[ParamId(1)] } else { &[] };
            // Directions with zero entries too (as a monodromy starting from the identity).
            let y: Vec<f64> = y[..n * (4 + params.len())]
                .iter()
                .zip(&zero_dirs)
                .map(|(&v, &z)| if z { 0.0 } else { v })
                .collect();
            let y = &y[..];
            let want = reference(n, &a, b, params, y);
            let mut cols = Columns::default();
            prop_assert!(cols.fill(n, &a), "a quarter of the entries is sparse");
            let mut got = vec![0.0; y.len()];
            cols.product(n, (b, params), (y, &mut got));
            prop_assert_eq!(&got, &want);
            let nonzeros = dense.iter().filter(|v| **v != 0.0).count();
            prop_assert_eq!(cols.fill(n, dense), nonzeros * 4 <= n * n);
        }

        /// Banded Jacobians (a few diagonals, some entries of them zero, as a chain's) go by
        /// diagonals and give the definition's sums; scattered ones do not qualify; and
        /// [`product`] gives the definition's sums either way.
        #[test]
        fn the_diagonal_kernel_matches_the_definition(
            values in proptest::collection::vec(-3.0f64..3.0, 12 * 12 + 12 * 2 + 12 * 5),
            offsets in proptest::collection::vec(-11isize..=11, 1..4),
            holes in proptest::collection::vec(proptest::bool::weighted(0.2), 12 * 12),
            scattered in proptest::collection::vec(0usize..144, 0..30),
            with_params in any::<bool>(),
        ) {
            let n = 12;
            let (dense, rest) = values.split_at(n * n);
            let (b, y) = rest.split_at(n * 2);
            let params: &[ParamId] = if with_params { &[ParamId(1)] } else { &[] };
            let y = &y[..n * (4 + params.len())];
            for banded in [true, false] {
                let mut a = vec![0.0; n * n];
                for k in 0..n * n {
                    let (i, j) = (k % n, k / n);
                    let on_band = offsets.contains(&(j as isize - i as isize));
                    let keep = if banded { on_band && !holes[k] } else { scattered.contains(&k) };
                    if keep {
                        a[k] = dense[k];
                    }
                }
                let want = reference(n, &a, b, params, y);
                let mut cols = Columns::default();
                let mut diags = Diagonals::default();
                if cols.fill(n, &a) {
                    let nnz = cols.entries.len();
                    // Each diagonal from its first nonzero to its last.
                    let mut ends = std::collections::BTreeMap::new();
                    for (k, w) in cols.start.windows(2).enumerate() {
                        for &(i, _) in &cols.entries[w[0]..w[1]] {
                            let e = ends.entry(k as isize - i as isize).or_insert((i, i));
                            *e = (e.0.min(i), e.1.max(i));
                        }
                    }
                    let stored: usize = ends.values().map(|(lo, hi)| hi - lo + 1).sum();
                    prop_assert_eq!(diags.fill(n, &cols), stored <= 2 * nnz);
                    if stored <= 2 * nnz {
                        let mut got = vec![0.0; y.len()];
                        diags.product(n, (b, params), (y, &mut got));
                        prop_assert_eq!(&got, &want);
                    }
                }
                let mut got = vec![0.0; y.len()];
                product(n, &a, (b, params), (y, &mut got));
                prop_assert_eq!(&got, &want);
            }
        }
    }
}
