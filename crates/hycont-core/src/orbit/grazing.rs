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
//! [`super::join_at_grazing`] (`grazing_join.rs`) goes the other way.

use super::PeriodicOrbit;
use super::grazing_join::JOIN_IDENTITY_TOL;
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
/// [`super::join_at_grazing`]), a turning point not inside its segment, an end that changes the
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
    assembled(
        system,
        orbit,
        (segments, starts, durations),
        (k, zero_length),
    )
}

/// The split orbit from its pieces (the impact ending segment `k`, the zero-length flight's
/// index).
fn assembled<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    (segments, starts, durations): (Vec<SegmentSpec>, Vec<Vec<f64>>, Vec<f64>),
    (impact_segment, zero_length): (usize, Option<usize>),
) -> Result<GrazingSplit> {
    let signature = Signature::with_closure(system, segments, orbit.signature.closure())?;
    let params = orbit.params.clone();
    Ok(GrazingSplit {
        orbit: PeriodicOrbit::new(system, signature, starts, durations, params)?,
        impact_segment,
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
    assembled(
        system,
        orbit,
        (segments, starts, durations),
        (k, zero_length),
    )
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

pub(super) fn invalid(segment: usize, reason: &str) -> Error {
    Error::InvalidSignature {
        segment,
        reason: reason.to_string(),
    }
}

/// Refuses a join where the flow of segment `first` arrives at `arrived` but segment `last`
/// starts elsewhere.
pub(super) fn check_unmoved(
    first: usize,
    last: usize,
    arrived: &[f64],
    target: &[f64],
) -> Result<()> {
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
