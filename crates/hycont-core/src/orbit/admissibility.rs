//! Admissibility of a hybrid periodic orbit: a solution of the orbit equations is a physical
//! orbit only if every segment stays in its mode's domain.
//!
//! An orbit is admissible when the simulator, started at each segment's start, would follow
//! it: no event of the segment's mode fires before the segment's end, and the segment's own
//! event fires there, in its direction. For segment $k$ in mode $m$ with duration $T_k$ and
//! every event $e$ that $m$ monitors with a direction ($\sigma_e = +1$ for a falling event,
//! $-1$ for a rising one, so that $\sigma_e h_e > 0$ before a crossing):
//! - $T_k \ge 0$ (a segment of zero duration is one point: at a grazing, a flight of no
//!   length between two impacts; its end conditions put it on its end event's surface);
//! - no **interior touch or crossing**: every local minimum of $\sigma_e h_e$ reached from the
//!   pre-crossing side (found on the dense output by [`super::scan`], not only at mesh points)
//!   is positive, and so is the end value of every other event reached from that side (a turn
//!   the scan finds within its [`super::scan::BOUNDARY_BAND`] of the segment's end is the end's);
//! - the segment's **terminal event** is reached in its declared direction:
//!   $-\sigma_e \dot h_e > 0$ at the end (a zero approach rate is a grazing impact), from a
//!   start not beyond its surface.
//!
//! [`check_admissible`] applies these to a solved orbit (with tolerance
//! [`ADMISSIBILITY_TOL`]) and names the first violation. [`AdmissibilityMargin`] turns them
//! into two measures whose zeros end a branch: the grazing margin (interior touches and
//! approach rates, labelled GR) and the domain margin (other events' values at segment ends).
//! Durations are checked by [`check_admissible`] only: a continuation ends at a collapsing
//! segment by its own shortest-segment monitor.

use super::measure::Measure;
use super::scan::{OrbitScan, ScanNeeds, Turn, Watch, scan};
use super::signature::SegmentEnd;
use super::{PeriodicOrbit, Touch};
use crate::Z2Symmetry;
use crate::error::{Error, Result};
use crate::simulate::SimulationSettings;
use crate::system::{EventId, HybridJacobians, HybridSystem, Mode};
use serde::{Deserialize, Serialize};

/// Tolerance of [`check_admissible`], relative to $1 + \max |x|$ over the segment starts.
pub const ADMISSIBILITY_TOL: f64 = 1e-8;

/// How a segment leaves its mode's domain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Violation {
    /// The segment's duration is negative.
    Duration,
    /// The flow touches or crosses the event's surface inside the segment.
    InteriorCrossing,
    /// The terminal event is reached against its declared direction (or tangentially).
    WrongDirection,
    /// The segment starts on the far side of the surface of the event that ends it.
    StartOutside,
    /// The segment ends past the surface of another event, crossed in its direction.
    EndOutside,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Violation::Duration => "its duration is negative",
            Violation::InteriorCrossing => "it touches or crosses an event surface inside",
            Violation::WrongDirection => {
                "it reaches its end event against the event's direction (or tangentially)"
            }
            Violation::StartOutside => "it starts beyond the surface of the event that ends it",
            Violation::EndOutside => "it ends beyond another event's surface",
        })
    }
}

/// Which admissibility margin an [`AdmissibilityMargin`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Margin {
    /// $\min$ over interior minima of $\sigma_e h_e$ and terminal approach rates
    /// $-\sigma_e \dot h_e$: zero at a grazing (an interior touch or a tangential impact).
    Grazing,
    /// $\min$ over the values $\sigma_e h_e$ of non-terminal events at segment ends (reached
    /// from the pre-crossing side): zero where a segment ends on another event's surface.
    Domain,
}

/// An admissibility margin of an orbit as a measure (positive for admissible orbits). The
/// value is `cap` when nothing bounds it.
#[derive(Debug, Clone, PartialEq)]
pub struct AdmissibilityMargin {
    /// Which margin.
    pub margin: Margin,
    /// The value when no condition applies (default `1e3`).
    pub cap: f64,
    /// The system's directed events with their signs $\sigma_e$.
    events: Vec<(EventId, f64)>,
}

impl AdmissibilityMargin {
    /// The margin `margin` of `system`'s orbits, capped at `1e3`.
    #[must_use]
    pub fn new<S: HybridSystem + ?Sized>(system: &S, margin: Margin) -> Self {
        Self {
            margin,
            cap: 1e3,
            events: directed_events(system),
        }
    }
}

