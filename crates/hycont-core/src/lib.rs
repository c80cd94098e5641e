//! # hycont-core
//!
//! Hybrid (impacting, piecewise-smooth) dynamical systems and their event-driven simulation: the
//! foundation of [hycont](https://docs.rs/hycont), a library for numerical continuation of
//! periodic orbits of hybrid systems.
//!
//! - [`HybridSystem`] and [`HybridJacobians`]: modes, vector fields, events with crossing
//!   directions, resets (jumps), Zeno transitions, and their first derivatives;
//!   [`FiniteDifferences`] supplies missing derivatives and [`check_derivatives`] checks supplied
//!   ones against central differences.
//! - [`Simulator`]: DOP853 ([`Dop853`]) with events located on the 7th-order dense output,
//!   restart guard after jumps, terminal events, stroboscopic sampling, Zeno detection, and
//!   variational equations with saltation matrices.
//!
//! Library functions return [`Result`] with the typed [`Error`]; nothing here panics on bad input.
#![deny(missing_docs)]
#![warn(clippy::pedantic)]
#![allow(
    clippy::module_name_repetitions,
    clippy::many_single_char_names,
    clippy::similar_names,
    clippy::cast_precision_loss,
    clippy::cast_possible_truncation,
    clippy::cast_possible_wrap,
    clippy::cast_sign_loss,
    clippy::float_cmp,
    clippy::needless_range_loop,
    clippy::doc_markdown,
    // `!(x > 0.0)` deliberately rejects NaN as well.
    clippy::neg_cmp_op_on_partial_ord,
    // The Runge-Kutta stage kernels must inline into the stepper to unroll.
    clippy::inline_always,
    clippy::too_many_lines,
    clippy::single_match_else,
    // `expect`s in this crate guard internal invariants, not inputs.
    clippy::missing_panics_doc
)]

pub mod error;
pub mod linalg;
pub mod orbit;
pub mod problem;
pub mod simulate;
pub mod system;

pub use error::{Error, Result};
/// The linear-algebra crate of results users compute with (monodromy, saltation matrices,
/// Floquet vectors, orbit states).
#[doc(no_inline)]
pub use nalgebra;
/// The dual numbers [`HybridModel`]s are evaluated on (re-exported for their
/// [`num_dual::DualNum`](https://docs.rs/num-dual/0.15/num_dual/trait.DualNum.html) methods).
#[doc(no_inline)]
pub use num_dual;
pub use simulate::{
    Dop853, EventConditioning, EventRecord, NonFiniteEvaluation, ParamSet, SampleTimes,
    Sensitivities, SensitivityMatrices, SimulationSettings, SimulationStats, Simulator,
    StepperStats, StopReason, TimeSeries, Trajectory, ZenoRecord, ZenoSettings,
};
pub use system::{
    AutoDiff, DerivativeCheck, DerivativeKind, DerivativeMismatch, Direction, EventAction, EventId,
    EventSpec, FiniteDifferences, HybridJacobians, HybridModel, HybridSystem, Mode, ParamId,
    Scalar, Tangents, Variation, Z2Symmetry, check_derivatives, check_derivatives_against,
    check_mode_dims, checked_symmetry, reset_dim, uniform_dims,
};
