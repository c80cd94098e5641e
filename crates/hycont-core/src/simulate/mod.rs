//! Event-driven simulation of hybrid systems.
//!
//! [`Simulator`] integrates a [`HybridSystem`] with the [`Dop853`] stepper, locates events on the
//! dense output, applies resets, switches modes, detects Zeno accumulation, samples the state at
//! prescribed times and optionally integrates the variational equations (with saltation matrices
//! at jumps). See [`SimulationSettings`] for the knobs and [`Trajectory`] for the result.

mod conditioning;
mod dop853;
mod events;
mod settings;
mod stepping;
mod tableau;
mod trajectory;
mod variational;
mod zeno;

pub use conditioning::EventConditioning;
pub use dop853::{Dop853, NonFiniteEvaluation, StepperStats};
pub use settings::{ParamSet, SampleTimes, Sensitivities, SimulationSettings, ZenoSettings};
pub use stepping::MAX_JUMPS_AT_ONE_INSTANT;
pub use trajectory::{
    EventRecord, SensitivityMatrices, SimulationStats, StopReason, TimeSeries, Trajectory,
    ZenoRecord,
};

use crate::error::{Error, Result, check_finite, check_len};
use crate::system::{EventAction, EventId, HybridJacobians, HybridSystem, Mode, ParamId};
use events::EventState;
use stepping::Records;
use variational::{Extension, Plain, Variational};

/// The event-driven simulator. Holds its work space, so that repeated runs do not allocate per
/// step (and reuse buffers across runs of the same dimension).
///
/// # Example: a bouncing ball coming to rest
/// ```
/// use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridSystem, Mode,
///                   SimulationSettings, Simulator, StopReason};
///
/// struct Ball;
/// impl HybridSystem for Ball {
///     fn state_dim(&self) -> usize { 2 }
///     fn parameter_names(&self) -> &[&'static str] { &["g", "e"] }
///     fn mode_count(&self) -> usize { 2 }
///     fn mode_name(&self, m: Mode) -> &'static str { ["flight", "rest"][m.0] }
///     fn events(&self, m: Mode) -> &[EventId] { if m.0 == 0 { &[EventId(0)] } else { &[] } }
///     fn event_spec(&self, _: EventId) -> EventSpec {
///         EventSpec { name: "impact", direction: Direction::Falling,
///                     action: EventAction::Jump { to: Mode(0) } }
///     }
///     fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
///         if m.0 == 0 { out[0] = x[1]; out[1] = -p[0]; } else { out.fill(0.0); }
///     }
///     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { x[0] }
///     fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
///         out[0] = x[0];
///         out[1] = -p[1] * x[1];
///     }
///     fn zeno_transition(&self, _: Mode, _: EventId, _: &[f64], _: &[f64], out: &mut [f64])
///         -> Option<Mode> { out.fill(0.0); Some(Mode(1)) }
/// }
///
/// let (g, e, v0) = (9.81, 0.5, 1.0);
/// let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
/// let traj = sim.run(&Ball, Mode(0), 0.0, &[0.0, v0], &[g, e], 5.0).unwrap();
/// assert_eq!(traj.stop, StopReason::EndReached);
/// // Flights 2 v0 e^k / g accumulate at t = 2 v0 / (g (1 - e)).
/// let t_rest = 2.0 * v0 / (g * (1.0 - e));
/// assert!((traj.zeno[0].t_accumulation - t_rest).abs() < 1e-9);
/// ```
#[derive(Debug, Clone)]
pub struct Simulator {
    settings: SimulationSettings,
    stepper: Dop853,
    /// Steppers of the other dimensions used lately (state alone, with sensitivities), kept
    /// so that alternating runs do not allocate.
    spare: Vec<Dop853>,
    /// The variational extension of the last run with sensitivities, kept for its work space.
    variational: Option<Variational>,
    y0: Vec<f64>,
    y_minus: Vec<f64>,
    y_plus: Vec<f64>,
    x_probe: Vec<f64>,
    zeno_out: Vec<f64>,
    events: Vec<EventState>,
    /// The first step of the next run, set by [`Simulator::resume`].
    resume_step: Option<f64>,
}

