//! The block and the forcing on the command line: dimensionless (`--xi`, `--theta-b`,
//! `--omega`, `--alpha`) or dimensional (size, mass, damping, amplitude, frequency), converted by
//! the study's eq. (5) ([`crate::block`]).

use crate::block::{Block, Dimensional, DimensionalInputs};
use crate::error::Result;
use crate::model::{DEFAULT_THETA_B, DEFAULT_XI, Parameters};
use clap::Args;

/// The block: damping and slenderness (the study's unless given), dimensionless or from its
/// dimensions. Dimensional values not given are the study's (Table I: R = 3.764 m,
/// M = 2e4 kg, c_b = 101 N m s, g = 9.81 m/s^2).
#[derive(Debug, Clone, Copy, Default, Args)]
pub struct BlockArgs {
    /// Damping xi (>= 0) [default: the study's 0.00022].
    #[arg(long, allow_hyphen_values = true, conflicts_with = "damping")]
    pub xi: Option<f64>,
    /// Slenderness angle theta_b in rad, in (acos(sqrt(2/3)), pi/2) [default: the study's
    /// 0.8795].
    #[arg(long = "theta-b", allow_hyphen_values = true)]
    pub theta_b: Option<f64>,
    /// Width of the block, m (with --height: gives theta_b = atan(height/width) and the
    /// half-diagonal R).
    #[arg(long, allow_hyphen_values = true, requires = "height", conflicts_with_all = ["theta_b", "radius"])]
    pub width: Option<f64>,
    /// Height of the block, m (with --width).
    #[arg(long, allow_hyphen_values = true, requires = "width")]
    pub height: Option<f64>,
    /// Half-diagonal R of the block (centre of mass to a corner), m [default: the study's
    /// 3.764].
    #[arg(long, allow_hyphen_values = true)]
    pub radius: Option<f64>,
    /// Mass of the block, kg (with --damping) [default: the study's 2e4].
    #[arg(long, allow_hyphen_values = true)]
    pub mass: Option<f64>,
    /// Rotational damping c_b, N m s: xi = c_b / (M R^2 sqrt(g/R)) [default: the study's xi].
    #[arg(long, allow_hyphen_values = true)]
    pub damping: Option<f64>,
    /// Gravity, m/s^2 [default: 9.81].
    #[arg(long, allow_hyphen_values = true)]
    pub gravity: Option<f64>,
}

/// The forcing: dimensionless `--omega`, `--alpha` or the ground motion's frequency and
/// amplitude.
#[derive(Debug, Clone, Copy, Args)]
pub struct ForcingArgs {
    /// Forcing frequency omega (> 0), in units of sqrt(g/R).
    #[arg(long, default_value_t = 1.3, allow_hyphen_values = true, conflicts_with_all = ["frequency", "frequency_hz"])]
    pub omega: f64,
    /// Forcing amplitude alpha (>= 0; the study's range is (0, 1.06]), in units of R.
    #[arg(
        long,
        default_value_t = 0.66,
        allow_hyphen_values = true,
        conflicts_with = "amplitude"
    )]
    pub alpha: f64,
    /// Ground motion's angular frequency, rad/s (instead of --omega).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "frequency_hz")]
    pub frequency: Option<f64>,
    /// Ground motion's frequency, Hz (instead of --omega).
    #[arg(long = "frequency-hz", allow_hyphen_values = true)]
    pub frequency_hz: Option<f64>,
    /// Ground motion's amplitude, m (instead of --alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub amplitude: Option<f64>,
}

impl Default for ForcingArgs {
    /// The study's start point, $(\omega, \alpha) = (1.3, 0.66)$.
    fn default() -> Self {
        Self {
            omega: 1.3,
            alpha: 0.66,
            frequency: None,
            frequency_hz: None,
            amplitude: None,
        }
    }
}

impl ForcingArgs {
    /// Whether the forcing was given in dimensional units.
    #[must_use]
    pub fn dimensional_given(&self) -> bool {
        self.frequency.is_some() || self.frequency_hz.is_some() || self.amplitude.is_some()
    }
}

impl BlockArgs {
    /// Whether any block option was given.
    #[must_use]
    pub fn given(&self) -> bool {
        self.xi.is_some() || self.theta_b.is_some() || self.dimensional_given()
    }

