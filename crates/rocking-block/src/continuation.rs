//! The study's continuation recipe through hycont's orbit runs: what a rocking-block branch
//! records (the exact amplitude, the grazing margin; SB and GR events), the branches of Figs. 3
//! and 4 (symmetric, switched to asymmetric at the first branch point, to period 2 at the first
//! period doubling), their labels, and the curves of Fig. 6.

use crate::error::{Error, Result};
use crate::model::{ALPHA, IMPACT_MINUS, IMPACT_PLUS, OMEGA, Parameters, RockingBlock};
use crate::orbits::{OrbitKind, orbit};
use hycont_continuation::observe::Observer;
use hycont_continuation::{
    CurveSpec, MeasureId, OrbitBranch, OrbitMethod, OrbitRun, RunDirection, SpecialKind,
};
use hycont_core::ParamId;
use hycont_core::orbit::{Extremum, GrazingMargin, ShootingSettings};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// Amp, $\max|\varphi|$ over the orbit (the true extremum), among a branch's measures.
pub const AMP: MeasureId = MeasureId::new(2);
/// The signed grazing margin of the flights' interior dips to the impact surface.
pub const GRAZING_MARGIN: MeasureId = MeasureId::new(3);

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

    /// The parameter of a handle, if it is one that is continued.
    #[must_use]
    pub fn of(id: ParamId) -> Option<Free> {
        [Free::Omega, Free::Alpha]
            .into_iter()
            .find(|f| f.id() == id)
    }

    /// The name in JSON output.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Free::Omega => "omega",
            Free::Alpha => "alpha",
        }
    }

    /// The study's range: omega in `[0.5, 4]`, alpha in `[0.01, 1.06]`.
    #[must_use]
    pub fn range(self) -> (f64, f64) {
        match self {
            Free::Omega => (0.5, 4.0),
            Free::Alpha => (0.01, 1.06),
        }
    }
}

/// The discretisation of the study's branches: multiple shooting (ten times cheaper per point
/// here than collocation, and agreeing with it to the printed digits) with integration
/// tolerances `rtol = 1e-10`, `atol = 1e-12`: the orbits' error (~1e-10) is far below the 1e-6
/// the study's comparisons need, and special points are located to 1e-9 of this problem.
#[must_use]
pub fn default_method() -> OrbitMethod {
    OrbitMethod::Shooting(ShootingSettings {
        rtol: 1e-10,
        atol: 1e-12,
    })
}

/// A run of the block at `params` in `free` over `range` by `method`, recording Amp and the
/// grazing margin (margin of the flights' interior dips to $\varphi = 0$, capped at
/// $\pi/2$), with the study's events: SB where Amp reaches the static boundary
/// $\pi/2 - \theta_b$, and GR where the margin reaches 0 (terminal: past it $\varphi$ changes sign
/// inside a flight). Orbits stand while Amp is below $\pi/2$: a branch whose Amp reaches it
/// (the block overturns) ends there. Steps 0.02 (first), 1e-8 to 0.1.
///
/// # Errors
/// Invalid parameters.
pub fn study_run<'a>(
    free: Free,
    params: &Parameters,
    range: (f64, f64),
    method: OrbitMethod,
) -> Result<OrbitRun<'a, RockingBlock>> {
    params.validate()?;
    let mut run = OrbitRun::new(&RockingBlock, free.id())?;
    run.method(method)
        .bounds(range.0, range.1)
        .steps(0.02, 1e-8, 0.1);
    let amp = run.add_measure("amp", Extremum::max_abs(0))?;
    let margin = GrazingMargin::new([IMPACT_PLUS, IMPACT_MINUS]).cap(FRAC_PI_2);
    let margin = run.add_measure("grazing_margin", margin)?;
    debug_assert_eq!((amp, margin), (AMP, GRAZING_MARGIN));
    run.bound(amp, -FRAC_PI_2, FRAC_PI_2)?
        .add_event(amp, params.static_boundary(), SpecialKind::BoundaryTouch)?
        .add_terminal_event(margin, 0.0, SpecialKind::Grazing)?;
    Ok(run)
}

