//! Periodic orbits of the rocking block: the symmetric orbit (hycont's symmetric-orbit search
//! from the block's seeds), the asymmetric pair, and orbits read off simulations; each with
//! $\psi = 0$ interior points, so that its amplitude is an unknown of the orbit (exact).

use crate::continuation::{Free, default_method, study_run};
use crate::error::{Error, Result};
use crate::model::{IMPACT_PLUS, PLUS, Parameters, RockingBlock};
use crate::simulation::{Outcome, SimulationRequest, simulate};
use hycont_core::SimulationSettings;
use hycont_core::orbit::{
    Closure, CollocationSettings, Measure, OrbitMethod, OrbitSolution, PeriodicOrbit, SegmentEnd,
    SegmentSpec, ShootingSettings, Signature, SymmetricSearch, TimeAverage, find_symmetric_orbit,
    solve_orbit, solve_shooting,
};
use hycont_core::problem::NewtonSettings;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// Which periodic orbit to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OrbitKind {
    /// The $\mathbb{Z}_2$-symmetric period-1 orbit (two flights of $\pi/\omega$).
    Symmetric,
    /// The asymmetric period-1 orbit leaning to $\varphi > 0$.
    AsymmetricPos,
    /// The asymmetric period-1 orbit leaning to $\varphi < 0$ (the image of the other).
    AsymmetricNeg,
    /// Whatever periodic orbit a simulation from the given initial condition settles on.
    Simulate,
}

impl OrbitKind {
    /// The kind in words (as the command line names it).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            OrbitKind::Symmetric => "symmetric",
            OrbitKind::AsymmetricPos => "asymmetric-pos",
            OrbitKind::AsymmetricNeg => "asymmetric-neg",
            OrbitKind::Simulate => "simulated",
        }
    }
}

/// A computed orbit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RockingOrbit {
    /// The solution: orbit with $\psi = 0$ interior points, multipliers, Newton history.
    pub solution: OrbitSolution,
    /// For symmetric orbits: the half map's multipliers $\mu$ ($\mu^2 = \lambda$).
    pub half_multipliers: Option<Vec<(f64, f64)>>,
}

/// The orbit near `guess` (with or without interior points) solved by shooting, with every
/// $\psi = 0$ interior point (the extrema of $\varphi$), so that the amplitude is exact.
///
/// # Errors
/// If Newton's method fails.
pub fn solve_with_extrema(guess: &PeriodicOrbit) -> Result<OrbitSolution> {
    let flights = guess.without_interior_points(&RockingBlock)?;
    let sol = solve_shooting(
        &RockingBlock,
        &flights,
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )?;
    with_extrema(&sol.orbit)
}

/// A solved orbit with its $\psi = 0$ interior points added, solved again.
fn with_extrema(solved: &PeriodicOrbit) -> Result<OrbitSolution> {
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-14);
    let with = solved.with_interior_points(&RockingBlock, 1, 0.0, &settings)?;
    let (shooting, newton) = (ShootingSettings::default(), NewtonSettings::default());
    Ok(solve_shooting(&RockingBlock, &with, shooting, &newton)?)
}

/// The symmetric period-1 orbit at `params`: hycont's symmetric-orbit search over one-flight
/// half orbits from the impact surface (48 forcing phases times 9 post-impact velocities,
/// half period $\pi/\omega$), then $\psi = 0$ interior points.
///
/// # Errors
/// [`hycont_core::Error::NewtonFailed`] or `NotPeriodic` if no guess converges.
pub fn symmetric_orbit(params: &Parameters) -> Result<RockingOrbit> {
    params.validate()?;
    let half = Signature::with_closure(
        &RockingBlock,
        vec![SegmentSpec {
            mode: PLUS,
            end: SegmentEnd::Event(IMPACT_PLUS),
        }],
        Closure::Symmetric,
    )?;
    let seeds = (0..48)
        .map(|i| 2.0 * PI * f64::from(i) / 48.0)
        .flat_map(|th| {
            [0.05, 0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 1.3]
                .map(|v| vec![0.0, v, th.sin(), th.cos()])
        })
        .collect();
    let mut search = SymmetricSearch::new(seeds).half_period(PI / params.omega);
    search.max_duration = 2.0 * PI / params.omega;
    let sol = find_symmetric_orbit(&RockingBlock, &half, &params.to_vec(), &search)?;
    Ok(RockingOrbit {
        solution: with_extrema(&sol.full.orbit)?,
        half_multipliers: Some(sol.half_floquet.multipliers),
    })
}

/// An orbit read off a simulation from $(\varphi_0, \psi_0)$ with forcing phase $\beta$, after
/// `periods` forcing periods, refined by Newton.
///
/// # Errors
/// [`hycont_core::Error::NotPeriodic`] if the simulation has not settled on a periodic orbit (or
/// ended: rest, overturn).
pub fn orbit_from_simulation(
    params: &Parameters,
    phi0: f64,
    psi0: f64,
    beta: f64,
    periods: f64,
) -> Result<RockingOrbit> {
    let req = SimulationRequest {
        params: *params,
        phi0,
        psi0,
        beta,
        periods,
        ..SimulationRequest::default()
    };
    let (report, traj) = simulate(&req)?;
    let from = format!("from phi0 = {phi0}, psi0 = {psi0}, beta = {beta}");
    let reason = match report.outcome {
        Outcome::OverturnPos | Outcome::OverturnNeg => {
            format!("the block overturns at t = {:.4} {from}", report.t_end)
        }
        _ if traj.mode_final == crate::REST => {
            format!("the block comes to rest {from} (no rocking orbit to settle on)")
        }
        _ => {
            let guess =
                PeriodicOrbit::from_simulation(&RockingBlock, &traj, &params.to_vec(), 1e-6)?;
            return Ok(RockingOrbit {
                solution: solve_with_extrema(&guess)?,
                half_multipliers: None,
            });
        }
    };
    Err(hycont_core::Error::NotPeriodic { reason }.into())
}

