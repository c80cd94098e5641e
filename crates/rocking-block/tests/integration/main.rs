//! The integration tests of `rocking-block` in one binary, a module per concern: one link and one
//! build of the library code they instantiate, instead of one per file.

mod common;

mod atlas;
mod autodiff;
mod cli;
mod cli_adaptive;
mod cli_basin;
mod cli_block;
mod cli_files;
mod cli_pictures;
mod cli_recipe;
mod cli_safety;
mod cli_starts;
mod collocation_branches;
mod continuation;
mod curves;
mod diagram;
mod grazing;
mod jacobians;
mod merge_edits;
mod orbits;
mod readers;
mod readme_simulation;
mod sampling;
mod slurm;
mod study;
mod threshold;
