//! Admissibility: solves refuse orbits that leave their modes' domains, branches end where
//! they would, and test functions do not report bifurcations through a multiplier's pole.
//!
//! The model: the Hopf normal form $\dot x = y + x(a - r^2)$, $\dot y = -x + y(a - r^2)$
//! between two walls $x = \pm w$ (events: $x$ rising through $w$, $x$ falling through $-w$).
//! Its limit cycle is the circle $r = \sqrt a$ (period $2\pi$), one segment from $(\sqrt a, 0)$
//! round to $y = 0$. The circle stays between the walls while $\sqrt a < w$ and touches both at
//! $a = w^2$: there the orbit grazes (GR), and beyond it the circle crosses the walls inside its
//! segment, which the simulator would not follow.

use approx::assert_abs_diff_eq;
use hycont_continuation::{EndReason, OrbitRun, RunDirection, SpecialKind};
use hycont_core::orbit::{
    PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings, Signature, Violation,
    check_admissible, solve_shooting,
};
use hycont_core::problem::NewtonSettings;
use hycont_core::{
    Direction, Error, EventAction, EventId, EventSpec, FiniteDifferences, HybridSystem, Mode,
    ParamId,
};
use std::f64::consts::PI;

const WALL: f64 = 1.4;
const A: ParamId = ParamId(0);

struct Walled;

impl HybridSystem for Walled {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "inside"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[EventId(0), EventId(1)]
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: if e.0 == 0 { "right wall" } else { "left wall" },
            direction: if e.0 == 0 {
                Direction::Rising
            } else {
                Direction::Falling
            },
            action: EventAction::Terminal,
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        f[0] = x[1] + x[0] * r;
        f[1] = -x[0] + x[1] * r;
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        if e.0 == 0 { x[0] - WALL } else { x[0] + WALL }
    }
}

fn circle(a: f64) -> PeriodicOrbit {
    let sig = Signature::new(
        &Walled,
        vec![SegmentSpec {
            mode: Mode(0),
            end: SegmentEnd::Interior {
                component: 1,
                value: 0.0,
            },
        }],
    )
    .unwrap();
    PeriodicOrbit::new(
        &Walled,
        sig,
        vec![vec![a.sqrt(), 0.0]],
        vec![2.0 * PI],
        vec![a],
    )
    .unwrap()
}

/// Inside the walls the circle is admissible; past them the solve is refused, naming the
/// segment, the wall and where the circle crosses it.
#[test]
fn solves_past_the_walls_are_refused() {
    let sys = FiniteDifferences::new(Walled);
    assert!(check_admissible(&sys, &circle(1.0)).is_ok());
    let newton = NewtonSettings::default();
    assert!(solve_shooting(&sys, &circle(1.0), ShootingSettings::default(), &newton).is_ok());
    // a = 4: the circle of radius 2 starts beyond the right wall (x = 2), swings left past
    // x = -1.4 and back right through x = 1.4, rising, before its end: the right wall is
    // reported (its event is checked first) at the segment's end, with margin 1.4 - 2.
    let err = solve_shooting(&sys, &circle(4.0), ShootingSettings::default(), &newton).unwrap_err();
    match err {
        Error::Inadmissible {
            segment: 0,
            event: Some(EventId(0)),
            violation: Violation::EndOutside,
            t,
            value,
        } => {
            assert_abs_diff_eq!(t, 2.0 * PI, epsilon = 1e-8);
            assert_abs_diff_eq!(value, WALL - 2.0, epsilon = 1e-8);
        }
        other => panic!("expected the right wall crossed before the end, got {other:?}"),
    }
    // Started at the leftmost point (-2, 0), the flow (clockwise) swings right: the
    // interior minimum of the right wall's margin 1.4 - x, half a turn in, is negative.
    let mut left = circle(4.0);
    left.starts[0] = vec![-2.0, 0.0];
    match check_admissible(&sys, &left).unwrap_err() {
        Error::Inadmissible {
            segment: 0,
            event: Some(EventId(0)),
            violation: Violation::InteriorCrossing,
            t,
            value,
        } => {
            assert_abs_diff_eq!(t, PI, epsilon = 1e-6);
            assert_abs_diff_eq!(value, WALL - 2.0, epsilon = 1e-8);
        }
        other => panic!("expected an interior crossing of the right wall, got {other:?}"),
    }
    // A negative duration is refused too.
    let mut backward = circle(1.0);
    backward.durations[0] = -2.0 * PI;
    assert!(matches!(
        check_admissible(&sys, &backward),
        Err(Error::Inadmissible {
            violation: Violation::Duration,
            ..
        })
    ));
}

