//! The rocking block's solution classifier (the study's basin-stability classes).
//!
//! A trial (forcing, phase and initial condition) is simulated in chunks of forcing periods and
//! stops as soon as its class is decided:
//! - **overturn_pos / overturn_neg**: the terminal overturn event ($|\varphi| = \pi/2$);
//! - **equilibrium**: the block is at rest (after chattering impacts accumulated) and can never
//!   lift off again ($\alpha\omega^2\tan\theta_b \le 1$), or it never left rest;
//! - **period 1 / period 2**: the stroboscopic samples $(\varphi, \psi)$ at $t = 2\pi k/\omega$
//!   repeat with period 1 or 2 to `tol` (max-norm), after at least `min_periods`. Slow
//!   convergence (a multiplier near 1, e.g. near BP1/BP2) is accelerated: when the period-1
//!   differences $d_k$ contract geometrically with ratio $\rho < 1$ and the predicted distance to
//!   the limit, $d_k \rho / (1 - \rho)$, is below `extrapolation_tol`, the orbit is classified
//!   from the current state; and every `newton_every` periods a Newton refinement on the
//!   stroboscopic map (restricted to $(\varphi, \psi)$ at the fixed forcing phase, Jacobian from
//!   the simulator's variational equations with saltation matrices) looks for the fixed point
//!   of the map (or of its square); when it converges, is stable, and the current state is within
//!   `newton_radius` of it, the orbit is classified from the fixed point;
//! - a period-1 orbit is **symmetric_p1** when the half-period sample is the $S$-image of the
//!   strobe sample ($x(t + T/2) = -x(t)$ to `symmetry_tol`), otherwise **asymmetric_p1_pos** or
//!   **asymmetric_p1_neg** by the sign of the mean of $\varphi$ over a period;
//! - **other**: not decided within `max_periods` (chaos, higher periods).
//!
//! Orbits that include rest (sticking) phases are classified by their periodicity and symmetry
//! like any other, and flagged `with_rest` (reported separately by the figures): at
//! $\alpha = 0.66$ true rest is absorbing only for $\omega < 1.1197$, so the study's
//! "equilibrium" at $\omega = 1.16$ is such rocking with rest phases.

use crate::error::Result;
use crate::model::{OVERTURN_POS, Parameters, REST, RockingBlock, initial_mode, initial_state};
use hycont_core::{SampleTimes, SimulationSettings, Simulator, StopReason};
use serde::{Deserialize, Serialize};

/// The study's solution classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// At rest for good.
    Equilibrium,
    /// Symmetric period-1 rocking.
    SymmetricP1,
    /// Asymmetric period-1 rocking leaning to $\varphi > 0$.
    AsymmetricP1Pos,
    /// Asymmetric period-1 rocking leaning to $\varphi < 0$.
    AsymmetricP1Neg,
    /// Period-2 rocking.
    Period2,
    /// Anything else (higher period, chaos, undecided).
    Other,
    /// Overturned to $\varphi = \pi/2$.
    OverturnPos,
    /// Overturned to $\varphi = -\pi/2$.
    OverturnNeg,
}

impl Class {
    /// All classes, in a fixed order (the index used in count tables).
    pub const ALL: [Class; 8] = [
        Class::Equilibrium,
        Class::SymmetricP1,
        Class::AsymmetricP1Pos,
        Class::AsymmetricP1Neg,
        Class::Period2,
        Class::Other,
        Class::OverturnPos,
        Class::OverturnNeg,
    ];

    /// The snake-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Class::Equilibrium => "equilibrium",
            Class::SymmetricP1 => "symmetric_p1",
            Class::AsymmetricP1Pos => "asymmetric_p1_pos",
            Class::AsymmetricP1Neg => "asymmetric_p1_neg",
            Class::Period2 => "period2",
            Class::Other => "other",
            Class::OverturnPos => "overturn_pos",
            Class::OverturnNeg => "overturn_neg",
        }
    }

    /// Index in [`Class::ALL`].
    #[must_use]
    pub fn index(self) -> usize {
        Class::ALL
            .iter()
            .position(|c| *c == self)
            .expect("every class is listed")
    }
}

