//! Continuation of hybrid periodic orbits: the typed run API ([`OrbitRun`]: run, restart,
//! switch, curves, whole diagrams) producing saved branches ([`OrbitBranch`]), and the continuation problem it
//! builds ([`OrbitContinuation`]).

mod atlas;
mod cascade;
mod collapse;
mod curves;
mod diagram;
mod diagram_check;
mod drive;
mod grazing_switch;
mod problem;
mod revisions;
mod run;
mod saved;
mod saved_points;
mod switching;
mod symmetric;
mod verify;

pub use atlas::OrbitAtlas;
pub use cascade::Cascade;
pub use curves::CurveSpec;
pub use diagram::{
    Diagram, DiagramBranch, DiagramBranchId, DiagramSettings, SwitchOutcome, SwitchRecord,
};
pub(crate) use problem::check_parameter;
pub use problem::{OrbitContinuation, SharedMeasures, can_switch};
pub use run::{OrbitRun, RunDirection};
pub use saved::OrbitBranch;
pub use verify::POINT_RESIDUAL_TOL;
