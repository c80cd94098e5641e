//! The rocking block's parameters $(\omega, \alpha, \xi, \theta_b)$: the study's defaults,
//! their validation and what follows from them (restitution, lift-off, the forcing period).

use crate::model::LIFT_OFF_MARGIN;
use hycont_core::{Error, Result};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// Default slenderness angle of the study (Table I), rad.
pub const DEFAULT_THETA_B: f64 = 0.8795;
/// Default dimensionless damping of the study (Table I made dimensionless).
pub const DEFAULT_XI: f64 = 0.00022;

/// The largest forcing frequency, amplitude and damping (dimensionless) a block takes, and
/// the reciprocal of the smallest forcing frequency: far beyond any physical block (the
/// study's are of order 1), and within what the model's terms ($\alpha\omega^2$, $\xi\psi$,
/// the period $2\pi/\omega$) and the integrator resolve, so that an extreme value is refused
/// by name instead of failing the integration.
pub const MAX_SCALE: f64 = 1e4;

/// Coefficient of restitution $e(\theta_b) = 1 - \tfrac32 \sin^2(\pi/2 - \theta_b)$.
///
/// ```
/// let e = rocking_block::restitution(rocking_block::DEFAULT_THETA_B);
/// assert!((e - 0.3902).abs() < 5e-4);
/// ```
#[must_use]
pub fn restitution(theta_b: f64) -> f64 {
    let c = (FRAC_PI_2 - theta_b).sin();
    1.0 - 1.5 * c * c
}

/// Parameters of the rocking block, defaulting to the study's (Table I, dimensionless).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Parameters {
    /// Forcing frequency $\omega > 0$.
    pub omega: f64,
    /// Forcing amplitude $\alpha \ge 0$ (the study's range is $(0, 1.06]$).
    pub alpha: f64,
    /// Damping $\xi \ge 0$.
    pub xi: f64,
    /// Slenderness angle $\theta_b \in (\arccos\sqrt{2/3}, \pi/2)$ (so that $0 < e < 1$).
    pub theta_b: f64,
}

impl Default for Parameters {
    /// The study's start point: $\omega = 1.3$, $\alpha = 0.66$, $\xi = 0.00022$,
    /// $\theta_b = 0.8795$.
    fn default() -> Self {
        Self {
            omega: 1.3,
            alpha: 0.66,
            xi: DEFAULT_XI,
            theta_b: DEFAULT_THETA_B,
        }
    }
}

impl Parameters {
    /// Parameters at forcing `(omega, alpha)` with the study's damping and slenderness.
    #[must_use]
    pub fn new(omega: f64, alpha: f64) -> Self {
        Self {
            omega,
            alpha,
            ..Self::default()
        }
    }

    /// Checks every parameter against its valid range.
    ///
    /// # Errors
    /// [`Error::ParameterOutOfRange`] naming the offending parameter and value.
    ///
    /// ```
    /// use rocking_block::Parameters;
    /// assert!(Parameters::default().validate().is_ok());
    /// let err = Parameters::new(-1.0, 0.66).validate().unwrap_err();
    /// assert!(err.to_string().contains("omega = -1"));
    /// ```
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(Error::ParameterOutOfRange {
                name,
                value,
                reason,
            })
        };
        if !(self.omega >= 1.0 / MAX_SCALE && self.omega <= MAX_SCALE) {
            return bad("omega", self.omega, "must be in [1e-4, 1e4]");
        }
        if !(self.alpha >= 0.0 && self.alpha <= MAX_SCALE) {
            return bad("alpha", self.alpha, "must be in [0, 1e4]");
        }
        if !(self.xi >= 0.0 && self.xi <= MAX_SCALE) {
            return bad("xi", self.xi, "must be in [0, 1e4]");
        }
        if !(self.theta_b > 0.0 && self.theta_b < FRAC_PI_2) {
            return bad("theta_b", self.theta_b, "must be in (0, pi/2)");
        }
        if restitution(self.theta_b) <= 0.0 {
            return bad(
                "theta_b",
                self.theta_b,
                "gives restitution e = 1 - 3/2 cos^2(theta_b) <= 0; need theta_b > acos(sqrt(2/3)) = 0.6155",
            );
        }
        Ok(())
    }

    /// Parameters from a vector in the model's order (`omega, alpha, xi, theta_b`; missing
    /// entries take the defaults).
    #[must_use]
    pub fn from_vec(p: &[f64]) -> Self {
        let d = Self::default();
        let at = |i: usize, default: f64| p.get(i).copied().unwrap_or(default);
        Self {
            omega: at(0, d.omega),
            alpha: at(1, d.alpha),
            xi: at(2, d.xi),
            theta_b: at(3, d.theta_b),
        }
    }

    /// The parameter vector in the model's order (`omega, alpha, xi, theta_b`).
    #[must_use]
    pub fn to_vec(&self) -> Vec<f64> {
        vec![self.omega, self.alpha, self.xi, self.theta_b]
    }

    /// The static boundary $\pi/2 - \theta_b$: where the centre of mass passes over the pivot.
    #[must_use]
    pub fn static_boundary(&self) -> f64 {
        FRAC_PI_2 - self.theta_b
    }

    /// The coefficient of restitution, see [`restitution`].
    #[must_use]
    pub fn restitution(&self) -> f64 {
        restitution(self.theta_b)
    }

    /// Whether a block at rest can ever lift off on the forcing's limit cycle ($|r| \le 1$):
    /// $\alpha\omega^2\tan\theta_b > 1$ by more than [`LIFT_OFF_MARGIN`].
    #[must_use]
    pub fn lift_off_possible(&self) -> bool {
        self.alpha * self.omega * self.omega * self.theta_b.tan() > 1.0 + LIFT_OFF_MARGIN
    }

    /// The forcing period $2\pi/\omega$.
    #[must_use]
    pub fn forcing_period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }
}
