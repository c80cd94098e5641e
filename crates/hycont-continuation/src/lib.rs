//! # hycont-continuation
//!
//! Pseudo-arclength continuation of solutions of zero problems composed with
//! [`hycont_core::problem`], with detection and location of folds (SN), branch points (BP),
//! period doublings (PD), tori (TR) and events on monitor functions (e.g. boundary touch SB,
//! grazing GR), branch switching, and serialisable, restartable [`Branch`] results.
//!
//! Hybrid periodic orbits are continued by [`OrbitContinuation`] (multiple shooting or
//! collocation; $\mathbb{Z}_2$-symmetric orbits on their half orbit, at half the cost, with
//! symmetry-breaking branch points detected from the half map), two-parameter curves of special
//! points by [`Codim2`] ([`OrbitRun::curve_at`] from a special point of a branch,
//! [`OrbitRun::curve_from`] further along a saved curve, [`OrbitRun::curve_through`] the other
//! curve through a fold-flip point), with their own codimension-two points (cusps CP; R1,
//! LPPD, R2, LPNS, PDNS from the multipliers besides the held one; [`Detect::codim2`]), and
//! whole bifurcation diagrams in one call by [`OrbitRun::diagram`] (every BP and PD switched
//! at to a depth; [`Diagram::cascades`] reads off period-doubling cascades), and whole
//! two-parameter families by [`OrbitRun::atlas`] (Henderson's charts, module [`atlas`]: a
//! covering of the family's surface bounded by the bounds, folds and admissibility, as an
//! [`OrbitAtlas`] that serialises and grows further);
//! `examples/symmetric_branch/` in the
//! `hycont` package shows a half-orbit branch and a switch to the asymmetric branch. The
//! augmented Jacobians are factorised with the problem's condensed local blocks (collocation's
//! interval interiors) and handed to [`ContinuationProblem::analyse_factorised`].
//!
//! Problem (what: [`ContinuationProblem`]), algorithm (how: PALC, [`continue_branch`]), settings
//! ([`ContinuationSettings`]) and results ([`Branch`]) are separate; observers
//! ([`Observer`]) see every point.
//!
//! ```
//! use hycont_continuation::{continue_branch, ContinuationProblem, ContinuationSettings, PointInfo,
//!                           SpecialKind, observe::Silent};
//! use hycont_core::problem::{Activity, Problem, UnknownMonitor, ZeroFunction};
//!
//! /// x^2 - l = 0: a fold at l = 0.
//! struct Parabola;
//! impl ZeroFunction for Parabola {
//!     fn unknowns(&self) -> usize { 2 }
//!     fn equations(&self) -> usize { 1 }
//!     fn jacobian_pattern(&self) -> Vec<(usize, usize)> { vec![(0, 0), (0, 1)] }
//!     fn evaluate(&mut self, u: &[f64], r: &mut [f64], j: Option<&mut [f64]>) -> hycont_core::Result<()> {
//!         r[0] = u[0] * u[0] - u[1];
//!         if let Some(j) = j { j[0] = 2.0 * u[0]; j[1] = -1.0; }
//!         Ok(())
//!     }
//! }
//! struct Fold { problem: Problem<'static> }
//! impl ContinuationProblem<'static> for Fold {
//!     fn problem(&mut self) -> &mut Problem<'static> { &mut self.problem }
//!     fn parameter_index(&self) -> usize { 1 }
//!     fn parameter_position(&self) -> usize { 0 }
//!     fn parameter_name(&self) -> String { "l".into() }
//!     fn parameter_names(&self) -> Vec<String> { vec!["l".into()] }
//!     fn monitor_names(&self) -> Vec<String> { vec![] }
//!     fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
//!         Ok(PointInfo { params: vec![u[1]], ..PointInfo::default() })
//!     }
//! }
//! let mut problem = Problem::new(2);
//! problem.add_part(Box::new(Parabola), vec![0, 1]).unwrap();
//! problem.add_monitor("l", Box::new(UnknownMonitor), vec![1], Activity::Active(1.0)).unwrap();
//! let mut fold = Fold { problem };
//! // Unknowns: x, l, and the active monitor's value (equal to l).
//! let branch = continue_branch(&mut fold, "parabola", &[1.0, 1.0, 1.0], -1.0,
//!                              &ContinuationSettings::default().parameter_bounds(-1.0, 2.0),
//!                              &mut Silent).unwrap();
//! let sn = branch.special(SpecialKind::Fold).next().unwrap();
//! assert!(sn.point.params[0].abs() < 1e-9);
//! ```
#![deny(missing_docs)]
// `!(x > 0.0)` deliberately rejects NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod atlas;
mod bifurcation_equation;
pub mod branch;
pub mod codim2;
pub mod error;
pub mod observe;
pub mod orbit;
mod palc;
pub mod quantity;
mod recheck;
pub mod settings;
pub mod switch;

