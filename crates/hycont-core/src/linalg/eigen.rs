//! Eigenvalues and eigenvectors of small dense real matrices (monodromy matrices).

use crate::error::{Error, Result};
use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DMatrix, DefaultAllocator, DimDiff, DimSub, OMatrix, SMatrix, U1};

/// A complex number of `f64` (as nalgebra's and faer's).
type Complex64 = Complex<f64>;

/// Eigenvalues of a small dense real matrix (column-major, `n x n`) as `(re, im)` pairs, sorted
/// by decreasing modulus: the real Schur form by Francis' double-shift QR (nalgebra; at most
/// $30 \max(n, 10)$ iterations, LAPACK's limit), its diagonal blocks' eigenvalues.
///
/// ```
/// // A rotation by 90 degrees: eigenvalues +-i.
/// let ev = hycont_core::linalg::eigenvalues(2, &[0.0, 1.0, -1.0, 0.0]).unwrap();
/// assert!(ev.iter().all(|z| z.0.abs() < 1e-15 && (z.1.abs() - 1.0).abs() < 1e-15));
/// ```
///
/// # Errors
/// [`Error::SingularMatrix`] if the matrix is not finite or the iteration does not converge.
pub fn eigenvalues(n: usize, a: &[f64]) -> Result<Vec<(f64, f64)>> {
    crate::error::check_len("matrix", a, n * n)?;
    let fail = |why: &str| Error::SingularMatrix {
        reason: format!("eigenvalue iteration failed: {why}"),
    };
    if !a.iter().all(|x| x.is_finite()) {
        return Err(fail("the matrix is not finite"));
    }
    if n == 0 {
        return Ok(Vec::new());
    }
    let limit = 30 * n.max(10);
    // Sizes up to 8 on the stack (a Floquet analysis at every point of a branch): the same
    // algorithm, generic over the dimension, gives the same numbers without its allocations.
    macro_rules! fixed {
        ($($k:literal)*) => {
            match n {
                $($k => schur_eigenvalues(SMatrix::<f64, $k, $k>::from_column_slice(a), limit),)*
                _ => schur_eigenvalues(DMatrix::from_column_slice(n, n, a), limit),
            }
        };
    }
    let mut out = fixed!(1 2 3 4 5 6 7 8).ok_or_else(|| fail("no convergence"))?;
    out.sort_by(|a, b| (b.0.hypot(b.1)).total_cmp(&a.0.hypot(a.1)));
    Ok(out)
}

/// The eigenvalues of `m` from its real Schur form (at most `limit` iterations), unsorted.
fn schur_eigenvalues<D>(m: OMatrix<f64, D, D>, limit: usize) -> Option<Vec<(f64, f64)>>
where
    D: DimSub<U1>,
    DefaultAllocator:
        Allocator<D, DimDiff<D, U1>> + Allocator<DimDiff<D, U1>> + Allocator<D, D> + Allocator<D>,
{
    let schur = nalgebra::linalg::Schur::try_new(m, f64::EPSILON, limit)?;
    Some(
        schur
            .complex_eigenvalues()
            .iter()
            .map(|z| (z.re, z.im))
            .collect(),
    )
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

#[cfg(test)]
mod tests {
    use super::eigenvalues;
    use proptest::prelude::*;

    proptest! {
        /// Against faer's eigenvalues (an independent QR implementation): every eigenvalue has
        /// a partner in faer's within $10^{-10} \|A\|_F$ (random matrices have well-conditioned
        /// eigenvalues: their errors are a few units of roundoff times $\|A\|$), the list is
        /// sorted by decreasing modulus, and the sum is the trace.
        #[test]
        fn eigenvalues_match_an_independent_implementation(
            n in 1usize..=8,
            values in proptest::collection::vec(-1.0f64..1.0, 64),
        ) {
            let a = &values[..n * n];
            let ev = eigenvalues(n, a).unwrap();
            let reference = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i + j * n])
                .eigenvalues()
                .unwrap();
            let norm = a.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-300);
            prop_assert_eq!(ev.len(), n);
            for &(re, im) in &ev {
                let d = reference
                    .iter()
                    .map(|z| (z.re - re).hypot(z.im - im))
                    .fold(f64::INFINITY, f64::min);
                prop_assert!(d <= 1e-10 * norm, "{:?} vs {:?}", ev, reference);
            }
            for w in ev.windows(2) {
                prop_assert!(w[0].0.hypot(w[0].1) >= w[1].0.hypot(w[1].1));
            }
            let trace: f64 = (0..n).map(|i| a[i + i * n]).sum();
            let sum: f64 = ev.iter().map(|z| z.0).sum();
            prop_assert!((sum - trace).abs() <= 1e-12 * norm * n as f64);
        }

        /// The sizes kept on the stack give the heap path's eigenvalues to the bit (the same
        /// algorithm, generic over the dimension), on matrices with some entries zero.
        #[test]
        fn stack_sizes_give_the_general_numbers(
            n in 1usize..=8,
            values in proptest::collection::vec(
                prop_oneof![3 => -1.0f64..1.0, 1 => Just(0.0)], 64),
        ) {
            let a = &values[..n * n];
            let stack = eigenvalues(n, a).unwrap();
            let m = nalgebra::DMatrix::from_column_slice(n, n, a);
            let mut heap = super::schur_eigenvalues(m, 30 * n.max(10)).unwrap();
            heap.sort_by(|a, b| (b.0.hypot(b.1)).total_cmp(&a.0.hypot(a.1)));
            let bits = |v: &[(f64, f64)]| -> Vec<(u64, u64)> {
                v.iter().map(|z| (z.0.to_bits(), z.1.to_bits())).collect()
            };
            prop_assert_eq!(bits(&stack), bits(&heap));
        }
    }

    #[test]
    fn non_finite_matrices_are_refused() {
        assert!(eigenvalues(2, &[1.0, f64::NAN, 0.0, 1.0]).is_err());
        assert!(eigenvalues(2, &[1.0, 0.0, 0.0]).is_err());
        assert!(eigenvalues(0, &[]).unwrap().is_empty());
    }
}
