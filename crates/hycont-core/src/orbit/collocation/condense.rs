//! Floquet multipliers of a collocation solution by condensation of its Jacobian.

use super::Mesh;
use super::basis::Basis;
use crate::error::{Error, Result};
use crate::orbit::PeriodicOrbit;
use crate::orbit::floquet::{Floquet, matmul, saltation};
use crate::system::HybridJacobians;

/// Multipliers from the collocation Jacobian by condensation: on each mesh interval the
/// linearised collocation equations $A_0 \delta x_{j,0} + A_1 (\delta x_{j,1}, \dots,
/// \delta x_{j,\mathrm{ncol}}) = 0$ (durations and parameters fixed) give the interval's transfer
/// matrix $Y_j$ from its first node to its last; $\Phi_k = Y_{\mathrm{ntst}-1} \cdots Y_0$ is the
/// discrete flow Jacobian of segment $k$, combined with the saltation matrices.
pub(super) fn condensed_floquet<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    nodes: &[Vec<f64>],
    ncol: usize,
) -> Result<Floquet> {
    let n = system.state_dim();
    let basis = Basis::new(ncol);
    let p = &orbit.params;
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i + i * n] = 1.0;
    }
    let rows = ncol * n;
    let mut xi = vec![0.0; n];
    let mut a = vec![0.0; n * n];
    for (k, seg) in orbit.signature.segments().iter().enumerate() {
        let t_k = orbit.durations[k];
        let mut phi = vec![0.0; n * n];
        for i in 0..n {
            phi[i + i * n] = 1.0;
        }
        for (j, w) in meshes[k].windows(2).enumerate() {
            let h = w[1] - w[0];
            let base = j * ncol * n;
            // A0 (rows x n) and A1 (rows x rows).
            let mut a0 = faer::Mat::<f64>::zeros(rows, n);
            let mut a1 = faer::Mat::<f64>::zeros(rows, rows);
            for c in 0..ncol {
                for comp in 0..n {
                    xi[comp] = (0..=ncol)
                        .map(|node| basis.l[c][node] * nodes[k][base + node * n + comp])
                        .sum();
                }
                system.vector_field_jacobian(seg.mode, &xi, p, &mut a, None);
                for i in 0..n {
                    let row = c * n + i;
                    for node in 0..=ncol {
                        for comp in 0..n {
                            let mut v = -h * t_k * a[i + comp * n] * basis.l[c][node];
                            if comp == i {
                                v += basis.dl[c][node];
                            }
                            if node == 0 {
                                a0[(row, comp)] = -v;
                            } else {
                                a1[(row, (node - 1) * n + comp)] = v;
                            }
                        }
                    }
                }
            }
            let x = faer::linalg::solvers::Solve::solve(&a1.partial_piv_lu(), &a0);
            // Y_j: the last node's rows; Phi <- Y_j Phi.
            let mut next = vec![0.0; n * n];
            for col in 0..n {
                for i in 0..n {
                    next[i + col * n] = (0..n)
                        .map(|l| x[(rows - n + i, l)] * phi[l + col * n])
                        .sum();
                }
            }
            phi = next;
        }
        if phi.iter().any(|v: &f64| !v.is_finite()) {
            return Err(Error::SingularMatrix {
                reason: format!("a collocation block of segment {k} is singular"),
            });
        }
        let end_state = &nodes[k][nodes[k].len() - n..];
        let s = saltation(system, orbit, k, end_state);
        m = matmul(n, &matmul(n, &s, &phi), &m);
    }
    Floquet::from_monodromy(system, &orbit.params, orbit.period(), m)
}
