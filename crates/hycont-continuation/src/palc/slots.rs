//! The test functions PALC watches along a run: what each slot means, where an event's value is
//! read, and the slots' values at a chart.

use super::{Chart, Palc};
use crate::branch::SpecialKind;
use crate::quantity::Quantity;
use crate::{ContinuationProblem, PointInfo};

/// Test-function values at a chart, one per slot of [`Palc::slots`], in that order.
#[derive(Debug, Clone)]
pub(super) struct Tests {
    pub(super) values: Vec<f64>,
}

/// Where an event's or bound's value is read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Source {
    /// The continuation parameter's unknown (no analysis needed).
    Continued,
    /// `info.params[i]`.
    Param(usize),
    /// `info.monitors[i]`.
    Monitor(usize),
}

impl Source {
    /// The value at chart `c` (`pi`: the continued parameter's index in the unknowns).
    pub(super) fn value(self, c: &Chart, pi: usize) -> f64 {
        match self {
            Source::Continued => c.u[pi],
            Source::Param(i) => c.info.params[i],
            Source::Monitor(i) => c.info.monitors[i],
        }
    }
}

/// What each test-function slot means.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Slot {
    Fold,
    BranchPoint,
    PeriodDoubling,
    Torus,
    Event {
        kind: SpecialKind,
        level: f64,
        source: Source,
        on: Quantity,
        terminal: bool,
    },
    Bound {
        source: Source,
        on: Quantity,
        level: f64,
    },
    /// A cusp of a fold curve: the continued parameter's tangent component changes sign where
    /// the one of the second parameter (unknown `second`) vanishes too.
    Cusp {
        second: usize,
    },
    /// A codimension-two point of a curve holding a multiplier at `held`: another multiplier
    /// crossing as `crossing` says.
    Codim2 {
        kind: SpecialKind,
        held: f64,
        crossing: Crossing,
    },
}

/// Which crossing of a multiplier other than the held one a codimension-two test watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Crossing {
    /// A real multiplier through $+1$.
    Plus,
    /// A real multiplier through $-1$.
    Minus,
    /// A complex pair through the unit circle.
    Circle,
}

impl Crossing {
    /// The kind of point where another multiplier crosses so on a curve holding one at
    /// `held`: R1, LPPD, LPNS on fold curves ($+1$); LPPD, R2, PDNS on period-doubling curves.
    pub(super) fn kind(self, held: f64) -> SpecialKind {
        match (held > 0.0, self) {
            (true, Crossing::Plus) => SpecialKind::Resonance1,
            (true, Crossing::Minus) | (false, Crossing::Plus) => SpecialKind::FoldFlip,
            (true, Crossing::Circle) => SpecialKind::FoldTorus,
            (false, Crossing::Minus) => SpecialKind::Resonance2,
            (false, Crossing::Circle) => SpecialKind::FlipTorus,
        }
    }
}

/// The codimension-two test of `crossing` on the multipliers other than the held one
/// ([`super::critical::others`]): $\prod (\lambda - 1)$, $\prod (\lambda + 1)$ (real parts
/// of complex products: a conjugate pair contributes $|\lambda \mp 1|^2 > 0$), or the torus
/// product over pairs.
fn codim2_test(info: &PointInfo, held: f64, crossing: Crossing) -> f64 {
    let others = super::critical::others(info, held);
    let trivial = vec![false; others.len()];
    match crossing {
        Crossing::Plus => crate::shifted_product(&others, &trivial, -1.0),
        Crossing::Minus => crate::shifted_product(&others, &trivial, 1.0),
        Crossing::Circle => pair_product(&others),
    }
}

/// Product over non-trivial multipliers of $(1 + \lambda)$: changes sign when a real
/// multiplier crosses $-1$.
pub(crate) fn pd_test(info: &PointInfo) -> f64 {
    crate::shifted_product(&info.multipliers, &info.trivial, 1.0)
}

/// Product over pairs of non-trivial multipliers of $(\lambda_i \lambda_j - 1)$, real part: changes
/// sign when a complex pair crosses the unit circle (also at neutral saddles, which are filtered
/// out after location).
pub(crate) fn tr_test(info: &PointInfo) -> f64 {
    let nt: Vec<(f64, f64)> = info
        .multipliers
        .iter()
        .zip(&info.trivial)
        .filter(|(_, t)| !**t)
        .map(|(m, _)| *m)
        .collect();
    pair_product(&nt)
}

/// Product over pairs of `nt` of $(\lambda_i \lambda_j - 1)$, real part.
fn pair_product(nt: &[(f64, f64)]) -> f64 {
    let mut acc = 1.0;
    for i in 0..nt.len() {
        for j in i + 1..nt.len() {
            let (a, b) = (nt[i], nt[j]);
            // Complex conjugate pair: |lambda|^2 - 1; real pairs: lambda_i lambda_j - 1.
            let re = a.0 * b.0 - a.1 * b.1;
            acc *= re - 1.0;
        }
    }
    acc
}

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// For a bound's slot, the sign its test function (value minus level) has inside the
    /// window: `+1` at its minimum, `-1` at its maximum; `None` for other slots.
    pub(super) fn inside_sign(&self, slot: usize) -> Option<f64> {
        let Slot::Bound { level, on, .. } = self.slots[slot] else {
            return None;
        };
        // A bound's two slots are adjacent: its minimum, then its maximum.
        let partner =
            [slot.wrapping_sub(1), slot + 1]
                .into_iter()
                .find_map(|k| match self.slots.get(k) {
                    Some(&Slot::Bound {
                        on: o, level: l, ..
                    }) if o == on => Some(l),
                    _ => None,
                })?;
        Some(if level <= partner { 1.0 } else { -1.0 })
    }

    pub(super) fn tests(&self, c: &Chart, det_ref: f64) -> Tests {
        let pi = self.p.parameter_index();
        let values = self
            .slots
            .iter()
            .map(|slot| match *slot {
                Slot::Fold | Slot::Cusp { .. } => c.t[pi],
                Slot::BranchPoint => {
                    c.det.0
                        * (c.det.1 - det_ref).clamp(-700.0, 700.0).exp()
                        * c.info.branch_point_factor.unwrap_or(1.0)
                }
                Slot::PeriodDoubling => pd_test(&c.info),
                Slot::Torus => tr_test(&c.info),
                Slot::Event { level, source, .. } | Slot::Bound { source, level, .. } => {
                    source.value(c, pi) - level
                }
                Slot::Codim2 { held, crossing, .. } => codim2_test(&c.info, held, crossing),
            })
            .collect();
        Tests { values }
    }

    /// The kind of special point a sign change of `slot` is.
    pub(super) fn kind_of(slot: Slot) -> SpecialKind {
        match slot {
            Slot::Fold => SpecialKind::Fold,
            Slot::Cusp { .. } => SpecialKind::Cusp,
            Slot::BranchPoint => SpecialKind::BranchPoint,
            Slot::PeriodDoubling => SpecialKind::PeriodDoubling,
            Slot::Torus => SpecialKind::Torus,
            Slot::Event { kind, .. } | Slot::Codim2 { kind, .. } => kind,
            Slot::Bound { .. } => SpecialKind::EndPoint,
        }
    }
}
