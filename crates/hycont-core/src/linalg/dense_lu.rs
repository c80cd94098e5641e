//! LU with partial pivoting of a small square pattern stored densely. Up to [`DENSE_UP_TO`]
//! unknowns (shooting with a few segments, small reduced systems) the arithmetic of a dense
//! factorisation costs less than a sparse one's bookkeeping; up to [`DENSE_FILLED_UP_TO`], a
//! pattern a quarter filled or more would fill in anyway ([`dense_pattern`] decides).

use super::LogProduct;
use crate::error::{Error, Result};

/// Largest dimension factorised densely.
pub(super) const DENSE_UP_TO: usize = 48;

/// Largest square pattern factorised densely because it is filled (see [`super::SparsePattern`]).
const DENSE_FILLED_UP_TO: usize = 2048;

/// Whether the `n x n` pattern `entries` is factorised densely: up to [`DENSE_UP_TO`]
/// unknowns, or up to [`DENSE_FILLED_UP_TO`] with at least a quarter of its places filled.
pub(super) fn dense_pattern(n: usize, entries: &[(usize, usize)]) -> bool {
    if (1..=DENSE_UP_TO).contains(&n) {
        return true;
    }
    if n > DENSE_FILLED_UP_TO || 4 * entries.len() < n * n {
        return false;
    }
    let mut places: Vec<(usize, usize)> = entries.to_vec();
    places.sort_unstable();
    places.dedup();
    4 * places.len() >= n * n
}

/// $P A = L U$ of an `n x n` pattern, column-major, $L$ unit lower triangular below the
/// diagonal and $U$ on and above it; `perm[i]` is the row of $A$ that is row `i` of $PA$.
#[derive(Debug)]
pub(super) struct DenseLu {
    n: usize,
    /// Position `r + c n` of each entry of the pattern.
    at: Vec<usize>,
    lu: Vec<f64>,
    perm: Vec<usize>,
    work: Vec<f64>,
    /// Reciprocals of $U$'s diagonal.
    inv: Vec<f64>,
    /// Sign of `perm`.
    sign: f64,
    ready: bool,
}

impl DenseLu {
    /// The pattern of `n x n` entries `(row, column)` (in range: checked by the caller).
    pub(super) fn new(n: usize, entries: &[(usize, usize)]) -> Self {
        Self {
            n,
            at: entries.iter().map(|&(r, c)| r + c * n).collect(),
            lu: vec![0.0; n * n],
            perm: (0..n).collect(),
            work: vec![0.0; n],
            inv: vec![0.0; n],
            sign: 1.0,
            ready: false,
        }
    }

    /// Factorises the matrix with the pattern's `values` (repeated entries add up).
    ///
    /// Returns `false`, leaving no factorisation, if a pivot is zero or not finite: the caller
    /// then factorises the matrix with the sparse LU, so that singular matrices behave as they
    /// always did (its other elimination order may keep a roundoff-sized pivot, which inverse
    /// iteration for a null vector needs, or it reports a zero determinant).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `values` does not match the pattern.
    pub(super) fn factorize(&mut self, values: &[f64]) -> Result<bool> {
        crate::error::check_len("sparse values", values, self.at.len())?;
        let n = self.n;
        self.ready = false;
        self.lu.fill(0.0);
        for (&p, v) in self.at.iter().zip(values) {
            self.lu[p] += v;
        }
        let mut pivots = std::mem::take(&mut self.work);
        let sign = super::dense::eliminate_above(
            &mut self.lu,
            (n, n, n),
            &mut self.perm,
            &mut pivots,
            0.0,
        );
        super::dense::reciprocals(&pivots, &mut self.inv);
        self.work = pivots;
        self.ready = sign.is_some();
        self.sign = sign.unwrap_or(1.0);
        Ok(self.ready)
    }

    /// Solves $A X = B$ (or $A^\top X = B$) in place for the `k` columns of `b`.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] without a factorisation.
    pub(super) fn solve(&mut self, b: &mut [f64], k: usize, transpose: bool) -> Result<()> {
        if !self.ready {
            return Err(Error::SingularMatrix {
                reason: "no factorisation to solve with (factorize first)".into(),
            });
        }
        let n = self.n;
        for col in b.chunks_exact_mut(n.max(1)).take(k) {
            if transpose {
                self.solve_transpose_one(col);
            } else {
                self.solve_one(col);
            }
        }
        Ok(())
    }

