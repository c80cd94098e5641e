//! Detectors and driver against problems with exactly known answers.

use crate::models;

use approx::assert_abs_diff_eq;
use hycont_continuation::observe::{Counter, Silent};
use hycont_continuation::{
    Branch, ContinuationSettings, Detect, EndReason, MeasureId, MonitorEvent, Quantity,
    SpecialKind, branch_switch_direction, continue_along, continue_branch,
};
use models::*;

#[test]
fn fold_of_x_squared_minus_l_is_located_at_zero() {
    let mut t = Test::new(1, parabola, no_multipliers);
    let b = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
    let folds: Vec<_> = b.special(SpecialKind::Fold).collect();
    assert_eq!(folds.len(), 1);
    let sn = folds[0];
    assert!(sn.located);
    assert!(
        sn.point.params[0].abs() < 1e-9,
        "fold at l = {:e}",
        sn.point.params[0]
    );
    assert!(sn.point.u[0].abs() < 1e-4);
    // No branch point on a fold.
    assert_eq!(b.special(SpecialKind::BranchPoint).count(), 0);
    // It turns and ends at the bound l = 2 on the other sheet, with an exact end point.
    assert_eq!(b.end, EndReason::Bound);
    let ep = b.special(SpecialKind::EndPoint).next().unwrap();
    assert!((ep.point.params[0] - 2.0).abs() < 1e-9 && ep.point.u[0] < 0.0);
}

/// Arclength weights change the steps, not the branch: weighing x by 100 makes each step
/// 10 times shorter in x near the fold, so the run takes more points to the same bound, and
/// the fold is at l = 0 either way. Invalid weights are refused.
#[test]
fn arclength_weights_change_the_steps_not_the_branch() {
    let mut points = Vec::new();
    for weights in [None, Some(vec![100.0, 1.0, 1.0])] {
        let mut t = Test::new(1, parabola, no_multipliers);
        t.weights = weights;
        let b = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
        let sn = b.special(SpecialKind::Fold).next().unwrap();
        assert!(sn.located && sn.point.params[0].abs() < 1e-9);
        for p in &b.points {
            assert_abs_diff_eq!(p.u[0] * p.u[0], p.u[1], epsilon = 1e-9);
        }
        points.push(b.points.len());
    }
    assert!(points[1] > 2 * points[0], "points {points:?}");
    for bad in [
        vec![1.0, 1.0],
        vec![0.0, 1.0, 1.0],
        vec![f64::NAN, 1.0, 1.0],
    ] {
        let mut t = Test::new(1, parabola, no_multipliers);
        t.weights = Some(bad.clone());
        let u0 = t.start(&[1.0], 1.0);
        let err = continue_branch(&mut t, "p", &u0, -1.0, &settings(), &mut Silent).unwrap_err();
        assert!(
            err.to_string().contains("unknown_weights"),
            "{bad:?}: {err}"
        );
    }
}

#[test]
fn pitchfork_branch_point_is_located_and_switched() {
    let mut t = Test::new(1, pitchfork, no_multipliers);
    let u0 = t.start(&[0.0], -1.0);
    let b = continue_branch(
        &mut t,
        "trivial",
        &u0,
        1.0,
        &settings().parameter_bounds(-2.0, 1.0),
        &mut Silent,
    )
    .unwrap();
    let bps: Vec<_> = b.special(SpecialKind::BranchPoint).collect();
    assert_eq!(
        bps.len(),
        1,
        "{:?}",
        b.special_points.iter().map(|s| s.kind).collect::<Vec<_>>()
    );
    let bp = bps[0];
    assert!(
        bp.located && bp.point.params[0].abs() < 1e-9,
        "BP at {:e}",
        bp.point.params[0]
    );
    // The other branch: x^2 = l, in both directions from the BP.
    let phi = branch_switch_direction(&mut t, &bp.point.u, &bp.point.tangent).unwrap();
    assert!(phi[0].abs() > 0.9, "switch direction {phi:?}");
    for dir in [1.0, -1.0] {
        let other = continue_along(
            &mut t,
            "x^2 = l",
            &bp.point.u,
            &phi,
            dir,
            &settings().parameter_bounds(-2.0, 1.0),
            &mut Silent,
        )
        .unwrap();
        assert!(other.points.len() > 5);
        for p in &other.points[1..] {
            assert_abs_diff_eq!(p.u[0] * p.u[0], p.u[1], epsilon = 1e-8);
        }
        assert!(other.points.last().unwrap().u[0] * dir > 0.0);
    }
}

