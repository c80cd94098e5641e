//! Simulating the rocking block from an initial condition, and summarising the outcome.

use crate::error::Result;
use crate::model::{
    IMPACT_MINUS, IMPACT_PLUS, OVERTURN_NEG, OVERTURN_POS, Parameters, REST, RockingBlock,
    initial_mode, initial_state,
};
use hycont_core::{
    Error as CoreError, HybridSystem, SampleTimes, SimulationSettings, SimulationStats, Simulator,
    StopReason, Trajectory,
};
use serde::{Deserialize, Serialize};

/// How a simulation ended, physically.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Still moving at the end time (possibly with rest phases, if lift-off is possible).
    Running,
    /// At rest at the end time, and lift-off is impossible ($\alpha\omega^2\tan\theta_b \le 1$):
    /// rest is absorbing.
    Rest,
    /// Overturned to the right ($\varphi = \pi/2$).
    OverturnPos,
    /// Overturned to the left ($\varphi = -\pi/2$).
    OverturnNeg,
}

impl Outcome {
    /// What the outcome means, in words (for the command line's output).
    ///
    /// ```
    /// use rocking_block::simulation::Outcome;
    /// assert!(Outcome::Running.describe().contains("still moving"));
    /// ```
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Outcome::Running => {
                "still moving at the end time: neither overturned nor at rest for good (simulate longer to see where it settles)"
            }
            Outcome::Rest => {
                "at rest for good: lift-off is impossible (alpha omega^2 tan(theta_b) <= 1)"
            }
            Outcome::OverturnPos => "overturned to the right (phi = pi/2)",
            Outcome::OverturnNeg => "overturned to the left (phi = -pi/2)",
        }
    }
}

/// What to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimulationRequest {
    /// Model parameters.
    pub params: Parameters,
    /// Initial angle $\varphi_0$.
    pub phi0: f64,
    /// Initial angular velocity $\psi_0$.
    pub psi0: f64,
    /// Forcing phase $\beta$: $(r_0, s_0) = (\sin\beta, \cos\beta)$.
    pub beta: f64,
    /// Explicit forcing-oscillator state $(r_0, s_0)$, overriding `beta` (e.g. to start from a
    /// state printed in the study).
    pub forcing_state: Option<[f64; 2]>,
    /// Duration in forcing periods $2\pi/\omega$.
    pub periods: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Dense samples per forcing period kept for plots and `max_abs_phi` (0: stroboscopic only).
    pub points_per_period: usize,
}

impl Default for SimulationRequest {
    /// The study's start point $(\omega, \alpha) = (1.3, 0.66)$ from
    /// $\varphi_0 = 0.01, \psi_0 = 0, \beta = 0$, 100 periods, `rtol = 1e-10`, `atol = 1e-12`.
    fn default() -> Self {
        Self {
            params: Parameters::default(),
            phi0: 0.01,
            psi0: 0.0,
            beta: 0.0,
            forcing_state: None,
            periods: 100.0,
            rtol: 1e-10,
            atol: 1e-12,
            points_per_period: 0,
        }
    }
}

/// Summary of a simulation (the `simulate --json` output).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimulationReport {
    /// Physical outcome.
    pub outcome: Outcome,
    /// Parameters used.
    pub parameters: Parameters,
    /// Initial condition $(\varphi_0, \psi_0, r_0, s_0)$.
    pub initial_state: [f64; 4],
    /// Final time.
    pub t_end: f64,
    /// Number of impacts.
    pub impacts: u64,
    /// Final state $(\varphi, \psi, r, s)$.
    pub final_state: Vec<f64>,
    /// Final mode: `"+"`, `"-"` or `"rest"`.
    pub final_mode: String,
    /// Times at which chattering impacts accumulated and the block came to rest.
    pub rest_times: Vec<f64>,
    /// Stroboscopic samples $(\varphi, \psi)$ at $t = 2\pi k/\omega$.
    pub strobe: Vec<[f64; 2]>,
    /// Largest $|\varphi|$ seen (over the dense samples and the events; only with dense samples).
    pub max_abs_phi: Option<f64>,
    /// Work counters.
    pub stats: SimulationStats,
}

