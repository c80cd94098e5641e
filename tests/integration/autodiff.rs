//! Exact derivatives by automatic differentiation ([`AutoDiff`] of a [`HybridModel`]) against
//! hand-coded ones: the two balls of `examples/two_balls` written once for any scalar, their
//! Jacobians equal to the hand-coded model's to rounding (vector field with and without the
//! parameter columns, event gradients, resets), a continuation through them locating the same
//! codimension-two point; and a model with more variables than one dual evaluation carries
//! (one evaluation per variable), against its closed-form Jacobian.

use crate::model_two_balls as model;

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::{
    AutoDiff, Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridModel,
    HybridSystem, Mode, ParamId, Scalar, Tangents,
};
use model::{
    A, E1, E2, FLIGHT, G1, IMPACT1, IMPACT2, TwoBalls, TwoBallsModel, WRAP, a_pd, a_sn, bisect,
};
use proptest::prelude::*;

/// The largest difference relative to 1 + |hand-coded|.
fn worst(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / (1.0 + y.abs()))
        .fold(0.0, f64::max)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Every Jacobian of the AD twin equals the hand-coded one to rounding.
    #[test]
    fn jacobians_equal_the_hand_coded_ones(
        x in proptest::collection::vec(-3.0f64..3.0, 5),
        p in proptest::collection::vec(0.2f64..2.0, 7),
    ) {
        let ad = AutoDiff::new(TwoBallsModel);
        let (n, np) = (5, 7);
        let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n * n]);
        let (mut ap, mut bp) = (vec![0.0; n * np], vec![0.0; n * np]);
        ad.vector_field_jacobian(FLIGHT, &x, &p, &mut a, Some(&mut ap));
        TwoBalls.vector_field_jacobian(FLIGHT, &x, &p, &mut b, Some(&mut bp));
        prop_assert!(worst(&a, &b) < 1e-15 && worst(&ap, &bp) < 1e-15, "{a:?} {b:?}");
        // Without the parameter columns: the state block alone, the same.
        let mut a2 = vec![0.0; n * n];
        ad.vector_field_jacobian(FLIGHT, &x, &p, &mut a2, None);
        prop_assert_eq!(&a2, &a);
        // Together with the vector field.
        let (mut f, mut g) = (vec![0.0; n], vec![0.0; n]);
        ad.vector_field_with_jacobian(FLIGHT, &x, &p, &mut f, &mut a2, None);
        TwoBalls.vector_field(FLIGHT, &x, &p, &mut g);
        prop_assert!(worst(&f, &g) < 1e-15);
        for e in [IMPACT1, IMPACT2, WRAP] {
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            let (mut ap, mut bp) = (vec![0.0; np], vec![0.0; np]);
            ad.event_gradient(e, &x, &p, &mut a, Some(&mut ap));
            TwoBalls.event_gradient(e, &x, &p, &mut b, Some(&mut bp));
            prop_assert!(worst(&a, &b) < 1e-15 && worst(&ap, &bp) < 1e-15);
            let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n * n]);
            let (mut ap, mut bp) = (vec![0.0; n * np], vec![0.0; n * np]);
            ad.reset_jacobian(e, &x, &p, &mut a, Some(&mut ap));
            TwoBalls.reset_jacobian(e, &x, &p, &mut b, Some(&mut bp));
            prop_assert!(worst(&a, &b) < 1e-15 && worst(&ap, &bp) < 1e-15);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The vector field's derivatives along many directions at once (what the variational
    /// equations integrate): the AD twin's, from one evaluation on duals seeded with the
    /// directions, equal the hand-coded model's Jacobians times the directions (the default)
    /// to rounding. Each of the 5 terms of a product is at most |f_x| |X| <= 8 * 3 in size, so
    /// the two orders of summation differ by at most 5 * 24 * 2^-52 = 3e-14: bound 1e-13.
    #[test]
    fn tangents_equal_the_hand_coded_products(
        x in proptest::collection::vec(-3.0f64..3.0, 5),
        p in proptest::collection::vec(0.2f64..2.0, 7),
        dirs in proptest::collection::vec(-3.0f64..3.0, 5 * 8),
        state_directions in 1usize..=5,
        params in proptest::sample::subsequence((0..7).map(ParamId).collect::<Vec<_>>(), 0..=3),
    ) {
        let ad = AutoDiff::new(TwoBallsModel);
        let (n, np) = (5, 7);
        let k = state_directions + params.len();
        let dirs = &dirs[..n * k];
        let mut outputs = Vec::new();
        for system in [&ad as &dyn HybridJacobians, &TwoBalls] {
            let (mut f, mut out, mut work) = (vec![0.0; n], vec![0.0; n * k], vec![0.0; n * (n + np)]);
            let tangents = Tangents { x: dirs, params: &params, out: &mut out, work: &mut work };
            system.vector_field_with_tangents(FLIGHT, &x, &p, &mut f, tangents);
            outputs.push((f, out));
        }
        let (by_ad, by_hand) = (&outputs[0], &outputs[1]);
        prop_assert!(worst(&by_ad.0, &by_hand.0) < 1e-15);
        prop_assert!(worst(&by_ad.1, &by_hand.1) < 1e-13, "{:?} {:?}", by_ad.1, by_hand.1);
    }
}

