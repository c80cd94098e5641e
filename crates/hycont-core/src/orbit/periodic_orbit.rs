//! A hybrid periodic orbit: signature, segment start states, durations and parameters.

use super::flow::{GuardedFlow, SegmentFlow};
use super::signature::{SegmentEnd, SegmentSpec, Signature};
use crate::error::{Error, Result, check_finite, check_len};
use crate::simulate::{SimulationSettings, Simulator, StopReason, TimeSeries, Trajectory};
use crate::system::{EventAction, HybridSystem, Mode};
use serde::{Deserialize, Serialize};

/// A (candidate) hybrid periodic orbit: segment $k$ starts at `starts[k]` in
/// `signature.segments()[k].mode` and lasts `durations[k]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PeriodicOrbit {
    /// The signature.
    pub signature: Signature,
    /// Start state of each segment.
    pub starts: Vec<Vec<f64>>,
    /// Duration of each segment.
    pub durations: Vec<f64>,
    /// Parameters.
    pub params: Vec<f64>,
}

/// Checks one finite start state per segment, of the dimension of the segment's mode.
fn check_starts<S: HybridSystem + ?Sized>(
    system: &S,
    signature: &Signature,
    starts: &[Vec<f64>],
) -> Result<()> {
    for (k, (x, seg)) in starts.iter().zip(signature.segments()).enumerate() {
        if seg.mode.0 >= system.mode_count() {
            return Err(Error::InvalidSignature {
                segment: k,
                reason: format!("mode {} does not exist", seg.mode),
            });
        }
        let n = system.mode_dim(seg.mode);
        if x.len() != n {
            return Err(Error::InvalidSignature {
                segment: k,
                reason: format!(
                    "the start state has {} components; mode {} has {n}",
                    x.len(),
                    seg.mode
                ),
            });
        }
        check_finite("segment start", x)?;
    }
    Ok(())
}

fn simulator(settings: &SimulationSettings) -> Result<Simulator> {
    Simulator::new(settings.clone())
}

impl PeriodicOrbit {
    /// An orbit from its parts, checked for consistent dimensions and finite values.
    /// Durations must be non-negative (zero: a segment collapsed at a grazing).
    ///
    /// # Errors
    /// Wrong dimensions, non-finite values or negative durations.
    pub fn new<S: HybridSystem + ?Sized>(
        system: &S,
        signature: Signature,
        starts: Vec<Vec<f64>>,
        durations: Vec<f64>,
        params: Vec<f64>,
    ) -> Result<Self> {
        let k = signature.len();
        if starts.len() != k || durations.len() != k {
            return Err(Error::DimensionMismatch {
                what: "segment starts/durations",
                expected: k,
                found: starts.len().min(durations.len()),
            });
        }
        check_starts(system, &signature, &starts)?;
        check_len("parameters", &params, system.parameter_count())?;
        check_finite("parameters", &params)?;
        if let Some((i, &d)) = durations
            .iter()
            .enumerate()
            .find(|(_, d)| !(d.is_finite() && **d >= 0.0))
        {
            return Err(Error::InvalidSignature {
                segment: i,
                reason: format!("duration {d} must be non-negative and finite"),
            });
        }
        Ok(Self {
            signature,
            starts,
            durations,
            params,
        })
    }

    /// The period (sum of the durations).
    #[must_use]
    pub fn period(&self) -> f64 {
        self.durations.iter().sum()
    }

    /// Number of segments.
    #[must_use]
    pub fn segment_count(&self) -> usize {
        self.durations.len()
    }

    /// The start state of segment `k` as a vector (`None` if there is no such segment).
    #[must_use]
    pub fn start(&self, k: usize) -> Option<nalgebra::DVector<f64>> {
        self.starts
            .get(k)
            .map(|x| nalgebra::DVector::from_column_slice(x))
    }

    /// The saltation matrices at the ends of the segments (identities at interior points), from
    /// the segments' end states (integrated with `settings`): the factors $S_k$ of the monodromy
    /// $M = S_{K-1}\Phi_{K-1} \cdots S_0\Phi_0$.
    ///
    /// # Errors
    /// If the orbit does not fit the system or cannot be integrated.
    pub fn saltation_matrices<S: crate::system::HybridJacobians + ?Sized>(
        &self,
        system: &S,
        settings: &SimulationSettings,
    ) -> Result<Vec<nalgebra::DMatrix<f64>>> {
        self.validate(system)?;
        let needs = super::ScanNeeds {
            ends: true,
            ..super::ScanNeeds::default()
        };
        let scanned = super::scan(system, self, &needs, settings)?;
        Ok((0..self.segment_count())
            .map(|k| super::floquet::saltation_matrix(system, self, k, &scanned.ends[k]))
            .collect())
    }

