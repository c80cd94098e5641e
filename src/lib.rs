#![doc = include_str!("../README.md")]
//!
//! ## Crates
//!
//! This facade re-exports the library crates:
//!
//! - [`hycont_core`] (also re-exported at the top level): hybrid systems, event-driven
//!   simulation with variational equations;
//! - [`rocking_block`]: the flagship application, the harmonically forced rocking block.
#![deny(missing_docs)]

pub use hycont_core;
pub use hycont_core::*;
pub use rocking_block;
