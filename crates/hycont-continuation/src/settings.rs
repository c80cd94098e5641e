//! Continuation settings: a validated builder with `Default`.

use crate::error::{Error, Result};
use crate::quantity::Quantity;
use hycont_core::problem::NewtonSettings;
use serde::{Deserialize, Serialize};

/// Bounds on the continuation parameter, other parameters and measures; leaving them ends the
/// branch with an end point (EP) located on the bound.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bound {
    /// What is bounded.
    pub on: BoundOn,
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
}

/// The quantity a [`Bound`] applies to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BoundOn {
    /// The continuation parameter, whichever it is.
    ContinuationParameter,
    /// A parameter or measure reported by the problem.
    Quantity(Quantity),
}

/// Which test functions are evaluated along the branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[allow(clippy::struct_excessive_bools)]
pub struct Detect {
    /// Folds (limit points): the tangent's parameter component changes sign.
    pub fold: bool,
    /// Branch points: the sign of the augmented Jacobian's determinant changes.
    pub branch_point: bool,
    /// Period doublings: a non-trivial multiplier crosses $-1$.
    pub period_doubling: bool,
    /// Torus (Neimark-Sacker) points: a complex pair crosses the unit circle.
    pub torus: bool,
    /// Events defined on monitors by the problem ([`crate::ContinuationProblem::monitor_events`]).
    pub monitor_events: bool,
    /// On curves of points with a multiplier held at $\pm 1$
    /// ([`crate::ContinuationProblem::held_multiplier`]: fold and period-doubling curves),
    /// the codimension-two points where another multiplier reaches $+1$, $-1$ or, as a complex
    /// pair, the unit circle: R1, LPPD, R2, LPNS, PDNS; on fold curves
    /// ([`crate::ContinuationProblem::cusp_parameter`]) cusps (CP), where both parameters are
    /// stationary along the curve (default off; on in [`crate::curve_settings`]).
    #[serde(default)]
    pub codim2: bool,
}

impl Default for Detect {
    fn default() -> Self {
        Self {
            fold: true,
            branch_point: true,
            period_doubling: true,
            torus: true,
            monitor_events: true,
            codim2: false,
        }
    }
}

/// Settings of [`crate::continue_branch`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContinuationSettings {
    /// First step (arclength, default `0.01`), taken within `[h_min, h_max]`
    /// ([`ContinuationSettings::first_step`]): bounds that exclude it (e.g. a smaller `h_max`
    /// alone) move the first step to the nearest of them.
    pub h0: f64,
    /// Smallest step before giving up (default `1e-7`).
    pub h_min: f64,
    /// Largest step (default `0.1`).
    pub h_max: f64,
    /// Step growth factor after an easy corrector (default `1.4`).
    pub growth: f64,
    /// Largest angle (rad) between consecutive tangents (default `0.15`).
    pub max_angle: f64,
    /// Largest number of points (default 2000).
    pub max_points: usize,
    /// Corrector iterations above which the step shrinks (default 5); at most twice this many
    /// are allowed.
    pub target_iterations: usize,
    /// Newton settings of the corrector (chord steps are disabled in the corrector).
    pub newton: NewtonSettings,
    /// Special points are located until their bracket is below this (default `1e-10`): a
    /// bracket in arclength along the step, in the problem's weighted norm
    /// ([`crate::ContinuationProblem::unknown_weights`]; a parameter weighs 1). The located
    /// parameter is therefore within `locate_tol` times $|dp/ds| \le 1$ (the parameter's
    /// component of the unit tangent) of the zero of the test function: `1e-10` or better,
    /// and closer where the branch turns (at a fold $dp/ds \to 0$). For orbits, unknowns
    /// other than parameters are the node or start states (weighted as a mean square over a
    /// segment, so that the norm does not depend on the mesh) and the durations.
    pub locate_tol: f64,
    /// Bounds ending the run.
    pub bounds: Vec<Bound>,
    /// Test functions evaluated.
    pub detect: Detect,
    /// Special-point kinds that end the branch when located (e.g. the branch point where an
    /// asymmetric branch rejoins the symmetric one).
    pub stop_at: Vec<crate::SpecialKind>,
    /// A located SN, BP, PD or TR point is reported only if a non-trivial multiplier lies
    /// within this distance of the kind's critical value (default `1e-4`, in `(0, 1)`); see
    /// [`crate::SpecialPoint::critical`].
    #[serde(default = "default_critical_tolerance")]
    pub critical_tolerance: f64,
    /// Re-discretise (collocation: re-adapt the mesh,
    /// [`crate::ContinuationProblem::rediscretise`]) every this many points, unless the error
    /// estimate is below a hundredth of [`ContinuationSettings::discretisation_tolerance`]; 0:
    /// only on the error estimate (default 10; AUTO's IAD is 3, COCO's NAdapt off).
    #[serde(default = "default_adapt_every")]
    pub adapt_every: usize,
    /// Re-discretise also at a point whose estimated discretisation error exceeds this
    /// (default `1e-6`, absolute, in the units of the state; `f64::INFINITY`: never). The mesh
    /// keeps its size, so equidistribution may not reach it: points report their estimate
    /// ([`crate::BranchPoint::discretisation_error`]), and a finer mesh is the remedy.
    #[serde(default = "default_discretisation_tolerance")]
    pub discretisation_tolerance: f64,
}