pub use branch::{
    Branch, BranchPoint, EndReason, NEUTRAL_BAND, RunStatistics, SpecialKind, SpecialPoint,
};
pub use codim2::{Codim2, CurveCondition, curve_settings};
pub use error::{Error, Result};
pub use hycont_core::orbit::{Discretisation, OrbitMethod};
pub use observe::Observer;
pub use orbit::{
    Cascade, CurveSpec, Diagram, DiagramBranch, DiagramBranchId, DiagramSettings, OrbitAtlas,
    OrbitBranch, OrbitContinuation, OrbitRun, POINT_RESIDUAL_TOL, RunDirection, SharedMeasures,
    SwitchOutcome, SwitchRecord, can_switch,
};
pub use quantity::{Label, MeasureId, Quantity};
pub use recheck::ANALYSIS_TOL;

/// Whether every branch and curve an [`OrbitRun`] returns is re-checked point by point (the
/// `invariants` feature, on in the test suites).
#[cfg(feature = "invariants")]
static CHECK_BRANCHES: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(true);

/// With the `invariants` feature (the test suites' invariant: every branch and curve an
/// [`OrbitRun`] returns is re-checked by [`OrbitBranch::check_points`], and a violation panics):
/// turns the re-check off or on for the process (default on). Benchmarks, built with the test
/// suites' features, turn it off to measure what users run.
#[cfg(feature = "invariants")]
pub fn check_branches(on: bool) {
    CHECK_BRANCHES.store(on, std::sync::atomic::Ordering::Relaxed);
}

/// Whether the re-check of [`check_branches`] is on.
#[cfg(feature = "invariants")]
pub(crate) fn checking_branches() -> bool {
    CHECK_BRANCHES.load(std::sync::atomic::Ordering::Relaxed)
}
pub use settings::{Bound, BoundOn, ContinuationSettings, Detect};
pub use switch::{branch_switch_direction, null_directions};

use hycont_core::problem::Problem;
use serde::{Deserialize, Serialize};

/// What a continuation problem reports about a solution point.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PointInfo {
    /// All parameters (names in [`ContinuationProblem::parameter_names`]).
    pub params: Vec<f64>,
    /// Monitor values (names in [`ContinuationProblem::monitor_names`]).
    pub monitors: Vec<f64>,
    /// Multipliers `(re, im)`, if the problem has any (periodic orbits).
    pub multipliers: Vec<(f64, f64)>,
    /// Which multipliers are trivial (never trigger PD, TR or stability changes).
    pub trivial: Vec<bool>,
    /// A factor of the branch-point test beyond the sign of the augmented Jacobian's
    /// determinant, for branch points the problem's own Jacobian cannot see: a half-orbit
    /// problem of a symmetric orbit is regular where the symmetry breaks (a half-map multiplier
    /// $\mu = -1$, a full-orbit multiplier $\lambda = \mu^2 = 1$), and reports
    /// $\prod (1 + \mu)$ over the non-trivial half-map multipliers here, so that the
    /// branch-point test changes sign there as on the full problem. `None`: no factor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub branch_point_factor: Option<f64>,
    /// The estimated discretisation error of the point (collocation: the largest interior
    /// error of the polynomials, in the units of the state); `None` where the problem has no
    /// estimate (shooting: the integrator's tolerance bounds it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub discretisation_error: Option<f64>,
}

/// Product over the non-trivial multipliers $m$ of $(\mathrm{shift} + m)$, real: a complex pair
/// contributes its squared modulus $|\mathrm{shift} + m|^2$ once. Changes sign when a real
/// multiplier crosses $-\mathrm{shift}$.
pub(crate) fn shifted_product(multipliers: &[(f64, f64)], trivial: &[bool], shift: f64) -> f64 {
    multipliers
        .iter()
        .zip(trivial)
        .filter(|(_, t)| !**t)
        .fold(1.0, |acc, ((re, im), _)| {
            if *im > 0.0 {
                acc * ((shift + re).powi(2) + im * im)
            } else if *im < 0.0 {
                acc
            } else {
                acc * (shift + re)
            }
        })
}

/// An event: a special point where a parameter or measure crosses `level` (COCO's
/// `coco_add_event`), labelled with `kind` (e.g. [`SpecialKind::BoundaryTouch`], a user's
/// [`SpecialKind::Custom`] label, or [`SpecialKind::UserPoint`] for a value asked for).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MonitorEvent {
    /// The label given to it.
    pub kind: SpecialKind,
    /// The quantity watched.
    pub on: Quantity,
    /// The level.
    pub level: f64,
    /// Whether the branch ends there (e.g. grazing: beyond it the orbits are not admissible).
    pub terminal: bool,
}