    /// Whether a dimensional block option was given.
    #[must_use]
    pub fn dimensional_given(&self) -> bool {
        [
            self.width,
            self.height,
            self.radius,
            self.mass,
            self.damping,
            self.gravity,
        ]
        .iter()
        .any(Option::is_some)
    }

    /// The dimensional block (given values, the study's for the rest) and its slenderness.
    ///
    /// # Errors
    /// Sizes, masses or damping that are not positive and finite.
    pub fn dimensional(&self) -> Result<(Dimensional, f64)> {
        let study = Dimensional::study();
        let (radius, theta_b) = match (self.width, self.height) {
            (Some(w), Some(h)) => Dimensional::size(w, h)?,
            _ => (
                self.radius.unwrap_or(study.radius),
                self.theta_b.unwrap_or(DEFAULT_THETA_B),
            ),
        };
        let d = Dimensional {
            radius,
            mass: self.mass.unwrap_or(study.mass),
            damping: self.damping.unwrap_or(study.damping),
            gravity: self.gravity.unwrap_or(study.gravity),
        };
        d.validate()?;
        Ok((d, theta_b))
    }

    /// The dimensionless block (validated).
    ///
    /// # Errors
    /// Invalid values, naming the option.
    pub fn block(&self) -> Result<Block> {
        let (d, theta_b) = self.dimensional()?;
        let block = if self.damping.is_some() {
            d.block(theta_b)?
        } else {
            Block {
                xi: self.xi.unwrap_or(DEFAULT_XI),
                theta_b,
            }
        };
        block.validate()?;
        Ok(block)
    }
}

/// The parameters of a command's block and forcing, validated, and the dimensional inputs they
/// came from (`None` when everything was dimensionless).
///
/// # Errors
/// Invalid values, naming the option.
pub fn parameters(
    block: &BlockArgs,
    forcing: &ForcingArgs,
) -> Result<(Parameters, Option<DimensionalInputs>)> {
    let b = block.block()?;
    let (d, _) = block.dimensional()?;
    let frequency = match (forcing.frequency, forcing.frequency_hz) {
        (Some(f), _) => Some(f),
        (None, Some(hz)) => Some(std::f64::consts::TAU * hz),
        (None, None) => None,
    };
    let omega = match frequency {
        Some(f) => d.omega(f)?,
        None => forcing.omega,
    };
    let alpha = match forcing.amplitude {
        Some(a) => d.alpha(a)?,
        None => forcing.alpha,
    };
    let params = b.at(omega, alpha);
    params.validate()?;
    let dimensional =
        (block.dimensional_given() || forcing.dimensional_given()).then(|| DimensionalInputs {
            block: d,
            size: block.width.zip(block.height),
            frequency,
            amplitude: forcing.amplitude,
            omega0: d.omega0(),
        });
    Ok((params, dimensional))
}

/// One line saying what dimensional inputs became (printed on stderr).
#[must_use]
pub fn describe(params: &Parameters, d: &DimensionalInputs) -> String {
    format!(
        "dimensionless (eq. (5), R = {} m, sqrt(g/R) = {:.6} rad/s): omega = {:.6}, alpha = {:.6}, xi = {:.6e}, theta_b = {:.6}",
        d.block.radius, d.omega0, params.omega, params.alpha, params.xi, params.theta_b
    )
}

/// The dimensional inputs of a figure's block (none when it was given dimensionless), told
/// to the user on stderr.
///
/// # Errors
/// Invalid values, naming the option.
pub(super) fn figure_dimensional(block: &BlockArgs) -> Result<Option<DimensionalInputs>> {
    if !block.dimensional_given() {
        return Ok(None);
    }
    let b = block.block()?;
    let (d, _) = block.dimensional()?;
    eprintln!(
        "dimensionless block (eq. (5), R = {} m): xi = {:.6e}, theta_b = {:.6}",
        d.radius, b.xi, b.theta_b
    );
    Ok(Some(DimensionalInputs {
        block: d,
        size: block.width.zip(block.height),
        frequency: None,
        amplitude: None,
        omega0: d.omega0(),
    }))
}

/// [`parameters`], telling the user on stderr what dimensional inputs became.
pub(super) fn resolve(
    block: &BlockArgs,
    forcing: &ForcingArgs,
) -> Result<(Parameters, Option<DimensionalInputs>)> {
    let (params, dims) = parameters(block, forcing)?;
    if let Some(d) = &dims {
        eprintln!("{}", describe(&params, d));
    }
    Ok((params, dims))
}
