//! Comparing a saved point (of a branch, a diagram, an atlas) with what its problem computes
//! at its unknowns again: the shared tolerances and comparisons of the re-checks that saved
//! results pass before they are used.

/// The relative tolerance within which a saved point's analysis (monitors, multipliers) must
/// be what the run computes at its unknowns again: far above the rounding of a recomputation
/// (an analysis on the full orbit of a point found on its half orbit included), far below an
/// edit that would change what the point says.
pub const ANALYSIS_TOL: f64 = 1e-6;

/// [`check_multipliers`], and where it fails, again within the multipliers' own accuracy: the
/// distance of each recomputed multiplier from the nearest of a second, independent
/// computation (`afresh`, [`crate::ContinuationProblem::analyse_afresh`]), twice over.
pub(crate) fn check_multipliers_within(
    p: &crate::BranchPoint,
    info: &crate::PointInfo,
    afresh: impl FnOnce() -> std::result::Result<crate::PointInfo, String>,
) -> std::result::Result<(), String> {
    if check_multipliers(p, info, &[]).is_ok() {
        return Ok(());
    }
    let other = afresh()?;
    let spread: Vec<f64> = info
        .multipliers
        .iter()
        .map(|m| {
            other
                .multipliers
                .iter()
                .map(|o| distance(*o, *m))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    check_multipliers(p, info, &spread)
}

/// The saved multipliers against the recomputed ones (matched nearest first, trivial ones to
/// trivial ones; each within the tolerances, plus twice its `spread` where given), and the
/// saved stability against the saved multipliers.
fn check_multipliers(
    p: &crate::BranchPoint,
    info: &crate::PointInfo,
    spread: &[f64],
) -> std::result::Result<(), String> {
    let saved = &p.multipliers;
    if saved.len() != info.multipliers.len() || p.trivial.len() != saved.len() {
        return Err(format!(
            "it has {} multipliers ({} flags), its orbit {}",
            saved.len(),
            p.trivial.len(),
            info.multipliers.len()
        ));
    }
    // Eigenvalues are computed to about the rounding of the monodromy's norm (its largest
    // multiplier, 7e9 beside 4e-7 at the rocking block's grazing): 1e4 times that is allowed
    // on top of the relative tolerance.
    let largest = info
        .multipliers
        .iter()
        .fold(0.0f64, |m, (re, im)| m.max(re.hypot(*im)));
    let noise = 1e-12 * largest;
    let allowed = |m: (f64, f64), i: usize| {
        ANALYSIS_TOL * (1.0 + m.0.hypot(m.1)) + noise + 2.0 * spread.get(i).copied().unwrap_or(0.0)
    };
    let mut claimed = vec![false; saved.len()];
    for (i, (m, t)) in info.multipliers.iter().zip(&info.trivial).enumerate() {
        let nearest = (0..saved.len())
            .filter(|&j| !claimed[j] && p.trivial[j] == *t)
            .min_by(|&a, &b| distance(saved[a], *m).total_cmp(&distance(saved[b], *m)));
        match nearest {
            Some(j) if distance(saved[j], *m) <= allowed(*m, i) => {
                claimed[j] = true;
            }
            _ => {
                return Err(format!(
                    "its multipliers {saved:?} are not its orbit's {:?}",
                    info.multipliers
                ));
            }
        }
    }
    let unstable = saved
        .iter()
        .zip(&p.trivial)
        .filter(|((re, im), t)| !**t && re.hypot(*im) > 1.0 + crate::branch::NEUTRAL_BAND)
        .count();
    if unstable != p.unstable {
        return Err(format!(
            "it says {} unstable multipliers, its multipliers have {unstable}",
            p.unstable
        ));
    }
    Ok(())
}

pub(crate) fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// Whether `a` and `b` agree to `tol` relative to `1 + |value|`.
pub(crate) fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

/// Whether two lists have the same length and agree entry by entry ([`close`]).
pub(crate) fn same_values(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| close(*x, *y, tol))
}