/// The branch of `start` in `free` over `range`, `direction`, by `method`.
///
/// # Errors
/// If the start cannot be continued.
pub fn continue_orbit(
    name: &str,
    start: &hycont_core::orbit::PeriodicOrbit,
    free: Free,
    range: (f64, f64),
    direction: RunDirection,
    method: OrbitMethod,
    observer: &mut dyn Observer,
) -> Result<OrbitBranch> {
    let params = Parameters::from_vec(&start.params);
    let mut run = study_run(free, &params, range, method)?;
    run.observer(Box::new(observer));
    Ok(run.run(name, start, direction)?)
}

/// The study's branches of Fig. 3 (in omega at alpha = 0.66) or Fig. 4 (in alpha at omega =
/// 1.3): the symmetric branch from the Fig. 2 orbit, the asymmetric branch switched on at its
/// first branch point (to where it rejoins the symmetric one), the period-2 branch switched on
/// at the asymmetric branch's first period doubling.
///
/// # Errors
/// Numerical failures at the start or at a branch switch.
pub fn study_branches(free: Free, observer: &mut dyn Observer) -> Result<Vec<OrbitBranch>> {
    let params = Parameters::new(1.3, 0.66);
    let sym = orbit(&params, OrbitKind::Symmetric, None)?.solution.orbit;
    let mut run = study_run(free, &params, free.range(), default_method())?;
    run.observer(Box::new(observer));
    let mut out = vec![run.run("symmetric", &sym, RunDirection::Both)?];
    let Some(bp) = out[0].special(SpecialKind::BranchPoint).next() else {
        return Ok(out);
    };
    let bp = bp.point.label;
    run.stop_at(SpecialKind::BranchPoint);
    out.push(run.switch_at("asymmetric", &out[0], bp, RunDirection::Up)?);
    run.settings_mut().stop_at.clear();
    let pd = out[1].special(SpecialKind::PeriodDoubling).next();
    if let Some(pd) = pd.map(|s| s.point.label) {
        out.push(run.switch_at("period-2", &out[1], pd, RunDirection::Up)?);
    }
    Ok(out)
}

/// The asymmetric orbit at `params` leaning to the side `positive` (mean $\varphi > 0$), by
/// continuation: the symmetric orbit at `params` is continued in alpha (down, then up) to a
/// symmetry-breaking branch point, the asymmetric branch is switched on there and continued to
/// `params.alpha`, where it ends on its bound; the mirror image is taken if it leans the other
/// way. Reaches asymmetric orbits no simulation settles on (unstable ones).
///
/// # Errors
/// [`Error::NoOrbit`] if no asymmetric branch from a branch point of the symmetric orbit's
/// alpha branch reaches `params.alpha`; the symmetric orbit's errors.
pub fn asymmetric_by_continuation(
    params: &Parameters,
    positive: bool,
) -> Result<hycont_core::orbit::PeriodicOrbit> {
    params.validate()?;
    let target = params.alpha;
    let sym = orbit(params, OrbitKind::Symmetric, None)?.solution.orbit;
    let mut run = study_run(Free::Alpha, params, (0.01, 10.0), default_method())?;
    run.stop_at(SpecialKind::BranchPoint);
    for dir in [RunDirection::Down, RunDirection::Up] {
        let b = run.run("symmetric", &sym, dir)?;
        let Some(bp) = b.special(SpecialKind::BranchPoint).find(|s| s.located) else {
            continue;
        };
        let (label, at) = (bp.point.label, bp.point[ALPHA]);
        // To the target alpha, where the branch ends on its bound (or back at a branch point).
        if target > at {
            run.bounds(0.01, target);
        } else {
            run.bounds(target, 10.0);
        }
        let Ok(asym) = run.switch_at("asymmetric", &b, label, RunDirection::Up) else {
            continue;
        };
        run.bounds(0.01, 10.0);
        let Some(end) = asym
            .branch
            .end_point()
            .filter(|p| (p[ALPHA] - target).abs() < 1e-9)
        else {
            continue;
        };
        let found = asym.orbit_of(end)?;
        if found.is_symmetric(&RockingBlock, 1e-6) {
            continue;
        }
        let lean = crate::orbits::mean_phi(&found)?;
        return Ok(if (lean > 0.0) == positive {
            found
        } else {
            found.symmetric_image(&RockingBlock)?
        });
    }
    Err(Error::NoOrbit(format!(
        "no asymmetric branch from a symmetry-breaking branch point of the symmetric orbits at \
         omega = {} reaches alpha = {target}",
        params.omega
    )))
}

