//! The only place that talks to faer: sparse matrices with a fixed pattern and their LU
//! factorisation, with the symbolic analysis done once and reused by every numeric factorisation.

use crate::error::{Error, Result};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};

/// A sparse matrix pattern (a list of `(row, col)` entries, duplicates summed) with its symbolic
/// LU analysis. Values are supplied in the order of the entries.
#[derive(Debug, Clone)]
pub struct SparsePattern {
    nrows: usize,
    ncols: usize,
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    lu: Option<SymbolicLu<usize>>,
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

    /// LU-factorises the square matrix with these values; the symbolic analysis is computed on
    /// the first call and reused afterwards.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if the matrix is not square or is structurally or numerically
    /// singular.
    pub fn factorize(&mut self, values: &[f64]) -> Result<SparseLu> {
        if self.nrows != self.ncols {
            return Err(Error::SingularMatrix {
                reason: format!("matrix is {} x {}, not square", self.nrows, self.ncols),
            });
        }
        let mat = self.matrix(values)?;
        if self.lu.is_none() {
            self.lu =
                Some(
                    SymbolicLu::try_new(mat.symbolic()).map_err(|e| Error::SingularMatrix {
                        reason: format!("symbolic LU failed: {e:?}"),
                    })?,
                );
        }
        let symbolic = self.lu.clone().expect("symbolic LU computed above");
        let lu = Lu::try_new_with_symbolic(symbolic, mat.as_ref()).map_err(|e| {
            Error::SingularMatrix {
                reason: format!("numeric LU failed: {e:?}"),
            }
        })?;
        Ok(SparseLu { lu, n: self.nrows })
    }
}

/// A numeric sparse LU factorisation.
#[derive(Debug, Clone)]
pub struct SparseLu {
    lu: Lu<usize, f64>,
    n: usize,
}

impl SparseLu {
    /// Solves $A x = b$ in place.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if the solution is not finite (numerically singular matrix).
    pub fn solve_in_place(&self, b: &mut [f64]) -> Result<()> {
        let mut col = faer::Mat::<f64>::from_fn(self.n, 1, |i, _| b[i]);
        self.lu.solve_in_place(col.as_mut());
        for (i, v) in b.iter_mut().enumerate() {
            *v = col[(i, 0)];
        }
        if b.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Error::SingularMatrix {
                reason: "the solution of the linear system is not finite".into(),
            })
        }
    }

    /// Solves $A X = B$ for several right-hand sides stored column-major (`n x k`).
    ///
    /// # Errors
    /// As [`SparseLu::solve_in_place`].
    pub fn solve_many_in_place(&self, b: &mut [f64], k: usize) -> Result<()> {
        let n = self.n;
        let mut m = faer::Mat::<f64>::from_fn(n, k, |i, j| b[i + j * n]);
        self.lu.solve_in_place(m.as_mut());
        for j in 0..k {
            for i in 0..n {
                b[i + j * n] = m[(i, j)];
            }
        }
        if b.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Error::SingularMatrix {
                reason: "the solution of the linear system is not finite".into(),
            })
        }
    }
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
