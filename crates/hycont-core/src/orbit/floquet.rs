//! Floquet multipliers of hybrid periodic orbits.
//!
//! The monodromy matrix of an orbit with segments $k = 0, \dots, K-1$ is
//! $$M = S_{K-1} \Phi_{K-1} \cdots S_1 \Phi_1 S_0 \Phi_0,$$
//! with $\Phi_k$ the flow Jacobian of segment $k$ and $S_k$ the saltation matrix of its end
//! ($I$ at interior points). Its eigenvalues are the Floquet multipliers; the system's structural
//! ones ([`crate::HybridSystem::trivial_multipliers`], e.g. 1 for the flow direction) are flagged
//! and excluded from the stability verdict.

use crate::error::Result;
use crate::linalg::eigenvalues;
use crate::system::{HybridJacobians, HybridSystem};
use serde::{Deserialize, Serialize};

use super::PeriodicOrbit;
use super::signature::SegmentEnd;

/// Multipliers within this (relative) distance of the unit circle are *neutral*: they count
/// as neither stable nor unstable in [`Floquet::unstable`] (and the continuation's branch points).
///
/// At a located fold or branch point a multiplier is exactly 1, at a period doubling -1, at a
/// torus bifurcation a pair lies on the circle; each discretisation puts it there only up to
/// its own error (shooting to about the integration tolerance, collocation to the mesh's
/// error, both well below $10^{-6}$). Without the band one method would call such a point
/// unstable and the other stable; with it both give the point the stability of its other
/// multipliers. Away from special points no multiplier comes this close to the circle.
pub const NEUTRAL_BAND: f64 = 1e-6;

/// Floquet multipliers of a periodic orbit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Floquet {
    /// All multipliers `(re, im)`, by decreasing modulus.
    pub multipliers: Vec<(f64, f64)>,
    /// Whether each multiplier is one of the system's trivial (structural) multipliers.
    pub trivial: Vec<bool>,
    /// Number of non-trivial multipliers outside the unit circle by more than
    /// [`NEUTRAL_BAND`] (relative).
    pub unstable: usize,
    /// The monodromy matrix (column-major), at the start of segment 0 (of that segment's
    /// mode's dimension).
    pub monodromy: Vec<f64>,
}

impl Floquet {
    /// Whether all non-trivial multipliers are inside the unit circle (up to the
    /// [`NEUTRAL_BAND`]).
    #[must_use]
    pub fn stable(&self) -> bool {
        self.unstable == 0
    }

    /// The monodromy matrix ($n \times n$).
    #[must_use]
    pub fn monodromy_matrix(&self) -> nalgebra::DMatrix<f64> {
        let n = self.multipliers.len();
        nalgebra::DMatrix::from_column_slice(n, n, &self.monodromy)
    }

    /// The Floquet vectors: unit eigenvectors of the monodromy matrix, as columns in the order
    /// of [`Floquet::multipliers`] (complex for complex multipliers).
    ///
    /// # Errors
    /// If the eigendecomposition fails.
    pub fn vectors(&self) -> Result<nalgebra::DMatrix<nalgebra::Complex<f64>>> {
        crate::linalg::eigenvectors(self.multipliers.len(), &self.monodromy).map(|(_, v)| v)
    }

    /// The non-trivial multipliers.
    pub fn nontrivial(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.multipliers
            .iter()
            .zip(&self.trivial)
            .filter(|(_, t)| !**t)
            .map(|(m, _)| *m)
    }

