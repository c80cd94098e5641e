//! # rocking-block
//!
//! The harmonically forced rocking rigid block of the study "Dynamical response of a rocking
//! rigid block" as a [`hycont_core::HybridSystem`]: the model ([`RockingBlock`], [`Parameters`]),
//! simulation with a physical outcome ([`simulate`]), figures, and the `rocking-block` command
//! line that reproduces the study.
//!
//! ```
//! use rocking_block::{simulate, Outcome, SimulationRequest};
//! let (report, _) = simulate(&SimulationRequest { periods: 20.0, ..Default::default() }).unwrap();
//! assert_eq!(report.outcome, Outcome::Running);
//! ```
#![deny(missing_docs)]

pub mod cli;
pub mod error;
pub mod model;
pub mod plot;
pub mod simulation;

pub use error::{Error, Result};
pub use model::{
    ALPHA, IMPACT_MINUS, IMPACT_PLUS, LIFT_OFF_MINUS, LIFT_OFF_PLUS, MINUS, OMEGA, OVERTURN_NEG,
    OVERTURN_POS, PLUS, Parameters, REST, RockingBlock, THETA_B, XI, initial_mode, initial_state,
    restitution,
};
pub use simulation::{Outcome, SimulationReport, SimulationRequest, simulate};
