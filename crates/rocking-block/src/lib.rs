//! # rocking-block
//!
//! The harmonically forced rocking rigid block of the study "Dynamical response of a rocking
//! rigid block" as a [`hycont_core::HybridSystem`]: the model ([`RockingBlock`], [`Parameters`]),
//! simulation with a physical outcome ([`simulate`]), figures, and the `rocking-block` command
//! line that reproduces the study.
//!
//! ```
//! use rocking_block::{simulate, Outcome, SimulationRequest};
//! // (omega, alpha) = (1.3, 0.66) from phi0 = 0.01 with forcing phase beta = pi/2: the block
//! // settles on an asymmetric period-1 orbit.
//! let req = SimulationRequest { beta: std::f64::consts::FRAC_PI_2, periods: 20.0, ..Default::default() };
//! let (report, _) = simulate(&req).unwrap();
//! assert_eq!(report.outcome, Outcome::Running);
//! ```
#![deny(missing_docs)]
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod basin;
pub mod block;
pub mod classes;
pub mod cli;
pub mod continuation;
pub mod error;
pub mod figures;
pub mod model;
pub mod model_ad;
pub mod orbits;
pub mod output;
pub mod parameters;
pub mod plot;
pub mod provenance;
pub mod report;
pub mod simulation;

pub use error::{Error, Result};
pub use model::{
    ALPHA, DEFAULT_THETA_B, DEFAULT_XI, IMPACT_MINUS, IMPACT_PLUS, LIFT_OFF_MINUS, LIFT_OFF_PLUS,
    MINUS, OMEGA, ON_GROUND, OVERTURN_NEG, OVERTURN_POS, PLUS, Parameters, REST, RockingBlock,
    THETA_B, XI, initial_mode, initial_state, restitution,
};
pub use simulation::{Outcome, SimulationReport, SimulationRequest, simulate};
