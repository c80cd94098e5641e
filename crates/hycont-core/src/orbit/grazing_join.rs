//! The inverse of [`super::split_at_grazing`]: where an impact becomes tangential or a
//! segment between impacts collapses, [`join_at_grazing`] removes the impacts and joins the
//! segments around them.

use super::PeriodicOrbit;
use super::grazing::{check_unmoved, invalid};
use super::signature::{SegmentEnd, SegmentSpec, Signature};
use crate::error::Result;
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{Direction, EventAction, EventId, HybridJacobians, Mode};

/// Where an orbit of a branch reaches a grazing from the side with the impact
/// ([`join_at_grazing`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JoinAt {
    /// Segment `segment` ends at a tangential impact ([`super::Touch::Approach`]): its end event is
    /// reached with zero approach rate.
    TangentialImpact {
        /// The segment.
        segment: usize,
    },
    /// Segment `segment` has collapsed to zero duration (a flight of no length between two
    /// impacts).
    Collapsed {
        /// The segment.
        segment: usize,
    },
}

/// An orbit of the signature on the other side of a grazing, without the impact
/// ([`join_at_grazing`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GrazingJoin {
    /// The orbit with the segments joined (the grazing orbit itself, in the new signature;
    /// exact to the grazing's location).
    pub orbit: PeriodicOrbit,
    /// The joined segment, whose flow touches the removed event's surface inside (or at its
    /// end, where that is an identity event's crossing, which then ends it).
    pub segment: usize,
    /// How many segments were removed.
    pub removed: usize,
}

/// Durations up to this fraction of the period count as zero where segments are joined (a
/// located grazing holds them to the location's accuracy, not exactly).
pub const JOIN_ZERO_DURATION: f64 = 1e-6;

/// Tolerance, relative to $1 + |x|$, within which the jumps between the joined segments
/// must compose to the identity.
pub const JOIN_IDENTITY_TOL: f64 = 1e-6;

