//! A block: its damping and slenderness (the study's by default), and the study's eq. (5), which
//! turns an engineer's dimensional block and forcing into the model's dimensionless parameters.
//!
//! With $R$ the half-diagonal of the block (centre of mass to a corner), $M$ its mass, $c_b$ the
//! rotational damping, $g$ the gravity, $A$ and $\Omega$ the ground motion's amplitude and angular
//! frequency, the study's eq. (5) reads
//! $$\Omega_0 = \sqrt{g/R},\quad \omega = \Omega/\Omega_0,\quad \alpha = A/R,\quad
//!   \xi = \frac{c_b}{M R^2 \Omega_0}.$$
//! A block of width $w$ and height $h$ has $R = \tfrac12\sqrt{w^2 + h^2}$ and
//! $\theta_b = \arctan(h/w)$ (the angle of the diagonal to the ground: its restitution is
//! $e = 1 - \tfrac32\cos^2\theta_b$, Housner's with slenderness $\pi/2 - \theta_b$).

use crate::error::{Error, Result};
use crate::model::{DEFAULT_THETA_B, DEFAULT_XI, Parameters};
use serde::{Deserialize, Serialize};

/// Standard gravity, m/s^2 (the study's $g = 9.81$).
pub const GRAVITY: f64 = 9.81;

/// The study's block (Table I): half-diagonal $R = 3.764$ m.
pub const STUDY_RADIUS: f64 = 3.764;

/// The study's block (Table I): mass $M = 2\times10^4$ kg.
pub const STUDY_MASS: f64 = 2.0e4;

/// The study's block (Table I): damping $c_b = 101$ N m s.
pub const STUDY_DAMPING: f64 = 101.0;

/// A block in the model's dimensionless terms: damping $\xi$ and slenderness angle $\theta_b$
/// (the forcing, $\omega$ and $\alpha$, comes on top: [`Block::at`]).
///
/// ```
/// use rocking_block::block::Block;
/// let b = Block::default();
/// assert_eq!((b.xi, b.theta_b), (0.00022, 0.8795));
/// assert!(Block { xi: 0.0, theta_b: 0.3 }.validate().is_err()); // restitution < 0
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Block {
    /// Damping $\xi \ge 0$.
    pub xi: f64,
    /// Slenderness angle $\theta_b$, rad.
    pub theta_b: f64,
}

impl Default for Block {
    /// The study's block: $\xi = 0.00022$, $\theta_b = 0.8795$.
    fn default() -> Self {
        Self {
            xi: DEFAULT_XI,
            theta_b: DEFAULT_THETA_B,
        }
    }
}

impl Block {
    /// The parameters of this block at forcing `(omega, alpha)`.
    #[must_use]
    pub fn at(&self, omega: f64, alpha: f64) -> Parameters {
        Parameters {
            omega,
            alpha,
            xi: self.xi,
            theta_b: self.theta_b,
        }
    }

    /// Whether this is the study's block.
    #[must_use]
    pub fn is_study(&self) -> bool {
        *self == Self::default()
    }

    /// What figure titles append to name this block: nothing for the study's block, else
    /// ` (block theta_b = .., xi = ..)`.
    ///
    /// ```
    /// use rocking_block::block::Block;
    /// assert_eq!(Block::default().note(), "");
    /// let other = Block { theta_b: 0.85, ..Block::default() };
    /// assert_eq!(other.note(), " (block theta_b = 0.85, xi = 0.00022)");
    /// ```
    #[must_use]
    pub fn note(&self) -> String {
        if self.is_study() {
            String::new()
        } else {
            format!(" (block theta_b = {}, xi = {})", self.theta_b, self.xi)
        }
    }

    /// Checks damping and slenderness (as [`Parameters::validate`]).
    ///
    /// # Errors
    /// [`hycont_core::Error::ParameterOutOfRange`] naming the bad value.
    pub fn validate(&self) -> Result<()> {
        Ok(self.at(1.0, 0.0).validate()?)
    }

    /// The static boundary $\pi/2 - \theta_b$.
    #[must_use]
    pub fn static_boundary(&self) -> f64 {
        self.at(1.0, 0.0).static_boundary()
    }
}

impl Parameters {
    /// The block of these parameters (damping and slenderness).
    #[must_use]
    pub fn block(&self) -> Block {
        Block {
            xi: self.xi,
            theta_b: self.theta_b,
        }
    }
}

