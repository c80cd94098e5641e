//! Settings of a two-dimensional atlas: a validated builder with `Default`.

use crate::error::{Error, Result};
use crate::quantity::Quantity;
use hycont_core::problem::NewtonSettings;
use serde::{Deserialize, Serialize};

/// Which test-function zeros are edges of an atlas (where it stops, with boundary charts on
/// them), besides its bounds and the problem's terminal events (e.g. admissibility: GR, DB),
/// which always are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[allow(clippy::struct_excessive_bools)]
pub struct AtlasEdges {
    /// Folds (SN): the problem at fixed parameters is singular, $\det [J; e_{p_1}^\top;
    /// e_{p_2}^\top] = 0$ (a multiplier $+1$; on a half orbit, of the half map: a fold of
    /// symmetric orbits). Stopping there keeps the atlas on one sheet over the parameter plane
    /// (default on).
    pub fold: bool,
    /// Symmetry-breaking branch points of a half-orbit problem (a half-map multiplier $-1$;
    /// default off).
    pub branch_point: bool,
    /// Period doublings: a non-trivial multiplier crosses $-1$ (default off).
    pub period_doubling: bool,
    /// Torus points: a complex pair crosses the unit circle (default off).
    pub torus: bool,
}

impl Default for AtlasEdges {
    fn default() -> Self {
        Self {
            fold: true,
            branch_point: false,
            period_doubling: false,
            torus: false,
        }
    }
}

/// A box bound of an atlas: `on` stays in `[min, max]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AtlasBound {
    /// The bounded parameter or measure.
    pub on: Quantity,
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
}

/// Settings of [`crate::atlas::cover`] (Henderson's covering by charts, in two dimensions).
///
/// Chart radii are arclengths in the problem's weighted norm
/// ([`crate::ContinuationProblem::unknown_weights`]), as PALC's steps: $\|v\|^2 = \sum_i
/// w_i v_i^2$ over all unknowns. Parameters weigh 1; an orbit's states weigh as a mean square
/// over each segment (collocation: each node `copies / nodes`; shooting: each start
/// `copies`, with `copies` 2 on half orbits) and durations `copies`. So a radius of `0.1` is
/// a move of at most `0.1` in the two free parameters, less where the orbits change fast
/// with them (the states take their share of the arclength).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtlasSettings {
    /// The first chart's radius (default `0.05`).
    pub radius: f64,
    /// Smallest radius before a direction is given up (default `1e-3`).
    pub min_radius: f64,
    /// Largest radius (default `0.1`).
    pub max_radius: f64,
    /// Radius growth after an easy chart (default `1.2`).
    pub growth: f64,
    /// Largest angle (rad) between the tangent planes of a chart and the one it grew from
    /// (default `0.2`).
    pub max_angle: f64,
    /// Largest distance of a corrected chart from its prediction, relative to the radius
    /// (default `0.2`).
    pub max_correction: f64,
    /// Largest number of charts (default `2000`).
    pub max_charts: usize,
    /// Newton settings of the projection corrector (default: [`NewtonSettings::default`] with
    /// at most 10 iterations).
    pub newton: NewtonSettings,
    /// Edges are located until the bracket along the search line is below this fraction of
    /// the radius (default `1e-6`).
    pub locate_tol: f64,
    /// Box bounds (their edges are the atlas's).
    pub bounds: Vec<AtlasBound>,
    /// Test-function zeros that are edges.
    pub edges: AtlasEdges,
}

impl Default for AtlasSettings {
    fn default() -> Self {
        Self {
            radius: 0.05,
            min_radius: 1e-3,
            max_radius: 0.1,
            growth: 1.2,
            max_angle: 0.2,
            max_correction: 0.2,
            max_charts: 2000,
            newton: NewtonSettings {
                max_iterations: 10,
                ..NewtonSettings::default()
            },
            locate_tol: 1e-6,
            bounds: Vec::new(),
            edges: AtlasEdges::default(),
        }
    }
}

impl AtlasSettings {
    /// Sets the first, smallest and largest chart radii.
    #[must_use]
    pub fn radii(mut self, first: f64, min: f64, max: f64) -> Self {
        self.radius = first;
        self.min_radius = min;
        self.max_radius = max;
        self
    }

    /// Bounds a parameter or measure to `[min, max]`.
    #[must_use]
    pub fn bound(mut self, on: impl Into<Quantity>, min: f64, max: f64) -> Self {
        self.bounds.push(AtlasBound {
            on: on.into(),
            min,
            max,
        });
        self
    }

    /// Sets the largest number of charts.
    #[must_use]
    pub fn max_charts(mut self, n: usize) -> Self {
        self.max_charts = n;
        self
    }

    /// Sets the edges.
    #[must_use]
    pub fn edges(mut self, edges: AtlasEdges) -> Self {
        self.edges = edges;
        self
    }

    /// Checks every setting.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the first bad value.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(Error::InvalidSetting {
                name,
                value,
                reason,
            })
        };
        let positive = |x: f64| x > 0.0 && x.is_finite();
        if !positive(self.min_radius) {
            return bad("min_radius", self.min_radius, "must be positive and finite");
        }
        if !positive(self.max_radius) || self.max_radius < self.min_radius {
            return bad(
                "max_radius",
                self.max_radius,
                "must be finite and >= min_radius",
            );
        }
        if !(self.radius >= self.min_radius && self.radius <= self.max_radius) {
            return bad(
                "radius",
                self.radius,
                "must lie in [min_radius, max_radius]",
            );
        }
        if !(self.growth >= 1.0 && self.growth.is_finite()) {
            return bad("growth", self.growth, "must be finite and >= 1");
        }
        if !(self.max_angle > 0.0 && self.max_angle < std::f64::consts::FRAC_PI_2) {
            return bad("max_angle", self.max_angle, "must lie in (0, pi/2)");
        }
        if !(self.max_correction > 0.0 && self.max_correction < 1.0) {
            return bad("max_correction", self.max_correction, "must lie in (0, 1)");
        }
        if self.max_charts == 0 {
            return bad("max_charts", 0.0, "must be at least 1");
        }
        if !(self.locate_tol > 0.0 && self.locate_tol < 1.0) {
            return bad("locate_tol", self.locate_tol, "must lie in (0, 1)");
        }
        self.newton.validate()?;
        for b in &self.bounds {
            if !(b.min.is_finite() && b.max.is_finite() && b.min < b.max) {
                return bad("bound", b.min, "needs finite min < max");
            }
        }
        Ok(())
    }
}
