//! A saved branch's points against what a run computes at their unknowns again: parameters,
//! analysis (monitors, multipliers, stability), tangents and special points. Points of a
//! branch continued on half orbits (their unknowns the exact images of their first half) are
//! analysed on the half orbit, as the run did, so that their analysis is reproduced to
//! rounding even where it is ill-conditioned (at grazing, the saltation's $1/\dot h$).

use super::problem::OrbitContinuation;
use super::run::OrbitRun;
use super::saved::OrbitBranch;
use crate::ContinuationProblem;
use crate::branch::{BranchPoint, SpecialKind};
use crate::error::{Error, Result};
use crate::recheck::{ANALYSIS_TOL, check_multipliers_within, close, distance, same_values};
use hycont_core::HybridJacobians;
use hycont_core::orbit::{Discretisation, PeriodicOrbit};

/// How far from the Jacobian's null space (relative, see [`OrbitRun::check_saved`]) a saved
/// branch point's tangent may be: it is the tangent of the chart before it, up to a step away
/// (7.7e-3 on the rocking block's asymmetric branch where it rejoins the symmetric one).
const BRANCH_POINT_TANGENT_TOL: f64 = 0.1;

/// A problem with the pattern of its augmented Jacobian $[J; t^\top]$ (and the number of
/// entries of $J$ in its values).
struct Slot<'a, S: ?Sized> {
    cp: OrbitContinuation<'a, S>,
    pattern: hycont_core::linalg::SparsePattern,
    k: usize,
}

