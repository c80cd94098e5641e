//! Terminal events located at one point: the run ends at the one the problem lists first
//! ([`ContinuationProblem::monitor_events`]), or the one its `end_among` names, not at
//! whichever rounding happens to place first.
//!
//! The model: $x^2 = l$ continued down from $(1, 1)$. Event A watches the monitor $x$ at
//! $0.7$, crossed at $l = 0.49$; event B watches $l$ at $0.49 + \delta$, crossed first (the
//! run goes down in $l$). Along the branch $dl/ds = 2x/\sqrt{1 + 4x^2} \approx 0.81$ at
//! $x = 0.7$, so B's zero lies $\delta / 0.81$ of arclength before A's. Zeros closer than the
//! location's tolerance (and their brackets' widths) cannot be ordered by the location: they
//! are one point, and precedence decides.

use crate::models::*;

use hycont_continuation::observe::Silent;
use hycont_continuation::{
    Branch, ContinuationProblem, ContinuationSettings, EndReason, MeasureId, MonitorEvent,
    Quantity, SpecialKind, continue_branch,
};
use hycont_core::ParamId;

const LOCATE_TOL: f64 = 1e-10;

fn label(text: &str) -> SpecialKind {
    SpecialKind::Custom(hycont_continuation::Label::new(text).unwrap())
}

fn event_a() -> MonitorEvent {
    MonitorEvent {
        kind: label("A"),
        on: MeasureId::new(0).into(),
        level: 0.7,
        terminal: true,
    }
}

fn event_b(delta: f64) -> MonitorEvent {
    MonitorEvent {
        kind: label("B"),
        on: Quantity::Parameter(ParamId(0)),
        level: 0.49 + delta,
        terminal: true,
    }
}

fn run(problem: &mut impl ContinuationProblem<'static>) -> Branch {
    let settings = ContinuationSettings {
        locate_tol: LOCATE_TOL,
        ..settings().parameter_bounds(-1.0, 2.0)
    };
    let u0 = [1.0, 1.0, 1.0];
    continue_branch(problem, "parabola", &u0, -1.0, &settings, &mut Silent).unwrap()
}

fn parabola_with(events: Vec<MonitorEvent>) -> Test {
    let mut t = Test::new(1, parabola, no_multipliers);
    t.events = events;
    t
}

/// The located end of a run with `events`: its kind and parameter.
fn end_of(events: Vec<MonitorEvent>) -> (SpecialKind, f64) {
    let b = run(&mut parabola_with(events));
    let end = b.special_points.last().unwrap();
    assert!(end.located);
    assert!(
        matches!(b.end, EndReason::Inadmissible(k) if k == end.kind),
        "{:?}",
        b.end
    );
    (end.kind, end.point.params[0])
}

/// With $\delta = 0.4$ tolerances B is located before A (alone, each run ends a little
/// before its zero, on the near side), yet both together end at A, listed first; listed the
/// other way, at B. With $\delta = 100$ tolerances the zeros are distinct points and B, met
/// first, ends the run whatever the order.
#[test]
fn coinciding_terminal_events_end_the_run_in_the_listed_order() {
    let delta = 0.4 * LOCATE_TOL;
    let (_, l_a) = end_of(vec![event_a()]);
    let (_, l_b) = end_of(vec![event_b(delta)]);
    assert!(l_b > l_a, "B is met first: {l_b} vs {l_a}");
    assert!((l_a - 0.49).abs() < 2.0 * LOCATE_TOL && (l_b - 0.49 - delta).abs() < 2.0 * LOCATE_TOL);
    assert_eq!(end_of(vec![event_a(), event_b(delta)]).0, label("A"));
    assert_eq!(end_of(vec![event_b(delta), event_a()]).0, label("B"));
    let apart = 100.0 * LOCATE_TOL;
    for events in [
        vec![event_a(), event_b(apart)],
        vec![event_b(apart), event_a()],
    ] {
        let (kind, l) = end_of(events);
        assert_eq!(kind, label("B"));
        assert!((l - 0.49 - apart).abs() < 2.0 * LOCATE_TOL, "{l}");
    }
}

/// A problem's `end_among` is asked once, at the point, with the coinciding events in the
/// listed order, and its choice ends the run; events that do not coincide are not put to it.
#[test]
fn the_problem_names_the_end_among_coinciding_events() {
    // A problem that knows the last of the coinciding events says more.
    let last = |located: &[MonitorEvent]| located.len() - 1;
    let delta = 0.4 * LOCATE_TOL;
    let mut p = parabola_with(vec![event_a(), event_b(delta)]);
    p.end_choice = Some(last);
    let b = run(&mut p);
    assert_eq!(b.special_points.last().unwrap().kind, label("B"));
    assert_eq!(p.asked.len(), 1, "{:?}", p.asked);
    let (l, kinds) = &p.asked[0];
    assert!((l - 0.49).abs() < 1e-9, "asked at the point: l = {l}");
    assert_eq!(kinds, &vec![label("A"), label("B")]);
    let mut apart = parabola_with(vec![event_a(), event_b(100.0 * LOCATE_TOL)]);
    apart.end_choice = Some(last);
    let b = run(&mut apart);
    assert_eq!(b.special_points.last().unwrap().kind, label("B"));
    assert!(apart.asked.is_empty(), "{:?}", apart.asked);
}
