//! The only place that talks to faer's solvers: sparse matrices with a fixed pattern and their
//! LU factorisation, with the symbolic analysis done once and reused by every numeric
//! factorisation; optionally with local unknowns condensed by small dense eliminations first
//! ([`EliminationBlock`]); and eigenvalues of small dense matrices.

mod condensed;
pub(crate) mod dense;
mod dense_blocked;
mod dense_lu;
mod eigen;
mod entries;
mod log_product;
mod sparse_lu;

use crate::error::{Error, Result};
pub use condensed::ReducedRows;
use condensed::{Condensation, Condensed};
use dense_lu::{DenseLu, dense_pattern};
pub use eigen::{eigenvalues, eigenvectors};
use entries::Entries;
use faer::sparse::SparseColMat;
use log_product::LogProduct;
use sparse_lu::SparseLu;

/// Unknowns (`cols`) that only the equations `rows` read, apart from a few other rows (*border
/// rows*, e.g. an arclength row); no row of another block may read them, and there must be at
/// least as many rows as unknowns. [`SparsePattern::with_blocks`] eliminates them by dense
/// Gaussian elimination with partial pivoting within `rows` before the sparse factorisation
/// (static condensation), so the sparse LU sees a much smaller system. Collocation's interior
/// nodes of one mesh interval with that interval's equations are such a block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EliminationBlock {
    /// The block's equations (row indices).
    pub rows: Vec<usize>,
    /// The block's local unknowns (column indices).
    pub cols: Vec<usize>,
}

/// Which factorisation is current.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Current {
    None,
    Full,
    Dense,
    Condensed,
}

/// A sparse matrix pattern (a list of `(row, col)` entries, duplicates summed) with its LU
/// factorisation: the symbolic analysis (fill-reducing ordering) is done once, on the first
/// [`SparsePattern::factorize`], and reused, together with the numeric storage and scratch
/// buffers, by every later factorisation (no allocation per Newton step). Values are supplied in
/// the order of the entries.
///
/// With [`EliminationBlock`]s the blocks' unknowns are condensed first; a block that is
/// numerically singular on its own (not just the matrix) falls back to the LU of the whole
/// matrix for that factorisation. Both give the same solves and determinant up to rounding.
/// A square pattern of at most 48 unknowns without blocks is factorised densely (partial
/// pivoting): at that size the arithmetic costs less than a sparse factorisation's bookkeeping.
/// So is one of at most 2048 unknowns with at least a quarter of its places filled (as the last
/// reduced system of a large system's collocation is): a sparse LU's fill would make it dense
/// anyway, without the dense kernels' blocking. A zero pivot there (a singular matrix) falls
/// back to the sparse LU for that factorisation.
///
/// ```
/// use hycont_core::linalg::{EliminationBlock, SparsePattern};
/// // [[2, 1, 0], [1, 3, 1], [0, 1, 4]] with unknown 0 local to equations 0 and 1.
/// let entries = [(0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 1), (2, 2)];
/// let block = EliminationBlock { rows: vec![0, 1], cols: vec![0] };
/// let mut a = SparsePattern::with_blocks(3, 3, &entries, &[block]).unwrap();
/// a.factorize(&[2.0, 1.0, 1.0, 3.0, 1.0, 1.0, 4.0]).unwrap();
/// let mut x = vec![3.0, 5.0, 5.0]; // A (1, 1, 1)
/// a.solve_in_place(&mut x).unwrap();
/// assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-14));
/// let (sign, log_abs) = a.determinant().unwrap(); // det = 18
/// assert_eq!(sign, 1.0);
/// assert!((log_abs - 18f64.ln()).abs() < 1e-14);
/// ```
#[derive(Debug)]
pub struct SparsePattern {
    nrows: usize,
    ncols: usize,
    /// The entries, for a full LU built later (none where it is built at once).
    entries: Entries,
    /// The whole matrix's LU: built at once without blocks, on the first fallback with them.
    full: Option<SparseLu>,
    /// The whole matrix's dense LU, instead of `full`, for small square patterns.
    dense: Option<DenseLu>,
    condensed: Option<Condensed>,
    current: Current,
}