/// The inverse of [`super::split_at_grazing`]: at a grazing reached from the side where the orbit
/// impacts there, the family on the other side flows past without the impact. The segment
/// before the impact (and any zero-length segments after it) is joined with the first
/// segment after them, which must be in the same mode and start where the joined segment's
/// flow arrives: at a tangential impact with a restitution law the reset leaves a state of
/// zero approach speed unchanged, and a flight of zero length between two impacts returns to
/// where it left. The joined segment has the summed duration and the later segment's end;
/// where the flow crosses, at the grazing point, an event of its mode whose reset leaves the
/// state unchanged (a turning point the signature ends segments at, on which the tangential
/// impact lay), the joined segments end there instead, with that event.
/// Where the removed impacts are the orbit's only events (every other segment has zero
/// length), the orbit beyond is one segment closed through a Poincaré section instead:
/// [`SegmentEnd::Interior`] on the state component that changes fastest at the grazing
/// point, at its value there; every removed jump must then leave the state unchanged.
///
/// For [`JoinAt::TangentialImpact`] the segments joined are `segment` and the first segment
/// after it of positive duration; for [`JoinAt::Collapsed`] the segment before the run of
/// zero-length segments through `segment` and the one after that run. Durations up to
/// [`JOIN_ZERO_DURATION`] times the period count as zero.
///
/// ```
/// # use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode};
/// use hycont_core::orbit::{JoinAt, PeriodicOrbit, SegmentEnd, SegmentSpec, Signature, join_at_grazing};
/// # /// x' = v, v' = -x; a wall at x = 1 (1 - x falls through 0) with v -> -e v.
/// # struct Wall;
/// # impl HybridSystem for Wall {
/// #     fn state_dim(&self) -> usize { 2 }
/// #     fn parameter_names(&self) -> &[&'static str] { &["e"] }
/// #     fn mode_count(&self) -> usize { 1 }
/// #     fn mode_name(&self, _: Mode) -> &'static str { "free" }
/// #     fn events(&self, _: Mode) -> &[EventId] { &[EventId(0)] }
/// #     fn event_spec(&self, _: EventId) -> EventSpec {
/// #         EventSpec { name: "wall", direction: Direction::Falling, action: EventAction::Jump { to: Mode(0) } }
/// #     }
/// #     fn vector_field(&self, _: Mode, x: &[f64], _: &[f64], f: &mut [f64]) { f[0] = x[1]; f[1] = -x[0]; }
/// #     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { 1.0 - x[0] }
/// #     fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) { out[0] = x[0]; out[1] = -p[0] * x[1]; }
/// # }
/// # impl HybridJacobians for Wall {
/// #     fn vector_field_jacobian(&self, _: Mode, _: &[f64], _: &[f64], dx: &mut [f64], _: Option<&mut [f64]>) {
/// #         dx.copy_from_slice(&[0.0, -1.0, 1.0, 0.0]);
/// #     }
/// #     fn event_gradient(&self, _: EventId, _: &[f64], _: &[f64], g: &mut [f64], _: Option<&mut [f64]>) {
/// #         g.copy_from_slice(&[-1.0, 0.0]);
/// #     }
/// # }
/// // x = cos t touches the wall at x = 1 with zero speed once a period: one segment ending
/// // at a tangential impact.
/// let impact = SegmentSpec { mode: Mode(0), end: SegmentEnd::Event(EventId(0)) };
/// let sig = Signature::new(&Wall, vec![impact]).unwrap();
/// let tau = 2.0 * std::f64::consts::PI;
/// let grazing = PeriodicOrbit::new(&Wall, sig, vec![vec![1.0, 0.0]], vec![tau], vec![0.8])
///     .unwrap();
/// let join = join_at_grazing(&Wall, &grazing, JoinAt::TangentialImpact { segment: 0 }).unwrap();
/// // Without the impact: one turn closed through the section v = 0 (v changes fastest there;
/// // its value is the flow's end state, integrated, 0 to rounding).
/// let SegmentEnd::Interior { component, value } = join.orbit.signature.segments()[0].end else {
///     panic!("not closed through a section")
/// };
/// assert!(component == 1 && value.abs() < 1e-10);
/// assert_eq!(join.orbit.durations, vec![tau]);
/// ```
///
/// # Errors
/// [`crate::Error::InvalidSignature`] naming the segment where the segments to join do not exist
/// within one period (a join across the orbit's closure), are in different modes, where a
/// collapsed segment is not of zero duration, or where the jumps between them do not
/// compose to the identity (to [`JOIN_IDENTITY_TOL`]: not a grazing); integration failures.
pub fn join_at_grazing<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    at: JoinAt,
) -> Result<GrazingJoin> {
    let span = segments_to_join(orbit, at)?;
    let first = match span {
        Span::Between(first, _) | Span::Whole(first) => first,
    };
    let specs = orbit.signature.segments();
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let mut sim = Simulator::new(settings)?;
    let flow = super::flow::SegmentFlow::plain(system, specs[first].mode);
    let arrived = sim
        .run(
            &flow,
            Mode(0),
            0.0,
            &orbit.starts[first],
            &orbit.params,
            orbit.durations[first],
        )?
        .state_final;
    let (segments, starts, durations) = match span {
        Span::Between(first, last) => join_between(system, orbit, (first, last), &arrived)?,
        Span::Whole(first) => {
            let removed: Vec<SegmentEnd> = specs.iter().map(|s| s.end).collect();
            let mode = specs[first].mode;
            let end = match crossed_identity_event(system, orbit, mode, &arrived, &removed) {
                Some(e) => SegmentEnd::Event(e),
                None => section_through(system, orbit, first, &arrived)?,
            };
            let segment = SegmentSpec {
                mode: specs[first].mode,
                end,
            };
            (
                vec![segment],
                vec![orbit.starts[first].clone()],
                vec![orbit.period()],
            )
        }
    };
    let removed = orbit.segment_count() - segments.len();
    let signature = Signature::with_closure(system, segments, orbit.signature.closure())?;
    Ok(GrazingJoin {
        orbit: PeriodicOrbit::new(system, signature, starts, durations, orbit.params.clone())?,
        segment: if matches!(span, Span::Whole(_)) {
            0
        } else {
            first
        },
        removed,
    })
}

/// A new orbit's segments, starts and durations.
type Pieces = (Vec<SegmentSpec>, Vec<Vec<f64>>, Vec<f64>);

/// The pieces of the orbit with segments `first` and `last` (and the zero-length segments
/// between) joined, from segment `first`'s flow, which arrives at `arrived`.
fn join_between<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    (first, last): (usize, usize),
    arrived: &[f64],
) -> Result<Pieces> {
    let specs = orbit.signature.segments();
    if specs[first].mode != specs[last].mode {
        return Err(invalid(
            first,
            &format!(
                "the segment after the grazing (segment {last}) is in {}, not in {}: nothing to join",
                specs[last].mode, specs[first].mode
            ),
        ));
    }
    check_unmoved(first, last, arrived, &orbit.starts[last])?;
    let mode = specs[first].mode;
    let mut segments = specs[..first].to_vec();
    let mut starts = orbit.starts[..=first].to_vec();
    let mut durations = orbit.durations[..first].to_vec();
    let removed: Vec<SegmentEnd> = specs[first..last].iter().map(|s| s.end).collect();
    match crossed_identity_event(system, orbit, mode, arrived, &removed) {
        // The flow crosses an identity event of its mode where the impact was (e.g.
        // the extremum a signature splits at): the segments end there instead.
        Some(e) => {
            segments.push(SegmentSpec {
                mode,
                end: SegmentEnd::Event(e),
            });
            segments.push(SegmentSpec {
                mode,
                end: specs[last].end,
            });
            starts.push(orbit.starts[last].clone());
            durations.push(orbit.durations[first]);
            durations.push(orbit.durations[first + 1..=last].iter().sum());
        }
        None => {
            segments.push(SegmentSpec {
                mode,
                end: specs[last].end,
            });
            durations.push(orbit.durations[first..=last].iter().sum());
        }
    }
    segments.extend_from_slice(&specs[last + 1..]);
    starts.extend_from_slice(&orbit.starts[last + 1..]);
    durations.extend_from_slice(&orbit.durations[last + 1..]);
    Ok((segments, starts, durations))
}

