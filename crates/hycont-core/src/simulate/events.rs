//! Event detection on one accepted step of the simulator.
//!
//! A crossing is found in three ways:
//! - a **sign change** of the event function $g$ between the step's ends (in the event's
//!   direction), located by the Illinois method on the dense output;
//! - a **dip**: $g$ keeps its sign $\sigma$ at both ends but moves toward zero at the start and
//!   away from it at the end ($\sigma \dot g(t_0) < 0 < \sigma \dot g(t_1)$), so it has an
//!   interior extremum nearest zero. The extremum is located as the root of $\dot g$ on the
//!   dense output; if $g$ reaches or passes zero there, the step holds two crossings (or a
//!   touch) and the first one in the event's direction is located. This sees low-velocity
//!   (near-grazing) impacts that sign checks at step ends step over;
//! - a **restart guard**: an event function that starts a segment on its zero (right after a
//!   jump onto its surface, or a start within rounding of it) is probed for an excursion to its
//!   pre-crossing side inside the step. If there is none and the step ends past the surface, the
//!   flow leaves the mode's domain at once and a directional event happens at the segment's
//!   start: a terminal event is never stepped over, and repeated jumps at one instant end in
//!   the system's Zeno transition. The exception is the event whose own jump started the
//!   segment while the flow still moves to its post-crossing side (an identity reset, a marker):
//!   that is the crossing just handled.
//!
//! The rate $\dot g = \nabla g \cdot f$ at the step's ends comes from the vector field there
//! (exactly through [`HybridSystem::event_component`] when the system gives that hint,
//! otherwise by a central difference of $g$ along $f$); inside the step it is a central
//! difference of $g$ along the dense output.

use super::Dop853;
use crate::system::{Direction, EventId, HybridSystem};

/// Fractions of a step probed for an excursion to the pre-crossing side of an event function
/// that starts a segment on its zero (restart guard): $2^{-40}, \dots, 2^{-1}$ and $j/8$, in
/// increasing order (made once: every segment start on a zero probes them).
pub(super) fn probe_fractions() -> &'static [f64; 47] {
    static FRACTIONS: std::sync::LazyLock<[f64; 47]> = std::sync::LazyLock::new(|| {
        let mut out = [0.0; 47];
        for (k, o) in out.iter_mut().take(40).enumerate() {
            *o = 2f64.powi(k as i32 - 40);
        }
        for j in 1..8 {
            out[39 + j] = j as f64 / 8.0;
        }
        out.sort_by(f64::total_cmp);
        out
    });
    &FRACTIONS
}

/// Relative step of central differences (about the cube root of the machine epsilon).
const CENTRAL_STEP: f64 = 6e-6;

/// Per-event bookkeeping of the current segment.
#[derive(Debug, Clone, Copy)]
pub(super) struct EventState {
    pub(super) id: EventId,
    pub(super) direction: Direction,
    /// $g$ at the current point.
    pub(super) value: f64,
    /// $\dot g$ at the current point.
    pub(super) rate: f64,
    /// The event function started the segment on (or within the guard band of) zero.
    pub(super) at_zero: bool,
    /// The segment starts right after this event's own jump, with the flow still moving to its
    /// post-crossing side: the crossing just handled, not a new one at the start.
    pub(super) continuing: bool,
    /// $g$ and $\dot g$ at the end of the pending step.
    pub(super) value_new: f64,
    pub(super) rate_new: f64,
}

/// What a pending step needs to have checked for one event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Check {
    /// Nothing can have happened.
    Quiet,
    /// A sign change in the event's direction between the ends.
    Crossing,
    /// The restart guard, with the pre-crossing sign wanted and whether, without an excursion
    /// to that side, the event happens at the step's start.
    Probe {
        /// The pre-crossing sign.
        want: f64,
        /// Without an excursion, the crossing is at the start (a directional event that is not
        /// the crossing just handled).
        at_start: bool,
    },
    /// An interior extremum nearest zero, with the sign $\sigma$ of $g$ at both ends.
    Dip(f64),
}

/// The band around zero within which an event function starting a segment counts as on its
/// surface.
pub(super) fn zero_band(x: &[f64]) -> f64 {
    1e-9 * (1.0 + x.iter().fold(0.0f64, |m, v| m.max(v.abs())))
}

