//! DOP853 against closed-form solutions: convergence order, tolerance proportionality, dense
//! output accuracy.

use hycont_core::Dop853;

/// y'' = -y as a first-order system: y(t) = (sin t, cos t) from (0, 1).
fn oscillator(_t: f64, y: &[f64], dy: &mut [f64]) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

/// A non-autonomous, nonlinear problem with known solution: y' = y cos t, y = exp(sin t).
fn exp_sin(t: f64, y: &[f64], dy: &mut [f64]) {
    dy[0] = y[0] * t.cos();
}

#[test]
fn fixed_step_convergence_order_is_eight() {
    let t1 = 10.0;
    let mut errors = Vec::new();
    for steps in [10usize, 20, 40, 80] {
        let mut st = Dop853::new(1);
        let y = st
            .integrate_fixed(&mut exp_sin, 0.0, &[1.0], t1, steps)
            .unwrap();
        errors.push((y[0] - t1.sin().exp()).abs());
    }
    let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    // The last ratio is close to round-off, so judge the first two (asymptotic regime).
    for order in &orders[..2] {
        assert!(
            (7.3..=9.0).contains(order),
            "observed order {order:.2} (errors {errors:?})"
        );
    }
}

#[test]
fn fixed_step_order_on_oscillator() {
    let t1 = 20.0;
    let err = |steps| {
        let mut st = Dop853::new(2);
        let y = st
            .integrate_fixed(&mut oscillator, 0.0, &[0.0, 1.0], t1, steps)
            .unwrap();
        ((y[0] - t1.sin()).powi(2) + (y[1] - t1.cos()).powi(2)).sqrt()
    };
    let (e1, e2) = (err(20), err(40));
    let order = (e1 / e2).log2();
    assert!(
        (7.5..=8.7).contains(&order),
        "order {order:.2} ({e1:e}, {e2:e})"
    );
}

#[test]
fn adaptive_error_tracks_tolerance() {
    for tol in [1e-6, 1e-9, 1e-12] {
        let mut st = Dop853::new(2);
        let y = st
            .integrate(&mut oscillator, 0.0, &[0.0, 1.0], 30.0, tol, tol)
            .unwrap();
        let err = (y[0] - 30f64.sin()).abs().max((y[1] - 30f64.cos()).abs());
        // Global error of a few hundred steps: within two orders of magnitude of the tolerance.
        assert!(err < 100.0 * tol, "tol {tol:e}: error {err:e}");
    }
}

#[test]
fn rhs_count_is_twelve_per_accepted_step_plus_rejections() {
    let mut st = Dop853::new(2);
    st.integrate(&mut oscillator, 0.0, &[0.0, 1.0], 50.0, 1e-10, 1e-12)
        .unwrap();
    let s = st.stats();
    // 1 (start) + 1 (initial step) + 11 per attempt + 1 per accepted step.
    assert_eq!(
        s.rhs_evaluations,
        2 + 11 * (s.accepted_steps + s.rejected_steps) + s.accepted_steps
    );
}

#[test]
fn dense_output_is_seventh_order_accurate() {
    // One step of size h from t = 0.3; compare the continuous extension at interior points with
    // the exact solution. Local interpolation error is O(h^8): halving h divides it by ~256.
    let err = |h: f64| {
        let mut st = Dop853::new(1);
        let t0 = 0.3;
        st.start(&mut exp_sin, t0, &[t0.sin().exp()]).unwrap();
        st.attempt(&mut exp_sin, h).unwrap();
        st.accept(&mut exp_sin).unwrap();
        st.prepare_dense(&mut exp_sin).unwrap();
        let mut worst: f64 = 0.0;
        for k in 1..10 {
            let t = t0 + h * f64::from(k) / 10.0;
            worst = worst.max((st.dense_component(0, t) - t.sin().exp()).abs());
        }
        worst
    };
    let (e1, e2) = (err(0.4), err(0.2));
    let order = (e1 / e2).log2();
    assert!(
        order > 7.0,
        "dense-output local order {order:.2} ({e1:e} -> {e2:e})"
    );
    assert!(
        e2 < 1e-9,
        "dense error {e2:e} at h = 0.2 (order {order:.2}, {e1:e} at h = 0.4)"
    );
}

