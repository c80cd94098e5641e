//! Continuation of the rocking block's periodic orbits: the study's branches (Figs. 3 and 4),
//! branch JSON in the study's format, and restarts.

use crate::error::{Error, Result};
use crate::model::{ALPHA, OMEGA, Parameters, RockingBlock};
use crate::orbits::{
    OrbitKind, RockingOrbit, amplitude, grazing_margin, mean_phi, orbit, solve_with_extrema,
};
use hycont_continuation::observe::Observer;
use hycont_continuation::observe::Silent;
use hycont_continuation::{
    Branch, BranchPoint, ContinuationSettings, EndReason, Measures, MonitorEvent,
    OrbitContinuation, OrbitMethod, SpecialKind, branch_switch_direction, continue_along,
    continue_branch,
};
use hycont_core::ParamId;
use hycont_core::orbit::{PeriodicOrbit, ShootingSettings};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::f64::consts::FRAC_PI_2;

/// Index of Amp among the monitors of a rocking-block branch (after `period` and
/// `min_duration`).
pub const AMP: usize = 2;

/// Index of the signed grazing margin (see [`grazing_margin`]) among the monitors.
pub const GRAZING_MARGIN: usize = 3;

/// The parameter continued.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Free {
    /// The forcing frequency.
    Omega,
    /// The forcing amplitude.
    Alpha,
}

impl Free {
    /// The parameter handle.
    #[must_use]
    pub fn id(self) -> ParamId {
        match self {
            Free::Omega => OMEGA,
            Free::Alpha => ALPHA,
        }
    }

    /// The name in JSON output.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Free::Omega => "omega",
            Free::Alpha => "alpha",
        }
    }
}

/// The measures recorded along rocking-block branches: the exact amplitude and the signed
/// grazing margin.
#[must_use]
pub fn measures() -> Measures<'static> {
    Measures {
        names: vec!["amp".into(), "grazing_margin".into()],
        compute: Box::new(|o: &PeriodicOrbit| vec![amplitude(o), grazing_margin(o)]),
    }
}

/// The events: boundary touch SB where Amp reaches the static boundary $\pi/2 - \theta_b$,
/// and grazing GR where an interior dip of a flight reaches the impact surface (the grazing
/// margin reaches 0; terminal: past it the orbit is not admissible). Grazing by a collapsing
/// flight is built into every orbit continuation.
#[must_use]
pub fn events(params: &Parameters) -> Vec<MonitorEvent> {
    vec![
        MonitorEvent {
            kind: SpecialKind::BoundaryTouch,
            monitor: AMP,
            level: params.static_boundary(),
            terminal: false,
        },
        MonitorEvent {
            kind: SpecialKind::Grazing,
            monitor: GRAZING_MARGIN,
            level: 0.0,
            terminal: true,
        },
    ]
}

/// The discretisation used for the study's branches: multiple shooting (ten times cheaper per
/// point here than collocation, and agreeing with it to the printed digits) with integration
/// tolerances `rtol = 1e-10`, `atol = 1e-12`: the orbits' error (~1e-10) is far below the
/// 1e-6 the study's comparisons need, and special points are located to 1e-9 of this problem.
#[must_use]
pub fn default_method() -> OrbitMethod {
    OrbitMethod::Shooting(ShootingSettings {
        rtol: 1e-10,
        atol: 1e-12,
    })
}

/// Settings for a branch in `free` over `[min, max]`. Orbits stand while their amplitude is
/// below $\pi/2$: a branch whose amplitude reaches it (the block overturns) ends there with a
/// located end point on the `amp` bound.
#[must_use]
pub fn settings(min: f64, max: f64) -> ContinuationSettings {
    ContinuationSettings::default()
        .parameter_bounds(min, max)
        .monitor_bounds(AMP, -FRAC_PI_2, FRAC_PI_2)
        .steps(0.02, 1e-8, 0.1)
}

/// The located special point a run ended on (a bound, an inadmissible orbit, a `stop_at`
/// kind): the last point of the branch it ends, which the run's points stop short of.
fn end_point(b: &Branch) -> Option<BranchPoint> {
    let ended_on_special = matches!(
        b.end,
        EndReason::Bound | EndReason::Inadmissible(_) | EndReason::Reached(_)
    );
    b.special_points
        .last()
        .filter(|s| ended_on_special && s.located)
        .map(|s| s.point.clone())
}

