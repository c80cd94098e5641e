//! Hybrid dynamical systems: modes, vector fields, events, resets and their Jacobians.
//!
//! A hybrid system has a continuous state $x \in \mathbb{R}^n$, parameters $p \in \mathbb{R}^{n_p}$
//! and a finite set of modes. In mode $m$ the state obeys $\dot x = f_m(x, p)$. Each mode has a set
//! of events $h_e(x, p) = 0$, each with a crossing direction; when one is crossed the system either
//! stops ([`EventAction::Terminal`]) or applies the reset (jump) $x^+ = g_e(x^-, p)$ and continues
//! in the event's target mode ([`EventAction::Jump`]).
//!
//! Capabilities are split into traits: [`HybridSystem`] (evaluation) and [`HybridJacobians`]
//! (first derivatives, needed for variational equations, saltation matrices and Newton's method).
//! A system without analytic derivatives gets them by central differences through
//! [`FiniteDifferences`]; [`check_derivatives`] compares supplied derivatives against central
//! differences (COCO's `chkderiv`).
//!
//! Jacobians are dense, column-major: entry $(i, j)$ of an $r \times c$ matrix is `out[i + j * r]`.

use serde::{Deserialize, Serialize};
use std::fmt;

/// A typed handle to a mode of a hybrid system (an index into the system's modes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Mode(pub usize);

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// A typed handle to an event (an index into the system's events).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct EventId(pub usize);

impl fmt::Display for EventId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "event #{}", self.0)
    }
}

/// A typed handle to a parameter: its index in the parameter vector.
///
/// Resolve names once with [`HybridSystem::parameter_id`] and keep the handle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ParamId(pub usize);

impl ParamId {
    /// Index of the parameter in the parameter vector.
    #[must_use]
    pub fn index(self) -> usize {
        self.0
    }
}

/// Which sign changes of an event function count as a crossing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Direction {
    /// From negative to positive.
    Rising,
    /// From positive to negative.
    Falling,
    /// Either way.
    Either,
}

impl Direction {
    /// Whether going from value `before` to value `after` is a crossing in this direction.
    ///
    /// A crossing starts strictly on one side and ends on the other side or on zero.
    ///
    /// ```
    /// use hycont_core::Direction;
    /// assert!(Direction::Falling.is_crossing(0.5, -1e-3));
    /// assert!(!Direction::Rising.is_crossing(0.5, -1e-3));
    /// assert!(!Direction::Either.is_crossing(0.0, 1.0));
    /// ```
    #[must_use]
    pub fn is_crossing(self, before: f64, after: f64) -> bool {
        let rising = before < 0.0 && after >= 0.0;
        let falling = before > 0.0 && after <= 0.0;
        match self {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Either => rising || falling,
        }
    }

    /// The sign an event function has before a crossing in this direction (`None` for `Either`).
    #[must_use]
    pub fn sign_before(self) -> Option<f64> {
        match self {
            Direction::Rising => Some(-1.0),
            Direction::Falling => Some(1.0),
            Direction::Either => None,
        }
    }
}

/// What happens when an event is crossed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EventAction {
    /// Apply the event's reset map and continue in mode `to`.
    Jump {
        /// The mode that follows the event.
        to: Mode,
    },
    /// Stop the simulation (for example: the block has overturned).
    Terminal,
}

/// Static description of an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EventSpec {
    /// A short name for messages and output (e.g. `"impact+"`).
    pub name: &'static str,
    /// Which crossings count.
    pub direction: Direction,
    /// What a crossing does.
    pub action: EventAction,
}

/// A hybrid dynamical system: modes, vector fields, events and resets.
///
/// Hot-path methods write into caller-provided buffers and must not allocate.
///
/// # Example: a bouncing ball
/// ```
/// use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridSystem, Mode};
///
/// /// Height y, velocity v; y'' = -g; impact at y = 0 with v -> -e v. Parameters: g, e.
/// struct Ball;
/// impl HybridSystem for Ball {
///     fn state_dim(&self) -> usize { 2 }
///     fn parameter_names(&self) -> &[&'static str] { &["g", "e"] }
///     fn mode_count(&self) -> usize { 1 }
///     fn mode_name(&self, _: Mode) -> &'static str { "flight" }
///     fn events(&self, _: Mode) -> &[EventId] { &[EventId(0)] }
///     fn event_spec(&self, _: EventId) -> EventSpec {
///         EventSpec { name: "impact", direction: Direction::Falling,
///                     action: EventAction::Jump { to: Mode(0) } }
///     }
///     fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
///         out[0] = x[1];
///         out[1] = -p[0];
///     }
///     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { x[0] }
///     fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
///         out[0] = x[0];
///         out[1] = -p[1] * x[1];
///     }
/// }
/// assert_eq!(Ball.parameter_id("e").map(|p| p.index()), Some(1));
/// ```
pub trait HybridSystem {
    /// Dimension $n$ of the continuous state: in every mode unless [`HybridSystem::mode_dim`]
    /// says otherwise, and then the largest of the modes' dimensions.
    fn state_dim(&self) -> usize;

