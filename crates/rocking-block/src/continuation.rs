//! The study's continuation recipe through hycont's orbit runs: what a rocking-block branch
//! records (the exact amplitude, the grazing margin; SB and GR events), the branches of Figs. 3
//! and 4 (symmetric, switched to asymmetric at the first branch point, to period 2 at the first
//! period doubling), their labels, and the curves of Fig. 6.

use crate::block::Block;
use crate::error::{Error, Result};
pub use crate::model::Free;
use crate::model::{ALPHA, OMEGA, Parameters, RockingBlock};
use crate::orbits::{OrbitKind, orbit};
use hycont_continuation::atlas::AtlasSettings;
use hycont_continuation::observe::Observer;
use hycont_continuation::{
    CurveSpec, Diagram, DiagramSettings, MeasureId, OrbitAtlas, OrbitBranch, OrbitMethod, OrbitRun,
    RunDirection, SpecialKind,
};
use hycont_core::orbit::{Extremum, PeriodicOrbit, ShootingSettings};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// Amp, $\max|\varphi|$ over the orbit (the true extremum), among a branch's measures.
pub const AMP: MeasureId = MeasureId::named(4, "amp");
/// The grazing margin of every branch ([`OrbitRun::admissibility`], on by default): the
/// flights' interior dips to the impact surface, the impacts' approach rates and the margins to
/// overturning; its zero ends a branch with GR.
pub const GRAZING_MARGIN: MeasureId = MeasureId::ADMISSIBLE_GRAZING;

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

/// How the study's branches are computed: the discretisation, the arclength steps, the point
/// count and the corrector's tolerance, and (collocation) the mesh adaptation. The default is
/// the study's recipe (Figs. 3 to 5): [`default_method`], steps 0.02 (first), 1e-8 to 0.1, at
/// most 2000 points each way, Newton tolerance 1e-10, the mesh re-adapted every 10 points or
/// where its error estimate exceeds 1e-6.
///
/// ```
/// use rocking_block::continuation::Recipe;
/// let dense = Recipe { h_max: 0.02, ..Recipe::default() };
/// assert!(dense.validate().is_ok());
/// assert!(Recipe { h_min: 0.5, ..dense }.validate().is_err()); // h_min above h_max
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Recipe {
    /// The discretisation.
    pub method: OrbitMethod,
    /// First arclength step.
    pub h0: f64,
    /// Smallest arclength step before a run gives up.
    pub h_min: f64,
    /// Largest arclength step (smaller: denser branches).
    pub h_max: f64,
    /// Largest number of points of a run (each way).
    pub max_points: usize,
    /// Newton tolerance of the corrector (the step relative to $1 + |u|$).
    pub tol: f64,
    /// Collocation: re-adapt the mesh every this many points (0: only above `mesh_tol`).
    pub adapt_every: usize,
    /// Collocation: re-adapt the mesh where its error estimate exceeds this.
    pub mesh_tol: f64,
}

impl Default for Recipe {
    fn default() -> Self {
        let s = hycont_continuation::ContinuationSettings::default();
        Self {
            method: default_method(),
            h0: 0.02,
            h_min: 1e-8,
            h_max: 0.1,
            max_points: s.max_points,
            tol: s.newton.tol,
            adapt_every: s.adapt_every,
            mesh_tol: s.discretisation_tolerance,
        }
    }
}

impl Recipe {
    /// The study's recipe on another discretisation.
    #[must_use]
    pub fn with_method(method: OrbitMethod) -> Self {
        Self {
            method,
            ..Self::default()
        }
    }

