//! Brute-force (stroboscopic) bifurcation diagrams: sweep a parameter, integrate a transient,
//! record samples, continue from the last state.

use crate::basin::Progress;
use hycont_core::{
    HybridSystem, Mode, Result, SampleTimes, SimulationSettings, Simulator, StopReason,
};
use serde::{Deserialize, Serialize};

/// What to sweep and record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    /// Parameter values, in sweep order.
    pub values: Vec<f64>,
    /// Index of the swept parameter.
    pub parameter: usize,
    /// Sampling period (e.g. the forcing period $2\pi/\omega$).
    pub period: f64,
    /// Periods integrated and discarded at each value.
    pub transient: usize,
    /// Periods recorded at each value.
    pub recorded: usize,
}

/// One value of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepPoint {
    /// Parameter value.
    pub value: f64,
    /// Recorded samples (states), one per period.
    pub samples: Vec<Vec<f64>>,
    /// Modes at the samples.
    pub modes: Vec<Mode>,
    /// Why the last integration stopped (a terminal event ends the sweep's trajectory).
    pub stop: StopReason,
}

/// Runs a brute-force sweep of `system` from `(mode, x0)` with parameters `p` (the swept one is
/// overwritten), continuing each value from the previous value's final state. After a terminal
/// event (e.g. overturning) the next value restarts from `(mode, x0)`. Stops between values
/// when `progress` says so ([`Progress::stopping`], e.g. on an interrupt), with the values
/// swept so far (values are not trials: they do not count in `progress.done`).
///
/// # Errors
/// Integration failures or invalid inputs.
pub fn brute_force<S: HybridSystem + ?Sized>(
    system: &S,
    mode: Mode,
    x0: &[f64],
    p: &[f64],
    sweep: &Sweep,
    settings: &SimulationSettings,
    progress: &Progress,
) -> Result<Vec<SweepPoint>> {
    let mut sim = Simulator::new(
        settings
            .clone()
            .samples(SampleTimes::new(0.0, sweep.period))
            .record_events(false),
    )?;
    let mut params = p.to_vec();
    let (mut m, mut x) = (mode, x0.to_vec());
    let mut t0 = 0.0;
    let mut out = Vec::with_capacity(sweep.values.len());
    for &v in &sweep.values {
        if progress.stopping() {
            break;
        }
        params[sweep.parameter] = v;
        let total = (sweep.transient + sweep.recorded) as f64 * sweep.period;
        let traj = sim.run(system, m, t0, &x, &params, t0 + total)?;
        let skip = sweep.transient + 1; // the sample at t0 and the transient
        let samples: Vec<Vec<f64>> = traj
            .samples
            .iter()
            .skip(skip)
            .map(|(_, _, s)| s.to_vec())
            .collect();
        let modes = traj.samples.mode.iter().skip(skip).copied().collect();
        out.push(SweepPoint {
            value: v,
            samples,
            modes,
            stop: traj.stop,
        });
        if matches!(traj.stop, StopReason::EndReached) {
            m = traj.mode_final;
            x.clone_from(&traj.state_final);
            // Keep the sampling phase: continue from a multiple of the period.
            t0 = 0.0;
        } else {
            m = mode;
            x = x0.to_vec();
            t0 = 0.0;
        }
    }
    Ok(out)
}
