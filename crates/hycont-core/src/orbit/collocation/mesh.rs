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

/// Estimates of $\|x^{(\mathrm{ncol}+1)}\|_\infty$ (derivative in $\tau$, the segment's time
/// scaled to $[0, 1]$) on each interval, from the jumps of the piecewise polynomial's
/// `ncol`-th derivative between neighbouring intervals (as in AUTO; largest over the state
/// components): the mean of the two jumps of an interior interval, the one jump of an end
/// interval.
fn high_derivatives(nodes: &[f64], mesh: &[f64], basis: &Basis, n: usize) -> Vec<f64> {
    let ncol = basis.ncol;
    let ntst = mesh.len() - 1;
    // ncol-th derivative (in tau) on each interval, `n` per interval.
    let mut d = vec![0.0; ntst * n];
    for (j, dj) in d.chunks_exact_mut(n).enumerate() {
        let scale = (mesh[j + 1] - mesh[j]).powi(ncol as i32);
        let interval = &nodes[j * ncol * n..(j * ncol + ncol + 1) * n];
        for (comp, x) in dj.iter_mut().enumerate() {
            let sum: f64 = (0..=ncol)
                .map(|i| basis.dn[i] * interval[i * n + comp])
                .sum();
            *x = sum / scale;
        }
    }
    let d = |j: usize| &d[j * n..(j + 1) * n];
    let jump = |a: usize, b: usize| -> f64 {
        let dist = 0.5 * (mesh[a + 1] - mesh[a] + mesh[b + 1] - mesh[b]);
        (0..n)
            .map(|c| ((d(b)[c] - d(a)[c]) / dist).abs())
            .fold(0.0, f64::max)
    };
    (0..ntst)
        .map(|j| {
            let left = if j > 0 { jump(j - 1, j) } else { 0.0 };
            let right = if j + 1 < ntst { jump(j, j + 1) } else { 0.0 };
            if j > 0 && j + 1 < ntst {
                0.5 * (left + right)
            } else {
                left.max(right)
            }
        })
        .collect()
}

/// The constant $C_m = \max_{z \in [0, 1]} \bigl|\int_0^z \prod_{i=1}^m (s - c_i)\,ds\bigr| / m!$
/// of the leading interior error of collocation at the Gauss points $c_i$ (de Boor and Swartz):
/// on an interval of width $h$, $x - p \approx x^{(m+1)} h^{m+1} \int_0^z \prod (s - c_i)\,ds
/// / m!$, the error at the interval's left end being of higher order ($h^{2m}$).
fn interior_error_constant(m: usize) -> f64 {
    static CONSTANTS: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let table = CONSTANTS.get_or_init(|| (0..=7).map(compute_constant).collect());
    table.get(m).copied().unwrap_or_else(|| compute_constant(m))
}

/// [`interior_error_constant`], computed (`ncol` is at most 7).
fn compute_constant(m: usize) -> f64 {
    let c = super::basis::gauss_legendre_points(m);
    // Coefficients of prod (s - c_i), lowest degree first, then of its integral from 0.
    let mut poly = vec![1.0];
    for ci in &c {
        let mut next = vec![0.0; poly.len() + 1];
        for (k, a) in poly.iter().enumerate() {
            next[k + 1] += a;
            next[k] -= ci * a;
        }
        poly = next;
    }
    let integral: Vec<f64> = std::iter::once(0.0)
        .chain(poly.iter().enumerate().map(|(k, a)| a / (k + 1) as f64))
        .collect();
    let factorial: f64 = (1..=m).map(|k| k as f64).product();
    (0..=1000)
        .map(|i| {
            let z = f64::from(i) / 1000.0;
            integral.iter().rev().fold(0.0, |acc, a| acc * z + a).abs()
        })
        .fold(0.0, f64::max)
        / factorial
}

/// The estimated largest error $\max |x(\tau) - p(\tau)|$ of one segment's collocation
/// polynomial: $C_m h_j^{m+1} \|x^{(m+1)}\|$ on each interval (see
/// [`interior_error_constant`] and [`high_derivatives`]), largest over intervals and
/// components. Zero for a single interval (no jump to estimate from).
pub(super) fn error_estimate(nodes: &[f64], mesh: &[f64], basis: &Basis, n: usize) -> f64 {
    let m = basis.ncol;
    let c = interior_error_constant(m);
    high_derivatives(nodes, mesh, basis, n)
        .iter()
        .zip(mesh.windows(2))
        .map(|(d, w)| {
            let h = w[1] - w[0];
            c * h.powi(m as i32 + 1) * d
        })
        .fold(0.0, f64::max)
}

/// One segment's node states on `new_mesh` (the same `ncol`): its piecewise polynomial on
/// `mesh` evaluated at the new nodes; the last node is copied.
pub(super) fn transfer_nodes(
    nodes: &[f64],
    mesh: &[f64],
    new_mesh: &[f64],
    ncol: usize,
    n: usize,
) -> Vec<f64> {
    let mut vals = Vec::with_capacity(((new_mesh.len() - 1) * ncol + 1) * n);
    let mut x = vec![0.0; n];
    for w in new_mesh.windows(2) {
        for i in 0..ncol {
            let tau = w[0] + (i as f64 / ncol as f64) * (w[1] - w[0]);
            eval_piecewise(nodes, mesh, ncol, n, tau, &mut x);
            vals.extend_from_slice(&x);
        }
    }
    vals.extend_from_slice(&nodes[nodes.len() - n..]);
    vals
}

/// A new mesh equidistributing the error estimate
/// $\|x^{(\mathrm{ncol}+1)}\|^{1/(\mathrm{ncol}+1)}$, the $(\mathrm{ncol}+1)$-th derivative
/// estimated from jumps of the piecewise polynomial's `ncol`-th derivative (as in AUTO).
pub(super) fn adapted_mesh(nodes: &[f64], mesh: &[f64], basis: &Basis, n: usize) -> Mesh {
    adapted_mesh_of_size(nodes, mesh, basis, n, mesh.len() - 1)
}

/// [`adapted_mesh`] with `size` intervals.
pub(super) fn adapted_mesh_of_size(
    nodes: &[f64],
    mesh: &[f64],
    basis: &Basis,
    n: usize,
    size: usize,
) -> Mesh {
    let ncol = basis.ncol;
    let ntst = mesh.len() - 1;
    let density: Vec<f64> = high_derivatives(nodes, mesh, basis, n)
        .iter()
        .map(|d| d.powf(1.0 / (ncol + 1) as f64))
        .collect();
    let total: f64 = density
        .iter()
        .zip(mesh.windows(2))
        .map(|(w, m)| w * (m[1] - m[0]))
        .sum();
    if !(total > 0.0) || ntst < 2 {
        return if size == ntst {
            mesh.to_vec()
        } else {
            uniform_mesh(size)
        };
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
    for k in 1..size {
        let target = total * k as f64 / size as f64;
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
