//! Floquet multipliers of a collocation solution by condensation of its Jacobian.
//!
//! On each mesh interval the linearised collocation equations (durations and parameters fixed)
//! read $A_I\,\delta x_I + A_0\,\delta x_{j,0} + A_1\,\delta x_{j,\mathrm{ncol}} = 0$ with
//! $\delta x_I$ the interior nodes. Eliminating $\delta x_I$ leaves $n$ equations
//! $S_0\,\delta x_{j,0} + S_1\,\delta x_{j,\mathrm{ncol}} = 0$: the interval's transfer matrix is
//! $Y_j = -S_1^{-1} S_0$, and $\Phi_k = Y_{\mathrm{ntst}-1} \cdots Y_0$ is the discrete flow
//! Jacobian of segment $k$, combined with the saltation matrices. The rows $[S_0\ S_1]$ come
//! either from a fresh elimination ([`condensed_floquet`]) or from a factorisation that has
//! already condensed the intervals ([`factorised_floquet`]).

use super::Mesh;
use super::basis::Basis;
use super::transfer::Transfer;
use crate::error::{Error, Result};
use crate::linalg::SparsePattern;
use crate::linalg::dense::eliminate;
use crate::orbit::PeriodicOrbit;
use crate::orbit::floquet::{Floquet, matmul_into, matmul_rect, saltation};
use crate::system::HybridJacobians;

/// Multipliers by eliminating each interval's interior nodes afresh.
pub(super) fn condensed_floquet<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    nodes: &[Vec<f64>],
    ncol: usize,
) -> Result<Floquet> {
    let basis = Basis::shared(ncol);
    let (mut block, mut perm, mut pivots) = (Vec::new(), Vec::new(), Vec::new());
    let (mut xi, mut a) = (Vec::new(), Vec::new());
    let mut small = Transfer::new(0);
    let transfer = |k: usize, j: usize, y: &mut [f64]| {
        let mode = orbit.signature.segments()[k].mode;
        // One interval's linearised collocation equations, column-major `rows x (interior,
        // first node, last node)`, in the segment's mode's dimension (every entry written).
        let n = orbit.starts[k].len();
        let (rows, inner) = (ncol * n, (ncol - 1) * n);
        let width = inner + 2 * n;
        block.resize(rows * width, 0.0);
        perm.resize(rows, 0);
        pivots.resize(rows, 0.0);
        xi.resize(n, 0.0);
        a.resize(n * n, 0.0);
        small.resize(n);
        let (t_k, h) = (orbit.durations[k], meshes[k][j + 1] - meshes[k][j]);
        let base = j * ncol * n;
        for c in 0..ncol {
            for comp in 0..n {
                xi[comp] = (0..=ncol)
                    .map(|node| basis.l[c][node] * nodes[k][base + node * n + comp])
                    .sum();
            }
            system.vector_field_jacobian(mode, &xi, &orbit.params, &mut a, None);
            let scale = -h * t_k;
            for (node, (&l, &dl)) in basis.l[c].iter().zip(&basis.dl[c]).enumerate() {
                // Interior nodes first, then the first and the last node.
                let col0 = match node {
                    0 => inner,
                    _ if node == ncol => inner + n,
                    _ => (node - 1) * n,
                };
                // Rows c n.. of the node's columns: -h T A l, plus dl on the diagonal.
                for (comp, a_col) in a.chunks_exact(n).enumerate() {
                    let at = (col0 + comp) * rows + c * n;
                    for (v, &aij) in block[at..at + n].iter_mut().zip(a_col) {
                        *v = scale * aij * l;
                    }
                    block[at + comp] += dl;
                }
            }
        }
        if eliminate(&mut block, (rows, inner, width), &mut perm, &mut pivots).is_none() {
            return Err(singular(k, j));
        }
        small.solve(|i, col| block[inner + i + (inner + col) * rows], k, j, y)
    };
    floquet_from_transfers(system, orbit, meshes, nodes, transfer)
}