/// A multiplier $\lambda = 1 - 2 \cdot 10^5\, l$ on the pitchfork's branches: $-1$ (a period
/// doubling) at $l = 10^{-5}$.
fn steep_multiplier(u: &[f64]) -> Vec<(f64, f64)> {
    vec![(1.0 - 2e5 * u[1], 0.0)]
}

/// A branch continued along a direction from a branch point tests its first step like any
/// other: on $l = x^2$ from the pitchfork at $l = 0$, the first step (0.01 in arclength, so
/// $x \approx \pm 0.01$, $l \approx 10^{-4}$) passes the period doubling of
/// `steep_multiplier` at $l = 10^{-5}$ and a user point at $l = 4 \cdot 10^{-5}$: both are
/// located there (to the location tolerance), both ways; the branch point itself is not
/// reported again.
#[test]
fn a_switched_branch_tests_its_first_step() {
    let mut t = Test::new(1, pitchfork, steep_multiplier);
    t.events = vec![user_point_on_l(4e-5)];
    let s = settings().parameter_bounds(-2.0, 1.0);
    let u0 = t.start(&[0.0], -1.0);
    let trivial = continue_branch(&mut t, "trivial", &u0, 1.0, &s, &mut Silent).unwrap();
    let bp = trivial.special(SpecialKind::BranchPoint).next().unwrap();
    let phi = branch_switch_direction(&mut t, &bp.point.u, &bp.point.tangent).unwrap();
    for dir in [1.0, -1.0] {
        let other =
            continue_along(&mut t, "x^2 = l", &bp.point.u, &phi, dir, &s, &mut Silent).unwrap();
        let kinds: Vec<_> = other.special_points.iter().map(|s| s.kind).collect();
        assert_eq!(
            kinds,
            [
                SpecialKind::PeriodDoubling,
                SpecialKind::UserPoint,
                SpecialKind::EndPoint
            ],
            "direction {dir}"
        );
        let (pd, uz) = (&other.special_points[0], &other.special_points[1]);
        assert!(pd.located && uz.located);
        assert_abs_diff_eq!(pd.point.params[0], 1e-5, epsilon = 1e-12);
        assert_abs_diff_eq!(uz.point.params[0], 4e-5, epsilon = 1e-12);
        assert_abs_diff_eq!(pd.point.u[0], dir * 1e-5f64.sqrt(), epsilon = 1e-8);
        assert!(
            other.points[0].params[0] > 4e-5,
            "the first chart is past both"
        );
    }
}

/// The bifurcating branch of a pitchfork, $l = x^2$, turns in $l$ at the branch point itself:
/// continued through it, the parameter's tangent component changes sign there, which is the
/// branch point's doing, not a fold (the tangent is undefined at a branch point).
#[test]
fn a_branch_through_a_pitchfork_has_a_branch_point_and_no_fold() {
    let mut t = Test::new(1, pitchfork, no_multipliers);
    let u0 = t.start(&[0.7], 0.49);
    let b = continue_branch(
        &mut t,
        "x^2 = l",
        &u0,
        -1.0,
        &settings().parameter_bounds(-2.0, 1.0),
        &mut Silent,
    )
    .unwrap();
    let kinds: Vec<_> = b.special_points.iter().map(|s| s.kind).collect();
    assert_eq!(
        kinds,
        [SpecialKind::BranchPoint, SpecialKind::EndPoint],
        "special points {kinds:?}"
    );
    // Located to 1e-10 in arclength along the chart's hyperplane. Close to the branch point the
    // corrector may land on the crossing branch x = 0, which meets the hyperplane at a small
    // angle (~2|x|), so the parameter is less accurate than from the trivial branch (1e-9,
    // above): about 1e-10 / (2|x|) with |x| ~ 1e-4 at the last charts.
    let bp = &b.special_points[0];
    assert!(
        bp.located && bp.point.params[0].abs() < 1e-6 && bp.point.u[0].abs() < 1e-4,
        "BP at {:?}",
        bp.point.u
    );
    // Through the branch point onto the x < 0 half, to the bound l = 1.
    let ep = &b.special_points[1];
    assert!((ep.point.params[0] - 1.0).abs() < 1e-9 && ep.point.u[0] < -0.9);
}

