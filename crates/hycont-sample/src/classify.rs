//! Attractor classification for periodically forced hybrid systems, by their stroboscopic map.
//!
//! A trial (parameters and initial state) is simulated in chunks of forcing periods and stops
//! as soon as it is decided:
//! - **terminal**: a terminal event (e.g. overturning);
//! - **absorbed**: the system says the state can never leave where it is
//!   ([`PeriodicallyForced::absorbed`], e.g. at rest for good);
//! - **periodic with period $k$** ($1 \le k \le$ `max_period`): the strobe samples (the [strobe
//!   components](PeriodicallyForced::strobe_components) at $t = jT$) repeat with period $k$ to
//!   `tol` (max-norm, relative to $1 + |x|$) after at least `min_periods`. Slow convergence (a
//!   multiplier near 1) is accelerated: when the period-1 differences $d_k$ contract
//!   geometrically with ratio $\rho < 1$ and the predicted distance to the limit,
//!   $d_k \rho/(1-\rho)$, is below `extrapolation_tol`, the trial is classified from its current
//!   state; and every `newton_every` periods Newton's method on the stroboscopic map (or its
//!   square), restricted to the strobe components (the forcing's own state is periodic), with
//!   the Jacobian from the variational equations with saltation matrices, looks for the fixed
//!   point; when it converges, is stable and the state is within `newton_radius` of it, the
//!   trial is classified from it;
//! - a period $k \ge 2$ found by repetition is checked against the lower periods $j \mid k$: a
//!   trial still converging to a period-$j$ orbit repeats with period $k$ first when its
//!   multipliers turn the deviation nearly round in $k$ periods (a multiplier near $-1$ flips
//!   it each period, and $x_k - x_{k-2}$ is a fraction $|1+\mu|$ of $x_k - x_{k-1}$); when
//!   Newton's method finds a stable period-$j$ orbit within `newton_radius`, the trial is
//!   classified from it (this check runs with `newton_every = 0` too);
//! - a period-1 orbit is **symmetric** when the system has a symmetry $S$ and the sample half
//!   a period later is the $S$-image of the strobe sample (to `symmetry_tol`);
//! - **undecided** after `max_periods` (chaos, periods above `max_period`, long transients).
//!
//! The strobes are at $t = jT$ from the trial's start: a periodic orbit whose impact falls
//! exactly on a strobe (a start on the impact) alternates between the states before and after
//! it there and looks like period 2; start such trials between impacts.
//!
//! The classification also reports the time average of the strobe components over the last
//! period (e.g. the side an asymmetric orbit leans to) and the modes visited then.

use crate::error::{Error, Result};
use crate::strobe_newton::{Fixed, PERIOD_ONE, refine};
use hycont_core::{
    EventId, FiniteDifferences, HybridJacobians, HybridSystem, Mode, SampleTimes,
    SimulationSettings, Simulator, StopReason,
};
use serde::{Deserialize, Serialize};

/// A hybrid system forced with a period, classified by its stroboscopic map ([`classify`]
/// also needs its derivatives: implement [`HybridJacobians`] or wrap the system in
/// [`FiniteDifferences`], which forwards this trait).
pub trait PeriodicallyForced: HybridSystem {
    /// The forcing period at parameters `p`.
    fn forcing_period(&self, p: &[f64]) -> f64;
    /// The state components compared at the strobes (not the forcing's own state).
    fn strobe_components(&self) -> &[usize];
    /// The mode the state `x` starts in (for the states Newton's method proposes).
    fn mode_at(&self, x: &[f64], p: &[f64]) -> Mode;
    /// Whether the motion can never leave where it is in `mode` at `x` (default: never).
    fn absorbed(&self, mode: Mode, x: &[f64], p: &[f64]) -> bool {
        let _ = (mode, x, p);
        false
    }
}