    /// Builds an orbit from the tail of a simulation that has converged to a periodic orbit:
    /// the last jump is matched with the latest earlier jump of the same event whose post-jump
    /// state agrees to `tol` (relative, max-norm); the jumps in between define the signature,
    /// durations and start states. The trajectory must have recorded its events.
    ///
    /// A tail that is not a periodic orbit is refused: a simulation that stopped at a Zeno
    /// accumulation or a terminal event, a cycle with a Zeno transition in it or after it (the
    /// tail is not the cycle), a cycle shorter than the one before it by the simulator's Zeno
    /// ratio ([`crate::ZenoSettings::max_ratio`]) and a cycle with a segment shorter than event
    /// location resolves ($10^{-10} \max(1, |t|)$): jumps accumulating, not repeating.
    ///
    /// # Errors
    /// [`Error::NotPeriodic`] naming the reason: no repetition within `tol`, or one of the
    /// above.
    pub fn from_simulation<S: HybridSystem + ?Sized>(
        system: &S,
        trajectory: &Trajectory,
        params: &[f64],
        tol: f64,
    ) -> Result<Self> {
        let not_periodic = |reason: String| Err(Error::NotPeriodic { reason });
        match trajectory.stop {
            StopReason::ZenoAccumulation { event, t } => {
                return not_periodic(format!(
                    "the simulation stopped where jumps of {event} accumulate (Zeno) at t = {t}: \
                     its tail converges to a point of accumulation, not to a periodic orbit"
                ));
            }
            StopReason::TerminalEvent { event, t } => {
                return not_periodic(format!(
                    "the simulation ended at the terminal {event} at t = {t}: its tail is not \
                     periodic"
                ));
            }
            StopReason::EndReached | StopReason::StepLimit { .. } => {}
        }
        let ev = &trajectory.events;
        let jumps: Vec<_> = ev.iter().filter(|e| e.mode_after.is_some()).collect();
        let Some(last) = jumps.last() else {
            return Err(Error::NotPeriodic {
                reason: "the trajectory has no jumps".into(),
            });
        };
        let close = |a: &[f64], b: &[f64]| {
            let scale = 1.0 + a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            a.iter().zip(b).all(|(u, v)| (u - v).abs() <= tol * scale)
        };
        let i_last = jumps.len() - 1;
        let Some(i_prev) = (0..i_last).rev().find(|&j| {
            jumps[j].event == last.event && close(&jumps[j].state_after, &last.state_after)
        }) else {
            return Err(Error::NotPeriodic {
                reason: format!(
                    "no earlier jump of {} repeats the last post-jump state to {tol:e}",
                    last.event
                ),
            });
        };
        let cycle = &jumps[i_prev..=i_last];
        let (t0, t1) = (cycle[0].t, last.t);
        if let Some(z) = trajectory.zeno.iter().find(|z| z.t >= t0) {
            return not_periodic(format!(
                "a Zeno transition at t = {} (to mode {}) follows the repeating jumps at t = {t0} \
                 and {t1}: the tail is not that cycle",
                z.t, z.mode_after
            ));
        }
        // Jumps that accumulate repeat their states ever more closely in ever shorter cycles:
        // the cycle before this one, if recorded, lasts about as long in a periodic tail, and
        // longer by the simulator's Zeno ratio (0.95) or more where jumps accumulate.
        let len = i_last - i_prev;
        if i_prev >= len {
            let before = t0 - jumps[i_prev - len].t;
            let ratio = (t1 - t0) / before;
            if ratio < crate::simulate::ZenoSettings::default().max_ratio {
                return not_periodic(format!(
                    "the repeating jumps at t = {t0} and {t1} come {:e} apart, {ratio:.3} times \
                     the cycle before: the jumps accumulate rather than repeat",
                    t1 - t0
                ));
            }
        }
        for (k, w) in cycle.windows(2).enumerate() {
            let d = w[1].t - w[0].t;
            if !(d > 1e-10 * w[1].t.abs().max(1.0)) {
                return not_periodic(format!(
                    "segment {k} of the repeating cycle lasts {d:e} (from t = {}): shorter \
                     than events are located, so the jumps accumulate rather than repeat",
                    w[0].t
                ));
            }
        }
        let mut segments = Vec::new();
        let mut starts = Vec::new();
        let mut durations = Vec::new();
        for w in cycle.windows(2) {
            segments.push(SegmentSpec {
                mode: w[0].mode_after.expect("jumps have a target mode"),
                end: SegmentEnd::Event(w[1].event),
            });
            starts.push(w[0].state_after.clone());
            durations.push(w[1].t - w[0].t);
        }
        let signature = Signature::new(system, segments)?;
        Self::new(system, signature, starts, durations, params.to_vec())
    }

