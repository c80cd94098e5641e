//! The orbit of the neighbouring signature at an interior grazing: where a segment's flow
//! touches an event surface at a turning point ([`Touch::Turn`]), the family beyond has an
//! impact there. [`split_at_grazing`] splits the segment at the turning point and inserts the
//! event with its reset; where the reset leads into another mode, the flow there leaves the
//! surface at once and returns to it (at the grazing itself in no time), so a zero-length
//! segment in that mode, ended by the event of that mode that leads back, follows (for a
//! rocking block: an impact onto the other corner, a flight on it of zero duration, an impact
//! back). The result is the same orbit (to rounding) as an orbit of the new signature: the
//! start of a branch of the family beyond the grazing.
//!
//! [`join_at_grazing`] goes the other way: where an impact becomes tangential or a segment
//! between impacts collapses, it removes the impacts and joins the segments around them.

use super::PeriodicOrbit;
use super::signature::{Closure, SegmentEnd, SegmentSpec, Signature};
use super::touch::Touch;
use crate::error::{Error, Result};
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{EventAction, EventId, HybridJacobians, Mode};

/// An orbit of the signature beyond a grazing ([`split_at_grazing`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GrazingSplit {
    /// The orbit with the new segments (the grazing orbit itself, in the new signature).
    pub orbit: PeriodicOrbit,
    /// The segment that ends at the new impact (the first part of the split segment).
    pub impact_segment: usize,
    /// The zero-length segment in the mode the impact leads into, where it leads into another
    /// mode.
    pub zero_length: Option<usize>,
}

/// Tolerance, relative to $1 + |x|$, within which the reset of the touched event lands on the
/// surface of the event that leads back (at a grazing the approach is tangential: the state
/// after the impact is on both surfaces).
const ON_SURFACE: f64 = 1e-8;

/// Splits `orbit` at the grazing `touch` into the orbit of the signature with an impact there
/// (see the module docs): at a [`Touch::Turn`] strictly inside its segment, the segment is
/// split at the turning point; at a [`Touch::End`] (a segment's end on the event's surface,
/// e.g. an extremum where a signature with interior points ends a segment), that end is
/// replaced by the impact, provided it keeps the state and the mode (an interior point, or an
/// event whose reset leaves the state unchanged there).
///
/// # Errors
/// [`Error::InvalidSignature`] for a tangential impact ([`Touch::Approach`]: see
/// [`join_at_grazing`]), a turning point not inside its segment, an end that changes the
/// state or mode or lies at the orbit's closure, an event that does not jump, or, where the
/// impact leads into another mode, no event of that mode on whose surface the reset lands and
/// that leads back; integration failures.
pub fn split_at_grazing<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    touch: &Touch,
) -> Result<GrazingSplit> {
    let (k, event) = match *touch {
        Touch::Turn { segment, event, .. } => (segment, event),
        Touch::End { segment, event } => return split_at_end(system, orbit, segment, event),
        Touch::Approach { segment, .. } => {
            return Err(invalid(
                segment,
                "the grazing is a tangential impact: remove it (join_at_grazing), not split",
            ));
        }
    };
    let value = touch.evaluate(system, orbit)?;
    let duration = orbit.durations[k];
    let t_star = value.fraction * duration;
    if !(t_star > 0.0 && t_star < duration) {
        return Err(invalid(
            k,
            &format!("the turning point at {t_star} is not inside the segment (0, {duration})"),
        ));
    }
    let spec = orbit.signature.segments()[k];
    let EventAction::Jump { to } = system.event_spec(event).action else {
        return Err(invalid(
            k,
            &format!("{event} does not jump: no impact to insert"),
        ));
    };
    let p = &orbit.params;
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let mut sim = Simulator::new(settings)?;
    let flow = super::flow::SegmentFlow::plain(system, spec.mode);
    let x_star = sim
        .run(&flow, Mode(0), 0.0, &orbit.starts[k], p, t_star)?
        .state_final;
    let mut after = vec![0.0; crate::system::reset_dim(system, event, x_star.len())];
    system.reset(event, &x_star, p, &mut after);
    let mut segments: Vec<SegmentSpec> = orbit.signature.segments()[..k].to_vec();
    let mut starts: Vec<Vec<f64>> = orbit.starts[..k].to_vec();
    let mut durations: Vec<f64> = orbit.durations[..k].to_vec();
    segments.push(SegmentSpec {
        mode: spec.mode,
        end: SegmentEnd::Event(event),
    });
    starts.push(orbit.starts[k].clone());
    durations.push(t_star);
    let (resume, zero_length) = resume_after_impact(
        system,
        (k, event),
        (spec.mode, to),
        after,
        p,
        (&mut segments, &mut starts, &mut durations),
    )?;
    segments.push(spec);
    starts.push(resume);
    durations.push(duration - t_star);
    segments.extend_from_slice(&orbit.signature.segments()[k + 1..]);
    starts.extend_from_slice(&orbit.starts[k + 1..]);
    durations.extend_from_slice(&orbit.durations[k + 1..]);
    let signature = Signature::with_closure(system, segments, orbit.signature.closure())?;
    Ok(GrazingSplit {
        orbit: PeriodicOrbit::new(system, signature, starts, durations, p.clone())?,
        impact_segment: k,
        zero_length,
    })
}

