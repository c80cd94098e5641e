//! Grazing curves from the GR points that end branches by default trace in one go, by either
//! discretisation, against closed forms.
//!
//! # The closed forms
//! COCO's impact oscillator (`examples/impact_oscillator/model.rs`, Recipes Ex. 15.2),
//! $\ddot x + c\dot x + kx = A\sin(wt + \beta)$ with a wall at $x = d$: without impacts the
//! periodic response is $x = R\sin(wt + \beta - \varphi)$ with
//! $$R = \frac{A}{\sqrt{(k - w^2)^2 + (cw)^2}}.$$
//! An impacting period-1 orbit grazes when its impact velocity vanishes: then the impact
//! does nothing ($v \mapsto -ev = 0$), so the orbit is the free response whose maximum touches
//! the wall, $R = d$:
//! $$A_{GR}(w) = d\sqrt{(k - w^2)^2 + (cw)^2}.$$
//! The symmetric two-sided impact oscillator (`examples/symmetric_branch/model.rs`, walls at
//! $\pm d$) has the same free response, symmetric, touching both walls at once: the same
//! $a_{GR}(\omega)$ ends its impacting symmetric orbits. The piecewise-linear oscillator
//! (`examples/piecewise_linear/model.rs`) grazes its switching surface $x = d$ at
//! $f = d\sqrt{(1 - \omega^2)^2 + (2\zeta\omega)^2}$ (derived in `tests/integration/piecewise_linear.rs`).
//!
//! # In one go
//! The admissibility margin that ends a branch at GR is the smallest of several conditions;
//! it is not smooth where an interior turning point reaches a segment's end, which is exactly
//! where these grazings happen. A curve that held it crawled (steps of 1e-5 to 1e-8, stopped at
//! its 4000-point limit after covering a few per cent of the curve). Holding the one
//! condition that attains it ([`Touch`]), each curve reaches both bounds in a few hundred
//! points; the bench `grazing_curves` times them.

use crate::model_impact_oscillator as impact;
use crate::model_piecewise_linear as pwl;
use crate::model_symmetric_branch as pair;

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{
    CurveCondition, CurveSpec, EndReason, MeasureId, OrbitBranch, OrbitRun, RunDirection,
    SpecialKind,
};
use hycont::orbit::{
    CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings,
    Signature, Touch,
};
use hycont::{FiniteDifferences, HybridJacobians};
use std::f64::consts::TAU;

/// Points a curve over the whole window may take: a few hundred do (the crawl took 4000 for a
/// few per cent of it).
const FEW: usize = 400;

fn methods() -> [OrbitMethod; 2] {
    [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ]
}

/// `A = d sqrt((k - w^2)^2 + (c w)^2)`.
fn graze(k: f64, c: f64, d: f64, w: f64) -> f64 {
    d * ((k - w * w).powi(2) + (c * w).powi(2)).sqrt()
}

/// The whole curve: both bounds reached, few points, every point within `tol` of `closed`.
fn check_curve(
    curve: &OrbitBranch,
    x: hycont::ParamId,
    y: hycont::ParamId,
    (lo, hi): (f64, f64),
    closed: impl Fn(f64) -> f64,
    tol: f64,
) {
    let b = &curve.branch;
    assert_eq!(b.end, EndReason::Bound, "{}", b.name);
    assert!(
        b.points.len() < FEW,
        "{}: {} points",
        b.name,
        b.points.len()
    );
    let xs = b.points.iter().map(|p| p[x]);
    let (min, max) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, c), v| {
        (a.min(v), c.max(v))
    });
    assert_abs_diff_eq!(min, lo, epsilon = 1e-9);
    assert_abs_diff_eq!(max, hi, epsilon = 1e-9);
    for p in b
        .points
        .iter()
        .chain(b.special_points.iter().map(|s| &s.point))
    {
        assert_abs_diff_eq!(p[y], closed(p[x]), epsilon = tol);
    }
}

