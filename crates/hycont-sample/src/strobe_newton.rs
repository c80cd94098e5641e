//! Newton's method on the stroboscopic map (or its square) for [`crate::classify`]: the fixed
//! point near a trial's state, its stability from the variational equations with saltation
//! matrices, and the samples the classification reads off it.

use crate::classify::{PeriodicallyForced, StrobeSettings, dist};
use crate::error::Result;
use hycont_core::{
    HybridJacobians, Mode, SampleTimes, Sensitivities, SimulationSettings, Simulator, StopReason,
};

/// How far (in newton_radius) Newton's iterates may wander from the state before the
/// refinement is abandoned.
const FAR: f64 = 4.0;

/// Distance of a fixed point of the squared map from its image after one period below which it
/// is a period-1 orbit.
pub(crate) const PERIOD_ONE: f64 = 1e-4;

/// A fixed point of the `k`-fold stroboscopic map: its state, its images half a period and one
/// period later, and whether it is stable.
pub(crate) struct Fixed {
    pub(crate) z: Vec<f64>,
    pub(crate) half: Vec<f64>,
    pub(crate) one: Vec<f64>,
    pub(crate) stable: bool,
    /// The modes at those three instants (the orbit has no Zeno transition: Newton refuses
    /// runs with one).
    pub(crate) modes: Vec<Mode>,
}

/// Newton's method on the `k`-fold stroboscopic map restricted to the strobe components from
/// `x` (the forcing's state is kept: it is periodic); `None` if it does not converge.
pub(crate) fn refine<S: PeriodicallyForced + HybridJacobians + ?Sized>(
    system: &S,
    p: &[f64],
    x: &[f64],
    mode: Mode,
    k: usize,
    settings: &StrobeSettings,
) -> Result<Option<Fixed>> {
    let comps = system.strobe_components();
    let m = comps.len();
    let period = system.forcing_period(p);
    let mut sim = Simulator::new(
        SimulationSettings::default()
            .rtol(settings.rtol)
            .atol(settings.atol)
            .max_steps(settings.max_steps_per_period.saturating_mul(k as u64))
            .record_events(false)
            .samples(SampleTimes::new(0.0, 0.5 * period)),
    )?;
    let mut z = x.to_vec();
    let mut mode = mode;
    // Converged when the map's residual is at the integration's accuracy.
    let accuracy = 10.0 * settings.rtol.max(settings.atol);
    for _ in 0..8 {
        let Ok(traj) = sim.run_with_sensitivities(
            system,
            mode,
            0.0,
            &z,
            p,
            k as f64 * period,
            Sensitivities::State,
        ) else {
            return Ok(None);
        };
        if !matches!(traj.stop, StopReason::EndReached) || !traj.zeno.is_empty() {
            return Ok(None);
        }
        let Some(sens) = traj.sensitivities.as_ref() else {
            return Ok(None);
        };
        let f: Vec<f64> = comps.iter().map(|&c| traj.state_final[c] - z[c]).collect();
        // The restricted Jacobian of the map minus I.
        let a = nalgebra::DMatrix::from_fn(m, m, |i, j| {
            sens.state_entry(comps[i], comps[j]) - if i == j { 1.0 } else { 0.0 }
        });
        let residual = f.iter().fold(0.0f64, |r, v| r.max(v.abs()));
        let scale = 1.0 + comps.iter().map(|&c| z[c].abs()).fold(0.0, f64::max);
        if residual < accuracy * scale {
            let jac = a + nalgebra::DMatrix::identity(m, m);
            let rho = jac
                .complex_eigenvalues()
                .iter()
                .map(|l| l.norm())
                .fold(0.0, f64::max);
            let at = |j: usize| traj.samples.iter().nth(j).map(|(_, _, s)| s.to_vec());
            let (Some(half), Some(one)) = (at(1), at(2)) else {
                return Ok(None);
            };
            let modes = traj.samples.iter().take(3).map(|(_, m, _)| m).collect();
            return Ok(Some(Fixed {
                z,
                half,
                one,
                stable: rho < 1.0 - 1e-9,
                modes,
            }));
        }
        let Some(dz) = a.lu().solve(&nalgebra::DVector::from_vec(f)) else {
            return Ok(None);
        };
        if comps.iter().zip(dz.iter()).any(|(_, d)| !d.is_finite()) {
            return Ok(None);
        }
        for (i, &c) in comps.iter().enumerate() {
            z[c] -= dz[i];
        }
        // A fixed point is accepted within `newton_radius` of the state: iterates that wander
        // far beyond it are not converging to one that would be (chaotic trials met unstable
        // orbits every attempt, half their time).
        if dz.iter().any(|d| d.abs() > 5.0) || dist(comps, &z, x) > FAR * settings.newton_radius {
            return Ok(None);
        }
        mode = system.mode_at(&z, p);
    }
    Ok(None)
}