/// The directed events of all modes: $(e, \sigma_e)$.
fn directed_events<S: HybridSystem + ?Sized>(system: &S) -> Vec<(EventId, f64)> {
    let mut out: Vec<(EventId, f64)> = Vec::new();
    for m in 0..system.mode_count() {
        for &e in system.events(Mode(m)) {
            if let Some(sigma) = system.event_spec(e).direction.sign_before()
                && !out.iter().any(|(f, _)| *f == e)
            {
                out.push((e, sigma));
            }
        }
    }
    out
}

fn needs(events: &[(EventId, f64)]) -> ScanNeeds {
    ScanNeeds {
        watches: events.iter().map(|(e, _)| Watch::Event(*e)).collect(),
        integrals: Vec::new(),
        ends: true,
    }
}

/// $\dot h_e = \nabla h_e \cdot f_m$ at `x`.
pub(super) fn rate<S: HybridJacobians + ?Sized>(
    system: &S,
    mode: Mode,
    e: EventId,
    x: &[f64],
    p: &[f64],
) -> f64 {
    let n = x.len();
    let (mut grad, mut f) = (vec![0.0; n], vec![0.0; n]);
    system.event_gradient(e, x, p, &mut grad, None);
    system.vector_field(mode, x, p, &mut f);
    grad.iter().zip(&f).map(|(g, v)| g * v).sum()
}

/// One admissibility condition's value: positive when satisfied.
#[derive(Debug, Clone, Copy)]
struct Condition {
    margin: Option<Margin>,
    violation: Violation,
    segment: usize,
    event: Option<EventId>,
    t: f64,
    value: f64,
}

