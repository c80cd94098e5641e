//! A user-defined hybrid system: a bouncing ball that comes to rest (Zeno), simulated with the
//! event-driven DOP853 simulator; then the same ball written once for any scalar
//! (`BallModel`, a `HybridModel`), whose exact derivatives by automatic differentiation
//! (`AutoDiff`) are checked against their closed forms, and the same run through it.
//!
//! Run with `cargo run --release --example bouncing_ball`.

use hycont::{
    AutoDiff, Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridModel,
    HybridSystem, Mode, Scalar, SimulationSettings, Simulator,
};

/// Height y and velocity v; y'' = -g; impact at y = 0 with v -> -e v; rest after accumulation.
struct Ball;

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
            action: EventAction::Jump { to: Mode(0) },
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
        out.fill(0.0);
        Some(Mode(1))
    }
}

/// The ball's equations for any scalar (modes and events are `Ball`'s): exact Jacobians by
/// `AutoDiff::new(BallModel)`.
struct BallModel;

impl HybridModel for BallModel {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        Ball.parameter_names()
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        Ball.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        Ball.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        Ball.event_spec(e)
    }
    fn vector_field<T: Scalar>(&self, m: Mode, x: &[T], p: &[T], out: &mut [T]) {
        if m.0 == 0 {
            out[0] = x[1];
            out[1] = -p[0];
        } else {
            out.fill(T::from(0.0));
        }
    }
    fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T {
        x[0]
    }
    fn reset<T: Scalar>(&self, _: EventId, x: &[T], p: &[T], out: &mut [T]) {
        out[0] = x[0];
        out[1] = -p[1] * x[1];
    }
    fn zeno_transition(
        &self,
        m: Mode,
        e: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        Ball.zeno_transition(m, e, x, p, out)
    }
}

fn main() -> Result<(), hycont::Error> {
    let (g, e, v0) = (9.81, 0.8, 3.0);
    let mut sim = Simulator::new(SimulationSettings::default())?;
    let traj = sim.run(&Ball, Mode(0), 0.0, &[0.0, v0], &[g, e], 10.0)?;
    println!(
        "{} impacts; at rest from t = {:.12}",
        traj.events.len(),
        traj.zeno[0].t_accumulation
    );
    println!(
        "closed form: t = 2 v0 / (g (1 - e)) = {:.12}",
        2.0 * v0 / (g * (1.0 - e))
    );
    println!("work: {:?}", traj.stats);
    // Exact derivatives: the impact's reset (y, v) -> (y, -e v) has d/d(y, v) = [[1, 0],
    // [0, -e]] and d/d(g, e) = [[0, 0], [0, -v]]; the flight's field d/dg = (0, -1).
    let exact = AutoDiff::new(BallModel);
    let (x, p) = ([0.0, -2.5], [g, e]);
    let (mut dx, mut dp) = ([0.0; 4], [0.0; 4]);
    exact.reset_jacobian(EventId(0), &x, &p, &mut dx, Some(&mut dp));
    assert_eq!((dx, dp), ([1.0, 0.0, 0.0, -e], [0.0, 0.0, 0.0, 2.5]));
    let mut df = [0.0; 4];
    exact.vector_field_jacobian(Mode(0), &x, &p, &mut [0.0; 4], Some(&mut df));
    assert_eq!(df, [0.0, -1.0, 0.0, 0.0]);
    println!("reset Jacobian (AD): {dx:?} (closed form [1, 0, 0, -e]), parameter columns {dp:?}");
    let again = sim.run(&exact, Mode(0), 0.0, &[0.0, v0], &[g, e], 10.0)?;
    println!(
        "through the AD twin: at rest from t = {:.12}",
        again.zeno[0].t_accumulation
    );
    Ok(())
}
