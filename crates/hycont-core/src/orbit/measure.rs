//! Measures of periodic orbits: scalar functions of an orbit recorded along branches, usable as
//! continuation parameters, event monitors and two-parameter conditions (COCO's monitor
//! functions on orbits).
//!
//! Generic measures for any hybrid system:
//! - [`Extremum`]: the true maximum, minimum or largest modulus of a state component over the
//!   orbit (segment starts and ends and the interior critical points, not mesh values);
//! - [`GrazingMargin`]: the signed margin of a trajectory's interior turning points to an event
//!   surface, zero at a grazing;
//! - [`SegmentValue`]: a state component at a segment's start or end (e.g. an impact velocity);
//! - [`TimeAverage`]: the time average of a state component;
//! - [`SegmentDuration`]: a segment's duration.
//!
//! A [`MeasureSet`] evaluates several measures with one integration pass over the orbit
//! ([`scan`]). Closures `Fn(&S, &PeriodicOrbit) -> f64` are measures too.
//!
//! ```
//! use hycont_core::orbit::{Extremum, Measure, MeasureSet, TimeAverage};
//! # use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridSystem, HybridJacobians, Mode};
//! # use hycont_core::orbit::{PeriodicOrbit, Signature, SegmentSpec, SegmentEnd};
//! # struct Osc;
//! # impl HybridSystem for Osc {
//! #     fn state_dim(&self) -> usize { 2 }
//! #     fn parameter_names(&self) -> &[&'static str] { &["w"] }
//! #     fn mode_count(&self) -> usize { 1 }
//! #     fn mode_name(&self, _: Mode) -> &'static str { "m" }
//! #     fn events(&self, _: Mode) -> &[EventId] { &[] }
//! #     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
//! #     fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
//! #         out[0] = p[0] * x[1]; out[1] = -p[0] * x[0];
//! #     }
//! #     fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 { 0.0 }
//! # }
//! # impl HybridJacobians for Osc {
//! #     fn vector_field_jacobian(&self, _: Mode, x: &[f64], p: &[f64], dx: &mut [f64], dp: Option<&mut [f64]>) {
//! #         dx.copy_from_slice(&[0.0, -p[0], p[0], 0.0]);
//! #         if let Some(dp) = dp { dp[0] = x[1]; dp[1] = -x[0]; }
//! #     }
//! #     fn event_gradient(&self, _: EventId, _: &[f64], _: &[f64], _: &mut [f64], _: Option<&mut [f64]>) {}
//! # }
//! // The circle x0 = 2 cos(t), x1 = -2 sin(t) of x0' = x1, x1' = -x0, as one segment from
//! // x1 = 0 to x1 = 0 (a full turn).
//! let sig = Signature::new(&Osc, vec![SegmentSpec {
//!     mode: Mode(0), end: SegmentEnd::Interior { component: 1, value: 0.0 } }]).unwrap();
//! let orbit = PeriodicOrbit::new(&Osc, sig, vec![vec![2.0, 0.0]],
//!                                vec![2.0 * std::f64::consts::PI], vec![1.0]).unwrap();
//! let mut set = MeasureSet::new();
//! let min = set.add("min_x0", Extremum::min(0)).unwrap();
//! let mean = set.add("mean_x0", TimeAverage::new(0)).unwrap();
//! let values = set.evaluate(&Osc, &orbit).unwrap();
//! assert!((values[min] + 2.0).abs() < 1e-9);   // the interior minimum at t = pi
//! assert!(values[mean].abs() < 1e-9);
//! ```

use super::scan::{OrbitScan, ScanNeeds, Turn, Watch};
use super::{MeasureSet, PeriodicOrbit, SegmentEnd, Touch};
use crate::error::{Error, Result};
use crate::system::{EventId, HybridJacobians, HybridSystem, Z2Symmetry};

