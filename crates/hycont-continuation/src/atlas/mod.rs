//! Two-dimensional atlases: Henderson's covering of a two-dimensional solution manifold by
//! charts (COCO's `atlas_2d`), for problems with two more unknowns than equations (e.g. the
//! periodic orbits of a system with two free parameters, [`crate::OrbitRun::atlas`]).
//!
//! A chart is a solution $u$ of $F(u) = 0$ ($F: \mathbb{R}^N \to \mathbb{R}^{N-2}$) with a
//! $W$-orthonormal basis $T = (t_0, t_1)$ of its tangent plane ($J t_a = 0$; $W$ the problem's
//! arclength weights), a radius $R$ and a convex polygon $P$ in the tangent coordinates
//! $s \in \mathbb{R}^2$: the part of the disc $|s| \le R$ the chart is responsible for. $P$ starts
//! as the octagon circumscribing the disc and is cut by each neighbour $j$ (whose centre
//! projects to $c = T^\top W (u_j - u)$) to the radical-line halfplane
//! $c \cdot s \le (|c|^2 + R^2 - R_j^2)/2$. A vertex of $P$ outside the disc is where the
//! manifold is not yet covered: the atlas grows a new chart there, predicted at
//! $u + T s$ with $|s| = R$ toward the vertex and corrected in the normal space,
//! $[F(u); (W T)^\top (u - u_p)] = 0$. A correction that moves farther than
//! [`AtlasSettings::max_correction`] $R$ or turns the tangent plane by more than
//! [`AtlasSettings::max_angle`] halves the radius (down to [`AtlasSettings::min_radius`]).
//! When no chart has a vertex outside its disc the manifold is covered.
//!
//! Edges: at each chart the atlas evaluates test functions oriented to be non-negative on
//! the start's side: the bounds, the problem's terminal events
//! ([`crate::MonitorEvent::terminal`]: e.g. admissibility, GR and DB) and the
//! [`AtlasEdges`] asked for (a fold: $\det [J; e_{p_1}^\top; e_{p_2}^\top]$; period doubling,
//! torus and symmetry breaking from the multipliers). A new chart with a negative test is not
//! kept: the zero is located between the chart it grew from and it (or, from a chart already
//! on that edge, across the edge), and the located point becomes a boundary chart, whose
//! polygon is cut by the edge's tangent line, so that the atlas follows the edge.
//!
//! ```
//! use hycont_continuation::atlas::{self, AtlasEnd, AtlasSettings};
//! use hycont_continuation::{ContinuationProblem, PointInfo, SpecialKind, observe::Silent};
//! use hycont_core::problem::{Activity, Problem, UnknownMonitor, ZeroFunction};
//!
//! /// The unit sphere x^2 + y^2 + z^2 = 1, with x and y free.
//! struct Sphere;
//! impl ZeroFunction for Sphere {
//!     fn unknowns(&self) -> usize { 3 }
//!     fn equations(&self) -> usize { 1 }
//!     fn jacobian_pattern(&self) -> Vec<(usize, usize)> { vec![(0, 0), (0, 1), (0, 2)] }
//!     fn evaluate(&mut self, u: &[f64], r: &mut [f64], j: Option<&mut [f64]>) -> hycont_core::Result<()> {
//!         r[0] = u[0] * u[0] + u[1] * u[1] + u[2] * u[2] - 1.0;
//!         if let Some(j) = j { for k in 0..3 { j[k] = 2.0 * u[k]; } }
//!         Ok(())
//!     }
//! }
//! struct Surface { problem: Problem<'static> }
//! impl ContinuationProblem<'static> for Surface {
//!     fn problem(&mut self) -> &mut Problem<'static> { &mut self.problem }
//!     fn parameter_index(&self) -> usize { 3 }
//!     fn parameter_position(&self) -> usize { 0 }
//!     fn parameter_name(&self) -> String { "x".into() }
//!     fn parameter_names(&self) -> Vec<String> { vec!["x".into(), "y".into()] }
//!     fn monitor_names(&self) -> Vec<String> { vec![] }
//!     fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
//!         Ok(PointInfo { params: vec![u[3], u[4]], ..PointInfo::default() })
//!     }
//! }
//! let mut problem = Problem::new(3);
//! problem.add_part(Box::new(Sphere), vec![0, 1, 2]).unwrap();
//! for (name, k) in [("x", 0), ("y", 1)] {
//!     problem.add_monitor(name, Box::new(UnknownMonitor), vec![k], Activity::Active(0.0)).unwrap();
//! }
//! let mut surface = Surface { problem };
//! // Unknowns: x, y, z, then the monitors' values x and y; near the north pole.
//! let u0 = [0.0, 0.0, 1.0, 0.0, 0.0];
//! let settings = AtlasSettings::default().radii(0.2, 1e-3, 0.2);
//! let a = atlas::cover(&mut surface, "cap", &u0, [3, 4], &settings, &mut Silent).unwrap();
//! // The fold over the (x, y) plane is the equator: the upper hemisphere is covered.
//! assert_eq!(a.end, AtlasEnd::Covered);
//! assert!(a.edge_charts(SpecialKind::Fold).all(|c| c.point.u[2].abs() < 1e-6));
//! assert!(a.charts.iter().all(|c| c.point.u[2] >= 0.0));
//! ```