/// [`split_at_grazing`] at the end of segment `k`, which lies on `event`'s surface: the end
/// is replaced by `event` (and its zero-length flight where its reset leads into another
/// mode), after which segment `k + 1` goes on from the state the impact leaves. Segment `k`'s
/// own end must keep the state and the mode (an interior point, e.g. an extremum at which a
/// signature splits its segments, or an event whose reset leaves the state unchanged there,
/// to [`JOIN_IDENTITY_TOL`]): it is dropped.
fn split_at_end<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    k: usize,
    event: EventId,
) -> Result<GrazingSplit> {
    let specs = orbit.signature.segments();
    let count = specs.len();
    if k + 1 == count && count > 1 && orbit.signature.closure() == Closure::Periodic {
        // At the closure: the same orbit with its last segment first.
        return split_at_end(system, &orbit.rotated(system, k)?, 0, event);
    }
    if k + 1 >= count {
        return Err(invalid(
            k,
            "the grazing is at the closure of a half orbit or of a one-segment orbit: split the orbit at an interior point first",
        ));
    }
    let spec = specs[k];
    if specs[k + 1].mode != spec.mode {
        return Err(invalid(
            k,
            &format!(
                "its end leads into {}: only an end that keeps the mode is replaced by {event}",
                specs[k + 1].mode
            ),
        ));
    }
    let EventAction::Jump { to } = system.event_spec(event).action else {
        return Err(invalid(
            k,
            &format!("{event} does not jump: no impact to insert"),
        ));
    };
    let p = &orbit.params;
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let mut sim = Simulator::new(settings)?;
    let flow = super::flow::SegmentFlow::plain(system, spec.mode);
    let y = sim
        .run(&flow, Mode(0), 0.0, &orbit.starts[k], p, orbit.durations[k])?
        .state_final;
    // The dropped end keeps the state: segment k + 1 starts where segment k arrives.
    check_unmoved(k, k + 1, &y, &orbit.starts[k + 1])?;
    let mut after = vec![0.0; crate::system::reset_dim(system, event, y.len())];
    system.reset(event, &y, p, &mut after);
    let mut segments = specs[..k].to_vec();
    segments.push(SegmentSpec {
        mode: spec.mode,
        end: SegmentEnd::Event(event),
    });
    let mut starts = orbit.starts[..=k].to_vec();
    let mut durations = orbit.durations[..=k].to_vec();
    let (resume, zero_length) = resume_after_impact(
        system,
        (k, event),
        (spec.mode, to),
        after,
        p,
        (&mut segments, &mut starts, &mut durations),
    )?;
    segments.extend_from_slice(&specs[k + 1..]);
    starts.push(resume);
    starts.extend_from_slice(&orbit.starts[k + 2..]);
    durations.extend_from_slice(&orbit.durations[k + 1..]);
    let signature = Signature::with_closure(system, segments, orbit.signature.closure())?;
    Ok(GrazingSplit {
        orbit: PeriodicOrbit::new(system, signature, starts, durations, p.clone())?,
        impact_segment: k,
        zero_length,
    })
}