/// Settings of the classifier (validated; `Default` as documented in the module).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ClassifierSettings {
    /// Periods simulated at most (default 600).
    pub max_periods: usize,
    /// Periods before periodicity is tested (default 10).
    pub min_periods: usize,
    /// Periods per simulation chunk (default 10).
    pub chunk: usize,
    /// Strobe repetition tolerance (default `1e-6`).
    pub tol: f64,
    /// Predicted distance to the limit accepted by the extrapolation (default `1e-4`).
    pub extrapolation_tol: f64,
    /// Half-period symmetry tolerance (default `1e-3`, well above the convergence tolerance and
    /// far below the asymmetry of asymmetric orbits, which is of order 0.1).
    pub symmetry_tol: f64,
    /// Periods between Newton refinements (default 30; 0 disables them).
    pub newton_every: usize,
    /// Largest distance (max-norm in $(\varphi, \psi)$) of the current state from a stable fixed
    /// point found by Newton for the trial to be classified by it (default 0.05).
    pub newton_radius: f64,
    /// Integration tolerances (default `1e-9`, `1e-11`).
    pub rtol: f64,
    /// See `rtol`.
    pub atol: f64,
}

impl Default for ClassifierSettings {
    fn default() -> Self {
        Self {
            max_periods: 600,
            min_periods: 10,
            chunk: 10,
            tol: 1e-6,
            extrapolation_tol: 1e-4,
            symmetry_tol: 1e-3,
            newton_every: 30,
            newton_radius: 0.05,
            rtol: 1e-9,
            atol: 1e-11,
        }
    }
}

/// How a trial was decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Decision {
    /// A terminal event (overturn).
    Event,
    /// At rest with lift-off impossible.
    Rest,
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
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Classification {
    /// The class.
    pub class: Class,
    /// How it was decided.
    pub decision: Decision,
    /// Forcing periods simulated.
    pub periods: usize,
    /// Whether the final motion includes rest (sticking) phases.
    pub with_rest: bool,
}

/// A fixed point found by [`refine`]: its state, its images after half a period and after one
/// period (in $(\varphi, \psi)$), and whether it is stable.
type Refined = ([f64; 4], [f64; 2], [f64; 2], bool);