mod check;
mod cover;
mod edges;
mod functions;
mod polygon;
mod settings;
mod solver;

pub use cover::{check, cover, extend};
pub use polygon::HalfPlane;
pub use settings::{AtlasBound, AtlasEdges, AtlasSettings};

use crate::branch::{BranchPoint, SpecialKind};
use crate::quantity::Quantity;
use serde::{Deserialize, Serialize};

/// Where a boundary chart lies: on which edge of the atlas.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub enum Edge {
    /// A bound: `on` at `level`.
    Bound {
        /// The bounded quantity.
        on: Quantity,
        /// The bound's value.
        level: f64,
    },
    /// A zero of a test function: a fold (SN), a symmetry-breaking branch point (BP), a period
    /// doubling (PD), a torus point (TR), or a terminal event with its label (e.g. GR, DB).
    Special {
        /// The kind.
        kind: SpecialKind,
    },
}

impl Edge {
    /// The label of the edge's kind (EP for a bound).
    #[must_use]
    pub fn label(&self) -> String {
        match self {
            Edge::Bound { .. } => SpecialKind::EndPoint.label().to_string(),
            Edge::Special { kind } => kind.label().to_string(),
        }
    }
}

/// One chart of an [`Atlas`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtlasChart {
    /// The solution with its analysis (parameters, monitors, multipliers, stability); its
    /// `tangent` is the first tangent vector, its `step` the radius of the chart it grew from.
    pub point: BranchPoint,
    /// The second tangent vector ($W$-orthonormal to `point.tangent`).
    pub tangent2: Vec<f64>,
    /// The chart's radius.
    pub radius: f64,
    /// The chart's polygon in its tangent coordinates, counter-clockwise.
    pub polygon: Vec<[f64; 2]>,
    /// The cuts of the chart by the edges it lies on or that cross its disc.
    pub cuts: Vec<EdgeCut>,
    /// The edge the chart lies on, if it is a boundary chart.
    pub edge: Option<Edge>,
    /// Indices of the charts whose discs meet this one's.
    pub neighbours: Vec<usize>,
    /// The neighbours' centres in this chart's tangent coordinates (in `neighbours`' order).
    #[serde(default)]
    pub centres: Vec<[f64; 2]>,
    /// The chart it grew from (`None` for the first).
    pub parent: Option<usize>,
    /// Whether part of its polygon is still uncovered.
    pub open: bool,
    /// Whether growing from it failed down to the smallest radius (the manifold may continue
    /// beyond: a singularity, a hidden edge, or a corrector failure).
    pub gave_up: bool,
    /// The test functions' values, oriented non-negative on the start's side.
    pub tests: Vec<f64>,
}

/// A cut of a chart's polygon by an edge: the edge's tangent line in the chart's tangent
/// coordinates, and how it was made (so that a saved atlas's cuts are checked by making them
/// again).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EdgeCut {
    /// The halfplane kept: the inside of the edge, linearised at the chart.
    pub line: HalfPlane,
    /// The index of the test function whose zero the edge is (in the order of the atlas's
    /// orientations: bounds, terminal events, then the edges asked for).
    pub test: usize,
    /// The radius the test's gradient was taken over (by differences a quarter of it away).
    pub radius: f64,
}