/// Multipliers from a factorised Jacobian whose first condensed blocks are the intervals of
/// every segment in order, with the collocation unknowns first among its columns (as
/// [`super::collocation_problem`] and continuation build them). `None` if the factorisation was
/// not condensed or its blocks do not have this layout.
pub(super) fn factorised_floquet<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    nodes: &[Vec<f64>],
    ncol: usize,
    jacobian: &SparsePattern,
) -> Result<Option<Floquet>> {
    let mut small = Transfer::new(0);
    let mut offsets = Vec::with_capacity(meshes.len());
    let (mut block, mut offset, mut columns) = (0, 0, 0);
    for (k, mesh) in meshes.iter().enumerate() {
        // (first block, first unknown, first found column) of the segment.
        offsets.push((block, offset, columns));
        block += mesh.len() - 1;
        offset += nodes[k].len();
        columns += 2 * orbit.starts[k].len() * (mesh.len() - 1);
    }
    // Every interval's columns of (first node, last node) over its n_k rows, `2 n_k` per
    // interval in one list, or give up.
    let mut found: Vec<&[f64]> = Vec::with_capacity(columns);
    for (k, mesh) in meshes.iter().enumerate() {
        let (b0, off, _) = offsets[k];
        let n = orbit.starts[k].len();
        for j in 0..mesh.len() - 1 {
            let Some(rows) = jacobian.reduced_rows(b0 + j) else {
                return Ok(None);
            };
            if rows.rows() != n {
                return Ok(None);
            }
            let first = off + j * ncol * n;
            // A node's n columns are consecutive among the sorted columns the rows read.
            for node in [first, first + ncol * n] {
                let Ok(at) = rows.columns().binary_search(&node) else {
                    return Ok(None);
                };
                for c in 0..n {
                    match (rows.columns().get(at + c), rows.column(at + c)) {
                        (Some(&col), Some(values)) if col == node + c => found.push(values),
                        _ => return Ok(None),
                    }
                }
            }
        }
    }
    let transfer = |k: usize, j: usize, y: &mut [f64]| {
        // In range: every column was found, with `n_k` rows.
        let n = orbit.starts[k].len();
        small.resize(n);
        let at = offsets[k].2 + 2 * n * j;
        let cols = &found[at..at + 2 * n];
        small.solve(|i, col| cols[col][i], k, j, y)
    };
    floquet_from_transfers(system, orbit, meshes, nodes, transfer).map(Some)
}

pub(super) fn singular(k: usize, j: usize) -> Error {
    Error::SingularMatrix {
        reason: format!("collocation block {j} of segment {k} is singular"),
    }
}

/// The monodromy from the intervals' transfer matrices (`transfer(k, j, y)` writes $Y_j$ of
/// segment `k`, column-major) and the saltation matrices, and its multipliers.
fn floquet_from_transfers<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    nodes: &[Vec<f64>],
    mut transfer: impl FnMut(usize, usize, &mut [f64]) -> Result<()>,
) -> Result<Floquet> {
    // M maps the first segment's start to segment k's (n_k x n_0); S_k is n_{k+1} x n_k.
    let mut m = identity(orbit.starts[0].len());
    for (k, mesh) in meshes.iter().enumerate() {
        let n = orbit.starts[k].len();
        let mut y = vec![0.0; n * n];
        let mut product = vec![0.0; n * n];
        let mut phi = identity(n);
        for j in 0..mesh.len() - 1 {
            transfer(k, j, &mut y)?;
            matmul_into(n, &y, &phi, &mut product);
            std::mem::swap(&mut phi, &mut product);
        }
        if phi.iter().any(|v: &f64| !v.is_finite()) {
            return Err(Error::SingularMatrix {
                reason: format!("a collocation block of segment {k} is singular"),
            });
        }
        let end_state = &nodes[k][nodes[k].len() - n..];
        let s = saltation(system, orbit, k, end_state);
        let n_to = s.len() / n;
        m = matmul_rect(n_to, n, &matmul_rect(n_to, n, &s, &phi), &m);
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
