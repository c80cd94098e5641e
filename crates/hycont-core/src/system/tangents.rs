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
        _ => match Rows::sparse(n, a) {
            Some(rows) => rows.product(n, (b, params), (y, dy)),
            None => product_any(n, a, (b, params), (y, dy)),
        },
    }
}

/// A Jacobian's nonzero entries row by row (compressed rows, columns increasing): large
/// systems' Jacobians are mostly zeros (a chain couples each state to a few neighbours), and
/// a product over the nonzeros costs $k \cdot nnz$ instead of $k n^2$ for $k$ directions.
struct Rows {
    /// Row `i`'s entries are `entries[start[i]..start[i + 1]]`.
    start: Vec<usize>,
    /// `(column, value)`.
    entries: Vec<(usize, f64)>,
}

impl Rows {
    /// The nonzeros of `a` ($n \times n$, column-major) when they are at most a quarter of
    /// its entries (denser Jacobians are multiplied as dense).
    fn sparse(n: usize, a: &[f64]) -> Option<Self> {
        let nnz = a.iter().filter(|v| **v != 0.0).count();
        if 4 * nnz > n * n {
            return None;
        }
        let mut start = Vec::with_capacity(n + 1);
        let mut entries = Vec::with_capacity(nnz);
        for i in 0..n {
            start.push(entries.len());
            entries.extend((0..n).map(|k| (k, a[i + k * n])).filter(|e| e.1 != 0.0));
        }
        start.push(entries.len());
        Some(Self { start, entries })
    }

    /// [`product_any`]'s sums without their zero terms: the same nonzero terms in the same
    /// order, so the same values (up to the sign of a zero).
    fn product(&self, n: usize, (b, params): (&[f64], &[ParamId]), (y, dy): (&[f64], &mut [f64])) {
        let first = y.len() / n - params.len();
        for (j, (col, out)) in y.chunks_exact(n).zip(dy.chunks_exact_mut(n)).enumerate() {
            for (i, o) in out.iter_mut().enumerate() {
                let mut acc = if j >= first {
                    b[params[j - first].index() * n + i]
                } else {
                    0.0
                };
                for &(k, v) in &self.entries[self.start[i]..self.start[i + 1]] {
                    acc += v * col[k];
                }
                *o = acc;
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
    use super::{Rows, product_any, product_n};
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

        /// The sparse kernel gives the definition's sums for Jacobians with few nonzeros
        /// (the zero terms dropped: the same values), and declines dense ones.
        #[test]
        fn the_sparse_kernel_matches_the_definition(
            values in proptest::collection::vec(-3.0f64..3.0, 12 * 12 + 12 * 2 + 12 * 5),
            keep in proptest::collection::vec(0usize..144, 0..36),
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
            let y = &y[..n * (4 + params.len())];
            let want = reference(n, &a, b, params, y);
            let rows = Rows::sparse(n, &a).expect("a quarter of the entries is sparse");
            let mut got = vec![0.0; y.len()];
            rows.product(n, (b, params), (y, &mut got));
            prop_assert_eq!(&got, &want);
            prop_assert!(Rows::sparse(n, dense).is_none() || dense.iter().filter(|v| **v != 0.0).count() * 4 <= n * n);
        }
    }
}