    /// The same orbit with its segments rotated so that it starts right after `event` (its last
    /// segment ends at `event`): e.g. to fix the index of the segment an impact ends, whatever
    /// the point where a simulation was read off ([`PeriodicOrbit::from_simulation`]).
    ///
    /// # Errors
    /// [`Error::InvalidSignature`] if no segment ends at `event`, or the orbit is a half orbit
    /// (its closure ties its first segment to its last).
    pub fn starting_after<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        event: crate::system::EventId,
    ) -> Result<Self> {
        let segs = self.signature.segments();
        let k = segs
            .iter()
            .position(|s| s.end == SegmentEnd::Event(event))
            .ok_or_else(|| Error::InvalidSignature {
                segment: 0,
                reason: format!("no segment ends at {event}"),
            })?;
        self.rotated(system, (k + 1) % segs.len())
    }

    /// The same orbit with segment `first` first (a full orbit's segments in cyclic order).
    ///
    /// # Errors
    /// [`Error::InvalidSignature`] for a half orbit (its closure ties its first segment to its
    /// last) or a segment that does not exist.
    pub(crate) fn rotated<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        first: usize,
    ) -> Result<Self> {
        let segs = self.signature.segments();
        if self.signature.closure() != super::Closure::Periodic || first >= segs.len() {
            return Err(Error::InvalidSignature {
                segment: first,
                reason: "only a full orbit's segments can be rotated, to one of its segments"
                    .into(),
            });
        }
        let order: Vec<usize> = (first..segs.len()).chain(0..first).collect();
        let signature = Signature::new(system, order.iter().map(|&i| segs[i]).collect())?;
        Self::new(
            system,
            signature,
            order.iter().map(|&i| self.starts[i].clone()).collect(),
            order.iter().map(|&i| self.durations[i]).collect(),
            self.params.clone(),
        )
    }

    /// Builds an orbit by integrating from `x0` along `signature` (each segment until its end
    /// condition, at most `max_duration` long), e.g. from a guess of one point of the orbit.
    /// The last segment's end state need not return to `x0`: Newton closes the orbit.
    ///
    /// Every other event of a segment's mode is watched: a flow that meets one before the
    /// segment's end does not follow the signature (a segment is missing there, or the
    /// signature has one too many), and no orbit with this signature passes near `x0`.
    ///
    /// # Errors
    /// [`Error::InvalidSignature`] naming the segment, the event met first and when, or a
    /// segment that does not reach its end condition within `max_duration`; integration
    /// failures.
    pub fn from_initial_state<S: HybridSystem + ?Sized>(
        system: &S,
        signature: Signature,
        x0: &[f64],
        params: &[f64],
        max_duration: f64,
        settings: &SimulationSettings,
    ) -> Result<Self> {
        let mut sim = simulator(settings)?;
        follow(&mut sim, system, signature, x0, params, max_duration).map(|(orbit, _)| orbit)
    }

    /// Splits every segment at the interior points where state component `component` crosses
    /// `value` (e.g. $\psi = 0$: the extrema of $\varphi$), by integrating each segment.
    ///
    /// # Errors
    /// If integration fails.
    pub fn with_interior_points<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        component: usize,
        value: f64,
        settings: &SimulationSettings,
    ) -> Result<Self> {
        let mut sim = simulator(&settings.clone().record_events(true))?;
        let mut segments = Vec::new();
        let mut starts = Vec::new();
        let mut durations = Vec::new();
        for (k, seg) in self.signature.segments().iter().enumerate() {
            let flow = SegmentFlow {
                system,
                mode: seg.mode,
                stop: None,
                split: Some((component, value)),
                time_sign: 1.0,
            };
            let traj = sim.run(
                &flow,
                Mode(0),
                0.0,
                &self.starts[k],
                &self.params,
                self.durations[k],
            )?;
            let mut t_prev = 0.0;
            let mut x_prev = self.starts[k].clone();
            // Crossings too close to the segment's ends are the end's own (e.g. psi = 0 at a
            // grazing impact); keep interior ones only.
            let margin = 1e-9 * self.durations[k].max(1.0);
            for e in &traj.events {
                if e.t <= margin || e.t >= self.durations[k] - margin {
                    continue;
                }
                segments.push(SegmentSpec {
                    mode: seg.mode,
                    end: SegmentEnd::Interior { component, value },
                });
                starts.push(x_prev.clone());
                durations.push(e.t - t_prev);
                t_prev = e.t;
                x_prev.clone_from(&e.state_after);
            }
            segments.push(*seg);
            starts.push(x_prev);
            durations.push(self.durations[k] - t_prev);
        }
        let signature = Signature::with_closure(system, segments, self.signature.closure())?;
        Self::new(system, signature, starts, durations, self.params.clone())
    }

    /// Merges interior points back: the orbit with events only (durations summed).
    ///
    /// # Errors
    /// Never for a valid orbit (kept fallible for signature validation).
    pub fn without_interior_points<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<Self> {
        let k = self.segment_count();
        // Start at a segment that follows an event, so that merged segments do not wrap.
        let first = (0..k)
            .find(|&i| {
                matches!(
                    self.signature.segments()[(i + k - 1) % k].end,
                    SegmentEnd::Event(_)
                )
            })
            .unwrap_or(0);
        let mut segments = Vec::new();
        let mut starts = Vec::new();
        let mut durations: Vec<f64> = Vec::new();
        let mut open = false;
        for j in 0..k {
            let i = (first + j) % k;
            let seg = self.signature.segments()[i];
            if !open {
                starts.push(self.starts[i].clone());
                durations.push(0.0);
                open = true;
            }
            *durations.last_mut().expect("pushed above") += self.durations[i];
            if let SegmentEnd::Event(_) = seg.end {
                segments.push(seg);
                open = false;
            }
        }
        if open {
            // No event at all: a smooth orbit split at interior points only.
            let seg = self.signature.segments()[(first + k - 1) % k];
            segments.push(seg);
        }
        let signature = Signature::new(system, segments)?;
        Self::new(system, signature, starts, durations, self.params.clone())
    }

    /// Dense samples of each segment (`points` per segment, both ends included; a zero-length
    /// segment its one point), e.g. for plots.
    ///
    /// # Errors
    /// If integration fails.
    pub fn sample<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        points: usize,
        settings: &SimulationSettings,
    ) -> Result<Vec<TimeSeries>> {
        let points = points.max(2);
        let mut out = Vec::new();
        let mut t0 = 0.0;
        for (k, seg) in self.signature.segments().iter().enumerate() {
            let d = self.durations[k];
            if d == 0.0 {
                // A zero-length segment: its one point.
                let mut ts = TimeSeries::new(system.mode_dim(seg.mode));
                ts.push(t0, seg.mode, &self.starts[k]);
                out.push(ts);
                continue;
            }
            let s = settings
                .clone()
                .samples(crate::SampleTimes::new(0.0, d / (points - 1) as f64));
            let mut sim = simulator(&s)?;
            let flow = SegmentFlow::plain(system, seg.mode);
            let traj = sim.run(&flow, Mode(0), 0.0, &self.starts[k], &self.params, d)?;
            let mut ts = TimeSeries::new(system.mode_dim(seg.mode));
            for (t, _, x) in traj.samples.iter() {
                ts.push(t0 + t, seg.mode, x);
            }
            t0 += d;
            out.push(ts);
        }
        Ok(out)
    }

    /// Checks the orbit against `system`: the signature still matches its events (e.g. after
    /// editing), one finite start state of the system's dimension and one finite duration per
    /// segment, and the system's number of finite parameters.
    ///
    /// # Errors
    /// As [`Signature::new`]; [`Error::DimensionMismatch`] or [`Error::NonFinite`] naming the
    /// bad value.
    pub fn validate<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<()> {
        let k = self.signature.len();
        if self.starts.len() != k || self.durations.len() != k {
            return Err(Error::DimensionMismatch {
                what: "segment starts/durations",
                expected: k,
                found: self.starts.len().min(self.durations.len()),
            });
        }
        check_starts(system, &self.signature, &self.starts)?;
        check_finite("durations", &self.durations)?;
        check_len("parameters", &self.params, system.parameter_count())?;
        check_finite("parameters", &self.params)?;
        Signature::with_closure(
            system,
            self.signature.segments().to_vec(),
            self.signature.closure(),
        )
        .map(|_| ())?;
        for seg in self.signature.segments() {
            if let SegmentEnd::Event(e) = seg.end
                && system.event_spec(e).action == EventAction::Terminal
            {
                return Err(Error::InvalidSignature {
                    segment: 0,
                    reason: "terminal event in a periodic orbit".into(),
                });
            }
        }
        Ok(())
    }
}