/// $\dot g = \nabla g \cdot f$ at state `x` with derivative `f`; `work` has the length of `x`.
pub(super) fn event_rate<S: HybridSystem + ?Sized>(
    system: &S,
    id: EventId,
    x: &[f64],
    f: &[f64],
    p: &[f64],
    work: &mut [f64],
) -> f64 {
    if let Some(c) = system.event_component(id) {
        return f[c];
    }
    let f_norm = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if f_norm == 0.0 {
        return 0.0;
    }
    let x_norm = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let eps = CENTRAL_STEP * (1.0 + x_norm) / f_norm;
    for ((w, xi), fi) in work.iter_mut().zip(x).zip(f) {
        *w = xi + eps * fi;
    }
    let up = system.event(id, work, p);
    for ((w, xi), fi) in work.iter_mut().zip(x).zip(f) {
        *w = xi - eps * fi;
    }
    let down = system.event(id, work, p);
    (up - down) / (2.0 * eps)
}

impl EventState {
    /// The state of event `id` at the start of a segment at `x` with derivative `f`.
    /// `fired` is the event whose jump started the segment, if any.
    pub(super) fn start<S: HybridSystem + ?Sized>(
        system: &S,
        id: EventId,
        fired: Option<EventId>,
        x: &[f64],
        f: &[f64],
        p: &[f64],
        work: &mut [f64],
    ) -> Self {
        let value = system.event(id, x, p);
        let rate = event_rate(system, id, x, f, p, work);
        let direction = system.event_spec(id).direction;
        let continuing =
            fired == Some(id) && direction.sign_before().is_some_and(|pre| rate * pre < 0.0);
        Self {
            id,
            direction,
            value,
            rate,
            continuing,
            at_zero: value.abs() <= zero_band(x),
            value_new: value,
            rate_new: rate,
        }
    }

    /// What the pending step (ending with `value_new`, `rate_new`) needs checked.
    pub(super) fn check(&self) -> Check {
        let g_new = self.value_new;
        if self.at_zero {
            // A directional event, unless it is the crossing just handled, fires at the start
            // when the flow leaves the domain at once (see `DenseStep::bracket`).
            let (want, at_start) = match self.direction.sign_before() {
                Some(sg) => (sg, !self.continuing),
                None if g_new != 0.0 => (-g_new.signum(), false),
                None => return Check::Quiet,
            };
            return if g_new * want > 0.0 {
                Check::Quiet
            } else {
                Check::Probe { want, at_start }
            };
        }
        if self.direction.is_crossing(self.value, g_new) {
            return Check::Crossing;
        }
        let sigma = self.value.signum();
        if self.value != 0.0
            && g_new * sigma > 0.0
            && self.rate * sigma < 0.0
            && self.rate_new * sigma > 0.0
        {
            return Check::Dip(sigma);
        }
        Check::Quiet
    }

    /// Makes the pending step's end the current point.
    pub(super) fn commit(&mut self, x_new: &[f64]) {
        self.value = self.value_new;
        self.rate = self.rate_new;
        if self.at_zero {
            self.at_zero = self.value.abs() <= zero_band(x_new);
        }
    }
}

/// Event `id`'s function on the dense output of `stepper`'s pending step at `tau`, `probe`
/// (the state's length) holding the interpolated state. An event on a coordinate surface
/// ([`HybridSystem::event_component`]: $h_e = x_c - v(p)$) reads $x_c$ alone, so only that
/// component is interpolated.
pub(super) fn event_at<S: HybridSystem + ?Sized>(
    stepper: &Dop853,
    system: &S,
    id: EventId,
    p: &[f64],
    tau: f64,
    probe: &mut [f64],
) -> f64 {
    match system.event_component(id) {
        Some(c) if c < probe.len() => probe[c] = stepper.dense_component(c, tau),
        _ => stepper.dense(tau, probe),
    }
    system.event(id, probe, p)
}

/// The accepted step `[t, t_new]` with its dense output built, as seen by one event.
pub(super) struct DenseStep<'a, S: ?Sized> {
    pub(super) stepper: &'a Dop853,
    pub(super) system: &'a S,
    pub(super) p: &'a [f64],
    pub(super) t: f64,
    pub(super) t_new: f64,
}