impl SparsePattern {
    /// Builds the pattern from `(row, col)` pairs.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if an index is out of range.
    pub fn new(nrows: usize, ncols: usize, entries: &[(usize, usize)]) -> Result<Self> {
        if nrows == ncols && dense_pattern(nrows, entries) {
            return Ok(Self {
                nrows,
                ncols,
                entries: Entries::new(nrows, ncols, entries)?,
                full: None,
                dense: Some(DenseLu::new(nrows, entries)),
                condensed: None,
                current: Current::None,
            });
        }
        Ok(Self {
            nrows,
            ncols,
            entries: Entries::default(),
            full: Some(SparseLu::new(nrows, ncols, entries)?),
            dense: None,
            condensed: None,
            current: Current::None,
        })
    }

    /// Builds a square pattern whose blocks' unknowns are condensed before the sparse
    /// factorisation (see [`EliminationBlock`]). Without blocks, as [`SparsePattern::new`].
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if an index is out of range, the matrix is not square, blocks
    /// overlap, a block has more unknowns than equations, a block's unknown is read by another
    /// block's equations or by none of its own.
    pub fn with_blocks(
        nrows: usize,
        ncols: usize,
        entries: &[(usize, usize)],
        blocks: &[EliminationBlock],
    ) -> Result<Self> {
        if blocks.is_empty() {
            return Self::new(nrows, ncols, entries);
        }
        Self::condensed((nrows, ncols), Entries::new(nrows, ncols, entries)?, blocks)
    }

    /// [`SparsePattern::with_blocks`] taking `entries`: they are freed as soon as they are
    /// kept compactly, before the layout is built (a large system's collocation pattern has
    /// millions of entries).
    ///
    /// # Errors
    /// As [`SparsePattern::with_blocks`].
    pub fn with_blocks_owned(
        nrows: usize,
        ncols: usize,
        entries: Vec<(usize, usize)>,
        blocks: &[EliminationBlock],
    ) -> Result<Self> {
        if blocks.is_empty() {
            return Self::new(nrows, ncols, &entries);
        }
        let compact = Entries::new(nrows, ncols, &entries)?;
        drop(entries);
        Self::condensed((nrows, ncols), compact, blocks)
    }