/// A branch-point factor from the analysis (as a half-orbit problem reports where the symmetry
/// breaks, which its own Jacobian does not see) marks a branch point where it changes sign,
/// located like the determinant's: on x^2 = l with factor x - 1/2, at l = 1/4; the fold at
/// l = 0 is still a fold.
#[test]
fn a_branch_point_factor_from_the_analysis_is_located() {
    fn half_minus_x(u: &[f64]) -> f64 {
        0.5 - u[0]
    }
    let mut t = Test::new(1, parabola, no_multipliers);
    let plain = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
    assert_eq!(plain.special(SpecialKind::BranchPoint).count(), 0);
    t.bp_factor = Some(half_minus_x);
    let b = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
    let kinds: Vec<_> = b.special_points.iter().map(|s| s.kind).collect();
    assert_eq!(
        kinds,
        [
            SpecialKind::BranchPoint,
            SpecialKind::Fold,
            SpecialKind::EndPoint
        ],
        "special points {kinds:?}"
    );
    let bp = &b.special_points[0];
    assert!(
        bp.located && (bp.point.params[0] - 0.25).abs() < 1e-9,
        "BP at l = {}",
        bp.point.params[0]
    );
    let sn = &b.special_points[1];
    assert!(sn.located && sn.point.params[0].abs() < 1e-9);
}

/// The unit circle $x^2 + l^2 = 1$ continued in $l$: the test problem's unknowns are
/// $(x, l, l)$ (the parameter and its monitor), so in the arclength metric the circle is an
/// ellipse whose curvature varies about threefold along it, and the steps are bounded by the
/// largest angle between consecutive tangents (0.15 rad), not by the corrector (every point
/// converges at once from the high-order predictor). The step control follows the curvature
/// (and its trend) below the angle: no step is rejected (without that, steps grown by the
/// factor 1.4 into a turn above the angle are rejected, halved, grown and rejected again: 17
/// times on this run), consecutive tangents stay within the angle, and the steps are not
/// timid (the longest above 0.2: the angle allows about 0.27 where the curvature is least).
#[test]
fn steps_follow_the_curvature_below_the_largest_angle_without_rejections() {
    fn circle(u: &[f64], r: &mut [f64], j: Option<&mut [f64]>) {
        r[0] = u[0] * u[0] + u[1] * u[1] - 1.0;
        if let Some(j) = j {
            j[0] = 2.0 * u[0];
            j[1] = 2.0 * u[1];
        }
    }
    let mut t = Test::new(1, circle, no_multipliers);
    let u0 = t.start(&[1.0], 0.0);
    let mut s = ContinuationSettings::default().steps(0.01, 1e-8, 1.0);
    s.max_points = 60;
    let b = continue_branch(&mut t, "circle", &u0, 1.0, &s, &mut Silent).unwrap();
    assert_eq!(b.statistics.rejected_steps, 0, "{:?}", b.statistics);
    for w in b.points.windows(2) {
        // Unit tangents in the (unweighted) arclength metric.
        let (p, q) = (&w[0].tangent, &w[1].tangent);
        let cos: f64 = p.iter().zip(q).map(|(a, b)| a * b).sum();
        let angle = cos.clamp(-1.0, 1.0).acos();
        assert!(angle <= s.max_angle, "{angle} at l = {}", w[1].params[0]);
    }
    let longest = b.points.iter().map(|p| p.step).fold(0.0, f64::max);
    assert!(longest > 0.2, "longest step {longest}");
}

/// The work counters of a run (evaluations while stepping and while locating) are consistent
/// and survive serialisation.
#[test]
fn run_statistics_count_the_work() {
    let mut t = Test::new(1, parabola, no_multipliers);
    let b = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
    let st = b.statistics;
    // Every point needs a factorisation at its solution; the fold and the end point were
    // located with more.
    assert!(st.jacobians >= b.points.len(), "{st:?}");
    assert!(st.location_jacobians > 0, "{st:?}");
    assert!(st.analyses >= b.points.len(), "{st:?}");
    // Saved runs keep them; files without them still load.
    let back = hycont_continuation::Branch::from_json(&b.to_json().unwrap()).unwrap();
    assert_eq!(back.statistics, st);
    let mut v: serde_json::Value = serde_json::from_str(&b.to_json().unwrap()).unwrap();
    v.as_object_mut().unwrap().remove("statistics");
    let old = hycont_continuation::Branch::from_json(&v.to_string()).unwrap();
    assert_eq!(
        old.statistics,
        hycont_continuation::RunStatistics::default()
    );
}

