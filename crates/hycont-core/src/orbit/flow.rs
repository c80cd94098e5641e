//! A single mode of a hybrid system as a system of its own: the flow of one segment, optionally
//! stopped at the segment's end condition or split at interior points.

use super::signature::SegmentEnd;
use crate::system::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, Tangents,
};

const STOP: EventId = EventId(0);
const SPLIT: EventId = EventId(1);
const NONE: [EventId; 0] = [];
const ONLY_STOP: [EventId; 1] = [STOP];
const ONLY_SPLIT: [EventId; 1] = [SPLIT];
const BOTH: [EventId; 2] = [STOP, SPLIT];

/// Mode `mode` of `system`, as a one-mode system whose events are: optionally the segment's end
/// condition (terminal, `EventId(0)`), and optionally an interior condition `x[c] = v` that is
/// recorded as an identity jump (`EventId(1)`).
pub(crate) struct SegmentFlow<'a, S: ?Sized> {
    pub system: &'a S,
    pub mode: Mode,
    pub stop: Option<SegmentEnd>,
    pub split: Option<(usize, f64)>,
    /// `-1.0` integrates backward in time ($\dot x = -f$), for negative durations.
    pub time_sign: f64,
}

impl<'a, S: HybridSystem + ?Sized> SegmentFlow<'a, S> {
    pub(crate) fn plain(system: &'a S, mode: Mode) -> Self {
        Self {
            system,
            mode,
            stop: None,
            split: None,
            time_sign: 1.0,
        }
    }

    /// The flow of `mode` backward in time.
    pub(crate) fn backward(system: &'a S, mode: Mode) -> Self {
        Self {
            time_sign: -1.0,
            ..Self::plain(system, mode)
        }
    }
}

impl<S: HybridSystem + ?Sized> HybridSystem for SegmentFlow<'_, S> {
    fn state_dim(&self) -> usize {
        self.system.state_dim()
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
        match (self.stop.is_some(), self.split.is_some()) {
            (false, false) => &NONE,
            (true, false) => &ONLY_STOP,
            (false, true) => &ONLY_SPLIT,
            (true, true) => &BOTH,
        }
    }
    fn event_spec(&self, event: EventId) -> EventSpec {
        if event == STOP {
            let direction = match self.stop {
                Some(SegmentEnd::Event(e)) => self.system.event_spec(e).direction,
                _ => Direction::Either,
            };
            EventSpec {
                name: "segment end",
                direction,
                action: EventAction::Terminal,
            }
        } else {
            EventSpec {
                name: "interior point",
                direction: Direction::Either,
                action: EventAction::Jump { to: Mode(0) },
            }
        }
    }
    #[inline]
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.system.vector_field(self.mode, x, p, out);
        if self.time_sign < 0.0 {
            for v in out.iter_mut() {
                *v = -*v;
            }
        }
    }
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        if event == STOP {
            match self.stop {
                Some(SegmentEnd::Event(e)) => self.system.event(e, x, p),
                Some(SegmentEnd::Interior { component, value }) => x[component] - value,
                None => 1.0,
            }
        } else {
            let (c, v) = self.split.unwrap_or((0, 0.0));
            x[c] - v
        }
    }
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        self.system.trivial_multipliers(p, period)
    }
}

impl<S: HybridJacobians + ?Sized> HybridJacobians for SegmentFlow<'_, S> {
    #[inline]
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        if self.time_sign < 0.0 {
            let mut dp = dp;
            self.system
                .vector_field_jacobian(self.mode, x, p, dx, dp.as_deref_mut());
            for v in dx.iter_mut() {
                *v = -*v;
            }
            if let Some(dp) = dp {
                for v in dp.iter_mut() {
                    *v = -*v;
                }
            }
        } else {
            self.system.vector_field_jacobian(self.mode, x, p, dx, dp);
        }
    }
    #[inline]
    fn vector_field_with_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        if self.time_sign < 0.0 {
            let mut dp = dp;
            self.system
                .vector_field_with_jacobian(self.mode, x, p, f, dx, dp.as_deref_mut());
            for v in f.iter_mut().chain(dx.iter_mut()) {
                *v = -*v;
            }
            if let Some(dp) = dp {
                for v in dp.iter_mut() {
                    *v = -*v;
                }
            }
        } else {
            self.system
                .vector_field_with_jacobian(self.mode, x, p, f, dx, dp);
        }
    }
    #[inline]
    fn vector_field_with_tangents(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        tangents: Tangents<'_>,
    ) {
        if self.time_sign < 0.0 {
            let Tangents {
                x: dirs,
                params,
                out,
                work,
            } = tangents;
            let inner = Tangents {
                x: dirs,
                params,
                out: &mut *out,
                work,
            };
            self.system
                .vector_field_with_tangents(self.mode, x, p, f, inner);
            for v in f.iter_mut().chain(out.iter_mut()) {
                *v = -*v;
            }
        } else {
            self.system
                .vector_field_with_tangents(self.mode, x, p, f, tangents);
        }
    }
    fn event_gradient(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        match (event == STOP, self.stop) {
            (true, Some(SegmentEnd::Event(e))) => self.system.event_gradient(e, x, p, dx, dp),
            _ => {
                let c = match (event == STOP, self.stop) {
                    (true, Some(SegmentEnd::Interior { component, .. })) => component,
                    _ => self.split.map_or(0, |s| s.0),
                };
                dx.fill(0.0);
                dx[c] = 1.0;
                if let Some(dp) = dp {
                    dp.fill(0.0);
                }
            }
        }
    }
}

/// Mode `mode` of `system` stopped at the segment's end condition (`EventId(0)`) or at any other
/// event of the mode (`EventId(1 + i)` for the `i`-th of `guards`), all terminal: a trajectory
/// that meets another event surface first does not follow the signature.
pub(crate) struct GuardedFlow<'a, S: ?Sized> {
    system: &'a S,
    mode: Mode,
    end: SegmentEnd,
    guards: Vec<EventId>,
    ids: Vec<EventId>,
}

impl<'a, S: HybridSystem + ?Sized> GuardedFlow<'a, S> {
    pub(crate) fn new(system: &'a S, mode: Mode, end: SegmentEnd) -> Self {
        let guards: Vec<EventId> = system
            .events(mode)
            .iter()
            .copied()
            .filter(|&e| end != SegmentEnd::Event(e))
            .collect();
        let ids = (0..=guards.len()).map(EventId).collect();
        Self {
            system,
            mode,
            end,
            guards,
            ids,
        }
    }

    /// The system's event that stopped the flow at `id`, `None` for the end condition.
    pub(crate) fn guard(&self, id: EventId) -> Option<EventId> {
        id.0.checked_sub(1)
            .and_then(|i| self.guards.get(i).copied())
    }
}

impl<S: HybridSystem + ?Sized> HybridSystem for GuardedFlow<'_, S> {
    fn state_dim(&self) -> usize {
        self.system.state_dim()
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
        &self.ids
    }
    fn event_spec(&self, event: EventId) -> EventSpec {
        let direction = match (self.guard(event), self.end) {
            (Some(g), _) | (None, SegmentEnd::Event(g)) => self.system.event_spec(g).direction,
            (None, SegmentEnd::Interior { .. }) => Direction::Either,
        };
        EventSpec {
            name: "segment end",
            direction,
            action: EventAction::Terminal,
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.system.vector_field(self.mode, x, p, out);
    }
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        match (self.guard(event), self.end) {
            (Some(g), _) | (None, SegmentEnd::Event(g)) => self.system.event(g, x, p),
            (None, SegmentEnd::Interior { component, value }) => x[component] - value,
        }
    }
}