/// Every condition of `orbit`, from its scan.
///
/// Between consecutive critical points an event function is monotone, so the values of
/// $\sigma_e h_e$ at a segment's start, at its critical points and at its end show every
/// crossing: one in the event's direction happens exactly where a value on the pre-crossing side
/// ($> 0$) is followed by one $\le 0$. A segment that starts on the surface is on the side its
/// rate points to.
fn conditions<S: HybridJacobians + ?Sized>(
    system: &S,
    events: &[(EventId, f64)],
    orbit: &PeriodicOrbit,
    scan: &OrbitScan,
) -> Vec<Condition> {
    let p = &orbit.params;
    let mut out = Vec::new();
    for (k, seg) in orbit.signature.segments().iter().enumerate() {
        let duration = orbit.durations[k];
        let cond = |margin, violation, event, t, value| Condition {
            margin,
            violation,
            segment: k,
            event,
            t,
            value,
        };
        out.push(cond(
            Some(Margin::Domain),
            Violation::Duration,
            None,
            0.0,
            duration,
        ));
        let terminal = match seg.end {
            SegmentEnd::Event(e) => Some(e),
            SegmentEnd::Interior { .. } => None,
        };
        let start = &orbit.starts[k];
        let band =
            super::scan::BOUNDARY_BAND * (1.0 + start.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        // A critical point found this close to the segment's end is the end's (the scan's band
        // at a split): its value is the end's, which the end's conditions below take. Counted
        // as an interior turn, the same value would move between the margins as integration
        // error puts the point before or after the end (e.g. an event function that is
        // extremal where the segment ends, as a position at the velocity's zero ending a
        // flight), and the margins would jump along a branch.
        let end_band = super::scan::boundary_margin(duration);
        let monitored = system.events(seg.mode);
        for &(e, sigma) in events.iter().filter(|(e, _)| monitored.contains(e)) {
            let h0 = sigma * system.event(e, start, p);
            if terminal == Some(e) && h0 < -band {
                out.push(cond(None, Violation::StartOutside, Some(e), 0.0, h0));
            }
            // On the pre-crossing side (or on the surface, moving into it)?
            let mut pre = if h0.abs() <= band {
                // Leaving the surface clearly to the far side is not a crossing; a tangential
                // start (a touch at an interior boundary) counts as on the near side.
                sigma * rate(system, seg.mode, e, start, p) >= -band
            } else {
                h0 > 0.0
            };
            for c in scan
                .critical_of(Watch::Event(e))
                .filter(|c| c.segment == k && c.t > 0.0 && c.t < duration - end_band)
            {
                let v = sigma * c.value;
                let is_min = (c.turn == Turn::Min) == (sigma > 0.0);
                if pre && is_min {
                    out.push(cond(
                        Some(Margin::Grazing),
                        Violation::InteriorCrossing,
                        Some(e),
                        c.t,
                        v,
                    ));
                }
                // After a minimum the function rises: the segment's end cannot be a crossing
                // in the event's direction (whatever the sign of a touching minimum).
                pre = v > 0.0 && !is_min;
            }
            let Some(end) = scan.ends.get(k) else {
                continue;
            };
            if terminal == Some(e) {
                let approach = -sigma * rate(system, seg.mode, e, end, p);
                out.push(cond(
                    Some(Margin::Grazing),
                    Violation::WrongDirection,
                    Some(e),
                    duration,
                    approach,
                ));
            } else if pre {
                // At an interior end (state continuous) a touch is an interior touch of the
                // orbit: a grazing.
                let margin = match seg.end {
                    SegmentEnd::Interior { .. } => Margin::Grazing,
                    SegmentEnd::Event(_) => Margin::Domain,
                };
                let h1 = sigma * system.event(e, end, p);
                out.push(cond(
                    Some(margin),
                    Violation::EndOutside,
                    Some(e),
                    duration,
                    h1,
                ));
            }
        }
    }
    out
}

impl<S: HybridJacobians + ?Sized> Measure<S> for AdmissibilityMargin {
    fn needs(&self) -> ScanNeeds {
        needs(&self.events)
    }
    fn value(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Result<f64> {
        Ok(conditions(system, &self.events, orbit, scan)
            .iter()
            .filter(|c| c.margin == Some(self.margin))
            .fold(self.cap, |m, c| m.min(c.value)))
    }
    fn invariant_under(&self, _: &S, symmetry: &Z2Symmetry) -> bool {
        self.events
            .iter()
            .all(|(e, _)| symmetry.events.get(e.0).is_some())
    }
    /// The condition that attains the margin: an interior turning point
    /// ([`Touch::Turn`]), a terminal approach rate ([`Touch::Approach`]) or an event's value at
    /// a segment's end ([`Touch::End`]); `None` where it is a duration (a collapsing segment)
    /// or nothing bounds the margin.
    fn touch(&self, system: &S, orbit: &PeriodicOrbit, scan: &OrbitScan) -> Option<Touch> {
        let c = conditions(system, &self.events, orbit, scan)
            .into_iter()
            .filter(|c| c.margin == Some(self.margin))
            .min_by(|a, b| a.value.total_cmp(&b.value))?;
        let event = c.event?;
        Some(match c.violation {
            Violation::InteriorCrossing => Touch::at_turn(system, orbit, c.segment, event, c.t),
            Violation::WrongDirection => Touch::Approach {
                segment: c.segment,
                event,
            },
            Violation::EndOutside => Touch::End {
                segment: c.segment,
                event,
            },
            Violation::Duration | Violation::StartOutside => return None,
        })
    }
}

/// Checks that `orbit` is admissible (see the module docs), integrating it once.
///
/// # Errors
/// [`Error::Inadmissible`] naming the first violated condition (segment, event, time from the
/// segment's start, value); integration failures.
pub fn check_admissible<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
) -> Result<()> {
    check_admissible_collapsed(system, orbit, &[])
}

/// [`check_admissible`] of an orbit whose segments `collapsed` have collapsed onto their end's
/// surface: a point of a grazing curve held by a segment's zero duration (and on a symmetric
/// orbit its image's), whose duration is zero by construction (zero to `1e-8` is not refused;
/// their other conditions are checked).
///
/// # Errors
/// As [`check_admissible`].
pub fn check_admissible_collapsed<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    collapsed: &[usize],
) -> Result<()> {
    if let Some(k) = orbit
        .durations
        .iter()
        .enumerate()
        .position(|(k, d)| !(*d >= 0.0 || (collapsed.contains(&k) && d.abs() <= 1e-8)))
    {
        return Err(Error::Inadmissible {
            segment: k,
            event: None,
            violation: Violation::Duration,
            t: 0.0,
            value: orbit.durations[k],
        });
    }
    let events = directed_events(system);
    let sc = scan(
        system,
        orbit,
        &needs(&events),
        &SimulationSettings::default(),
    )?;
    let scale = 1.0
        + orbit
            .starts
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = ADMISSIBILITY_TOL * scale;
    match conditions(system, &events, orbit, &sc)
        .into_iter()
        .find(|c| {
            c.value < -tol
                && !(collapsed.contains(&c.segment) && c.violation == Violation::Duration)
        }) {
        None => Ok(()),
        Some(c) => Err(Error::Inadmissible {
            segment: c.segment,
            event: c.event,
            violation: c.violation,
            t: c.t,
            value: c.value,
        }),
    }
}
