//! The only place that talks to faer: sparse matrices with a fixed pattern and their LU
//! factorisation, with the symbolic analysis done once and reused by every numeric factorisation.

use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::lu::simplicial::{
    SimplicialLu, factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch,
};
use faer::sparse::linalg::lu::{LuSymbolicParams, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};
use nalgebra::{Complex, DMatrix};

/// A complex number of `f64` (as nalgebra's and faer's).
type Complex64 = Complex<f64>;

/// The symbolic LU of a pattern (its fill-reducing column ordering) with the numeric factors,
/// row pivoting and scratch space, all reused.
struct LuState {
    symbolic: SymbolicLu<usize>,
    numeric: SimplicialLu<usize, f64>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    factor_buf: MemBuffer,
    solve_buf: MemBuffer,
    solve_cols: usize,
    ready: bool,
}

impl std::fmt::Debug for LuState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LuState")
            .field("ready", &self.ready)
            .field("solve_cols", &self.solve_cols)
            .finish_non_exhaustive()
    }
}

/// A sparse matrix pattern (a list of `(row, col)` entries, duplicates summed) with its LU
/// factorisation: the symbolic analysis (fill-reducing ordering) is done once, on the first
/// [`SparsePattern::factorize`], and reused, together with the numeric storage and scratch
/// buffers, by every later factorisation (no allocation per Newton step). Values are supplied in
/// the order of the entries.
#[derive(Debug)]
pub struct SparsePattern {
    nrows: usize,
    ncols: usize,
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    lu: Option<LuState>,
}

impl SparsePattern {
    /// Builds the pattern from `(row, col)` pairs.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if an index is out of range.
    pub fn new(nrows: usize, ncols: usize, entries: &[(usize, usize)]) -> Result<Self> {
        let pairs: Vec<Pair<usize, usize>> =
            entries.iter().map(|&(r, c)| Pair::new(r, c)).collect();
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(nrows, ncols, &pairs)
            .map_err(|_| Error::InvalidSetting {
                name: "sparse pattern",
                value: entries.len() as f64,
                reason: "an entry is out of range",
            })?;
        Ok(Self {
            nrows,
            ncols,
            entries: entries.len(),
            symbolic,
            argsort,
            lu: None,
        })
    }

