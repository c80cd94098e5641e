//! Periodic orbits (shooting and collocation) against closed-form references, convergence order,
//! agreement of the two discretisations, Jacobians against finite differences, typed errors.

use crate::common;

use approx::assert_abs_diff_eq;
use common::{ImpactOscillator, Relaxation};
use hycont_core::orbit::{
    Collocation, CollocationSettings, LinearizationCache, PeriodicOrbit, SegmentEnd, SegmentSpec,
    Shooting, ShootingSettings, Signature, gauss_legendre_points, monodromy_by_shooting,
    monodromy_from_cache, pack, shooting_problem, shooting_problem_cached, solve_collocation,
    solve_shooting, unpack,
};
use hycont_core::problem::{
    Activity, NewtonSettings, Problem, UnknownMonitor, ZeroFunction, newton,
};
use hycont_core::{Error, EventId, Mode, SimulationSettings};

/// A deliberately rough guess of the relaxation orbit at parameter a.
fn relaxation_guess(a: f64) -> PeriodicOrbit {
    Relaxation::orbit([0.6, 1.0], 1.2 * Relaxation::period(a), a)
}

#[test]
fn shooting_finds_the_closed_form_orbit_and_multipliers() {
    for a in [2.0, 3.0, 5.0] {
        let sol = solve_shooting(
            &Relaxation,
            &relaxation_guess(a),
            ShootingSettings::default(),
            &NewtonSettings::default(),
        )
        .unwrap();
        let t = Relaxation::period(a);
        assert_abs_diff_eq!(sol.orbit.durations[0], t, epsilon = 1e-10);
        assert_abs_diff_eq!(sol.orbit.starts[0][0], 0.5, epsilon = 1e-10);
        assert_abs_diff_eq!(sol.orbit.starts[0][1], Relaxation::y0(a), epsilon = 1e-10);
        let m: Vec<f64> = sol.floquet.multipliers.iter().map(|z| z.0).collect();
        assert!(
            (m[0] - 1.0).abs() < 1e-9 && (m[1] - (-2.0 * t).exp()).abs() < 1e-9,
            "{m:?}"
        );
        assert_eq!(sol.floquet.trivial, vec![true, false]);
        assert!(sol.floquet.stable());
    }
}