/// Follows `x0` along `signature` (each segment until its end condition, at most
/// `max_duration`) with `sim`: the orbit of [`PeriodicOrbit::from_initial_state`] and the state
/// after the last segment's end (after its jump). A segment whose flow meets another event of
/// its mode first is an error (the trajectory leaves the signature there).
pub(crate) fn follow<S: HybridSystem + ?Sized>(
    sim: &mut Simulator,
    system: &S,
    signature: Signature,
    x0: &[f64],
    params: &[f64],
    max_duration: f64,
) -> Result<(PeriodicOrbit, Vec<f64>)> {
    let first = signature.segments()[0].mode;
    check_len("initial state", x0, system.mode_dim(first))?;
    let mut x = x0.to_vec();
    let mut starts = Vec::new();
    let mut durations = Vec::new();
    for (k, seg) in signature.segments().iter().enumerate() {
        starts.push(x.clone());
        let flow = GuardedFlow::new(system, seg.mode, seg.end);
        let traj = sim.run(&flow, Mode(0), 0.0, &x, params, max_duration)?;
        let guard = match traj.stop {
            StopReason::TerminalEvent { event, .. } => flow.guard(event),
            _ => None,
        };
        let reason = match (traj.stop, guard) {
            (StopReason::TerminalEvent { t, .. }, None) => {
                durations.push(t);
                None
            }
            (StopReason::TerminalEvent { t, .. }, Some(e)) => Some(format!(
                "the flow from {x:?} meets event {:?} at t = {t} before the segment's end \
                 (the signature misses a segment there, or has one too many)",
                system.event_spec(e).name
            )),
            _ => Some(format!(
                "the end condition is not reached within {max_duration} from {x:?}"
            )),
        };
        if let Some(reason) = reason {
            return Err(Error::InvalidSignature { segment: k, reason });
        }
        x.clone_from(&traj.state_final);
        if let SegmentEnd::Event(e) = seg.end {
            let mut y = vec![f64::NAN; crate::system::reset_dim(system, e, x.len())];
            system.reset(e, &x, params, &mut y);
            x = y;
        }
    }
    let orbit = PeriodicOrbit::new(system, signature, starts, durations, params.to_vec())?;
    Ok((orbit, x))
}

