//! Collocation meshes: the uniform start, evaluation of a segment's piecewise polynomial, and
//! adaptation by equidistribution of the error estimate.

use super::Mesh;
use super::basis::{Basis, lagrange};

pub(super) fn uniform_mesh(ntst: usize) -> Mesh {
    (0..=ntst).map(|j| j as f64 / ntst as f64).collect()
}

/// Evaluates the piecewise polynomial of one segment at $\tau$.
pub(super) fn eval_piecewise(
    nodes: &[f64],
    mesh: &[f64],
    ncol: usize,
    n: usize,
    tau: f64,
    out: &mut [f64],
) {
    let ntst = mesh.len() - 1;
    let j = match mesh.partition_point(|&m| m <= tau) {
        0 => 0,
        idx => (idx - 1).min(ntst - 1),
    };
    let h = mesh[j + 1] - mesh[j];
    let z = (tau - mesh[j]) / h;
    let basis_nodes: Vec<f64> = (0..=ncol).map(|i| i as f64 / ncol as f64).collect();
    for comp in 0..n {
        out[comp] = (0..=ncol)
            .map(|i| lagrange(&basis_nodes, i, z) * nodes[(j * ncol + i) * n + comp])
            .sum();
    }
}

/// A new mesh equidistributing the error estimate
/// $\|x^{(\mathrm{ncol}+1)}\|^{1/(\mathrm{ncol}+1)}$, the $(\mathrm{ncol}+1)$-th derivative
/// estimated from jumps of the piecewise polynomial's `ncol`-th derivative (as in AUTO).
pub(super) fn adapted_mesh(nodes: &[f64], mesh: &[f64], basis: &Basis, n: usize) -> Mesh {
    let ncol = basis.ncol;
    let ntst = mesh.len() - 1;
    // ncol-th derivative (in tau) on each interval.
    let d: Vec<Vec<f64>> = (0..ntst)
        .map(|j| {
            let h = mesh[j + 1] - mesh[j];
            (0..n)
                .map(|comp| {
                    (0..=ncol)
                        .map(|i| basis.dn[i] * nodes[(j * ncol + i) * n + comp])
                        .sum::<f64>()
                        / h.powi(ncol as i32)
                })
                .collect()
        })
        .collect();
    let jump = |a: usize, b: usize| -> f64 {
        let dist = 0.5 * (mesh[a + 1] - mesh[a] + mesh[b + 1] - mesh[b]);
        (0..n)
            .map(|c| ((d[b][c] - d[a][c]) / dist).abs())
            .fold(0.0, f64::max)
    };
    let density: Vec<f64> = (0..ntst)
        .map(|j| {
            let left = if j > 0 { jump(j - 1, j) } else { 0.0 };
            let right = if j + 1 < ntst { jump(j, j + 1) } else { 0.0 };
            let both = if j > 0 && j + 1 < ntst {
                0.5 * (left + right)
            } else {
                left.max(right)
            };
            both.powf(1.0 / (ncol + 1) as f64)
        })
        .collect();
    let total: f64 = density
        .iter()
        .zip(mesh.windows(2))
        .map(|(w, m)| w * (m[1] - m[0]))
        .sum();
    if !(total > 0.0) || ntst < 2 {
        return mesh.to_vec();
    }
    // Mix with a uniform density (10 %) so that no interval grows unboundedly.
    let floor = 0.1 * total;
    let dens: Vec<f64> = density.iter().map(|w| w + floor).collect();
    let total: f64 = dens
        .iter()
        .zip(mesh.windows(2))
        .map(|(w, m)| w * (m[1] - m[0]))
        .sum();
    let mut out = vec![0.0];
    let mut acc = 0.0;
    let mut j = 0;
    for k in 1..ntst {
        let target = total * k as f64 / ntst as f64;
        while j < ntst && acc + dens[j] * (mesh[j + 1] - mesh[j]) < target {
            acc += dens[j] * (mesh[j + 1] - mesh[j]);
            j += 1;
        }
        let j_c = j.min(ntst - 1);
        out.push(mesh[j_c] + (target - acc) / dens[j_c]);
    }
    out.push(1.0);
    out
}