impl<S: PeriodicallyForced> PeriodicallyForced for FiniteDifferences<S> {
    fn forcing_period(&self, p: &[f64]) -> f64 {
        self.inner().forcing_period(p)
    }
    fn strobe_components(&self) -> &[usize] {
        self.inner().strobe_components()
    }
    fn mode_at(&self, x: &[f64], p: &[f64]) -> Mode {
        self.inner().mode_at(x, p)
    }
    fn absorbed(&self, mode: Mode, x: &[f64], p: &[f64]) -> bool {
        self.inner().absorbed(mode, x, p)
    }
}

/// Settings of [`classify`] (validated; defaults as documented per field).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StrobeSettings {
    /// Periods simulated at most (default 300: on the rocking block's sampling mixes, 0.01 to
    /// 0.06 % of the trials are decided between 300 and 600 periods).
    pub max_periods: usize,
    /// Periods before periodicity is tested (default 10).
    pub min_periods: usize,
    /// Periods per simulation chunk (default 10); the tests for periodicity run after each
    /// chunk. The first chunk is simulated one period at a time, so that a trial absorbed early
    /// (e.g. at rest for good) stops within a period of it.
    pub chunk: usize,
    /// Strobe repetition tolerance (default `1e-6`).
    pub tol: f64,
    /// Predicted distance to the limit accepted by the extrapolation (default `1e-4`).
    pub extrapolation_tol: f64,
    /// Half-period symmetry tolerance (default `1e-3`).
    pub symmetry_tol: f64,
    /// Longest period (in forcing periods) recognised (default 8): the strobe samples of the
    /// last `k` periods repeat those `k` periods before, for the smallest such `k`.
    pub max_period: usize,
    /// Periods between scheduled Newton refinements (default 30; 0 disables them), doubled
    /// after each refinement that fails; a refinement also runs as soon as a geometric
    /// convergence is predicted to end within `newton_radius`. A period above 1 found by
    /// repetition is checked against the lower periods by Newton whatever this is (see the
    /// module's docs).
    pub newton_every: usize,
    /// Largest distance (max-norm in the strobe components) of the state from a stable fixed
    /// point found by Newton for the trial to be classified by it (default 0.05).
    pub newton_radius: f64,
    /// Integration steps allowed per forcing period, on average over each simulated piece
    /// (default 10,000, hundreds of times what a trial takes); a trial that needs more is an error
    /// (`Error::StepBudget`, counted as a failure by the basin runs) rather than a wait.
    pub max_steps_per_period: u64,
    /// Integration tolerances (default `1e-7`, `1e-9`; Newton's refinement converges to ten
    /// times them). Classes are robust to them: on the rocking block's sampling mixes, `1e-9`
    /// changes the class of 0.1 % of the trials (near basin boundaries) at twice the cost.
    pub rtol: f64,
    /// See `rtol`.
    pub atol: f64,
}

impl Default for StrobeSettings {
    fn default() -> Self {
        Self {
            max_periods: 300,
            min_periods: 10,
            chunk: 10,
            tol: 1e-6,
            extrapolation_tol: 1e-4,
            symmetry_tol: 1e-3,
            max_period: 8,
            newton_every: 30,
            newton_radius: 0.05,
            max_steps_per_period: 10_000,
            rtol: 1e-7,
            atol: 1e-9,
        }
    }
}