#[test]
fn collocation_finds_the_closed_form_orbit_and_multipliers() {
    let a = 3.0;
    let sol = solve_collocation(
        &Relaxation,
        &relaxation_guess(a),
        CollocationSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    let t = Relaxation::period(a);
    let orbit = &sol.solution.orbit;
    assert_abs_diff_eq!(orbit.durations[0], t, epsilon = 1e-10);
    assert_abs_diff_eq!(orbit.starts[0][1], Relaxation::y0(a), epsilon = 1e-10);
    let m: Vec<f64> = sol
        .solution
        .floquet
        .multipliers
        .iter()
        .map(|z| z.0)
        .collect();
    assert_abs_diff_eq!(m[1], (-2.0 * t).exp(), epsilon = 1e-9);
}

#[test]
fn collocation_converges_at_order_two_ncol() {
    // Error in the period at the mesh points is O(h^(2 ncol)): check the observed order for
    // ncol = 2 and 3 over ntst = 4, 8, 16 (before round-off).
    let a = 3.0;
    let t = Relaxation::period(a);
    for ncol in [2usize, 3] {
        let errors: Vec<f64> = [4usize, 8, 16]
            .iter()
            .map(|&ntst| {
                let sol = solve_collocation(
                    &Relaxation,
                    &relaxation_guess(a),
                    CollocationSettings {
                        ntst,
                        ncol,
                        adapt: 0,
                    },
                    &NewtonSettings {
                        tol: 1e-13,
                        residual_tol: 1e-13,
                        ..NewtonSettings::default()
                    },
                )
                .unwrap();
                (sol.solution.orbit.durations[0] - t).abs()
            })
            .collect();
        for w in errors.windows(2) {
            let order = (w[0] / w[1]).log2();
            let expected = 2.0 * ncol as f64;
            assert_abs_diff_eq!(order, expected, epsilon = 0.6);
        }
    }
}

#[test]
fn gauss_legendre_points_are_the_roots_of_legendre_polynomials() {
    // P_3 on (0, 1): roots 1/2 and 1/2 +- sqrt(3/5)/2.
    let z = gauss_legendre_points(3);
    let r = 0.5 * (0.6f64).sqrt();
    for (a, b) in z.iter().zip([0.5 - r, 0.5, 0.5 + r]) {
        assert_abs_diff_eq!(*a, b, epsilon = 1e-15);
    }
}

#[test]
fn shooting_and_collocation_jacobians_match_finite_differences() {
    let guess = relaxation_guess(2.5);
    let mut shooting = Shooting::new(
        &Relaxation,
        Relaxation::signature(),
        ShootingSettings::default(),
    )
    .unwrap();
    let u = pack(&guess);
    check_part(&mut shooting, &u, 1e-6);
    let mut coll = Collocation::new(
        &Relaxation,
        Relaxation::signature(),
        vec![vec![0.0, 0.3, 0.7, 1.0]],
        3,
    )
    .unwrap();
    let nu = coll.unknowns();
    let mut u: Vec<f64> = (0..nu).map(|i| 0.3 + 0.01 * i as f64).collect();
    u[nu - 2] = 1.1; // duration
    u[nu - 1] = 2.5; // parameter
    check_part(&mut coll, &u, 1e-7);
}

fn check_part(part: &mut dyn ZeroFunction, u: &[f64], tol: f64) {
    assert_eq!(part.jacobian_len(), part.jacobian_pattern().len());
    let nu = part.unknowns();
    let mut problem = Problem::new(nu);
    struct Wrap<'a>(&'a mut dyn ZeroFunction);
    impl ZeroFunction for Wrap<'_> {
        fn unknowns(&self) -> usize {
            self.0.unknowns()
        }
        fn equations(&self) -> usize {
            self.0.equations()
        }
        fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
            self.0.jacobian_pattern()
        }
        fn jacobian_len(&self) -> usize {
            self.0.jacobian_len()
        }
        fn evaluate(
            &mut self,
            u: &[f64],
            r: &mut [f64],
            j: Option<&mut [f64]>,
        ) -> hycont_core::Result<()> {
            self.0.evaluate(u, r, j)
        }
    }
    problem
        .add_part(Box::new(Wrap(part)), (0..nu).collect())
        .unwrap();
    let (err, row, col) = problem.check_jacobian(u, 1e-6).unwrap();
    assert!(err < tol, "Jacobian entry ({row}, {col}) off by {err:e}");
}

#[test]
fn a_family_of_orbits_gives_a_singular_jacobian_error() {
    // The elastic impact oscillator (e = 1) has a continuum of periodic orbits (every
    // amplitude): the shooting Jacobian is singular at any of them.
    let sys = ImpactOscillator { cap: None };
    let sig = Signature::new(
        &sys,
        vec![SegmentSpec {
            mode: Mode(0),
            end: SegmentEnd::Event(EventId(0)),
        }],
    )
    .unwrap();
    let orbit = PeriodicOrbit::new(
        &sys,
        sig,
        vec![vec![0.0, 1.0]],
        vec![std::f64::consts::PI],
        vec![1.0, 1.0],
    )
    .unwrap();
    let err = solve_shooting(
        &sys,
        &orbit,
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            Error::SingularMatrix { .. } | Error::NewtonFailed { .. }
        ),
        "{err}"
    );
}