    /// The condensed pattern of `entries` with `blocks` (at least one); refuses a matrix that
    /// is not square.
    fn condensed(
        (nrows, ncols): (usize, usize),
        entries: Entries,
        blocks: &[EliminationBlock],
    ) -> Result<Self> {
        if nrows != ncols {
            return Err(Error::InvalidSetting {
                name: "elimination blocks",
                value: nrows as f64,
                reason: "condensation needs a square matrix",
            });
        }
        let n = nrows;
        let condensed = Some(Condensed::new(n, &entries, blocks)?);
        Ok(Self {
            nrows: n,
            ncols: n,
            entries,
            full: None,
            dense: None,
            condensed,
            current: Current::None,
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
        self.full.as_ref().map_or(self.entries.len(), SparseLu::len)
    }

    /// Whether `entries` are this pattern's entries in order; `None` where the pattern did
    /// not keep them (a sparse LU built at once).
    pub(crate) fn has_entries(
        &self,
        entries: impl Iterator<Item = (usize, usize)>,
    ) -> Option<bool> {
        (self.condensed.is_some() || self.dense.is_some()).then(|| self.entries.eq_pairs(entries))
    }

    /// Whether the pattern has no entries.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The matrix with the given values (in entry order).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `values` has the wrong length.
    pub fn matrix(&self, values: &[f64]) -> Result<SparseColMat<usize, f64>> {
        match &self.full {
            Some(full) => full.matrix(values),
            None => SparseLu::new(self.nrows, self.ncols, &self.entries.pairs())?.matrix(values),
        }
    }

    /// LU-factorises the square matrix with these values (partial pivoting after a COLAMD
    /// fill-reducing column ordering, after condensing the blocks if there are any); the
    /// symbolic analysis is computed on the first call and reused afterwards.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if the matrix is not square or is structurally or numerically
    /// singular.
    pub fn factorize(&mut self, values: &[f64]) -> Result<()> {
        self.current = Current::None;
        if let Some(c) = self.condensed.as_mut()
            && c.factorize(values)? == Condensation::Done
        {
            self.current = Current::Condensed;
            return Ok(());
        }
        if let Some(d) = self.dense.as_mut()
            && d.factorize(values)?
        {
            self.current = Current::Dense;
            return Ok(());
        }
        if self.full.is_none() {
            self.full = Some(SparseLu::new(
                self.nrows,
                self.ncols,
                &self.entries.pairs(),
            )?);
        }
        let full = self.full.as_mut().expect("built above");
        full.factorize(values)?;
        self.current = Current::Full;
        Ok(())
    }

    /// The rows [`EliminationBlock`] number `block` (in the order given to
    /// [`SparsePattern::with_blocks`]) leaves after its unknowns are eliminated, in the last
    /// factorisation: $n$ equations over the block's other columns equivalent to the block's
    /// equations (collocation: an interval's transfer from its first node to its last). `None`
    /// unless the last factorisation was condensed (no blocks, or a block singular on its own).
    #[must_use]
    pub fn reduced_rows(&self, block: usize) -> Option<ReducedRows<'_>> {
        match (self.current, self.condensed.as_ref()) {
            (Current::Condensed, Some(c)) => c.reduced_rows(block),
            _ => None,
        }
    }

    /// Whether a factorisation is available for [`SparsePattern::solve_in_place`].
    #[must_use]
    pub fn is_factorized(&self) -> bool {
        self.current != Current::None
    }

    fn solve_cols(&mut self, b: &mut [f64], k: usize, transpose: bool) -> Result<()> {
        let n = self.nrows();
        match (self.current, self.condensed.as_mut()) {
            (Current::None, _) => {
                return Err(Error::SingularMatrix {
                    reason: "no factorisation to solve with (factorize first)".into(),
                });
            }
            (Current::Condensed, Some(c)) => {
                for col in b.chunks_exact_mut(n.max(1)).take(k) {
                    if transpose {
                        c.solve_transpose(col)?;
                    } else {
                        c.solve(col)?;
                    }
                }
            }
            (Current::Dense, _) => self
                .dense
                .as_mut()
                .map_or_else(not_factorized, Ok)?
                .solve(b, k, transpose)?,
            (_, _) => self
                .full
                .as_mut()
                .map_or_else(not_factorized, Ok)?
                .solve(b, k, transpose)?,
        }
        if b.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Error::SingularMatrix {
                reason: "the solution is not finite: the matrix is singular to working precision (for an orbit's equations: a segment ending at an event its flow does not cross, with rate zero there, or conditions that depend on each other; non-finite values of the system are reported by name before this)".into(),
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
        match (self.current, self.condensed.as_ref()) {
            (Current::Condensed, Some(c)) => c.determinant(),
            (Current::Full, _) => self
                .full
                .as_ref()
                .map_or_else(not_factorized, Ok)?
                .determinant(),
            (Current::Dense, _) => self
                .dense
                .as_ref()
                .map_or_else(not_factorized, Ok)?
                .determinant(),
            _ => Err(Error::SingularMatrix {
                reason: "no factorisation to take the determinant of".into(),
            }),
        }
    }

    /// Solves $A x = b$ in place with the last factorisation.
    ///
    /// # Errors
    /// [`Error::SingularMatrix`] if there is no factorisation or the solution is not finite
    /// (numerically singular matrix).
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        crate::error::check_len("right-hand side", b, self.nrows())?;
        self.solve_cols(b, 1, false)
    }

    /// Solves $A^\top x = b$ in place with the last factorisation.
    ///
    /// # Errors
    /// As [`SparsePattern::solve_in_place`].
    pub fn solve_transpose_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        crate::error::check_len("right-hand side", b, self.nrows())?;
        self.solve_cols(b, 1, true)
    }