/// Time-average of $\varphi$ over an orbit (its sign tells an asymmetric orbit's leaning side).
///
/// # Errors
/// If the orbit cannot be integrated (never for a solved orbit).
pub fn mean_phi(orbit: &PeriodicOrbit) -> Result<f64> {
    Ok(TimeAverage::new(0).evaluate(&RockingBlock, orbit)?)
}

/// The asymmetric period-1 orbit leaning to the side `positive`: by simulation from a few
/// forcing phases, mirrored by the symmetry if it leans the other way; where no simulation
/// settles on one (it is unstable), by continuation in alpha from a symmetry-breaking branch
/// point of the symmetric orbits ([`hycont_continuation::OrbitRun::symmetry_broken_at`]).
///
/// # Errors
/// Invalid parameters; [`Error::NoOrbit`] (with the simulations' failure) if neither finds one.
pub fn asymmetric_orbit(params: &Parameters, positive: bool) -> Result<RockingOrbit> {
    params.validate()?;
    let (mut last, mut tried) = (None, 0);
    for beta in [FRAC_PI_2, 0.0, PI, 1.0, 2.0, 4.0, 5.0] {
        for phi0 in [0.01, 0.1, -0.1] {
            tried += 1;
            match orbit_from_simulation(params, phi0, 0.0, beta, 300.0) {
                Ok(found) if !found.solution.orbit.is_symmetric(&RockingBlock, 1e-6) => {
                    return leaning(&found.solution.orbit, positive);
                }
                Ok(_) => {}
                Err(e) => last = Some(e),
            }
        }
    }
    let by_simulation = match last {
        Some(e) => format!("none of {tried} simulations settled on one (the last: {e})"),
        None => format!("none of {tried} simulations settled on one"),
    };
    let sym = symmetric_orbit(params)?.solution.orbit;
    let mut run = study_run(Free::Alpha, params, (0.01, 10.0), default_method())?;
    match run.symmetry_broken_at(&sym, params.alpha)? {
        Some((found, _)) => leaning(&found, positive),
        None => Err(Error::NoOrbit(format!(
            "no asymmetric orbit: {by_simulation}; no asymmetric branch from a \
             symmetry-breaking branch point of the symmetric orbits reaches alpha = {}",
            params.alpha
        ))),
    }
}

/// The asymmetric orbit `found`, or its mirror image, leaning to the side `positive`, solved
/// with its extrema.
fn leaning(found: &PeriodicOrbit, positive: bool) -> Result<RockingOrbit> {
    let orbit = if (mean_phi(found)? > 0.0) == positive {
        found.clone()
    } else {
        found.symmetric_image(&RockingBlock)?
    };
    Ok(RockingOrbit {
        solution: solve_with_extrema(&orbit)?,
        half_multipliers: None,
    })
}

/// The orbit of the given kind (for [`OrbitKind::Simulate`], from $\varphi_0 = 0.01$, $\psi_0 = 0$,
/// $\beta = \pi/2$ unless `initial` is given).
///
/// # Errors
/// As the individual constructors.
pub fn orbit(
    params: &Parameters,
    kind: OrbitKind,
    initial: Option<(f64, f64, f64)>,
) -> Result<RockingOrbit> {
    params.validate()?;
    let found = match kind {
        OrbitKind::Symmetric => symmetric_orbit(params),
        OrbitKind::AsymmetricPos => asymmetric_orbit(params, true),
        OrbitKind::AsymmetricNeg => asymmetric_orbit(params, false),
        OrbitKind::Simulate => {
            let (phi0, psi0, beta) = initial.unwrap_or((0.01, 0.0, FRAC_PI_2));
            orbit_from_simulation(params, phi0, psi0, beta, 300.0)
        }
    };
    // Where the search or the solve fails, say for which block and forcing.
    found.map_err(|e| match e {
        crate::Error::Core(
            c @ (hycont_core::Error::NotPeriodic { .. }
            | hycont_core::Error::NewtonFailed { .. }
            | hycont_core::Error::SingularMatrix { .. }
            | hycont_core::Error::StepSizeUnderflow { .. }
            | hycont_core::Error::NonFiniteVectorField { .. }),
        ) => crate::Error::NoOrbit(format!(
            "no {} orbit at omega = {}, alpha = {} (xi = {}, theta_b = {}): {c}",
            kind.name(),
            params.omega,
            params.alpha,
            params.xi,
            params.theta_b
        )),
        other => other,
    })
}

impl RockingOrbit {
    /// The same orbit re-solved by collocation (multipliers from the collocation Jacobian; a
    /// symmetric orbit on its half orbit, [`solve_orbit`]).
    ///
    /// # Errors
    /// If the collocation Newton solve fails.
    pub fn by_collocation(&self, settings: CollocationSettings) -> Result<Self> {
        let method = OrbitMethod::Collocation(settings);
        let newton = NewtonSettings::default();
        let s = solve_orbit(&RockingBlock, &self.solution.orbit, &method, &newton, 1e-8)?;
        Ok(Self {
            half_multipliers: s.half_floquet.map(|f| f.multipliers),
            solution: s.solution,
        })
    }
}
