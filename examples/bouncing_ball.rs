//! A user-defined hybrid system: a bouncing ball that comes to rest (Zeno), simulated with the
//! event-driven DOP853 simulator.
//!
//! Run with `cargo run --release --example bouncing_ball`.

use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridSystem, Mode, SimulationSettings, Simulator,
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
    Ok(())
}
