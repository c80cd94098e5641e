//! Results: branches of points with their special points, serialisable and restartable.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// The kind of a special point (the study's labels).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SpecialKind {
    /// Fold (saddle-node, limit point).
    #[serde(rename = "SN")]
    Fold,
    /// Branch point (e.g. symmetry breaking).
    #[serde(rename = "BP")]
    BranchPoint,
    /// Period doubling.
    #[serde(rename = "PD")]
    PeriodDoubling,
    /// Torus (Neimark-Sacker).
    #[serde(rename = "TR")]
    Torus,
    /// Boundary touch (a monitor reaches a boundary level, e.g. Amp at the static boundary).
    #[serde(rename = "SB")]
    BoundaryTouch,
    /// Grazing (an interior extremum touches the impact surface).
    #[serde(rename = "GR")]
    Grazing,
    /// End point of the branch.
    #[serde(rename = "EP")]
    EndPoint,
}

impl SpecialKind {
    /// The study's two-letter label.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            SpecialKind::Fold => "SN",
            SpecialKind::BranchPoint => "BP",
            SpecialKind::PeriodDoubling => "PD",
            SpecialKind::Torus => "TR",
            SpecialKind::BoundaryTouch => "SB",
            SpecialKind::Grazing => "GR",
            SpecialKind::EndPoint => "EP",
        }
    }
}

/// One point of a branch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchPoint {
    /// Label, unique within the branch (points and special points share the numbering).
    pub label: usize,
    /// The unknowns (for restarts).
    pub u: Vec<f64>,
    /// The unit tangent (for restarts).
    pub tangent: Vec<f64>,
    /// All parameters.
    pub params: Vec<f64>,
    /// The problem's monitors (names in [`Branch::monitor_names`]).
    pub monitors: Vec<f64>,
    /// Floquet (or other) multipliers `(re, im)`.
    pub multipliers: Vec<(f64, f64)>,
    /// Which multipliers are trivial.
    pub trivial: Vec<bool>,
    /// Number of non-trivial multipliers outside the unit circle.
    pub unstable: usize,
    /// Corrector iterations.
    pub newton_iterations: usize,
    /// Arclength step that reached this point.
    pub step: f64,
}

impl BranchPoint {
    /// Whether the point is stable (no unstable non-trivial multiplier).
    #[must_use]
    pub fn stable(&self) -> bool {
        self.unstable == 0
    }
}

/// A located (or bracketed) special point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpecialPoint {
    /// What it is.
    pub kind: SpecialKind,
    /// The point itself.
    pub point: BranchPoint,
    /// Continuation-parameter values of the two branch points bracketing it.
    pub bracket: (f64, f64),
    /// Whether it was located to the tolerance (otherwise `point` is the best estimate).
    pub located: bool,
    /// Final parameter uncertainty of the location.
    pub accuracy: f64,
    /// For monitor events: the index of the monitor.
    pub monitor: Option<usize>,
}

/// Why a branch ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum EndReason {
    /// A bound was reached (an EP special point is on it).
    Bound,
    /// The point limit was reached.
    MaxPoints,
    /// The corrector failed with the smallest step; the reason.
    CorrectorFailed(String),
    /// A special point that ends admissible orbits (e.g. grazing) was reached.
    Inadmissible(SpecialKind),
    /// The branch closed on itself (returned to its start).
    Closed,
    /// A special point of a kind in [`crate::ContinuationSettings::stop_at`] was reached.
    Reached(SpecialKind),
}

/// A branch: its points, special points, and how it ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Branch {
    /// A name (e.g. `symmetric`).
    pub name: String,
    /// Name of the continuation parameter.
    pub parameter: String,
    /// Index of the continuation parameter in [`BranchPoint::params`].
    pub parameter_index: usize,
    /// Names of all parameters.
    pub parameter_names: Vec<String>,
    /// Names of the monitors.
    pub monitor_names: Vec<String>,
    /// The points, in continuation order.
    pub points: Vec<BranchPoint>,
    /// The special points, in continuation order.
    pub special_points: Vec<SpecialPoint>,
    /// How it ended.
    pub end: EndReason,
    /// The work it took.
    #[serde(default)]
    pub statistics: RunStatistics,
}

/// The work a continuation run did: evaluations of the problem, split into stepping along the
/// branch and locating special points.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunStatistics {
    /// Jacobian evaluations (each with a residual and a sparse LU factorisation) while stepping.
    pub jacobians: usize,
    /// Residual-only evaluations (chord iterations) while stepping.
    pub residuals: usize,
    /// Jacobian evaluations while locating special points.
    pub location_jacobians: usize,
    /// Residual-only evaluations while locating special points.
    pub location_residuals: usize,
    /// Analyses of solutions (multipliers and monitors).
    pub analyses: usize,
    /// Steps retried with half the step size (corrector failure or too large an angle).
    pub rejected_steps: usize,
}

impl std::ops::Add for RunStatistics {
    type Output = RunStatistics;
    fn add(self, o: RunStatistics) -> RunStatistics {
        RunStatistics {
            jacobians: self.jacobians + o.jacobians,
            residuals: self.residuals + o.residuals,
            location_jacobians: self.location_jacobians + o.location_jacobians,
            location_residuals: self.location_residuals + o.location_residuals,
            analyses: self.analyses + o.analyses,
            rejected_steps: self.rejected_steps + o.rejected_steps,
        }
    }
}

impl Branch {
    /// The point (regular or special) with the given label.
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`].
    pub fn point(&self, label: usize) -> Result<&BranchPoint> {
        self.points
            .iter()
            .chain(self.special_points.iter().map(|s| &s.point))
            .find(|p| p.label == label)
            .ok_or_else(|| Error::NoSuchLabel {
                label,
                branch: self.name.clone(),
            })
    }

    /// The special points of one kind.
    pub fn special(&self, kind: SpecialKind) -> impl Iterator<Item = &SpecialPoint> {
        self.special_points.iter().filter(move |s| s.kind == kind)
    }

    /// The continuation parameter of a point.
    #[must_use]
    pub fn parameter_of(&self, p: &BranchPoint) -> f64 {
        p.params[self.parameter_index]
    }

    /// JSON text of the branch.
    ///
    /// # Errors
    /// Never for finite data (serde_json refuses NaN).
    pub fn to_json(&self) -> std::result::Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// A branch from JSON text.
    ///
    /// # Errors
    /// If the text is not a serialised branch.
    pub fn from_json(text: &str) -> std::result::Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }
}