/// After the impact by `event` that ends segment `k` in `mode` and leaves the state `after`:
/// where it leads into another mode `to`, the zero-length flight there (ended by the event
/// that leads back, [`event_back`]) is appended to the pieces of the new orbit. Returns the
/// state in `mode` the orbit resumes with and the flight's index.
fn resume_after_impact<S: HybridJacobians + ?Sized>(
    system: &S,
    (k, event): (usize, EventId),
    (mode, to): (Mode, Mode),
    after: Vec<f64>,
    p: &[f64],
    (segments, starts, durations): (&mut Vec<SegmentSpec>, &mut Vec<Vec<f64>>, &mut Vec<f64>),
) -> Result<(Vec<f64>, Option<usize>)> {
    if to == mode {
        return Ok((after, None));
    }
    let back = event_back(system, (k, event), (to, mode), &after, p)?;
    let zero_length = segments.len();
    segments.push(SegmentSpec {
        mode: to,
        end: SegmentEnd::Event(back),
    });
    let mut resumed = vec![0.0; crate::system::reset_dim(system, back, after.len())];
    system.reset(back, &after, p, &mut resumed);
    starts.push(after);
    durations.push(0.0);
    Ok((resumed, Some(zero_length)))
}

/// The event that ends the zero-length flight in mode `to` after the impact by `event` (which
/// ends segment `k`): the event of `to` that leads back into `from` and on whose surface the
/// impact's reset `after` lands (at a grazing the approach is tangential).
fn event_back<S: HybridJacobians + ?Sized>(
    system: &S,
    (k, event): (usize, EventId),
    (to, from): (Mode, Mode),
    after: &[f64],
    p: &[f64],
) -> Result<EventId> {
    let scale = 1.0 + after.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let back = system.events(to).iter().copied().find(|&e| {
        matches!(system.event_spec(e).action, EventAction::Jump { to: m } if m == from)
            && system.event(e, after, p).abs() <= ON_SURFACE * scale
    });
    back.ok_or_else(|| {
        invalid(
            k,
            &format!(
                "{event} leads into {to}, where no event that leads back to {from} starts on the surface its reset lands on"
            ),
        )
    })
}

fn invalid(segment: usize, reason: &str) -> Error {
    Error::InvalidSignature {
        segment,
        reason: reason.to_string(),
    }
}

/// Where an orbit of a branch reaches a grazing from the side with the impact
/// ([`join_at_grazing`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JoinAt {
    /// Segment `segment` ends at a tangential impact ([`Touch::Approach`]): its end event is
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
    /// The joined segment, whose flow touches the removed event's surface inside.
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

/// The inverse of [`split_at_grazing`]: at a grazing reached from the side where the orbit
/// impacts there, the family on the other side flows past without the impact. The segment
/// before the impact (and any zero-length segments after it) is joined with the first
/// segment after them, which must be in the same mode and start where the joined segment's
/// flow arrives: at a tangential impact with a restitution law the reset leaves a state of
/// zero approach speed unchanged, and a flight of zero length between two impacts returns to
/// where it left. The joined segment has the summed duration and the later segment's end.
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
/// [`Error::InvalidSignature`] naming the segment where the segments to join do not exist
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
        Span::Between(first, last) => {
            if specs[first].mode != specs[last].mode {
                return Err(invalid(
                    first,
                    &format!(
                        "the segment after the grazing (segment {last}) is in {}, not in {}: nothing to join",
                        specs[last].mode, specs[first].mode
                    ),
                ));
            }
            check_unmoved(first, last, &arrived, &orbit.starts[last])?;
            let mut segments = specs[..first].to_vec();
            segments.push(SegmentSpec {
                mode: specs[first].mode,
                end: specs[last].end,
            });
            segments.extend_from_slice(&specs[last + 1..]);
            let mut starts = orbit.starts[..=first].to_vec();
            starts.extend_from_slice(&orbit.starts[last + 1..]);
            let mut durations = orbit.durations[..first].to_vec();
            durations.push(orbit.durations[first..=last].iter().sum());
            durations.extend_from_slice(&orbit.durations[last + 1..]);
            (segments, starts, durations)
        }
        Span::Whole(first) => {
            let end = section_through(system, orbit, first, &arrived)?;
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

/// Refuses a join where the flow of segment `first` arrives at `arrived` but segment `last`
/// starts elsewhere.
fn check_unmoved(first: usize, last: usize, arrived: &[f64], target: &[f64]) -> Result<()> {
    let scale = 1.0 + target.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let gap = arrived
        .iter()
        .zip(target)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    if gap > JOIN_IDENTITY_TOL * scale {
        return Err(invalid(
            first,
            &format!(
                "the jumps from its end to segment {last} move the state by {gap:.3e}: not a grazing, nothing to join"
            ),
        ));
    }
    Ok(())
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
