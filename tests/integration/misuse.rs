//! Ordinary mistakes through the public API give typed errors naming the bad value, never a
//! panic and never a wrong answer as success (the bouncing ball on a vibrating table,
//! `examples/vibrating_table/model.rs`).
//!
//! The signature of a period-1 orbit is [flight to the phase wrap, flight to the impact]: the
//! phase $\theta$ grows by $\omega T = 2\pi$ per period and the wrap takes $2\pi$ off it. A
//! signature without the wrap cannot close ($\theta$ would have to return to itself after
//! growing by $2\pi$), and one with an extra impact asks for a second impact within the same
//! forcing period that the period-1 flow does not have.

use crate::model_vibrating_table as model;

use hycont::hycont_continuation::{Error as ContError, OrbitRun, RunDirection};
use hycont::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
use hycont::{Error, SimulationSettings};
use model::{A, FLIGHT, IMPACT, Table, WRAP};

const E: f64 = 0.5;
const G: f64 = 1.0;

/// The post-impact state of the stable period-1 orbit at amplitude `a`, `omega = 1` (closed
/// form of `tests/integration/vibrating_table.rs`).
fn post_impact(a: f64) -> [f64; 3] {
    let omega: f64 = 1.0;
    let a_fold = std::f64::consts::PI * G * (1.0 - E) / ((1.0 + E) * omega * omega);
    let theta0 = (a_fold / a).acos();
    let w_plus = E * G * 2.0 * std::f64::consts::PI / omega / (1.0 + E);
    [0.0, w_plus, theta0]
}

fn signature(ends: &[hycont::EventId]) -> Signature {
    Signature::new(
        &Table,
        ends.iter()
            .map(|&e| SegmentSpec {
                mode: FLIGHT,
                end: SegmentEnd::Event(e),
            })
            .collect(),
    )
    .unwrap()
}

fn follow(ends: &[hycont::EventId]) -> hycont::Result<PeriodicOrbit> {
    PeriodicOrbit::from_initial_state(
        &Table,
        signature(ends),
        &post_impact(1.3),
        &[1.3, 1.0, E, G],
        20.0,
        &SimulationSettings::default(),
    )
}

#[test]
fn the_right_signature_is_followed() {
    let orbit = follow(&[WRAP, IMPACT]).unwrap();
    approx::assert_abs_diff_eq!(orbit.period(), 2.0 * std::f64::consts::PI, epsilon = 1e-6);
}

/// A missing wrap segment: the flow to the impact meets the wrap first.
#[test]
fn a_signature_missing_a_segment_is_refused_with_the_reason() {
    let err = follow(&[IMPACT]).unwrap_err();
    let Error::InvalidSignature { segment, reason } = &err else {
        panic!("{err:?}")
    };
    assert_eq!(*segment, 0);
    assert!(
        reason.contains("wrap") && reason.contains("misses a segment"),
        "{reason}"
    );
}

/// An extra impact segment: after the impact the flow meets the wrap before another impact.
#[test]
fn a_signature_with_an_extra_segment_is_refused_with_the_reason() {
    let err = follow(&[WRAP, IMPACT, IMPACT]).unwrap_err();
    let Error::InvalidSignature { segment, reason } = &err else {
        panic!("{err:?}")
    };
    assert_eq!(*segment, 2);
    assert!(reason.contains("wrap"), "{reason}");
}

/// A continuation direction of zero is neither way: refused, naming the setting.
#[test]
fn a_zero_direction_is_refused() {
    use hycont::hycont_continuation::{ContinuationSettings, continue_branch};
    let fd = hycont::FiniteDifferences::new(Table);
    let run = OrbitRun::new(&fd, A).unwrap();
    let guess = follow(&[WRAP, IMPACT]).unwrap();
    let (mut problem, u0) = run.problem(&guess).unwrap();
    for direction in [0.0, f64::NAN, f64::INFINITY] {
        let err = continue_branch(
            &mut problem,
            "b",
            &u0,
            direction,
            &ContinuationSettings::default(),
            &mut hycont::hycont_continuation::observe::Silent,
        )
        .unwrap_err();
        assert!(
            matches!(
                err,
                ContError::InvalidSetting {
                    name: "direction",
                    ..
                }
            ),
            "{err:?}"
        );
    }
}

/// A start that Newton cannot correct says how many iterations it tried, not "after 0".
#[test]
fn a_failed_start_reports_its_iterations() {
    let fd = hycont::FiniteDifferences::new(Table);
    let mut run = OrbitRun::new(&fd, A).unwrap();
    run.bounds(0.9, 1.8).max_points(5);
    let mut guess = follow(&[WRAP, IMPACT]).unwrap();
    guess.durations[0] = 0.05;
    guess.durations[1] = 0.05;
    let err = run.run("b", &guess, RunDirection::Up).unwrap_err();
    let text = err.to_string();
    assert!(!text.contains("after 0 iterations"), "{text}");
    assert!(
        text.contains("did not converge in") && text.contains("iterations"),
        "{text}"
    );
}