/// Sets to zero the durations a solve left negative by no more than its resolution
/// `resolution` (the Newton step tolerance $\text{tol}\,(1 + \|u\|_\infty)$,
/// [`crate::problem::NewtonSettings::resolution`]): segments of zero length, e.g. the flight
/// of no time a grazing orbit has in the signature beyond it. There the family that keeps the
/// segment at zero length crosses the one that changes its duration (a branch point), and a
/// solve at fixed parameters moves the duration by rounding either way; the orbit itself is
/// the same to the solve's tolerance. Larger negative durations are left for the caller to
/// refuse or locate.
pub(crate) fn settle_zero_durations(durations: &mut [f64], resolution: f64) {
    for d in durations {
        if *d < 0.0 && *d >= -resolution {
            *d = 0.0;
        }
    }
}

#[cfg(test)]
mod tests {
    /// Within the resolution below zero: zero; beyond it, positive, or not finite: unchanged.
    #[test]
    fn durations_a_rounding_below_zero_are_zero() {
        let mut d = [-1e-12, -1e-10, -1.1e-10, 0.0, 2e-12, 1.5, f64::NAN];
        super::settle_zero_durations(&mut d, 1e-10);
        assert_eq!(&d[..6], &[0.0, 0.0, -1.1e-10, 0.0, 2e-12, 1.5]);
        assert!(d[6].is_nan());
    }
}
