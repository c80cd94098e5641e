//! The symmetric two-sided impact oscillator's period-doubling cascade in one diagram
//! (`examples/symmetric_branch/model.rs`, `omega = 0.6`, `k = 1`, `c = 0.1`, `d = 1`,
//! `e = 0.8`, continued in the amplitude `a`): the symmetric orbit breaks its symmetry at a
//! branch point, the asymmetric orbits double, and each doubled branch doubles again,
//! towards smaller `a`.
//!
//! Each doubling is located on the branch switched on at the previous one. Late in a cascade
//! the next doubling is closer to the last than a first step (PD6 is 4e-6 in `a` past PD5):
//! a switched branch that did not test its first step missed it and the cascade ended at
//! PD5. The references: every doubling carries a multiplier at -1 (the critical tolerance
//! 1e-6), and the intervals shrink by ratios approaching Feigenbaum's delta, so that
//! `PD5 + (PD5 - PD4) / delta` estimates PD6 to within the ratios' distance from delta (a few
//! 1e-3 relative) times the interval (4e-6): 1e-8.

use crate::model_symmetric_branch as pair;

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{DiagramSettings, OrbitRun, SpecialKind};
use pair::{A, ImpactPair};

const FEIGENBAUM_DELTA: f64 = 4.669_201_609_102_99;

#[test]
fn the_impact_pairs_cascade_goes_on_past_a_doubling_inside_a_first_step() {
    let found = pair::find_symmetric(&[1.0, 0.6, 1.0, 0.1, 1.0, 0.8]).unwrap();
    let mut run = OrbitRun::new(&ImpactPair, A).unwrap();
    run.bounds(0.05, 3.0);
    let settings = DiagramSettings {
        depth: 6,
        ..DiagramSettings::default()
    };
    let diagram = run
        .diagram("symmetric", &found.full.orbit, &settings)
        .unwrap();
    let cascades = diagram.cascades();
    assert_eq!(cascades.len(), 1, "{cascades:?}");
    let pd = &cascades[0].doublings;
    assert_eq!(pd.len(), 6, "PD1 to PD6: {pd:?}");
    assert!(
        pd.windows(2).all(|w| w[1] < w[0]),
        "towards smaller a: {pd:?}"
    );
    let ratios = cascades[0].ratios();
    assert!(
        ratios[1..]
            .iter()
            .all(|r| (r - FEIGENBAUM_DELTA).abs() < 0.05),
        "{ratios:?}"
    );
    let estimate = pd[4] - (pd[3] - pd[4]) / FEIGENBAUM_DELTA;
    assert_abs_diff_eq!(pd[5], estimate, epsilon = 1e-8);
    // Every doubling is genuine: a multiplier at -1.
    for (_, s) in diagram.special_points() {
        if s.kind == SpecialKind::PeriodDoubling {
            let (re, im) = s.critical.expect("a located PD carries its multiplier");
            assert!((re + 1.0).abs() <= 1e-6 && im.abs() <= 1e-8, "{re} {im}");
        }
    }
}
