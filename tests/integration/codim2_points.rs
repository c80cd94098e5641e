//! Codimension-two points on two-parameter curves against closed forms, on a hybrid system
//! where they lie at computable places: two balls bouncing on vibrating tables driven by one
//! forcing (each the Holmes ball of `tests/integration/vibrating_table.rs`), with restitutions $e_1, e_2$,
//! gravities $g_1, g_2$, and ball 2's table a phase $\psi$ ahead.
//!
//! # The closed forms
//! The balls do not interact, so a period-1 orbit is a pair of the single ball's period-1
//! orbits and its non-trivial multipliers are the union of theirs. Ball $i$ alone (with
//! $\omega = 1$): impact phase $\theta_i$ with $a \cos\theta_i = \pi g_i (1-e_i)/(1+e_i)$,
//! (ball 2: relative to its table's phase $\theta + \psi$), multipliers with product $e_i^2$
//! and trace $1 + e_i^2 - \kappa_i (1+e_i)$,
//! $\kappa_i = a \sin\theta_i (1+e_i)/g_i$; a fold (multiplier $+1$) at
//! $a_\mathrm{SN}(e, g) = \pi g (1-e)/(1+e)$, a period doubling ($-1$) at
//! $a_\mathrm{PD}(e, g) = g F(e)$, $F(e) = \sqrt{4(1+e^2)^2/(1+e)^4 + \pi^2(1-e)^2/(1+e)^2}$, and
//! between them, where complex, the pair on the circle $|\lambda| = e$.
//!
//! Ball 1's fold and period-doubling curves in $(a, e_2)$ are the lines $a = a_\mathrm{SN}(e_1,
//! g_1)$ and $a = a_\mathrm{PD}(e_1, g_1)$; along them ball 2's multipliers move with $e_2$:
//! - on the fold curve, ball 2 at its fold is a 1:1 resonance (R1):
//!   $a_\mathrm{SN}(e_2, g_2) = a_\mathrm{SN}(e_1, g_1)$, i.e. $e_2 = (1 - r)/(1 + r)$ with
//!   $r = a_\mathrm{SN}(e_1, g_1)/(\pi g_2)$; at its period doubling a fold-flip point (LPPD):
//!   $g_2 F(e_2) = a_\mathrm{SN}(e_1, g_1)$; its complex pair reaches the unit circle at
//!   $e_2 = 1$ (LPNS, where $a < g_2$ keeps it complex);
//! - on the period-doubling curve, ball 2 at its fold is LPPD:
//!   $e_2 = (1 - r)/(1 + r)$, $r = a_\mathrm{PD}(e_1, g_1)/(\pi g_2)$; at its period doubling
//!   R2: $g_2 F(e_2) = a_\mathrm{PD}(e_1, g_1)$; its complex pair on the unit circle at
//!   $e_2 = 1$ (PDNS).
//!
//! Roots of $F$ are found by bisection to rounding. The phase $\psi$ and the gravities keep the
//! balls' impacts apart (equal times would make two events coincide: a domain boundary of the
//! orbits' signature).

use crate::model_two_balls as model;

