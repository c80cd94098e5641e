//! # hycont
//!
//! Numerical continuation of periodic orbits of hybrid (impacting, piecewise-smooth) dynamical
//! systems. This facade re-exports the library crates:
//!
//! - [`hycont_core`] (also re-exported at the top level): hybrid systems, event-driven
//!   simulation with variational equations;
//! - [`rocking_block`]: the flagship application, the harmonically forced rocking block.
//!
//! ```
//! use hycont::{SimulationSettings, Simulator};
//! use hycont::rocking_block::{initial_mode, initial_state, Parameters, RockingBlock};
//!
//! let params = Parameters::new(1.3, 0.66);
//! let x0 = initial_state(0.01, 0.0, 0.0);
//! let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
//! let traj = sim.run(&RockingBlock, initial_mode(&x0, &params), 0.0, &x0, &params.to_vec(), 100.0).unwrap();
//! println!("{} impacts, final state {:?}", traj.stats.jumps, traj.state_final);
//! ```
#![deny(missing_docs)]

pub use hycont_core;
pub use hycont_core::*;
pub use rocking_block;