/// An event of `mode` other than the `removed` ends whose surface the flow crosses at the
/// grazing point `arrived`, in the event's direction, with a reset that leaves the state
/// there unchanged and keeps the mode (to [`JOIN_IDENTITY_TOL`]): e.g. a turning point a
/// signature ends its segments at, on which a tangential impact lay. Joining there keeps
/// that end.
fn crossed_identity_event<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    mode: Mode,
    arrived: &[f64],
    removed: &[SegmentEnd],
) -> Option<EventId> {
    let p = &orbit.params;
    let scale = 1.0 + arrived.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let n = arrived.len();
    let (mut f, mut grad, mut after) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    system.vector_field(mode, arrived, p, &mut f);
    system.events(mode).iter().copied().find(|&e| {
        let spec = system.event_spec(e);
        if removed.contains(&SegmentEnd::Event(e))
            || spec.action != (EventAction::Jump { to: mode })
            || system.event(e, arrived, p).abs() > JOIN_IDENTITY_TOL * scale
        {
            return false;
        }
        system.reset(e, arrived, p, &mut after);
        let moved = (after.iter().zip(arrived)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        system.event_gradient(e, arrived, p, &mut grad, None);
        let rate: f64 = grad.iter().zip(&f).map(|(g, v)| g * v).sum();
        let crosses = match spec.direction {
            Direction::Falling => rate < 0.0,
            Direction::Rising => rate > 0.0,
            Direction::Either => rate != 0.0,
        };
        moved <= JOIN_IDENTITY_TOL * scale && crosses
    })
}

/// The Poincaré section that closes an orbit whose only events are removed: through the
/// grazing point `arrived` (the end of segment `first`), on the component that changes
/// fastest there; every removed jump (followed from `arrived` through the zero-length
/// segments) must leave the state unchanged.
fn section_through<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    first: usize,
    arrived: &[f64],
) -> Result<SegmentEnd> {
    let specs = orbit.signature.segments();
    let count = specs.len();
    let mut state = arrived.to_vec();
    for j in (0..count).map(|i| (first + i) % count) {
        if let SegmentEnd::Event(e) = specs[j].end {
            let mut after = vec![0.0; state.len()];
            system.reset(e, &state, &orbit.params, &mut after);
            check_unmoved(j, (j + 1) % count, &state, &after)?;
            state = after;
        }
    }
    let mut f = vec![0.0; arrived.len()];
    system.vector_field(specs[first].mode, arrived, &orbit.params, &mut f);
    let component = (0..f.len())
        .max_by(|&a, &b| f[a].abs().total_cmp(&f[b].abs()))
        .filter(|&c| f[c] != 0.0)
        .ok_or_else(|| invalid(first, "the flow is at rest at the grazing: no section"))?;
    Ok(SegmentEnd::Interior {
        component,
        value: arrived[component],
    })
}

/// The segments that [`join_at_grazing`] joins.
#[derive(Debug, Clone, Copy)]
enum Span {
    /// The first and the last.
    Between(usize, usize),
    /// The one segment of positive duration, closed on itself.
    Whole(usize),
}

/// The segments that [`join_at_grazing`] joins.
fn segments_to_join(orbit: &PeriodicOrbit, at: JoinAt) -> Result<Span> {
    let count = orbit.segment_count();
    let zero = JOIN_ZERO_DURATION * orbit.period();
    let is_zero = |k: usize| orbit.durations[k] <= zero;
    let (JoinAt::TangentialImpact { segment } | JoinAt::Collapsed { segment }) = at;
    if segment >= count {
        return Err(invalid(segment, &format!("the orbit has {count} segments")));
    }
    if let JoinAt::Collapsed { segment } = at
        && !is_zero(segment)
    {
        return Err(invalid(
            segment,
            &format!(
                "its duration {} is not zero: it has not collapsed",
                orbit.durations[segment]
            ),
        ));
    }
    let positive: Vec<usize> = (0..count).filter(|&k| !is_zero(k)).collect();
    if let [only] = positive[..] {
        return Ok(Span::Whole(only));
    }
    let across = || {
        invalid(
            segment,
            "the segments to join lie across the orbit's closure: rotate the orbit so that the grazing lies inside one period",
        )
    };
    let first = match at {
        JoinAt::TangentialImpact { segment } => segment,
        JoinAt::Collapsed { segment } => (0..segment)
            .rev()
            .find(|&k| !is_zero(k))
            .ok_or_else(across)?,
    };
    let last = (first + 1..count)
        .find(|&k| !is_zero(k))
        .ok_or_else(across)?;
    Ok(Span::Between(first, last))
}