/// What is continued: a zero problem with exactly one more unknown than equations (one active
/// monitor, the continuation parameter), and an analysis of each solution point.
pub trait ContinuationProblem<'a> {
    /// The zero problem.
    fn problem(&mut self) -> &mut Problem<'a>;
    /// Index of the continuation parameter in the unknowns.
    fn parameter_index(&self) -> usize;
    /// Index of the continuation parameter in [`PointInfo::params`].
    fn parameter_position(&self) -> usize;
    /// Name of the continuation parameter.
    fn parameter_name(&self) -> String;
    /// Names of all parameters.
    fn parameter_names(&self) -> Vec<String>;
    /// Names of the monitors reported by [`ContinuationProblem::analyse`].
    fn monitor_names(&self) -> Vec<String>;
    /// Parameters, monitors and multipliers of a solution.
    ///
    /// # Errors
    /// If the analysis fails (the continuation then shrinks the step).
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo>;
    /// [`ContinuationProblem::analyse`] at a point where the continuation has just factorised
    /// the augmented Jacobian $[J(u); r^\top]$ (`jacobian`; its rows, columns and elimination
    /// blocks begin with those of [`ContinuationProblem::problem`]). A problem may read what it
    /// needs off the factorisation (collocation: the multipliers from the condensed intervals);
    /// the default ignores it.
    ///
    /// # Errors
    /// As [`ContinuationProblem::analyse`].
    fn analyse_factorised(
        &mut self,
        u: &[f64],
        jacobian: &hycont_core::linalg::SparsePattern,
    ) -> hycont_core::Result<PointInfo> {
        let _ = jacobian;
        self.analyse(u)
    }
    /// [`ContinuationProblem::analyse`] by a second, independent computation where the
    /// problem has one (shooting: the monodromy integrated afresh rather than composed from
    /// the linearisation its last evaluation cached; collocation: from the solution rather than
    /// the factorisation). The re-checks of saved points compare the two where a saved
    /// multiplier differs from the recomputed one: their difference is the multipliers' own
    /// accuracy, which near a grazing (an impact at nearly zero speed, whose saltation
    /// amplifies the integration's rounding) can be a percent of a multiplier of $10^{30}$.
    /// The default is [`ContinuationProblem::analyse`].
    ///
    /// # Errors
    /// As [`ContinuationProblem::analyse`].
    fn analyse_afresh(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        self.analyse(u)
    }
    /// Checks the corrected start of a run (after the first corrector solve, before any step),
    /// e.g. that an orbit is physical; an error refuses the run. Default: accepts every start.
    ///
    /// # Errors
    /// What is wrong with the start.
    fn check_start(&mut self, u: &[f64]) -> Result<()> {
        let _ = u;
        Ok(())
    }
    /// Events to detect and locate (default: none), in order of precedence: where terminal
    /// events are located at one point (closer than the location's tolerance, e.g. two
    /// margins that vanish together where a segment collapses), the run ends at the one
    /// [`ContinuationProblem::end_among`] names, by default the one listed first, not at
    /// whichever rounding places first.
    fn monitor_events(&self) -> Vec<MonitorEvent> {
        Vec::new()
    }
    /// Which of the terminal events `located` (of [`ContinuationProblem::monitor_events`], in
    /// its order, at least one), all located at the point `u`, ends the run: an index into
    /// `located`. Default: 0, the one listed first. A problem overrides it where the point
    /// itself tells which event says more (an orbit's segment collapsing tangentially is a
    /// grazing, one collapsing across another event's surface a boundary).
    fn end_among(&mut self, u: &[f64], located: &[MonitorEvent]) -> usize {
        let _ = (u, located);
        0
    }
    /// The critical value ($+1$ or $-1$) of a non-trivial multiplier the problem holds at
    /// every point (a fold or period-doubling curve), whose other multipliers' crossings
    /// of $\pm 1$ and of the unit circle are the curve's codimension-two points
    /// ([`crate::Detect::codim2`]); default `None`.
    fn held_multiplier(&self) -> Option<f64> {
        None
    }
    /// On a fold curve, the index in the unknowns of its second parameter: a cusp (CP) is
    /// where both parameters are stationary along the curve ([`crate::Detect::codim2`]);
    /// default `None`.
    fn cusp_parameter(&self) -> Option<usize> {
        None
    }
    /// Weights $w_i > 0$ of the unknowns in the arclength norm
    /// $\|v\|^2 = \sum_i w_i v_i^2$ (default: all 1). A discretised function should weigh
    /// its node values so that the norm approximates an integral, independent of the mesh
    /// (as AUTO's and COCO's $L_2$ norms): otherwise refining the mesh shrinks every step in
    /// the parameter.
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        None
    }
    /// Whether a step's corrector starts with chord steps from the previous point's
    /// factorisation (corrected exactly for the new arclength row) instead of factorising at
    /// the predictor; the point itself is factorised exactly either way (default `false`).
    /// Worth it where a residual costs a small part of a Jacobian and its factorisation:
    /// collocation, where it saves a factorisation per point for about three residuals (10 %
    /// of the rocking block's branch). Not for shooting, whose Jacobian rides on the
    /// integration a residual needs anyway: there the extra residuals cost more than the
    /// factorisation saved.
    fn chord_steps(&self) -> bool {
        false
    }
    /// Re-discretises the problem for the solution `u` with tangent `t`, aiming at a
    /// discretisation error below `tolerance` (collocation: moves the mesh to equidistribute
    /// the error estimate, and adds intervals where the estimate exceeds `tolerance`). Returns
    /// `u` and `t` carried over to the new discretisation (of another length when the layout
    /// changed), or `None` when the problem keeps its discretisation (the default, and a
    /// collocation mesh that would hardly move). The continuation calls it every
    /// [`ContinuationSettings::adapt_every`] points and at points whose
    /// [`PointInfo::discretisation_error`] exceeds
    /// [`ContinuationSettings::discretisation_tolerance`], then corrects the carried point.
    ///
    /// # Errors
    /// If the new problem cannot be built.
    fn rediscretise(
        &mut self,
        u: &[f64],
        t: &[f64],
        tolerance: f64,
    ) -> Result<Option<Rediscretised>> {
        let _ = (u, t, tolerance);
        Ok(None)
    }
    /// The revision of the discretisation the unknowns are on: 0 at first, a new one at each
    /// [`ContinuationProblem::rediscretise`] that changed it (recorded in
    /// [`BranchPoint::discretisation`]).
    fn discretisation_revision(&self) -> usize {
        0
    }
    /// Returns to an earlier revision of the discretisation (a run ends on the revision it
    /// started on, so that the other direction of a branch starts where it did); whether the
    /// layout changed (see [`Rediscretised::layout_changed`]).
    ///
    /// # Errors
    /// An unknown revision, or a problem that cannot be rebuilt.
    fn restore_discretisation(&mut self, revision: usize) -> Result<bool> {
        let _ = revision;
        Ok(false)
    }
}

