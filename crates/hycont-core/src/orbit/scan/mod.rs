//! One integration pass over an orbit's segments that collects what measures need: each
//! segment's end state (before its jump), the critical points of scalar functions along the
//! flow, and integrals of state components.
//!
//! A critical point of $q(x)$ along the flow of mode $m$ is a zero of
//! $\dot q = \nabla q(x) \cdot f_m(x)$: a local minimum where $\dot q$ rises through zero, a
//! local maximum where it falls. They are located as events on the dense output (to the
//! simulator's event tolerance). Segment boundaries that are interior points of the signature
//! (state continuous, e.g. a split at $\psi = 0$) are critical points when $\dot q$ vanishes
//! there; those are reported with the exact state of the orbit's unknowns.

mod critical;

use super::PeriodicOrbit;
use crate::error::{Error, Result};
use crate::simulate::{SimulationSettings, Simulator, StopReason, ZenoSettings};
use crate::system::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode,
};
use critical::{SegmentScan, boundary_points};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;

/// A scalar function of the state whose critical points along the flow a scan reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Watch {
    /// State component $x_c$ (critical where $f_c(x) = 0$).
    Component(usize),
    /// The event function $h_e(x, p)$, in the modes that monitor the event (critical where
    /// $\nabla h_e \cdot f = 0$).
    Event(EventId),
}

/// Whether a critical point is a local minimum or maximum of the watched function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Turn {
    /// A local minimum.
    Min,
    /// A local maximum.
    Max,
}

/// A critical point of a watched function along a segment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CriticalPoint {
    /// The watched function.
    pub watch: Watch,
    /// Minimum or maximum.
    pub turn: Turn,
    /// The segment it lies in (a boundary point belongs to the segment it starts).
    pub segment: usize,
    /// Time from the segment's start.
    pub t: f64,
    /// The state there.
    pub state: Vec<f64>,
    /// The value of the watched function there.
    pub value: f64,
}

/// What a scan must collect (the union of what a set of measures needs).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ScanNeeds {
    /// Functions whose critical points are wanted.
    pub watches: Vec<Watch>,
    /// State components whose integrals over each segment are wanted.
    pub integrals: Vec<usize>,
    /// Whether the segments' end states are wanted (a scan always has them; a measure that
    /// needs nothing else asks for this).
    pub ends: bool,
}

impl ScanNeeds {
    /// Adds `other`'s needs (without duplicates).
    pub fn merge(&mut self, other: &ScanNeeds) {
        for w in &other.watches {
            if !self.watches.contains(w) {
                self.watches.push(*w);
            }
        }
        for c in &other.integrals {
            if !self.integrals.contains(c) {
                self.integrals.push(*c);
            }
        }
        self.ends |= other.ends;
    }

    /// Whether anything needs integrating.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.watches.is_empty() && self.integrals.is_empty() && !self.ends
    }
}

/// The result of [`scan`].
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct OrbitScan {
    /// End state of each segment, before its jump.
    pub ends: Vec<Vec<f64>>,
    /// Critical points of the watched functions, by segment and time.
    pub critical: Vec<CriticalPoint>,
    /// `integrals[k][i]`: the integral over segment `k` of the `i`-th component of
    /// [`ScanNeeds::integrals`].
    pub integrals: Vec<Vec<f64>>,
    /// The components integrated, in the order of `integrals[k]`.
    pub integrated: Vec<usize>,
}

impl OrbitScan {
    /// The critical points of one watched function.
    pub fn critical_of(&self, watch: Watch) -> impl Iterator<Item = &CriticalPoint> {
        self.critical.iter().filter(move |c| c.watch == watch)
    }

    /// The integral of state component `component` over the whole orbit, if it was integrated.
    #[must_use]
    pub fn integral(&self, component: usize) -> Option<f64> {
        let i = self.integrated.iter().position(|&c| c == component)?;
        Some(self.integrals.iter().map(|v| v[i]).sum())
    }
}

/// The value of a watched function and its rate $\dot q = \nabla q \cdot f$ along the flow of
/// `mode`.
pub(crate) fn watched<S: HybridJacobians + ?Sized>(
    system: &S,
    watch: Watch,
    mode: Mode,
    x: &[f64],
    p: &[f64],
    f: &mut [f64],
    grad: &mut [f64],
) -> (f64, f64) {
    system.vector_field(mode, x, p, f);
    match watch {
        Watch::Component(c) => (x[c], f[c]),
        Watch::Event(e) => {
            system.event_gradient(e, x, p, grad, None);
            let rate = grad.iter().zip(f.iter()).map(|(a, b)| a * b).sum();
            (system.event(e, x, p), rate)
        }
    }
}

/// Whether `watch` applies in `mode` (events only where the mode monitors them).
fn applies<S: HybridSystem + ?Sized>(system: &S, watch: Watch, mode: Mode) -> bool {
    match watch {
        // A component of a state some modes do not have is watched where it exists.
        Watch::Component(c) => c < system.mode_dim(mode),
        Watch::Event(e) => system.events(mode).contains(&e),
    }
}