/// Appends the located special point a run ended on to its points (see [`end_point`]), so
/// that the branch's points reach it (figures draw them), and relabels.
fn close_end(b: &mut Branch) {
    if let Some(p) = end_point(b) {
        b.points.push(p);
    }
    relabel(b);
}

/// Joins a backward and a forward run from the same start into one branch, in increasing
/// continuation order (backward reversed), with the end points the runs ended on at both ends
/// (see [`end_point`]), relabelled.
fn join(name: &str, backward: Branch, forward: Branch) -> Branch {
    let mut points: Vec<BranchPoint> = end_point(&backward).into_iter().collect();
    let fwd_end = end_point(&forward);
    points.extend(backward.points.into_iter().rev());
    points.extend(forward.points.into_iter().skip(1));
    points.extend(fwd_end);
    let mut specials = backward.special_points;
    specials.reverse();
    specials.extend(forward.special_points);
    let mut out = Branch {
        name: name.to_string(),
        points,
        special_points: specials,
        end: forward.end,
        statistics: backward.statistics + forward.statistics,
        ..forward
    };
    relabel(&mut out);
    out
}

fn relabel(b: &mut Branch) {
    for (i, p) in b.points.iter_mut().enumerate() {
        p.label = i + 1;
    }
    let base = b.points.len();
    for (i, s) in b.special_points.iter_mut().enumerate() {
        s.point.label = base + i + 1;
    }
}

/// Relative tolerance to which a start orbit must be symmetric to be continued on its half
/// orbit.
const SYMMETRIC_TOL: f64 = 1e-6;

/// The continuation problem of a rocking-block orbit in `free` (the study's measures and
/// events) and its starting unknowns. A symmetric orbit (to 1e-6) is continued on its half
/// orbit: the same orbits and special points for half the work per point (see
/// [`OrbitContinuation`]); [`continue_in`] returns its branches in the full orbit's unknowns.
///
/// # Errors
/// Invalid parameters, or an orbit that cannot be solved or continued.
pub fn orbit_continuation(
    start: &PeriodicOrbit,
    free: Free,
    method: &OrbitMethod,
) -> Result<(OrbitContinuation<'static, RockingBlock>, Vec<f64>)> {
    let params = Parameters {
        omega: start.params[0],
        alpha: start.params[1],
        xi: start.params[2],
        theta_b: start.params[3],
    };
    params.validate()?;
    let half;
    let start = if start.is_symmetric(&RockingBlock, SYMMETRIC_TOL) {
        half = start.half_of_symmetric(&RockingBlock, SYMMETRIC_TOL)?;
        &half
    } else {
        start
    };
    OrbitContinuation::new(
        &RockingBlock,
        start,
        method,
        free.id(),
        measures(),
        events(&params),
    )
    .map_err(cont_err)
}

/// Runs `cp` from `u0` with `settings` in `direction`. The branch ends with the located special
/// point a run ended on (a bound, an inadmissible orbit, a `stop_at` kind); both ways, the runs
/// are joined, unless the first closes the branch (a closed curve, all of it in that run).
/// Points are in the full orbit's unknowns (see [`OrbitContinuation::full_branch`]).
///
/// # Errors
/// If the start cannot be continued.
pub fn continue_in(
    cp: &mut OrbitContinuation<'static, RockingBlock>,
    name: &str,
    u0: &[f64],
    direction: Direction,
    settings: &ContinuationSettings,
    observer: &mut dyn Observer,
) -> Result<Branch> {
    let mut run = |dir: f64, observer: &mut dyn Observer| {
        continue_branch(cp, name, u0, dir, settings, observer).map_err(cont_err)
    };
    let single = |mut b: Branch| {
        close_end(&mut b);
        b
    };
    let branch = match direction {
        Direction::Up => single(run(1.0, observer)?),
        Direction::Down => single(run(-1.0, observer)?),
        Direction::Both => {
            let back = run(-1.0, observer)?;
            if back.end == EndReason::Closed {
                single(back)
            } else {
                let fwd = run(1.0, observer)?;
                join(name, back, fwd)
            }
        }
    };
    Ok(cp.full_branch(&branch))
}

