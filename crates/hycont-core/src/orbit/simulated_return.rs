//! An independent check of a located orbit: the event-driven simulator, started on the orbit,
//! finds the impacts on its own and should come back to where it started one period later.

use super::PeriodicOrbit;
use super::signature::Closure;
use crate::error::{Error, Result};
use crate::simulate::{SampleTimes, SimulationSettings, Simulator};
use crate::system::HybridSystem;
use serde::{Deserialize, Serialize};

/// How a periodic orbit's own simulation returns ([`PeriodicOrbit::simulated_return`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct SimulatedReturn {
    /// The max-norm distance between the state half-way through the first segment and the
    /// simulated state one period later.
    pub gap: f64,
    /// The events the simulator met in that period, by its own event detection (for an orbit
    /// of the signature it was located in: one per segment ending at an event).
    pub events: usize,
}

impl PeriodicOrbit {
    /// Simulates the orbit for one period from the middle of its first segment (away from its
    /// jumps) with `settings`' tolerances, and reports how far it lands from where it
    /// started and how many events it met: an independent check of an orbit located by
    /// shooting or collocation (its own event detection, its own integrator steps). Near a
    /// grazing the return is ill-conditioned (the time of an impact of small speed moves
    /// with the rounding of its approach), so the gap there is larger than the tolerances.
    ///
    /// ```
    /// # use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridSystem, Mode};
    /// use hycont_core::SimulationSettings;
    /// use hycont_core::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
    /// # /// x' = v, v' = -x; a wall at x = 1 (1 - x falls through 0) with v -> -v.
    /// # struct Wall;
    /// # impl HybridSystem for Wall {
    /// #     fn state_dim(&self) -> usize { 2 }
    /// #     fn parameter_names(&self) -> &[&'static str] { &[] }
    /// #     fn mode_count(&self) -> usize { 1 }
    /// #     fn mode_name(&self, _: Mode) -> &'static str { "free" }
    /// #     fn events(&self, _: Mode) -> &[EventId] { &[EventId(0)] }
    /// #     fn event_spec(&self, _: EventId) -> EventSpec {
    /// #         EventSpec { name: "wall", direction: Direction::Falling, action: EventAction::Jump { to: Mode(0) } }
    /// #     }
    /// #     fn vector_field(&self, _: Mode, x: &[f64], _: &[f64], f: &mut [f64]) { f[0] = x[1]; f[1] = -x[0]; }
    /// #     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { 1.0 - x[0] }
    /// #     fn reset(&self, _: EventId, x: &[f64], _: &[f64], out: &mut [f64]) { out[0] = x[0]; out[1] = -x[1]; }
    /// # }
    /// // The elastic wall at x = 1 cuts the circle x^2 + v^2 = 4: the impact turns v = sqrt 3
    /// // into -sqrt 3, and the flow takes 4 pi / 3 round the circle back to the wall.
    /// let impact = SegmentSpec { mode: Mode(0), end: SegmentEnd::Event(EventId(0)) };
    /// let sig = Signature::new(&Wall, vec![impact]).unwrap();
    /// let start = vec![1.0, -3f64.sqrt()];
    /// let duration = 4.0 * std::f64::consts::PI / 3.0;
    /// let orbit = PeriodicOrbit::new(&Wall, sig, vec![start], vec![duration], vec![]).unwrap();
    /// let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    /// let back = orbit.simulated_return(&Wall, &settings).unwrap();
    /// assert!(back.gap < 1e-9 && back.events == 1);
    /// ```
    ///
    /// # Errors
    /// A half orbit ([`Closure::Symmetric`]: unfold it first,
    /// [`PeriodicOrbit::unfold_symmetric`]), an orbit that does not fit the system, invalid
    /// settings, integration failures; [`Error::NotPeriodic`] where the simulation stops
    /// before the period is over (a terminal event, Zeno accumulation, the step limit).
    pub fn simulated_return<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        settings: &SimulationSettings,
    ) -> Result<SimulatedReturn> {
        self.validate(system)?;
        if self.signature.closure() == Closure::Symmetric {
            return Err(Error::InvalidSignature {
                segment: 0,
                reason: "a half orbit returns only through its symmetry: unfold it first".into(),
            });
        }
        let period = self.period();
        let t0 = 0.5 * self.durations[0];
        let settings = settings
            .clone()
            .record_events(true)
            .samples(SampleTimes::new(t0, period));
        let mut sim = Simulator::new(settings)?;
        let mode = self.signature.segments()[0].mode;
        // A hair past the second sample, so that it is taken.
        let end = t0 + period * (1.0 + 1e-6);
        let traj = sim.run(system, mode, 0.0, &self.starts[0], &self.params, end)?;
        if traj.samples.len() < 2 {
            return Err(Error::NotPeriodic {
                reason: format!(
                    "the simulation of one period stopped early ({:?})",
                    traj.stop
                ),
            });
        }
        let gap = traj
            .samples
            .state(0)
            .iter()
            .zip(traj.samples.state(1))
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let events = traj
            .events
            .iter()
            .filter(|e| e.t > t0 && e.t <= t0 + period)
            .count();
        Ok(SimulatedReturn { gap, events })
    }
}