/// Checks that every watch and integral refers to the system.
///
/// # Errors
/// [`Error::InvalidMeasure`] naming the bad component or event.
pub fn check_needs<S: HybridSystem + ?Sized>(system: &S, needs: &ScanNeeds) -> Result<()> {
    let n = system.state_dim();
    let monitored =
        |e: &EventId| (0..system.mode_count()).any(|m| system.events(Mode(m)).contains(e));
    for w in &needs.watches {
        match *w {
            Watch::Component(c) if c >= n => {
                return Err(Error::InvalidMeasure {
                    reason: format!("state component {c} does not exist (dimension {n})"),
                });
            }
            Watch::Event(e) if !monitored(&e) => {
                return Err(Error::InvalidMeasure {
                    reason: format!("{e} is not monitored in any mode of the system"),
                });
            }
            _ => {}
        }
    }
    // An integrated component must exist in every mode the orbit may visit.
    let common = (0..system.mode_count())
        .map(|m| system.mode_dim(Mode(m)))
        .min()
        .unwrap_or(n);
    if let Some(c) = needs.integrals.iter().find(|&&c| c >= common) {
        return Err(Error::InvalidMeasure {
            reason: format!(
                "state component {c} is not in every mode's state (the smallest has {common} components): its integral over an orbit is undefined"
            ),
        });
    }
    Ok(())
}

/// One segment's mode as a system for the scan: the state extended by the integrals, and one
/// recorded identity event per watched function (its rate $\dot q$ crossing zero either way;
/// whether it is a minimum or a maximum is classified at the few points found).
struct ScanFlow<'a, S: ?Sized> {
    system: &'a S,
    mode: Mode,
    n: usize,
    watches: Vec<Watch>,
    /// Per watch: the state component its rate is, where the system's hints say so
    /// ([`HybridSystem::rate_component`], [`HybridSystem::event_component`]).
    rate_of: Vec<Option<usize>>,
    integrals: &'a [usize],
    ids: Vec<EventId>,
    /// `-1.0` integrates backward (a negative duration).
    time_sign: f64,
    /// The rates of all watched functions at the last state asked for: the simulator evaluates
    /// every event at the same state in turn, and one vector field serves them all.
    rates: RefCell<Rates>,
}

/// See [`ScanFlow::rates`].
struct Rates {
    x: Vec<f64>,
    values: Vec<f64>,
    f: Vec<f64>,
    grad: Vec<f64>,
    valid: bool,
}

impl<S: HybridJacobians + ?Sized> HybridSystem for ScanFlow<'_, S> {
    fn state_dim(&self) -> usize {
        self.n + self.integrals.len()
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
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "critical point",
            direction: Direction::Either,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        let n = self.n;
        self.system
            .vector_field(self.mode, &x[..n], p, &mut out[..n]);
        for (i, &c) in self.integrals.iter().enumerate() {
            out[n + i] = x[c];
        }
        if self.time_sign < 0.0 {
            for v in out.iter_mut() {
                *v = -*v;
            }
        }
    }
    /// A watch whose rate is a state component is that component's surface: the simulator
    /// then interpolates that component alone and takes the rate from the vector field.
    fn event_component(&self, event: EventId) -> Option<usize> {
        self.rate_of.get(event.0).copied().flatten()
    }
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        if let Some(j) = self.rate_of[event.0] {
            return x[j];
        }
        let mut r = self.rates.borrow_mut();
        let x = &x[..self.n];
        if !(r.valid && r.x == x) {
            let Rates {
                f, grad, values, ..
            } = &mut *r;
            self.system.vector_field(self.mode, x, p, f);
            values.clear();
            for &w in &self.watches {
                values.push(match w {
                    Watch::Component(c) => f[c],
                    Watch::Event(e) => {
                        self.system.event_gradient(e, x, p, grad, None);
                        grad.iter().zip(f.iter()).map(|(a, b)| a * b).sum()
                    }
                });
            }
            r.x.clear();
            r.x.extend_from_slice(x);
            r.valid = true;
        }
        r.values[event.0]
    }
}

/// Relative width of the band at each end of a segment in which critical points found by
/// integration belong to the boundary (see [`scan`]).
pub const BOUNDARY_BAND: f64 = 1e-6;

/// The band's width in time at the ends of a segment of duration `duration`:
/// [`BOUNDARY_BAND`]` * max(1, |T_k|)`.
pub(super) fn boundary_margin(duration: f64) -> f64 {
    BOUNDARY_BAND * duration.abs().max(1.0)
}

/// Scans `orbit` (each segment integrated once from its start for its duration): end states,
/// critical points of `needs.watches` and integrals of `needs.integrals`. Boundaries that are
/// interior points of the signature are checked directly and, when critical, reported with
/// their exact states; a critical point found by integration within
/// [`BOUNDARY_BAND`]` * max(1, T_k)` of such a boundary is that point and is not reported again.
/// The band is wider than any difference step a gradient takes, so that a critical point at a
/// split is not reported twice with values that differ by the integration error (which would
/// make a measure jump).
/// A segment with a negative duration (a continuation step past its collapse) is integrated
/// backward and contributes its end state and integrals only.
///
/// # Errors
/// Invalid needs or an integration failure.
pub fn scan<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    needs: &ScanNeeds,
    settings: &SimulationSettings,
) -> Result<OrbitScan> {
    check_needs(system, needs)?;
    scan_with(&mut scan_simulator(settings)?, system, orbit, needs)
}