/// A solution and tangent carried to a new discretisation by
/// [`ContinuationProblem::rediscretise`].
#[derive(Debug, Clone, PartialEq)]
pub struct Rediscretised {
    /// The unknowns on the new discretisation.
    pub u: Vec<f64>,
    /// The tangent on the new discretisation (any length; it is normalised).
    pub t: Vec<f64>,
    /// Whether the layout changed: the number of unknowns, the Jacobian's pattern or the
    /// arclength weights (a refined mesh), so that the continuation must set them up again (a
    /// mesh that only moved keeps them).
    pub layout_changed: bool,
}

/// Continues the branch through `u0` (an approximate solution) in the direction of increasing
/// (`direction > 0`) or decreasing (`direction < 0`) continuation parameter; `direction` must
/// be finite and non-zero.
///
/// A failure in the middle of the branch does not error: the branch so far is returned, with
/// [`Branch::end`] saying why it stopped.
///
/// # Errors
/// Invalid settings (a zero or non-finite `direction` included), `u0` of the wrong length or
/// not finite, a problem that is not one-dimensional, or no solution near `u0`.
pub fn continue_branch<'a, P: ContinuationProblem<'a> + ?Sized>(
    problem: &mut P,
    name: &str,
    u0: &[f64],
    direction: f64,
    settings: &ContinuationSettings,
    observer: &mut dyn Observer,
) -> Result<Branch> {
    palc::Palc::new(problem, settings.clone())?.run(name, u0, None, direction, observer)
}

/// Continues from `u0` along the direction `tangent` (e.g. a branch-switching direction) for
/// `direction > 0`, or its opposite for `direction < 0` (finite and non-zero).
///
/// # Errors
/// As [`continue_branch`].
pub fn continue_along<'a, P: ContinuationProblem<'a> + ?Sized>(
    problem: &mut P,
    name: &str,
    u0: &[f64],
    tangent: &[f64],
    direction: f64,
    settings: &ContinuationSettings,
    observer: &mut dyn Observer,
) -> Result<Branch> {
    palc::Palc::new(problem, settings.clone())?.run(name, u0, Some(tangent), direction, observer)
}