    /// $L U x = P b$.
    fn solve_one(&mut self, b: &mut [f64]) {
        let (n, a) = (self.n, &self.lu);
        let y = &mut self.work;
        for (yi, &p) in y.iter_mut().zip(&self.perm) {
            *yi = b[p];
        }
        for k in 0..n {
            let yk = y[k];
            if yk != 0.0 {
                for (yi, l) in y[k + 1..].iter_mut().zip(&a[k * n + k + 1..(k + 1) * n]) {
                    *yi -= l * yk;
                }
            }
        }
        super::dense::solve_upper(a, n, &self.inv, y);
        b.copy_from_slice(y);
    }

    /// $U^\top L^\top P z = d$.
    fn solve_transpose_one(&mut self, d: &mut [f64]) {
        let (n, a) = (self.n, &self.lu);
        let v = &mut self.work;
        v.copy_from_slice(d);
        super::dense::solve_upper_transpose(a, n, &self.inv, v);
        for k in (0..n).rev() {
            let below = &a[k * n + k + 1..(k + 1) * n];
            v[k] -= super::dense::dot(below, &v[k + 1..]);
        }
        for (&p, &vi) in self.perm.iter().zip(v.iter()) {
            d[p] = vi;
        }
    }

    /// Sign and $\ln|\det A|$.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] without a factorisation.
    pub(super) fn determinant(&self) -> Result<(f64, f64)> {
        if !self.ready {
            return Err(Error::SingularMatrix {
                reason: "no factorisation to take the determinant of".into(),
            });
        }
        let mut det = LogProduct::new();
        for k in 0..self.n {
            det.push(self.lu[k + k * self.n]);
        }
        let (sign, log) = det.finish();
        Ok((sign * self.sign, log))
    }
}

#[cfg(test)]
mod tests {
    use super::super::sparse_lu::SparseLu;
    use super::DenseLu;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    proptest! {
        /// Solves, transposed solves and the determinant agree with the sparse LU's (faer) on
        /// random sparse matrices made nonsingular by a dominant diagonal of either sign; the
        /// residuals $\|Ax - b\|$ are at roundoff.
        #[test]
        fn agrees_with_the_sparse_lu(
            n in 1usize..12,
            seed in proptest::collection::vec(-1.0f64..1.0, 12 * 12 + 24),
            density in 0.2f64..1.0,
        ) {
            let mut entries = Vec::new();
            let mut values = Vec::new();
            for c in 0..n {
                for r in 0..n {
                    let v = seed[r + 12 * c];
                    if r == c {
                        entries.push((r, c));
                        values.push(if v < 0.0 { v - n as f64 } else { v + n as f64 });
                    } else if v.abs() < density {
                        entries.push((r, c));
                        values.push(v);
                    }
                }
            }
            // A repeated entry adds up.
            entries.push((0, n - 1));
            values.push(0.5);
            let mut dense = DenseLu::new(n, &entries);
            let mut sparse = SparseLu::new(n, n, &entries).unwrap();
            prop_assert!(dense.factorize(&values).unwrap());
            sparse.factorize(&values).unwrap();
            let rhs = &seed[144..144 + n];
            for transpose in [false, true] {
                let (mut x, mut y) = (rhs.to_vec(), rhs.to_vec());
                dense.solve(&mut x, 1, transpose).unwrap();
                sparse.solve(&mut y, 1, transpose).unwrap();
                for (a, b) in x.iter().zip(&y) {
                    assert_relative_eq!(*a, *b, epsilon = 1e-12, max_relative = 1e-10);
                }
                let mut ax = vec![0.0; n];
                for (&(r, c), v) in entries.iter().zip(&values) {
                    let (i, j) = if transpose { (c, r) } else { (r, c) };
                    ax[i] += v * x[j];
                }
                for (a, b) in ax.iter().zip(rhs) {
                    prop_assert!((a - b).abs() <= 1e-12 * n as f64);
                }
            }
            let (s_d, l_d) = dense.determinant().unwrap();
            let (s_s, l_s) = sparse.determinant().unwrap();
            prop_assert_eq!(s_d, s_s);
            assert_relative_eq!(l_d, l_s, epsilon = 1e-10, max_relative = 1e-10);
        }
    }

    /// Without a factorisation, solves and the determinant are errors; a zero or non-finite
    /// pivot leaves no factorisation (the caller falls back to the sparse LU).
    #[test]
    fn singular_and_unfactorised_matrices() {
        let mut lu = DenseLu::new(2, &[(0, 0), (1, 0)]);
        assert!(lu.solve(&mut [1.0, 2.0], 1, false).is_err());
        assert!(lu.determinant().is_err());
        assert!(!lu.factorize(&[f64::NAN, 2.0]).unwrap());
        assert!(!lu.factorize(&[1.0, 2.0]).unwrap());
        assert!(lu.solve(&mut [1.0, 2.0], 1, false).is_err());
        assert!(lu.determinant().is_err());
    }
}