    /// Solves $A X = B$ for `k` right-hand sides stored column-major (`n x k`).
    ///
    /// # Errors
    /// As [`SparsePattern::solve_in_place`].
    pub fn solve_many_in_place(&mut self, b: &mut [f64], k: usize) -> Result<()> {
        crate::error::check_len("right-hand sides", b, self.nrows() * k)?;
        self.solve_cols(b, k, false)
    }
}

fn not_factorized<T>() -> Result<T> {
    Err(Error::SingularMatrix {
        reason: "no factorisation (factorize first)".into(),
    })
}

/// The max norm $\max_i |v_i|$ (NaNs ignored, as a fold with `f64::max`; 0 for an empty slice),
/// in four independent lanes the compiler vectorises (the maximum is exact, so the order does
/// not matter): Newton's and continuation's convergence tests over all unknowns.
///
/// ```
/// assert_eq!(hycont_core::linalg::max_norm(&[1.0, -3.0, f64::NAN, 2.0]), 3.0);
/// ```
#[must_use]
#[inline(always)]
pub fn max_norm(v: &[f64]) -> f64 {
    let mut lanes = [0.0_f64; 4];
    let chunks = v.chunks_exact(4);
    let tail = chunks.remainder();
    for chunk in chunks {
        for (l, x) in lanes.iter_mut().zip(chunk) {
            let y = x.abs();
            *l = if y > *l { y } else { *l };
        }
    }
    for x in tail {
        let y = x.abs();
        lanes[0] = if y > lanes[0] { y } else { lanes[0] };
    }
    lanes
        .into_iter()
        .fold(0.0, |s, l| if l > s { l } else { s })
}

/// Parity sign of a permutation given as an index array.
fn permutation_sign(perm: &[usize]) -> f64 {
    if perm.len() <= 64 {
        // A bit set on the stack (small blocks, every factorisation).
        let mut seen = 0u64;
        let mut sign = 1.0;
        for start in 0..perm.len() {
            let mut i = start;
            let mut len = 0;
            while seen & (1 << i) == 0 {
                seen |= 1 << i;
                i = perm[i];
                len += 1;
            }
            if len > 0 && len % 2 == 0 {
                sign = -sign;
            }
        }
        return sign;
    }
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

#[cfg(test)]
mod tests {
    use super::{max_norm, permutation_sign};
    use proptest::prelude::*;

    /// The parity by definition: the number of inversions.
    fn inversion_sign(perm: &[usize]) -> f64 {
        let mut inversions = 0;
        for i in 0..perm.len() {
            for j in i + 1..perm.len() {
                if perm[i] > perm[j] {
                    inversions += 1;
                }
            }
        }
        if inversions % 2 == 0 { 1.0 } else { -1.0 }
    }

    proptest! {
        /// The lane-wise maximum is the fold with `f64::max` (NaNs ignored), for every length
        /// and remainder.
        #[test]
        fn max_norm_is_the_fold(
            v in proptest::collection::vec(prop_oneof![-1e3f64..1e3, Just(f64::NAN)], 0..40),
        ) {
            let want = v.iter().fold(0.0f64, |s, x| s.max(x.abs()));
            prop_assert_eq!(max_norm(&v), want);
        }

        /// Both the bit-set path (up to 64 entries) and the general one give the parity of the
        /// inversion count.
        #[test]
        fn permutation_sign_is_the_inversion_parity(
            perm in (1usize..100).prop_flat_map(|n| Just((0..n).collect::<Vec<_>>()).prop_shuffle())
        ) {
            prop_assert_eq!(permutation_sign(&perm), inversion_sign(&perm));
        }
    }
}