/// The simulator [`scan`] integrates with at `settings` (events recorded, not conditioned, no
/// Zeno detection: a scan follows one segment's flow).
///
/// # Errors
/// Invalid settings.
pub(crate) fn scan_simulator(settings: &SimulationSettings) -> Result<Simulator> {
    Simulator::new(
        settings
            .clone()
            .record_events(true)
            .event_conditioning(false)
            .zeno(ZenoSettings {
                min_contracting: usize::MAX,
                min_interval: 0.0,
                ..ZenoSettings::default()
            }),
    )
}

/// [`scan`] with a simulator made by [`scan_simulator`], which keeps its work space from one
/// scan to the next (a run starts afresh from its inputs: the results are those of a new one).
///
/// # Errors
/// As [`scan`].
pub(crate) fn scan_with<S: HybridJacobians + ?Sized>(
    sim: &mut Simulator,
    system: &S,
    orbit: &PeriodicOrbit,
    needs: &ScanNeeds,
) -> Result<OrbitScan> {
    check_needs(system, needs)?;
    let mut out = OrbitScan {
        integrated: needs.integrals.clone(),
        ..OrbitScan::default()
    };
    let segs = orbit.signature.segments();
    let mut boundary = OrbitScan::default();
    boundary_points(system, orbit, &needs.watches, &mut boundary);
    let boundary = boundary.critical;
    for (k, seg) in segs.iter().enumerate() {
        let (duration, n) = (orbit.durations[k], system.mode_dim(seg.mode));
        // Critical points only forward (a negative duration contributes its end and integrals).
        let watches: Vec<Watch> = if duration >= 0.0 {
            needs
                .watches
                .iter()
                .copied()
                .filter(|&w| applies(system, w, seg.mode))
                .collect()
        } else {
            Vec::new()
        };
        let flow = segment_flow(system, seg.mode, &watches, &needs.integrals, duration);
        let mut x0 = orbit.starts[k].clone();
        x0.resize(n + needs.integrals.len(), 0.0);
        let traj = sim.run(&flow, Mode(0), 0.0, &x0, &orbit.params, duration.abs())?;
        if !matches!(traj.stop, StopReason::EndReached) {
            return Err(Error::InvalidSignature {
                segment: k,
                reason: format!("the scan of the segment stopped early: {:?}", traj.stop),
            });
        }
        let found = SegmentScan {
            orbit,
            k,
            watches: &watches,
            boundary: &boundary,
        };
        found.record(system, &flow, &traj.events, &mut out.critical);
        let sign = duration.signum();
        out.ends.push(traj.state_final[..n].to_vec());
        out.integrals
            .push(traj.state_final[n..].iter().map(|v| sign * v).collect());
    }
    for c in boundary {
        if !out
            .critical
            .iter()
            .any(|o| o.segment == c.segment && o.watch == c.watch && o.t == 0.0)
        {
            out.critical.push(c);
        }
    }
    out.critical
        .sort_by(|a, b| a.segment.cmp(&b.segment).then(a.t.total_cmp(&b.t)));
    Ok(out)
}

/// The flow that scans one segment in `mode` (backward for a negative `duration`): the state,
/// the integrals, and one event per group of `watches` whose rates are the same state
/// component by the system's hints (one function up to a constant: one event finds the
/// critical points of all of them; the others are added where their rate vanishes too, see
/// [`SegmentScan::record`]).
fn segment_flow<'a, S: HybridJacobians + ?Sized>(
    system: &'a S,
    mode: Mode,
    watches: &[Watch],
    integrals: &'a [usize],
    duration: f64,
) -> ScanFlow<'a, S> {
    let n = system.mode_dim(mode);
    let hinted = |w: &Watch| {
        let c = match *w {
            Watch::Component(c) => Some(c),
            Watch::Event(e) => system.event_component(e),
        };
        c.and_then(|c| system.rate_component(mode, c))
            .filter(|&j| j < n)
    };
    let mut detected: Vec<Watch> = Vec::new();
    for w in watches {
        if hinted(w).is_none() || !detected.iter().any(|d| hinted(d) == hinted(w)) {
            detected.push(*w);
        }
    }
    let rate_of = detected.iter().map(hinted).collect();
    ScanFlow {
        system,
        mode,
        n,
        ids: (0..detected.len()).map(EventId).collect(),
        rate_of,
        watches: detected,
        integrals,
        time_sign: duration.signum(),
        rates: RefCell::new(Rates {
            x: Vec::with_capacity(n),
            values: Vec::new(),
            f: vec![0.0; n],
            grad: vec![0.0; n],
            valid: false,
        }),
    }
}
