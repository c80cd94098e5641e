//! Driving a run of an [`OrbitRun`]: one PALC for both directions, joined into one branch,
//! with user points at the start.

use super::run::{OrbitRun, RunDirection};
use crate::branch::{Branch, BranchPoint, EndReason, SpecialKind, SpecialPoint};
use crate::error::Result;
use crate::observe::Observer;
use crate::palc::Palc;
use crate::settings::ContinuationSettings;
use crate::{ContinuationProblem, MonitorEvent};
use hycont_core::HybridJacobians;

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// Runs `cp` from `u0` in `direction` with `settings` (along `start.1` from the point
    /// `start.0`, which then begins each run, when given), joined both ways, with the runs'
    /// end points and user points at the start; points in the full orbit's unknowns for a half
    /// orbit problem is left to the caller.
    pub(super) fn continue_in<P: ContinuationProblem<'a> + ?Sized>(
        &mut self,
        cp: &mut P,
        name: &str,
        u0: &[f64],
        start: Option<(&BranchPoint, &[f64])>,
        direction: RunDirection,
        settings: &ContinuationSettings,
    ) -> Result<Branch> {
        let user_points: Vec<MonitorEvent> = cp
            .monitor_events()
            .into_iter()
            .filter(|e| e.kind == SpecialKind::UserPoint)
            .collect();
        let observer = self.observer.as_mut();
        // One driver for both directions: they share the layout and, from a start without a
        // direction, the first chart.
        let mut palc = Palc::new(cp, settings.clone())?;
        let mut go = |sign: f64, observer: &mut dyn Observer| -> Result<Branch> {
            Ok(match start {
                None => palc.run(name, u0, None, sign, observer)?,
                Some((point, t)) => {
                    let mut b = palc.run(name, u0, Some(t), sign, observer)?;
                    b.points.insert(0, point.clone());
                    b
                }
            })
        };
        Ok(match direction {
            RunDirection::Up | RunDirection::Down => {
                let sign = if direction == RunDirection::Up {
                    1.0
                } else {
                    -1.0
                };
                let mut b = go(sign, observer)?;
                mark_start(&mut b, None, &user_points);
                closed(b)
            }
            RunDirection::Both => {
                let mut back = go(-1.0, observer)?;
                if back.end == EndReason::Stopped {
                    // Asked to stop: the way run so far.
                    mark_start(&mut back, None, &user_points);
                    back.relabel();
                    back
                } else if back.end == EndReason::Closed {
                    mark_start(&mut back, None, &user_points);
                    closed(back)
                } else {
                    let mut fwd = go(1.0, observer)?;
                    mark_start(&mut fwd, Some(&mut back), &user_points);
                    Branch::joined(name, back, fwd)
                }
            }
        })
    }
}

fn closed(mut b: Branch) -> Branch {
    b.close_end();
    b
}

/// Reports the start of a run as a user point when it lies on a user point's level (to
/// $10^{-12}$ relative): a run's test functions only see levels crossed after its start. The
/// same crossing located within rounding of the start by the first step of `run` or of the
/// other run from the same start (`other`) is dropped.
fn mark_start(run: &mut Branch, other: Option<&mut Branch>, user_points: &[MonitorEvent]) {
    let Some(p) = run.points.first().cloned() else {
        return;
    };
    let param = run.parameter_of(&p);
    let marks: Vec<SpecialPoint> = user_points
        .iter()
        .filter(|e| {
            p.get(e.on)
                .is_some_and(|v| (v - e.level).abs() <= 1e-12 * e.level.abs().max(1.0))
        })
        .map(|e| SpecialPoint {
            kind: SpecialKind::UserPoint,
            point: p.clone(),
            bracket: (param, param),
            located: true,
            accuracy: 0.0,
            on: Some(e.on),
            level: Some(e.level),
            critical: None,
        })
        .collect();
    let near = |s: &SpecialPoint| {
        marks.iter().any(|m| {
            s.kind == SpecialKind::UserPoint
                && s.on == m.on
                && s.level == m.level
                && s.point
                    .params
                    .iter()
                    .zip(&p.params)
                    .all(|(a, b)| (a - b).abs() <= 1e-9 * b.abs().max(1.0))
        })
    };
    run.special_points.retain(|s| !near(s));
    if let Some(other) = other {
        other.special_points.retain(|s| !near(s));
    }
    run.special_points.splice(0..0, marks);
}