#[test]
fn fold_of_x_squared_minus_l_by_newton_and_monitors() {
    // x^2 - l = 0 with l held by an inactive monitor: x = sqrt(l); released (active) with x fixed
    // by a second monitor, l = x^2.
    struct Fold;
    impl ZeroFunction for Fold {
        fn unknowns(&self) -> usize {
            2
        }
        fn equations(&self) -> usize {
            1
        }
        fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
            vec![(0, 0), (0, 1)]
        }
        fn evaluate(
            &mut self,
            u: &[f64],
            r: &mut [f64],
            j: Option<&mut [f64]>,
        ) -> hycont_core::Result<()> {
            r[0] = u[0] * u[0] - u[1];
            if let Some(j) = j {
                j[0] = 2.0 * u[0];
                j[1] = -1.0;
            }
            Ok(())
        }
    }
    let mut problem = Problem::new(2);
    problem.add_part(Box::new(Fold), vec![0, 1]).unwrap();
    let l = problem
        .add_monitor(
            "l",
            Box::new(UnknownMonitor),
            vec![1],
            Activity::Inactive(2.0),
        )
        .unwrap();
    let sol = newton(&mut problem, &[1.0, 1.0], &NewtonSettings::default()).unwrap();
    assert_abs_diff_eq!(sol.u[0], 2f64.sqrt(), epsilon = 1e-9);
    // Free l (its value becomes an unknown) and hold x = 3 instead.
    problem.set_activity(l, Activity::Active(1.0)).unwrap();
    problem
        .add_monitor(
            "x",
            Box::new(UnknownMonitor),
            vec![0],
            Activity::Inactive(3.0),
        )
        .unwrap();
    assert_eq!(problem.unknowns(), 3);
    let u0 = problem.initial_unknowns(&[2.0, 2.0]);
    let sol = newton(&mut problem, &u0, &NewtonSettings::default()).unwrap();
    assert!((sol.u[1] - 9.0).abs() < 1e-8 && (sol.u[2] - 9.0).abs() < 1e-8);
}