/// The fold-flip point on ball 1's fold curve at e2 (ball 2's period doubling), by `run`.
fn fold_flip<S: HybridJacobians>(run: &mut OrbitRun<'_, S>, a_ref: f64) -> f64 {
    run.bounds(0.3, 3.0);
    let start = model::orbit(1.1 * a_ref, 0.65, 1.0);
    let branch = run.run("period-1", &start, RunDirection::Both).unwrap();
    let sn = branch
        .special(SpecialKind::Fold)
        .find(|s| (s.point[A] - a_ref).abs() < 1e-6)
        .unwrap()
        .point
        .label;
    let spec = CurveSpec::new(E2).bounds(0.56, 0.95);
    let curve = run.curve_at("SN", &branch, sn, &spec).unwrap();
    curve.first(SpecialKind::FoldFlip).unwrap().point[E2]
}

/// The fold-flip point on ball 1's fold curve through the AD twin: at its closed form, and
/// where the hand-coded model puts it.
#[test]
fn a_curve_through_the_ad_twin_finds_the_same_point() {
    let a_ref = a_sn(E1, G1);
    let ad = AutoDiff::new(TwoBallsModel);
    let by_ad = fold_flip(&mut OrbitRun::new(&ad, A).unwrap(), a_ref);
    let by_hand = fold_flip(&mut OrbitRun::new(&TwoBalls, A).unwrap(), a_ref);
    let reference = bisect(|e| a_pd(e, 1.0) - a_ref, 0.6, 0.99);
    assert_abs_diff_eq!(by_ad, reference, epsilon = 1e-8);
    assert_abs_diff_eq!(by_ad, by_hand, epsilon = 1e-10);
}

/// A chain of 20 damped pendulums, x_i'' = -sin(x_i) - c x_i' + k (x_{i-1} - 2 x_i + x_{i+1})
/// (40 states, more than one dual evaluation carries): its Jacobian in closed form.
struct Chain;

const LINKS: usize = 20;

impl HybridModel for Chain {
    fn state_dim(&self) -> usize {
        2 * LINKS
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["c", "k"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "chain"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "none",
            direction: Direction::Either,
            action: EventAction::Terminal,
        }
    }
    fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
        for i in 0..LINKS {
            let left = if i > 0 { x[i - 1] } else { T::from(0.0) };
            let right = if i + 1 < LINKS {
                x[i + 1]
            } else {
                T::from(0.0)
            };
            f[i] = x[LINKS + i];
            f[LINKS + i] = -x[i].sin() - p[0] * x[LINKS + i] + p[1] * (left - x[i] * 2.0 + right);
        }
    }
    fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T {
        x[0]
    }
}

#[test]
fn many_variables_are_differentiated_one_at_a_time() {
    let n = 2 * LINKS;
    let x: Vec<f64> = (0..n).map(|i| 0.1 * i as f64 - 1.3).collect();
    let p = [0.2, 0.7];
    let (mut dx, mut dp) = (vec![0.0; n * n], vec![0.0; n * 2]);
    AutoDiff::new(Chain).vector_field_jacobian(Mode(0), &x, &p, &mut dx, Some(&mut dp));
    let at = |r: usize, c: usize| dx[r + c * n];
    for i in 0..LINKS {
        assert_eq!(at(i, LINKS + i), 1.0);
        assert_eq!(at(LINKS + i, i), -x[i].cos() - 2.0 * p[1]);
        assert_eq!(at(LINKS + i, LINKS + i), -p[0]);
        if i > 0 {
            assert_eq!(at(LINKS + i, i - 1), p[1]);
        }
        assert_eq!(dp[LINKS + i], -x[LINKS + i]);
    }
    let nonzero = dx.iter().filter(|v| **v != 0.0).count();
    assert_eq!(nonzero, LINKS + LINKS * 2 + 2 * (LINKS - 1));
    // Along two directions (the second also moving k): more state than one dual evaluation
    // carries, so the Jacobians are formed and multiplied; the products are the closed form's
    // (each a sum of at most four terms, in the same order: exact equality).
    let dirs: Vec<f64> = (0..2 * n).map(|i| (0.37 * i as f64).sin()).collect();
    let (mut f, mut out, mut work) = (vec![0.0; n], vec![0.0; 2 * n], vec![0.0; n * (n + 2)]);
    let tangents = Tangents {
        x: &dirs,
        params: &[ParamId(1)],
        out: &mut out,
        work: &mut work,
    };
    AutoDiff::new(Chain).vector_field_with_tangents(Mode(0), &x, &p, &mut f, tangents);
    for j in 0..2 {
        for r in 0..n {
            let mut want = if j == 1 { dp[r + n] } else { 0.0 };
            for c in 0..n {
                want += at(r, c) * dirs[c + j * n];
            }
            assert_eq!(out[r + j * n], want, "row {r}, direction {j}");
        }
    }
}