/// The branch of `start` in `free` over `[min, max]`, both directions, joined, and the
/// problem of full orbits to switch branches on (see
/// [`OrbitContinuation::full_orbit_problem`]).
///
/// # Errors
/// If the start orbit cannot be continued.
pub fn branch_both_ways(
    name: &str,
    start: &PeriodicOrbit,
    free: Free,
    min: f64,
    max: f64,
    observer: &mut dyn Observer,
) -> Result<(Branch, OrbitContinuation<'static, RockingBlock>)> {
    let (mut cp, u0) = orbit_continuation(start, free, &default_method())?;
    let s = settings(min, max);
    let b = continue_in(&mut cp, name, &u0, Direction::Both, &s, observer)?;
    let full = if cp.is_half_orbit() {
        cp.full_orbit_problem(measures()).map_err(cont_err)?
    } else {
        cp
    };
    Ok((b, full))
}

/// Converts a continuation error.
pub(crate) fn cont_err(e: hycont_continuation::Error) -> Error {
    match e {
        hycont_continuation::Error::Core(c) => Error::Core(c),
        other => Error::Continuation(other.to_string()),
    }
}

/// The study's branches of Fig. 3 (continuation in omega at alpha = 0.66) or Fig. 4 (in alpha at
/// omega = 1.3).
///
/// # Errors
/// Numerical failures at the start or at a branch switch.
pub fn study_branches(free: Free, observer: &mut dyn Observer) -> Result<Vec<Branch>> {
    let params = Parameters::new(1.3, 0.66);
    let sym = orbit(&params, OrbitKind::Symmetric, None)?.solution.orbit;
    let (min, max) = match free {
        Free::Omega => (0.5, 4.0),
        Free::Alpha => (0.01, 1.06),
    };
    let (symmetric, mut cp) = branch_both_ways("symmetric", &sym, free, min, max, observer)?;
    let mut out = vec![symmetric];
    // The asymmetric branch from the first branch point (BP1 in omega, BP3 in alpha).
    let Some(bp) = out[0].special(SpecialKind::BranchPoint).next().cloned() else {
        return Ok(out);
    };
    let phi = branch_switch_direction(&mut cp, &bp.point.u, &bp.point.tangent).map_err(cont_err)?;
    let s = settings(min, max).stop_at(SpecialKind::BranchPoint);
    let mut asym = continue_along(&mut cp, "asymmetric", &bp.point.u, &phi, 1.0, &s, observer)
        .map_err(cont_err)?;
    // Start the asymmetric branch at the branch point itself.
    asym.points.insert(0, bp.point.clone());
    // It ends where it rejoins the symmetric branch, at another branch point. Located from the
    // asymmetric side, the corrector can slip onto the symmetric branch (both cross the chart's
    // hyperplanes there), so use the symmetric branch's located point: the same orbit.
    if asym.end == EndReason::Reached(SpecialKind::BranchPoint)
        && let Some(end) = asym.special_points.last().cloned()
    {
        let q = free.id().index();
        let near = out[0]
            .special(SpecialKind::BranchPoint)
            .filter(|s| s.located)
            .min_by(|x, y| {
                (x.point.params[q] - end.bracket.1)
                    .abs()
                    .total_cmp(&(y.point.params[q] - end.bracket.1).abs())
            })
            .cloned();
        if let Some(sym_bp) = near.filter(|s| (s.point.params[q] - end.bracket.1).abs() < 1e-2) {
            asym.special_points.pop();
            asym.special_points.push(sym_bp);
        }
    }
    close_end(&mut asym);
    let pd = asym.special(SpecialKind::PeriodDoubling).next().cloned();
    out.push(asym);
    // The period-2 branch from the first period doubling.
    if let Some(pd) = pd {
        let (mut doubled, u0, dir) = cp
            .from_period_doubling(&pd.point, measures())
            .map_err(cont_err)?;
        let s = settings(min, max);
        let mut p2 = continue_along(&mut doubled, "period-2", &u0, &dir, 1.0, &s, observer)
            .map_err(cont_err)?;
        close_end(&mut p2);
        out.push(p2);
    }
    Ok(out)
}

