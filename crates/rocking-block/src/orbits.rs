//! Periodic orbits of the rocking block: the symmetric orbit, the asymmetric pair, orbits read
//! off simulations; exact amplitude and grazing measure; reports in the study's JSON format.

use crate::error::Result;
use crate::model::{
    IMPACT_PLUS, MINUS, PLUS, Parameters, RockingBlock, initial_mode, initial_state,
};
use hycont_core::orbit::{
    Closure, CollocationSettings, OrbitSolution, PeriodicOrbit, SegmentEnd, SegmentSpec,
    ShootingSettings, Signature, SymmetricSolution, solve_collocation, solve_shooting,
    solve_symmetric_collocation, solve_symmetric_shooting,
};
use hycont_core::problem::NewtonSettings;
use hycont_core::{
    EventAction, EventId, EventSpec, HybridSystem, Mode, SimulationSettings, Simulator, StopReason,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// Index of $\psi$ in the state: interior points $\psi = 0$ are the extrema of $\varphi$.
const PSI: usize = 1;

/// How to discretise the orbit's boundary-value problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Method {
    /// Multiple shooting on the simulator's variational equations.
    Shooting,
    /// Orthogonal collocation with the given settings.
    Collocation(CollocationSettings),
}

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

/// A computed orbit with its measures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RockingOrbit {
    /// The solution: orbit with $\psi = 0$ interior points, multipliers, Newton history.
    pub solution: OrbitSolution,
    /// For symmetric orbits: the half map's multipliers $\mu$ ($\mu^2 = \lambda$).
    pub half_multipliers: Option<Vec<(f64, f64)>>,
}

/// One flight of an orbit in a report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentReport {
    /// `"+"` or `"-"`.
    pub mode: String,
    /// Duration of the flight (impact to impact).
    pub duration: f64,
    /// State right after the impact that starts it.
    pub start: Vec<f64>,
}

/// An orbit in the study's JSON format (`orbits` entries of `fig2.json`, `orbit --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrbitReport {
    /// Name (`symmetric`, `asymmetric-pos`, ...).
    pub name: String,
    /// Forcing frequency.
    pub omega: f64,
    /// Forcing amplitude.
    pub alpha: f64,
    /// $\max |\varphi|$ over the orbit (the exact extremum).
    pub amp: f64,
    /// Period.
    pub period: f64,
    /// Whether all non-trivial multipliers are inside the unit circle.
    pub stable: bool,
    /// All Floquet multipliers `[re, im]`.
    pub multipliers: Vec<[f64; 2]>,
    /// Which multipliers are trivial (the forcing oscillator's 1 and $e^{-2T}$).
    pub trivial: Vec<bool>,
    /// Whether the orbit is $\mathbb{Z}_2$-symmetric.
    pub symmetric: bool,
    /// Half-map multipliers of a symmetric orbit.
    pub half_multipliers: Option<Vec<[f64; 2]>>,
    /// Smallest $|\varphi|$ at an interior extremum turning back from the impact surface (a
    /// grazing measure: 0 at grazing), if the orbit has such an extremum.
    pub grazing: Option<f64>,
    /// Flights, impact to impact.
    pub segments: Vec<SegmentReport>,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Final residual.
    pub residual: f64,
}

fn newton_settings() -> NewtonSettings {
    NewtonSettings::default()
}

fn sim_settings() -> SimulationSettings {
    SimulationSettings::default().rtol(1e-12).atol(1e-14)
}

/// Exact $\max|\varphi|$: the largest $|\varphi|$ at the $\psi = 0$ interior points (impact points
/// have $\varphi = 0$).
#[must_use]
pub fn amplitude(orbit: &PeriodicOrbit) -> f64 {
    orbit.starts.iter().map(|x| x[0].abs()).fold(0.0, f64::max)
}

/// The grazing measure: the smallest $|\varphi|$ at an interior extremum where $|\varphi|$ has a
/// local minimum (the flight turns back before reaching the impact surface), among the
/// orbit's interior points.
#[must_use]
pub fn grazing_measure(orbit: &PeriodicOrbit) -> Option<f64> {
    turn_backs(orbit)
        .map(|(_, phi)| phi.abs())
        .min_by(f64::total_cmp)
}

/// Interior points of a flight where $s\varphi$ has a local minimum ($s = \pm 1$ the sign of
/// the mode: the flight turns back towards its impact surface), with $s$ and $\varphi$ there.
fn turn_backs(orbit: &PeriodicOrbit) -> impl Iterator<Item = (f64, f64)> + '_ {
    let segs = orbit.signature.segments();
    let k = segs.len();
    (0..k)
        .filter(move |&i| matches!(segs[(i + k - 1) % k].end, SegmentEnd::Interior { .. }))
        .filter_map(move |i| {
            let sign = match segs[i].mode {
                PLUS => 1.0,
                MINUS => -1.0,
                _ => return None,
            };
            let x = &orbit.starts[i];
            let mut f = [0.0; 4];
            RockingBlock.vector_field(segs[i].mode, x, &orbit.params, &mut f);
            // s phi has a local minimum where psi = 0 and s psi' > 0.
            (sign * f[PSI] > 0.0).then_some((sign, x[0]))
        })
}

