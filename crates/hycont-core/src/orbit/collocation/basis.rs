//! The collocation basis: Gauss-Legendre points and the Lagrange polynomials on equidistant
//! nodes of an interval, tabulated at those points.

use std::borrow::Cow;
use std::sync::OnceLock;

/// Gauss-Legendre points on $(0, 1)$.
#[must_use]
pub fn gauss_legendre_points(m: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(m);
    for i in 1..=m {
        // Newton's method on P_m from the Chebyshev-like guess.
        let mut x = (std::f64::consts::PI * (i as f64 - 0.25) / (m as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=m {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pm = if m == 0 { 1.0 } else { p1 };
            let pm1 = if m == 1 { 1.0 } else { p0 };
            let dp = m as f64 * (x * pm - pm1) / (x * x - 1.0);
            let dx = pm / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push(0.5 * (1.0 - x));
    }
    out.sort_by(f64::total_cmp);
    out
}

/// Lagrange basis on `ncol + 1` equidistant nodes of $[0, 1]$, tabulated at the Gauss points.
#[derive(Debug, Clone)]
pub(super) struct Basis {
    pub(super) ncol: usize,
    /// `l[c][i]` = $L_i(z_c)$.
    pub(super) l: Vec<Vec<f64>>,
    /// `dl[c][i]` = $L_i'(z_c)$.
    pub(super) dl: Vec<Vec<f64>>,
    /// $L_i^{(\mathrm{ncol})}$ (constant).
    pub(super) dn: Vec<f64>,
}

pub(super) fn lagrange(nodes: &[f64], i: usize, z: f64) -> f64 {
    nodes
        .iter()
        .enumerate()
        .filter(|(m, _)| *m != i)
        .map(|(_, &zm)| (z - zm) / (nodes[i] - zm))
        .product()
}

fn lagrange_derivative(nodes: &[f64], i: usize, z: f64) -> f64 {
    let mut sum = 0.0;
    for k in 0..nodes.len() {
        if k == i {
            continue;
        }
        let mut prod = 1.0 / (nodes[i] - nodes[k]);
        for (m, &zm) in nodes.iter().enumerate() {
            if m != i && m != k {
                prod *= (z - zm) / (nodes[i] - zm);
            }
        }
        sum += prod;
    }
    sum
}

impl Basis {
    pub(super) fn new(ncol: usize) -> Self {
        let nodes: Vec<f64> = (0..=ncol).map(|i| i as f64 / ncol as f64).collect();
        let z = gauss_legendre_points(ncol);
        let l = z
            .iter()
            .map(|&zc| (0..=ncol).map(|i| lagrange(&nodes, i, zc)).collect())
            .collect();
        let dl = z
            .iter()
            .map(|&zc| {
                (0..=ncol)
                    .map(|i| lagrange_derivative(&nodes, i, zc))
                    .collect()
            })
            .collect();
        let fact: f64 = (1..=ncol).map(|k| k as f64).product();
        let dn = (0..=ncol)
            .map(|i| {
                let denom: f64 = (0..=ncol)
                    .filter(|&m| m != i)
                    .map(|m| nodes[i] - nodes[m])
                    .product();
                fact / denom
            })
            .collect();
        Self { ncol, l, dl, dn }
    }

    /// The basis for `ncol` points, made once per process for the degrees collocation takes
    /// (1 to 7; others are made afresh): a Gauss point search and the Lagrange tables cost
    /// more than a point's error estimate.
    pub(super) fn shared(ncol: usize) -> Cow<'static, Self> {
        static BASES: [OnceLock<Basis>; 8] = [const { OnceLock::new() }; 8];
        match BASES.get(ncol) {
            Some(cell) if ncol >= 1 => Cow::Borrowed(cell.get_or_init(|| Self::new(ncol))),
            _ => Cow::Owned(Self::new(ncol)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Basis;

    /// The shared bases are the ones made afresh, to the bit, on first use and after, for
    /// every degree collocation takes and for one beyond them (made afresh).
    #[test]
    fn shared_bases_are_fresh_ones() {
        let bits = |b: &Basis| {
            let rows = b.l.iter().chain(&b.dl).chain(std::iter::once(&b.dn));
            (
                b.ncol,
                rows.flatten().map(|v| v.to_bits()).collect::<Vec<_>>(),
            )
        };
        for ncol in 1..=9 {
            let fresh = bits(&Basis::new(ncol));
            assert_eq!(bits(&Basis::shared(ncol)), fresh);
            assert_eq!(bits(&Basis::shared(ncol)), fresh);
        }
    }
}