    /// Whether this is the study's recipe.
    #[must_use]
    pub fn is_study(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the settings as a run would (steps ordered and positive, tolerances positive,
    /// a valid collocation mesh).
    ///
    /// # Errors
    /// The first invalid setting, named.
    pub fn validate(&self) -> Result<()> {
        if let OrbitMethod::Collocation(c) = self.method {
            c.validate()?;
        }
        let mut run = OrbitRun::new(&RockingBlock, OMEGA)?;
        self.apply(&mut run);
        run.settings_mut().validate()?;
        Ok(())
    }

    /// Sets `run`'s discretisation, steps, point count, tolerance and mesh adaptation.
    pub fn apply(&self, run: &mut OrbitRun<'_, RockingBlock>) {
        run.method(self.method)
            .steps(self.h0, self.h_min, self.h_max)
            .max_points(self.max_points);
        let s = run.settings_mut();
        s.newton.tol = self.tol;
        s.adapt_every = self.adapt_every;
        s.discretisation_tolerance = self.mesh_tol;
    }
}

/// A run of the block at `params` in `free` over `range` by `method`, recording Amp, with the
/// study's events: SB where Amp reaches the static boundary $\pi/2 - \theta_b$, and GR where
/// the run's default admissibility ends the branch ([`GRAZING_MARGIN`] reaches 0: past it
/// $\varphi$ changes sign inside a flight). Orbits stand while Amp is below $\pi/2$: a branch whose Amp reaches it
/// (the block overturns) ends there. Steps, points and tolerances: the study's [`Recipe`].
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
    Recipe::with_method(method).apply(&mut run);
    run.bounds(range.0, range.1);
    let amp = run.add_measure("amp", Extremum::max_abs(0))?;
    debug_assert_eq!(amp, AMP);
    run.bound(amp, -FRAC_PI_2, FRAC_PI_2)?.add_event(
        amp,
        params.static_boundary(),
        SpecialKind::BoundaryTouch,
    )?;
    Ok(run)
}

/// The study's branches of Fig. 3 (in omega at alpha = 0.66) or Fig. 4 (in alpha at omega =
/// 1.3): the symmetric branch from the Fig. 2 orbit, the asymmetric branch switched on at its
/// first branch point (to where it rejoins the symmetric one), the period-2 branch switched on
/// at the asymmetric branch's first period doubling; then, beyond the study, the branch
/// switched on at the symmetric branch's grazing point ([`GRAZED`], last): where the orbit's
/// interior dip touches phi = 0 it splits into two impacts with a zero-length flight between
/// them, and the family with those two extra impacts goes on from there (in both figures it
/// turns back from the grazing parameter: a branch point, a fold, and a grazing of its own).
/// Where that switch fails (another block, say) the study's branches are returned without
/// it ([`past_grazing`] says why).
///
/// # Errors
/// Numerical failures at the start or at a branch switch.
pub fn study_branches(
    free: Free,
    block: &Block,
    observer: &mut dyn Observer,
) -> Result<Vec<OrbitBranch>> {
    study_branches_with(free, block, &Recipe::default(), observer)
}

/// [`study_branches`] by another [`Recipe`]: another discretisation (the figures use shooting;
/// collocation adapts its mesh along the branches, and switches start on the mesh of the point
/// switched at), denser or sparser steps, another tolerance.
///
/// # Errors
/// As [`study_branches`]; an invalid recipe.
pub fn study_branches_with(
    free: Free,
    block: &Block,
    recipe: &Recipe,
    observer: &mut dyn Observer,
) -> Result<Vec<OrbitBranch>> {
    recipe.validate()?;
    let start = study_start(block)?;
    study_branches_from(free, block, recipe, &start, observer)
}

/// The start of the study's branches in both figures: the Fig. 2 orbit, the symmetric orbit at
/// omega = 1.3, alpha = 0.66 (found by [`orbit`]'s search over seeds on the impact surface).
/// Figs. 3 and 4 both start there: computed once, it serves both
/// ([`study_branches_from`]).
///
/// # Errors
/// An invalid block; no symmetric orbit found.
pub fn study_start(block: &Block) -> Result<PeriodicOrbit> {
    Ok(orbit(&block.at(1.3, 0.66), OrbitKind::Symmetric, None)?
        .solution
        .orbit)
}

/// [`study_branches_with`] from a given start, the Fig. 2 orbit of `block` ([`study_start`]).
///
/// ```
/// use hycont_continuation::observe::Silent;
/// use rocking_block::block::Block;
/// use rocking_block::continuation::{Free, Recipe, study_branches_from, study_start};
/// let block = Block::default();
/// let start = study_start(&block).unwrap();
/// let recipe = Recipe::default();
/// let fig3 = study_branches_from(Free::Omega, &block, &recipe, &start, &mut Silent).unwrap();
/// let fig4 = study_branches_from(Free::Alpha, &block, &recipe, &start, &mut Silent).unwrap();
/// assert_eq!(fig3[0].branch.name, fig4[0].branch.name);
/// ```
///
/// # Errors
/// As [`study_branches_with`].
pub fn study_branches_from(
    free: Free,
    block: &Block,
    recipe: &Recipe,
    start: &PeriodicOrbit,
    observer: &mut dyn Observer,
) -> Result<Vec<OrbitBranch>> {
    recipe.validate()?;
    let params = block.at(1.3, 0.66);
    let mut run = study_run(free, &params, free.range(), recipe.method)?;
    recipe.apply(&mut run);
    run.observer(Box::new(observer));
    let mut out = vec![whole(run.run("symmetric", start, RunDirection::Both)?)?];
    // Beyond the study: a switch that fails leaves the study's branches whole (the figure
    // says why, from [`past_grazing`]).
    let grazed = match grazed_from(&mut run, &out[0]) {
        Ok(b) => b.map(whole).transpose()?,
        Err(_) => None,
    };
    let Some(bp) = out[0].special(SpecialKind::BranchPoint).next() else {
        out.extend(grazed);
        return Ok(out);
    };
    let bp = bp.point.label;
    run.stop_at(SpecialKind::BranchPoint);
    out.push(whole(run.switch_at(
        "asymmetric",
        &out[0],
        bp,
        RunDirection::Up,
    )?)?);
    run.settings_mut().stop_at.clear();
    let pd = out[1].special(SpecialKind::PeriodDoubling).next();
    if let Some(pd) = pd.map(|s| s.point.label) {
        out.push(whole(run.switch_at(
            "period-2",
            &out[1],
            pd,
            RunDirection::Up,
        )?)?);
    }
    out.extend(grazed);
    Ok(out)
}

/// The name of the branch [`study_branches_from`] switches to at the symmetric branch's
/// grazing point: the symmetric orbits with the dip's two extra impacts.
pub const GRAZED: &str = "past grazing";

/// The branch past the first grazing point of `symmetric` (a symmetric branch of Fig. 3 or 4
/// in `free`, e.g. the first of [`study_branches_from`]), by `recipe` (`None` without a
/// grazing point): what [`study_branches_from`] adds to the study's branches where the switch
/// succeeds.
///
/// # Errors
/// An invalid recipe; the switch's failure ([`Error::Continuation`]).
pub fn past_grazing(
    free: Free,
    block: &Block,
    recipe: &Recipe,
    symmetric: &OrbitBranch,
    observer: &mut dyn Observer,
) -> Result<Option<OrbitBranch>> {
    recipe.validate()?;
    let mut run = study_run(free, &block.at(1.3, 0.66), free.range(), recipe.method)?;
    recipe.apply(&mut run);
    run.observer(Box::new(observer));
    grazed_from(&mut run, symmetric)?.map(whole).transpose()
}

fn grazed_from(
    run: &mut OrbitRun<'_, RockingBlock>,
    symmetric: &OrbitBranch,
) -> Result<Option<OrbitBranch>> {
    let Some(gr) = symmetric.special(SpecialKind::Grazing).next() else {
        return Ok(None);
    };
    let label = gr.point.label;
    Ok(Some(run.switch_at(
        GRAZED,
        symmetric,
        label,
        RunDirection::Up,
    )?))
}

/// The block's bifurcation diagram in `free` over `window` from `start` (its first branch named
/// `name`) in one call
/// ([`OrbitRun::diagram`] on the study's run: Amp, SB events, GR and DB ends, the [`Recipe`]'s
/// steps): the branch through `start` both ways, then at every BP and PD up to
/// `settings.depth` levels (and `settings.max_branches` branches) the branch switched on
/// there. From the Fig. 2 orbit at depth 2 it holds every special point of Fig. 3 (in omega)
/// or Fig. 4 (in alpha); deeper in alpha, the period-doubling cascade.
///
/// # Errors
/// Invalid parameters or recipe; no branch through `start`.
pub fn study_diagram(
    name: &str,
    free: Free,
    window: (f64, f64),
    recipe: &Recipe,
    start: &PeriodicOrbit,
    settings: &DiagramSettings,
    observer: &mut dyn Observer,
) -> Result<Diagram> {
    recipe.validate()?;
    let params = Parameters::from_vec(&start.params);
    let mut run = study_run(free, &params, window, recipe.method)?;
    recipe.apply(&mut run);
    run.observer(Box::new(observer));
    Ok(run.diagram(name, start, settings)?)
}

/// A two-parameter curve of Fig. 6: the kind of point it continues and the curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// SN, PD, BP, SB or GR.
    pub kind: SpecialKind,
    /// The curve (both parameters in every point).
    pub branch: OrbitBranch,
}

