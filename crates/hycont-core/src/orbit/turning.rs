//! Turning points of an event function along a segment's flow, located on the integrator's
//! dense output (for [`super::Touch::Turn`]).

use super::PeriodicOrbit;
use crate::error::{Error, Result};
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode,
};
use std::cell::RefCell;

/// The critical point of $h_e$ (a minimum of $\sigma h_e$) along segment `k`'s flow nearest
/// `t_ref`, searched over $[0, \max(T_k, t_{ref}) + T_k/4]$ on the integrator's dense output.
pub(super) fn turning_time<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    k: usize,
    e: EventId,
    sigma: f64,
    t_ref: f64,
) -> Result<f64> {
    let mode = orbit.signature.segments()[k].mode;
    let duration = orbit.durations[k].abs();
    let flow = RateFlow {
        system,
        mode,
        event: e,
        sigma,
        scratch: RefCell::new((
            vec![0.0; system.mode_dim(mode)],
            vec![0.0; system.mode_dim(mode)],
        )),
    };
    let t_end = duration.max(t_ref) + 0.25 * duration.max(1e-3);
    let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-12).atol(1e-13))?;
    let traj = sim.run(&flow, Mode(0), 0.0, &orbit.starts[k], &orbit.params, t_end)?;
    traj.events
        .iter()
        .map(|r| r.t)
        .min_by(|a, b| (a - t_ref).abs().total_cmp(&(b - t_ref).abs()))
        .ok_or_else(|| Error::InvalidMeasure {
            reason: format!(
                "touch of {e}: the flow of segment {k} does not turn back towards its surface \
                 within t in [0, {t_end}]"
            ),
        })
}

/// A segment's mode with one event: the rate $\sigma \dot h_e$ rising through zero (a minimum
/// of $\sigma h_e$), recorded by an identity jump.
struct RateFlow<'a, S: ?Sized> {
    system: &'a S,
    mode: Mode,
    event: EventId,
    sigma: f64,
    scratch: RefCell<(Vec<f64>, Vec<f64>)>,
}

const TURN: [EventId; 1] = [EventId(0)];

impl<S: HybridJacobians + ?Sized> HybridSystem for RateFlow<'_, S> {
    fn state_dim(&self) -> usize {
        self.system.mode_dim(self.mode)
    }
    fn parameter_names(&self) -> &[&'static str] {
        self.system.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        self.system.mode_name(self.mode)
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &TURN
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "turning point",
            direction: Direction::Rising,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.system.vector_field(self.mode, x, p, out);
    }
    fn event(&self, _: EventId, x: &[f64], p: &[f64]) -> f64 {
        let mut s = self.scratch.borrow_mut();
        let (g, f) = &mut *s;
        self.system.event_gradient(self.event, x, p, g, None);
        self.system.vector_field(self.mode, x, p, f);
        self.sigma * g.iter().zip(f.iter()).map(|(a, b)| a * b).sum::<f64>()
    }
}
