//! A forced oscillator whose stiffness changes at a switching surface (a mode switch without a
//! jump) through the public API, against closed forms and matrix exponentials.
//!
//! # The references
//! On the forcing oscillator's limit cycle $r = \sin\theta$, $\theta = \omega t + \beta$, each
//! mode of `examples/piecewise_linear/model.rs` is linear in $(x, v, r, s, 1)$:
//! $$\dot y = A_m y, \qquad A_m = \begin{pmatrix} 0 & 1 & 0 & 0 & 0 \\
//!   -1-k_m & -2\zeta & f & 0 & k_m d \\ 0 & 0 & 0 & \omega & 0 \\ 0 & 0 & -\omega & 0 & 0 \\
//!   0&0&0&0&0 \end{pmatrix},$$
//! $k_\mathrm{soft} = 0$, $k_\mathrm{stiff} = k$, so each segment's flow is $e^{A_m t}$.
//! - An orbit inside the soft region is the linear steady state
//!   $x = (f/D)\sin(\theta - \phi)$, $D = \sqrt{(1-\omega^2)^2 + (2\zeta\omega)^2}$,
//!   $\tan\phi = 2\zeta\omega/(1-\omega^2)$; its non-trivial multipliers are
//!   $e^{(-\zeta \pm i\sqrt{1-\zeta^2})T}$, $T = 2\pi/\omega$.
//! - It grazes the switching surface where its maximum $f/D$ reaches $d$:
//!   $f_\mathrm{GR}(\omega) = d\,D(\omega)$; beyond it the orbit crosses into the stiff region,
//!   and the two-mode orbits shrink their stiff segment to zero duration there.
//! - A two-mode orbit is fixed by the state $(d, v_0, \sin\beta, \cos\beta)$ at the engaging
//!   crossing and the stiff duration $t_1$: $x(t_1) = d$ under $e^{A_\mathrm{stiff} t}$, then
//!   $(x, v)(T) = (d, v_0)$ under $e^{A_\mathrm{soft}(T - t_1)}$. Three equations in
//!   $(v_0, \beta, t_1)$, solved by Newton on the exact flows. The force is continuous at
//!   $x = d$, so the saltation matrices are the identity and the non-trivial multipliers are
//!   the eigenvalues of $e^{B_\mathrm{soft}(T - t_1)} e^{B_\mathrm{stiff} t_1}$, with $B_m$
//!   the $(x, v)$ block of $A_m$.

use crate::model_piecewise_linear as model;

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{
    CollocationSettings, Extremum, GrazingMargin, Measure, OrbitMethod, PeriodicOrbit, SegmentEnd,
    SegmentSpec, ShootingSettings, Signature, solve_shooting,
};
use hycont::problem::NewtonSettings;
use hycont::{FiniteDifferences, SimulationSettings, Simulator};
use model::{F, OMEGA, Oscillator, SOFT, STIFF, UP};
use nalgebra::{DMatrix, Matrix2};
use std::f64::consts::PI;

const ZETA: f64 = 0.05;
const K: f64 = 1.0;
const D_SWITCH: f64 = 1.0;

fn params(f: f64, omega: f64) -> Vec<f64> {
    vec![f, omega, ZETA, K, D_SWITCH]
}

fn gain(omega: f64) -> f64 {
    ((1.0 - omega * omega).powi(2) + (2.0 * ZETA * omega).powi(2)).sqrt()
}

fn f_graze(omega: f64) -> f64 {
    D_SWITCH * gain(omega)
}

/// The linear steady state, from its maximum, as one soft segment ending a period later at
/// v = 0.
fn soft_orbit(f: f64, omega: f64) -> PeriodicOrbit {
    let phi = (2.0 * ZETA * omega).atan2(1.0 - omega * omega);
    let theta = phi + 0.5 * PI;
    let sig = Signature::new(
        &Oscillator,
        vec![SegmentSpec {
            mode: SOFT,
            end: SegmentEnd::Interior {
                component: 1,
                value: 0.0,
            },
        }],
    )
    .unwrap();
    let x0 = vec![f / gain(omega), 0.0, theta.sin(), theta.cos()];
    PeriodicOrbit::new(
        &Oscillator,
        sig,
        vec![x0],
        vec![2.0 * PI / omega],
        params(f, omega),
    )
    .unwrap()
}