/// A dimensional block: its size, mass and damping, and the gravity.
///
/// ```
/// use rocking_block::block::{Dimensional, STUDY_RADIUS};
/// // The study's Table I: R = 3.764 m, M = 2e4 kg, c_b = 101 N m s -> xi = 0.00022.
/// let d = Dimensional::study();
/// let block = d.block(0.8795).unwrap();
/// assert!((block.xi - 0.00022).abs() < 1e-6);
/// // Forcing of amplitude 2.484 m at 2.099 rad/s: the study's (omega, alpha) = (1.3, 0.66).
/// let (omega, alpha) = d.forcing(2.0988, 2.48424).unwrap();
/// assert!((omega - 1.3).abs() < 1e-4 && (alpha - 0.66).abs() < 1e-5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Dimensional {
    /// Half-diagonal $R$ (centre of mass to a corner), m.
    pub radius: f64,
    /// Mass $M$, kg.
    pub mass: f64,
    /// Rotational damping $c_b$, N m s.
    pub damping: f64,
    /// Gravity $g$, m/s^2.
    pub gravity: f64,
}

/// A positive finite length, mass or rate, or an error naming it.
fn positive(name: &'static str, value: f64) -> Result<f64> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidArgument {
            name,
            value: value.to_string(),
            reason: "must be > 0 and finite",
        })
    }
}

impl Dimensional {
    /// The study's block (Table I).
    #[must_use]
    pub fn study() -> Self {
        Self {
            radius: STUDY_RADIUS,
            mass: STUDY_MASS,
            damping: STUDY_DAMPING,
            gravity: GRAVITY,
        }
    }

    /// The half-diagonal and slenderness of a block `width` x `height` (m):
    /// $R = \tfrac12\sqrt{w^2+h^2}$, $\theta_b = \arctan(h/w)$.
    ///
    /// # Errors
    /// A size that is not positive and finite.
    ///
    /// ```
    /// let (r, theta_b) = rocking_block::block::Dimensional::size(3.0, 4.0).unwrap();
    /// assert!((r - 2.5).abs() < 1e-15 && (theta_b - (4.0f64 / 3.0).atan()).abs() < 1e-15);
    /// ```
    pub fn size(width: f64, height: f64) -> Result<(f64, f64)> {
        let (w, h) = (positive("width", width)?, positive("height", height)?);
        Ok((0.5 * w.hypot(h), h.atan2(w)))
    }

    /// Checks every value.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] naming the bad value (damping may be zero).
    pub fn validate(&self) -> Result<()> {
        positive("radius", self.radius)?;
        positive("mass", self.mass)?;
        positive("gravity", self.gravity)?;
        if !(self.damping >= 0.0 && self.damping.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "damping",
                value: self.damping.to_string(),
                reason: "must be >= 0 and finite",
            });
        }
        Ok(())
    }

    /// The natural frequency $\Omega_0 = \sqrt{g/R}$, rad/s (the unit of dimensionless time).
    #[must_use]
    pub fn omega0(&self) -> f64 {
        (self.gravity / self.radius).sqrt()
    }

    /// The dimensionless block of slenderness `theta_b`: $\xi = c_b/(M R^2 \Omega_0)$.
    ///
    /// # Errors
    /// Invalid values ([`Dimensional::validate`], [`Block::validate`]).
    pub fn block(&self, theta_b: f64) -> Result<Block> {
        self.validate()?;
        let xi = self.damping / (self.mass * self.radius * self.radius * self.omega0());
        let block = Block { xi, theta_b };
        block.validate()?;
        Ok(block)
    }

    /// The dimensionless forcing `(omega, alpha)` of ground motion at `frequency` rad/s with
    /// `amplitude` m: $\omega = \Omega/\Omega_0$, $\alpha = A/R$.
    ///
    /// # Errors
    /// Invalid values, a frequency that is not positive or an amplitude below zero.
    pub fn forcing(&self, frequency: f64, amplitude: f64) -> Result<(f64, f64)> {
        Ok((self.omega(frequency)?, self.alpha(amplitude)?))
    }

    /// The dimensionless frequency $\omega = \Omega/\Omega_0$ of `frequency` rad/s.
    ///
    /// # Errors
    /// Invalid values, or a frequency that is not positive and finite.
    pub fn omega(&self, frequency: f64) -> Result<f64> {
        self.validate()?;
        Ok(positive("frequency", frequency)? / self.omega0())
    }

    /// The dimensionless amplitude $\alpha = A/R$ of `amplitude` m.
    ///
    /// # Errors
    /// Invalid values, or an amplitude below zero or not finite.
    pub fn alpha(&self, amplitude: f64) -> Result<f64> {
        self.validate()?;
        if !(amplitude >= 0.0 && amplitude.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "amplitude",
                value: amplitude.to_string(),
                reason: "must be >= 0 and finite",
            });
        }
        Ok(amplitude / self.radius)
    }
}

/// Dimensional inputs as given, with what eq. (5) made of them (written into result files).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DimensionalInputs {
    /// The block's dimensions, mass, damping and gravity (given or the study's).
    pub block: Dimensional,
    /// Width and height, m, when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size: Option<(f64, f64)>,
    /// The forcing's angular frequency, rad/s, when given (`--frequency-hz` times 2 pi).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency: Option<f64>,
    /// The forcing's amplitude, m, when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// The unit of dimensionless time, sqrt(g/R), rad/s.
    pub omega0: f64,
}