    /// Dimension $n_m$ of the state in `mode` (default: [`HybridSystem::state_dim`] in every
    /// mode). Systems whose modes have states of different dimensions (COCO's segment-dependent
    /// dimensions: a stick mode with fewer states than a slip mode) override it; their resets
    /// map a state of the dimension of the modes that monitor the event to one of the target
    /// mode's dimension, and every mode that monitors an event has the same dimension
    /// ([`check_mode_dims`]). The simulator follows such systems across their jumps, and
    /// periodic orbits carry one start state of its mode's dimension per segment (shooting and
    /// collocation alike; the monodromy in the first segment's space, through rectangular
    /// saltation matrices; half orbits of a symmetry through its leading blocks,
    /// [`Z2Symmetry::apply`]). Sensitivities of one run across a jump between dimensions
    /// refuse them with a typed error.
    fn mode_dim(&self, mode: Mode) -> usize {
        let _ = mode;
        self.state_dim()
    }

    /// Names of the parameters, in the order of the parameter vector.
    fn parameter_names(&self) -> &[&'static str];

    /// Number of parameters $n_p$.
    fn parameter_count(&self) -> usize {
        self.parameter_names().len()
    }

    /// Resolves a parameter name to a typed handle (do this once, not in loops).
    fn parameter_id(&self, name: &str) -> Option<ParamId> {
        self.parameter_names()
            .iter()
            .position(|n| *n == name)
            .map(ParamId)
    }

    /// Number of modes; valid modes are `Mode(0)..Mode(mode_count() - 1)`.
    fn mode_count(&self) -> usize;

    /// A short name of a mode (e.g. `"+"`).
    fn mode_name(&self, mode: Mode) -> &'static str;

    /// The events monitored while in `mode`.
    fn events(&self, mode: Mode) -> &[EventId];

    /// Direction, action and name of an event.
    fn event_spec(&self, event: EventId) -> EventSpec;

    /// Writes $f_m(x, p)$ into `out` (length $n$).
    fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], out: &mut [f64]);

    /// The event function $h_e(x, p)$.
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64;

    /// Writes the reset $g_e(x, p)$ into `out` (of the target mode's dimension, which may
    /// differ from `x`'s: [`HybridSystem::mode_dim`]). The default is the identity (between
    /// modes of different dimensions: the components both have; the simulator reports the
    /// rest of a larger target as not written).
    fn reset(&self, event: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        let _ = (event, p);
        let k = x.len().min(out.len());
        out[..k].copy_from_slice(&x[..k]);
    }

    /// The system's $\mathbb{Z}_2$ symmetry, if it has one (default: none).
    fn symmetry(&self) -> Option<Z2Symmetry> {
        None
    }

    /// Floquet multipliers every periodic orbit of period `period` has for structural reasons, as
    /// `(re, im)`; the default is the flow direction's multiplier 1 of an autonomous system.
    /// Stability is judged on the others.
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        let _ = (p, period);
        vec![(1.0, 0.0)]
    }

    /// A structural hint: `Some(j)` when, in `mode`, the time derivative of state component `c`
    /// is exactly state component `j` ($f_c(x, p) = x_j$, e.g. a position whose velocity is in
    /// the state). Scans of orbits then find the extrema of $x_c$ from $x_j$ without evaluating
    /// the vector field. Default: `None`. [`check_derivatives`] verifies hints.
    fn rate_component(&self, mode: Mode, c: usize) -> Option<usize> {
        let _ = (mode, c);
        None
    }

    /// A structural hint: `Some(c)` when the event function is $h_e(x, p) = x_c - v(p)$ (an
    /// event on a coordinate surface), so that with [`HybridSystem::rate_component`] a scan
    /// watches its turning points through a state component. Default: `None`.
    /// [`check_derivatives`] verifies hints.
    fn event_component(&self, event: EventId) -> Option<usize> {
        let _ = event;
        None
    }

    /// Where to go when the jumps of `event` accumulate (Zeno behaviour) in `mode`.
    ///
    /// The simulator calls this when it detects an accumulation of `event` (see
    /// [`crate::ZenoSettings`]); `x` is the state right after the last jump. Return the mode to
    /// continue in and write its initial state into `out`, or return `None` (the default) to end
    /// the simulation with [`crate::StopReason::ZenoAccumulation`]. `out` has
    /// [`HybridSystem::state_dim`] entries; the state of the returned mode is its first
    /// [`HybridSystem::mode_dim`] (all of them where every mode has the same dimension).
    fn zeno_transition(
        &self,
        mode: Mode,
        event: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        let _ = (mode, event, x, p, out);
        None
    }
}