/// A two-mode orbit read off a simulation, starting at the engaging crossing.
pub fn two_mode_orbit(f: f64, omega: f64) -> PeriodicOrbit {
    let p = params(f, omega);
    let x0 = soft_orbit(0.9 * f_graze(omega), omega).starts[0].clone();
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(&Oscillator, SOFT, 0.0, &x0, &p, 400.0 * PI / omega)
        .unwrap();
    PeriodicOrbit::from_simulation(&Oscillator, &traj, &p, 1e-9)
        .unwrap()
        .starting_after(&Oscillator, UP)
        .unwrap()
}

/// The flow matrix of mode `k_m` (0 soft, `K` stiff) on the forcing cycle.
fn flow(k_m: f64, f: f64, omega: f64, t: f64) -> DMatrix<f64> {
    let mut a = DMatrix::<f64>::zeros(5, 5);
    a[(0, 1)] = 1.0;
    a[(1, 0)] = -1.0 - k_m;
    a[(1, 1)] = -2.0 * ZETA;
    a[(1, 2)] = f;
    a[(1, 4)] = k_m * D_SWITCH;
    a[(2, 3)] = omega;
    a[(3, 2)] = -omega;
    (a * t).exp()
}

/// The reference two-mode orbit `(v0, beta, t1)` by Newton on the exact flows from `guess`.
fn reference(f: f64, omega: f64, guess: [f64; 3]) -> [f64; 3] {
    let period = 2.0 * PI / omega;
    let residual = |z: [f64; 3]| {
        let y0 = nalgebra::DVector::from_vec(vec![D_SWITCH, z[0], z[1].sin(), z[1].cos(), 1.0]);
        let y1 = flow(K, f, omega, z[2]) * &y0;
        let y2 = flow(0.0, f, omega, period - z[2]) * &y1;
        [y1[0] - D_SWITCH, y2[0] - D_SWITCH, y2[1] - z[0]]
    };
    let mut z = guess;
    for _ in 0..20 {
        let r = residual(z);
        let mut jac = nalgebra::Matrix3::<f64>::zeros();
        for j in 0..3 {
            let mut w = z;
            let h = 1e-7 * z[j].abs().max(1.0);
            w[j] += h;
            let rw = residual(w);
            for i in 0..3 {
                jac[(i, j)] = (rw[i] - r[i]) / h;
            }
        }
        let dz = jac.lu().solve(&nalgebra::Vector3::from(r)).unwrap();
        for j in 0..3 {
            z[j] -= dz[j];
        }
        if dz.amax() < 1e-14 {
            break;
        }
    }
    z
}