/// The asymmetric orbit at `params` leaning to the side `positive` (mean $\varphi > 0$), by
/// continuation: the symmetric orbit at `params` is continued in alpha (down, then up) to a
/// symmetry-breaking branch point, the asymmetric branch is switched on there and continued to
/// `params.alpha`, where it ends with a located end point; the mirror image is taken if it leans
/// the other way. Reaches asymmetric orbits no simulation settles on (unstable ones).
///
/// # Errors
/// [`Error::Continuation`] if no asymmetric branch from a branch point of the symmetric orbit's
/// alpha branch reaches `params.alpha`; the symmetric orbit's errors.
pub fn asymmetric_by_continuation(params: &Parameters, positive: bool) -> Result<RockingOrbit> {
    params.validate()?;
    let target = params.alpha;
    let sym = orbit(params, OrbitKind::Symmetric, None)?.solution.orbit;
    let (mut cp, u0) = orbit_continuation(&sym, Free::Alpha, &default_method())?;
    let (lo, hi) = (0.01, 10.0);
    let q = ALPHA.index();
    for dir in [-1.0, 1.0] {
        let s = settings(lo, hi).stop_at(SpecialKind::BranchPoint);
        let b =
            continue_branch(&mut cp, "symmetric", &u0, dir, &s, &mut Silent).map_err(cont_err)?;
        let Some(bp) = b
            .special(SpecialKind::BranchPoint)
            .find(|s| s.located)
            .map(|s| cp.full_point(&s.point))
        else {
            continue;
        };
        let mut full = cp.full_orbit_problem(measures()).map_err(cont_err)?;
        let Ok(phi) = branch_switch_direction(&mut full, &bp.u, &bp.tangent) else {
            continue;
        };
        // To the target alpha, where the branch ends on its bound (or back at a branch point).
        let bounds = if target > bp.params[q] {
            (lo, target)
        } else {
            (target, hi)
        };
        let s = settings(bounds.0, bounds.1).stop_at(SpecialKind::BranchPoint);
        let asym = continue_along(&mut full, "asymmetric", &bp.u, &phi, 1.0, &s, &mut Silent)
            .map_err(cont_err)?;
        let Some(end) = end_point(&asym).filter(|p| (p.params[q] - target).abs() < 1e-9) else {
            continue;
        };
        let found = full.orbit(&end.u);
        if found.is_symmetric(&RockingBlock, SYMMETRIC_TOL) {
            continue;
        }
        let found = if (mean_phi(&found)? > 0.0) == positive {
            found
        } else {
            found.symmetric_image(&RockingBlock)?
        };
        return solve_with_extrema(&found);
    }
    Err(Error::Continuation(format!(
        "no asymmetric branch from a symmetry-breaking branch point of the symmetric orbits at \
         omega = {} reaches alpha = {target}",
        params.omega
    )))
}

fn multipliers_json(m: &[(f64, f64)]) -> Value {
    Value::Array(m.iter().map(|(a, b)| json!([a, b])).collect())
}

/// A branch in the study's JSON format (`name`, `free`, `points`, `special_points`), with the
/// end reason and labels added.
#[must_use]
pub fn branch_json(b: &Branch, free: Free) -> Value {
    let point = |p: &BranchPoint| {
        json!({
            "label": p.label,
            "omega": p.params[0],
            "alpha": p.params[1],
            "amp": p.monitors[AMP],
            "period": p.monitors[0],
            "stable": p.stable(),
            "unstable": p.unstable,
            "multipliers": multipliers_json(&p.multipliers),
            "trivial": p.trivial,
            "newton_iterations": p.newton_iterations,
        })
    };
    json!({
        "name": b.name,
        "free": [free.name()],
        "end": format!("{:?}", b.end),
        "points": b.points.iter().map(point).collect::<Vec<_>>(),
        "special_points": b.special_points.iter().map(|s| json!({
            "kind": s.kind.label(),
            "label": s.point.label,
            "omega": s.point.params[0],
            "alpha": s.point.params[1],
            "amp": s.point.monitors[AMP],
            "period": s.point.monitors[0],
            "stable": s.point.stable(),
            "multipliers": multipliers_json(&s.point.multipliers),
            "located": s.located,
            "accuracy": s.accuracy,
            "bracket": [s.bracket.0, s.bracket.1],
        })).collect::<Vec<_>>(),
    })
}

