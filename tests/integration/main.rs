//! The integration tests of `hycont` in one binary, a module per concern: one link and one
//! build of the library code they instantiate, instead of one per file.

// The examples' models that several modules test, loaded once.
#[path = "../../examples/impact_oscillator/model.rs"]
#[allow(dead_code)] // each test module uses part of it
mod model_impact_oscillator;
#[path = "../../examples/piecewise_linear/model.rs"]
#[allow(dead_code)] // each test module uses part of it
mod model_piecewise_linear;
#[path = "../../examples/symmetric_branch/model.rs"]
#[allow(dead_code)] // each test module uses part of it
mod model_symmetric_branch;
#[path = "../../examples/two_balls/model.rs"]
mod model_two_balls;
#[path = "../../examples/vibrating_table/model.rs"]
#[allow(dead_code)] // each test module uses part of it
mod model_vibrating_table;

mod atlas;
mod autodiff;
mod boundary_curves;
mod codim2_points;
mod collapse_ends;
mod cusp_point;
mod grazing_curves;
mod grazing_impacts;
mod grazing_switch;
mod handles;
mod impact_chain;
mod impact_pair_cascade;
mod misuse;
mod piecewise_linear;
mod public_api_fuzz;
mod stick_slip;
mod symmetric_codim2;
mod symmetry_checks;
mod table_basins;
mod table_basins_cli;
mod trajectories;
mod vibrating_table;