/// Study labels (SN1, BP1, ...) for the special points of a figure's branches: numbered per kind
/// in increasing parameter order, starting after `offsets` (Fig. 4 continues Fig. 3's
/// numbering), with points that appear on two branches (e.g. a branch point) counted once.
#[must_use]
pub fn study_labels(
    branches: &[OrbitBranch],
    free: Free,
    offsets: &[(SpecialKind, usize)],
) -> Vec<(SpecialKind, f64, f64, String)> {
    let mut all: Vec<(SpecialKind, f64, f64)> = Vec::new();
    for s in branches.iter().flat_map(|b| &b.branch.special_points) {
        if matches!(s.kind, SpecialKind::EndPoint | SpecialKind::UserPoint) {
            continue;
        }
        let (p, amp) = (s.point[free.id()], s.point[AMP]);
        if !all
            .iter()
            .any(|(k, x, a)| *k == s.kind && (x - p).abs() < 1e-6 && (a - amp).abs() < 1e-4)
        {
            all.push((s.kind, p, amp));
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

/// A two-parameter curve of Fig. 6: the kind of point it continues and the curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// SN, PD, BP, SB or GR.
    pub kind: SpecialKind,
    /// The curve (both parameters in every point).
    pub branch: OrbitBranch,
}

impl Curve {
    /// `(omega, alpha)` of every point.
    #[must_use]
    pub fn points(&self) -> Vec<(f64, f64)> {
        let pts = &self.branch.branch.points;
        pts.iter().map(|p| (p[OMEGA], p[ALPHA])).collect()
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

/// The study's two-parameter curves (Fig. 6), each from a special point of Figs. 3 and 4: SN
/// from SN1, BP from BP1, SB from SB2, GR from GR1 (continued in omega), PD from PD1 (in
/// alpha), over omega in `[0.5, 4]` and alpha in `[0.01, 1.06]`, with user points (UZ) where
/// they cross alpha = 0.66 and omega = 1.3: there they meet the special points of Figs. 3 and 4.
///
/// # Errors
/// Numerical failures.
pub fn study_curves(observer: &mut dyn Observer) -> Result<Vec<Curve>> {
    let params = Parameters::new(1.3, 0.66);
    let fig3 = study_branches(Free::Omega, observer)?;
    let fig4 = study_branches(Free::Alpha, observer)?;
    let label = |b: &OrbitBranch, k: SpecialKind, last: bool| -> Result<usize> {
        let mut it = b.special(k);
        let s = if last { it.last() } else { it.next() };
        s.map(|s| s.point.label)
            .ok_or_else(|| Error::NoOrbit(format!("no {} on branch {}", k.label(), b.branch.name)))
    };
    let mut curves = Vec::new();
    for (free, second, starts) in [
        (
            Free::Omega,
            Free::Alpha,
            vec![
                (SpecialKind::Fold, &fig3[0], false),
                (SpecialKind::BranchPoint, &fig3[0], false),
                (SpecialKind::BoundaryTouch, &fig3[1], true),
                (SpecialKind::Grazing, &fig3[0], false),
            ],
        ),
        (
            Free::Alpha,
            Free::Omega,
            vec![(SpecialKind::PeriodDoubling, &fig4[1], false)],
        ),
    ] {
        let mut run = study_run(free, &params, free.range(), default_method())?;
        run.observer(Box::new(&mut *observer));
        let spec = CurveSpec::new(second.id())
            .bounds(second.range().0, second.range().1)
            .user_points(ALPHA, [0.66])
            .user_points(OMEGA, [1.3]);
        for (kind, branch, last) in starts {
            let at = label(branch, kind, last)?;
            let curve = run.curve_at(kind.label(), branch, at, &spec)?;
            curves.push(Curve {
                kind,
                branch: curve,
            });
        }
    }
    Ok(curves)
}
