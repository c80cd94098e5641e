//! The orbit of the neighbouring signature at an interior grazing: where a segment's flow
//! touches an event surface at a turning point ([`Touch::Turn`]), the family beyond has an
//! impact there. [`split_at_grazing`] splits the segment at the turning point and inserts the
//! event with its reset; where the reset leads into another mode, the flow there leaves the
//! surface at once and returns to it (at the grazing itself in no time), so a zero-length
//! segment in that mode, ended by the event of that mode that leads back, follows (for a
//! rocking block: an impact onto the other corner, a flight on it of zero duration, an impact
//! back). The result is the same orbit (to rounding) as an orbit of the new signature: the
//! start of a branch of the family beyond the grazing.

use super::PeriodicOrbit;
use super::signature::{SegmentEnd, SegmentSpec, Signature};
use super::touch::Touch;
use crate::error::{Error, Result};
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{EventAction, HybridJacobians, Mode};

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

/// Splits `orbit` at the interior grazing `touch` (a [`Touch::Turn`] strictly inside its
/// segment) into the orbit of the signature with an impact there (see the module docs).
///
/// # Errors
/// [`Error::InvalidSignature`] for a touch that is not an interior turning point of its
/// segment, an event that does not jump, or, where the impact leads into another mode, no
/// event of that mode on whose surface the reset lands and that leads back; integration
/// failures.
pub fn split_at_grazing<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    touch: &Touch,
) -> Result<GrazingSplit> {
    let Touch::Turn {
        segment: k, event, ..
    } = *touch
    else {
        return Err(invalid(
            touch.segment(),
            "the grazing is not an interior turning point",
        ));
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
    let n = system.state_dim();
    let mut after = vec![0.0; n];
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
    let mut zero_length = None;
    let resume = if to == spec.mode {
        after
    } else {
        // The flight in the other mode: zero long at the grazing, ended by the event of that
        // mode that leads back and on whose surface the reset lands.
        let scale = 1.0 + after.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let back = system.events(to).iter().copied().find(|&e| {
            matches!(system.event_spec(e).action, EventAction::Jump { to: m } if m == spec.mode)
                && system.event(e, &after, p).abs() <= ON_SURFACE * scale
        });
        let Some(back) = back else {
            return Err(invalid(
                k,
                &format!(
                    "{event} leads into {to}, where no event that leads back to {} starts on the surface its reset lands on",
                    spec.mode
                ),
            ));
        };
        zero_length = Some(segments.len());
        segments.push(SegmentSpec {
            mode: to,
            end: SegmentEnd::Event(back),
        });
        starts.push(after.clone());
        durations.push(0.0);
        let mut resumed = vec![0.0; n];
        system.reset(back, &after, p, &mut resumed);
        resumed
    };
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

fn invalid(segment: usize, reason: &str) -> Error {
    Error::InvalidSignature {
        segment,
        reason: reason.to_string(),
    }
}