/// The derivative of the continuous extension: Hairer's interpolant matches the derivative at
/// both ends of the step ($u'(0) = f(t_n, y_n)$, $u'(1) = f(t_{n+1}, y_{n+1})$ by its
/// construction), and inside, as the derivative of a 7th-order interpolant, it is accurate to
/// $O(h^7)$ against $y' = e^{\sin t}\cos t$.
#[test]
fn dense_output_derivative_matches_the_vector_field() {
    let err = |h: f64| {
        let mut st = Dop853::new(1);
        let t0 = 0.3;
        st.start(&mut exp_sin, t0, &[t0.sin().exp()]).unwrap();
        st.attempt(&mut exp_sin, h).unwrap();
        st.accept(&mut exp_sin).unwrap();
        st.prepare_dense(&mut exp_sin).unwrap();
        let (mut f0, mut f1) = ([0.0], [0.0]);
        exp_sin(t0, &[st.dense_component(0, t0)], &mut f0);
        exp_sin(t0 + h, &[st.dense_component(0, t0 + h)], &mut f1);
        let scale = 1e-14 * f0[0].abs().max(f1[0].abs()).max(1.0);
        assert!((st.dense_derivative_component(0, t0) - f0[0]).abs() <= scale);
        assert!((st.dense_derivative_component(0, t0 + h) - f1[0]).abs() <= scale);
        let mut worst: f64 = 0.0;
        for k in 1..10 {
            let t = t0 + h * f64::from(k) / 10.0;
            let exact = t.sin().exp() * t.cos();
            worst = worst.max((st.dense_derivative_component(0, t) - exact).abs());
        }
        worst
    };
    let (e1, e2) = (err(0.4), err(0.2));
    let order = (e1 / e2).log2();
    assert!(
        order > 6.0,
        "derivative's local order {order:.2} ({e1:e} -> {e2:e})"
    );
    assert!(e2 < 1e-8, "derivative error {e2:e} at h = 0.2");
}

#[test]
fn nan_rhs_is_reported_with_time_and_state() {
    // y' = -1 from y = 1, with the right-hand side returning sqrt(y): NaN once y < 0.
    let mut rhs = |_t: f64, y: &[f64], dy: &mut [f64]| dy[0] = -1.0 + 0.0 * y[0].sqrt();
    let mut st = Dop853::new(1);
    let err = st
        .integrate(&mut rhs, 0.0, &[1.0], 3.0, 1e-8, 1e-10)
        .unwrap_err();
    let text = err.to_string();
    assert!(text.contains("NaN"), "{text}");
    assert!(
        matches!(err, hycont_core::Error::NonFiniteVectorField { t, .. } if t > 0.9 && t <= 3.0),
        "{text}"
    );
}

/// The step-size controller is Hairer's PI formula
/// $h_{new} = h \min(6, \max(0.333, 0.9\, \mathrm{err}^{-(1/8 - \beta/5)}\, \mathrm{err}_{old}^\beta))$
/// with $\mathrm{err}_{old} \ge 10^{-4}$ the last accepted error (initially $10^{-4}$), no growth
/// right after a rejection, and $h \max(0.333, 0.9\, \mathrm{err}^{-1/8})$ on a rejection: the
/// stepper against the formula, step by step, to a few units of roundoff.
#[test]
fn step_size_controller_is_hairers_pi_formula() {
    let beta = 0.03;
    let mut st = Dop853::new(1);
    st.set_controller_beta(beta);
    let accepted = |err: f64, old: f64| {
        (0.9 * err.powf(-(1.0 / 8.0 - 0.2 * beta)) * old.max(1e-4).powf(beta)).clamp(0.333, 6.0)
    };
    // (h, err, expected new h)
    let steps = [
        (1.0, 0.5, accepted(0.5, 1e-4)),
        (2.0, 0.2, 2.0 * accepted(0.2, 0.5)),
        (1.0, 3.0, (0.9 * 3.0f64.powf(-1.0 / 8.0)).max(0.333)),
        (0.5, 0.01, 0.5 * accepted(0.01, 0.2).min(1.0)),
        (1.0, 1e-9, accepted(1e-9, 0.01)),
        (1.0, 0.7, accepted(0.7, 1e-9)),
        (1.0, 1e6, 0.333),
    ];
    for (h, err, want) in steps {
        let got = st.next_step_size(h, err);
        assert!(
            (got - want).abs() <= 1e-14 * want,
            "h {h}, err {err}: {got} vs {want}"
        );
    }
}