use crate::model_vibrating_table as table;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Second derivatives by hyper-dual numbers against the closed forms of the vibrating
    /// table, $f = (w,\ -g + a\omega^2\sin\theta,\ \omega)$ with parameters $(a, \omega, e, g)$:
    /// $\partial_\theta^2 f_1 = -a\omega^2\sin\theta$, $\partial_a\partial_\theta f_1 =
    /// \omega^2\cos\theta$, $\partial_\omega^2 f_1 = 2a\sin\theta$, $\partial_\omega
    /// \partial_\theta f_1 = 2a\omega\cos\theta$, every other component zero; the impact's reset
    /// $w \mapsto -e w$ has $\partial_e \partial_w = -1$; and $B(a, b) = B(b, a)$.
    #[test]
    fn second_derivatives_equal_the_closed_forms(
        z in 0.0f64..2.0, w in -3.0f64..3.0, th in -3.0f64..3.0,
        a in 0.5f64..2.0, om in 0.5f64..2.0,
    ) {
        use hycont::Variation;
        let m = AutoDiff::new(table::TableModel);
        let (x, p) = ([z, w, th], [a, om, 0.5, 1.0]);
        let e = |k: usize, n: usize| { let mut v = vec![0.0; n]; v[k] = 1.0; v };
        let (ex, ep) = (|k| e(k, 3), |k| e(k, 4));
        let none: [f64; 0] = [];
        let at = |xa: Vec<f64>, pa: Vec<f64>, xb: Vec<f64>, pb: Vec<f64>| {
            let mut out = [0.0; 3];
            m.vector_field_second_derivative(table::FLIGHT, &x, &p,
                Variation { x: &xa, p: &pa }, Variation { x: &xb, p: &pb }, &mut out).unwrap();
            out
        };
        let close = |got: [f64; 3], want: f64| {
            assert_abs_diff_eq!(got[0], 0.0);
            assert_abs_diff_eq!(got[2], 0.0);
            assert_abs_diff_eq!(got[1], want, epsilon = 1e-13 * (1.0 + want.abs()));
        };
        close(at(ex(2), vec![0.0; 4], ex(2), vec![0.0; 4]), -a * om * om * th.sin());
        close(at(vec![0.0; 3], ep(table::A.index()), ex(2), vec![0.0; 4]), om * om * th.cos());
        close(at(vec![0.0; 3], ep(table::OMEGA.index()), vec![0.0; 3], ep(table::OMEGA.index())), 2.0 * a * th.sin());
        close(at(vec![0.0; 3], ep(table::OMEGA.index()), ex(2), vec![0.0; 4]), 2.0 * a * om * th.cos());
        close(at(ex(0), vec![0.0; 4], ex(1), vec![0.0; 4]), 0.0);
        // Symmetry on general directions.
        let (u, v) = ([0.3, -1.2, 0.7], [1.1, 0.4, -0.5]);
        let (pu, pv) = ([0.2, -0.3, 0.0, 0.1], [-0.6, 0.5, 0.3, 0.0]);
        let ab = at(u.to_vec(), pu.to_vec(), v.to_vec(), pv.to_vec());
        let ba = at(v.to_vec(), pv.to_vec(), u.to_vec(), pu.to_vec());
        for k in 0..3 {
            assert_abs_diff_eq!(ab[k], ba[k], epsilon = 1e-13);
        }
        let mut r = [0.0; 3];
        m.reset_second_derivative(table::IMPACT, &x, &p, Variation { x: &ex(1), p: &none },
            Variation { x: &[0.0; 3], p: &ep(2) }, &mut r).unwrap();
        prop_assert_eq!(r, [0.0, -1.0, 0.0]);
    }
}
