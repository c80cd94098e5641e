//! Analytic Jacobians of the rocking block against central differences, at random states and
//! parameters (proptest), in every mode, including event gradients and reset Jacobians.

use hycont_core::{
    AutoDiff, DerivativeKind, HybridJacobians, Mode, check_derivatives, check_derivatives_against,
};
use proptest::prelude::*;
use rocking_block::model_ad::RockingBlockModel;
use rocking_block::{MINUS, PLUS, REST, RockingBlock};

/// Central differences with step eps^(1/3) have truncation error ~ h^2 |f'''| / 6 ~ 1e-11 here;
/// 1e-7 (scaled by 1 + |value|) leaves room for round-off while catching any wrong entry.
const TOL: f64 = 1e-7;

fn mode_strategy() -> impl Strategy<Value = Mode> {
    prop_oneof![Just(PLUS), Just(MINUS), Just(REST)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, rng_seed: proptest::test_runner::RngSeed::Fixed(20261122), ..ProptestConfig::default() })]

    #[test]
    fn jacobians_match_central_differences(
        mode in mode_strategy(),
        phi in -1.5f64..1.5,
        psi in -2.0f64..2.0,
        r in -1.5f64..1.5,
        s in -1.5f64..1.5,
        omega in 0.3f64..4.0,
        alpha in 0.0f64..1.2,
        xi in 0.0f64..0.1,
        theta_b in 0.65f64..1.5,
    ) {
        let x = [phi, psi, r, s];
        let p = [omega, alpha, xi, theta_b];
        let check = check_derivatives(&RockingBlock, mode, &x, &p).unwrap();
        for m in &check.worst {
            prop_assert!(m.error < TOL, "{m:?} in mode {mode} at x = {x:?}, p = {p:?}");
        }
    }
}

/// The checks must be able to fail: a deliberately wrong Jacobian is caught by central
/// differences and, entry by entry, by the AD twin.
#[test]
fn a_wrong_jacobian_is_detected() {
    struct Wrong;
    impl hycont_core::HybridSystem for Wrong {
        fn state_dim(&self) -> usize {
            4
        }
        fn parameter_names(&self) -> &[&'static str] {
            RockingBlock.parameter_names()
        }
        fn mode_count(&self) -> usize {
            3
        }
        fn mode_name(&self, m: Mode) -> &'static str {
            RockingBlock.mode_name(m)
        }
        fn events(&self, m: Mode) -> &[hycont_core::EventId] {
            RockingBlock.events(m)
        }
        fn event_spec(&self, e: hycont_core::EventId) -> hycont_core::EventSpec {
            RockingBlock.event_spec(e)
        }
        fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
            RockingBlock.vector_field(m, x, p, out);
        }
        fn event(&self, e: hycont_core::EventId, x: &[f64], p: &[f64]) -> f64 {
            RockingBlock.event(e, x, p)
        }
        fn reset(&self, e: hycont_core::EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
            RockingBlock.reset(e, x, p, out);
        }
    }
    impl HybridJacobians for Wrong {
        fn vector_field_jacobian(
            &self,
            m: Mode,
            x: &[f64],
            p: &[f64],
            dx: &mut [f64],
            dp: Option<&mut [f64]>,
        ) {
            RockingBlock.vector_field_jacobian(m, x, p, dx, dp);
            dx[1] *= 1.001; // d psi' / d phi off by 0.1 %
        }
        fn event_gradient(
            &self,
            e: hycont_core::EventId,
            x: &[f64],
            p: &[f64],
            dx: &mut [f64],
            dp: Option<&mut [f64]>,
        ) {
            RockingBlock.event_gradient(e, x, p, dx, dp);
        }
    }
    let (x, p) = ([0.3, 0.2, 0.5, 0.8], [1.3, 0.66, 0.00022, 0.8795]);
    let check = check_derivatives(&Wrong, PLUS, &x, &p).unwrap();
    assert!(check.max_error() > 1e-4, "{check:?}");
    // Against the exact derivatives of the AD twin the wrong entry is named, with the error the
    // 0.1 % makes (|0.001 v| / (1 + |v|)) to rounding; the parameter columns are right to
    // rounding, and the missing reset Jacobian (the identity) is caught too.
    let exact = AutoDiff::new(RockingBlockModel);
    let check = check_derivatives_against(&Wrong, &exact, PLUS, &x, &p).unwrap();
    let of = |kind: DerivativeKind| check.worst.iter().find(|m| m.kind == kind).unwrap();
    let state = of(DerivativeKind::VectorFieldState);
    assert_eq!((state.row, state.col), (1, 0), "{state:?}");
    let v = state.numeric;
    assert!(
        (state.error - 0.001 * v.abs() / (1.0 + v.abs())).abs() < 1e-14,
        "{state:?}"
    );
    assert!(of(DerivativeKind::VectorFieldParams).error < 1e-15);
    let resets = check
        .worst
        .iter()
        .filter(|m| matches!(m.kind, DerivativeKind::ResetState(_)));
    assert!(
        resets.clone().count() > 0 && resets.clone().all(|m| m.error > 1e-2),
        "{check:?}"
    );
    // The right system against it: rounding everywhere.
    let check = check_derivatives_against(&RockingBlock, &exact, PLUS, &x, &p).unwrap();
    assert!(check.max_error() < 1e-14, "{check:?}");
}
