#![doc = include_str!("../README.md")]
//!
//! ## Crates
//!
//! This facade re-exports the library crates:
//!
//! - [`hycont_core`] (also re-exported at the top level): hybrid systems, event-driven
//!   simulation with variational equations;
//! - [`hycont_continuation`]: pseudo-arclength continuation of periodic orbits, special points,
//!   branch switching and two-parameter curves;
//! - [`hycont_sample`]: brute-force bifurcation diagrams and basin stability.
#![deny(missing_docs)]

pub use hycont_continuation;
pub use hycont_core;
pub use hycont_core::*;
pub use hycont_sample;
