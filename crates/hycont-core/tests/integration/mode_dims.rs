//! Modes with states of their own dimension ([`HybridSystem::mode_dim`]) in the simulator.
//!
//! The shuttle: in mode A (one state, x' = 1) x climbs from 0 to 1, where event UP
//! (h = 1 - x, falling) jumps into mode B with the state (x) -> (x, -v0); in mode B (two
//! states, x' = y, y' = a) x falls back, x(t) = 1 - v0 t + a t^2 / 2, to 0, where event DOWN
//! (h = x, falling) jumps back into A with (x, y) -> (x). Closed form: A lasts 1, B lasts
//! t_B = (v0 - sqrt(v0^2 - 2 a)) / a (the first root of x(t) = 0) and ends with
//! y = -sqrt(v0^2 - 2 a); the motion repeats with period 1 + t_B.

use crate::common;

use approx::assert_abs_diff_eq;
use hycont_core::orbit::{SegmentEnd, SegmentSpec, Signature};
use hycont_core::{
    Direction, Error, EventAction, EventId, EventSpec, HybridSystem, Mode, SampleTimes,
    Sensitivities, SimulationSettings, Simulator, check_mode_dims, uniform_dims,
};

use common::shuttle::{A, B, DOWN, P, Shuttle, UP};

fn fall_time() -> f64 {
    let [v0, a] = P;
    (v0 - (v0 * v0 - 2.0 * a).sqrt()) / a
}

/// Three periods from x = 0 in A: six jumps alternating between the modes at the closed
/// form's times (1e-9), the states before and after each of their modes' sizes, samples in A
/// of one component and in B of two on the closed form (1e-9), every recorded step of its
/// mode's size, and the run ending in A at x = 0.5 of the fourth climb.
#[test]
fn the_simulator_follows_a_system_across_its_modes_dimensions() {
    let system = Shuttle::default();
    assert!(!uniform_dims(&system));
    check_mode_dims(&system).unwrap();
    let t_b = fall_time();
    let period = 1.0 + t_b;
    let settings = SimulationSettings::default()
        .rtol(1e-12)
        .atol(1e-13)
        .record_steps(true)
        .samples(SampleTimes::new(0.5, period / 2.0));
    let mut sim = Simulator::new(settings).unwrap();
    let end = 3.0 * period + 0.5;
    let traj = sim.run(&system, A, 0.0, &[0.0], &P, end).unwrap();
    assert_eq!(traj.events.len(), 6);
    for (i, e) in traj.events.iter().enumerate() {
        let k = (i / 2) as f64;
        let (t, from, to) = if i % 2 == 0 {
            (k * period + 1.0, A, B)
        } else {
            ((k + 1.0) * period, B, A)
        };
        assert_abs_diff_eq!(e.t, t, epsilon = 1e-9);
        assert_eq!((e.mode_before, e.mode_after), (from, Some(to)));
        assert_eq!(e.state_before.len(), system.mode_dim(from));
        assert_eq!(e.state_after.len(), system.mode_dim(to));
        if to == A {
            let y = -(P[0] * P[0] - 2.0 * P[1]).sqrt();
            assert_abs_diff_eq!(e.state_before[1], y, epsilon = 1e-9);
        }
    }
    let [v0, a] = P;
    for (t, mode, x) in traj.samples.iter() {
        let s = t % period;
        assert_eq!(x.len(), system.mode_dim(mode), "t = {t}");
        if s < 1.0 {
            assert_eq!(mode, A);
            assert_abs_diff_eq!(x[0], s, epsilon = 1e-9);
        } else {
            let u = s - 1.0;
            assert_eq!(mode, B);
            assert_abs_diff_eq!(x[0], 1.0 - v0 * u + 0.5 * a * u * u, epsilon = 1e-9);
            assert_abs_diff_eq!(x[1], -v0 + a * u, epsilon = 1e-9);
        }
    }
    assert!(traj.samples.len() >= 7);
    assert!(!traj.steps.uniform());
    assert!(
        traj.steps
            .iter()
            .all(|(_, m, x)| x.len() == system.mode_dim(m))
    );
    assert_eq!(traj.mode_final, A);
    assert_eq!(traj.state_final.len(), 1);
    assert_abs_diff_eq!(traj.state_final[0], 0.5, epsilon = 1e-9);
    assert!(traj.stats.steps > 6);
}