/// Study labels (SN1, BP1, ...) for the special points of a figure's branches: numbered per kind
/// in increasing parameter order, starting after `offsets` (Fig. 4 continues Fig. 3's
/// numbering), with points that appear on two branches (e.g. a branch point) counted once.
#[must_use]
pub fn study_labels(
    branches: &[Branch],
    free: Free,
    offsets: &[(SpecialKind, usize)],
) -> Vec<(SpecialKind, f64, f64, String)> {
    let q = free.id().index();
    let mut all: Vec<(SpecialKind, f64, f64)> = Vec::new();
    for b in branches {
        for s in &b.special_points {
            if s.kind == SpecialKind::EndPoint {
                continue;
            }
            let (p, amp) = (s.point.params[q], s.point.monitors[AMP]);
            if !all
                .iter()
                .any(|(k, x, a)| *k == s.kind && (x - p).abs() < 1e-6 && (a - amp).abs() < 1e-4)
            {
                all.push((s.kind, p, amp));
            }
        }
    }
    all.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut counts: Vec<(SpecialKind, usize)> = offsets.to_vec();
    all.into_iter()
        .map(|(k, p, a)| {
            let n = match counts.iter_mut().find(|(kk, _)| *kk == k) {
                Some((_, c)) => {
                    *c += 1;
                    *c
                }
                None => {
                    counts.push((k, 1));
                    1
                }
            };
            (k, p, a, format!("{}{n}", k.label()))
        })
        .collect()
}

/// Whether a branch ended where it should (bounds, a stop point, admissibility) rather than by
/// a failure.
#[must_use]
pub fn ended_cleanly(b: &Branch) -> bool {
    !matches!(b.end, EndReason::CorrectorFailed(_))
}

/// A saved continuation run: the branch (with unknowns and tangents at every point) and what is
/// needed to restart from any of its labelled points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedRun {
    /// The parameter continued.
    pub free: Free,
    /// The orbit the run started from (its signature is the branch's).
    pub start: PeriodicOrbit,
    /// The branch, in `hycont-continuation`'s format.
    pub branch: Branch,
}

impl SavedRun {
    /// The orbit at a labelled point (shooting layout: start states, durations, parameters).
    ///
    /// # Errors
    /// [`Error::Continuation`] if the label does not exist.
    pub fn orbit_at(&self, label: usize) -> Result<(PeriodicOrbit, f64)> {
        let p = self.branch.point(label).map_err(cont_err)?;
        let orbit = hycont_core::orbit::unpack(&self.start, &p.u);
        // Direction of the run at that point: the sign of the tangent's parameter component
        // (the last unknown is the active parameter).
        let dir = p.tangent.last().copied().unwrap_or(1.0).signum();
        Ok((orbit, if dir == 0.0 { 1.0 } else { dir }))
    }
}

/// Which way(s) to continue.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Both ways from the start (decreasing first), joined in increasing order.
    Both,
    /// Increasing parameter.
    Up,
    /// Decreasing parameter.
    Down,
}

/// Continues `start` in `free` over `[min, max]` in the given direction(s).
///
/// # Errors
/// If the start cannot be continued.
#[allow(clippy::too_many_arguments)]
pub fn continue_orbit(
    name: &str,
    start: &PeriodicOrbit,
    free: Free,
    min: f64,
    max: f64,
    direction: Direction,
    method: &OrbitMethod,
    observer: &mut dyn Observer,
) -> Result<Branch> {
    let (mut cp, u0) = orbit_continuation(start, free, method)?;
    continue_in(&mut cp, name, &u0, direction, &settings(min, max), observer)
}

/// A two-parameter curve of the study: the kind of point it continues and the branch in
/// (omega, alpha) (continued in omega; alpha is the last monitor).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// SN, PD, BP, SB or GR.
    pub kind: SpecialKind,
    /// The curve.
    pub branch: Branch,
}

impl Curve {
    /// `(omega, alpha)` of every point.
    #[must_use]
    pub fn points(&self) -> Vec<(f64, f64)> {
        self.branch
            .points
            .iter()
            .map(|p| (p.params[0], p.params[1]))
            .collect()
    }

    /// alpha at `omega` by linear interpolation along the curve (the first crossing), if the
    /// curve reaches that omega.
    #[must_use]
    pub fn alpha_at(&self, omega: f64) -> Option<f64> {
        self.points().windows(2).find_map(|w| {
            let ((w0, a0), (w1, a1)) = (w[0], w[1]);
            let (lo, hi) = (w0.min(w1), w0.max(w1));
            (omega >= lo && omega <= hi && hi > lo)
                .then(|| a0 + (a1 - a0) * (omega - w0) / (w1 - w0))
        })
    }
}

