//! `PeriodicOrbit::from_simulation` takes only tails that are periodic orbits: a simulation
//! stopped by a Zeno accumulation or a terminal event, or one whose jumps end in a Zeno
//! transition, is refused with the reason, not turned into a one-segment "orbit" of a few
//! nanoseconds that the solvers then fail on.
//!
//! The system: a bouncing ball, $\ddot y = -g$, impacts at $y = 0$ with $v \mapsto -ev$. Its
//! bounces shrink geometrically ($v_{k+1} = e v_k$, flight times $2v_k/g$) and accumulate at
//! $t^* = t_0 + 2v_0/(g(1-e))$: no periodic orbit.

use hycont::orbit::PeriodicOrbit;
use hycont::{
    Direction, Error, EventAction, EventId, EventSpec, HybridSystem, Mode, SimulationSettings,
    Simulator, StopReason,
};

#[derive(Clone, Copy, PartialEq)]
enum End {
    /// Jumps accumulate and the simulation stops (no Zeno transition).
    Stop,
    /// Jumps accumulate and the ball rests (a Zeno transition to mode 1).
    Rest,
    /// The first impact is terminal.
    Terminal,
}

struct Ball(End);

impl HybridSystem for Ball {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["g", "e"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        ["flight", "rest"][m.0]
    }
    fn events(&self, m: Mode) -> &[EventId] {
        if m.0 == 0 { &[EventId(0)] } else { &[] }
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "impact",
            direction: Direction::Falling,
            action: if self.0 == End::Terminal {
                EventAction::Terminal
            } else {
                EventAction::Jump { to: Mode(0) }
            },
        }
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        if m.0 == 0 {
            out[0] = x[1];
            out[1] = -p[0];
        } else {
            out.fill(0.0);
        }
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[0]
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = x[0];
        out[1] = -p[1] * x[1];
    }
    fn zeno_transition(
        &self,
        _: Mode,
        _: EventId,
        _: &[f64],
        _: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        (self.0 == End::Rest).then(|| {
            out.fill(0.0);
            Mode(1)
        })
    }
}

fn refusal(end: End) -> (StopReason, String) {
    let ball = Ball(end);
    let p = [9.81, 0.8];
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim.run(&ball, Mode(0), 0.0, &[1.0, 0.0], &p, 20.0).unwrap();
    match PeriodicOrbit::from_simulation(&ball, &traj, &p, 1e-8) {
        Err(Error::NotPeriodic { reason }) => (traj.stop, reason),
        Err(other) => panic!("expected NotPeriodic, got {other}"),
        Ok(orbit) => panic!(
            "accepted an 'orbit' of {} segments lasting {:e}",
            orbit.segment_count(),
            orbit.period()
        ),
    }
}

#[test]
fn a_zeno_accumulation_is_not_a_periodic_orbit() {
    let (stop, reason) = refusal(End::Stop);
    assert!(
        matches!(stop, StopReason::ZenoAccumulation { .. }),
        "{stop:?}"
    );
    assert!(reason.contains("Zeno"), "{reason}");
    // With a transition to rest the simulation runs to its end, but the tail is rest.
    let (stop, reason) = refusal(End::Rest);
    assert_eq!(stop, StopReason::EndReached);
    assert!(reason.contains("Zeno transition"), "{reason}");
}

/// Simulated to just before the accumulation (t* = sqrt(2/g) + 2 e sqrt(2 g) / (g (1 - e))),
/// without reaching the Zeno detector's horizon: the last bounces repeat their states to a
/// loose tolerance, in ever shorter cycles.
#[test]
fn accumulating_jumps_are_not_a_periodic_orbit() {
    let ball = Ball(End::Stop);
    let (g, e) = (9.81_f64, 0.8);
    let t_star = (2.0 / g).sqrt() + 2.0 * e * (2.0 * g).sqrt() / (g * (1.0 - e));
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(&ball, Mode(0), 0.0, &[1.0, 0.0], &[g, e], t_star - 1e-6)
        .unwrap();
    assert_eq!(traj.stop, StopReason::EndReached);
    match PeriodicOrbit::from_simulation(&ball, &traj, &[g, e], 1e-5) {
        Err(Error::NotPeriodic { reason }) => {
            assert!(reason.contains("times the cycle before"), "{reason}");
        }
        other => panic!("expected the accumulation refused, got {other:?}"),
    }
}

#[test]
fn a_terminal_event_is_not_a_periodic_orbit() {
    let (stop, reason) = refusal(End::Terminal);
    assert!(matches!(stop, StopReason::TerminalEvent { .. }), "{stop:?}");
    assert!(reason.contains("terminal"), "{reason}");
}

/// The relay $\dot x = -\operatorname{sign} x$: from $x = 1$ it reaches 0 at $t = 1$, where each
/// side's flow points into the other: the switches accumulate at once (a sliding motion the
/// model has no mode for), and its Zeno transition puts it back on one side at the same
/// instant. The simulator stops with `Error::Stalled` after `MAX_JUMPS_AT_ONE_INSTANT` jumps
/// at $t = 1$ instead of looping to its step limit (or its memory's).
#[test]
fn jumps_without_time_advancing_stall_with_an_error() {
    struct Relay;
    impl HybridSystem for Relay {
        fn state_dim(&self) -> usize {
            1
        }
        fn parameter_names(&self) -> &[&'static str] {
            &[]
        }
        fn mode_count(&self) -> usize {
            2
        }
        fn mode_name(&self, m: Mode) -> &'static str {
            ["positive", "negative"][m.0]
        }
        fn events(&self, m: Mode) -> &[EventId] {
            [&[EventId(0)], &[EventId(1)]][m.0]
        }
        fn event_spec(&self, e: EventId) -> EventSpec {
            EventSpec {
                name: "switch",
                direction: if e.0 == 0 {
                    Direction::Falling
                } else {
                    Direction::Rising
                },
                action: EventAction::Jump { to: Mode(1 - e.0) },
            }
        }
        fn vector_field(&self, m: Mode, _: &[f64], _: &[f64], out: &mut [f64]) {
            out[0] = if m.0 == 0 { -1.0 } else { 1.0 };
        }
        fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
            x[0]
        }
        fn zeno_transition(
            &self,
            _: Mode,
            _: EventId,
            x: &[f64],
            _: &[f64],
            out: &mut [f64],
        ) -> Option<Mode> {
            out.copy_from_slice(x);
            Some(Mode(0))
        }
    }
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    match sim.run(&Relay, Mode(0), 0.0, &[1.0], &[], 5.0) {
        Err(Error::Stalled { jumps, t, .. }) => {
            assert!(jumps > hycont::simulate::MAX_JUMPS_AT_ONE_INSTANT);
            assert!((t - 1.0).abs() < 1e-9, "{t}");
        }
        other => panic!(
            "expected the stall reported, got {:?}",
            other.map(|t| t.stop)
        ),
    }
}
