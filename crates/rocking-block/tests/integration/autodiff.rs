//! The rocking block by automatic differentiation (`AutoDiff<RockingBlockModel>`) against its
//! hand-coded Jacobians: every Jacobian, and the derivatives along the variational equations'
//! directions, equal to rounding in every mode, at random states and parameters, and a branch
//! through the AD system with the same special points.

use hycont_continuation::{OrbitRun, RunDirection, SpecialKind};
use hycont_core::orbit::PeriodicOrbit;
use hycont_core::{AutoDiff, EventId, HybridJacobians, HybridSystem, ParamId, Tangents};
use proptest::prelude::*;
use rocking_block::block::Block;
use rocking_block::continuation::study_start;
use rocking_block::model_ad::RockingBlockModel;
use rocking_block::{ALPHA, MINUS, PLUS, REST, RockingBlock};

/// Relative to 1 + |hand-coded|: a few ulp of the largest terms.
const TOL: f64 = 1e-14;

fn close(a: &[f64], b: &[f64]) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= TOL * (1.0 + y.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, rng_seed: proptest::test_runner::RngSeed::Fixed(20261126), ..ProptestConfig::default() })]

    #[test]
    fn jacobians_equal_the_hand_coded_ones(
        mode in prop_oneof![Just(PLUS), Just(MINUS), Just(REST)],
        x in (-1.5f64..1.5, -2.0f64..2.0, -0.99f64..0.99, -1.5f64..1.5),
        p in (0.3f64..4.0, 0.0f64..1.2, 0.0f64..0.1, 0.65f64..1.5),
        dirs in proptest::collection::vec(-2.0f64..2.0, 4 * 6),
        param in 0usize..4,
    ) {
        let x = [x.0, x.1, x.2, x.3];
        let p = [p.0, p.1, p.2, p.3];
        let ad = AutoDiff::new(RockingBlockModel);
        let (mut a, mut h) = ([0.0; 16], [0.0; 16]);
        let (mut ap, mut hp) = ([0.0; 16], [0.0; 16]);
        let (mut fa, mut fh) = ([0.0; 4], [0.0; 4]);
        ad.vector_field_with_jacobian(mode, &x, &p, &mut fa, &mut a, Some(&mut ap));
        RockingBlock.vector_field_with_jacobian(mode, &x, &p, &mut fh, &mut h, Some(&mut hp));
        prop_assert!(close(&fa, &fh) && close(&a, &h) && close(&ap, &hp), "{a:?}\n{h:?}");
        tangents_match(mode, (&x, &p), &dirs, param, (&h, &hp))?;
        for e in RockingBlock.events(mode).iter().copied().chain([EventId(0), EventId(1)]) {
            let (mut a, mut h) = ([0.0; 4], [0.0; 4]);
            let (mut ap, mut hp) = ([0.0; 4], [0.0; 4]);
            ad.event_gradient(e, &x, &p, &mut a, Some(&mut ap));
            RockingBlock.event_gradient(e, &x, &p, &mut h, Some(&mut hp));
            prop_assert!(close(&a, &h) && close(&ap, &hp), "event {e:?}: {a:?} {h:?}");
            let (mut a, mut h) = ([0.0; 16], [0.0; 16]);
            let (mut ap, mut hp) = ([0.0; 16], [0.0; 16]);
            ad.reset_jacobian(e, &x, &p, &mut a, Some(&mut ap));
            RockingBlock.reset_jacobian(e, &x, &p, &mut h, Some(&mut hp));
            prop_assert!(close(&a, &h) && close(&ap, &hp), "reset {e:?}: {a:?} {h:?}");
        }
    }
}

/// The field's derivatives along six directions (four of the state; two also moving `param`
/// and the next parameter), as the variational equations ask for them: by AD from duals seeded
/// with the directions, equal to the hand-coded Jacobians `(h, hp)` times the directions. The
/// AD's implied Jacobian entries agree with `h` to `TOL` (1 + |h|) (as checked above), so a
/// product may differ by `TOL` times the sum over its terms of (1 + |h|) |direction|.
fn tangents_match(
    mode: hycont_core::Mode,
    (x, p): (&[f64], &[f64]),
    dirs: &[f64],
    param: usize,
    (h, hp): (&[f64], &[f64]),
) -> Result<(), TestCaseError> {
    let (n, k) = (4, 6);
    let params = [ParamId(param), ParamId((param + 1) % 4)];
    let (mut f, mut out, mut work) = ([0.0; 4], [0.0; 24], [0.0; 32]);
    let tangents = Tangents {
        x: dirs,
        params: &params,
        out: &mut out,
        work: &mut work,
    };
    AutoDiff::new(RockingBlockModel).vector_field_with_tangents(mode, x, p, &mut f, tangents);
    for j in 0..k {
        for i in 0..n {
            let direct = if j >= 4 {
                hp[i + params[j - 4].index() * n]
            } else {
                0.0
            };
            let col = &dirs[j * n..(j + 1) * n];
            let want = direct + (0..n).map(|c| h[i + c * n] * col[c]).sum::<f64>();
            let scale = (0..n).map(|c| (1.0 + h[i + c * n].abs()) * col[c].abs());
            let bound = TOL * (scale.sum::<f64>() + if j >= 4 { 1.0 + direct.abs() } else { 0.0 });
            let got = out[i + j * n];
            prop_assert!(
                (got - want).abs() <= bound,
                "mode {mode:?}, row {i}, direction {j}: {got} vs {want}"
            );
        }
    }
    Ok(())
}

/// The special points (kind, alpha) of the symmetric branch in alpha from `start` by `system`.
fn specials<S: HybridJacobians>(system: &S, start: &PeriodicOrbit) -> Vec<(SpecialKind, f64)> {
    let mut run = OrbitRun::new(system, ALPHA).unwrap();
    run.bounds(0.01, 1.06);
    let b = run.run("symmetric", start, RunDirection::Both).unwrap();
    b.branch
        .special_points
        .iter()
        .map(|s| (s.kind, s.point[ALPHA]))
        .collect()
}

/// Fig. 4's symmetric branch in alpha from the Fig. 2 orbit by both: the same fold, branch
/// point and grazing point.
#[test]
fn a_branch_through_the_ad_system_has_the_same_special_points() {
    let start = study_start(&Block::default()).unwrap();
    let a = specials(&AutoDiff::new(RockingBlockModel), &start);
    let h = specials(&RockingBlock, &start);
    assert_eq!(a.len(), h.len(), "{a:?} {h:?}");
    assert!(a.iter().any(|(k, _)| *k == SpecialKind::BranchPoint));
    for ((ka, pa), (kh, ph)) in a.iter().zip(&h) {
        assert_eq!(ka, kh);
        assert!((pa - ph).abs() < 1e-10, "{ka:?}: {pa} vs {ph}");
    }
}
