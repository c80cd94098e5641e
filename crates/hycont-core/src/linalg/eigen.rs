//! Eigenvalues and eigenvectors of small dense real matrices (monodromy matrices).

use crate::error::{Error, Result};
use nalgebra::{Complex, DMatrix};

/// A complex number of `f64` (as nalgebra's and faer's).
type Complex64 = Complex<f64>;

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