use approx::assert_abs_diff_eq;
use hycont::check_derivatives;
use hycont::hycont_continuation::{CurveSpec, OrbitBranch, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{CollocationSettings, OrbitMethod, ShootingSettings};
use model::{A, E1, E2, FLIGHT, G1, PSI, TwoBalls, a_pd, a_sn, bisect, orbit};
use std::f64::consts::PI;

/// Ball 1's fold or period doubling (the one at `a_ref`) on the branch in `a` through `a0`.
fn ball_one_point(
    run: &mut OrbitRun<'_, TwoBalls>,
    (a0, e2, g2): (f64, f64, f64),
    kind: SpecialKind,
    a_ref: f64,
) -> (OrbitBranch, usize) {
    let branch = run
        .run("period-1", &orbit(a0, e2, g2), RunDirection::Both)
        .unwrap();
    let label = branch
        .special(kind)
        .find(|s| (s.point[A] - a_ref).abs() < 1e-6)
        .unwrap_or_else(|| {
            panic!(
                "no {kind} at a = {a_ref}: {:?}",
                branch.branch.special_points
            )
        })
        .point
        .label;
    (branch, label)
}

/// The curve of ball 1's `kind` point in `(a, e2)` over `e2` in `window` from the branch
/// through `(a0, e2_0, g2)`, and the located points of `found` on it.
fn points_on_curve(
    method: OrbitMethod,
    (a0, e2_0, g2): (f64, f64, f64),
    kind: SpecialKind,
    a_ref: f64,
    window: (f64, f64),
    found: SpecialKind,
) -> Vec<(f64, f64, (f64, f64))> {
    let mut run = OrbitRun::new(&TwoBalls, A).unwrap();
    run.method(method).bounds(0.3, 3.0);
    let (branch, label) = ball_one_point(&mut run, (a0, e2_0, g2), kind, a_ref);
    let spec = CurveSpec::new(E2).bounds(window.0, window.1);
    let curve = run.curve_at(kind.label(), &branch, label, &spec).unwrap();
    // The curve is ball 1's line a = a_ref.
    for p in &curve.branch.points {
        assert_abs_diff_eq!(p[A], a_ref, epsilon = 1e-8);
    }
    curve
        .special(found)
        .inspect(|s| assert!(s.located, "{s:?}"))
        .map(|s| (s.point[E2], s.point[A], s.critical.expect("its multiplier")))
        .collect()
}

fn shooting() -> OrbitMethod {
    OrbitMethod::Shooting(ShootingSettings::default())
}

/// By both discretisations: exactly one located `found` point on the curve of
/// [`points_on_curve`], at `e2_ref` (to 1e-8); its multiplier.
fn the_point_at(
    start: (f64, f64, f64),
    (kind, a_ref): (SpecialKind, f64),
    window: (f64, f64),
    found: SpecialKind,
    e2_ref: f64,
) -> (f64, f64) {
    let mut critical = (f64::NAN, f64::NAN);
    for method in [
        shooting(),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let pts = points_on_curve(method, start, kind, a_ref, window, found);
        assert_eq!(pts.len(), 1, "{method:?}: {pts:?}");
        assert_abs_diff_eq!(pts[0].0, e2_ref, epsilon = 1e-8);
        critical = pts[0].2;
    }
    critical
}

#[test]
fn the_analytic_jacobians_match_differences() {
    for (x, p) in [
        (
            [0.3, -0.7, 1.1, 0.4, 0.9],
            [1.2, 1.0, 0.5, 0.7, 1.0, 1.2, -1.5],
        ),
        (
            [0.0, 2.0, 0.5, -1.0, -2.5],
            [0.8, 1.3, 0.6, 0.3, 2.0, 1.0, 0.4],
        ),
    ] {
        let check = check_derivatives(&TwoBalls, FLIGHT, &x, &p).unwrap();
        assert!(check.max_error() < 1e-7, "{check:?}");
    }
}

/// From the fold-flip point on ball 1's fold curve, the other curve through it in one call:
/// ball 2's period-doubling curve, the closed form a = g2 F(e2) (omega = 1), through the
/// point.
#[test]
fn the_period_doubling_curve_through_a_fold_flip_point() {
    let a_ref = a_sn(E1, G1);
    let mut run = OrbitRun::new(&TwoBalls, A).unwrap();
    run.method(shooting()).bounds(0.3, 3.0);
    let (branch, label) =
        ball_one_point(&mut run, (1.1 * a_ref, 0.65, 1.0), SpecialKind::Fold, a_ref);
    let spec = CurveSpec::new(E2).bounds(0.56, 0.95);
    let fold = run.curve_at("SN", &branch, label, &spec).unwrap();
    let lppd = fold.first(SpecialKind::FoldFlip).unwrap().point.label;
    let pd = run.curve_through("PD", &fold, lppd, &spec).unwrap();
    assert_eq!(
        pd.condition,
        Some(hycont::hycont_continuation::CurveCondition::PeriodDoubling)
    );
    assert!(pd.branch.points.len() > 10);
    for p in &pd.branch.points {
        assert_abs_diff_eq!(p[A], a_pd(p[E2], 1.0), epsilon = 1e-8);
    }
    // Through the fold-flip point; and it meets ball 1's fold line there again (LPPD).
    let meet = pd.first(SpecialKind::FoldFlip).unwrap();
    assert_abs_diff_eq!(meet.point[A], a_ref, epsilon = 1e-8);
    // Only from LPPD points.
    let not = fold.branch.points[3].label;
    assert!(run.curve_through("x", &fold, not, &spec).is_err());
}

/// Curves end where their orbits leave their domain, as branches do: on ball 1's
/// period-doubling curve past ball 2's fold (its other, unstable sheet), ball 2's impact
/// reaches ball 1's, a domain boundary (DB), at $\theta_2' = \theta_1 + \psi$ (ball 2's phase
/// relative to its table), i.e. $a_\mathrm{SN}(e_2, g_2) = a \cos(\theta_1 + \psi)$ with
/// $\cos\theta_1 = a_\mathrm{SN}(e_1, g_1)/a$.
#[test]
fn a_curve_ends_at_its_domain_boundary() {
    let a_ref = a_pd(E1, G1);
    let theta1 = (a_sn(E1, G1) / a_ref).acos();
    let r = a_ref * (theta1 + PSI).cos() / (PI * 1.2);
    let db_ref = (1.0 - r) / (1.0 + r);
    let mut run = OrbitRun::new(&TwoBalls, A).unwrap();
    run.method(shooting()).bounds(0.3, 3.0);
    let (branch, label) = ball_one_point(
        &mut run,
        (1.05 * a_ref, 0.5, 1.2),
        SpecialKind::PeriodDoubling,
        a_ref,
    );
    let spec = CurveSpec::new(E2).bounds(0.3, 0.55);
    let curve = run.curve_at("PD", &branch, label, &spec).unwrap();
    let db = hycont::hycont_continuation::Label::new("DB").unwrap();
    let ends: Vec<_> = curve.special(SpecialKind::Custom(db)).collect();
    assert_eq!(ends.len(), 1, "{:?}", curve.branch.special_points);
    assert!(ends[0].located);
    assert_abs_diff_eq!(ends[0].point[E2], db_ref, epsilon = 1e-8);
    // It ends the curve there: the run that met it stopped (the joined curve's first point),
    // after the fold-flip point where the curve turned onto ball 2's unstable sheet.
    let first = &curve.branch.points[0];
    assert_abs_diff_eq!(first[E2], db_ref, epsilon = 1e-8);
    assert_eq!(curve.special(SpecialKind::FoldFlip).count(), 1);
}

/// On ball 1's fold curve (g2 = 1.2), ball 2's fold: a 1:1 resonance (R1), a second
/// multiplier +1, at e2 = (1 - r)/(1 + r), r = a_SN(e1, g1)/(pi g2); by both discretisations.
#[test]
fn a_resonance_one_on_the_fold_curve() {
    let a_ref = a_sn(E1, G1);
    let r = a_ref / (PI * 1.2);
    let fold = (SpecialKind::Fold, a_ref);
    let start = (1.1 * a_ref, 0.8, 1.2);
    let m = the_point_at(
        start,
        fold,
        (0.45, 0.95),
        SpecialKind::Resonance1,
        (1.0 - r) / (1.0 + r),
    );
    assert_abs_diff_eq!(m.0, 1.0, epsilon = 1e-6);
}

/// On ball 1's fold curve, ball 2's period doubling: a fold-flip point (LPPD), with a
/// multiplier -1 besides the held +1, where g2 F(e2) = a_SN(e1, g1); by both
/// discretisations.
#[test]
fn a_fold_flip_on_the_fold_curve() {
    let a_ref = a_sn(E1, G1);
    let e2_ref = bisect(|e| a_pd(e, 1.0) - a_ref, 0.6, 0.99);
    let fold = (SpecialKind::Fold, a_ref);
    let start = (1.1 * a_ref, 0.65, 1.0);
    let m = the_point_at(start, fold, (0.56, 0.95), SpecialKind::FoldFlip, e2_ref);
    assert_abs_diff_eq!(m.0, -1.0, epsilon = 1e-6);
}

/// On ball 1's fold curve with g2 = 1.2 (ball 2 between its fold and period doubling, complex
/// multipliers of modulus e2): they reach the unit circle at e2 = 1, LPNS; by both
/// discretisations.
#[test]
fn a_fold_torus_point_on_the_fold_curve() {
    let a_ref = a_sn(E1, G1);
    let fold = (SpecialKind::Fold, a_ref);
    let start = (1.1 * a_ref, 0.8, 1.2);
    let (re, im) = the_point_at(start, fold, (0.7, 1.2), SpecialKind::FoldTorus, 1.0);
    assert_abs_diff_eq!(re.hypot(im), 1.0, epsilon = 1e-6);
}

/// On ball 1's period-doubling curve (g2 = 1.2): ball 2's fold is LPPD (e2 = (1 - r)/(1 + r)),
/// ball 2's period doubling R2 (a second -1), by both discretisations.
#[test]
fn fold_flip_and_resonance_two_on_the_period_doubling_curve() {
    let a_ref = a_pd(E1, G1);
    let r = a_ref / (PI * 1.2);
    let flip = (SpecialKind::PeriodDoubling, a_ref);
    let (window, lppd_ref) = ((0.3, 0.55), (1.0 - r) / (1.0 + r));
    let m = the_point_at(
        (1.05 * a_ref, 0.5, 1.2),
        flip,
        window,
        SpecialKind::FoldFlip,
        lppd_ref,
    );
    assert_abs_diff_eq!(m.0, 1.0, epsilon = 1e-6);
    let r2_ref = bisect(|e| a_pd(e, 1.2) - a_ref, 0.57, 0.9);
    let start = (0.95 * a_ref, 0.75, 1.2);
    let m = the_point_at(start, flip, (0.58, 0.9), SpecialKind::Resonance2, r2_ref);
    assert_abs_diff_eq!(m.0, -1.0, epsilon = 1e-6);
}

/// On ball 1's period-doubling curve with g2 = 2 (ball 2 between its fold and period
/// doubling): its complex pair on the unit circle at e2 = 1, PDNS; by both discretisations.
#[test]
fn a_flip_torus_point_on_the_period_doubling_curve() {
    let a_ref = a_pd(E1, G1);
    let flip = (SpecialKind::PeriodDoubling, a_ref);
    let start = (1.05 * a_ref, 0.9, 2.0);
    let (re, im) = the_point_at(start, flip, (0.75, 1.2), SpecialKind::FlipTorus, 1.0);
    assert_abs_diff_eq!(re.hypot(im), 1.0, epsilon = 1e-6);
}