impl<S: HybridSystem + ?Sized> DenseStep<'_, S> {
    fn g(&self, id: EventId, tau: f64, probe: &mut [f64]) -> f64 {
        event_at(self.stepper, self.system, id, self.p, tau, probe)
    }

    /// A bracket `(ta, ga, tb, gb)` of the first crossing of `ev` in the step, with `ga`
    /// strictly on the pre-crossing side (or `ta == tb == t` for an event at the step's start),
    /// or `None`. `probe` has the state's length.
    pub(super) fn bracket(
        &self,
        ev: &EventState,
        check: Check,
        tol: f64,
        probe: &mut [f64],
    ) -> Option<(f64, f64, f64, f64)> {
        let (t, t_new) = (self.t, self.t_new);
        match check {
            Check::Quiet => None,
            Check::Crossing => Some((t, ev.value, t_new, ev.value_new)),
            Check::Probe { want, at_start } => {
                let mut found = None;
                for &fr in probe_fractions() {
                    let tp = t + fr * (t_new - t);
                    let gp = self.g(ev.id, tp, probe);
                    match found {
                        None if gp * want > 0.0 => found = Some((tp, gp, t_new, ev.value_new)),
                        Some((ta, ga, _, _)) if gp * want <= 0.0 => {
                            return Some((ta, ga, tp, gp));
                        }
                        _ => {}
                    }
                }
                if found.is_none() && at_start && ev.value_new * want < 0.0 {
                    // No excursion to the pre-crossing side even $2^{-40}$ of a step in, and the
                    // step ends strictly past the surface: the flow leaves the mode's domain at
                    // the start (a start within rounding of the surface, or a re-impact at
                    // vanishing velocity). The event happens at `t`.
                    return Some((t, ev.value, t, ev.value_new));
                }
                found
            }
            Check::Dip(sigma) => {
                let dt = CENTRAL_STEP * (t_new - t);
                // On a coordinate surface the rate is the interpolant's derivative of that
                // component; otherwise a central difference.
                let component = self
                    .system
                    .event_component(ev.id)
                    .filter(|c| *c < probe.len());
                let mut rate = |tau: f64| match component {
                    Some(c) => self.stepper.dense_derivative_component(c, tau),
                    None => {
                        (self.g(ev.id, tau + dt, probe) - self.g(ev.id, tau - dt, probe))
                            / (2.0 * dt)
                    }
                };
                // The extremum to 1e-9 of the step: its value is then exact to second order.
                let tol_extremum = tol.max(1e-9 * (t_new - t));
                let tau = locate_root(t, ev.rate, t_new, ev.rate_new, tol_extremum, &mut rate);
                let g_min = self.g(ev.id, tau, probe);
                if g_min * sigma > 0.0 {
                    None
                } else if ev.direction.is_crossing(ev.value, g_min) {
                    Some((t, ev.value, tau, g_min))
                } else if g_min != 0.0 && ev.direction.is_crossing(g_min, ev.value_new) {
                    Some((tau, g_min, t_new, ev.value_new))
                } else {
                    None
                }
            }
        }
    }
}

/// Locates the crossing of `g` in `[a, b]`, where `g(a)` is strictly on the pre-crossing side and
/// `g(b)` on the other side or zero, by the Illinois method with a bisection safeguard. Returns a
/// time on the post-crossing side within `tol` of the crossing.
pub(crate) fn locate_root(
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
    tol: f64,
    mut g: impl FnMut(f64) -> f64,
) -> f64 {
    // The pre-crossing sign (g(a) is strictly non-zero); zero counts as post-crossing.
    let pre = ga.signum();
    let post = |v: f64| v == 0.0 || v.signum() != pre;
    let mut side = 0i8;
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        let width = b - a;
        let mut c = if ga == gb {
            0.5 * (a + b)
        } else {
            (a * gb - b * ga) / (gb - ga)
        };
        // Keep c strictly inside, at least tol/2 from the ends, so the bracket shrinks below tol.
        let margin = (0.5 * tol).min(0.25 * width);
        c = c.clamp(a + margin, b - margin);
        let gc = g(c);
        if post(gc) {
            // c is on the post-crossing side (or on zero): new right end.
            b = c;
            gb = gc;
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        } else {
            a = c;
            ga = gc;
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        }
        // Bisection safeguard when the bracket shrinks slowly.
        if b - a > 0.5 * width {
            let m = 0.5 * (a + b);
            let gm = g(m);
            if post(gm) {
                b = m;
                gb = gm;
            } else {
                a = m;
                ga = gm;
            }
            side = 0;
        }
    }
    b
}