#[test]
fn period_doubling_of_the_logistic_map_at_r_3() {
    let mut t = Test::new(1, logistic, logistic_multiplier);
    let u0 = t.start(&[1.0 - 1.0 / 2.5], 2.5);
    let b = continue_branch(
        &mut t,
        "fixed point",
        &u0,
        1.0,
        &settings().parameter_bounds(2.0, 3.5),
        &mut Silent,
    )
    .unwrap();
    let pd: Vec<_> = b.special(SpecialKind::PeriodDoubling).collect();
    assert_eq!(pd.len(), 1);
    assert_abs_diff_eq!(pd[0].point.params[0], 3.0, epsilon = 1e-9);
    assert!((pd[0].point.multipliers[0].0 + 1.0).abs() < 1e-8);
    // Stability: stable before r = 3, unstable after.
    assert!(b.points.iter().all(|p| (p.params[0] < 3.0) == p.stable()));
    assert_eq!(b.special(SpecialKind::Torus).count(), 0);
}

#[test]
fn torus_point_of_the_delayed_logistic_map_at_r_2() {
    let mut t = Test::new(2, delayed_logistic, delayed_logistic_multipliers);
    let x = 1.0 - 1.0 / 1.6;
    let u0 = t.start(&[x, x], 1.6);
    let b = continue_branch(
        &mut t,
        "fixed point",
        &u0,
        1.0,
        &settings().parameter_bounds(1.5, 2.4),
        &mut Silent,
    )
    .unwrap();
    let tr: Vec<_> = b.special(SpecialKind::Torus).collect();
    assert_eq!(
        tr.len(),
        1,
        "{:?}",
        b.special_points
            .iter()
            .map(|s| (s.kind, s.point.params[0]))
            .collect::<Vec<_>>()
    );
    assert_abs_diff_eq!(tr[0].point.params[0], 2.0, epsilon = 1e-9);
    assert_eq!(b.special(SpecialKind::PeriodDoubling).count(), 0);
}

#[test]
fn monitor_events_are_located() {
    let mut t = Test::new(1, parabola, no_multipliers);
    t.events = vec![MonitorEvent {
        kind: SpecialKind::BoundaryTouch,
        on: MeasureId::new(0).into(),
        level: 0.7,
        terminal: false,
    }];
    let b = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
    let sb: Vec<_> = b.special(SpecialKind::BoundaryTouch).collect();
    assert_eq!(sb.len(), 1);
    assert_abs_diff_eq!(sb[0].point.monitors[0], 0.7, epsilon = 1e-9);
    assert_abs_diff_eq!(sb[0].point.params[0], 0.49, epsilon = 1e-9);
    assert_eq!(sb[0].on, Some(Quantity::Measure(MeasureId::new(0))));
    assert_eq!(sb[0].level, Some(0.7));
}

/// Levels of the continued parameter are located on the level itself, not within a bracket
/// around it: on $x^2 = l$ from $(1, 1)$ down through the fold and back up, the user point at
/// $l = 0.49$ on both sheets ($x = \pm 0.7$) and the end point at the bound $l = 2$
/// ($x = -\sqrt 2$) have $l$ at the level to a few units of roundoff (the corrector holds
/// it), $x$ at its root to the corrector's tolerance, an arclength uncertainty of roundoff,
/// and the branch's tangent there, $(t_x, t_l) \propto (1, 2x)$, oriented along the run.
#[test]
fn levels_of_the_continued_parameter_are_located_on_the_level() {
    let mut t = Test::new(1, parabola, no_multipliers);
    t.events = vec![user_point_on_l(0.49)];
    let b = parabola_down(&mut t, &settings().parameter_bounds(-1.0, 2.0));
    let kinds: Vec<_> = b.special_points.iter().map(|s| s.kind).collect();
    assert_eq!(
        kinds,
        [
            SpecialKind::UserPoint,
            SpecialKind::Fold,
            SpecialKind::UserPoint,
            SpecialKind::EndPoint
        ]
    );
    let levels = [(0, 0.49, 0.7), (2, 0.49, -0.7), (3, 2.0, -(2.0f64.sqrt()))];
    for (i, level, x) in levels {
        let sp = &b.special_points[i];
        let (u, t) = (&sp.point.u, &sp.point.tangent);
        assert!(sp.located, "{sp:?}");
        assert!((u[1] - level).abs() <= 4.0 * f64::EPSILON * level, "{sp:?}");
        assert!(sp.accuracy <= 1e-14, "{sp:?}");
        assert_abs_diff_eq!(u[0], x, epsilon = 1e-9);
        assert_abs_diff_eq!(t[1], 2.0 * u[0] * t[0], epsilon = 1e-9);
        // Along the run: l falls on the upper sheet and rises on the lower one.
        assert!(t[1] * x < 0.0, "{sp:?}");
    }
}