/// The study's two-parameter curves (Fig. 6), each from a special point of Figs. 3 and 4: SN
/// from SN1, BP from BP1, SB from SB2, GR from GR1 (continued in omega), PD from PD1 (in
/// alpha), over omega in `[0.5, 4]` and alpha in `[0.01, 1.06]`, with user points (UZ) where
/// they cross alpha = 0.66 and omega = 1.3: there they meet the special points of Figs. 3 and 4.
///
/// # Errors
/// Numerical failures.
pub fn study_curves(block: &Block, observer: &mut dyn Observer) -> Result<Vec<Curve>> {
    let params = block.at(1.3, 0.66);
    let (start, recipe) = (study_start(block)?, Recipe::default());
    let fig3 = study_branches_from(Free::Omega, block, &recipe, &start, observer)?;
    let fig4 = study_branches_from(Free::Alpha, block, &recipe, &start, observer)?;
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
            let curve = whole(run.curve_at(kind.label(), branch, at, &spec)?)?;
            curves.push(Curve {
                kind,
                branch: curve,
            });
        }
    }
    Ok(curves)
}

/// The window of the study's atlas ([`study_atlas`]): omega in [0.7, 4], alpha in [0.1, 0.9].
pub const ATLAS_WINDOW: [(f64, f64); 2] = [(0.7, 4.0), (0.1, 0.9)];

