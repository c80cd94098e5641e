//! Floquet multipliers of a collocation solution by condensation of its Jacobian.

use super::Mesh;
use super::basis::Basis;
use crate::error::{Error, Result};
use crate::linalg::dense::{eliminate, solve_upper};
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
    let mut m = identity(n);
    // One interval's linearised collocation equations, column-major `rows x (interior, first
    // node, last node)`; eliminating the interior leaves `n` rows [S_0 | S_1] with
    // S_0 dx_0 + S_1 dx_last = 0, so Y_j = -S_1^{-1} S_0.
    let rows = ncol * n;
    let inner = (ncol - 1) * n;
    let width = inner + 2 * n;
    let mut block = vec![0.0; rows * width];
    let mut perm = vec![0; rows];
    let mut pivots = vec![0.0; rows];
    let mut small = vec![0.0; n * 2 * n];
    let mut xi = vec![0.0; n];
    let mut a = vec![0.0; n * n];
    let mut next = vec![0.0; n * n];
    for (k, seg) in orbit.signature.segments().iter().enumerate() {
        let t_k = orbit.durations[k];
        let mut phi = identity(n);
        for (j, w) in meshes[k].windows(2).enumerate() {
            let h = w[1] - w[0];
            let base = j * ncol * n;
            for c in 0..ncol {
                for comp in 0..n {
                    xi[comp] = (0..=ncol)
                        .map(|node| basis.l[c][node] * nodes[k][base + node * n + comp])
                        .sum();
                }
                system.vector_field_jacobian(seg.mode, &xi, p, &mut a, None);
                for node in 0..=ncol {
                    // Interior nodes first, then the first and the last node.
                    let col0 = match node {
                        0 => inner,
                        _ if node == ncol => inner + n,
                        _ => (node - 1) * n,
                    };
                    for comp in 0..n {
                        let col = &mut block[(col0 + comp) * rows..(col0 + comp + 1) * rows];
                        for i in 0..n {
                            let mut v = -h * t_k * a[i + comp * n] * basis.l[c][node];
                            if comp == i {
                                v += basis.dl[c][node];
                            }
                            col[c * n + i] = v;
                        }
                    }
                }
            }
            let singular = || Error::SingularMatrix {
                reason: format!("collocation block {j} of segment {k} is singular"),
            };
            if !eliminate(&mut block, (rows, inner, width), &mut perm, &mut pivots) {
                return Err(singular());
            }
            // [S_1 | S_0] from the rows left, then S_1 Y = -S_0.
            for i in 0..n {
                for col in 0..n {
                    small[i + col * n] = block[inner + i + (inner + n + col) * rows];
                    small[i + (n + col) * n] = -block[inner + i + (inner + col) * rows];
                }
            }
            if !eliminate(&mut small, (n, n, 2 * n), &mut perm[..n], &mut pivots[..n]) {
                return Err(singular());
            }
            // Y_j = U^{-1} (L^{-1} P (-S_0)); Phi <- Y_j Phi.
            let (u, y) = small.split_at_mut(n * n);
            for col in y.chunks_exact_mut(n) {
                solve_upper(u, n, col);
            }
            next.fill(0.0);
            for col in 0..n {
                for l in 0..n {
                    let f = phi[l + col * n];
                    for i in 0..n {
                        next[i + col * n] += small[i + (n + l) * n] * f;
                    }
                }
            }
            std::mem::swap(&mut phi, &mut next);
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

fn identity(n: usize) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i + i * n] = 1.0;
    }
    m
}
