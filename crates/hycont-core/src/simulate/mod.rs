//! Event-driven simulation of hybrid systems.
//!
//! [`Simulator`] integrates a [`HybridSystem`] with the [`Dop853`] stepper, locates events on the
//! dense output, applies resets, switches modes, detects Zeno accumulation, samples the state at
//! prescribed times and optionally integrates the variational equations (with saltation matrices
//! at jumps). See [`SimulationSettings`] for the knobs and [`Trajectory`] for the result.

mod dop853;
mod events;
mod settings;
mod tableau;
mod trajectory;
mod variational;
mod zeno;

pub use dop853::{Dop853, NonFiniteEvaluation, StepperStats};
pub use settings::{ParamSet, SampleTimes, Sensitivities, SimulationSettings, ZenoSettings};
pub use trajectory::{
    EventRecord, SensitivityMatrices, SimulationStats, StopReason, TimeSeries, Trajectory,
    ZenoRecord,
};

use crate::error::{Error, Result, check_finite, check_len};
use crate::system::{EventAction, EventId, HybridJacobians, HybridSystem, Mode};
use events::{DenseStep, EventState, event_rate};
use variational::{Extension, Plain, Variational};
use zeno::{Zeno, ZenoWatch};

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
    y0: Vec<f64>,
    y_minus: Vec<f64>,
    y_plus: Vec<f64>,
    x_probe: Vec<f64>,
    zeno_out: Vec<f64>,
    events: Vec<EventState>,
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
            y0: Vec::new(),
            y_minus: Vec::new(),
            y_plus: Vec::new(),
            x_probe: Vec::new(),
            zeno_out: Vec::new(),
            events: Vec::new(),
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
        let mut ext = Plain {
            n: system.state_dim(),
        };
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

    /// Like [`Simulator::run`], integrating the variational equations as well; the trajectory's
    /// `sensitivities` then hold $\partial x(t_f)/\partial x_0$ (and $\partial x(t_f)/\partial p$),
    /// saltation matrices included.
    ///
    /// # Errors
    /// As [`Simulator::run`], and [`Error::InvalidTransition`] when an event is crossed
    /// tangentially (the saltation matrix is undefined at grazing).
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
                let selected: Vec<usize> =
                    (0..np).filter(|&q| which.includes_parameter(q)).collect();
                let mut ext = Variational::new(n, np, selected);
                self.run_impl(system, &mut ext, mode, t0, x0, p, t_end, which)
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
        check_len("initial state", x0, system.state_dim())?;
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
        let n = system.state_dim();
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

    /// The earliest event of the current segment located in the accepted, pending step from
    /// `t` to `t_new` (its time and index in `self.events`), the events' values and rates at
    /// the step's end updated; the dense output is built where an event needs a closer look.
    fn earliest_event<S: HybridSystem + ?Sized, F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        system: &S,
        p: &[f64],
        (t, t_new): (f64, f64),
        tolerance: f64,
        rhs: &mut F,
    ) -> std::result::Result<Option<(f64, usize)>, NonFiniteEvaluation> {
        let n = system.state_dim();
        let mut earliest: Option<(f64, usize)> = None;
        for idx in 0..self.events.len() {
            let x_new = &self.stepper.new_state()[..n];
            let f_new = &self.stepper.new_derivative()[..n];
            let ev = &mut self.events[idx];
            ev.value_new = system.event(ev.id, x_new, p);
            ev.rate_new = event_rate(system, ev.id, x_new, f_new, p, &mut self.x_probe[..n]);
            let ev = *ev;
            let check = ev.check();
            if check == events::Check::Quiet {
                continue;
            }
            self.stepper.prepare_dense(rhs)?;
            let tol = tolerance * t_new.abs().max(1.0);
            let step = DenseStep {
                stepper: &self.stepper,
                system,
                p,
                t,
                t_new,
            };
            if let Some((ta, ga, tb, gb)) = step.bracket(&ev, check, tol, &mut self.x_probe[..n]) {
                let tol = tolerance * tb.abs().max(1.0);
                let stepper = &self.stepper;
                let probe = &mut self.x_probe;
                let te = events::locate_root(ta, ga, tb, gb, tol, |tau| {
                    stepper.dense(tau, &mut probe[..n]);
                    system.event(ev.id, &probe[..n], p)
                });
                if earliest.is_none_or(|(t_best, _)| te < t_best) {
                    earliest = Some((te, idx));
                }
            }
        }
        Ok(earliest)
    }

    /// After a jump into `mode` at `te` by `event`: where the jumps accumulate
    /// ([`ZenoWatch`]), the system's Zeno transition applied to `self.y_plus` (continue in its
    /// mode, recorded in `zeno.log`), or the run's stop where the system has none.
    fn zeno_check<S: HybridSystem + ?Sized>(
        &mut self,
        system: &S,
        p: &[f64],
        (event, te): (EventId, f64),
        mode: Mode,
        zeno: &mut Zeno,
        settings: &ZenoSettings,
    ) -> Result<std::ops::ControlFlow<StopReason, Mode>> {
        use std::ops::ControlFlow::{Break, Continue};
        let n = system.state_dim();
        let Some(t_acc) = zeno.watch.jump_at(te, settings) else {
            return Ok(Continue(mode));
        };
        match system.zeno_transition(mode, event, &self.y_plus[..n], p, &mut self.zeno_out) {
            Some(m2) if m2.0 < system.mode_count() => {
                zeno.log.push(ZenoRecord {
                    t: te,
                    t_accumulation: t_acc,
                    event,
                    mode_after: m2,
                    state_after: self.zeno_out.clone(),
                });
                self.y_plus[..n].copy_from_slice(&self.zeno_out);
                zeno.watch = ZenoWatch::default();
                Ok(Continue(m2))
            }
            Some(m2) => Err(Error::InvalidTransition {
                t: te,
                mode,
                reason: format!("Zeno transition to mode {m2}, which does not exist"),
            }),
            None => Ok(Break(StopReason::ZenoAccumulation { event, t: te })),
        }
    }

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
        let n = system.state_dim();
        let na = ext.dim();
        let s = self.settings.clone();
        if self.stepper.dim() != na {
            self.stepper = Dop853::new(na);
        }
        self.stepper.reset_stats();
        let n_err = if s.sensitivities_in_error { na } else { n };
        self.stepper.set_tolerances(s.rtol, s.atol, n_err);
        self.stepper.set_controller_beta(s.controller_beta);
        self.y0.resize(na, 0.0);
        self.y_minus.resize(na, 0.0);
        self.y_plus.resize(na, 0.0);
        self.x_probe.resize(na, 0.0);
        self.zeno_out.resize(n, 0.0);
        ext.initial(x0, &mut self.y0);

        let mut samples = TimeSeries::new(n);
        let mut steps = TimeSeries::new(n);
        let mut event_log = Vec::new();
        let mut stats = SimulationStats::default();
        let mut next_sample = s.samples.map(|st| st.first_index_from(t0));

        let to_error = |e: NonFiniteEvaluation, mode: Mode| Error::NonFiniteVectorField {
            t: e.t,
            mode,
            index: e.index,
            value: e.value,
            state: e.state[..n].to_vec(),
        };

        let mut t = t0;
        if s.record_steps {
            steps.push(t, mode, &self.y0);
        }
        {
            let mut rhs = |_t: f64, y: &[f64], dy: &mut [f64]| ext.rhs(system, mode, p, y, dy);
            self.stepper
                .start(&mut rhs, t, &self.y0)
                .map_err(|e| to_error(e, mode))?;
        }
        Self::start_segment(
            &mut self.events,
            system,
            mode,
            None,
            &self.y0,
            self.stepper.derivative(),
            p,
            &mut self.x_probe[..n],
        );
        let span = (t_end - t0).max(f64::MIN_POSITIVE);
        let mut h = match s.h_initial {
            Some(h) => h.min(span),
            None => {
                let mut rhs = |_t: f64, y: &[f64], dy: &mut [f64]| ext.rhs(system, mode, p, y, dy);
                self.stepper
                    .initial_step(&mut rhs, 1.0, s.h_max.min(span))
                    .map_err(|e| to_error(e, mode))?
            }
        };

        let mut zeno = Zeno::default();

        let stop = 'outer: loop {
            // Samples at the current time (only the very first point; later samples are emitted
            // on the step that reaches them).
            if let (Some(st), Some(k)) = (s.samples, next_sample.as_mut())
                && st.time(*k) <= t
                && t == t0
            {
                samples.push(t, mode, self.stepper.state());
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
                .earliest_event(system, p, (t, t_new), s.event_tolerance, &mut rhs)
                .map_err(|e| to_error(e, mode))?;

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
                        samples.push(ts, mode, self.stepper.new_state());
                    } else {
                        self.stepper
                            .prepare_dense(&mut rhs)
                            .map_err(|e| to_error(e, mode))?;
                        self.stepper.dense(ts, &mut self.x_probe[..n]);
                        samples.push(ts, mode, &self.x_probe);
                    }
                    *k += 1;
                }
            }

            let Some((te, idx)) = earliest else {
                // --- No event: commit the step.
                if s.record_steps {
                    steps.push(t_new, mode, self.stepper.new_state());
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
            stats.events += 1;
            self.stepper
                .prepare_dense(&mut rhs)
                .map_err(|e| to_error(e, mode))?;
            self.stepper.dense(te, &mut self.y_minus);
            if s.record_steps {
                steps.push(te, mode, &self.y_minus);
            }
            match system.event_spec(ev.id).action {
                EventAction::Terminal => {
                    if s.record_events {
                        event_log.push(EventRecord {
                            t: te,
                            event: ev.id,
                            mode_before: mode,
                            mode_after: None,
                            state_before: self.y_minus[..n].to_vec(),
                            state_after: self.y_minus[..n].to_vec(),
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
                    if to.0 >= system.mode_count() {
                        return Err(Error::InvalidTransition {
                            t: te,
                            mode,
                            reason: format!("{} leads to mode {to}, which does not exist", ev.id),
                        });
                    }
                    ext.jump(
                        system,
                        ev.id,
                        mode,
                        to,
                        te,
                        p,
                        &self.y_minus,
                        &mut self.y_plus,
                    )?;
                    stats.jumps += 1;
                    if s.record_events {
                        event_log.push(EventRecord {
                            t: te,
                            event: ev.id,
                            mode_before: mode,
                            mode_after: Some(to),
                            state_before: self.y_minus[..n].to_vec(),
                            state_after: self.y_plus[..n].to_vec(),
                        });
                    }
                    mode = to;
                    t = te;

                    match self.zeno_check(system, p, (ev.id, te), mode, &mut zeno, &s.zeno)? {
                        std::ops::ControlFlow::Continue(m) => mode = m,
                        std::ops::ControlFlow::Break(stop) => break 'outer stop,
                    }
                    if s.record_steps {
                        steps.push(te, mode, &self.y_plus);
                    }
                    let mut rhs =
                        |_t: f64, y: &[f64], dy: &mut [f64]| ext.rhs(system, mode, p, y, dy);
                    self.stepper
                        .start(&mut rhs, te, &self.y_plus)
                        .map_err(|e| to_error(e, mode))?;
                    Self::start_segment(
                        &mut self.events,
                        system,
                        mode,
                        Some(ev.id),
                        &self.y_plus,
                        self.stepper.derivative(),
                        p,
                        &mut self.x_probe[..n],
                    );
                    h = h_next.min(h);
                }
            }
        };

        let stepper_stats = self.stepper.stats();
        stats.steps = stepper_stats.accepted_steps;
        stats.rejected_steps = stepper_stats.rejected_steps;
        stats.rhs_evaluations = stepper_stats.rhs_evaluations;
        stats.dense_outputs = stepper_stats.dense_outputs;
        let final_aug: &[f64] = match stop {
            StopReason::TerminalEvent { .. } | StopReason::ZenoAccumulation { .. } => &self.y_plus,
            _ => self.stepper.state(),
        };
        stats.zeno_transitions = zeno.log.len() as u64;
        let sensitivities = (zeno.log.is_empty() && which != Sensitivities::None).then(|| {
            SensitivityMatrices::from_augmented(final_aug, n, system.parameter_count(), which)
        });
        Ok(Trajectory {
            stop,
            t_final: t,
            mode_final: mode,
            state_final: final_aug[..n].to_vec(),
            samples,
            steps,
            events: event_log,
            zeno: zeno.log,
            sensitivities,
            stats,
        })
    }
}

fn stats_steps(stepper: &Dop853) -> u64 {
    let st = stepper.stats();
    st.accepted_steps + st.rejected_steps
}