fn default_adapt_every() -> usize {
    10
}

fn default_discretisation_tolerance() -> f64 {
    1e-6
}

fn default_critical_tolerance() -> f64 {
    1e-4
}

impl Default for ContinuationSettings {
    fn default() -> Self {
        Self {
            h0: 0.01,
            h_min: 1e-7,
            h_max: 0.1,
            growth: 1.4,
            max_angle: 0.15,
            max_points: 2000,
            target_iterations: 5,
            newton: NewtonSettings {
                chord_contraction: 0.0,
                ..NewtonSettings::default()
            },
            locate_tol: 1e-10,
            bounds: Vec::new(),
            detect: Detect::default(),
            stop_at: Vec::new(),
            critical_tolerance: default_critical_tolerance(),
            adapt_every: default_adapt_every(),
            discretisation_tolerance: default_discretisation_tolerance(),
        }
    }
}

impl ContinuationSettings {
    /// Sets the first, smallest and largest steps.
    #[must_use]
    pub fn steps(mut self, h0: f64, h_min: f64, h_max: f64) -> Self {
        self.h0 = h0;
        self.h_min = h_min;
        self.h_max = h_max;
        self
    }

    /// The first step a run takes: [`ContinuationSettings::h0`] within `[h_min, h_max]`.
    #[must_use]
    pub fn first_step(&self) -> f64 {
        self.h0.max(self.h_min).min(self.h_max)
    }

    /// Bounds the continuation parameter to `[min, max]`.
    #[must_use]
    pub fn parameter_bounds(mut self, min: f64, max: f64) -> Self {
        self.bounds.push(Bound {
            on: BoundOn::ContinuationParameter,
            min,
            max,
        });
        self
    }

    /// Bounds a parameter or measure to `[min, max]`.
    #[must_use]
    pub fn bounds(mut self, on: impl Into<Quantity>, min: f64, max: f64) -> Self {
        self.bounds.push(Bound {
            on: BoundOn::Quantity(on.into()),
            min,
            max,
        });
        self
    }

    /// The bounds of the continuation parameter (the tightest if there are several;
    /// infinite without one).
    #[must_use]
    pub fn continuation_bounds(&self) -> (f64, f64) {
        self.bounds
            .iter()
            .filter(|b| b.on == BoundOn::ContinuationParameter)
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(lo, hi), b| {
                (lo.max(b.min), hi.min(b.max))
            })
    }

    /// Sets the largest number of points.
    #[must_use]
    pub fn max_points(mut self, n: usize) -> Self {
        self.max_points = n;
        self
    }

    /// Ends the branch at the first located special point of this kind.
    #[must_use]
    pub fn stop_at(mut self, kind: crate::SpecialKind) -> Self {
        self.stop_at.push(kind);
        self
    }

    /// Sets when the discretisation is adapted: every `every` points (0: never on a count)
    /// and where the error estimate exceeds `tolerance` (`f64::INFINITY`: never).
    #[must_use]
    pub fn adaptation(mut self, every: usize, tolerance: f64) -> Self {
        self.adapt_every = every;
        self.discretisation_tolerance = tolerance;
        self
    }

    /// Sets which test functions are evaluated.
    #[must_use]
    pub fn detect(mut self, detect: Detect) -> Self {
        self.detect = detect;
        self
    }

    /// Checks every invariant.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the first offending setting.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(Error::InvalidSetting {
                name,
                value,
                reason,
            })
        };
        if !(self.critical_tolerance > 0.0 && self.critical_tolerance < 1.0) {
            return bad(
                "critical_tolerance",
                self.critical_tolerance,
                "must be in (0, 1)",
            );
        }
        if !(self.h_min > 0.0) {
            return bad("h_min", self.h_min, "must be > 0");
        }
        if !(self.h_max >= self.h_min) {
            return bad("h_max", self.h_max, "must be >= h_min");
        }
        if !(self.h0 > 0.0 && self.h0.is_finite()) {
            return bad(
                "h0",
                self.h0,
                "must be > 0 and finite (it is taken within [h_min, h_max])",
            );
        }
        if !self.h_max.is_finite() {
            return bad("h_max", self.h_max, "must be finite");
        }
        if !(self.growth >= 1.0 && self.growth <= 4.0) {
            return bad("growth", self.growth, "must be in [1, 4]");
        }
        if !(self.max_angle > 0.0 && self.max_angle < 1.5) {
            return bad("max_angle", self.max_angle, "must be in (0, 1.5) rad");
        }
        if self.max_points < 2 {
            return bad("max_points", self.max_points as f64, "must be >= 2");
        }
        if self.target_iterations < 2 {
            return bad(
                "target_iterations",
                self.target_iterations as f64,
                "must be >= 2",
            );
        }
        if !(self.discretisation_tolerance > 0.0) {
            return bad(
                "discretisation_tolerance",
                self.discretisation_tolerance,
                "must be > 0 (infinity: never re-discretise on the estimate)",
            );
        }
        if !(self.locate_tol > 0.0) {
            return bad("locate_tol", self.locate_tol, "must be > 0");
        }
        for b in &self.bounds {
            if !(b.min < b.max) {
                return bad("bounds", b.min, "min must be < max");
            }
        }
        self.newton.validate()?;

        Ok(())
    }
}