/// The settings of the study's atlas: chart radii 0.05 (first), 1e-3 to 0.1 (arclength in the
/// branches' weighted norm), the window [`ATLAS_WINDOW`], Amp within $\pm\pi/2$ (past it the
/// block overturns), the fold (SN) as an edge besides the run's GR and DB.
#[must_use]
pub fn atlas_settings() -> AtlasSettings {
    let [(w0, w1), (a0, a1)] = ATLAS_WINDOW;
    AtlasSettings::default()
        .radii(0.05, 1e-3, 0.1)
        .max_charts(5000)
        .bound(OMEGA, w0, w1)
        .bound(ALPHA, a0, a1)
        .bound(AMP, -FRAC_PI_2, FRAC_PI_2)
}

/// The atlas named `name` of the block's symmetric period-one orbits in (omega, alpha) through
/// `start` (e.g. the Fig. 2 orbit, [`study_start`]), on half orbits, by `method`
/// ([`OrbitRun::atlas`] on the study's run: Amp measured, GR and DB edges), with `settings`
/// ([`atlas_settings`] for the study's): its edges are the fold (SN) curve, the grazing (GR)
/// curve and the window's bounds.
///
/// # Errors
/// An invalid start or settings; no orbit near the start.
pub fn study_atlas(
    name: &str,
    start: &PeriodicOrbit,
    method: OrbitMethod,
    settings: &AtlasSettings,
    observer: &mut dyn Observer,
) -> Result<OrbitAtlas> {
    let params = Parameters::from_vec(&start.params);
    let mut run = study_run(Free::Omega, &params, ATLAS_WINDOW[0], method)?;
    run.observer(Box::new(observer));
    let atlas = run.atlas(name, start, ALPHA, settings)?;
    if atlas.atlas.end == hycont_continuation::atlas::AtlasEnd::Stopped {
        return Err(stopped());
    }
    Ok(atlas)
}

/// A branch or curve of the recipe, unless its observer stopped it ([`Error::Interrupted`]:
/// the recipe is not complete without it).
fn whole(branch: OrbitBranch) -> Result<OrbitBranch> {
    if branch.branch.end == hycont_continuation::EndReason::Stopped {
        Err(stopped())
    } else {
        Ok(branch)
    }
}

fn stopped() -> Error {
    Error::Interrupted {
        detail: "the continuation was stopped".into(),
    }
}