/// COCO's impact oscillator: the default GR (impact velocity zero) at the closed form, and
/// the grazing curve from it over w in [0.2, 1.58] held by the impact's approach rate,
/// within 1e-9 of the closed form.
#[test]
fn the_impact_oscillators_grazing_curve_traces_in_one_go() {
    use impact::{AMP, W};
    let sys = impact::ImpactOscillator;
    let start = impact::impacting_orbit().unwrap();
    for method in methods() {
        let mut run = OrbitRun::new(&sys, AMP).unwrap();
        run.method(method).bounds(0.01, 2.0);
        let branch = run.run("impacting", &start, RunDirection::Down).unwrap();
        assert_eq!(
            branch.branch.end,
            EndReason::Inadmissible(SpecialKind::Grazing)
        );
        let gr = branch.first(SpecialKind::Grazing).unwrap();
        assert_eq!(gr.on, Some(MeasureId::ADMISSIBLE_GRAZING.into()));
        assert_abs_diff_eq!(gr.point[AMP], graze(1.0, 0.1, 1.0, 1.0), epsilon = 1e-9);
        let spec = CurveSpec::new(W).bounds(0.2, 1.58);
        let curve = run
            .curve_at("grazing", &branch, gr.point.label, &spec)
            .unwrap();
        assert!(
            matches!(
                curve.condition,
                Some(CurveCondition::Touch {
                    touch: Touch::Approach { segment: 0, .. },
                    kind: SpecialKind::Grazing,
                    ..
                })
            ),
            "{method:?}: {:?}",
            curve.condition
        );
        check_curve(
            &curve,
            W,
            AMP,
            (0.2, 1.58),
            |w| graze(1.0, 0.1, 1.0, w),
            1e-9,
        );
        // Saved, the curve continues from either end with its condition.
        let end = curve.branch.points.last().unwrap().label;
        let again = run
            .curve_from("again", &curve, end, &CurveSpec::new(W).bounds(0.2, 1.7))
            .unwrap();
        assert!(
            again
                .branch
                .points
                .iter()
                .all(|p| { (p[AMP] - graze(1.0, 0.1, 1.0, p[W])).abs() < 1e-9 })
        );
    }
}

/// The piecewise-linear oscillator's soft orbit: its branch ends at the default GR where its
/// maximum (the end of its segment, split at v = 0) reaches the switching surface; the curve
/// holds that end on the surface.
#[test]
fn the_piecewise_linear_grazing_curve_traces_in_one_go() {
    let osc = FiniteDifferences::new(pwl::Oscillator);
    let (zeta, d, omega) = (0.05, 1.0, 0.8);
    let end = SegmentEnd::Interior {
        component: 1,
        value: 0.0,
    };
    let sig = Signature::new(
        &osc,
        vec![SegmentSpec {
            mode: pwl::SOFT,
            end,
        }],
    )
    .unwrap();
    let soft = PeriodicOrbit::new(
        &osc,
        sig,
        vec![vec![0.8, 0.0, 1.0, 0.0]],
        vec![TAU / omega],
        vec![0.3, omega, zeta, 1.0, d],
    )
    .unwrap();
    let closed = |w: f64| d * ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
    for method in methods() {
        let mut run = OrbitRun::new(&osc, pwl::F).unwrap();
        run.method(method).bounds(0.01, 3.0);
        let up = run.run("soft", &soft, RunDirection::Up).unwrap();
        let gr = up.first(SpecialKind::Grazing).unwrap();
        assert_eq!(gr.on, Some(MeasureId::ADMISSIBLE_GRAZING.into()));
        let spec = CurveSpec::new(pwl::OMEGA).bounds(0.2, 1.58);
        let curve = run.curve_at("grazing", &up, gr.point.label, &spec).unwrap();
        check_curve(&curve, pwl::OMEGA, pwl::F, (0.2, 1.58), closed, 1e-9);
    }
}

/// The symmetric orbit of the two-sided impact oscillator with one impact on each wall, at
/// `(a, omega) = (1, 0.6)`.
fn impact_pair() -> PeriodicOrbit {
    pair::find_symmetric(&[1.0, 0.6, 1.0, 0.1, 1.0, 0.8])
        .unwrap()
        .full
        .orbit
}