    /// Number of rows.
    #[must_use]
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    #[must_use]
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of entries (with duplicates) the values must supply.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries
    }

    /// Whether the pattern has no entries.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries == 0
    }

    /// The matrix with the given values (in entry order).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `values` has the wrong length.
    pub fn matrix(&self, values: &[f64]) -> Result<SparseColMat<usize, f64>> {
        if values.len() != self.entries {
            return Err(Error::DimensionMismatch {
                what: "sparse values",
                expected: self.entries,
                found: values.len(),
            });
        }
        SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values).map_err(|_| {
            Error::InvalidSetting {
                name: "sparse values",
                value: values.len() as f64,
                reason: "out of memory building the matrix",
            }
        })
    }

    /// LU-factorises the square matrix with these values (partial pivoting after a COLAMD
    /// fill-reducing column ordering); the symbolic analysis is computed on the first call and
    /// reused afterwards.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if the matrix is not square or is structurally or numerically
    /// singular.
    pub fn factorize(&mut self, values: &[f64]) -> Result<()> {
        if self.nrows != self.ncols {
            return Err(Error::SingularMatrix {
                reason: format!("matrix is {} x {}, not square", self.nrows, self.ncols),
            });
        }
        let mat = self.matrix(values)?;
        if self.lu.is_none() {
            // The simplicial kernel: fast for the block-structured systems of this library (up to
            // a few thousand unknowns), and its factors give the determinant's sign.
            let params = LuSymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..LuSymbolicParams::default()
            };
            let symbolic = factorize_symbolic_lu(mat.symbolic(), params).map_err(|e| {
                Error::SingularMatrix {
                    reason: format!("symbolic LU failed: {e:?}"),
                }
            })?;
            let n = self.nrows;
            let factor_buf =
                MemBuffer::new(factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n));
            let solve_buf = MemBuffer::new(
                faer::sparse::linalg::lu::simplicial::solve_in_place_scratch::<usize, f64>(
                    n,
                    1,
                    Par::Seq,
                ),
            );
            self.lu = Some(LuState {
                symbolic,
                numeric: SimplicialLu::new(),
                row_perm: vec![0; n],
                row_perm_inv: vec![0; n],
                factor_buf,
                solve_buf,
                solve_cols: 1,
                ready: false,
            });
        }
        let st = self.lu.as_mut().expect("created above");
        st.ready = false;
        factorize_simplicial_numeric_lu(
            &mut st.row_perm,
            &mut st.row_perm_inv,
            &mut st.numeric,
            mat.as_ref(),
            st.symbolic.col_perm(),
            MemStack::new(&mut st.factor_buf),
        )
        .map_err(|e| Error::SingularMatrix {
            reason: format!("numeric LU failed: {e:?}"),
        })?;
        st.ready = true;
        Ok(())
    }

    /// Whether a factorisation is available for [`SparsePattern::solve_in_place`].
    #[must_use]
    pub fn is_factorized(&self) -> bool {
        self.lu.as_ref().is_some_and(|st| st.ready)
    }

    fn solve_cols(&mut self, b: &mut [f64], k: usize, transpose: bool) -> Result<()> {
        let n = self.nrows;
        let Some(st) = self.lu.as_mut().filter(|st| st.ready) else {
            return Err(Error::SingularMatrix {
                reason: "no factorisation to solve with (factorize first)".into(),
            });
        };
        if k > st.solve_cols {
            st.solve_buf = MemBuffer::new(
                faer::sparse::linalg::lu::simplicial::solve_in_place_scratch::<usize, f64>(
                    n,
                    k,
                    Par::Seq,
                ),
            );
            st.solve_cols = k;
        }
        let rhs = MatMut::from_column_major_slice_mut(b, n, k);
        // SAFETY-free: the permutation arrays are the ones the factorisation produced.
        let row_perm = PermRef::new_checked(&st.row_perm, &st.row_perm_inv, n);
        let stack = MemStack::new(&mut st.solve_buf);
        if transpose {
            st.numeric.solve_transpose_in_place_with_conj(
                row_perm,
                st.symbolic.col_perm(),
                Conj::No,
                rhs,
                Par::Seq,
                stack,
            );
        } else {
            st.numeric.solve_in_place_with_conj(
                row_perm,
                st.symbolic.col_perm(),
                Conj::No,
                rhs,
                Par::Seq,
                stack,
            );
        }
        if b.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Error::SingularMatrix {
                reason: "the solution of the linear system is not finite".into(),
            })
        }
    }

    /// Sign of the determinant of the last factorised matrix: `+1.0`, `-1.0`, or `0.0` for an
    /// exactly singular one (the product of the signs of $U$'s diagonal and of the row and column
    /// permutations' parities). Branch points are where this sign changes along a branch.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if nothing has been factorised.
    pub fn determinant_sign(&self) -> Result<f64> {
        self.determinant().map(|(sign, _)| sign)
    }

    /// Sign and natural logarithm of the absolute value of the determinant of the last factorised
    /// matrix (`(0.0, -inf)` for an exactly singular one).
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if nothing has been factorised.
    pub fn determinant(&self) -> Result<(f64, f64)> {
        let Some(st) = self.lu.as_ref().filter(|st| st.ready) else {
            return Err(Error::SingularMatrix {
                reason: "no factorisation to take the determinant of".into(),
            });
        };
        let u = st.numeric.u_factor_unsorted();
        let mut sign =
            permutation_sign(&st.row_perm) * permutation_sign(st.symbolic.col_perm().arrays().0);
        let mut log_abs = 0.0;
        for j in 0..self.nrows {
            let rows = u.row_idx_of_col_raw(j);
            let vals = u.val_of_col(j);
            let diag = rows
                .iter()
                .zip(vals)
                .filter(|(r, _)| **r == j)
                .map(|(_, v)| *v)
                .sum::<f64>();
            if diag == 0.0 {
                return Ok((0.0, f64::NEG_INFINITY));
            }
            sign *= diag.signum();
            log_abs += diag.abs().ln();
        }
        Ok((sign, log_abs))
    }

    /// Solves $A x = b$ in place with the last factorisation.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if there is no factorisation or the solution is not finite
    /// (numerically singular matrix).
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        crate::error::check_len("right-hand side", b, self.nrows)?;
        self.solve_cols(b, 1, false)
    }

    /// Solves $A^\top x = b$ in place with the last factorisation.
    ///
    /// # Errors
    /// As [`SparsePattern::solve_in_place`].
    pub fn solve_transpose_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        crate::error::check_len("right-hand side", b, self.nrows)?;
        self.solve_cols(b, 1, true)
    }

    /// Solves $A X = B$ for `k` right-hand sides stored column-major (`n x k`).
    ///
    /// # Errors
    /// As [`SparsePattern::solve_in_place`].
    pub fn solve_many_in_place(&mut self, b: &mut [f64], k: usize) -> Result<()> {
        crate::error::check_len("right-hand sides", b, self.nrows * k)?;
        self.solve_cols(b, k, false)
    }
}

