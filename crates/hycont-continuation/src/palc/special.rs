//! The special points of a step: the test functions that change sign in it, each located,
//! checked and labelled, and whether one of them ends the run.

use super::critical;
use super::slots::{Crossing, Slot};
use super::{Chart, Palc, START_EVENT_TOL};
use crate::branch::{Branch, EndReason, SpecialKind, SpecialPoint};
use crate::observe::Observer;
use crate::{ContinuationProblem, MonitorEvent};

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// The test functions that change sign between `a` and `b` (a step `h`), each located:
    /// (arclength along the step, slot, chart, located, accuracy), in the order of the step.
    /// Branch points first: a fold test change next to a located one is the branch point's.
    ///
    /// From a singular start (`from_singular`: the first step of a run along a given
    /// direction, which starts at a branch point, period doubling or grazing) the fold and
    /// branch-point tests are not watched, they vanish at the start itself, and neither are
    /// events and bounds the start lies on (within [`START_EVENT_TOL`] of their level, e.g.
    /// the grazing a switch starts at): the start is located on them already.
    fn located_in_step(
        &mut self,
        a: &Chart,
        b: &Chart,
        h: f64,
        from_singular: bool,
    ) -> Vec<Located> {
        let det_ref = a.det.1;
        let ta = self.tests(a, det_ref);
        let tb = self.tests(b, det_ref);
        let singular =
            |slot: Slot| matches!(slot, Slot::Fold | Slot::BranchPoint | Slot::Cusp { .. });
        let on_it = |slot: usize| match self.slots[slot] {
            Slot::Event { level, .. } | Slot::Bound { level, .. } => {
                ta.values[slot].abs() <= START_EVENT_TOL * (1.0 + level.abs())
            }
            _ => false,
        };
        let changed = |slot: usize| {
            let (ga, gb) = (ta.values[slot], tb.values[slot]);
            let crossed = match self.inside_sign(slot) {
                // A bound ends a run that leaves the window: from inside (or on it) to outside,
                // not back in from a start a rounding outside (e.g. a located end point).
                Some(side) => side * ga >= 0.0 && side * gb < 0.0,
                None => ga != 0.0 && ga * gb <= 0.0,
            };
            crossed && !(from_singular && (singular(self.slots[slot]) || on_it(slot)))
        };
        let mut order: Vec<usize> = (0..self.slots.len()).filter(|&k| changed(k)).collect();
        order.sort_by_key(|&k| self.slots[k] != Slot::BranchPoint);
        let mut found: Vec<Located> = Vec::new();
        self.locating = true;
        for slot in order {
            let bp = found
                .iter()
                .find(|f| self.slots[f.slot] == Slot::BranchPoint && f.located)
                .map(|f| f.s);
            let result = match (self.slots[slot], bp) {
                (Slot::Fold, Some(s_bp)) => self.locate_fold_beside(a, b, h, slot, s_bp),
                _ => Some(self.locate(a, (a, 0.0), (b, h), slot)),
            };
            if let Some((chart, located, accuracy)) = result {
                let s = self.wdot(&a.t, &chart.u) - self.wdot(&a.t, &a.u);
                found.push(Located {
                    s,
                    slot,
                    chart,
                    located,
                    accuracy,
                });
            }
        }
        self.locating = false;
        found.sort_by(|x, y| x.s.total_cmp(&y.s));
        self.first_end_by_precedence(&mut found);
        found
    }

    /// Of the terminal events located at the first one's point (closer than the location's
    /// tolerance or their brackets' widths, where rounding alone orders them), the one the
    /// problem names ([`ContinuationProblem::end_among`]) ends the run: moved to the first
    /// one's place.
    fn first_end_by_precedence(&mut self, found: &mut [Located]) {
        let event = |slot: Slot| match slot {
            Slot::Event {
                kind,
                level,
                on,
                terminal: true,
                ..
            } => Some(MonitorEvent {
                kind,
                on,
                level,
                terminal: true,
            }),
            _ => None,
        };
        let Some(first) = found
            .iter()
            .position(|f| event(self.slots[f.slot]).is_some())
        else {
            return;
        };
        let (s, width) = (found[first].s, found[first].accuracy);
        let tol = self.settings.locate_tol;
        // In the problem's order (slots hold the events as listed).
        let mut together: Vec<usize> = (first..found.len())
            .filter(|&i| {
                event(self.slots[found[i].slot]).is_some()
                    && found[i].s - s <= tol + width + found[i].accuracy
            })
            .collect();
        if together.len() < 2 {
            return;
        }
        together.sort_by_key(|&i| found[i].slot);
        let events: Vec<MonitorEvent> = (together.iter())
            .filter_map(|&i| event(self.slots[found[i].slot]))
            .collect();
        let pick = self.p.end_among(&found[first].chart.u, &events);
        let chosen = together.get(pick).copied().unwrap_or(together[0]);
        found[first..=chosen].rotate_right(1);
    }

    /// The special point of a located sign change in the step from `a` to `b` (`None` for a
    /// located sign change without a multiplier at the kind's critical value: a multiplier
    /// through infinity for PD, a neutral saddle for TR; see [`critical`]).
    fn special_point(
        &self,
        f: Located,
        (a, b): (&Chart, &Chart),
        h: f64,
        label: usize,
    ) -> Option<SpecialPoint> {
        let kind = Self::kind_of(self.slots[f.slot]);
        let mut c = f.chart;
        let tol = self.settings.critical_tolerance;
        let (genuine, critical) = match self.slots[f.slot] {
            Slot::Codim2 { held, crossing, .. } => {
                critical::genuine_codim2(&c.info, held, crossing, tol)
            }
            // Both parameters stationary: a turning point of the curve in the continued
            // parameter alone is not a cusp.
            Slot::Cusp { second } => (c.t[second].abs() <= tol, None),
            _ => critical::genuine(kind, &c.info, tol),
        };
        let always_checked = matches!(
            self.slots[f.slot],
            Slot::Codim2 {
                crossing: Crossing::Circle,
                ..
            } | Slot::Cusp { .. }
        );
        if (f.located || kind == SpecialKind::Torus || always_checked) && !genuine {
            return None;
        }
        // At a branch point the augmented Jacobian is singular and the tangent solved there
        // tends to the other branch's direction: keep this branch's tangent, from the
        // bracketing chart (branch switching needs it). Not where only the problem's
        // branch-point factor changed sign: the Jacobian is regular there.
        if kind == SpecialKind::BranchPoint && a.det.0 != b.det.0 {
            c.t.clone_from(&a.t);
        }
        let (on, level) = match self.slots[f.slot] {
            Slot::Event { on, level, .. } | Slot::Bound { on, level, .. } => {
                (Some(on), Some(level))
            }
            _ => (None, None),
        };
        Some(SpecialPoint {
            kind,
            point: self.point(&c, label, h),
            bracket: (self.parameter(&a.u), self.parameter(&b.u)),
            located: f.located,
            accuracy: f.accuracy,
            on,
            level,
            critical,
        })
    }

    /// Whether a special point at `slot` of `kind` ends the run, and why.
    fn ends_run(&self, slot: usize, kind: SpecialKind) -> Option<EndReason> {
        if self.settings.stop_at.contains(&kind) {
            return Some(EndReason::Reached(kind));
        }
        match self.slots[slot] {
            Slot::Bound { .. } => Some(EndReason::Bound),
            Slot::Event {
                terminal: true,
                kind,
                ..
            } => Some(EndReason::Inadmissible(kind)),
            _ => None,
        }
    }

    /// The special points of the step `h` from `a` to `b`, labelled from `*label + 1` on, into
    /// `branch` (and the observer); the reason the run ends at one of them, if it does.
    pub(super) fn record_special_points(
        &mut self,
        (a, b): (&Chart, &Chart),
        h: f64,
        label: &mut usize,
        branch: &mut Branch,
        observer: &mut dyn Observer,
        from_singular: bool,
    ) -> Option<EndReason> {
        for f in self.located_in_step(a, b, h, from_singular) {
            let slot = f.slot;
            let Some(special) = self.special_point(f, (a, b), h, *label + 1) else {
                self.stats.discarded_tests += 1;
                continue;
            };
            *label += 1;
            observer.special(&special);
            let end = self.ends_run(slot, special.kind);
            branch.special_points.push(special);
            if end.is_some() {
                return end;
            }
        }
        None
    }
}

/// A test function's sign change located in a step.
pub(super) struct Located {
    /// Arclength from the step's start.
    s: f64,
    slot: usize,
    chart: Chart,
    located: bool,
    accuracy: f64,
}