/// Continues a two-parameter curve through `orbit` in both directions over omega in
/// `[0.5, 4.0]`, alpha in `(0, 1.06]`, joined.
///
/// # Errors
/// If the curve's start cannot be solved.
pub fn curve(
    name: &str,
    orbit: &PeriodicOrbit,
    condition: hycont_continuation::Condition,
    omega_range: (f64, f64),
    observer: &mut dyn Observer,
) -> Result<Curve> {
    use hycont_continuation::{Codim2, ContinuationProblem, curve_settings};
    let (mut cp, u0) = Codim2::new(
        &RockingBlock,
        orbit,
        ShootingSettings {
            rtol: 1e-10,
            atol: 1e-12,
        },
        OMEGA,
        ALPHA,
        condition,
        measures(),
        measures(),
    )
    .map_err(cont_err)?;
    let alpha_monitor = cp.monitor_names().len() - 1;
    let s = curve_settings()
        .parameter_bounds(omega_range.0, omega_range.1)
        .monitor_bounds(alpha_monitor, 0.01, 1.06);
    let back = continue_branch(&mut cp, name, &u0, -1.0, &s, observer).map_err(cont_err)?;
    let fwd = continue_branch(&mut cp, name, &u0, 1.0, &s, observer).map_err(cont_err)?;
    Ok(Curve {
        kind: condition.kind(),
        branch: join(name, back, fwd),
    })
}

/// The study's two-parameter curves (Fig. 6), started from the special points of Figs. 3 and 4:
/// SN from SN1, BP from BP1, PD from PD1, SB from SB2 and GR from GR1 (symmetric-orbit folds and
/// branch points on the half-orbit problem).
///
/// # Errors
/// Numerical failures.
pub fn study_curves(observer: &mut dyn Observer) -> Result<Vec<Curve>> {
    use hycont_continuation::Condition;
    use hycont_core::orbit::unpack;
    let params = Parameters::new(1.3, 0.66);
    let fig3 = study_branches(Free::Omega, observer)?;
    let fig4 = study_branches(Free::Alpha, observer)?;
    let template = orbit(&params, OrbitKind::Symmetric, None)?.solution.orbit;
    let at = |p: &BranchPoint| unpack(&template, &p.u);
    let find = |b: &Branch, k: SpecialKind| -> Result<BranchPoint> {
        b.special(k)
            .next()
            .map(|s| s.point.clone())
            .ok_or_else(|| Error::Continuation(format!("no {} on branch {}", k.label(), b.name)))
    };
    let range = (0.5, 4.0);
    let mut curves = Vec::new();
    let sn = at(&find(&fig3[0], SpecialKind::Fold)?).half_of_symmetric(&RockingBlock, 1e-5)?;
    curves.push(curve("SN", &sn, Condition::SymmetricFold, range, observer)?);
    let bp =
        at(&find(&fig3[0], SpecialKind::BranchPoint)?).half_of_symmetric(&RockingBlock, 1e-5)?;
    curves.push(curve(
        "BP",
        &bp,
        Condition::SymmetryBreaking,
        range,
        observer,
    )?);
    let pd = at(&find(&fig4[1], SpecialKind::PeriodDoubling)?);
    curves.push(curve(
        "PD",
        &pd,
        Condition::PeriodDoubling,
        range,
        observer,
    )?);
    let sb = fig3[1]
        .special(SpecialKind::BoundaryTouch)
        .last()
        .map(|s| s.point.clone())
        .ok_or_else(|| Error::Continuation("no SB on the asymmetric branch".into()))?;
    curves.push(curve(
        "SB",
        &at(&sb),
        Condition::Monitor {
            index: 0,
            level: params.static_boundary(),
        },
        range,
        observer,
    )?);
    // Grazing of a flight's interior dip: the grazing margin (measure 1) held at zero. On a
    // symmetric orbit the mirror flight grazes at the same point: use the half orbit.
    let gr = at(&find(&fig3[0], SpecialKind::Grazing)?).half_of_symmetric(&RockingBlock, 1e-5)?;
    curves.push(curve(
        "GR",
        &gr,
        Condition::Grazing { index: 1 },
        range,
        observer,
    )?);
    Ok(curves)
}