/// Newton on the `k`-fold stroboscopic map restricted to $(\varphi, \psi)$ from `x` (the forcing
/// oscillator's state is kept: it is periodic). Returns the fixed point's full state, its
/// half-period image, its image after one period, and whether it is stable, or `None` if Newton
/// fails.
fn refine(params: &Parameters, x: &[f64], mode: hycont_core::Mode, k: usize) -> Option<Refined> {
    use hycont_core::Sensitivities;
    let period = params.forcing_period();
    let p = params.to_vec();
    let mut sim = Simulator::new(
        SimulationSettings::default()
            .rtol(1e-10)
            .atol(1e-12)
            .record_events(false)
            .samples(SampleTimes::new(0.0, 0.5 * period)),
    )
    .ok()?;
    let mut z = [x[0], x[1], x[2], x[3]];
    let mut m = mode;
    for _ in 0..8 {
        let traj = sim
            .run_with_sensitivities(
                &RockingBlock,
                m,
                0.0,
                &z,
                &p,
                k as f64 * period,
                Sensitivities::State,
            )
            .ok()?;
        if !matches!(traj.stop, StopReason::EndReached) || !traj.zeno.is_empty() {
            return None;
        }
        let sens = traj.sensitivities?;
        let f = [traj.state_final[0] - z[0], traj.state_final[1] - z[1]];
        let a = [
            [sens.state_entry(0, 0) - 1.0, sens.state_entry(0, 1)],
            [sens.state_entry(1, 0), sens.state_entry(1, 1) - 1.0],
        ];
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        if det.abs() < 1e-14 {
            return None;
        }
        let dz = [
            -(a[1][1] * f[0] - a[0][1] * f[1]) / det,
            -(-a[1][0] * f[0] + a[0][0] * f[1]) / det,
        ];
        let res = f[0].abs().max(f[1].abs());
        if res < 1e-10 {
            // Multipliers: eigenvalues of the (phi, psi) block (the monodromy is triangular).
            let (b00, b01, b10, b11) = (a[0][0] + 1.0, a[0][1], a[1][0], a[1][1] + 1.0);
            let tr = b00 + b11;
            let dt = b00 * b11 - b01 * b10;
            let disc = tr * tr - 4.0 * dt;
            let rho = if disc >= 0.0 {
                (0.5 * (tr.abs() + disc.sqrt())).abs()
            } else {
                dt.abs().sqrt()
            };
            let at = |j: usize| {
                traj.samples
                    .iter()
                    .nth(j)
                    .map_or([f64::NAN, f64::NAN], |(_, _, s)| [s[0], s[1]])
            };
            return Some((z, at(1), at(2), rho < 1.0 - 1e-9));
        }
        z[0] += dz[0];
        z[1] += dz[1];
        m = initial_mode(&z, params);
        if dz[0].abs() > 1.0 || dz[1].abs() > 5.0 {
            return None;
        }
    }
    None
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .take(2)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Classifies the motion from $(\varphi_0, \psi_0)$ with forcing phase $\beta$.
///
/// # Errors
/// Invalid parameters or an integration failure.
pub fn classify(
    params: &Parameters,
    beta: f64,
    phi0: f64,
    psi0: f64,
    settings: &ClassifierSettings,
) -> Result<Classification> {
    params.validate()?;
    const PER: usize = 8; // samples per period: the strobe is every 8th, the half period the 4th
    let period = params.forcing_period();
    let mut sim = Simulator::new(
        SimulationSettings::default()
            .rtol(settings.rtol)
            .atol(settings.atol)
            .record_events(false)
            .samples(SampleTimes::new(0.0, period / PER as f64)),
    )?;
    let p = params.to_vec();
    let x0 = initial_state(phi0, psi0, beta);
    let mut mode = initial_mode(&x0, params);
    let mut x = x0.to_vec();
    let mut strobe: Vec<[f64; 2]> = Vec::new();
    let mut half: Vec<[f64; 2]> = Vec::new();
    let mut rest_recent = false;
    let mut diffs: Vec<f64> = Vec::new();
    let mut periods = 0;
    let lift_off = params.lift_off_possible();
    while periods < settings.max_periods {
        let n = settings.chunk.min(settings.max_periods - periods);
        let t0 = periods as f64 * period;
        let traj = sim.run(&RockingBlock, mode, t0, &x, &p, t0 + n as f64 * period)?;
        if let StopReason::TerminalEvent { event, .. } = traj.stop {
            let class = if event == OVERTURN_POS {
                Class::OverturnPos
            } else {
                Class::OverturnNeg
            };
            return Ok(Classification {
                class,
                decision: Decision::Event,
                periods: periods + n,
                with_rest: false,
            });
        }
        if traj.mode_final == REST && !lift_off {
            return Ok(Classification {
                class: Class::Equilibrium,
                decision: Decision::Rest,
                periods: periods + n,
                with_rest: true,
            });
        }
        // Samples: t0 + j T / 8 for j = 0 ..= 8 n (the first repeats the last of the previous
        // chunk).
        let samples: Vec<(hycont_core::Mode, [f64; 2])> = traj
            .samples
            .iter()
            .map(|(_, m, s)| (m, [s[0], s[1]]))
            .collect();
        rest_recent =
            samples.iter().rev().take(PER + 1).any(|(m, _)| *m == REST) || !traj.zeno.is_empty();
        for (j, (_, s)) in samples.iter().enumerate() {
            if j == 0 && !strobe.is_empty() {
                continue;
            }
            if j % PER == 0 {
                strobe.push(*s);
            } else if j % PER == PER / 2 {
                half.push(*s);
            }
        }
        let last_period_phi: Vec<f64> = samples.iter().rev().take(PER).map(|(_, s)| s[0]).collect();
        mode = traj.mode_final;
        x.clone_from(&traj.state_final);
        periods += n;
        if periods < settings.min_periods || strobe.len() < 4 {
            continue;
        }
        let k = strobe.len() - 1;
        let d1 = dist(&strobe[k], &strobe[k - 1]);
        let d2 = dist(&strobe[k], &strobe[k - 2]);
        diffs.clear();
        diffs.extend((k.saturating_sub(8)..k).map(|i| dist(&strobe[i + 1], &strobe[i])));
        let scale = 1.0 + strobe[k][0].abs().max(strobe[k][1].abs());
        let converged_p1 = d1 <= settings.tol * scale;
        // Geometric convergence: ratios of successive differences consistently below 1.
        let extrapolated_p1 = !converged_p1 && diffs.len() >= 6 && {
            let ratios: Vec<f64> = diffs.windows(2).map(|w| w[1] / w[0]).collect();
            let rho = ratios.iter().copied().fold(0.0, f64::max);
            rho < 0.999
                && ratios.iter().all(|r| *r > 0.0)
                && d1 * rho / (1.0 - rho) <= settings.extrapolation_tol
        };
        if converged_p1 || extrapolated_p1 {
            let h = half.last().copied().unwrap_or([0.0, 0.0]);
            let s = strobe[k];
            let asym = (h[0] + s[0]).abs().max((h[1] + s[1]).abs());
            let class = if asym <= settings.symmetry_tol + 10.0 * d1 {
                Class::SymmetricP1
            } else {
                let mean: f64 =
                    last_period_phi.iter().sum::<f64>() / last_period_phi.len().max(1) as f64;
                if mean > 0.0 {
                    Class::AsymmetricP1Pos
                } else {
                    Class::AsymmetricP1Neg
                }
            };
            let decision = if converged_p1 {
                Decision::Converged
            } else {
                Decision::Extrapolated
            };
            return Ok(Classification {
                class,
                decision,
                periods,
                with_rest: rest_recent,
            });
        }
        // Newton refinement for slowly converging trials.
        if settings.newton_every > 0
            && periods % settings.newton_every < settings.chunk
            && periods >= 2 * settings.min_periods
        {
            for kk in [1usize, 2] {
                if let Some((z, h, one, stable)) = refine(params, &x, mode, kk) {
                    let here = [x[0], x[1]];
                    // A fixed point of the squared map that returns after one period is period 1.
                    let period_one = kk == 1 || dist(&one, &z) <= 1e-6;
                    if kk == 2 && period_one {
                        continue;
                    }
                    if stable && dist(&here, &z) <= settings.newton_radius {
                        let class = if kk == 2 {
                            Class::Period2
                        } else if (h[0] + z[0]).abs().max((h[1] + z[1]).abs())
                            <= settings.symmetry_tol
                        {
                            Class::SymmetricP1
                        } else {
                            let mean: f64 = last_period_phi.iter().sum::<f64>()
                                / last_period_phi.len().max(1) as f64;
                            if mean > 0.0 {
                                Class::AsymmetricP1Pos
                            } else {
                                Class::AsymmetricP1Neg
                            }
                        };
                        return Ok(Classification {
                            class,
                            decision: Decision::Newton,
                            periods,
                            with_rest: rest_recent,
                        });
                    }
                }
            }
        }
        if d2 <= settings.tol * scale
            && k >= 3
            && dist(&strobe[k - 1], &strobe[k - 3]) <= settings.tol * scale
        {
            return Ok(Classification {
                class: Class::Period2,
                decision: Decision::Converged,
                periods,
                with_rest: rest_recent,
            });
        }
    }
    Ok(Classification {
        class: Class::Other,
        decision: Decision::Undecided,
        periods,
        with_rest: rest_recent,
    })
}

/// The rocking block's classifier for [`hycont_sample::basin`] studies with variables
/// `[omega, alpha, beta, phi0, psi0]` (the study's default damping and slenderness).
///
/// Its classes are the eight of [`Class::ALL`], then the periodic and other classes again with
/// the suffix `_with_rest` for motions that include rest phases (so that the counts report
/// them separately); [`base_class`] maps an index back to the study's class.
#[derive(Debug, Clone, Copy, Default)]
pub struct RockingClassifier {
    /// Classifier settings.
    pub settings: ClassifierSettings,
}

/// Classes that can carry rest phases (counted separately with `_with_rest`).
const WITH_REST: [Class; 5] = [
    Class::SymmetricP1,
    Class::AsymmetricP1Pos,
    Class::AsymmetricP1Neg,
    Class::Period2,
    Class::Other,
];

/// The study class of a [`RockingClassifier`] class index, and whether it had rest phases.
#[must_use]
pub fn base_class(index: usize) -> (Class, bool) {
    if index < Class::ALL.len() {
        (Class::ALL[index], false)
    } else {
        (WITH_REST[index - Class::ALL.len()], true)
    }
}

impl hycont_sample::basin::Classifier for RockingClassifier {
    fn classes(&self) -> Vec<String> {
        Class::ALL
            .iter()
            .map(|c| c.name().to_string())
            .chain(WITH_REST.iter().map(|c| format!("{}_with_rest", c.name())))
            .collect()
    }
    fn classify(&self, v: &[f64]) -> std::result::Result<usize, String> {
        let c = classify(
            &Parameters::new(v[0], v[1]),
            v[2],
            v[3],
            v[4],
            &self.settings,
        )
        .map_err(|e| e.to_string())?;
        Ok(match WITH_REST.iter().position(|x| *x == c.class) {
            Some(i) if c.with_rest => Class::ALL.len() + i,
            _ => c.class.index(),
        })
    }
}