/// The signed grazing margin $g$ of an orbit: the smallest $s\varphi$ over the points where a
/// flight turns back towards its impact surface ($\psi = 0$, $s\psi' > 0$, $s = \pm 1$ the
/// sign of the flight's mode), including turning points that are not in the orbit's signature
/// (found by integrating every segment), capped at $\pi/2$ (the value when no flight turns
/// back). $g$ reaches $0$ where such an interior dip grazes the impact surface, and is negative
/// past it, where $\varphi$ changes sign inside a flight (the orbit is not admissible).
///
/// This is the test function of the interior-dip grazing event; grazing by a flight collapsing
/// to zero duration is the continuation's built-in segment-collapse event.
#[must_use]
pub fn grazing_margin(orbit: &PeriodicOrbit) -> f64 {
    let settings = SimulationSettings::default().rtol(1e-10).atol(1e-12);
    // The orbit was just computed from these segments, so integrating them again does not fail
    // in practice; if it does, the signature's own turning points still give a bound.
    let split = orbit.with_interior_points(&RockingBlock, PSI, 0.0, &settings);
    let margin = |o: &PeriodicOrbit| {
        turn_backs(o)
            .map(|(sign, phi)| sign * phi)
            .fold(FRAC_PI_2, f64::min)
    };
    split.as_ref().map_or_else(|_| margin(orbit), margin)
}

/// Adds $\psi = 0$ interior points and re-solves, so that the amplitude is exact.
fn refine_with_extrema(
    solution: &OrbitSolution,
    shooting: ShootingSettings,
) -> Result<OrbitSolution> {
    let with = solution
        .orbit
        .with_interior_points(&RockingBlock, PSI, 0.0, &sim_settings())?;
    Ok(solve_shooting(
        &RockingBlock,
        &with,
        shooting,
        &newton_settings(),
    )?)
}

/// The block with every event terminal: a run stops at its first event (the scan for
/// symmetric orbits looks at the first impact only).
struct UntilFirstEvent;

impl HybridSystem for UntilFirstEvent {
    fn state_dim(&self) -> usize {
        RockingBlock.state_dim()
    }
    fn parameter_names(&self) -> &[&'static str] {
        RockingBlock.parameter_names()
    }
    fn mode_count(&self) -> usize {
        RockingBlock.mode_count()
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        RockingBlock.mode_name(mode)
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        RockingBlock.events(mode)
    }
    fn event_spec(&self, event: EventId) -> EventSpec {
        EventSpec {
            action: EventAction::Terminal,
            ..RockingBlock.event_spec(event)
        }
    }
    #[inline]
    fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        RockingBlock.vector_field(mode, x, p, out);
    }
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        RockingBlock.event(event, x, p)
    }
}