/// A start in B takes B's two states; the wrong number is a dimension error.
#[test]
fn a_start_has_its_modes_dimension() {
    let system = Shuttle::default();
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim.run(&system, B, 0.0, &[1.0, -P[0]], &P, 0.5).unwrap();
    assert_eq!(traj.state_final.len(), 2);
    let e = sim.run(&system, B, 0.0, &[1.0], &P, 0.5).unwrap_err();
    assert!(
        matches!(
            e,
            Error::DimensionMismatch {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{e}"
    );
}

/// What does not support modes of their own dimension yet says so with a typed error naming
/// the dimensions: sensitivities across a jump between dimensions; an event watched in modes
/// of two dimensions is refused naming the event and the modes. Periodic orbits take them
/// (tests/integration/mode_dim_orbits.rs).
#[test]
fn what_does_not_support_them_refuses_them() {
    let system = Shuttle::default();
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let e = sim
        .run_with_sensitivities(&system, A, 0.0, &[0.0], &P, 0.5, Sensitivities::State)
        .unwrap_err();
    assert!(
        matches!(&e, Error::InvalidSystem { reason } if reason.contains("mode #0: 1, mode #1: 2")),
        "{e}"
    );
    let segments = vec![
        SegmentSpec {
            mode: A,
            end: SegmentEnd::Event(UP),
        },
        SegmentSpec {
            mode: B,
            end: SegmentEnd::Event(DOWN),
        },
    ];
    Signature::new(&system, segments.clone()).unwrap();
    let clash = Shuttle {
        clash: true,
        ..Shuttle::default()
    };
    let e = sim.run(&clash, A, 0.0, &[0.0], &P, 0.5).unwrap_err();
    assert!(
        matches!(&e, Error::InvalidSystem { reason } if reason.contains("event #0") && reason.contains("mode #1 (2 states)")),
        "{e}"
    );
    let e = Signature::new(&clash, segments).unwrap_err();
    assert!(matches!(e, Error::InvalidSystem { .. }), "{e}");
}

/// A ball on the floor (height, velocity: h'' = -1, impacts v -> -e v) whose impacts
/// accumulate comes to rest in a mode of one state (the time at rest, s' = 1): a Zeno
/// transition into a mode of another dimension.
struct Settling;

const FLY: Mode = Mode(0);
const REST: Mode = Mode(1);
const E: f64 = 0.5;

impl HybridSystem for Settling {
    fn state_dim(&self) -> usize {
        2
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        if mode == FLY { 2 } else { 1 }
    }
    fn parameter_names(&self) -> &[&'static str] {
        &[]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        if mode == FLY { "flight" } else { "rest" }
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        if mode == FLY { &[UP] } else { &[] }
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "floor",
            direction: Direction::Falling,
            action: EventAction::Jump { to: FLY },
        }
    }
    fn vector_field(&self, mode: Mode, x: &[f64], _: &[f64], f: &mut [f64]) {
        if mode == FLY {
            f[0] = x[1];
            f[1] = -1.0;
        } else {
            f[0] = 1.0;
        }
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[0]
    }
    fn reset(&self, _: EventId, x: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = x[0];
        out[1] = -E * x[1];
    }
    fn zeno_transition(
        &self,
        _: Mode,
        _: EventId,
        _: &[f64],
        _: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        out[0] = 0.0;
        Some(REST)
    }
}

/// Dropped from h = 1/2 with g = 1: the first impact at t1 = 1 with speed 1, then flights of
/// 2 e^k, accumulating at t1 + 2 e / (1 - e) = 3; the run goes on at rest with one state, the
/// time at rest, which is t_end - 3 at the end (to the accumulation's estimate, 1e-6).
#[test]
fn impacts_that_accumulate_come_to_rest_in_a_mode_of_fewer_states() {
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let mut sim = Simulator::new(settings).unwrap();
    let traj = sim.run(&Settling, FLY, 0.0, &[0.5, 0.0], &[], 4.0).unwrap();
    assert_eq!(traj.zeno.len(), 1);
    let z = &traj.zeno[0];
    assert_eq!((z.mode_after, z.state_after.len()), (REST, 1));
    assert_abs_diff_eq!(z.t_accumulation, 3.0, epsilon = 1e-6);
    assert_eq!(traj.mode_final, REST);
    assert_eq!(traj.state_final.len(), 1);
    assert_abs_diff_eq!(traj.state_final[0], 4.0 - 3.0, epsilon = 1e-6);
}

/// A reset into a mode of more states that writes only some of them: the jump is an error
/// naming the component left unwritten, not a state with a stale value in it.
#[test]
fn a_reset_that_leaves_a_component_unwritten_is_an_error() {
    struct Forgetful;
    impl HybridSystem for Forgetful {
        fn state_dim(&self) -> usize {
            2
        }
        fn mode_dim(&self, mode: Mode) -> usize {
            Shuttle::default().mode_dim(mode)
        }
        fn parameter_names(&self) -> &[&'static str] {
            &["v0", "a"]
        }
        fn mode_count(&self) -> usize {
            2
        }
        fn mode_name(&self, mode: Mode) -> &'static str {
            Shuttle::default().mode_name(mode)
        }
        fn events(&self, mode: Mode) -> &[EventId] {
            if mode == A { &[UP] } else { &[DOWN] }
        }
        fn event_spec(&self, e: EventId) -> EventSpec {
            Shuttle::default().event_spec(e)
        }
        fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
            Shuttle::default().vector_field(mode, x, p, f);
        }
        fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
            Shuttle::default().event(e, x, p)
        }
        // The default reset: the identity on the one component both modes have.
    }
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let e = sim.run(&Forgetful, A, 0.0, &[0.0], &P, 2.0).unwrap_err();
    assert!(
        matches!(&e, Error::NonFiniteReset { event, index: 1, value, .. } if *event == UP && value.is_nan()),
        "{e}"
    );
}