/// The problems a saved branch's points are analysed on: the full orbits' on each
/// discretisation revision, and, for a symmetric template, the half orbits'.
struct Problems<'a, S: ?Sized> {
    full: Vec<Option<Slot<'a, S>>>,
    half: Vec<Option<Slot<'a, S>>>,
    /// The half orbits' template and the system's symmetry, when the run continues
    /// symmetric orbits on half orbits and the template is one.
    halves: Option<(PeriodicOrbit, hycont_core::Z2Symmetry)>,
}

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// Every point's parameters against its unknowns, and its analysis and tangent against
    /// this run's.
    pub(super) fn check_analyses(&self, saved: &OrbitBranch) -> Result<()> {
        let b = &saved.branch;
        let revisions = saved.rediscretised.len() + 1;
        let halves = self
            .half_orbits
            .then(|| {
                let half = saved
                    .template
                    .half_of_symmetric(self.system, self.symmetry_tol)
                    .ok()?;
                Some((half, self.system.symmetry()?))
            })
            .flatten();
        let mut problems = Problems {
            full: (0..revisions).map(|_| None).collect(),
            half: (0..revisions).map(|_| None).collect(),
            halves,
        };
        let mut singular_starts = 0;
        for p in b
            .points
            .iter()
            .chain(b.special_points.iter().map(|s| &s.point))
        {
            let bad = |reason: String| Error::InvalidPoint {
                label: p.label,
                branch: b.name.clone(),
                reason,
            };
            check_parameters(saved, p).map_err(bad)?;
            let (slot, u, t) = self.problem_of(saved, p, &mut problems)?;
            // As a run's chart: the Jacobian at the point factorised with its tangent as the
            // last row (which gives the tangent again), then the analysis (which reads that
            // factorisation, or the linearisation it cached). At a singular point (a branch
            // point, a switched branch's start) the analysis is afresh.
            let (regular, factorised) = slot.tangent(&u, &t)?;
            let info = if factorised {
                slot.cp.analyse_factorised(&u, &slot.pattern)
            } else {
                slot.cp.analyse(&u)
            }
            .map_err(|e| bad(format!("its analysis fails: {e}")))?;
            if !same_values(&p.monitors, &info.monitors, ANALYSIS_TOL) {
                return Err(bad(format!(
                    "its monitors {:?} are not its orbit's {:?}",
                    p.monitors, info.monitors
                )));
            }
            let afresh = || slot.cp.analyse_afresh(&u).map_err(|e| e.to_string());
            check_multipliers_within(p, &info, afresh).map_err(bad)?;
            let special = b.special_points.iter().find(|s| std::ptr::eq(&s.point, p));
            if let Some(special) = special {
                let s = &self.settings;
                let tolerances = (s.critical_tolerance, s.locate_tol);
                check_special(special, &info, tolerances).map_err(bad)?;
            }
            // A branch point keeps the tangent of the chart before it (its Jacobian is
            // singular): up to a step off the null space there. Elsewhere the tangent is the
            // branch's, except at one start at a singular point (a switched branch's, whose
            // tangent is the switching direction in the null space).
            let problem = slot.cp.problem_mut();
            if special.is_some_and(|s| s.kind == SpecialKind::BranchPoint) {
                let defect = null_defect(problem, &u, &t)?;
                if !(defect <= BRANCH_POINT_TANGENT_TOL) {
                    return Err(bad(format!(
                        "its tangent is not in the null space of its Jacobian (|J t| / |J||t| = {defect:e})"
                    )));
                }
            } else if !(regular <= ANALYSIS_TOL) {
                let defect = null_defect(problem, &u, &t)?;
                singular_starts += 1;
                if !(defect <= ANALYSIS_TOL && singular_starts == 1) {
                    return Err(bad(format!(
                        "its tangent is not the branch's there (the problem is singular at it, or it is not a null vector: |J t| / |J||t| = {defect:e}; at most one singular start per branch)"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The problem point `p` is analysed on, with its unknowns and tangent there: the half
    /// orbits' where its unknowns and tangent are exactly those of a half orbit's full orbit
    /// (a point of a branch continued on half orbits), else the full orbits' (a switched
    /// branch's start at a symmetry breaking: a symmetric orbit with an asymmetric tangent).
    fn problem_of<'p>(
        &self,
        saved: &OrbitBranch,
        p: &BranchPoint,
        problems: &'p mut Problems<'a, S>,
    ) -> Result<(&'p mut Slot<'a, S>, Vec<f64>, Vec<f64>)> {
        let disc = saved.discretisation_of(p)?;
        let rev = p.discretisation;
        if let Some((half, sym)) = &problems.halves {
            let half_disc = halved(disc, saved.template.segment_count());
            let (u, t) = (
                first_half(disc, &saved.template, &p.u),
                first_half(disc, &saved.template, &p.tangent),
            );
            let image = |v: &[f64]| half_disc.repeat_unknowns(half, v, Some(sym));
            if image(&u) == p.u && image(&t) == p.tangent {
                let slot = match &mut problems.half[rev] {
                    Some(slot) => slot,
                    empty => empty.insert(self.problem_on(half.clone(), half_disc)?),
                };
                return Ok((slot, u, t));
            }
        }
        let slot = match &mut problems.full[rev] {
            Some(slot) => slot,
            empty => empty.insert(self.problem_on(saved.template.clone(), disc.clone())?),
        };
        Ok((slot, p.u.clone(), p.tangent.clone()))
    }

    /// This run's problem on orbits like `like` discretised by `disc`.
    fn problem_on(&self, like: PeriodicOrbit, disc: Discretisation) -> Result<Slot<'a, S>> {
        let mut cp = OrbitContinuation::on_discretisation(
            self.system,
            like,
            disc,
            self.free,
            self.measures.clone(),
            self.events.clone(),
        )?;
        let (pattern, k) = crate::switch::augmented_pattern(cp.problem_mut())?;
        Ok(Slot { cp, pattern, k })
    }
}

impl<S: HybridJacobians + ?Sized> Slot<'_, S> {
    /// Factorises $[J(u); t^\top]$ and solves it for $e_N$: how far `t` is from the branch's
    /// tangent $x$ there (the sine of their angle; infinite where the factorisation fails or
    /// `t` is zero), and whether the factorisation succeeded.
    fn tangent(&mut self, u: &[f64], t: &[f64]) -> Result<(f64, bool)> {
        let problem = self.cp.problem_mut();
        let mut residual = vec![0.0; problem.equations()];
        let mut values = Vec::new();
        problem.evaluate(u, &mut residual, Some(&mut values))?;
        values.truncate(self.k);
        values.reserve_exact(t.len());
        values.extend_from_slice(t);
        let mut x = vec![0.0; t.len()];
        if let Some(last) = x.last_mut() {
            *last = 1.0;
        }
        if self.pattern.factorize(&values).is_err() || self.pattern.solve_in_place(&mut x).is_err()
        {
            return Ok((f64::INFINITY, false));
        }
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let (xn, tn) = (norm(&x), norm(t));
        if !(xn > 0.0 && xn.is_finite() && tn > 0.0 && tn.is_finite()) {
            return Ok((f64::INFINITY, false));
        }
        let cos = x.iter().zip(t).map(|(a, b)| a * b).sum::<f64>() / (xn * tn);
        Ok(((1.0 - cos * cos).max(0.0).sqrt(), true))
    }
}

/// The discretisation of the first half of a full orbit of `segments` segments discretised
/// by `disc` (collocation: its first half of meshes).
fn halved(disc: &Discretisation, segments: usize) -> Discretisation {
    match disc {
        Discretisation::Shooting(s) => Discretisation::Shooting(*s),
        Discretisation::Collocation { meshes, ncol } => Discretisation::Collocation {
            meshes: meshes[..segments / 2].to_vec(),
            ncol: *ncol,
        },
    }
}

/// The unknowns (or tangent) `v` of a full orbit like `like` on `disc` cut to its first half:
/// the first half of the segment values and of the durations, then the rest (the inverse of
/// [`Discretisation::repeat_unknowns`] on its image).
fn first_half(disc: &Discretisation, like: &PeriodicOrbit, v: &[f64]) -> Vec<f64> {
    let (nv, kk) = (disc.segment_values(like), like.segment_count());
    let mut out = Vec::with_capacity(v.len() - nv / 2 - kk / 2);
    out.extend_from_slice(&v[..nv / 2]);
    out.extend_from_slice(&v[nv..nv + kk / 2]);
    out.extend_from_slice(&v[nv + kk..]);
    out
}

/// A point's parameters: those of its unknowns, the held ones the template's (the problem
/// holds them there), the continued one its last unknown.
fn check_parameters(
    saved: &OrbitBranch,
    p: &crate::BranchPoint,
) -> std::result::Result<(), String> {
    let orbit = saved.orbit_of(p).map_err(|e| e.to_string())?;
    let free = saved.free.index();
    let held = saved
        .template
        .params
        .iter()
        .zip(&p.params)
        .enumerate()
        .all(|(j, (x, y))| j == free || close(*x, *y, 1e-12));
    let continued =
        p.u.last()
            .is_some_and(|x| close(*x, orbit.params[free], 1e-12));
    if same_values(&p.params, &orbit.params, 1e-12) && held && continued {
        Ok(())
    } else {
        Err(format!(
            "its parameters {:?} are not those of its unknowns {:?} with the held ones {:?}",
            p.params, orbit.params, saved.template.params
        ))
    }
}

/// How far `t` is from the null space of the Jacobian at `u`: $\max_i |(J t)_i|$ over
/// $\max_i \sum_j |J_{ij} t_j|$ (infinite for a zero or non-finite `t`).
fn null_defect(
    problem: &mut hycont_core::problem::Problem<'_>,
    u: &[f64],
    t: &[f64],
) -> Result<f64> {
    let mut residual = vec![0.0; problem.equations()];
    let mut values = Vec::new();
    problem.evaluate(u, &mut residual, Some(&mut values))?;
    let mut jt = vec![0.0; residual.len()];
    let mut scale = vec![0.0; residual.len()];
    for ((i, j), v) in problem.jacobian_entries().iter().zip(&values) {
        jt[*i] += v * t[*j];
        scale[*i] += (v * t[*j]).abs();
    }
    let worst = jt.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = scale.iter().fold(0.0f64, |m, x| m.max(*x));
    Ok(if scale > 0.0 && scale.is_finite() {
        worst / scale
    } else {
        f64::INFINITY
    })
}

/// A special point is what it says: not located only with an accuracy above the location
/// tolerance; located, a fold, branch point, period doubling or torus point has a multiplier
/// at the kind's critical value (to the run's critical tolerance, and [`ANALYSIS_TOL`] for
/// the recomputation), the one it records, and an event or bound has its quantity at its
/// level (to [`ANALYSIS_TOL`] relative).
fn check_special(
    s: &crate::SpecialPoint,
    info: &crate::PointInfo,
    (critical_tolerance, locate_tol): (f64, f64),
) -> std::result::Result<(), String> {
    if !s.located {
        if s.accuracy <= locate_tol {
            return Err(format!(
                "it says it is not located, with an accuracy {:e} within the location tolerance {locate_tol:e}",
                s.accuracy
            ));
        }
        return Ok(());
    }
    if matches!(
        s.kind,
        SpecialKind::Fold
            | SpecialKind::BranchPoint
            | SpecialKind::PeriodDoubling
            | SpecialKind::Torus
    ) {
        let tol = critical_tolerance + ANALYSIS_TOL;
        let (genuine, critical) = crate::palc::critical::genuine(s.kind, info, tol);
        if !genuine {
            return Err(format!(
                "a located {} point without a multiplier at its critical value ({critical:?})",
                s.kind
            ));
        }
        if let (Some(saved), Some(m)) = (s.critical, critical)
            && distance(saved, m) > ANALYSIS_TOL * (1.0 + m.0.hypot(m.1))
        {
            return Err(format!(
                "its critical multiplier {saved:?} is not its orbit's {m:?}"
            ));
        }
    }
    if let (Some(on), Some(level)) = (s.on, s.level) {
        let value = s.point.get(on);
        if !value.is_some_and(|v| close(v, level, ANALYSIS_TOL)) {
            return Err(format!(
                "a located {} point where {on} is {value:?}, not its level {level}",
                s.kind
            ));
        }
    }
    Ok(())
}
