//! A fixed sparse pattern in compressed-column form with faer's simplicial LU: the symbolic
//! analysis (COLAMD column ordering) once, then numeric factorisations that reuse the
//! structure, the factors' storage and the scratch space (no allocation per factorisation once
//! the factors have reached their size).

use super::{LogProduct, permutation_sign};
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::lu::simplicial::{
    SimplicialLu, factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch,
    solve_in_place_scratch,
};
use faer::sparse::linalg::lu::{LuSymbolicParams, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{Pair, SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

/// The factors, row pivoting and scratch space of the last numeric factorisation.
struct Factors {
    symbolic: SymbolicLu<usize>,
    numeric: SimplicialLu<usize, f64>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    factor_buf: MemBuffer,
    solve_buf: MemBuffer,
    solve_cols: usize,
    ready: bool,
}

/// A pattern of `(row, col)` entries (duplicates summed) and its LU factorisation.
pub(super) struct SparseLu {
    nrows: usize,
    ncols: usize,
    structure: SymbolicSparseColMat<usize>,
    /// Position of each entry's value in the compressed columns.
    slot: Vec<usize>,
    vals: Vec<f64>,
    factors: Option<Factors>,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("nrows", &self.nrows)
            .field("ncols", &self.ncols)
            .field("entries", &self.slot.len())
            .field("factorized", &self.is_factorized())
            .finish_non_exhaustive()
    }
}

impl SparseLu {
    /// The compressed-column structure of the entries.
    pub(super) fn new(nrows: usize, ncols: usize, entries: &[(usize, usize)]) -> Result<Self> {
        let pairs: Vec<Pair<usize, usize>> =
            entries.iter().map(|&(r, c)| Pair::new(r, c)).collect();
        let (structure, _) = SymbolicSparseColMat::try_new_from_indices(nrows, ncols, &pairs)
            .map_err(|_| Error::InvalidSetting {
                name: "sparse pattern",
                value: entries.len() as f64,
                reason: "an entry is out of range",
            })?;
        let (col_ptr, row_idx) = (structure.col_ptr(), structure.row_idx());
        let slot = entries
            .iter()
            .map(|&(r, c)| {
                let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
                col_ptr[c]
                    + rows
                        .binary_search(&r)
                        .expect("every entry is in the structure")
            })
            .collect();
        let vals = vec![0.0; row_idx.len()];
        Ok(Self {
            nrows,
            ncols,
            structure,
            slot,
            vals,
            factors: None,
        })
    }

    pub(super) fn len(&self) -> usize {
        self.slot.len()
    }

    /// Loads the values (in entry order, summing duplicates) into the compressed columns.
    fn load(&mut self, values: &[f64]) -> Result<()> {
        crate::error::check_len("sparse values", values, self.slot.len())?;
        self.vals.fill(0.0);
        for (&s, v) in self.slot.iter().zip(values) {
            self.vals[s] += v;
        }
        Ok(())
    }

    /// The matrix with these values (entry order).
    pub(super) fn matrix(&self, values: &[f64]) -> Result<SparseColMat<usize, f64>> {
        crate::error::check_len("sparse values", values, self.slot.len())?;
        let mut vals = vec![0.0; self.vals.len()];
        for (&s, v) in self.slot.iter().zip(values) {
            vals[s] += v;
        }
        Ok(SparseColMat::new(self.structure.clone(), vals))
    }

    /// Factorises the matrix with these values (entry order).
    pub(super) fn factorize(&mut self, values: &[f64]) -> Result<()> {
        if self.nrows != self.ncols {
            return Err(Error::SingularMatrix {
                reason: format!("matrix is {} x {}, not square", self.nrows, self.ncols),
            });
        }
        self.load(values)?;
        let mat = SparseColMatRef::new(self.structure.as_ref(), &self.vals);
        if self.factors.is_none() {
            self.factors = Some(Self::analyse(mat)?);
        }
        let st = self.factors.as_mut().expect("created above");
        st.ready = false;
        factorize_simplicial_numeric_lu(
            &mut st.row_perm,
            &mut st.row_perm_inv,
            &mut st.numeric,
            mat,
            st.symbolic.col_perm(),
            MemStack::new(&mut st.factor_buf),
        )
        .map_err(|e| Error::SingularMatrix {
            reason: format!("numeric LU failed: {e:?}"),
        })?;
        st.ready = true;
        Ok(())
    }

    /// The symbolic analysis and the factors' storage.
    fn analyse(mat: SparseColMatRef<'_, usize, f64>) -> Result<Factors> {
        // The simplicial kernel: fast for the block-structured systems of this library (up to a
        // few thousand unknowns), and its factors give the determinant's sign.
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..LuSymbolicParams::default()
        };
        let symbolic =
            factorize_symbolic_lu(mat.symbolic(), params).map_err(|e| Error::SingularMatrix {
                reason: format!("symbolic LU failed: {e:?}"),
            })?;
        let n = mat.nrows();
        Ok(Factors {
            symbolic,
            numeric: SimplicialLu::new(),
            row_perm: vec![0; n],
            row_perm_inv: vec![0; n],
            factor_buf: MemBuffer::new(factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n)),
            solve_buf: MemBuffer::new(solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq)),
            solve_cols: 1,
            ready: false,
        })
    }

    pub(super) fn is_factorized(&self) -> bool {
        self.factors.as_ref().is_some_and(|st| st.ready)
    }

    /// Solves $A X = B$ (or $A^\top X = B$) for `k` columns stored column-major.
    pub(super) fn solve(&mut self, b: &mut [f64], k: usize, transpose: bool) -> Result<()> {
        let n = self.nrows;
        let Some(st) = self.factors.as_mut().filter(|st| st.ready) else {
            return Err(Error::SingularMatrix {
                reason: "no factorisation to solve with (factorize first)".into(),
            });
        };
        if k > st.solve_cols {
            st.solve_buf = MemBuffer::new(solve_in_place_scratch::<usize, f64>(n, k, Par::Seq));
            st.solve_cols = k;
        }
        let rhs = MatMut::from_column_major_slice_mut(b, n, k);
        let row_perm = PermRef::new_checked(&st.row_perm, &st.row_perm_inv, n);
        let col_perm = st.symbolic.col_perm();
        let stack = MemStack::new(&mut st.solve_buf);
        if transpose {
            st.numeric.solve_transpose_in_place_with_conj(
                row_perm,
                col_perm,
                Conj::No,
                rhs,
                Par::Seq,
                stack,
            );
        } else {
            st.numeric
                .solve_in_place_with_conj(row_perm, col_perm, Conj::No, rhs, Par::Seq, stack);
        }
        Ok(())
    }

    /// Sign and $\ln|\det|$ of the last factorised matrix (`(0.0, -inf)` if exactly singular).
    pub(super) fn determinant(&self) -> Result<(f64, f64)> {
        let Some(st) = self.factors.as_ref().filter(|st| st.ready) else {
            return Err(Error::SingularMatrix {
                reason: "no factorisation to take the determinant of".into(),
            });
        };
        let u = st.numeric.u_factor_unsorted();
        let sign =
            permutation_sign(&st.row_perm) * permutation_sign(st.symbolic.col_perm().arrays().0);
        let mut det = LogProduct::new();
        for j in 0..self.nrows {
            let diag = u
                .row_idx_of_col_raw(j)
                .iter()
                .zip(u.val_of_col(j))
                .filter(|(r, _)| **r == j)
                .map(|(_, v)| *v)
                .sum::<f64>();
            if diag == 0.0 {
                return Ok((0.0, f64::NEG_INFINITY));
            }
            det.push(diag);
        }
        let (s, log_abs) = det.finish();
        Ok((sign * s, log_abs))
    }
}