/// The impact pair's symmetric branch ends both ways at default GR points: where its impacts
/// vanish (the closed form), and where its flight dips to the other wall between impacts (its
/// physical end). Both grazing curves trace over omega in [0.2, 0.8] in one go; the first
/// within 1e-9 of the closed form, the second the same by both discretisations.
#[test]
fn the_impact_pairs_grazing_curves_trace_in_one_go() {
    use pair::{A, OMEGA};
    let sys = pair::ImpactPair;
    let start = impact_pair();
    let mut physical_end = Vec::new();
    for method in methods() {
        let mut run = OrbitRun::new(&sys, A).unwrap();
        run.method(method).bounds(0.05, 3.0);
        let branch = run.run("pair", &start, RunDirection::Both).unwrap();
        let grs: Vec<_> = branch.special(SpecialKind::Grazing).collect();
        assert_eq!(grs.len(), 2, "{method:?}");
        assert_abs_diff_eq!(grs[0].point[A], graze(1.0, 0.1, 1.0, 0.6), epsilon = 1e-9);
        let spec = CurveSpec::new(OMEGA)
            .bounds(0.2, 0.8)
            .user_points(OMEGA, [0.4, 0.7]);
        let vanishing = run
            .curve_at("vanishing", &branch, grs[0].point.label, &spec)
            .unwrap();
        check_curve(
            &vanishing,
            OMEGA,
            A,
            (0.2, 0.8),
            |w| graze(1.0, 0.1, 1.0, w),
            1e-9,
        );
        let dip = run
            .curve_at("dip", &branch, grs[1].point.label, &spec)
            .unwrap();
        assert!(matches!(
            dip.condition,
            Some(CurveCondition::Touch {
                touch: Touch::Turn { .. },
                ..
            })
        ));
        assert_eq!(dip.branch.end, EndReason::Bound);
        assert!(dip.branch.points.len() < FEW);
        let uz: Vec<f64> = dip
            .special(SpecialKind::UserPoint)
            .map(|s| s.point[A])
            .collect();
        assert_eq!(uz.len(), 2);
        physical_end.push((grs[1].point[A], uz));
    }
    // Shooting and collocation (NTST 20, NCOL 4) agree on the physical end and its curve.
    let (a, b) = (&physical_end[0], &physical_end[1]);
    assert_abs_diff_eq!(a.0, b.0, epsilon = 1e-8);
    for (x, y) in a.1.iter().zip(&b.1) {
        assert_abs_diff_eq!(x, y, epsilon = 1e-8);
    }
}

/// A touch's gradient is the derivative of its value (central differences over every
/// coordinate of the orbit) for each kind of touch.
#[test]
fn touch_gradients_are_the_derivatives_of_their_values() {
    let sys = pair::ImpactPair;
    let mut orbit = impact_pair();
    orbit.params[0] = 1.2;
    let touches = [
        Touch::Approach {
            segment: 0,
            event: pair::RIGHT,
        },
        Touch::End {
            segment: 0,
            event: pair::LEFT,
        },
        Touch::Turn {
            segment: 0,
            event: pair::LEFT,
            fraction: 0.6,
        },
    ];
    for touch in touches {
        check_gradient(&sys, &orbit, touch);
    }
}

fn check_gradient<S: HybridJacobians>(sys: &S, orbit: &PeriodicOrbit, touch: Touch) {
    let v = touch.evaluate(sys, orbit).unwrap();
    let n = orbit.starts[0].len();
    let kk = orbit.segment_count();
    let mut i = 0;
    let coords = kk * (n + 1) + orbit.params.len();
    assert_eq!(v.gradient.len(), coords);
    while i < coords {
        let h = 1e-6;
        let shifted = |s: f64| {
            let mut o = orbit.clone();
            if i < kk * n {
                o.starts[i / n][i % n] += s;
            } else if i < kk * (n + 1) {
                o.durations[i - kk * n] += s;
            } else {
                o.params[i - kk * (n + 1)] += s;
            }
            touch.near(v.fraction).evaluate(sys, &o).unwrap().value
        };
        let fd = (shifted(h) - shifted(-h)) / (2.0 * h);
        assert_abs_diff_eq!(v.gradient[i], fd, epsilon = 1e-6 * (1.0 + fd.abs()));
        i += 1;
    }
}

/// The case: the impact pair at `omega = 0.6`, `a = 1.5`, beyond its physical end
/// (a = 1.3603, where its flight dips to the other wall) solves the orbit equations, but a run
/// from it (or a restart at it) with admissibility on is refused by either discretisation,
/// naming the segment and the wall crossed; it used to return some 60 non-physical points.
#[test]
fn a_start_beyond_the_physical_end_is_refused() {
    use hycont::hycont_continuation::Error as RunError;
    use hycont::orbit::Violation;
    use pair::A;
    let sys = pair::ImpactPair;
    let start = impact_pair();
    for method in methods() {
        let mut off = OrbitRun::new(&sys, A).unwrap();
        off.method(method)
            .bounds(0.9, 1.6)
            .admissibility(false)
            .unwrap();
        off.add_user_points(A, [1.5]).unwrap();
        let past = off.run("past", &start, RunDirection::Up).unwrap();
        let uz = past.first(SpecialKind::UserPoint).unwrap().point.label;
        let beyond = past.orbit_at(uz).unwrap();
        let mut run = OrbitRun::new(&sys, A).unwrap();
        run.method(method).bounds(0.9, 1.6);
        for result in [
            run.run("beyond", &beyond, RunDirection::Both),
            run.restart("beyond", &past, uz, None),
        ] {
            match result {
                Err(RunError::InadmissibleStart {
                    segment: 0,
                    event: Some(e),
                    violation: Violation::InteriorCrossing,
                    ..
                }) => assert_eq!(e, pair::LEFT),
                other => panic!(
                    "{method:?}: expected the start refused, got {:?}",
                    other.err()
                ),
            }
        }
    }
}
