// The exact period-1 orbits of the impacting chain (`model.rs`) with one impact per period,
// and their Floquet multipliers, from matrix exponentials and one scalar equation.
//
// Flight. With z = (x, v) in R^{2N}, z' = M z + b sin(theta), theta = w t + beta,
// M = [[0, I], [-k L, -c L]], b = A e_{v_1}. The harmonic response is
// z_p(theta) = Im(Z e^{i theta}) = Re(Z) sin(theta) + Im(Z) cos(theta), Z = (i w I - M)^{-1} b
// (differentiate: i w Z e^{i theta} = (M Z + b) e^{i theta}). Every flight is
// z(t) = z_p(theta_0 + w t) + exp(M t) (z(0) - z_p(theta_0)).
//
// Period 1 with one impact. Start right after the impact, at phase theta_0; after
// T = 2 pi / w the phase and z_p are back, the state is z^- = z_p + E (z_0 - z_p),
// E = exp(M T), and the impact maps it to R z^- (R: v_N -> -e v_N). Closing the orbit,
// z_0 = R z^-, is linear in z_0: (I - R E) z_0 = R (I - E) z_p(theta_0), so
// z_0(theta_0) = P sin(theta_0) + Q cos(theta_0), P = G Re(Z), Q = G Im(Z),
// G = (I - R E)^{-1} R (I - E). The impact happens at the stop, x_N(z_0) = d (R keeps
// positions): a sin(theta_0) + b cos(theta_0) = d with a = P_{x_N}, b = Q_{x_N}, i.e.
// rho sin(theta_0 + phi) = d, rho = hypot(a, b), phi = atan2(b, a): two phases while
// rho > d, which meet at the fold rho = d. The orbit is physical when it reaches the stop
// moving towards it (v_N^- > 0, so v_N(z_0) < 0) and stays below it in flight.
//
// Grazing. As the impact velocity goes to 0 the impact changes nothing and the orbit is the
// harmonic response touching the stop: |Z_{x_N}| = d.
//
// Multipliers. Over one period from right after the impact the mechanical states map by
// S E, with the saltation matrix S = R + (f^+ - R f^-) h_x / (h_x f^-) at the impact
// (h = d - x_N, h_x = -e_{x_N}^T, f^- = M z^- + b sin(theta_0), f^+ = M R z^- + b sin(theta_0));
// the forcing oscillator adds its trivial multipliers 1 and exp(-2 T). The monodromy of the
// whole state is block triangular (the oscillator does not see the chain), so its other
// multipliers are the eigenvalues of S E.

use nalgebra::{Complex, DMatrix, DVector};

/// The exact impacting orbit: its start right after the impact (chain, then
/// `(sin theta_0, cos theta_0)`), the period, and the chain's multipliers `(re, im)`.
#[derive(Debug, Clone)]
pub struct ExactOrbit {
    pub start: Vec<f64>,
    pub period: f64,
    pub multipliers: Vec<(f64, f64)>,
}

/// The linear flight of the chain with `n` masses at parameters `p = (k, c, A, w, d, e)`:
/// `(M, b)`.
pub fn flight(n: usize, p: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let pattern = |i: usize, j: usize| match i.abs_diff(j) {
        0 if i + 1 < n => 2.0,
        0 => 1.0,
        1 => -1.0,
        _ => 0.0,
    };
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    for i in 0..n {
        m[(i, n + i)] = 1.0;
        for j in 0..n {
            m[(n + i, j)] = -p[0] * pattern(i, j);
            m[(n + i, n + j)] = -p[1] * pattern(i, j);
        }
    }
    let mut b = DVector::zeros(2 * n);
    b[n] = p[2];
    (m, b)
}

/// `Z = (i w I - M)^{-1} b`, the complex amplitude of the harmonic response.
pub fn response(n: usize, p: &[f64]) -> DVector<Complex<f64>> {
    let (m, b) = flight(n, p);
    let a = DMatrix::from_fn(2 * n, 2 * n, |i, j| {
        Complex::new(-m[(i, j)], if i == j { p[3] } else { 0.0 })
    });
    let rhs = b.map(|v| Complex::new(v, 0.0));
    a.lu()
        .solve(&rhs)
        .expect("i w is not an eigenvalue of a damped chain")
}

