//! The chain of `N` masses against a stop (`examples/impact_chain/model.rs`, state dimension
//! `2N + 2`) against its exact reference (`examples/impact_chain/reference.rs`, derived
//! there): the impacting period-1 orbit and its Floquet multipliers from matrix exponentials
//! and one scalar equation for the impact phase, for N = 1, 2, 5, 10, 25, 50, by multiple
//! shooting and by collocation; and a branch in the forcing frequency whose fold and
//! grazing are the reference's.
//!
//! Tolerances: starts to 1e-8 (the states are at most of order 1; shooting integrates to
//! 1e-12 relative, collocation's error at NTST 20 is about 1e-11 here); each multiplier to
//! 1e-8 relative to `max(1, |mu|)` (the chain's multipliers reach 550, and an eigenvalue
//! moves by the monodromy's error times its condition).

#[path = "../../examples/impact_chain/model.rs"]
mod model;
#[path = "../../examples/impact_chain/reference.rs"]
mod reference;
#[path = "../../examples/impact_chain/setup.rs"]
mod setup;

use hycont::orbit::{
    CollocationSettings, Floquet, PeriodicOrbit, ShootingSettings, solve_collocation,
    solve_shooting,
};
use hycont::problem::NewtonSettings;
use model::ImpactChain;

/// The largest distance from each exact multiplier to the closest computed non-trivial one,
/// relative to `max(1, |mu|)`, after checking that there are as many.
fn multiplier_error(floquet: &Floquet, exact: &[(f64, f64)]) -> f64 {
    let computed: Vec<(f64, f64)> = floquet.nontrivial().collect();
    assert_eq!(computed.len(), exact.len());
    exact
        .iter()
        .map(|m| {
            let d = computed
                .iter()
                .map(|q| (q.0 - m.0).hypot(q.1 - m.1))
                .fold(f64::INFINITY, f64::min);
            d / m.0.hypot(m.1).max(1.0)
        })
        .fold(0.0, f64::max)
}

fn start_error(orbit: &PeriodicOrbit, exact: &[f64]) -> f64 {
    (orbit.starts[0].iter().zip(exact))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Both discretisations, from the exact orbit, stay on it: starts to 1e-8, multipliers to
/// 1e-8 relative, for every chain length (state dimension 4 to 102); and the exact orbits
/// are those the derivation says: one physical impacting orbit at each length, unstable from
/// N = 5 on (a multiplier beyond the unit circle), stable for N = 1 and 2.
#[test]
fn both_methods_find_the_exact_orbit_of_every_chain() {
    for n in setup::SIZES {
        let chain = ImpactChain { masses: n };
        let p = setup::parameters(n);
        let physical: Vec<_> = reference::exact_orbits(n, &p)
            .into_iter()
            .filter(|o| reference::is_physical(n, &p, o))
            .collect();
        assert_eq!(physical.len(), 1, "N = {n}");
        let exact = &physical[0];
        let guess = setup::exact_orbit(n).unwrap();
        let newton = NewtonSettings::default();
        let shooting = solve_shooting(&chain, &guess, ShootingSettings::default(), &newton)
            .unwrap_or_else(|e| panic!("N = {n}: shooting: {e}"));
        let collocation =
            solve_collocation(&chain, &guess, CollocationSettings::default(), &newton)
                .unwrap_or_else(|e| panic!("N = {n}: collocation: {e}"))
                .solution;
        for (method, sol) in [("shooting", &shooting), ("collocation", &collocation)] {
            let start = start_error(&sol.orbit, &exact.start);
            let mu = multiplier_error(&sol.floquet, &exact.multipliers);
            assert!(start < 1e-8, "N = {n}, {method}: start off by {start:e}");
            assert!(mu < 1e-8, "N = {n}, {method}: multipliers off by {mu:e}");
            assert_eq!(sol.floquet.stable(), n <= 2, "N = {n}, {method}");
        }
    }
}

/// The root of `f` in `[a, b]` (a sign change) by bisection, to roundoff.
fn root(f: impl Fn(f64) -> f64, (mut a, mut b): (f64, f64)) -> f64 {
    let fa = f(a);
    assert!(fa * f(b) < 0.0, "no sign change in [{a}, {b}]");
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if (f(m) > 0.0) == (fa > 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// The reference's period-doubling function at `p`: the most negative real multiplier of
/// the physical orbit, plus one.
fn doubling_function(n: usize, p: &[f64]) -> f64 {
    let orbit = reference::exact_orbits(n, p)
        .into_iter()
        .find(|o| reference::is_physical(n, p, o))
        .expect("a physical orbit");
    let most_negative = (orbit.multipliers.iter())
        .filter(|m| m.1.abs() < 1e-9)
        .map(|m| m.0)
        .fold(f64::INFINITY, f64::min);
    most_negative + 1.0
}

/// Up in `w` from the exact orbit at `w = 1.3`, the impacting branches end at the grazing
/// (GR: the impact velocity vanishes, `|Z_{x_N}| = d`). The one mass's branch folds first
/// (SN: the two impact phases of the derivation meet, `rho = d`) and comes back to it; the
/// two masses' branch doubles its period first (PD: a multiplier of the reference's S E
/// through -1) and grazes before it would fold. Each located to 1e-8 in `w` by both
/// discretisations; the reference's roots bracketed by a scan of its functions.
#[test]
fn the_branch_in_the_forcing_frequency_folds_doubles_and_grazes_where_the_reference_does() {
    use hycont::hycont_continuation::{OrbitMethod, OrbitRun, RunDirection, SpecialKind};
    type Function = fn(usize, &[f64]) -> f64;
    type Expected = (SpecialKind, Function, (f64, f64));
    let expected: [(usize, [Expected; 2]); 2] = [
        (
            1,
            [
                (SpecialKind::Fold, reference::fold_function, (1.6, 1.8)),
                (
                    SpecialKind::Grazing,
                    reference::grazing_function,
                    (1.3, 1.4),
                ),
            ],
        ),
        (
            2,
            [
                (SpecialKind::PeriodDoubling, doubling_function, (1.3, 1.4)),
                (
                    SpecialKind::Grazing,
                    reference::grazing_function,
                    (1.6, 1.75),
                ),
            ],
        ),
    ];
    for (n, points) in expected {
        let chain = ImpactChain { masses: n };
        let p = setup::parameters(n);
        let at = |w: f64| {
            let mut q = p.clone();
            q[3] = w;
            q
        };
        let orbit = setup::exact_orbit(n).unwrap();
        for method in [
            OrbitMethod::Shooting(ShootingSettings::default()),
            OrbitMethod::Collocation(CollocationSettings::default()),
        ] {
            let mut run = OrbitRun::new(&chain, model::W).unwrap();
            run.method(method).bounds(1.0, 2.0);
            let branch = run.run("impacting", &orbit, RunDirection::Up).unwrap();
            for (kind, f, bracket) in &points {
                let exact = root(|w| f(n, &at(w)), *bracket);
                let found = branch.first(*kind).unwrap().point[model::W];
                assert!(
                    (found - exact).abs() < 1e-8,
                    "N = {n}: {} at {found}, reference {exact}",
                    kind.label()
                );
            }
        }
    }
}