/// A bound on a monitor ends the branch with an end point located on it: on x^2 = l, past the
/// fold, the monitor x reaches -0.5 at l = 0.25.
#[test]
fn a_monitor_bound_ends_the_branch_at_a_located_end_point() {
    let mut t = Test::new(1, parabola, no_multipliers);
    let b = parabola_down(
        &mut t,
        &settings()
            .parameter_bounds(-1.0, 2.0)
            .bounds(MeasureId::new(0), -0.5, 2.0),
    );
    assert_eq!(b.end, EndReason::Bound);
    let ep = b.special_points.last().unwrap();
    assert_eq!(
        (ep.kind, ep.on),
        (SpecialKind::EndPoint, Some(MeasureId::new(0).into()))
    );
    assert!(ep.located);
    assert!((ep.point.monitors[0] + 0.5).abs() < 1e-9);
    assert_abs_diff_eq!(ep.point.params[0], 0.25, epsilon = 1e-9);
    // The fold came first.
    assert_eq!(b.special_points[0].kind, SpecialKind::Fold);
}

#[test]
fn reversing_the_direction_finds_the_same_special_points() {
    let mut t = Test::new(1, logistic, logistic_multiplier);
    let s = settings().parameter_bounds(2.0, 3.5);
    let fwd = {
        let u0 = t.start(&[1.0 - 1.0 / 2.1], 2.1);
        continue_branch(&mut t, "f", &u0, 1.0, &s, &mut Silent)
    }
    .unwrap();
    let bwd = {
        let u0 = t.start(&[1.0 - 1.0 / 3.4], 3.4);
        continue_branch(&mut t, "b", &u0, -1.0, &s, &mut Silent)
    }
    .unwrap();
    let pf = fwd
        .special(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .point
        .params[0];
    let pb = bwd
        .special(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .point
        .params[0];
    assert_abs_diff_eq!(pf, pb, epsilon = 1e-8);
}

#[test]
fn branches_serialise_and_restart_from_a_label() {
    let mut t = Test::new(1, parabola, no_multipliers);
    let s = settings().parameter_bounds(-1.0, 2.0).max_points(20);
    let b = {
        let u0 = t.start(&[1.0], 1.0);
        continue_branch(&mut t, "parabola", &u0, -1.0, &s, &mut Silent)
    }
    .unwrap();
    assert_eq!(b.end, EndReason::MaxPoints);
    let json = b.to_json().unwrap();
    let back = Branch::from_json(&json).unwrap();
    assert_eq!(back, b);
    let last = back.points.last().unwrap();
    let p = back.point(last.label).unwrap();
    let more = continue_along(
        &mut t,
        "restart",
        &p.u,
        &p.tangent,
        1.0,
        &settings().parameter_bounds(-1.0, 2.0),
        &mut Silent,
    )
    .unwrap();
    // Continues in the same direction (decreasing l) and reaches the fold.
    assert!(more.points[1].params[0] < p.params[0]);
    assert_eq!(more.special(SpecialKind::Fold).count(), 1);
    assert!(back.point(9999).is_err());
}

#[test]
fn a_failure_mid_branch_ends_it_gracefully() {
    let mut t = Test::new(1, logistic, logistic_multiplier);
    t.fail_above = 2.8;
    let mut counter = Counter::default();
    let b = {
        let u0 = t.start(&[1.0 - 1.0 / 2.5], 2.5);
        continue_branch(&mut t, "f", &u0, 1.0, &settings(), &mut counter)
    }
    .unwrap();
    assert!(
        matches!(b.end, EndReason::CorrectorFailed(_)),
        "{:?}",
        b.end
    );
    assert!(b.points.len() > 3);
    assert!(b.points.iter().all(|p| p.params[0] <= 2.8));
    assert_eq!(counter.points, b.points.len());
}

#[test]
fn detectors_can_be_switched_off_and_settings_are_validated() {
    let mut t = Test::new(1, parabola, no_multipliers);
    let s = settings().parameter_bounds(-1.0, 2.0).detect(Detect {
        fold: false,
        ..Detect::default()
    });
    let b = {
        let u0 = t.start(&[1.0], 1.0);
        continue_branch(&mut t, "parabola", &u0, -1.0, &s, &mut Silent)
    }
    .unwrap();
    assert_eq!(b.special(SpecialKind::Fold).count(), 0);
    // A first step outside [h_min, h_max] is taken at the nearest of them ...
    let clamped = ContinuationSettings::default().steps(0.1, 1e-3, 0.01);
    assert!(clamped.validate().is_ok());
    assert_eq!(clamped.first_step(), 0.01);
    // ... but a window with h_max below h_min is refused.
    let bad = ContinuationSettings::default().steps(0.005, 1e-2, 1e-3);
    assert!(
        {
            let u0 = t.start(&[1.0], 1.0);
            continue_branch(&mut t, "x", &u0, 1.0, &bad, &mut Silent)
        }
        .is_err()
    );
}

/// An observer that asks to stop after hearing `left` points.
struct StopAfterPoints {
    left: usize,
}

impl hycont_continuation::Observer for StopAfterPoints {
    fn point(&mut self, _: &hycont_continuation::BranchPoint, _: f64) {
        self.left = self.left.saturating_sub(1);
    }
    fn stop(&mut self) -> bool {
        self.left == 0
    }
}

/// A run whose observer asks it to stop ends cleanly with the points it has, `Stopped`, all
/// on the branch.
#[test]
fn a_run_stops_when_its_observer_asks() {
    let mut t = Test::new(1, parabola, no_multipliers);
    let u0 = t.start(&[1.0], 1.0);
    let mut stop = StopAfterPoints { left: 5 };
    let s = settings().parameter_bounds(-1.0, 2.0);
    let b = continue_branch(&mut t, "parabola", &u0, -1.0, &s, &mut stop).unwrap();
    assert_eq!(b.end, EndReason::Stopped);
    assert_eq!(b.points.len(), 5);
    for p in &b.points {
        assert_abs_diff_eq!(p.u[0] * p.u[0], p.u[1], epsilon = 1e-9);
    }
}

/// A run that starts exactly on a bound and steps out of the window ends there with an end
/// point at the bound (its test function starts at zero and has no sign change to find); one
/// that steps into the window runs on to the other bound. On x^2 = l from (1, 1) with bounds
/// [1, 2]: down (out of the window) ends at l = 1 at once, up ends at l = 2.
#[test]
fn a_run_that_starts_on_its_bound_and_steps_out_ends_there() {
    let s = settings().parameter_bounds(1.0, 2.0);
    let mut t = Test::new(1, parabola, no_multipliers);
    let out = parabola_down(&mut t, &s);
    assert_eq!(out.end, EndReason::Bound);
    assert!(
        out.points.iter().all(|p| p.params[0] >= 1.0 - 1e-12),
        "{:?}",
        out.points.len()
    );
    assert!(out.points.len() <= 2, "{}", out.points.len());
    let ep = out.special(SpecialKind::EndPoint).next().unwrap();
    assert!((ep.point.params[0] - 1.0).abs() < 1e-12);
    let mut t = Test::new(1, parabola, no_multipliers);
    let u0 = t.start(&[1.0], 1.0);
    let up = continue_branch(&mut t, "parabola", &u0, 1.0, &s, &mut Silent).unwrap();
    assert_eq!(up.end, EndReason::Bound);
    let ep = up.special(SpecialKind::EndPoint).next().unwrap();
    assert!((ep.point.params[0] - 2.0).abs() < 1e-9);
}

/// A (non-terminal) user point where the continued parameter $l$ reaches `level`.
fn user_point_on_l(level: f64) -> MonitorEvent {
    MonitorEvent {
        kind: SpecialKind::UserPoint,
        on: Quantity::Parameter(hycont_core::ParamId(0)),
        level,
        terminal: false,
    }
}