/// `(E, P, Q)` of the derivation, with `T = 2 pi / w`.
fn closing(n: usize, p: &[f64]) -> (DMatrix<f64>, DVector<f64>, DVector<f64>) {
    let (m, _) = flight(n, p);
    let period = 2.0 * std::f64::consts::PI / p[3];
    let e = (&m * period).exp();
    let mut r = DMatrix::identity(2 * n, 2 * n);
    r[(2 * n - 1, 2 * n - 1)] = -p[5];
    let id = DMatrix::<f64>::identity(2 * n, 2 * n);
    let g = (&id - &r * &e)
        .lu()
        .solve(&(&r * (&id - &e)))
        .expect("I - R E is regular off the fold");
    let z = response(n, p);
    let (re, im) = (z.map(|c| c.re), z.map(|c| c.im));
    (e, &g * re, &g * im)
}

/// `rho - d`: positive where two impacting phases exist, zero at the fold.
pub fn fold_function(n: usize, p: &[f64]) -> f64 {
    let (_, pm, qm) = closing(n, p);
    pm[n - 1].hypot(qm[n - 1]) - p[4]
}

/// `|Z_{x_N}| - d`: zero at the grazing.
pub fn grazing_function(n: usize, p: &[f64]) -> f64 {
    response(n, p)[n - 1].norm() - p[4]
}

/// The two impacting orbits (either may be unphysical: check with [`is_physical`]), or none
/// beyond the fold.
pub fn exact_orbits(n: usize, p: &[f64]) -> Vec<ExactOrbit> {
    let (e, pm, qm) = closing(n, p);
    let (a, b) = (pm[n - 1], qm[n - 1]);
    let (rho, phi) = (a.hypot(b), b.atan2(a));
    if rho < p[4] {
        return Vec::new();
    }
    let s = (p[4] / rho).asin();
    [s - phi, std::f64::consts::PI - s - phi]
        .into_iter()
        .map(|theta| orbit_at(n, p, &e, &pm * theta.sin() + &qm * theta.cos(), theta))
        .collect()
}

fn orbit_at(n: usize, p: &[f64], e: &DMatrix<f64>, z0: DVector<f64>, theta: f64) -> ExactOrbit {
    let (m, b) = flight(n, p);
    let z = response(n, p);
    let zp = z.map(|c| c.re) * theta.sin() + z.map(|c| c.im) * theta.cos();
    let minus = &zp + e * (&z0 - &zp);
    let mut r = DMatrix::identity(2 * n, 2 * n);
    r[(2 * n - 1, 2 * n - 1)] = -p[5];
    let forcing = &b * theta.sin();
    let f_minus = &m * &minus + &forcing;
    let f_plus = &m * (&r * &minus) + &forcing;
    // h_x f^- = -v_N^-; the column of S's rank-one term is (f^+ - R f^-) / (h_x f^-).
    let column = (&f_plus - &r * &f_minus) / (-f_minus[n - 1]);
    let mut salt = r.clone();
    for i in 0..2 * n {
        salt[(i, n - 1)] -= column[i];
    }
    let mut multipliers: Vec<(f64, f64)> = (salt * e)
        .complex_eigenvalues()
        .iter()
        .map(|c| (c.re, c.im))
        .collect();
    multipliers.sort_by(|x, y| x.0.hypot(x.1).total_cmp(&y.0.hypot(y.1)).reverse());
    let mut start: Vec<f64> = z0.iter().copied().collect();
    start.extend([theta.sin(), theta.cos()]);
    ExactOrbit {
        start,
        period: 2.0 * std::f64::consts::PI / p[3],
        multipliers,
    }
}

/// Whether the orbit reaches the stop moving towards it and stays below it in flight
/// (checked on 2000 instants of the period).
pub fn is_physical(n: usize, p: &[f64], orbit: &ExactOrbit) -> bool {
    if orbit.start[2 * n - 1] >= 0.0 {
        return false;
    }
    let (m, _) = flight(n, p);
    let z = response(n, p);
    let theta = orbit.start[2 * n].atan2(orbit.start[2 * n + 1]);
    let harmonic = |th: f64| z.map(|c| c.re) * th.sin() + z.map(|c| c.im) * th.cos();
    let steps = 2000;
    let dt = orbit.period / f64::from(steps);
    let step = (&m * dt).exp();
    // The free part exp(M t) (z_0 - z_p(theta_0)), stepped.
    let mut free = DVector::from_column_slice(&orbit.start[..2 * n]) - harmonic(theta);
    (1..steps).all(|k| {
        free = &step * &free;
        let t = dt * f64::from(k);
        (harmonic(theta + p[3] * t) + &free)[n - 1] < p[4]
    })
}