/// The most integration steps a simulation takes (the library's default): one that needs more
/// is an error ([`crate::Error::StepLimit`]), not a trajectory cut short.
pub const MAX_STEPS: u64 = 50_000_000;

/// Simulates the block and returns the report and the full trajectory.
///
/// # Errors
/// Invalid parameters or tolerances, non-finite initial conditions, an integration failure
/// (a stall included, [`hycont_core::Error::Stalled`]), or more than [`MAX_STEPS`] steps
/// ([`crate::Error::StepLimit`]).
///
/// ```
/// use rocking_block::{simulate, Outcome, Parameters, SimulationRequest};
/// // Forcing too weak to lift the block: it stays at rest.
/// let req = SimulationRequest { params: Parameters::new(1.3, 0.3), phi0: 0.0, periods: 5.0,
///                               ..SimulationRequest::default() };
/// let (report, _) = simulate(&req).unwrap();
/// assert_eq!(report.outcome, Outcome::Rest);
/// assert_eq!(report.impacts, 0);
/// ```
pub fn simulate(req: &SimulationRequest) -> Result<(SimulationReport, Trajectory)> {
    req.params.validate()?;
    let [r0, s0] = req
        .forcing_state
        .unwrap_or([req.beta.sin(), req.beta.cos()]);
    check_start(req.phi0, req.psi0, req.beta)?;
    for (name, value) in [("r0", r0), ("s0", s0)] {
        if !value.is_finite() {
            return Err(CoreError::NonFinite {
                what: name,
                index: 0,
                value,
            }
            .into());
        }
    }
    let radius = r0.hypot(s0);
    if !(radius > 0.0 && radius <= 2.0) {
        return Err(crate::Error::InvalidArgument {
            name: "r0/s0",
            value: format!("({r0:?}, {s0:?})"),
            reason: "the forcing oscillator's state must be on or near its unit circle (0 < r0^2 + s0^2 <= 4)",
        });
    }
    if !(req.periods >= 0.0 && req.periods.is_finite()) {
        return Err(crate::Error::InvalidArgument {
            name: "periods",
            value: format!("{:?}", req.periods),
            reason: "must be >= 0 and finite",
        });
    }
    check_samples(req.periods, req.points_per_period.max(1))?;
    let tolerances = [
        (
            "rtol",
            req.rtol,
            1e-14,
            "must be in [1e-14, 1e-2] (met by the integrator, and a trajectory worth the name)",
        ),
        (
            "atol",
            req.atol,
            1e-20,
            "must be in [1e-20, 1e-2] (met by the integrator, and a trajectory worth the name)",
        ),
    ];
    for (name, value, lo, reason) in tolerances {
        if !(value >= lo && value <= 1e-2) {
            return Err(crate::Error::InvalidArgument {
                name,
                value: format!("{value:?}"),
                reason,
            });
        }
    }
    let period = req.params.forcing_period();
    let per = req.points_per_period.max(1);
    let settings = SimulationSettings::default()
        .rtol(req.rtol)
        .atol(req.atol)
        .max_steps(MAX_STEPS)
        .samples(SampleTimes::new(0.0, period / per as f64));
    let mut sim = Simulator::new(settings)?;
    let mut x0 = initial_state(req.phi0, req.psi0, req.beta);
    x0[2] = r0;
    x0[3] = s0;
    let mode = initial_mode(&x0, &req.params);
    let p = req.params.to_vec();
    let t_end = req.periods * period;
    let traj = sim.run(&RockingBlock, mode, 0.0, &x0, &p, t_end)?;
    if let StopReason::StepLimit { t } = traj.stop {
        return Err(crate::Error::StepLimit {
            t,
            t_end,
            steps: MAX_STEPS,
        });
    }

    let outcome = match traj.stop {
        StopReason::TerminalEvent { event, .. } if event == OVERTURN_POS => Outcome::OverturnPos,
        StopReason::TerminalEvent { event, .. } if event == OVERTURN_NEG => Outcome::OverturnNeg,
        _ if traj.mode_final == REST && !req.params.lift_off_possible() => Outcome::Rest,
        _ => Outcome::Running,
    };
    let impacts = traj
        .events
        .iter()
        .filter(|e| e.event == IMPACT_PLUS || e.event == IMPACT_MINUS)
        .count() as u64;
    let strobe = traj
        .samples
        .iter()
        .enumerate()
        .filter(|(i, _)| i % per == 0)
        .map(|(_, (_, _, x))| [x[0], x[1]])
        .collect();
    let max_abs_phi = (req.points_per_period > 0).then(|| {
        let dense = traj.samples.iter().map(|(_, _, x)| x[0].abs());
        let events = traj.events.iter().map(|e| e.state_before[0].abs());
        dense
            .chain(events)
            .chain(std::iter::once(traj.state_final[0].abs()))
            .fold(0.0, f64::max)
    });
    let report = SimulationReport {
        outcome,
        parameters: req.params,
        initial_state: x0,
        t_end: traj.t_final,
        impacts,
        final_state: traj.state_final.clone(),
        final_mode: RockingBlock.mode_name(traj.mode_final).to_string(),
        rest_times: traj.zeno.iter().map(|z| z.t_accumulation).collect(),
        strobe,
        max_abs_phi,
        stats: traj.stats,
    };
    Ok((report, traj))
}