#[test]
fn a_soft_orbit_is_the_linear_steady_state() {
    let (f, omega) = (0.3, 0.8);
    let fd = FiniteDifferences::new(Oscillator);
    let sol = solve_shooting(
        &fd,
        &soft_orbit(f, omega),
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    let max = Extremum::max(0).evaluate(&fd, &sol.orbit).unwrap();
    assert_abs_diff_eq!(max, f / gain(omega), epsilon = 1e-10);
    let margin = GrazingMargin::new([UP]).evaluate(&fd, &sol.orbit).unwrap();
    assert_abs_diff_eq!(margin, D_SWITCH - f / gain(omega), epsilon = 1e-10);
    let period = 2.0 * PI / omega;
    let nontrivial: Vec<(f64, f64)> = sol.floquet.nontrivial().collect();
    assert_eq!(nontrivial.len(), 2);
    let omega_d = (1.0 - ZETA * ZETA).sqrt() * period;
    for (re, im) in nontrivial {
        let modulus = re.hypot(im);
        assert_abs_diff_eq!(modulus, (-ZETA * period).exp(), epsilon = 1e-9);
        let angle = im.atan2(re).abs();
        let expected = (omega_d.sin().atan2(omega_d.cos())).abs();
        assert_abs_diff_eq!(angle, expected, epsilon = 1e-8);
    }
}

#[test]
fn a_two_mode_orbit_matches_matrix_exponentials() {
    let (f, omega) = (0.5, 0.8);
    let guess = two_mode_orbit(f, omega);
    for (method, tol) in [
        (OrbitMethod::Shooting(ShootingSettings::default()), 1e-9),
        (
            OrbitMethod::Collocation(CollocationSettings::default()),
            1e-8,
        ),
    ] {
        let fd = FiniteDifferences::new(Oscillator);
        let mut run = OrbitRun::new(&fd, F).unwrap();
        run.method(method).bounds(0.49, 0.51).max_points(2);
        let b = run.run("one point", &guess, RunDirection::Up).unwrap();
        let o = b.orbit_of(&b.branch.points[0]).unwrap();
        let modes: Vec<_> = o.signature.segments().iter().map(|s| s.mode).collect();
        assert_eq!(modes, [STIFF, SOFT]);
        let z = [
            o.starts[0][1],
            o.starts[0][2].atan2(o.starts[0][3]),
            o.durations[0],
        ];
        let r = reference(f, omega, z);
        for (a, b) in z.iter().zip(&r) {
            assert_abs_diff_eq!(a, b, epsilon = tol);
        }
        assert_abs_diff_eq!(o.starts[0][0], D_SWITCH, epsilon = tol);
        // The multipliers: eigenvalues of the (x, v) blocks' product.
        let block = |k_m: f64, t: f64| {
            let m = flow(k_m, f, omega, t);
            Matrix2::new(m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)])
        };
        let m = block(0.0, 2.0 * PI / omega - r[2]) * block(K, r[2]);
        let (tr, det) = (m.trace(), m.determinant());
        let p = &b.branch.points[0];
        let nontrivial: Vec<_> = p
            .multipliers
            .iter()
            .zip(&p.trivial)
            .filter(|x| !*x.1)
            .collect();
        assert_eq!(nontrivial.len(), 2);
        let (l1, l2) = (nontrivial[0].0, nontrivial[1].0);
        assert_abs_diff_eq!(l1.0 + l2.0, tr, epsilon = 10.0 * tol);
        let product = l1.0 * l2.0 - l1.1 * l2.1;
        assert_abs_diff_eq!(product, det, epsilon = 10.0 * tol);
    }
}

#[test]
fn the_orbits_graze_the_switching_surface_at_the_closed_form() {
    let omega = 0.8;
    let fd = FiniteDifferences::new(Oscillator);
    let mut run = OrbitRun::new(&fd, F).unwrap();
    run.bounds(0.1, 1.0);
    let margin = run.add_measure("margin", GrazingMargin::new([UP])).unwrap();
    run.add_terminal_event(margin, 0.0, SpecialKind::Grazing)
        .unwrap();
    // From the two-mode side: the stiff segment collapses.
    let two = run
        .run("two-mode", &two_mode_orbit(0.5, omega), RunDirection::Down)
        .unwrap();
    let gr = two
        .special(SpecialKind::Grazing)
        .next()
        .expect("a collapse");
    assert_abs_diff_eq!(gr.point[F], f_graze(omega), epsilon = 1e-8);
    // From the soft side: the maximum reaches the surface (the margin's event).
    let soft = run
        .run("soft", &soft_orbit(0.3, omega), RunDirection::Up)
        .unwrap();
    let gr = soft
        .special(SpecialKind::Grazing)
        .next()
        .expect("a grazing");
    assert_eq!(gr.on, Some(margin.into()));
    assert_abs_diff_eq!(gr.point[F], f_graze(omega), epsilon = 1e-8);
    // The grazing curve in (f, omega) from the margin's event, against f = d D(omega), by
    // both discretisations. From the collapse the condition is singular (the stiff segment's
    // duration grows like a square root at a tangency): a typed error says so.
    let spec = CurveSpec::new(OMEGA)
        .bounds(0.6, 1.4)
        .user_points(OMEGA, [0.7, 0.9]);
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        run.method(method);
        let on = run
            .run("soft", &soft_orbit(0.3, omega), RunDirection::Up)
            .unwrap();
        let label = on.special(SpecialKind::Grazing).next().unwrap().point.label;
        let c = run.curve_at("GR", &on, label, &spec).unwrap();
        let uz: Vec<_> = c.special(SpecialKind::UserPoint).collect();
        assert_eq!(uz.len(), 2, "{method:?}: {:?}", c.branch.end);
        for s in uz.iter().map(|s| &s.point).chain(&c.branch.points) {
            assert_abs_diff_eq!(s[F], f_graze(s[OMEGA]), epsilon = 1e-8);
        }
    }
    let collapse = two
        .special(SpecialKind::Grazing)
        .next()
        .unwrap()
        .point
        .label;
    assert!(matches!(
        run.curve_at("GR", &two, collapse, &spec),
        Err(hycont::hycont_continuation::Error::WrongSpecialPoint { .. })
    ));
}