#[test]
fn orbit_from_simulation_and_back() {
    // Simulate the relaxation oscillator to its orbit and read it off.
    let a = 2.0;
    let mut sim = hycont_core::Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(&Relaxation, Mode(0), 0.0, &[0.0, 0.0], &[a], 30.0)
        .unwrap();
    let orbit = PeriodicOrbit::from_simulation(&Relaxation, &traj, &[a], 1e-6).unwrap();
    assert_eq!(orbit.segment_count(), 1);
    assert_abs_diff_eq!(orbit.durations[0], Relaxation::period(a), epsilon = 1e-8);
    // Interior points at y = 1.2 (y decays through it once per period) split the segment.
    let split = orbit
        .with_interior_points(&Relaxation, 1, 1.05, &SimulationSettings::default())
        .unwrap();
    assert_eq!(split.segment_count(), 2);
    let back = split.without_interior_points(&Relaxation).unwrap();
    assert_abs_diff_eq!(back.period(), orbit.period(), epsilon = 1e-12);
    // Both discretisations solve the split problem to the same orbit.
    let sh = solve_shooting(
        &Relaxation,
        &split,
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    let co = solve_collocation(
        &Relaxation,
        &split,
        CollocationSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    for (a, b) in sh.orbit.durations.iter().zip(&co.solution.orbit.durations) {
        assert_abs_diff_eq!(a, b, epsilon = 1e-9);
    }
    let mut problem = shooting_problem(&Relaxation, &split, ShootingSettings::default()).unwrap();
    assert_eq!(problem.equations(), problem.unknowns());
    assert!(problem.monitor_id("a").is_some());
    let _ = &mut problem;
}

#[test]
fn cached_linearisations_reproduce_the_monodromy_and_miss_when_stale() {
    let a = 3.0;
    let guess = relaxation_guess(a)
        .with_interior_points(&Relaxation, 1, 0.9, &SimulationSettings::default())
        .unwrap();
    assert_eq!(guess.segment_count(), 2);
    let settings = ShootingSettings::default();
    let cache = LinearizationCache::default();
    let mut problem =
        shooting_problem_cached(&Relaxation, &guess, settings, cache.clone()).unwrap();
    let sol = newton(&mut problem, &pack(&guess), &NewtonSettings::default()).unwrap();
    let orbit = unpack(&guess, &sol.u);
    // Newton's last Jacobian was at the previous iterate: the cache is stale, so it must miss.
    assert!(
        monodromy_from_cache(&Relaxation, &orbit, &cache)
            .unwrap()
            .is_none()
    );
    // One Jacobian evaluation at the solution (as continuation does for its tangent) fills it.
    let mut residual = vec![0.0; problem.equations()];
    problem.factorize(&sol.u, &mut residual).unwrap();
    let cached = monodromy_from_cache(&Relaxation, &orbit, &cache)
        .unwrap()
        .expect("cache filled at this orbit");
    let fresh = monodromy_by_shooting(&Relaxation, &orbit, settings).unwrap();
    for (c, f) in cached.multipliers.iter().zip(&fresh.multipliers) {
        assert!(
            (c.0 - f.0).abs() < 1e-12 && (c.1 - f.1).abs() < 1e-12,
            "{c:?} vs {f:?}"
        );
    }
    // A different parameter value is a miss, not a wrong answer.
    let mut other = orbit.clone();
    other.params[0] += 1e-9;
    assert!(
        monodromy_from_cache(&Relaxation, &other, &cache)
            .unwrap()
            .is_none()
    );
}

#[test]
fn invalid_signatures_are_rejected() {
    let e = Signature::new(&Relaxation, vec![]).unwrap_err();
    assert!(matches!(e, Error::InvalidSignature { .. }));
    let e = Signature::new(
        &Relaxation,
        vec![SegmentSpec {
            mode: Mode(0),
            end: SegmentEnd::Event(EventId(3)),
        }],
    )
    .unwrap_err();
    assert!(e.to_string().contains("not monitored"), "{e}");
    let bad_duration = PeriodicOrbit::new(
        &Relaxation,
        Relaxation::signature(),
        vec![vec![0.5, 1.0]],
        vec![-1.0],
        vec![2.0],
    );
    assert!(bad_duration.is_err());
}

/// Dense Gaussian elimination with partial pivoting (small test systems).
fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap();
        a.swap(k, p);
        b.swap(k, p);
        let (top, rest) = a.split_at_mut(k + 1);
        let pivot = &top[k];
        for (i, row) in rest.iter_mut().enumerate() {
            let m = row[k] / pivot[k];
            for (x, p) in row[k..].iter_mut().zip(&pivot[k..]) {
                *x -= m * p;
            }
            b[k + 1 + i] -= m * b[k];
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    x
}

/// Parameters held by inactive monitors are not differentiated (shooting skips their
/// sensitivities); the Jacobian's other columns are unchanged, and Newton steps are the same as
/// with the full Jacobian. "Unchanged" to the integration's accuracy (rtol 1e-12 here; 1e-9
/// allows for the amplification into the sensitivities): the left-out columns no longer take
/// part in the step-size control, so the steps differ slightly.
#[test]
fn held_parameters_are_not_differentiated_and_newton_steps_do_not_change() {
    let guess = relaxation_guess(2.5);
    let mut problem = shooting_problem(&Relaxation, &guess, ShootingSettings::default()).unwrap();
    let u = pack(&guess);
    let (m, nu) = (problem.equations(), problem.unknowns());
    assert_eq!(m, nu);
    let mut residual = vec![0.0; m];
    let mut values = Vec::new();
    problem
        .evaluate(&u, &mut residual, Some(&mut values))
        .unwrap();
    let mut held = vec![vec![0.0; nu]; m];
    for (&(r, c), v) in problem.jacobian_entries().iter().zip(&values) {
        held[r][c] += v;
    }
    let full = problem.dense_jacobian(&u).unwrap();
    let param = nu - 1; // pack: starts, durations, parameters
    for r in 0..m {
        for c in (0..nu).filter(|&c| c != param) {
            let (h, f) = (held[r][c], full[r][c]);
            assert_abs_diff_eq!(h, f, epsilon = 1e-9 * (1.0 + f.abs()));
        }
    }
    // The parameter's sensitivities were left out: its column differs from the full one.
    assert!((0..m - 1).any(|r| full[r][param] != 0.0 && held[r][param] != full[r][param]));
    // A Newton step (the parameter's monitor row has residual zero) is the same either way.
    let mut b: Vec<f64> = residual.iter().map(|x| -x).collect();
    b[m - 1] = 0.0;
    let (xh, xf) = (dense_solve(held, b.clone()), dense_solve(full, b));
    for (h, f) in xh.iter().zip(&xf) {
        assert_abs_diff_eq!(h, f, epsilon = 1e-9 * (1.0 + f.abs()));
    }
    assert_eq!(xh[param], 0.0);
}

/// A Jacobian asked for as a Newton direction may be approximate (shooting integrates it at a
/// looser tolerance), the residual may not: it is the exact one (continuation's chord
/// corrector uses such Jacobians at its predictor; its convergence test uses exact residuals).
#[test]
fn newton_direction_jacobians_are_approximate_and_residuals_exact() {
    use hycont_core::problem::JacobianUse;
    let guess = relaxation_guess(2.5);
    let mut problem = shooting_problem(&Relaxation, &guess, ShootingSettings::default()).unwrap();
    let u = pack(&guess);
    let m = problem.equations();
    let (mut r_exact, mut r_dir) = (vec![0.0; m], vec![0.0; m]);
    let (mut j_exact, mut j_dir) = (Vec::new(), Vec::new());
    problem
        .evaluate_for(&u, &mut r_exact, &mut j_exact, JacobianUse::Exact)
        .unwrap();
    problem
        .evaluate_for(&u, &mut r_dir, &mut j_dir, JacobianUse::NewtonDirection)
        .unwrap();
    let mut r_plain = vec![0.0; m];
    problem.evaluate(&u, &mut r_plain, None).unwrap();
    assert_eq!(r_dir, r_plain, "the residual is the exact one");
    // Integrated at rtol 1e-6 instead of 1e-12: close, not equal.
    let worst = j_exact
        .iter()
        .zip(&j_dir)
        .map(|(a, b)| (a - b).abs() / (1.0 + a.abs()))
        .fold(0.0, f64::max);
    assert!(worst > 0.0 && worst < 1e-4, "difference {worst:e}");
}

/// Results as nalgebra types: the monodromy of the relaxation orbit is $S\Phi$ with the flow's
/// closed-form Jacobian $\Phi = \mathrm{diag}(e^{-T}, e^{-2T})$ and the saltation matrix at the
/// event, which maps the vector field before the jump onto the one after it
/// ($S f^-(y) = f^+(g(y))$); the Floquet vectors are the monodromy's eigenvectors.
#[test]
fn monodromy_saltation_and_floquet_vectors_as_matrices() {
    use hycont_core::nalgebra::{Complex, DMatrix, DVector};
    let a = 3.0;
    let sol = solve_shooting(
        &Relaxation,
        &relaxation_guess(a),
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    let t = Relaxation::period(a);
    let start = sol.orbit.start(0).unwrap();
    assert_abs_diff_eq!(
        start,
        DVector::from_vec(vec![0.5, Relaxation::y0(a)]),
        epsilon = 1e-10
    );
    assert!(sol.orbit.start(1).is_none());
    let m = sol.floquet.monodromy_matrix();
    let s = &sol
        .orbit
        .saltation_matrices(&Relaxation, &SimulationSettings::default())
        .unwrap()[0];
    let phi = DMatrix::from_diagonal(&DVector::from_vec(vec![(-t).exp(), (-2.0 * t).exp()]));
    assert_abs_diff_eq!(s * phi, m, epsilon = 1e-9);
    // S f- = f+ at the event: y- = (1.5, y0 e^{-2T}), y+ = g(y-) = (0.5, y0).
    let y_minus = DVector::from_vec(vec![1.5, Relaxation::y0(a) * (-2.0 * t).exp()]);
    let f_minus = DVector::from_vec(vec![a - 1.5, -2.0 * y_minus[1]]);
    let f_plus = DVector::from_vec(vec![a - 0.5, -2.0 * Relaxation::y0(a)]);
    assert_abs_diff_eq!(s * f_minus, f_plus, epsilon = 1e-9);
    // M v = lambda v for each Floquet vector, in the order of the multipliers.
    let v = sol.floquet.vectors().unwrap();
    let mc = m.map(|x| Complex::new(x, 0.0));
    for (i, &(re, im)) in sol.floquet.multipliers.iter().enumerate() {
        let col = v.column(i);
        let residual = &mc * col - col * Complex::new(re, im);
        assert!(residual.norm() < 1e-10, "{i}: {residual}");
        assert_abs_diff_eq!(col.norm(), 1.0, epsilon = 1e-12);
    }
}