/// Parity sign of a permutation given as an index array.
fn permutation_sign(perm: &[usize]) -> f64 {
    let mut seen = vec![false; perm.len()];
    let mut sign = 1.0;
    for start in 0..perm.len() {
        if seen[start] {
            continue;
        }
        let mut len = 0;
        let mut i = start;
        while !seen[i] {
            seen[i] = true;
            i = perm[i];
            len += 1;
        }
        if len % 2 == 0 {
            sign = -sign;
        }
    }
    sign
}

/// Eigenvalues of a small dense real matrix (column-major, `n x n`) as `(re, im)` pairs, sorted
/// by decreasing modulus.
///
/// # Errors
/// [`Error::SingularMatrix`] if the eigenvalue iteration fails to converge.
pub fn eigenvalues(n: usize, a: &[f64]) -> Result<Vec<(f64, f64)>> {
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i + j * n]);
    let ev = m.eigenvalues().map_err(|e| Error::SingularMatrix {
        reason: format!("eigenvalue iteration failed: {e:?}"),
    })?;
    let mut out: Vec<(f64, f64)> = ev.iter().map(|z| (z.re, z.im)).collect();
    out.sort_by(|a, b| (b.0.hypot(b.1)).total_cmp(&a.0.hypot(a.1)));
    Ok(out)
}

/// Eigenvalues and eigenvectors (columns, unit Euclidean norm) of a small dense real matrix
/// (column-major, `n x n`), sorted by decreasing eigenvalue modulus.
///
/// # Errors
/// [`Error::SingularMatrix`] if the eigendecomposition fails to converge.
pub fn eigenvectors(n: usize, a: &[f64]) -> Result<(Vec<Complex64>, DMatrix<Complex64>)> {
    crate::error::check_len("matrix", a, n * n)?;
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i + j * n]);
    let evd = m.eigen().map_err(|e| Error::SingularMatrix {
        reason: format!("eigendecomposition failed: {e:?}"),
    })?;
    let (s, u) = (evd.S(), evd.U());
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| s[j].norm().total_cmp(&s[i].norm()));
    let values = order.iter().map(|&i| s[i]).collect();
    let mut vectors = DMatrix::from_fn(n, n, |r, c| u[(r, order[c])]);
    for mut col in vectors.column_iter_mut() {
        let norm = col.norm();
        if norm > 0.0 {
            col /= Complex64::new(norm, 0.0);
        }
    }
    Ok((values, vectors))
}