    /// Multipliers of a monodromy matrix, with the system's trivial ones flagged (each trivial
    /// value claims the closest multiplier not yet claimed).
    ///
    /// # Errors
    /// If the eigenvalue iteration fails.
    pub fn from_monodromy<S: HybridSystem + ?Sized>(
        system: &S,
        params: &[f64],
        period: f64,
        monodromy: Vec<f64>,
    ) -> Result<Self> {
        // The monodromy lives in the first segment's space, whose dimension may be less than
        // the system's largest (`HybridSystem::mode_dim`).
        let n = monodromy.len().isqrt();
        if n * n != monodromy.len() {
            return Err(crate::Error::DimensionMismatch {
                what: "monodromy matrix (n x n entries)",
                expected: n * n,
                found: monodromy.len(),
            });
        }
        let multipliers = eigenvalues(n, &monodromy)?;
        let mut trivial = vec![false; n];
        for (tr, ti) in system.trivial_multipliers(params, period) {
            let best = multipliers
                .iter()
                .enumerate()
                .filter(|(i, _)| !trivial[*i])
                .min_by(|a, b| {
                    let da = (a.1.0 - tr).hypot(a.1.1 - ti);
                    let db = (b.1.0 - tr).hypot(b.1.1 - ti);
                    da.total_cmp(&db)
                })
                .map(|(i, _)| i);
            if let Some(i) = best {
                trivial[i] = true;
            }
        }
        let unstable = multipliers
            .iter()
            .zip(&trivial)
            .filter(|((re, im), t)| !**t && re.hypot(*im) > 1.0 + NEUTRAL_BAND)
            .count();
        Ok(Self {
            multipliers,
            trivial,
            unstable,
            monodromy,
        })
    }
}

/// $C = A B$ for a column-major $m \times l$ matrix $A$ and $l \times n$ matrix $B$ ($C$:
/// $m \times n$).
pub(crate) fn matmul_rect(m: usize, l: usize, a: &[f64], b: &[f64]) -> Vec<f64> {
    let n = b.len() / l.max(1);
    let mut c = vec![0.0; m * n];
    let a = nalgebra::DMatrixView::from_slice(&a[..m * l], m, l);
    let b = nalgebra::DMatrixView::from_slice(b, l, n);
    nalgebra::DMatrixViewMut::from_slice(&mut c, m, n).gemm(1.0, &a, &b, 0.0);
    c
}

/// $C = A B$ for column-major $n \times n$ matrices, by nalgebra (three times faster than a
/// plain loop at $n = 4$: `cargo bench -p hycont-core --bench dense`).
pub(crate) fn matmul(n: usize, a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; n * n];
    matmul_into(n, a, b, &mut c);
    c
}

/// [`matmul`] into `c` (no allocation); up to $n = 8$ with nalgebra's fixed-size matrices
/// (the collocation monodromy does one such product per mesh interval).
pub(crate) fn matmul_into(n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    match n {
        1 => matmul_fixed::<1>(a, b, c),
        2 => matmul_fixed::<2>(a, b, c),
        3 => matmul_fixed::<3>(a, b, c),
        4 => matmul_fixed::<4>(a, b, c),
        5 => matmul_fixed::<5>(a, b, c),
        6 => matmul_fixed::<6>(a, b, c),
        7 => matmul_fixed::<7>(a, b, c),
        8 => matmul_fixed::<8>(a, b, c),
        _ => matmul_dynamic(n, a, b, c),
    }
}

/// [`matmul_into`] for `N` known at compile time: for $n \le 5$ the same sums in the same
/// order as the dynamic product (nalgebra's column-by-column `gemv` below its `matrixmultiply`
/// threshold), so the same numbers.
fn matmul_fixed<const N: usize>(a: &[f64], b: &[f64], c: &mut [f64]) {
    let a = nalgebra::SMatrix::<f64, N, N>::from_column_slice(a);
    let b = nalgebra::SMatrix::<f64, N, N>::from_column_slice(b);
    c.copy_from_slice((a * b).as_slice());
}

/// [`matmul_into`] for any `n`.
fn matmul_dynamic(n: usize, a: &[f64], b: &[f64], c: &mut [f64]) {
    let a = nalgebra::DMatrixView::from_slice(a, n, n);
    let b = nalgebra::DMatrixView::from_slice(b, n, n);
    // beta = 0: `c` is not read.
    nalgebra::DMatrixViewMut::from_slice(c, n, n).gemm(1.0, &a, &b, 0.0);
}