impl Simulator {
    /// A simulator with the given settings.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if the settings are invalid.
    pub fn new(settings: SimulationSettings) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            stepper: Dop853::new(0),
            spare: Vec::new(),
            variational: None,
            y0: Vec::new(),
            y_minus: Vec::new(),
            y_plus: Vec::new(),
            x_probe: Vec::new(),
            zeno_out: Vec::new(),
            events: Vec::new(),
            resume_step: None,
        })
    }

    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// Simulates `system` from state `x0` in `mode` at time `t0` until `t_end` (or a terminal
    /// event, an unresolved Zeno accumulation, or the step limit).
    ///
    /// # Errors
    /// Wrong dimensions, non-finite inputs, `t_end < t0`, an invalid mode, a vector field that
    /// returns a non-finite value (the error says when and where), or a step-size underflow.
    pub fn run<S: HybridSystem + ?Sized>(
        &mut self,
        system: &S,
        mode: Mode,
        t0: f64,
        x0: &[f64],
        p: &[f64],
        t_end: f64,
    ) -> Result<Trajectory> {
        let n = if mode.0 < system.mode_count() {
            system.mode_dim(mode)
        } else {
            system.state_dim()
        };
        let mut ext = Plain { n };
        self.run_impl(
            system,
            &mut ext,
            mode,
            t0,
            x0,
            p,
            t_end,
            Sensitivities::None,
        )
    }

    /// Continues the run that ended in `from` (at its final time, in its final mode, from its
    /// final state) until `t_end`, starting with the step size it proposed last
    /// ([`Trajectory::next_step`]) rather than a new estimate: a long simulation split into
    /// pieces (e.g. to look at the state between them) then costs about what it costs in one
    /// piece.
    ///
    /// # Errors
    /// As [`Simulator::run`].
    ///
    /// ```
    /// # use hycont_core::{EventId, EventSpec, HybridSystem, Mode, SimulationSettings, Simulator};
    /// // x' = -x, no events.
    /// struct Decay;
    /// impl HybridSystem for Decay {
    ///     fn state_dim(&self) -> usize { 1 }
    ///     fn parameter_names(&self) -> &[&'static str] { &[] }
    ///     fn mode_count(&self) -> usize { 1 }
    ///     fn mode_name(&self, _: Mode) -> &'static str { "decay" }
    ///     fn events(&self, _: Mode) -> &[EventId] { &[] }
    ///     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!("no events") }
    ///     fn vector_field(&self, _: Mode, x: &[f64], _: &[f64], out: &mut [f64]) {
    ///         out[0] = -x[0];
    ///     }
    ///     fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 { unreachable!("no events") }
    /// }
    /// let mut sim = Simulator::new(SimulationSettings::default())?;
    /// let first = sim.run(&Decay, Mode(0), 0.0, &[1.0], &[], 1.0)?;
    /// let second = sim.resume(&Decay, &first, &[], 2.0)?;
    /// assert!((second.state_final[0] - (-2.0f64).exp()).abs() < 1e-8);
    /// # Ok::<(), hycont_core::Error>(())
    /// ```
    pub fn resume<S: HybridSystem + ?Sized>(
        &mut self,
        system: &S,
        from: &Trajectory,
        p: &[f64],
        t_end: f64,
    ) -> Result<Trajectory> {
        self.resume_step =
            (from.next_step > 0.0 && from.next_step.is_finite()).then_some(from.next_step);
        let run = self.run(
            system,
            from.mode_final,
            from.t_final,
            &from.state_final,
            p,
            t_end,
        );
        self.resume_step = None;
        run
    }

    /// Like [`Simulator::run`], integrating the variational equations as well; the trajectory's
    /// `sensitivities` then hold $\partial x(t_f)/\partial x_0$ (and $\partial x(t_f)/\partial p$),
    /// saltation matrices included.
    ///
    /// # Errors
    /// As [`Simulator::run`], [`Error::InvalidTransition`] when an event is crossed
    /// tangentially (the saltation matrix is undefined at grazing), and
    /// [`Error::InvalidSystem`] for a system whose modes have states of different dimensions
    /// (their sensitivities are not carried across them yet).
    #[allow(clippy::too_many_arguments)]
    pub fn run_with_sensitivities<S: HybridJacobians + ?Sized>(
        &mut self,
        system: &S,
        mode: Mode,
        t0: f64,
        x0: &[f64],
        p: &[f64],
        t_end: f64,
        which: Sensitivities,
    ) -> Result<Trajectory> {
        let (n, np) = (system.state_dim(), system.parameter_count());
        match which {
            Sensitivities::None => self.run(system, mode, t0, x0, p, t_end),
            Sensitivities::State
            | Sensitivities::StateAndParameters
            | Sensitivities::StateAndSomeParameters(_) => {
                crate::system::require_uniform_dims(system, "a run with sensitivities")?;
                let selected = (0..np)
                    .filter(|&q| which.includes_parameter(q))
                    .map(ParamId);
                let mut ext = match self.variational.take() {
                    Some(mut v) if v.fits(n, np) => {
                        v.select(selected);
                        v
                    }
                    _ => Variational::new(n, np, selected.collect()),
                };
                let out = self.run_impl(system, &mut ext, mode, t0, x0, p, t_end, which);
                self.variational = Some(ext);
                out
            }
        }
    }

    fn validate_inputs<S: HybridSystem + ?Sized>(
        system: &S,
        mode: Mode,
        t0: f64,
        x0: &[f64],
        p: &[f64],
        t_end: f64,
    ) -> Result<()> {
        if mode.0 >= system.mode_count() {
            return Err(Error::InvalidMode {
                mode,
                count: system.mode_count(),
            });
        }
        if system.state_dim() == 0 {
            return Err(Error::InvalidSystem {
                reason:
                    "its state has no components (state_dim() = 0): there is nothing to integrate"
                        .into(),
            });
        }
        if !crate::system::uniform_dims(system) {
            crate::system::check_mode_dims(system)?;
        }
        check_len("initial state", x0, system.mode_dim(mode))?;
        check_len("parameters", p, system.parameter_count())?;
        check_finite("initial state", x0)?;
        check_finite("parameters", p)?;
        check_finite("start time", &[t0])?;
        check_finite("end time", &[t_end])?;
        if t_end < t0 {
            return Err(Error::InvalidTimeSpan { t0, t_end });
        }
        Ok(())
    }

    /// Evaluates the events of `mode` (value and rate) at the start of a segment at `y` (with
    /// derivative `f`; both possibly augmented) and flags those starting on zero. `fired` is the
    /// event whose jump started the segment.
    #[allow(clippy::too_many_arguments)]
    fn start_segment<S: HybridSystem + ?Sized>(
        events: &mut Vec<EventState>,
        system: &S,
        mode: Mode,
        fired: Option<EventId>,
        y: &[f64],
        f: &[f64],
        p: &[f64],
        work: &mut [f64],
    ) {
        let n = system.mode_dim(mode);
        events.clear();
        for &id in system.events(mode) {
            events.push(EventState::start(
                system,
                id,
                fired,
                &y[..n],
                &f[..n],
                p,
                work,
            ));
        }
    }

    /// The event loop of [`Simulator::run`] and its sensitivity variants: steps, the earliest
    /// event of each accepted step, samples, terminal events and jumps (the pieces in
    /// `stepping.rs`), and the trajectory. Still one loop (177 lines): the step size, time,
    /// mode and sample index it carries between iterations would otherwise travel through
    /// every piece.
    #[allow(clippy::too_many_arguments, clippy::too_many_lines)]
    fn run_impl<S: HybridSystem + ?Sized, E: Extension<S>>(
        &mut self,
        system: &S,
        ext: &mut E,
        mut mode: Mode,
        t0: f64,
        x0: &[f64],
        p: &[f64],
        t_end: f64,
        which: Sensitivities,
    ) -> Result<Trajectory> {
        Self::validate_inputs(system, mode, t0, x0, p, t_end)?;
        // The state's dimension in the current mode.
        let mut n = system.mode_dim(mode);
        let s = self.settings.clone();
        let mut rec = Records::new(n);
        let mut next_sample = s.samples.map(|st| st.first_index_from(t0));
        let to_error =
            |e: NonFiniteEvaluation, mode: Mode| non_finite(&e, mode, system.mode_dim(mode));
        let mut t = t0;
        let mut h = self.begin(system, ext, mode, (t0, t_end), x0, p)?;
        // The step size the integrator proposed last, before truncation at `t_end`.
        let mut proposed = h;
        if s.record_steps {
            rec.steps.push_state(t, mode, &self.y0[..n]);
        }

        let stop = 'outer: loop {
            // Samples at the current time (only the very first point; later samples are emitted
            // on the step that reaches them).
            if let (Some(st), Some(k)) = (s.samples, next_sample.as_mut())
                && st.time(*k) <= t
                && t == t0
            {
                rec.samples.push_state(t, mode, &self.stepper.state()[..n]);
                *k += 1;
            }
            if t >= t_end {
                break StopReason::EndReached;
            }
            if stats_steps(&self.stepper) >= s.max_steps {
                break StopReason::StepLimit { t };
            }
            let remaining = t_end - t;
            h = h.min(s.h_max);
            proposed = h;
            let last = 1.01 * h >= remaining;
            if last {
                h = remaining;
            }
            if h <= 4.0 * f64::EPSILON * t.abs().max(1.0) && !last {
                return Err(Error::StepSizeUnderflow { t, h, mode });
            }
            let mut rhs = |_t: f64, y: &[f64], dy: &mut [f64]| ext.rhs(system, mode, p, y, dy);
            let err = self
                .stepper
                .attempt(&mut rhs, h)
                .map_err(|e| to_error(e, mode))?;
            let h_next = self.stepper.next_step_size(h, err);
            if err > 1.0 {
                self.stepper.reject();
                h = h_next;
                continue;
            }
            self.stepper
                .accept(&mut rhs)
                .map_err(|e| to_error(e, mode))?;
            let t_new = if last { t_end } else { t + h };

            // --- Event detection on the pending step.
            let earliest = self
                .earliest_event(system, p, (t, t_new, n), s.event_tolerance, &mut rhs)
                .map_err(|e| to_error(e, mode))?;
            self.events_finite(mode, t_new, &self.stepper.new_state()[..n], true)?;

            let t_stop = earliest.map_or(t_new, |(te, _)| te);
            // A sample that coincides with the end time up to rounding (k * period computed
            // differently from t_end) belongs to this run.
            let sample_limit = if earliest.is_none() && last {
                t_stop + 8.0 * f64::EPSILON * t_stop.abs().max(1.0)
            } else {
                t_stop
            };
            // --- Samples inside (t, t_stop].
            if let (Some(st), Some(k)) = (s.samples, next_sample.as_mut()) {
                while st.time(*k) <= sample_limit {
                    let ts = st.time(*k);
                    if ts >= t_new && earliest.is_none() {
                        rec.samples
                            .push_state(ts, mode, &self.stepper.new_state()[..n]);
                    } else {
                        self.stepper
                            .prepare_dense(&mut rhs)
                            .map_err(|e| to_error(e, mode))?;
                        self.stepper.dense(ts, &mut self.x_probe[..n]);
                        rec.samples.push_state(ts, mode, &self.x_probe[..n]);
                    }
                    *k += 1;
                }
            }

            let Some((te, idx)) = earliest else {
                // --- No event: commit the step.
                if s.record_steps {
                    rec.steps
                        .push_state(t_new, mode, &self.stepper.new_state()[..n]);
                }
                for ev in &mut self.events {
                    ev.commit(&self.stepper.new_state()[..n]);
                }
                self.stepper.commit();
                t = t_new;
                h = h_next;
                continue;
            };

            // --- An event at te.
            let ev = self.events[idx];
            rec.stats.events += 1;
            self.stepper
                .prepare_dense(&mut rhs)
                .map_err(|e| to_error(e, mode))?;
            self.stepper.dense(te, &mut self.y_minus);
            if s.record_steps {
                rec.steps.push_state(te, mode, &self.y_minus[..n]);
            }
            let conditioning = if s.record_events && s.conditioning {
                conditioning::conditioning(
                    system,
                    ev.id,
                    p,
                    &self.stepper,
                    (t, t_new),
                    (te, &self.y_minus),
                    (s.rtol, s.atol, s.event_tolerance),
                    &mut self.x_probe[..n],
                )
            } else {
                EventConditioning::default()
            };
            match system.event_spec(ev.id).action {
                EventAction::Terminal => {
                    if s.record_events {
                        rec.events.push(EventRecord {
                            t: te,
                            event: ev.id,
                            mode_before: mode,
                            mode_after: None,
                            state_before: self.y_minus[..n].to_vec(),
                            state_after: self.y_minus[..n].to_vec(),
                            conditioning,
                        });
                    }
                    self.y_plus.copy_from_slice(&self.y_minus);
                    t = te;
                    break 'outer StopReason::TerminalEvent {
                        event: ev.id,
                        t: te,
                    };
                }
                EventAction::Jump { to } => {
                    t = te;
                    match self.jump(
                        system,
                        ext,
                        p,
                        (ev.id, mode, to, te),
                        conditioning,
                        &mut rec,
                    )? {
                        std::ops::ControlFlow::Continue(m) => mode = m,
                        std::ops::ControlFlow::Break(stop) => {
                            mode = to;
                            n = system.mode_dim(mode);
                            break 'outer stop;
                        }
                    }
                    n = system.mode_dim(mode);
                    h = h_next.min(h);
                }
            }
        };

        let stepper_stats = self.stepper.stats();
        rec.stats.steps = stepper_stats.accepted_steps;
        rec.stats.rejected_steps = stepper_stats.rejected_steps;
        rec.stats.rhs_evaluations = stepper_stats.rhs_evaluations;
        rec.stats.dense_outputs = stepper_stats.dense_outputs;
        let final_aug: &[f64] = match stop {
            StopReason::TerminalEvent { .. } | StopReason::ZenoAccumulation { .. } => &self.y_plus,
            _ => self.stepper.state(),
        };
        rec.stats.zeno_transitions = rec.zeno.log.len() as u64;
        let sensitivities = (rec.zeno.log.is_empty() && which != Sensitivities::None).then(|| {
            SensitivityMatrices::from_augmented(final_aug, n, system.parameter_count(), which)
        });
        Ok(Trajectory {
            stop,
            t_final: t,
            mode_final: mode,
            state_final: final_aug[..n].to_vec(),
            samples: rec.samples,
            steps: rec.steps,
            events: rec.events,
            zeno: rec.zeno.log,
            sensitivities,
            stats: rec.stats,
            next_step: proposed,
        })
    }
}

/// The error of a right-hand side that returned a non-finite value in `mode` (`n` states):
/// of the vector field, or of the variational equations carried with it (their components
/// after the state's are the sensitivities, column-major: to the start's state, then to the
/// parameters), whose non-finite values come from the vector field's Jacobian.
fn non_finite(e: &NonFiniteEvaluation, mode: Mode, n: usize) -> Error {
    if e.index < n {
        return Error::NonFiniteVectorField {
            t: e.t,
            mode,
            index: e.index,
            value: e.value,
            state: e.state[..n].to_vec(),
        };
    }
    let k = e.index - n;
    Error::NonFiniteDerivative {
        of: format!(
            "vector field of mode {mode} (in the variational equations at t = {})",
            e.t
        ),
        row: k % n,
        column: k / n,
        columns: "sensitivity",
        value: e.value,
        state: e.state[..n].to_vec(),
    }
}

fn stats_steps(stepper: &Dop853) -> u64 {
    let st = stepper.stats();
    st.accepted_steps + st.rejected_steps
}
