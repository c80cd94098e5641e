//! The pieces of a simulation run ([`Simulator`]'s run loop): its start, the earliest event in
//! an accepted step, a jump and the Zeno check after it, and what the run records.

use super::events::{self, DenseStep, event_rate};
use super::variational::Extension;
use super::zeno::{Zeno, ZenoWatch};
use super::{
    Dop853, EventRecord, NonFiniteEvaluation, SimulationStats, Simulator, StopReason, TimeSeries,
    ZenoRecord, ZenoSettings, non_finite,
};
use crate::error::{Error, Result};
use crate::system::{EventId, HybridSystem, Mode};

/// What a run records as it goes: samples, steps, events, statistics, Zeno transitions.
pub(super) struct Records {
    pub(super) samples: TimeSeries,
    pub(super) steps: TimeSeries,
    pub(super) events: Vec<EventRecord>,
    pub(super) stats: SimulationStats,
    pub(super) zeno: Zeno,
    /// The instant of the latest jumps and how many happened at it.
    instant: (f64, usize),
}

/// The most jumps (Zeno transitions included) a run makes at one instant before it is
/// [`Error::Stalled`]: a system whose resets or Zeno transitions lead straight back into the
/// same jumps would otherwise loop without time advancing until the step limit.
pub const MAX_JUMPS_AT_ONE_INSTANT: usize = 10_000;

impl Records {
    /// Empty records of a system with `n` states.
    pub(super) fn new(n: usize) -> Self {
        Self {
            samples: TimeSeries::new(n),
            steps: TimeSeries::new(n),
            events: Vec::new(),
            stats: SimulationStats::default(),
            zeno: Zeno::default(),
            instant: (f64::NAN, 0),
        }
    }

    /// Counts a jump at `t`: an error once [`MAX_JUMPS_AT_ONE_INSTANT`] happened without time
    /// advancing (by more than rounding).
    fn count_jump(&mut self, t: f64, event: EventId, mode: Mode) -> Result<()> {
        let same = (t - self.instant.0).abs() <= 4.0 * f64::EPSILON * t.abs().max(1.0);
        self.instant = if same {
            (self.instant.0, self.instant.1 + 1)
        } else {
            (t, 1)
        };
        if self.instant.1 > MAX_JUMPS_AT_ONE_INSTANT {
            return Err(Error::Stalled {
                t,
                jumps: self.instant.1,
                event,
                mode,
            });
        }
        Ok(())
    }
}

