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
    let dn = &basis.dn[..=ncol];
    // ncol-th derivative (in tau) on each interval, `n` per interval: the sum over the
    // interval's nodes in node order, component by component.
    let mut d = vec![0.0; ntst * n];
    for (j, dj) in d.chunks_exact_mut(n.max(1)).enumerate() {
        let scale = (mesh[j + 1] - mesh[j]).powi(ncol as i32);
        let interval = &nodes[j * ncol * n..(j * ncol + ncol + 1) * n];
        let mut states = interval.chunks_exact(n.max(1)).zip(dn);
        if let Some((x, &c)) = states.next() {
            for (o, xi) in dj.iter_mut().zip(x) {
                *o = c * xi;
            }
        }
        for (x, &c) in states {
            for (o, xi) in dj.iter_mut().zip(x) {
                *o += c * xi;
            }
        }
        for o in dj.iter_mut() {
            *o /= scale;
        }
    }
    // The jump between intervals j and j + 1, once for both.
    let jumps: Vec<f64> = (1..ntst)
        .map(|b| {
            let a = b - 1;
            let dist = 0.5 * (mesh[a + 1] - mesh[a] + mesh[b + 1] - mesh[b]);
            let (da, db) = (&d[a * n..(a + 1) * n], &d[b * n..(b + 1) * n]);
            da.iter()
                .zip(db)
                .map(|(x, y)| ((y - x) / dist).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    (0..ntst)
        .map(|j| {
            let left = if j > 0 { jumps[j - 1] } else { 0.0 };
            let right = if j + 1 < ntst { jumps[j] } else { 0.0 };
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

#[cfg(test)]
mod tests {
    use super::high_derivatives;
    use crate::orbit::collocation::basis::Basis;

    /// The estimate of $x^{(m+1)}$ is exact for $x(\tau) = c\,\tau^{m+1}$ on any mesh. On an
    /// interval with equally spaced nodes $\tau_0, \dots, \tau_m$, the interpolant's $m$-th
    /// derivative is $m!$ times the divided difference $x[\tau_0, \dots, \tau_m]$, which for
    /// $\tau^{m+1}$ is $\sum_i \tau_i = (m + 1)\,\bar\tau$ ($\bar\tau$ the interval's
    /// midpoint): $(m+1)!\,c\,\bar\tau$. Neighbouring midpoints lie half the two widths
    /// apart, the distance the jump is divided by, so every jump, and every interval's
    /// estimate, is $(m+1)!\,|c|$ (largest over the components). Tolerance: the rounding of
    /// the node values, amplified by the $m$-th derivative weights over $h^m$ and by the
    /// division by the midpoints' distance.
    #[test]
    fn the_high_derivative_is_exact_for_a_polynomial_of_degree_ncol_plus_1() {
        let mesh = [0.0, 0.15, 0.35, 0.5, 0.8, 1.0];
        let coefficients = [1.0, -2.5, 0.5];
        let n = coefficients.len();
        for ncol in 1..=7 {
            let basis = Basis::new(ncol);
            let mut nodes = Vec::new();
            for w in mesh.windows(2) {
                for i in 0..ncol {
                    let tau = w[0] + (i as f64 / ncol as f64) * (w[1] - w[0]);
                    nodes.extend(coefficients.iter().map(|c| c * tau.powi(ncol as i32 + 1)));
                }
            }
            nodes.extend(coefficients.iter().copied());
            let factorial: f64 = (1..=ncol + 1).map(|k| k as f64).product();
            let expected = factorial * 2.5;
            let weights: f64 = basis.dn[..=ncol].iter().map(|d| d.abs()).sum();
            let h_min = 0.15f64;
            let tol = 64.0 * f64::EPSILON * 2.5 * weights / (h_min.powi(ncol as i32) * h_min);
            for (j, d) in high_derivatives(&nodes, &mesh, &basis, n)
                .iter()
                .enumerate()
            {
                assert!(
                    (d - expected).abs() <= tol,
                    "ncol {ncol}, interval {j}: {d} against {expected} (tolerance {tol:e})"
                );
            }
        }
    }
}