impl AtlasChart {
    /// Whether the chart is a boundary chart.
    #[must_use]
    pub fn is_boundary(&self) -> bool {
        self.edge.is_some()
    }
}

/// Why an atlas stopped growing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[non_exhaustive]
pub enum AtlasEnd {
    /// No chart has an uncovered part left: the manifold within the edges is covered.
    Covered,
    /// [`AtlasSettings::max_charts`] charts were made; [`extend`] with a larger limit goes on.
    ChartLimit,
    /// The observer asked it to stop ([`crate::Observer::stop`]); [`extend`] goes on.
    Stopped,
}

/// Work done by an atlas.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AtlasStatistics {
    /// Projection corrector solves.
    pub corrections: usize,
    /// Jacobian factorisations.
    pub factorisations: usize,
    /// Charts rejected (the radius halved).
    pub rejected: usize,
    /// Edge points located.
    pub located: usize,
}

/// A covering of a two-dimensional solution manifold by charts (serde: save it and
/// [`extend`] it later).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Atlas {
    /// The atlas's name.
    pub name: String,
    /// The parameters' names.
    pub parameter_names: Vec<String>,
    /// The monitors' names.
    pub monitor_names: Vec<String>,
    /// The two free parameters' indices in the unknowns.
    pub unknown_params: [usize; 2],
    /// The charts, in the order they were made.
    pub charts: Vec<AtlasChart>,
    /// The settings it was made with.
    pub settings: AtlasSettings,
    /// The test functions' orientation: their sign at the first chart (`tests` are the values
    /// times this).
    pub orientation: Vec<f64>,
    /// The fold test's scale: $\log|\det [J; e_{p_1}^\top; e_{p_2}^\top]|$ at the first chart.
    pub fold_scale: f64,
    /// Why it stopped.
    pub end: AtlasEnd,
    /// Work done.
    pub stats: AtlasStatistics,
}

impl Atlas {
    /// The boundary charts.
    pub fn boundary(&self) -> impl Iterator<Item = &AtlasChart> {
        self.charts.iter().filter(|c| c.is_boundary())
    }

    /// The boundary charts on edges of `kind` (e.g. [`SpecialKind::Fold`]).
    pub fn edge_charts(&self, kind: SpecialKind) -> impl Iterator<Item = &AtlasChart> {
        self.charts
            .iter()
            .filter(move |c| c.edge == Some(Edge::Special { kind }))
    }

    /// Triangles of three mutually neighbouring charts (indices increasing, each triple once),
    /// for pictures and interpolation. They cover the region the charts cover but are not a
    /// disjoint mesh: where four or more charts' discs overlap, their triangles overlap (6,076
    /// for 806 charts of the rocking block's atlas, against about 2 per chart of a
    /// triangulation).
    #[must_use]
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        let mut out = Vec::new();
        for (i, c) in self.charts.iter().enumerate() {
            for &j in c.neighbours.iter().filter(|&&j| j > i) {
                for &k in self.charts[j].neighbours.iter().filter(|&&k| k > j) {
                    if c.neighbours.contains(&k) {
                        out.push([i, j, k]);
                    }
                }
            }
        }
        out
    }

    /// The atlas as JSON.
    ///
    /// # Errors
    /// If serialisation fails.
    pub fn to_json(&self) -> std::result::Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// An atlas from JSON (as written by [`Atlas::to_json`]); measure handles index its
    /// charts' points again.
    ///
    /// # Errors
    /// If the text is not an atlas.
    pub fn from_json(text: &str) -> std::result::Result<Self, serde_json::Error> {
        let mut atlas: Self = serde_json::from_str(text)?;
        atlas.restore_keys();
        Ok(atlas)
    }

    /// Gives every chart's point the measure keys of the atlas's monitor names.
    pub(crate) fn restore_keys(&mut self) {
        let keys = crate::branch::MeasureKeys::of(&self.monitor_names);
        for c in &mut self.charts {
            c.point.measure_keys = keys.clone();
        }
    }
}
