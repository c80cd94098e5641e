//! The integration tests of `hycont-continuation` in one binary, a module per concern: one link and one
//! build of the library code they instantiate, instead of one per file.

mod common;
mod models;

mod admissibility;
mod atlas_sphere;
mod closed_form;
mod coinciding_ends;
mod diagram;
mod mesh_adaptation;
mod saved_atlas;
mod saved_diagram;
mod symmetry_breaking;