impl StrobeSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidStudy`] naming the bad setting.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: &str| {
            Err(Error::InvalidStudy {
                reason: format!("invalid classifier setting: {what}"),
            })
        };
        if self.chunk == 0
            || self.max_periods == 0
            || self.max_period == 0
            || self.max_steps_per_period == 0
        {
            return bad("chunk, max_periods, max_period and max_steps_per_period must be >= 1");
        }
        for (name, v) in [
            ("tol", self.tol),
            ("extrapolation_tol", self.extrapolation_tol),
            ("symmetry_tol", self.symmetry_tol),
            ("newton_radius", self.newton_radius),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return bad(&format!("{name} = {v} must be > 0 and finite"));
            }
        }
        Ok(())
    }
}

/// What a trial settled on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Attractor {
    /// A terminal event ended the motion.
    Terminal {
        /// The event.
        event: EventId,
    },
    /// The motion was absorbed ([`PeriodicallyForced::absorbed`]).
    Absorbed,
    /// A periodic orbit of the stroboscopic map.
    Periodic {
        /// Its period in forcing periods (1 to [`StrobeSettings::max_period`]).
        period: usize,
        /// Whether a period-1 orbit is symmetric (its half-period sample is the image of its
        /// strobe sample under the system's symmetry).
        symmetric: bool,
    },
    /// Not decided within `max_periods` (chaos, higher periods).
    Undecided,
}

/// How a trial was decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Decision {
    /// A terminal event.
    Event,
    /// Absorbed.
    Absorbed,
    /// Strobe samples repeated to the tolerance.
    Converged,
    /// Geometric convergence extrapolated.
    Extrapolated,
    /// A Newton refinement of the stroboscopic map found the (stable) orbit.
    Newton,
    /// `max_periods` reached.
    Undecided,
}

/// The result of classifying one trial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Classification {
    /// What the trial settled on.
    pub attractor: Attractor,
    /// How it was decided.
    pub decision: Decision,
    /// Forcing periods simulated.
    pub periods: usize,
    /// Time average (trapezoidal, over the samples of the last period) of each strobe component.
    pub mean: Vec<f64>,
    /// The modes of the samples of the last period (and the sample that begins it).
    pub modes: Vec<Mode>,
    /// Whether jumps accumulated (Zeno) in the last chunk.
    pub zeno: bool,
}

/// Samples per forcing period: the strobe is every 4th, the half period the 2nd (8 cost 4-11 %
/// more on the rocking block's mixes and changed no class of 80,000 trials).
const PER: usize = 4;

pub(crate) fn dist(comps: &[usize], a: &[f64], b: &[f64]) -> f64 {
    comps
        .iter()
        .map(|&c| (a[c] - b[c]).abs())
        .fold(0.0, f64::max)
}

/// The largest deviation of `half` from the symmetry's image of `strobe` in the strobe
/// components (`INFINITY` without a symmetry).
fn asymmetry<S: PeriodicallyForced + HybridJacobians + ?Sized>(
    system: &S,
    strobe: &[f64],
    half: &[f64],
) -> f64 {
    let Some(sym) = system.symmetry() else {
        return f64::INFINITY;
    };
    let mut image = vec![0.0; strobe.len()];
    sym.apply(strobe, &mut image);
    dist(system.strobe_components(), &image, half)
}

/// The running record of a trial: strobe and half-period samples (full states).
struct Record {
    strobe: Vec<Vec<f64>>,
    half: Vec<Vec<f64>>,
    /// The last period's samples (for the averages).
    last_period: Vec<Vec<f64>>,
    /// The modes of the last period's samples and the one before them.
    recent_modes: Vec<Mode>,
    zeno: bool,
    /// No Newton refinement before this period (after one that failed).
    newton_after: usize,
    /// Periods to wait after the next refinement that fails (doubling with each failure).
    newton_wait: usize,
    /// Stable fixed points of the `k`-fold map Newton found farther than `newton_radius`.
    stable_found: Vec<(usize, Fixed)>,
}

impl Record {
    fn mean(&self, comps: &[usize]) -> Vec<f64> {
        comps
            .iter()
            .map(|&c| {
                let v: Vec<f64> = self.last_period.iter().map(|x| x[c]).collect();
                v.iter().sum::<f64>() / v.len().max(1) as f64
            })
            .collect()
    }
    fn modes(&self) -> Vec<Mode> {
        let mut m = self.recent_modes.clone();
        m.sort();
        m.dedup();
        m
    }
    fn finish(
        &self,
        comps: &[usize],
        attractor: Attractor,
        decision: Decision,
        periods: usize,
    ) -> Classification {
        Classification {
            attractor,
            decision,
            periods,
            mean: self.mean(comps),
            modes: self.modes(),
            zeno: self.zeno,
        }
    }
}

/// Classifies the motion of `system` at parameters `p` from state `x0` in `mode` at $t = 0$.
///
/// # Errors
/// Invalid settings, inputs, or an integration failure.
pub fn classify<S: PeriodicallyForced + HybridJacobians + ?Sized>(
    system: &S,
    p: &[f64],
    mode: Mode,
    x0: &[f64],
    settings: &StrobeSettings,
) -> Result<Classification> {
    settings.validate()?;
    let period = system.forcing_period(p);
    if !(period > 0.0 && period.is_finite()) {
        return Err(Error::InvalidStudy {
            reason: format!("forcing period {period} must be > 0 and finite"),
        });
    }
    let comps = system.strobe_components();
    // One simulator per piece length, each with its step budget.
    let simulator = |periods: usize| {
        let budget = settings.max_steps_per_period.saturating_mul(periods as u64);
        Simulator::new(
            SimulationSettings::default()
                .rtol(settings.rtol)
                .atol(settings.atol)
                .record_events(false)
                .max_steps(budget)
                .samples(SampleTimes::new(0.0, period / PER as f64)),
        )
        .map(|sim| (sim, budget))
    };
    let (mut single, mut chunked) = (simulator(1)?, simulator(settings.chunk)?);
    let (mut mode, mut x) = (mode, x0.to_vec());
    let mut rec = Record {
        strobe: Vec::new(),
        half: Vec::new(),
        last_period: Vec::new(),
        recent_modes: Vec::new(),
        zeno: false,
        newton_after: 0,
        newton_wait: settings.newton_every,
        stable_found: Vec::new(),
    };
    let mut periods = 0;
    let mut chunk_zeno = false;
    let mut last: Option<hycont_core::Trajectory> = None;
    while periods < settings.max_periods {
        // The first chunk one period at a time: a trial absorbed early (e.g. at rest for good)
        // stops there rather than at the chunk's end.
        let first = periods < settings.chunk;
        let n = if first { 1 } else { settings.chunk }.min(settings.max_periods - periods);
        let t0 = periods as f64 * period;
        let (sim, budget) = if first { &mut single } else { &mut chunked };
        // Each piece continues the last one with the step size it proposed.
        let t1 = t0 + n as f64 * period;
        let traj = match &last {
            Some(last) => sim.resume(system, last, p, t1)?,
            None => sim.run(system, mode, t0, &x, p, t1)?,
        };
        if let StopReason::TerminalEvent { event, .. } = traj.stop {
            let attractor = Attractor::Terminal { event };
            return Ok(rec.finish(comps, attractor, Decision::Event, periods + n));
        }
        if let StopReason::StepLimit { .. } = traj.stop {
            return Err(Error::StepBudget {
                steps: *budget,
                periods: n,
                t: t0,
            });
        }
        let samples: Vec<(Mode, Vec<f64>)> = traj
            .samples
            .iter()
            .map(|(_, m, s)| (m, s.to_vec()))
            .collect();
        chunk_zeno |= !traj.zeno.is_empty();
        rec.zeno = chunk_zeno;
        rec.recent_modes = samples
            .iter()
            .rev()
            .take(PER + 1)
            .map(|(m, _)| *m)
            .collect();
        rec.last_period = samples
            .iter()
            .rev()
            .take(PER)
            .map(|(_, x)| x.clone())
            .collect();
        if system.absorbed(traj.mode_final, &traj.state_final, p) {
            return Ok(rec.finish(comps, Attractor::Absorbed, Decision::Absorbed, periods + n));
        }
        // Samples: t0 + j T / PER for j = 0 ..= PER n (the first repeats the previous chunk's last).
        for (j, (_, s)) in samples.iter().enumerate() {
            if j == 0 && !rec.strobe.is_empty() {
                continue;
            }
            if j % PER == 0 {
                rec.strobe.push(s.clone());
            } else if j % PER == PER / 2 {
                rec.half.push(s.clone());
            }
        }
        mode = traj.mode_final;
        x.clone_from(&traj.state_final);
        last = Some(traj);
        periods += n;
        if first && periods < settings.chunk.min(settings.max_periods) {
            continue;
        }
        chunk_zeno = false;
        if periods < settings.min_periods || rec.strobe.len() < 4 {
            continue;
        }
        if let Some(c) = decide(system, p, &x, mode, periods, &mut rec, settings)? {
            return Ok(c);
        }
    }
    Ok(rec.finish(comps, Attractor::Undecided, Decision::Undecided, periods))
}

/// The classification of a trial within `newton_radius` of the stable fixed point `f` of the
/// `kk`-fold stroboscopic map: that orbit, with its own modes (not the transient's last
/// chunk).
fn from_fixed<S: PeriodicallyForced + HybridJacobians + ?Sized>(
    system: &S,
    rec: &mut Record,
    kk: usize,
    f: Fixed,
    periods: usize,
    settings: &StrobeSettings,
) -> Classification {
    rec.zeno = false;
    rec.recent_modes = f.modes;
    let symmetric = kk == 1 && asymmetry(system, &f.z, &f.half) <= settings.symmetry_tol;
    let attractor = Attractor::Periodic {
        period: kk,
        symmetric,
    };
    rec.finish(
        system.strobe_components(),
        attractor,
        Decision::Newton,
        periods,
    )
}

/// The tests after a chunk: period-1 convergence or extrapolation, Newton refinement, period 2.
fn decide<S: PeriodicallyForced + HybridJacobians + ?Sized>(
    system: &S,
    p: &[f64],
    x: &[f64],
    mode: Mode,
    periods: usize,
    rec: &mut Record,
    settings: &StrobeSettings,
) -> Result<Option<Classification>> {
    let comps = system.strobe_components();
    let st = &rec.strobe;
    let k = st.len() - 1;
    let d1 = dist(comps, &st[k], &st[k - 1]);
    let diffs: Vec<f64> = (k.saturating_sub(8)..k)
        .map(|i| dist(comps, &st[i + 1], &st[i]))
        .collect();
    let scale = 1.0 + comps.iter().map(|&c| st[k][c].abs()).fold(0.0, f64::max);
    let converged = d1 <= settings.tol * scale;
    // Geometric convergence: ratios of successive differences consistently below 1; the
    // predicted distance to the limit.
    let remaining = (diffs.len() >= 6)
        .then(|| {
            let ratios: Vec<f64> = diffs.windows(2).map(|w| w[1] / w[0]).collect();
            let rho = ratios.iter().copied().fold(0.0, f64::max);
            (rho < 0.999 && ratios.iter().all(|r| *r > 0.0)).then(|| d1 * rho / (1.0 - rho))
        })
        .flatten();
    let extrapolated = !converged && remaining.is_some_and(|r| r <= settings.extrapolation_tol);
    if converged || extrapolated {
        let symmetric = rec
            .half
            .last()
            .is_some_and(|h| asymmetry(system, &st[k], h) <= settings.symmetry_tol + 10.0 * d1);
        let decision = if converged {
            Decision::Converged
        } else {
            Decision::Extrapolated
        };
        let attractor = Attractor::Periodic {
            period: 1,
            symmetric,
        };
        return Ok(Some(rec.finish(comps, attractor, decision, periods)));
    }
    // Newton refinement for slowly converging trials: as soon as a geometric convergence is
    // predicted to end within `newton_radius`, otherwise every `newton_every` periods; after a
    // refinement that fails, not again for `newton_every` periods, doubled with each failure
    // (a chaotic trial's refinements keep finding the unstable orbits inside its attractor).
    let scheduled = periods % settings.newton_every.max(1) < settings.chunk
        && periods >= 2 * settings.min_periods;
    let predicted = remaining.is_some_and(|r| r <= settings.newton_radius);
    // A stable fixed point found earlier, now within `newton_radius`.
    if let Some(i) = rec
        .stable_found
        .iter()
        .position(|(_, f)| dist(comps, x, &f.z) <= settings.newton_radius)
    {
        let (kk, f) = rec.stable_found.swap_remove(i);
        return Ok(Some(from_fixed(system, rec, kk, f, periods, settings)));
    }
    if settings.newton_every > 0 && periods >= rec.newton_after && (scheduled || predicted) {
        rec.newton_after = periods + rec.newton_wait;
        rec.newton_wait = rec.newton_wait.saturating_mul(2);
        for kk in [1usize, 2]
            .into_iter()
            .filter(|kk| *kk <= settings.max_period)
        {
            let Some(f) = refine(system, p, x, mode, kk, settings)? else {
                continue;
            };
            // A fixed point of the squared map that returns after one period is period 1.
            if kk == 2 && dist(comps, &f.one, &f.z) <= PERIOD_ONE {
                continue;
            }
            if f.stable && dist(comps, x, &f.z) <= settings.newton_radius {
                return Ok(Some(from_fixed(system, rec, kk, f, periods, settings)));
            }
            // Stable but not near yet: checked again after every chunk, without a refinement.
            if f.stable && rec.stable_found.len() < 4 {
                rec.stable_found.push((kk, f));
            }
        }
    }
    // Period kk: the last kk samples repeat those kk periods before (the smallest such kk).
    for kk in 2..=settings.max_period {
        if k + 1 < 2 * kk {
            break;
        }
        if (0..kk).all(|i| dist(comps, &st[k - i], &st[k - i - kk]) <= settings.tol * scale) {
            if let Some(c) = lower_period(system, p, x, mode, kk, rec, periods, settings)? {
                return Ok(Some(c));
            }
            let attractor = Attractor::Periodic {
                period: kk,
                symmetric: false,
            };
            return Ok(Some(rec.finish(
                comps,
                attractor,
                Decision::Converged,
                periods,
            )));
        }
    }
    Ok(None)
}

/// The check of a period `kk >= 2` found by repetition: a trial still converging to an orbit of
/// a lower period `j` (a divisor of `kk`) repeats with period `kk` first when its multipliers
/// turn the deviation nearly round in `kk` periods ($\mu^{kk} \approx 1$, e.g. $\mu$ near $-1$
/// for `kk = 2`: the deviation flips each period and $x_k - x_{k-2}$ is a fraction $|1+\mu|$
/// of $x_k - x_{k-1}$). That trial is classified from the lower period's orbit when Newton's
/// method finds it stable and within `newton_radius`, the same test as the refinements' (an
/// orbit of period `kk` near a stable one of period `j` is not an attractor of its own there:
/// past a period doubling the lower period is unstable).
#[allow(clippy::too_many_arguments)]
fn lower_period<S: PeriodicallyForced + HybridJacobians + ?Sized>(
    system: &S,
    p: &[f64],
    x: &[f64],
    mode: Mode,
    kk: usize,
    rec: &mut Record,
    periods: usize,
    settings: &StrobeSettings,
) -> Result<Option<Classification>> {
    let comps = system.strobe_components();
    for j in (1..kk).filter(|j| kk.is_multiple_of(*j)) {
        let Some(f) = refine(system, p, x, mode, j, settings)? else {
            continue;
        };
        if f.stable && dist(comps, x, &f.z) <= settings.newton_radius {
            // Of period j exactly: a period-j fixed point that returns after one period was
            // found as j = 1 already.
            if j > 1 && dist(comps, &f.one, &f.z) <= PERIOD_ONE {
                continue;
            }
            return Ok(Some(from_fixed(system, rec, j, f, periods, settings)));
        }
    }
    Ok(None)
}
