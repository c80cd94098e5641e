//! The integration tests of `hycont-core` in one binary, a module per concern: one link and one
//! build of the library code they instantiate, instead of one per file.

mod common;

mod collocation_error;
mod condensation;
mod dop853;
mod event_conditioning;
mod grazing_events;
mod linalg;
mod measures;
mod mode_dim_orbits;
mod mode_dims;
mod newton;
mod non_finite;
mod orbits;
mod simulator;
mod symmetric_search;
