//! The signature of a hybrid periodic orbit: per segment, the mode and what ends it.

use crate::error::{Error, Result};
use crate::system::{EventAction, EventId, HybridSystem, Mode};
use serde::{Deserialize, Serialize};

/// What ends a segment of a periodic orbit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum SegmentEnd {
    /// A system event: its reset is applied and its target mode follows (COCO's event + reset).
    Event(EventId),
    /// An interior point: state component `component` equals `value` (e.g. $\psi = 0$ at an
    /// extremum of $\varphi$); the state is continuous and the mode unchanged.
    Interior {
        /// Index of the state component.
        component: usize,
        /// The value it takes.
        value: f64,
    },
}

/// One segment of a signature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SegmentSpec {
    /// The mode the segment flows in.
    pub mode: Mode,
    /// What ends it.
    pub end: SegmentEnd,
}

/// How the last segment connects back to the first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Closure {
    /// A full periodic orbit: $x_K = x_0$.
    #[default]
    Periodic,
    /// Half of a $\mathbb{Z}_2$-symmetric orbit: $x_K = S x_0$ (the system's
    /// [`crate::HybridSystem::symmetry`]), the last segment leading into $\sigma(m_0)$.
    Symmetric,
}

/// A validated, cyclic sequence of segments: segment $k$ ends where segment $k+1$ (cyclically)
/// starts, in the mode its end leads to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Signature {
    segments: Vec<SegmentSpec>,
    closure: Closure,
}

impl Signature {
    /// Validates `segments` against `system`: every event is monitored in its segment's mode and
    /// is a jump into the next segment's mode; interior points keep the mode.
    ///
    /// # Errors
    /// [`Error::InvalidSignature`] saying which segment is inconsistent.
    pub fn new<S: HybridSystem + ?Sized>(system: &S, segments: Vec<SegmentSpec>) -> Result<Self> {
        Self::with_closure(system, segments, Closure::Periodic)
    }

    /// Like [`Signature::new`] with the given closure; a [`Closure::Symmetric`] signature is half
    /// of a symmetric orbit and requires the system to have a symmetry.
    ///
    /// # Errors
    /// [`Error::InvalidSignature`] saying which segment is inconsistent;
    /// [`Error::InvalidSystem`] for modes whose dimensions do not fit their events
    /// ([`crate::check_mode_dims`]).
    pub fn with_closure<S: HybridSystem + ?Sized>(
        system: &S,
        segments: Vec<SegmentSpec>,
        closure: Closure,
    ) -> Result<Self> {
        let uniform = crate::system::uniform_dims(system);
        if !uniform {
            crate::system::check_mode_dims(system)?;
        }
        let k = segments.len();
        let symmetry = match closure {
            Closure::Periodic => None,
            // A symmetric closure needs a valid symmetry (else Error::InvalidSymmetry).
            Closure::Symmetric => Some(crate::system::checked_symmetry(system)?),
        };
        if k == 0 {
            return Err(Error::InvalidSignature {
                segment: 0,
                reason: "a signature needs at least one segment".into(),
            });
        }
        if let Some((i, seg)) = segments
            .iter()
            .enumerate()
            .find(|(_, s)| s.mode.0 >= system.mode_count())
        {
            return Err(Error::InvalidSignature {
                segment: i,
                reason: format!("mode {} does not exist", seg.mode),
            });
        }
        for (i, seg) in segments.iter().enumerate() {
            let next =
                match (&symmetry, i + 1 == k) {
                    (Some(sym), true) => *sym.modes.get(segments[0].mode.0).ok_or_else(|| {
                        Error::InvalidSignature {
                            segment: i,
                            reason: format!("the symmetry does not map mode {}", segments[0].mode),
                        }
                    })?,
                    _ => segments[(i + 1) % k].mode,
                };
            match seg.end {
                SegmentEnd::Event(e) => {
                    if !system.events(seg.mode).contains(&e) {
                        return Err(Error::InvalidSignature {
                            segment: i,
                            reason: format!("{e} is not monitored in mode {}", seg.mode),
                        });
                    }
                    match system.event_spec(e).action {
                        EventAction::Jump { to } if to == next => {}
                        EventAction::Jump { to } => {
                            return Err(Error::InvalidSignature {
                                segment: i,
                                reason: format!(
                                    "{e} leads to mode {to} but the next segment is in mode {next}"
                                ),
                            });
                        }
                        EventAction::Terminal => {
                            return Err(Error::InvalidSignature {
                                segment: i,
                                reason: format!("{e} is terminal"),
                            });
                        }
                    }
                }
                SegmentEnd::Interior { component, value } => {
                    if component >= system.mode_dim(seg.mode) || !value.is_finite() {
                        return Err(Error::InvalidSignature {
                            segment: i,
                            reason: format!("interior point x[{component}] = {value} is invalid"),
                        });
                    }
                    if next != seg.mode {
                        return Err(Error::InvalidSignature {
                            segment: i,
                            reason: "an interior point must keep the mode".into(),
                        });
                    }
                }
            }
        }
        Ok(Self { segments, closure })
    }

    /// The mode that follows segment `k` (for the last segment of a symmetric half orbit, the
    /// image $\sigma(m_0)$ of the first mode).
    #[must_use]
    pub fn next_mode<S: HybridSystem + ?Sized>(&self, system: &S, k: usize) -> Mode {
        let kk = self.segments.len();
        match (self.closure, k + 1 == kk) {
            (Closure::Symmetric, true) => system
                .symmetry()
                .map_or(self.segments[0].mode, |s| s.modes[self.segments[0].mode.0]),
            _ => self.segments[(k + 1) % kk].mode,
        }
    }

    /// How the last segment connects to the first.
    #[must_use]
    pub fn closure(&self) -> Closure {
        self.closure
    }

    /// A signature built from parts of validated ones (e.g. a repetition of a periodic
    /// signature), which is valid by construction.
    pub(crate) fn from_validated(segments: Vec<SegmentSpec>, closure: Closure) -> Self {
        Self { segments, closure }
    }

    /// The segments.
    #[must_use]
    pub fn segments(&self) -> &[SegmentSpec] {
        &self.segments
    }

    /// Number of segments.
    #[must_use]
    pub fn len(&self) -> usize {
        self.segments.len()
    }

    /// Whether there are no segments (never true for a validated signature).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }
}
