//! The critical multiplier of a located special point, and whether it is genuine.
//!
//! A test function can change sign without the bifurcation it stands for: the period-doubling
//! product $\prod (1 + \lambda)$ changes sign when a multiplier passes through infinity (at
//! grazing the saltation matrix has a $1/\dot h$ factor), and the torus product when a real pair
//! crosses $\lambda_i \lambda_j = 1$ (a neutral saddle). At a located point the multiplier the
//! kind names must therefore sit at its critical value:
//! - SN, BP: a non-trivial multiplier at $+1$ (for a symmetric orbit's symmetry-breaking BP the
//!   full orbit's $\lambda = \mu^2 = 1$);
//! - PD: a real non-trivial multiplier at $-1$;
//! - TR: a non-real multiplier on the unit circle.
//!
//! Sign changes whose nearest multiplier is further than the tolerance from the critical value
//! are not reported. Problems without multipliers are not checked.

use super::slots::Crossing;
use crate::PointInfo;
use crate::branch::SpecialKind;

/// Imaginary parts below this count as real.
const REAL: f64 = 1e-8;

/// The non-trivial multiplier nearest the critical value of `kind` and its distance from it
/// (`None` for kinds without one, or without multipliers).
pub(super) fn critical_multiplier(
    kind: SpecialKind,
    info: &PointInfo,
) -> Option<((f64, f64), f64)> {
    let distance: fn((f64, f64)) -> Option<f64> = match kind {
        SpecialKind::Fold | SpecialKind::BranchPoint => |m| Some((m.0 - 1.0).hypot(m.1)),
        SpecialKind::PeriodDoubling => |m| (m.1.abs() <= REAL).then(|| (m.0 + 1.0).abs()),
        SpecialKind::Torus => |m| (m.1.abs() > REAL).then(|| (m.0.hypot(m.1) - 1.0).abs()),
        _ => return None,
    };
    info.multipliers
        .iter()
        .zip(&info.trivial)
        .filter(|(_, t)| !**t)
        .filter_map(|(m, _)| distance(*m).map(|d| (*m, d)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Whether a sign change of `kind`'s test function is genuine: the problem has no multipliers,
/// or one sits within `tol` of the critical value. Returns the critical multiplier too.
pub(crate) fn genuine(kind: SpecialKind, info: &PointInfo, tol: f64) -> (bool, Option<(f64, f64)>) {
    let checked = matches!(
        kind,
        SpecialKind::Fold
            | SpecialKind::BranchPoint
            | SpecialKind::PeriodDoubling
            | SpecialKind::Torus
    );
    if !checked || info.multipliers.is_empty() {
        return (true, None);
    }
    match critical_multiplier(kind, info) {
        Some((m, d)) => (d <= tol, Some(m)),
        None => (false, None),
    }
}

/// The non-trivial multipliers other than the one nearest `held` (the one a curve holds at its
/// critical value).
pub(super) fn others(info: &PointInfo, held: f64) -> Vec<(f64, f64)> {
    let mut nt: Vec<(f64, f64)> = info
        .multipliers
        .iter()
        .zip(&info.trivial)
        .filter(|(_, t)| !**t)
        .map(|(m, _)| *m)
        .collect();
    if let Some(i) = (0..nt.len()).min_by(|&a, &b| {
        let d = |m: (f64, f64)| (m.0 - held).hypot(m.1);
        d(nt[a]).total_cmp(&d(nt[b]))
    }) {
        nt.remove(i);
    }
    nt
}

/// Whether a located codimension-two point is genuine: among the multipliers other than the
/// held one, one at $+1$, a real one at $-1$, or a non-real one on the unit circle (not a
/// neutral saddle), within `tol`; returns that multiplier too.
pub(super) fn genuine_codim2(
    info: &PointInfo,
    held: f64,
    crossing: Crossing,
    tol: f64,
) -> (bool, Option<(f64, f64)>) {
    let distance: fn((f64, f64)) -> Option<f64> = match crossing {
        Crossing::Plus => |m| Some((m.0 - 1.0).hypot(m.1)),
        Crossing::Minus => |m| (m.1.abs() <= REAL).then(|| (m.0 + 1.0).abs()),
        Crossing::Circle => |m| (m.1.abs() > REAL).then(|| (m.0.hypot(m.1) - 1.0).abs()),
    };
    others(info, held)
        .into_iter()
        .filter_map(|m| distance(m).map(|d| (m, d)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or((false, None), |(m, d)| (d <= tol, Some(m)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(multipliers: &[(f64, f64)]) -> PointInfo {
        PointInfo {
            multipliers: multipliers.to_vec(),
            trivial: vec![false; multipliers.len()],
            ..PointInfo::default()
        }
    }

    /// A PD test that changed sign through a pole (the multiplier +2.7e9 of a collocation run
    /// at grazing) is not genuine; one at -1 is, and reports that multiplier.
    #[test]
    fn period_doubling_needs_a_real_multiplier_at_minus_one() {
        let pole = info(&[(2.7e9, 0.0), (0.3, 0.0)]);
        assert!(!genuine(SpecialKind::PeriodDoubling, &pole, 1e-4).0);
        let pd = info(&[(-1.0 + 1e-9, 0.0), (0.3, 0.0)]);
        assert_eq!(
            genuine(SpecialKind::PeriodDoubling, &pd, 1e-4),
            (true, Some((-1.0 + 1e-9, 0.0)))
        );
        // A complex pair at -1 +- i 0.01 is not a real crossing.
        let pair = info(&[(-1.0, 0.01), (-1.0, -0.01)]);
        assert!(!genuine(SpecialKind::PeriodDoubling, &pair, 1e-4).0);
    }

    /// On a fold curve (a multiplier held at +1), another at +1 is R1, at -1 LPPD, a complex
    /// pair on the unit circle LPNS; the held one never counts.
    #[test]
    fn codimension_two_points_exclude_the_held_multiplier() {
        let r1 = info(&[(1.0 + 1e-12, 0.0), (1.0 - 1e-9, 0.0), (0.3, 0.0)]);
        assert!(genuine_codim2(&r1, 1.0, Crossing::Plus, 1e-4).0);
        let fold = info(&[(1.0, 0.0), (0.3, 0.0), (-0.5, 0.0)]);
        assert!(!genuine_codim2(&fold, 1.0, Crossing::Plus, 1e-4).0);
        assert!(!genuine_codim2(&fold, 1.0, Crossing::Minus, 1e-4).0);
        let flip = info(&[(1.0, 0.0), (-1.0 + 1e-10, 0.0)]);
        assert_eq!(
            genuine_codim2(&flip, 1.0, Crossing::Minus, 1e-4),
            (true, Some((-1.0 + 1e-10, 0.0)))
        );
        assert_eq!(Crossing::Minus.kind(1.0), SpecialKind::FoldFlip);
        assert_eq!(Crossing::Plus.kind(-1.0), SpecialKind::FoldFlip);
        assert_eq!(Crossing::Minus.kind(-1.0), SpecialKind::Resonance2);
        let (c, s) = (0.6f64, 0.8f64);
        let lpns = info(&[(1.0, 0.0), (c, s), (c, -s)]);
        assert!(genuine_codim2(&lpns, 1.0, Crossing::Circle, 1e-4).0);
        let saddle = info(&[(-1.0, 0.0), (2.0, 0.0), (0.5, 0.0)]);
        assert!(!genuine_codim2(&saddle, -1.0, Crossing::Circle, 1e-4).0);
    }

    /// TR needs a complex pair on the unit circle (not a neutral saddle); SN and BP a
    /// multiplier at +1; problems without multipliers are not checked.
    #[test]
    fn torus_fold_and_branch_points() {
        let saddle = info(&[(2.0, 0.0), (0.5, 0.0)]);
        assert!(!genuine(SpecialKind::Torus, &saddle, 1e-4).0);
        let (c, s) = (0.6f64, 0.8f64);
        let ns = info(&[(c, s), (c, -s)]);
        assert!(genuine(SpecialKind::Torus, &ns, 1e-4).0);
        let fold = info(&[(1.0 + 2e-9, 0.0), (0.2, 0.0)]);
        assert!(genuine(SpecialKind::Fold, &fold, 1e-4).0);
        assert!(!genuine(SpecialKind::BranchPoint, &info(&[(0.5, 0.0)]), 1e-4).0);
        assert_eq!(
            genuine(SpecialKind::PeriodDoubling, &info(&[]), 1e-4),
            (true, None)
        );
    }
}