/// Continued in $a$ upward, the circles end at a located GR where they touch the walls,
/// $a = w^2$, with no special point past it; the admissibility can be switched off.
#[test]
fn branches_end_where_the_orbits_touch_the_walls() {
    let sys = FiniteDifferences::new(Walled);
    let mut run = OrbitRun::new(&sys, A).unwrap();
    run.bounds(0.5, 3.0);
    let branch = run.run("circles", &circle(1.0), RunDirection::Up).unwrap();
    assert_eq!(
        branch.branch.end,
        EndReason::Inadmissible(SpecialKind::Grazing)
    );
    let gr = branch.first(SpecialKind::Grazing).unwrap();
    assert!(gr.located);
    assert_abs_diff_eq!(gr.point[A], WALL * WALL, epsilon = 1e-8);
    assert!(
        branch
            .branch
            .points
            .iter()
            .all(|p| p[A] <= WALL * WALL + 1e-8)
    );
    // Off: the branch runs on to its bound (through orbits the simulator would not follow).
    run.admissibility(false).unwrap();
    let branch = run.run("circles", &circle(1.0), RunDirection::Up).unwrap();
    assert_eq!(branch.branch.end, EndReason::Bound);
    assert!(branch.first(SpecialKind::Grazing).is_err());
}

/// A start past the walls (a = 4: the circle of radius 2 crosses both) solves the orbit
/// equations, but no simulation follows it: with admissibility on, a run from it and a restart
/// from such a point of a branch computed with admissibility off are refused, by either
/// discretisation, naming the segment and the violation; with admissibility off, the run goes.
#[test]
fn runs_refuse_a_start_past_the_walls() {
    use hycont_continuation::Error as RunError;
    use hycont_core::orbit::{CollocationSettings, OrbitMethod};
    let sys = FiniteDifferences::new(Walled);
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let mut run = OrbitRun::new(&sys, A).unwrap();
        run.method(method).bounds(0.5, 5.0).max_points(20);
        let refused = |r: Result<_, RunError>| match r {
            Err(RunError::InadmissibleStart {
                segment: 0,
                violation,
                value,
                ..
            }) => {
                assert!(
                    matches!(
                        violation,
                        Violation::InteriorCrossing | Violation::EndOutside
                    ),
                    "{violation:?}"
                );
                assert!(value < -0.5, "{value}");
            }
            other => panic!("expected the start refused, got {:?}", other.map(|_| ())),
        };
        refused(run.run("past", &circle(4.0), RunDirection::Up));
        // Inside the walls the same run starts (and ends at the grazing).
        assert!(run.run("inside", &circle(1.0), RunDirection::Up).is_ok());
        // Admissibility off: the branch past the walls is computed ...
        run.admissibility(false).unwrap();
        let off = run.run("past", &circle(4.0), RunDirection::Up).unwrap();
        // Its points are orbits, but not physical ones: the re-check says which.
        assert!(off.check_points(&sys, false).is_ok());
        match off.check_points(&sys, true) {
            Err(RunError::InvalidPoint { reason, .. }) => {
                assert!(reason.contains("not admissible"), "{reason}");
            }
            other => panic!("expected the points refused, got {other:?}"),
        }
        // A point moved off its orbit fails the orbit equations.
        let mut moved = off.clone();
        moved.branch.points[1].u[0] += 1e-3;
        match moved.check_points(&sys, false) {
            Err(RunError::InvalidPoint { reason, .. }) => {
                assert!(reason.contains("do not hold"), "{reason}");
            }
            other => panic!("expected the moved point refused, got {other:?}"),
        }
        let last = off.branch.points.last().unwrap().label;
        assert!(run.restart("again", &off, last, None).is_ok());
        // ... and a run with admissibility on refuses to restart from it.
        run.admissibility(true).unwrap();
        refused(run.restart("again", &off, last, None));
    }
}