/// The saltation matrix $S_k$ at the end of segment `k` of `orbit`, whose state before the jump
/// is `end_state`: $S = g_x + (f^+ - g_x f^-) h_x / (h_x f^-)$ with $h$ the event function, $g$
/// its reset and $f^\mp$ the vector fields before and after (the identity at interior points).
/// It is $n_{k+1} \times n_k$ where the event leads into a mode of another dimension
/// ([`crate::HybridSystem::mode_dim`]). The monodromy is
/// $M = S_{K-1}\Phi_{K-1} \cdots S_0 \Phi_0$, in the first segment's space.
#[must_use]
pub fn saltation_matrix<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    k: usize,
    end_state: &[f64],
) -> nalgebra::DMatrix<f64> {
    let (n, n_to) = (end_state.len(), next_dim(system, orbit, k));
    nalgebra::DMatrix::from_vec(n_to, n, saltation(system, orbit, k, end_state))
}

/// The dimension of the state segment `k` of `orbit` ends in (the next segment's mode's).
pub(crate) fn next_dim<S: HybridSystem + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    k: usize,
) -> usize {
    system.mode_dim(orbit.signature.next_mode(system, k))
}

/// The saltation matrix $S_k$ at the end of segment `k` ($n_{k+1} \times n_k$, column-major;
/// the identity at interior points).
pub(crate) fn saltation<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    k: usize,
    end_state: &[f64],
) -> Vec<f64> {
    let next_mode = orbit.signature.next_mode(system, k);
    let (n, m) = (end_state.len(), system.mode_dim(next_mode));
    let p = &orbit.params;
    let segs = orbit.signature.segments();
    let mut s = vec![0.0; m * n];
    match segs[k].end {
        SegmentEnd::Interior { .. } => {
            for i in 0..n.min(m) {
                s[i + i * m] = 1.0;
            }
        }
        SegmentEnd::Event(e) => {
            // One work space for f^-, f^+, h_x, g_x and g(x).
            let mut work = vec![0.0; 2 * (n + m) + m * n];
            let (fm, rest) = work.split_at_mut(n);
            let (fp, rest) = rest.split_at_mut(m);
            let (hx, rest) = rest.split_at_mut(n);
            let (xp, gx) = rest.split_at_mut(m);
            system.vector_field(segs[k].mode, end_state, p, fm);
            system.event_gradient(e, end_state, p, hx, None);
            system.reset(e, end_state, p, xp);
            system.reset_jacobian(e, end_state, p, gx, None);
            system.vector_field(next_mode, xp, p, fp);
            let denom: f64 = hx.iter().zip(fm.iter()).map(|(a, b)| a * b).sum();
            for j in 0..n {
                for i in 0..m {
                    let gxf: f64 = (0..n).map(|l| gx[i + l * m] * fm[l]).sum();
                    s[i + j * m] = gx[i + j * m] + (fp[i] - gxf) * hx[j] / denom;
                }
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::{matmul_dynamic, matmul_into};
    use proptest::prelude::*;

    proptest! {
        /// The fixed-size products give the dynamic product's numbers: to the bit up to
        /// $n = 5$ (the same sums in the same order), within roundoff of the sums' magnitudes
        /// where the dynamic product goes to `matrixmultiply` (6 to 8).
        #[test]
        fn fixed_size_products_agree_with_the_dynamic_one(
            n in 1usize..=8,
            entries in proptest::collection::vec(-10.0f64..10.0, 128),
        ) {
            let (a, b) = (&entries[..n * n], &entries[64..64 + n * n]);
            let (mut fixed, mut dynamic) = (vec![0.0; n * n], vec![0.0; n * n]);
            matmul_into(n, a, b, &mut fixed);
            matmul_dynamic(n, a, b, &mut dynamic);
            for (k, (x, y)) in fixed.iter().zip(&dynamic).enumerate() {
                let (i, j) = (k % n, k / n);
                let magnitude: f64 = (0..n).map(|l| (a[i + l * n] * b[l + j * n]).abs()).sum();
                let tol = if n <= 5 { 0.0 } else { 4.0 * n as f64 * f64::EPSILON * magnitude };
                prop_assert!((x - y).abs() <= tol, "n = {}, entry {}: {} vs {}", n, k, x, y);
            }
        }
    }
}