/// The oscillator written once (`OscillatorModel`) and differentiated automatically: its
/// Jacobians are the closed forms (in each mode the `(x, v)` block of `A_m`, the forcing
/// oscillator's `d(r + omega s - r rho)/d(r, s) = (1 - 3 r^2 - s^2, omega - 2 r s)` and
/// `(-omega - 2 r s, 1 - r^2 - 3 s^2)`, the parameter columns), and a run through it grazes
/// the switching surface at the closed form f = d D(omega).
#[test]
fn automatic_differentiation_gives_the_closed_form_jacobians() {
    use hycont::{AutoDiff, HybridJacobians};
    let ad = AutoDiff::new(model::OscillatorModel);
    let (x, v, r, s) = (0.7, -0.4, 0.6, 0.8);
    let p = params(0.5, 0.8);
    for (m, k_m) in [(SOFT, 0.0), (STIFF, K)] {
        let (mut dx, mut dp) = ([0.0; 16], [0.0; 20]);
        ad.vector_field_jacobian(m, &[x, v, r, s], &p, &mut dx, Some(&mut dp));
        let w = p[1];
        #[rustfmt::skip]
        let expected = [
            0.0, -1.0 - k_m, 0.0, 0.0,
            1.0, -2.0 * ZETA, 0.0, 0.0,
            0.0, p[0], 1.0 - 3.0 * r * r - s * s, -w - 2.0 * r * s,
            0.0, 0.0, w - 2.0 * r * s, 1.0 - r * r - 3.0 * s * s,
        ];
        for (a, b) in dx.iter().zip(expected) {
            assert_abs_diff_eq!(*a, b, epsilon = 1e-15);
        }
        // Columns f, omega, zeta, k, d.
        let spring = if m == STIFF { x - D_SWITCH } else { 0.0 };
        #[rustfmt::skip]
        let expected_p = [
            0.0, r, 0.0, 0.0,
            0.0, 0.0, s, -r,
            0.0, -2.0 * v, 0.0, 0.0,
            0.0, -spring, 0.0, 0.0,
            0.0, k_m, 0.0, 0.0,
        ];
        for (a, b) in dp.iter().zip(expected_p) {
            assert_abs_diff_eq!(*a, b, epsilon = 1e-15);
        }
    }
    let omega = 0.8;
    let mut run = OrbitRun::new(&ad, F).unwrap();
    run.bounds(0.1, 1.0);
    let margin = run.add_measure("margin", GrazingMargin::new([UP])).unwrap();
    run.add_terminal_event(margin, 0.0, SpecialKind::Grazing)
        .unwrap();
    let soft = run
        .run("soft", &soft_orbit(0.3, omega), RunDirection::Up)
        .unwrap();
    let gr = soft
        .special(SpecialKind::Grazing)
        .next()
        .expect("a grazing");
    assert_abs_diff_eq!(gr.point[F], f_graze(omega), epsilon = 1e-8);
}