/// Checks an initial condition: finite $\varphi_0$, $\psi_0$, $\beta$ and the block standing on
/// its base, $|\varphi_0| < \pi/2$ (at $|\varphi_0| \ge \pi/2$ it has overturned: the model's
/// modes do not describe it).
///
/// # Errors
/// [`hycont_core::Error::NonFinite`] naming a non-finite value, or
/// [`crate::Error::InvalidArgument`] for $|\varphi_0| \ge \pi/2$.
///
/// ```
/// use rocking_block::simulation::check_start;
/// assert!(check_start(0.1, 0.0, 0.0).is_ok());
/// assert!(check_start(1.6, 0.0, 0.0).is_err());
/// assert!(check_start(f64::NAN, 0.0, 0.0).is_err());
/// ```
pub fn check_start(phi0: f64, psi0: f64, beta: f64) -> Result<()> {
    for (name, value) in [("phi0", phi0), ("psi0", psi0), ("beta", beta)] {
        if !value.is_finite() {
            return Err(CoreError::NonFinite {
                what: name,
                index: 0,
                value,
            }
            .into());
        }
    }
    if psi0.abs() > 1e6 {
        return Err(crate::Error::InvalidArgument {
            name: "psi0",
            value: format!("{psi0:?}"),
            reason: "must satisfy |psi0| <= 1e6 (faster, the block overturns within a step the integrator can take)",
        });
    }
    if phi0.abs() >= std::f64::consts::FRAC_PI_2 {
        return Err(crate::Error::InvalidArgument {
            name: "phi0",
            value: format!("{phi0:?}"),
            reason: "must satisfy |phi0| < pi/2 (at |phi0| >= pi/2 the block has overturned)",
        });
    }
    Ok(())
}

/// Bytes a dense sample takes (the stored state, and its CSV line when written).
const BYTES_PER_SAMPLE: f64 = 200.0;

/// The memory a run may use for its samples: half of what the system reports available
/// (`MemAvailable` in `/proc/meminfo`), or 2 GiB where that is unknown.
fn sample_memory() -> f64 {
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find_map(|l| l.strip_prefix("MemAvailable:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
                .map(|kb| kb * 1024.0)
        });
    available.map_or(2.0 * 1024f64.powi(3), |b| 0.5 * b)
}

/// Refuses dense sampling that would not fit in memory.
fn check_samples(periods: f64, points_per_period: usize) -> Result<()> {
    let samples = periods.ceil() * points_per_period as f64;
    let budget = sample_memory();
    if samples * BYTES_PER_SAMPLE > budget {
        return Err(crate::Error::InvalidArgument {
            name: "points-per-period",
            value: format!("{points_per_period} (x {periods} periods = {samples:e} samples)"),
            reason: "the samples would not fit in memory: ask for fewer points per period or periods",
        });
    }
    Ok(())
}
