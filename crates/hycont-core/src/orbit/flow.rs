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
        mut tangents: Tangents<'_>,
    ) {
        if self.time_sign < 0.0 {
            self.system
                .vector_field_with_tangents(self.mode, x, p, f, tangents.reborrow());
            for v in f.iter_mut().chain(tangents.out.iter_mut()) {
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

#[cfg(test)]
mod tests {
    use super::SegmentFlow;
    use crate::system::{
        AutoDiff, Direction, EventAction, EventId, EventSpec, FiniteDifferences, HybridJacobians,
        HybridModel, Mode, ParamId, Scalar, Tangents,
    };
    use approx::assert_relative_eq;

    /// A pendulum, x0' = x1, x1' = -p0 sin x0 + p1.
    struct Pendulum;

    impl HybridModel for Pendulum {
        fn state_dim(&self) -> usize {
            2
        }
        fn parameter_names(&self) -> &[&'static str] {
            &["g", "torque"]
        }
        fn mode_count(&self) -> usize {
            1
        }
        fn mode_name(&self, _: Mode) -> &'static str {
            "swing"
        }
        fn events(&self, _: Mode) -> &[EventId] {
            &[]
        }
        fn event_spec(&self, _: EventId) -> EventSpec {
            EventSpec {
                name: "none",
                direction: Direction::Either,
                action: EventAction::Terminal,
            }
        }
        fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
            f[0] = x[1];
            f[1] = -p[0] * x[0].sin() + p[1];
        }
        fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T {
            x[0]
        }
    }

    /// The field and its derivatives along the directions through `flow`.
    fn tangents<S: HybridJacobians>(flow: &S) -> ([f64; 2], [f64; 6]) {
        let (mut f, mut out, mut work) = ([0.0; 2], [0.0; 6], [0.0; 8]);
        let t = Tangents {
            x: &[0.3, -1.2, 0.5, 0.7, 1.1, -0.4],
            params: &[ParamId(1)],
            out: &mut out,
            work: &mut work,
        };
        flow.vector_field_with_tangents(Mode(0), &[0.8, -0.6], &[9.81, 0.2], &mut f, t);
        (f, out)
    }

    /// Backward in time the field and every derivative along the directions change sign exactly
    /// (AD's seeded evaluation and the default's Jacobian products alike), and forward the
    /// segment's flow is the system's.
    #[test]
    fn backward_flow_negates_the_field_and_its_tangents() {
        let ad = AutoDiff::new(Pendulum);
        let direct = tangents(&ad);
        let forward = tangents(&SegmentFlow::plain(&ad, Mode(0)));
        let backward = tangents(&SegmentFlow::backward(&ad, Mode(0)));
        assert_eq!(forward, direct);
        assert_eq!(backward.0, direct.0.map(|v| -v));
        assert_eq!(backward.1, direct.1.map(|v| -v));
        // The default (Jacobians formed, here by central differences, then multiplied).
        let fd = FiniteDifferences::new(AutoDiff::new(Pendulum));
        let (f, out) = tangents(&fd);
        assert_eq!(
            tangents(&SegmentFlow::backward(&fd, Mode(0))),
            (f.map(|v| -v), out.map(|v| -v))
        );
        assert_relative_eq!(out[..], direct.1[..], max_relative = 1e-8);
        // The third direction moves the torque: its derivative is f_x x_3 + (0, 1), to rounding.
        let (c, s) = (0.8f64.cos(), 0.8f64.sin());
        assert_relative_eq!(
            direct.0[..],
            [-0.6, -9.81 * s + 0.2][..],
            max_relative = 1e-15
        );
        let want = [-0.4, -9.81 * c * 1.1 + 1.0];
        assert_relative_eq!(direct.1[4..], want[..], max_relative = 1e-15);
    }
}