/// First derivatives of a [`HybridSystem`].
///
/// All matrices are column-major; `dp` arguments are `None` when parameter derivatives are not
/// needed, so implementations can skip that work.
pub trait HybridJacobians: HybridSystem {
    /// $\partial f_m / \partial x$ into `dx` ($n \times n$) and $\partial f_m / \partial p$ into
    /// `dp` ($n \times n_p$).
    fn vector_field_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    );

    /// The vector field $f_m$ into `f` and its Jacobians as
    /// [`HybridJacobians::vector_field_jacobian`], together (the variational equations need
    /// both at every stage). Override to share work between them, e.g. trigonometric functions
    /// of the state; the default calls the two methods.
    fn vector_field_with_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        self.vector_field(mode, x, p, f);
        self.vector_field_jacobian(mode, x, p, dx, dp);
    }

    /// The vector field $f_m$ into `f` and its derivatives along the directions of `tangents`
    /// (Jacobian-matrix products, see [`Tangents`]): what the variational equations integrate
    /// at every stage. The default forms the Jacobians with
    /// [`HybridJacobians::vector_field_with_jacobian`] in `tangents.work` and multiplies;
    /// [`AutoDiff`] differentiates along the directions directly.
    ///
    /// ```
    /// use hycont_core::{HybridJacobians, Mode, ParamId, Tangents};
    /// # use hycont_core::{HybridSystem, EventId, EventSpec};
    /// /// x' = p0 x^2 (one state, one parameter).
    /// struct Quadratic;
    /// # impl HybridSystem for Quadratic {
    /// #     fn state_dim(&self) -> usize { 1 }
    /// #     fn parameter_names(&self) -> &[&'static str] { &["p0"] }
    /// #     fn mode_count(&self) -> usize { 1 }
    /// #     fn mode_name(&self, _: Mode) -> &'static str { "m" }
    /// #     fn events(&self, _: Mode) -> &[EventId] { &[] }
    /// #     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
    /// #     fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
    /// #         f[0] = p[0] * x[0] * x[0];
    /// #     }
    /// #     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { x[0] }
    /// # }
    /// impl HybridJacobians for Quadratic {
    ///     fn vector_field_jacobian(&self, _: Mode, x: &[f64], p: &[f64], dx: &mut [f64],
    ///                              dp: Option<&mut [f64]>) {
    ///         dx[0] = 2.0 * p[0] * x[0];
    ///         if let Some(dp) = dp { dp[0] = x[0] * x[0]; }
    ///     }
    ///     fn event_gradient(&self, _: EventId, _: &[f64], _: &[f64], dx: &mut [f64],
    ///                       dp: Option<&mut [f64]>) {
    ///         dx[0] = 1.0;
    ///         if let Some(dp) = dp { dp[0] = 0.0; }
    ///     }
    /// }
    /// // Two directions: the state by 0.5, then the state by 2 and p0 by one.
    /// let (mut f, mut out, mut work) = ([0.0], [0.0; 2], [0.0; 2]);
    /// let tangents = Tangents { x: &[0.5, 2.0], params: &[ParamId(0)], out: &mut out, work: &mut work };
    /// Quadratic.vector_field_with_tangents(Mode(0), &[3.0], &[2.0], &mut f, tangents);
    /// assert_eq!(f, [18.0]);
    /// assert_eq!(out, [12.0 * 0.5, 12.0 * 2.0 + 9.0]); // f_x = 2 p0 x = 12, f_p = x^2 = 9
    /// ```
    fn vector_field_with_tangents(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        tangents: Tangents<'_>,
    ) {
        tangents::by_jacobians(self, mode, x, p, f, tangents);
    }

    /// $\partial h_e / \partial x$ into `dx` (length $n$) and $\partial h_e / \partial p$ into `dp`
    /// (length $n_p$).
    fn event_gradient(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    );

    /// $\partial g_e / \partial x$ into `dx` ($n_+ \times n_-$) and $\partial g_e / \partial p$
    /// into `dp` ($n_+ \times n_p$), column-major with leading dimension $n_+$: $n_-$ is the
    /// dimension of `x` (of the modes that monitor the event), $n_+$ that of the mode the event
    /// leads to ([`reset_dim`]; $n_+ = n_- = n$ where every mode has the same dimension).
    /// The default is the identity's: the unit entries of the components both states have, and
    /// $0$.
    fn reset_jacobian(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let _ = p;
        let (n_from, n_to) = (x.len(), reset_dim(self, event, x.len()));
        dx[..n_to * n_from].fill(0.0);
        for i in 0..n_from.min(n_to) {
            dx[i + i * n_to] = 1.0;
        }
        if let Some(dp) = dp {
            dp.fill(0.0);
        }
    }
}

mod autodiff;
mod derivatives;
mod dims;
mod symmetry;
mod tangents;
pub use autodiff::{AutoDiff, HybridModel, Scalar, Variation};
pub use derivatives::{
    DerivativeCheck, DerivativeKind, DerivativeMismatch, FiniteDifferences, check_derivatives,
    check_derivatives_against,
};
pub(crate) use dims::require_uniform_dims;
pub use dims::{check_mode_dims, reset_dim, uniform_dims};
pub use symmetry::{Z2Symmetry, checked_symmetry};
pub use tangents::Tangents;