/// A scalar measure of a periodic orbit.
pub trait Measure<S: ?Sized> {
    /// What the measure needs from the scan of the orbit (default: nothing, no integration).
    fn needs(&self) -> ScanNeeds {
        ScanNeeds::default()
    }
    /// The value on a full orbit, with the scan of [`Measure::needs`] (empty if it needs none).
    ///
    /// # Errors
    /// If the measure does not apply to the orbit (e.g. a segment index out of range).
    fn value(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64>;
    /// Whether, on a $\mathbb{Z}_2$-symmetric orbit, the value equals the value computed on its
    /// half orbit (the first half of the segments); then half orbits need not be unfolded to
    /// be measured. Default: `false`.
    fn invariant_under(&self, system: &S, symmetry: &Z2Symmetry) -> bool {
        let _ = (system, symmetry);
        false
    }
    /// The gradient of the value with respect to the orbit's coordinates (the segment starts,
    /// the durations, the parameters, in the order of [`super::pack`]) when it is known exactly,
    /// e.g. because the value is one of them; `None` (the default) where it is not (the
    /// two-parameter curves then take differences).
    fn gradient(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Vec<f64>> {
        let _ = (system, orbit, scan);
        None
    }
    /// Where the value is attained, as one smooth condition ([`Touch`]), for a measure that is
    /// the smallest of several conditions (a margin): a two-parameter curve holding the measure
    /// at zero holds this touch instead, which stays smooth where the smallest condition
    /// changes. Default: `None` (the measure is held itself).
    fn touch(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Touch> {
        let _ = (system, orbit, scan);
        None
    }
    /// The value on `orbit` (a full or a half orbit), with its own scan at the
    /// [`MeasureSet`]'s default tolerances: a shorthand for a one-measure set.
    ///
    /// # Errors
    /// As [`MeasureSet::evaluate`].
    fn evaluate(&self, system: &S, orbit: &PeriodicOrbit) -> Result<f64>
    where
        Self: Sized,
        S: HybridJacobians,
    {
        let mut set = MeasureSet::new();
        set.add("measure", Borrowed(self))?;
        Ok(set.evaluate(system, orbit)?[0])
    }
}

/// A measure by reference (for [`Measure::evaluate`]).
struct Borrowed<'m, M>(&'m M);

impl<S: ?Sized, M: Measure<S>> Measure<S> for Borrowed<'_, M> {
    fn needs(&self) -> ScanNeeds {
        self.0.needs()
    }
    fn value(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64> {
        self.0.value(system, orbit, scan)
    }
    fn invariant_under(&self, system: &S, symmetry: &Z2Symmetry) -> bool {
        self.0.invariant_under(system, symmetry)
    }
    fn gradient(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Vec<f64>> {
        self.0.gradient(system, orbit, scan)
    }
    fn touch(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Touch> {
        self.0.touch(system, orbit, scan)
    }
}

/// The unit vector of coordinate `i` of `orbit` (see [`Measure::gradient`]), times `sign`.
fn unit(orbit: &PeriodicOrbit, i: usize, sign: f64) -> Vec<f64> {
    let kk = orbit.segment_count();
    let len = orbit.start_offset(kk) + kk + orbit.params.len();
    let mut g = vec![0.0; len];
    g[i] = sign;
    g
}

impl<S: ?Sized, F: Fn(&S, &PeriodicOrbit) -> f64> Measure<S> for F {
    fn value(&self, system: &S, orbit: &PeriodicOrbit, _: &OrbitScan) -> Result<f64> {
        Ok(self(system, orbit))
    }
}

/// Row `c` of $S$ as $\pm e_c$: `Some(+1.0)` or `Some(-1.0)`, else `None`.
fn component_sign(symmetry: &Z2Symmetry, n: usize, c: usize) -> Option<f64> {
    let row = |j: usize| symmetry.matrix[c + j * n];
    let own = row(c);
    ((own == 1.0 || own == -1.0) && (0..n).all(|j| j == c || row(j) == 0.0)).then_some(own)
}

fn check_component<S: HybridSystem + ?Sized>(system: &S, c: usize) -> Result<()> {
    if c < system.state_dim() {
        Ok(())
    } else {
        Err(Error::InvalidMeasure {
            reason: format!(
                "state component {c} does not exist (dimension {})",
                system.state_dim()
            ),
        })
    }
}

fn check_segment(orbit: &PeriodicOrbit, k: usize) -> Result<()> {
    if k < orbit.segment_count() {
        Ok(())
    } else {
        Err(Error::InvalidMeasure {
            reason: format!(
                "segment {k} does not exist (the orbit has {})",
                orbit.segment_count()
            ),
        })
    }
}

/// Which extremum an [`Extremum`] measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ExtremumKind {
    /// $\max_t x_c(t)$.
    Max,
    /// $\min_t x_c(t)$.
    Min,
    /// $\max_t |x_c(t)|$.
    MaxAbs,
}

/// The true extremum of state component $x_c$ over the orbit: over the segments' start states,
/// their end states before jumps, and the interior critical points of $x_c$ (located on the
/// integrator's dense output), so that it is smooth along a branch (not a mesh maximum). Where
/// the orbit's signature splits a segment at an extremum (e.g. at $\dot x_c = 0$), the value is
/// the split point's state, exact to the orbit's unknowns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Extremum {
    /// The component.
    pub component: usize,
    /// Which extremum.
    pub kind: ExtremumKind,
}

impl Extremum {
    /// $\max_t x_c(t)$.
    #[must_use]
    pub fn max(component: usize) -> Self {
        Self {
            component,
            kind: ExtremumKind::Max,
        }
    }
    /// $\min_t x_c(t)$.
    #[must_use]
    pub fn min(component: usize) -> Self {
        Self {
            component,
            kind: ExtremumKind::Min,
        }
    }
    /// $\max_t |x_c(t)|$ (e.g. the rocking block's amplitude).
    #[must_use]
    pub fn max_abs(component: usize) -> Self {
        Self {
            component,
            kind: ExtremumKind::MaxAbs,
        }
    }
}

impl Extremum {
    /// The extremum and, when it is attained at a segment start, that segment.
    fn attained(&self, orbit: &PeriodicOrbit, scan: &OrbitScan) -> (f64, Option<usize>) {
        let c = self.component;
        let key = |v: f64| match self.kind {
            ExtremumKind::Max => v,
            ExtremumKind::Min => -v,
            ExtremumKind::MaxAbs => v.abs(),
        };
        // End states count where a jump follows (the next start is the state after it); at
        // an interior point the next start is the same state, exactly.
        let segs = orbit.signature.segments();
        let ends = scan
            .ends
            .iter()
            .zip(segs)
            .filter(|(_, s)| matches!(s.end, SegmentEnd::Event(_)))
            .map(|(x, _)| (x[c], None));
        let starts = orbit
            .starts
            .iter()
            .enumerate()
            .map(|(k, x)| (x[c], Some(k)));
        let interior = scan
            .critical_of(Watch::Component(c))
            .filter(|p| p.t > 0.0)
            .map(|p| (p.value, None));
        let mut best = (f64::NEG_INFINITY, f64::NAN, None);
        for (v, at) in starts.chain(ends).chain(interior) {
            if key(v) > best.0 {
                best = (key(v), v, at);
            }
        }
        match self.kind {
            ExtremumKind::MaxAbs => (best.0, best.2),
            _ => (best.1, best.2),
        }
    }
}

impl<S: HybridSystem + ?Sized> Measure<S> for Extremum {
    fn needs(&self) -> ScanNeeds {
        ScanNeeds {
            watches: vec![Watch::Component(self.component)],
            ..ScanNeeds::default()
        }
    }
    fn value(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64> {
        check_component(system, self.component)?;
        Ok(self.attained(orbit, scan).0)
    }
    fn invariant_under(&self, system: &S, symmetry: &Z2Symmetry) -> bool {
        match component_sign(symmetry, system.state_dim(), self.component) {
            Some(_) if self.kind == ExtremumKind::MaxAbs => true,
            Some(s) => s > 0.0,
            None => false,
        }
    }
    /// Exact where the extremum is a segment's start (e.g. a split of the signature at
    /// $\dot x_c = 0$): the unit vector of that coordinate.
    fn gradient(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Vec<f64>> {
        let c = self.component;
        let k = self.attained(orbit, scan).1?;
        let sign = match self.kind {
            ExtremumKind::MaxAbs => orbit.starts[k][c].signum(),
            _ => 1.0,
        };
        let _ = system;
        Some(unit(orbit, orbit.start_offset(k) + c, sign))
    }
}

/// The signed grazing margin of an orbit to the surfaces of `events`: the smallest value of
/// $\sigma h_e(x)$ over the points where the flow turns back towards the surface $h_e = 0$
/// before reaching it (local minima of $\sigma h_e$ along segments in modes that monitor $e$,
/// with $\sigma = +1$ for a falling event, $-1$ for a rising one: $\sigma h_e > 0$ before the
/// crossing), or `cap` when there is no such point. It is zero where such a turning point
/// touches the surface (a grazing) and negative past it, where the trajectory crosses the
/// surface inside a segment (the orbit no longer has its signature).
#[derive(Debug, Clone, PartialEq)]
pub struct GrazingMargin {
    /// The events whose surfaces are watched.
    pub events: Vec<EventId>,
    /// The value without turning points (default `f64::MAX`).
    pub cap: f64,
}

impl GrazingMargin {
    /// The margin to the surfaces of `events`.
    #[must_use]
    pub fn new(events: impl IntoIterator<Item = EventId>) -> Self {
        Self {
            events: events.into_iter().collect(),
            cap: f64::MAX,
        }
    }

    /// Sets the value reported when no flow turns back towards a surface.
    #[must_use]
    pub fn cap(mut self, cap: f64) -> Self {
        self.cap = cap;
        self
    }
}

impl<S: HybridJacobians + ?Sized> Measure<S> for GrazingMargin {
    fn needs(&self) -> ScanNeeds {
        ScanNeeds {
            watches: self.events.iter().map(|&e| Watch::Event(e)).collect(),
            ..ScanNeeds::default()
        }
    }
    fn value(&self, system: &S, _: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64> {
        let mut margin = self.cap;
        for &e in &self.events {
            let sigma = system
                .event_spec(e)
                .direction
                .sign_before()
                .ok_or_else(|| Error::InvalidMeasure {
                    reason: format!("{e} has no crossing direction: a grazing margin needs one"),
                })?;
            let wanted = if sigma > 0.0 { Turn::Min } else { Turn::Max };
            for p in scan
                .critical_of(Watch::Event(e))
                .filter(|p| p.turn == wanted)
            {
                margin = margin.min(sigma * p.value);
            }
        }
        Ok(margin)
    }
    /// The turning point that attains the margin.
    fn touch(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Touch> {
        let mut best: Option<(f64, Touch)> = None;
        for &e in &self.events {
            let sigma = system.event_spec(e).direction.sign_before()?;
            let wanted = if sigma > 0.0 { Turn::Min } else { Turn::Max };
            for p in scan
                .critical_of(Watch::Event(e))
                .filter(|p| p.turn == wanted)
            {
                let v = sigma * p.value;
                if best.as_ref().is_none_or(|b| v < b.0) {
                    best = Some((v, Touch::at_turn(system, orbit, p.segment, e, p.t)));
                }
            }
        }
        best.map(|b| b.1)
    }
    /// Invariant when the events are closed under the symmetry's event map (the mirrored
    /// segments then have the same margins).
    fn invariant_under(&self, _: &S, symmetry: &Z2Symmetry) -> bool {
        self.events.iter().all(|e| {
            symmetry
                .events
                .get(e.0)
                .is_some_and(|m| self.events.contains(m))
        })
    }
}

/// Where a [`SegmentValue`] is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SegmentPoint {
    /// The segment's start state (after the previous jump).
    Start,
    /// The segment's end state (before its jump): needs an integration.
    End,
}

/// State component $x_c$ at a segment's start or end, e.g. the velocity just before an impact
/// (COCO's grazing monitor of an impacting orbit: it vanishes at a grazing impact).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SegmentValue {
    /// The segment.
    pub segment: usize,
    /// The component.
    pub component: usize,
    /// Start or end.
    pub at: SegmentPoint,
}

impl SegmentValue {
    /// $x_c$ at the start of segment `segment`.
    #[must_use]
    pub fn start(segment: usize, component: usize) -> Self {
        Self {
            segment,
            component,
            at: SegmentPoint::Start,
        }
    }
    /// $x_c$ at the end of segment `segment`, before its jump.
    #[must_use]
    pub fn end(segment: usize, component: usize) -> Self {
        Self {
            segment,
            component,
            at: SegmentPoint::End,
        }
    }
}

impl<S: HybridSystem + ?Sized> Measure<S> for SegmentValue {
    fn needs(&self) -> ScanNeeds {
        ScanNeeds {
            ends: self.at == SegmentPoint::End,
            ..ScanNeeds::default()
        }
    }
    fn value(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64> {
        check_component(system, self.component)?;
        check_segment(orbit, self.segment)?;
        let n = orbit.starts[self.segment].len();
        if self.component >= n {
            return Err(Error::InvalidMeasure {
                reason: format!(
                    "state component {} does not exist in segment {}'s mode ({n} components)",
                    self.component, self.segment
                ),
            });
        }
        Ok(match self.at {
            SegmentPoint::Start => orbit.starts[self.segment][self.component],
            SegmentPoint::End => scan.ends[self.segment][self.component],
        })
    }
    fn gradient(&self, system: &S, orbit: &PeriodicOrbit, _: &OrbitScan) -> Option<Vec<f64>> {
        let _ = system;
        (self.at == SegmentPoint::Start && self.segment < orbit.segment_count()).then(|| {
            unit(
                orbit,
                orbit.start_offset(self.segment) + self.component,
                1.0,
            )
        })
    }
}

/// The time average $\frac1T \int_0^T x_c\,dt$ of state component $x_c$ over the orbit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimeAverage {
    /// The component.
    pub component: usize,
}

impl TimeAverage {
    /// The time average of component `component`.
    #[must_use]
    pub fn new(component: usize) -> Self {
        Self { component }
    }
}

impl<S: HybridSystem + ?Sized> Measure<S> for TimeAverage {
    fn needs(&self) -> ScanNeeds {
        ScanNeeds {
            integrals: vec![self.component],
            ..ScanNeeds::default()
        }
    }
    fn value(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64> {
        check_component(system, self.component)?;
        let integral = scan
            .integral(self.component)
            .ok_or_else(|| Error::InvalidMeasure {
                reason: format!("component {} was not integrated", self.component),
            })?;
        Ok(integral / orbit.period())
    }
    fn invariant_under(&self, system: &S, symmetry: &Z2Symmetry) -> bool {
        component_sign(symmetry, system.state_dim(), self.component) == Some(1.0)
    }
}

/// The duration of segment `segment`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SegmentDuration {
    /// The segment.
    pub segment: usize,
}

impl SegmentDuration {
    /// The duration of segment `segment`.
    #[must_use]
    pub fn new(segment: usize) -> Self {
        Self { segment }
    }
}

impl<S: ?Sized> Measure<S> for SegmentDuration {
    fn value(&self, _: &S, orbit: &PeriodicOrbit, _: &OrbitScan) -> Result<f64> {
        check_segment(orbit, self.segment)?;
        Ok(orbit.durations[self.segment])
    }
    fn gradient(&self, _: &S, orbit: &PeriodicOrbit, _: &OrbitScan) -> Option<Vec<f64>> {
        let kk = orbit.segment_count();
        (self.segment < kk).then(|| unit(orbit, orbit.start_offset(kk) + self.segment, 1.0))
    }
}