/// The symmetric period-1 orbit at `params`: a scan over the forcing phase and post-impact
/// velocity of a one-flight half orbit, then Newton on the half-orbit problem
/// ($x_1 = S x_0$), then $\psi = 0$ interior points for the exact amplitude.
///
/// # Errors
/// [`crate::Error::Core`] with [`hycont_core::Error::NewtonFailed`] if no scanned guess converges.
pub fn symmetric_orbit(params: &Parameters) -> Result<RockingOrbit> {
    params.validate()?;
    let p = params.to_vec();
    let half_period = PI / params.omega;
    let signature = Signature::with_closure(
        &RockingBlock,
        vec![SegmentSpec {
            mode: PLUS,
            end: SegmentEnd::Event(IMPACT_PLUS),
        }],
        Closure::Symmetric,
    )?;
    // Rank guesses by how nearly one flight closes symmetrically in half a period.
    let mut candidates = Vec::new();
    let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-6).atol(1e-8))?;
    for i in 0..48 {
        let theta = 2.0 * PI * f64::from(i) / 48.0;
        for psi0 in [0.05, 0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 1.3] {
            let x0 = [0.0, psi0, theta.sin(), theta.cos()];
            let traj = sim.run(&UntilFirstEvent, PLUS, 0.0, &x0, &p, 2.0 * half_period)?;
            let StopReason::TerminalEvent { event, t } = traj.stop else {
                continue;
            };
            if event != IMPACT_PLUS {
                continue;
            }
            let mut y = [0.0; 4];
            RockingBlock.reset(event, &traj.state_final, &p, &mut y);
            let miss = (t - half_period).abs() / half_period
                + (0..4).map(|j| (y[j] + x0[j]).abs()).sum::<f64>();
            candidates.push((miss, x0, t));
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let shooting = ShootingSettings::default();
    let mut last_err = None;
    for (_, x0, t) in candidates.into_iter().take(12) {
        let guess = PeriodicOrbit::new(
            &RockingBlock,
            signature.clone(),
            vec![x0.to_vec()],
            vec![t],
            p.clone(),
        )?;
        match solve_symmetric_shooting(&RockingBlock, &guess, shooting, &newton_settings()) {
            Ok(sol) if (sol.half.period() - half_period).abs() < 1e-6 * half_period => {
                return finish_symmetric(&sol, shooting);
            }
            Ok(_) => {}
            Err(e) => last_err = Some(e),
        }
    }
    Err(last_err
        .unwrap_or_else(|| hycont_core::Error::NotPeriodic {
            reason: format!(
                "no symmetric period-1 orbit found at omega = {}, alpha = {}",
                params.omega, params.alpha
            ),
        })
        .into())
}

fn finish_symmetric(sol: &SymmetricSolution, shooting: ShootingSettings) -> Result<RockingOrbit> {
    let refined = refine_with_extrema(&sol.full, shooting)?;
    Ok(RockingOrbit {
        solution: refined,
        half_multipliers: Some(sol.half_floquet.multipliers.clone()),
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
    params.validate()?;
    let p = params.to_vec();
    let x0 = initial_state(phi0, psi0, beta);
    let mut sim = Simulator::new(SimulationSettings::default())?;
    let traj = sim.run(
        &RockingBlock,
        initial_mode(&x0, params),
        0.0,
        &x0,
        &p,
        periods * params.forcing_period(),
    )?;
    let from = format!("from phi0 = {phi0}, psi0 = {psi0}, beta = {beta}");
    let reason = match traj.stop {
        StopReason::TerminalEvent { event, t }
            if event == crate::OVERTURN_NEG || event == crate::OVERTURN_POS =>
        {
            Some(format!("the block overturns at t = {t:.4} {from}"))
        }
        StopReason::EndReached if traj.mode_final == crate::REST && !traj.zeno.is_empty() => Some(
            format!("the block comes to rest {from} (no rocking orbit to settle on)"),
        ),
        StopReason::EndReached => None,
        other => Some(format!(
            "the simulation {from} ended with {other:?} in mode {}",
            RockingBlock.mode_name(traj.mode_final)
        )),
    };
    if let Some(reason) = reason {
        return Err(hycont_core::Error::NotPeriodic { reason }.into());
    }
    let guess = PeriodicOrbit::from_simulation(&RockingBlock, &traj, &p, 1e-6)?;
    solve_with_extrema(&guess)
}

/// The orbit near `guess` (with or without interior points) solved by shooting, with every
/// $\psi = 0$ interior point, so that the amplitude is exact.
pub(crate) fn solve_with_extrema(guess: &PeriodicOrbit) -> Result<RockingOrbit> {
    let guess = guess.without_interior_points(&RockingBlock)?;
    let shooting = ShootingSettings::default();
    let sol = solve_shooting(&RockingBlock, &guess, shooting, &newton_settings())?;
    let refined = refine_with_extrema(&sol, shooting)?;
    Ok(RockingOrbit {
        solution: refined,
        half_multipliers: None,
    })
}

/// Time-average of $\varphi$ over an orbit (sign tells the leaning side of an asymmetric orbit).
///
/// # Errors
/// If sampling the orbit fails (never for a solved orbit).
pub fn mean_phi(orbit: &PeriodicOrbit) -> Result<f64> {
    let series = orbit.sample(&RockingBlock, 64, &sim_settings())?;
    let mut acc = 0.0;
    for s in &series {
        for w in
            s.t.windows(2)
                .zip(s.x.chunks(4).collect::<Vec<_>>().windows(2))
        {
            let ((t0, t1), (a, b)) = ((w.0[0], w.0[1]), (w.1[0], w.1[1]));
            acc += 0.5 * (a[0] + b[0]) * (t1 - t0);
        }
    }
    Ok(acc / orbit.period())
}

/// The asymmetric period-1 orbit leaning to the side `positive`: found by simulation from a few
/// forcing phases, and mapped by the symmetry if it leans the other way; where no simulation
/// settles on one (it is unstable), by continuation from a symmetry-breaking branch point of the
/// symmetric orbits ([`crate::continuation::asymmetric_by_continuation`]).
///
/// # Errors
/// Invalid parameters; [`crate::Error::Continuation`] (with the simulations' failure) if neither
/// finds one.
pub fn asymmetric_orbit(params: &Parameters, positive: bool) -> Result<RockingOrbit> {
    params.validate()?;
    let by_simulation = match asymmetric_by_simulation(params, positive) {
        Ok(found) => return Ok(found),
        Err(e) => e,
    };
    crate::continuation::asymmetric_by_continuation(params, positive).map_err(|e| {
        crate::Error::Continuation(format!(
            "no asymmetric orbit: by simulation, {by_simulation}; by {e}"
        ))
    })
}

/// [`asymmetric_orbit`] by simulation only.
fn asymmetric_by_simulation(params: &Parameters, positive: bool) -> Result<RockingOrbit> {
    let (mut last, mut tried, mut symmetric) = (None, 0, 0);
    for beta in [FRAC_PI_2, 0.0, PI, 1.0, 2.0, 4.0, 5.0] {
        for phi0 in [0.01, 0.1, -0.1] {
            match orbit_from_simulation(params, phi0, 0.0, beta, 300.0) {
                Ok(found) if !found.solution.orbit.is_symmetric(&RockingBlock, 1e-6) => {
                    let lean = mean_phi(&found.solution.orbit)?;
                    if (lean > 0.0) == positive {
                        return Ok(found);
                    }
                    let image = found.solution.orbit.symmetric_image(&RockingBlock)?;
                    let sol = solve_shooting(
                        &RockingBlock,
                        &image,
                        ShootingSettings::default(),
                        &newton_settings(),
                    )?;
                    return Ok(RockingOrbit {
                        solution: sol,
                        half_multipliers: None,
                    });
                }
                Ok(_) => symmetric += 1,
                Err(e) => last = Some(e),
            }
            tried += 1;
        }
    }
    let last = last.map_or_else(String::new, |e| format!("; the last failure: {e}"));
    Err(hycont_core::Error::NotPeriodic {
        reason: format!(
            "none of {tried} simulations settled on an asymmetric orbit ({symmetric} on the \
             symmetric one{last})"
        ),
    }
    .into())
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
    match kind {
        OrbitKind::Symmetric => symmetric_orbit(params),
        OrbitKind::AsymmetricPos => asymmetric_orbit(params, true),
        OrbitKind::AsymmetricNeg => asymmetric_orbit(params, false),
        OrbitKind::Simulate => {
            let (phi0, psi0, beta) = initial.unwrap_or((0.01, 0.0, FRAC_PI_2));
            orbit_from_simulation(params, phi0, psi0, beta, 300.0)
        }
    }
}

impl RockingOrbit {
    /// The same orbit re-solved by collocation (multipliers from the collocation Jacobian; for a
    /// symmetric orbit the half-orbit problem is solved by collocation too).
    ///
    /// # Errors
    /// If the collocation Newton solve fails.
    pub fn by_collocation(&self, settings: CollocationSettings) -> Result<Self> {
        let orbit = &self.solution.orbit;
        if self.half_multipliers.is_some() {
            let half = orbit.half_of_symmetric(&RockingBlock, 1e-8)?;
            let sol =
                solve_symmetric_collocation(&RockingBlock, &half, settings, &newton_settings())?;
            return Ok(Self {
                solution: sol.full,
                half_multipliers: Some(sol.half_floquet.multipliers),
            });
        }
        let sol = solve_collocation(&RockingBlock, orbit, settings, &newton_settings())?;
        Ok(Self {
            solution: sol.solution,
            half_multipliers: None,
        })
    }

    /// The report of this orbit under `name`.
    ///
    /// # Errors
    /// If merging the interior points fails (never for a valid orbit).
    pub fn report(&self, name: &str) -> Result<OrbitReport> {
        let orbit = &self.solution.orbit;
        let flights = orbit.without_interior_points(&RockingBlock)?;
        let fl = &self.solution.floquet;
        Ok(OrbitReport {
            name: name.to_string(),
            omega: orbit.params[0],
            alpha: orbit.params[1],
            amp: amplitude(orbit),
            period: orbit.period(),
            stable: fl.stable(),
            multipliers: fl.multipliers.iter().map(|&(a, b)| [a, b]).collect(),
            trivial: fl.trivial.clone(),
            symmetric: orbit.is_symmetric(&RockingBlock, 1e-6),
            half_multipliers: self
                .half_multipliers
                .as_ref()
                .map(|m| m.iter().map(|&(a, b)| [a, b]).collect()),
            grazing: grazing_measure(orbit),
            segments: flights
                .signature
                .segments()
                .iter()
                .zip(&flights.durations)
                .zip(&flights.starts)
                .map(|((s, d), x)| SegmentReport {
                    mode: RockingBlock.mode_name(s.mode).to_string(),
                    duration: *d,
                    start: x.clone(),
                })
                .collect(),
            newton_iterations: self.solution.newton.len(),
            residual: self.solution.residual,
        })
    }
}
