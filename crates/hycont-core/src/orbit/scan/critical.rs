//! The critical points a scan reports: those the integration's events found in a segment
//! (classified as minima or maxima, recorded once) and those at segment boundaries that are
//! interior points of the signature.

use super::{CriticalPoint, OrbitScan, ScanFlow, Turn, Watch, applies, boundary_margin, watched};
use crate::orbit::PeriodicOrbit;
use crate::orbit::signature::SegmentEnd;
use crate::system::{HybridJacobians, HybridSystem, Mode};

/// Segment `k` of a scan: its watches and the boundary critical points already registered.
pub(super) struct SegmentScan<'s> {
    pub(super) orbit: &'s PeriodicOrbit,
    pub(super) k: usize,
    pub(super) watches: &'s [Watch],
    pub(super) boundary: &'s [CriticalPoint],
}

impl SegmentScan<'_> {
    /// Adds the critical points the scan's `events` found in the segment: each event's watched
    /// function, and the other watched functions critical at the same point (the simulator
    /// restarts on their zero and does not report them); not the points within
    /// [`BOUNDARY_BAND`] of a boundary registered as that function's critical point.
    pub(super) fn record<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        flow: &ScanFlow<'_, S>,
        events: &[crate::simulate::EventRecord],
        critical: &mut Vec<CriticalPoint>,
    ) {
        let (orbit, k, n) = (self.orbit, self.k, flow.n);
        let duration = orbit.durations[k];
        let mode = flow.mode;
        let segments = orbit.signature.segments().len();
        let margin = boundary_margin(duration);
        // Work space: the field and a gradient at an event's state.
        let mut work = vec![0.0; 2 * n];
        for e in events {
            let first = flow.watches[e.event.0];
            // Inside the band at an end, the point is the boundary's when the boundary was
            // registered as this function's critical point (its exact state); otherwise it is
            // kept (a start slightly off its split, e.g. during Newton's iterations).
            let registered = |segment: usize| {
                self.boundary
                    .iter()
                    .any(|c| c.segment == segment && c.watch == first)
            };
            if (e.t <= margin && registered(k))
                || (e.t >= duration - margin && registered((k + 1) % segments))
            {
                continue;
            }
            let state = &e.state_before[..n];
            let turn = classify(system, first, mode, state, &orbit.params);
            push_unique(critical, system, orbit, first, turn, (k, e.t), state);
            let scale = 1.0 + state.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for &w in self.watches.iter().filter(|&&w| w != first) {
                let (f, g) = work.split_at_mut(n);
                let rate = watched(system, w, mode, state, &orbit.params, f, g).1;
                if rate.abs() <= 1e-9 * scale {
                    let turn = classify(system, w, mode, state, &orbit.params);
                    push_unique(critical, system, orbit, w, turn, (k, e.t), state);
                }
            }
        }
    }
}

/// Adds the critical points that are segment boundaries of the signature: the start of a
/// segment that follows an interior point (the state is continuous there) where a watched
/// function's rate vanishes to $10^{-6}$ relative to $|\nabla q| |f|$ (a start that is
/// critical only to that tolerance changes the value at second order), classified by the sign
/// of the rate a short way ($10^{-6}$ relative) along the flow on either side.
pub(super) fn boundary_points<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    watches: &[Watch],
    out: &mut OrbitScan,
) {
    let segs = orbit.signature.segments();
    let kk = segs.len();
    let p = &orbit.params;
    for k in 0..kk {
        let before = (k + kk - 1) % kk;
        if !matches!(segs[before].end, SegmentEnd::Interior { .. }) || orbit.durations[k] < 0.0 {
            continue;
        }
        let mode = segs[k].mode;
        let n = system.mode_dim(mode);
        let (mut f, mut grad) = (vec![0.0; n], vec![0.0; n]);
        let x = &orbit.starts[k];
        for &w in watches.iter().filter(|&&w| applies(system, w, mode)) {
            let (value, rate) = watched(system, w, mode, x, p, &mut f, &mut grad);
            let gnorm = match w {
                Watch::Component(_) => 1.0,
                Watch::Event(_) => grad.iter().map(|g| g * g).sum::<f64>().sqrt(),
            };
            let fnorm = f.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !(rate.abs() <= 1e-6 * (gnorm * fnorm).max(f64::MIN_POSITIVE)) {
                continue;
            }
            let turn = classify(system, w, mode, x, p);
            out.critical.push(CriticalPoint {
                watch: w,
                turn,
                segment: k,
                t: 0.0,
                state: x.clone(),
                value,
            });
        }
    }
}

/// Whether a critical point of `watch` at `x` is a minimum or a maximum: the sign of the change
/// of its rate a short way ($10^{-6}$ relative) along the flow on either side.
fn classify<S: HybridJacobians + ?Sized>(
    system: &S,
    watch: Watch,
    mode: Mode,
    x: &[f64],
    p: &[f64],
) -> Turn {
    let n = x.len();
    // Work space: the direction (the field at x), the field and a gradient at a shifted state,
    // the shifted state.
    let mut work = vec![0.0; 4 * n];
    let (dir, rest) = work.split_at_mut(n);
    let (f, rest) = rest.split_at_mut(n);
    let (g, shifted) = rest.split_at_mut(n);
    system.vector_field(mode, x, p, dir);
    let fnorm = dir.iter().map(|v| v * v).sum::<f64>().sqrt();
    let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    let dt = 1e-6 * scale / fnorm.max(f64::MIN_POSITIVE);
    let mut rate_at = |sign: f64| {
        for ((s, a), b) in shifted.iter_mut().zip(x).zip(&*dir) {
            *s = a + sign * dt * b;
        }
        watched(system, watch, mode, shifted, p, f, g).1
    };
    if rate_at(1.0) - rate_at(-1.0) > 0.0 {
        Turn::Min
    } else {
        Turn::Max
    }
}

/// Records a critical point unless the same one (watch, segment, turn, time to
/// $10^{-8} \max(1, T_k)$) is already recorded.
fn push_unique<S: HybridSystem + ?Sized>(
    critical: &mut Vec<CriticalPoint>,
    system: &S,
    orbit: &PeriodicOrbit,
    watch: Watch,
    turn: Turn,
    (segment, t): (usize, f64),
    state: &[f64],
) {
    let tol = 1e-8 * orbit.durations[segment].abs().max(1.0);
    if critical.iter().any(|c| {
        c.watch == watch && c.segment == segment && c.turn == turn && (c.t - t).abs() <= tol
    }) {
        return;
    }
    let value = match watch {
        Watch::Component(c) => state[c],
        Watch::Event(e) => system.event(e, state, &orbit.params),
    };
    critical.push(CriticalPoint {
        watch,
        turn,
        segment,
        t,
        state: state.to_vec(),
        value,
    });
}