impl Simulator {
    /// The jump by `event` from mode `from` to `to` at `te` (the state before it in
    /// `self.y_minus`, after it in `self.y_plus`, the extension's part by its saltation), then
    /// the Zeno check and the next segment's start; the mode the run continues in, or the stop
    /// where the jumps accumulate without a transition.
    pub(super) fn jump<S: HybridSystem + ?Sized, E: Extension<S>>(
        &mut self,
        system: &S,
        ext: &mut E,
        p: &[f64],
        (event, from, to, te): (EventId, Mode, Mode, f64),
        conditioning: super::EventConditioning,
        rec: &mut Records,
    ) -> Result<std::ops::ControlFlow<StopReason, Mode>> {
        use std::ops::ControlFlow::{Break, Continue};
        let n = system.mode_dim(from);
        if to.0 >= system.mode_count() {
            return Err(Error::InvalidTransition {
                t: te,
                mode: from,
                reason: format!("{event} leads to mode {to}, which does not exist"),
            });
        }
        // Into a mode of another dimension (plain runs only): the reset writes its state.
        let n_to = system.mode_dim(to);
        if n_to != n {
            self.y_plus.resize(n_to, 0.0);
            // A component the reset leaves unwritten stays NaN: an error naming it, not a
            // stale value.
            self.y_plus.fill(f64::NAN);
        }
        ext.jump(
            system,
            event,
            from,
            to,
            te,
            p,
            &self.y_minus,
            &mut self.y_plus,
        )?;
        if let Some(index) = self.y_plus[..n_to].iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFiniteReset {
                event,
                index,
                value: self.y_plus[index],
                state: self.y_minus[..n].to_vec(),
            });
        }
        rec.stats.jumps += 1;
        rec.count_jump(te, event, from)?;
        if self.settings.record_events {
            rec.events.push(EventRecord {
                t: te,
                event,
                mode_before: from,
                mode_after: Some(to),
                state_before: self.y_minus[..n].to_vec(),
                state_after: self.y_plus[..n_to].to_vec(),
                conditioning,
            });
        }
        let zeno = self.settings.zeno;
        let mode = match self.zeno_check(system, p, (event, te), to, &mut rec.zeno, &zeno)? {
            Continue(m) => m,
            Break(stop) => return Ok(Break(stop)),
        };
        self.start_after_jump(system, ext, p, (event, mode, te), n, rec)?;
        Ok(Continue(mode))
    }

    /// Starts the segment after a jump by `event` into `mode` at `te` (the state in
    /// `self.y_plus`; `n_from` states before the jump): the stepper of the new mode's
    /// dimension where it differs, the first derivative, the events of the segment.
    fn start_after_jump<S: HybridSystem + ?Sized, E: Extension<S>>(
        &mut self,
        system: &S,
        ext: &mut E,
        p: &[f64],
        (event, mode, te): (EventId, Mode, f64),
        n_from: usize,
        rec: &mut Records,
    ) -> Result<()> {
        let n = system.mode_dim(mode);
        if self.settings.record_steps {
            rec.steps.push_state(te, mode, &self.y_plus[..n]);
        }
        if n != n_from {
            ext.set_state_dim(n);
            self.fit_stepper(ext.dim(), n);
        }
        let mut rhs = |_t: f64, y: &[f64], dy: &mut [f64]| ext.rhs(system, mode, p, y, dy);
        self.stepper
            .start(&mut rhs, te, &self.y_plus)
            .map_err(|e| non_finite(&e, mode, n))?;
        Self::start_segment(
            &mut self.events,
            system,
            mode,
            Some(event),
            &self.y_plus,
            self.stepper.derivative(),
            p,
            &mut self.x_probe[..n],
        );
        self.events_finite(mode, te, &self.y_plus[..n], false)
    }

    /// Prepares a run from `x0` at `t0` in `mode`: the stepper for the extension's dimension
    /// and the settings' tolerances, the work space, the first derivative, the events of the
    /// first segment; returns the first step (the settings' or the stepper's estimate, within
    /// the span to `t_end`).
    pub(super) fn begin<S: HybridSystem + ?Sized, E: Extension<S>>(
        &mut self,
        system: &S,
        ext: &mut E,
        mode: Mode,
        (t0, t_end): (f64, f64),
        x0: &[f64],
        p: &[f64],
    ) -> Result<f64> {
        let (n, na) = (system.mode_dim(mode), ext.dim());
        self.fit_stepper(na, n);
        self.stepper.reset_stats();
        self.y0.resize(na, 0.0);
        // A Zeno transition may lead into a mode of any dimension.
        self.zeno_out.resize(system.state_dim(), 0.0);
        ext.initial(x0, &mut self.y0);
        let mut rhs = |_t: f64, y: &[f64], dy: &mut [f64]| ext.rhs(system, mode, p, y, dy);
        self.stepper
            .start(&mut rhs, t0, &self.y0)
            .map_err(|e| non_finite(&e, mode, n))?;
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
        self.events_finite(mode, t0, &self.y0[..n], false)?;
        let span = (t_end - t0).max(f64::MIN_POSITIVE);
        Ok(match self.resume_step.or(self.settings.h_initial) {
            Some(h) => h.min(span),
            None => self
                .stepper
                .initial_step(&mut rhs, 1.0, self.settings.h_max.min(span))
                .map_err(|e| non_finite(&e, mode, n))?,
        })
    }

    /// The stepper for an augmented state of `na` values, of which the first `n` are the
    /// state (a spare one of that dimension where there is one), with the settings'
    /// tolerances; the work space of that size.
    fn fit_stepper(&mut self, na: usize, n: usize) {
        if self.stepper.dim() != na {
            let at = self.spare.iter().position(|st| st.dim() == na);
            let next = at.map_or_else(|| Dop853::new(na), |i| self.spare.swap_remove(i));
            let stats = self.stepper.stats();
            self.spare.push(std::mem::replace(&mut self.stepper, next));
            if self.spare.len() > 3 {
                self.spare.remove(0);
            }
            // One run's statistics across the steppers of its modes' dimensions.
            self.stepper.carry_stats(stats);
        }
        let s = &self.settings;
        let n_err = if s.sensitivities_in_error { na } else { n };
        self.stepper.set_tolerances(s.rtol, s.atol, n_err);
        self.stepper.set_controller_beta(s.controller_beta);
        self.y_minus.resize(na, 0.0);
        self.y_plus.resize(na, 0.0);
        self.x_probe.resize(na, 0.0);
    }

    /// An error naming the first event of the current segment whose value is not finite at
    /// the segment's start (`pending == false`) or at the end of the pending step at `t` in
    /// state `x`.
    pub(super) fn events_finite(&self, mode: Mode, t: f64, x: &[f64], pending: bool) -> Result<()> {
        let bad = self.events.iter().find(|e| {
            let v = if pending { e.value_new } else { e.value };
            !v.is_finite()
        });
        match bad {
            Some(e) => Err(Error::NonFiniteEvent {
                event: e.id,
                mode,
                t,
                value: if pending { e.value_new } else { e.value },
                state: x.to_vec(),
            }),
            None => Ok(()),
        }
    }

    /// The earliest event of the current segment located in the accepted, pending step from
    /// `t` to `t_new` (its time and index in `self.events`; `n` states in the current mode), the events' values and rates at
    /// the step's end updated; the dense output is built where an event needs a closer look.
    pub(super) fn earliest_event<S: HybridSystem + ?Sized, F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        system: &S,
        p: &[f64],
        (t, t_new, n): (f64, f64, usize),
        tolerance: f64,
        rhs: &mut F,
    ) -> std::result::Result<Option<(f64, usize)>, NonFiniteEvaluation> {
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
                    events::event_at(stepper, system, ev.id, p, tau, &mut probe[..n])
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
    pub(super) fn zeno_check<S: HybridSystem + ?Sized>(
        &mut self,
        system: &S,
        p: &[f64],
        (event, te): (EventId, f64),
        mode: Mode,
        zeno: &mut Zeno,
        settings: &ZenoSettings,
    ) -> Result<std::ops::ControlFlow<StopReason, Mode>> {
        use std::ops::ControlFlow::{Break, Continue};
        let n = system.mode_dim(mode);
        let Some(t_acc) = zeno.watch.jump_at(te, settings) else {
            return Ok(Continue(mode));
        };
        match system.zeno_transition(mode, event, &self.y_plus[..n], p, &mut self.zeno_out) {
            Some(m2) if m2.0 < system.mode_count() => {
                let n2 = system.mode_dim(m2);
                zeno.log.push(ZenoRecord {
                    t: te,
                    t_accumulation: t_acc,
                    event,
                    mode_after: m2,
                    state_after: self.zeno_out[..n2].to_vec(),
                });
                if n2 != n {
                    self.y_plus.resize(n2, 0.0);
                }
                self.y_plus[..n2].copy_from_slice(&self.zeno_out[..n2]);
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
}