/// A user measure whose exact gradient has too few entries is a typed error naming it, not a
/// panic in the two-parameter curves that use gradients.
#[test]
fn a_measure_gradient_of_the_wrong_length_is_refused() {
    use hycont::orbit::{Measure, MeasureSet, OrbitScan};
    struct Short;
    impl<S: ?Sized> Measure<S> for Short {
        fn value(&self, _: &S, orbit: &PeriodicOrbit, _: &OrbitScan) -> hycont::Result<f64> {
            Ok(orbit.period())
        }
        fn gradient(&self, _: &S, _: &PeriodicOrbit, _: &OrbitScan) -> Option<Vec<f64>> {
            Some(vec![1.0; 2])
        }
    }
    let fd = hycont::FiniteDifferences::new(Table);
    let orbit = follow(&[WRAP, IMPACT]).unwrap();
    let mut set = MeasureSet::new();
    set.add("short", Short).unwrap();
    let err = set.evaluate_with_gradient(&fd, &orbit, 0).unwrap_err();
    assert!(
        matches!(&err, Error::InvalidMeasure { reason } if reason.contains("\"short\"") && reason.contains("2 entries")),
        "{err}"
    );
}

/// Monitors of a problem by handle: a handle of another problem is a typed error.
#[test]
fn a_monitor_handle_out_of_range_is_refused() {
    use hycont::problem::{Activity, MonitorId, Problem, UnknownMonitor};
    let mut problem = Problem::new(1);
    let m = problem
        .add_monitor(
            "x",
            Box::new(UnknownMonitor),
            vec![0],
            Activity::Inactive(1.0),
        )
        .unwrap();
    assert!(problem.activity(m).is_ok());
    let other = MonitorId(3);
    for err in [
        problem.activity(other).unwrap_err(),
        problem
            .set_activity(other, Activity::Active(1.0))
            .unwrap_err(),
        problem.monitor_value(other, &[1.0]).unwrap_err(),
    ] {
        assert!(
            matches!(
                err,
                Error::IndexOutOfRange {
                    what: "monitor",
                    index: 3,
                    count: 1
                }
            ),
            "{err}"
        );
    }
    assert!(matches!(
        problem.set_activity(m, Activity::Inactive(f64::NAN)),
        Err(Error::NonFinite { .. })
    ));
}

/// Two-parameter curve conditions naming a measure or a segment the problem does not have, or
/// a non-finite level, are typed errors.
#[test]
fn curve_conditions_out_of_range_are_refused() {
    use hycont::hycont_continuation::MeasureId;
    use hycont::hycont_continuation::codim2::{Codim2, CurveCondition};
    let fd = hycont::FiniteDifferences::new(Table);
    let run = OrbitRun::new(&fd, A).unwrap();
    let orbit = follow(&[WRAP, IMPACT]).unwrap();
    let (problem, _) = run.problem(&orbit).unwrap();
    for condition in [
        CurveCondition::Collapse { segment: 9 },
        CurveCondition::Measure {
            measure: MeasureId::new(99),
            level: 0.0,
        },
        CurveCondition::Measure {
            measure: MeasureId::new(2),
            level: f64::NAN,
        },
    ] {
        let Err(err) = Codim2::new(
            &fd,
            &orbit,
            problem.discretisation(),
            A,
            model::OMEGA,
            condition,
            problem.measures().clone(),
            Vec::new(),
        ) else {
            panic!("{condition:?} accepted")
        };
        assert!(
            matches!(
                err,
                ContError::InvalidSetting { .. } | ContError::NoSuchQuantity { .. }
            ),
            "{condition:?}: {err}"
        );
    }
}

/// Guesses whose signature does not fit the flow (a segment missing, one too many) are refused
/// by the solver, never returned as an orbit with a zero duration or a phase running away; a
/// swapped signature gives the same orbit started elsewhere or an error, never a negative
/// duration.
#[test]
fn solves_that_leave_the_signature_are_refused() {
    use hycont::orbit::{ShootingSettings, solve_shooting};
    use hycont::problem::NewtonSettings;
    let fd = hycont::FiniteDifferences::new(Table);
    let newton = NewtonSettings::default();
    let good = solve_shooting(
        &fd,
        &follow(&[WRAP, IMPACT]).unwrap(),
        ShootingSettings::default(),
        &newton,
    )
    .unwrap()
    .orbit;
    let build = |ends: &[hycont::EventId], starts: Vec<Vec<f64>>, durations: Vec<f64>| {
        PeriodicOrbit::new(
            &Table,
            signature(ends),
            starts,
            durations,
            good.params.clone(),
        )
        .unwrap()
    };
    // Swapped: the solver may find the same orbit started elsewhere (a valid answer: positive
    // durations, period 2 pi), never a negative duration.
    let swapped = build(&[IMPACT, WRAP], good.starts.clone(), good.durations.clone());
    if let Ok(sol) = solve_shooting(&fd, &swapped, ShootingSettings::default(), &newton) {
        assert!(
            sol.orbit.durations.iter().all(|d| *d > 0.0),
            "{:?}",
            sol.orbit.durations
        );
        approx::assert_abs_diff_eq!(sol.orbit.period(), good.period(), epsilon = 1e-8);
    }
    let missing = build(&[IMPACT], vec![good.starts[0].clone()], vec![good.period()]);
    let mut starts = good.starts.clone();
    starts.push(good.starts[0].clone());
    let mut durations = good.durations.clone();
    durations.push(1e-3);
    let extra = build(&[WRAP, IMPACT, IMPACT], starts, durations);
    for (name, guess) in [("missing", missing), ("extra", extra)] {
        match solve_shooting(&fd, &guess, ShootingSettings::default(), &newton) {
            Ok(sol) => panic!("{name}: accepted {:?}", sol.orbit.durations),
            Err(e) => assert!(
                matches!(
                    e,
                    Error::Inadmissible { .. }
                        | Error::NewtonFailed { .. }
                        | Error::InvalidSignature { .. }
                ),
                "{name}: {e}"
            ),
        }
    }
}
