//! Hybrid periodic orbits: signatures, multi-segment boundary-value problems, Floquet multipliers.
//!
//! ```text
//! Trajectory ──PeriodicOrbit::from_simulation──▶ PeriodicOrbit ──solve_shooting──▶ OrbitSolution
//!                                                     (signature, starts,            (orbit, Floquet,
//!                                                      durations, params)              Newton history)
//! ```

mod admissibility;
mod collocation;
mod discretisation;
mod end_condition;
mod floquet;
mod flow;
mod grazing;
mod grazing_join;
mod measure;
mod measure_set;
mod periodic_orbit;
mod scan;
mod shooting;
mod signature;
mod simulated_return;
mod symmetry;
mod touch;
mod turning;

pub use admissibility::{
    ADMISSIBILITY_TOL, AdmissibilityMargin, Margin, Violation, check_admissible,
    check_admissible_collapsed,
};
pub use collocation::{
    Collocation, CollocationSettings, CollocationSolution, MAX_NTST, Mesh,
    collocation_adapted_meshes, collocation_error_estimate, collocation_floquet,
    collocation_floquet_factorised, collocation_pack, collocation_problem,
    collocation_refined_meshes, collocation_transfer, collocation_unpack, gauss_legendre_points,
    solve_collocation,
};
pub use discretisation::{Discretisation, OrbitEquations, OrbitMethod, orbit_problem};
pub use floquet::{Floquet, NEUTRAL_BAND, saltation_matrix};
pub use grazing::{GrazingSplit, split_at_grazing};
pub use grazing_join::{
    GrazingJoin, JOIN_IDENTITY_TOL, JOIN_ZERO_DURATION, JoinAt, join_at_grazing,
};
pub use measure::{
    Extremum, ExtremumKind, GrazingMargin, Measure, SegmentDuration, SegmentPoint, SegmentValue,
    TimeAverage,
};
pub use measure_set::MeasureSet;
pub use periodic_orbit::PeriodicOrbit;
pub(crate) use periodic_orbit::settle_zero_durations;
pub use scan::{BOUNDARY_BAND, CriticalPoint, OrbitScan, ScanNeeds, Turn, Watch, scan};
pub use shooting::{CachedSegment, LinearizationCache, Shooting, ShootingSettings};
pub use signature::{Closure, SegmentEnd, SegmentSpec, Signature};
pub use simulated_return::SimulatedReturn;
pub use symmetry::{
    SolvedOrbit, SymmetricSearch, SymmetricSolution, find_symmetric_orbit, solve_orbit,
    solve_symmetric_collocation, solve_symmetric_shooting, symmetric_floquet,
};
pub use touch::{Touch, TouchValue};

use crate::error::{Error, Result};
use crate::problem::{NewtonIteration, NewtonSettings, Problem, newton};
use crate::simulate::{Sensitivities, SimulationSettings, Simulator};
use crate::system::{HybridJacobians, Mode};
use flow::SegmentFlow;
use serde::{Deserialize, Serialize};

/// A solved periodic orbit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrbitSolution {
    /// The orbit.
    pub orbit: PeriodicOrbit,
    /// Its Floquet multipliers.
    pub floquet: Floquet,
    /// The Newton iterations that found it.
    pub newton: Vec<NewtonIteration>,
    /// $\|F\|_\infty$ at the solution.
    pub residual: f64,
}

/// Packs an orbit into the shooting unknowns `[x_0 .. x_{K-1}, T_0 .. T_{K-1}, p]`.
#[must_use]
pub fn pack(orbit: &PeriodicOrbit) -> Vec<f64> {
    let mut u: Vec<f64> = orbit.starts.iter().flatten().copied().collect();
    u.extend_from_slice(&orbit.durations);
    u.extend_from_slice(&orbit.params);
    u
}

impl PeriodicOrbit {
    /// The index of segment `k`'s start state in the unknowns of [`pack`] (the sum of the
    /// earlier segments' state dimensions).
    ///
    /// ```
    /// # use hycont_core::Mode;
    /// # use hycont_core::orbit::{PeriodicOrbit, Signature, SegmentSpec, SegmentEnd};
    /// # let spec = SegmentSpec { mode: Mode(0), end: SegmentEnd::Interior { component: 0, value: 0.0 } };
    /// # let signature: Signature = serde_json::from_value(serde_json::json!({
    /// #     "segments": [spec, spec], "closure": "Periodic" })).unwrap();
    /// let orbit = PeriodicOrbit {
    ///     signature,
    ///     starts: vec![vec![0.0; 3], vec![0.0; 4]],
    ///     durations: vec![1.0, 2.0],
    ///     params: vec![],
    /// };
    /// assert_eq!(orbit.start_offset(1), 3);
    /// ```
    #[must_use]
    pub fn start_offset(&self, k: usize) -> usize {
        self.starts[..k].iter().map(Vec::len).sum()
    }

    /// The orbit traversed twice: the signature, starts and durations repeated (the guess for a
    /// period-doubled orbit, which the period-doubling direction then perturbs).
    #[must_use]
    pub fn doubled(&self) -> Self {
        let mut segments = self.signature.segments().to_vec();
        segments.extend_from_slice(self.signature.segments());
        let mut starts = self.starts.clone();
        starts.extend(self.starts.iter().cloned());
        let mut durations = self.durations.clone();
        durations.extend_from_slice(&self.durations);
        Self {
            signature: Signature::from_validated(segments, self.signature.closure()),
            starts,
            durations,
            params: self.params.clone(),
        }
    }
}

/// Unpacks shooting unknowns into an orbit with the signature of `like` (each segment start
/// as long as `like`'s).
#[must_use]
pub fn unpack(like: &PeriodicOrbit, u: &[f64]) -> PeriodicOrbit {
    let k = like.segment_count();
    let mut off = 0;
    let starts = like
        .starts
        .iter()
        .map(|x| {
            off += x.len();
            u[off - x.len()..off].to_vec()
        })
        .collect();
    PeriodicOrbit {
        signature: like.signature.clone(),
        starts,
        durations: u[off..off + k].to_vec(),
        params: u[off + k..off + k + like.params.len()].to_vec(),
    }
}

/// The shooting problem of an orbit: the [`Shooting`] equations with every parameter held by an
/// inactive monitor named after it.
///
/// # Errors
/// Invalid settings.
pub fn shooting_problem<'a, S: HybridJacobians + ?Sized>(
    system: &'a S,
    guess: &PeriodicOrbit,
    settings: ShootingSettings,
) -> Result<Problem<'a>> {
    let shooting = Shooting::new(system, guess.signature.clone(), settings)?;
    problem_of_shooting(system, shooting, &guess.params)
}

/// Like [`shooting_problem`], with the shooting part recording its linearisations into `cache`.
///
/// # Errors
/// Invalid settings.
pub fn shooting_problem_cached<'a, S: HybridJacobians + ?Sized>(
    system: &'a S,
    guess: &PeriodicOrbit,
    settings: ShootingSettings,
    cache: LinearizationCache,
) -> Result<Problem<'a>> {
    let shooting = Shooting::new(system, guess.signature.clone(), settings)?.with_cache(cache);
    problem_of_shooting(system, shooting, &guess.params)
}

/// `shooting` over all unknowns, every parameter held at `params` by an inactive monitor.
fn problem_of_shooting<'a, S: HybridJacobians + ?Sized>(
    system: &'a S,
    shooting: Shooting<'a, S>,
    params: &[f64],
) -> Result<Problem<'a>> {
    let first_param = shooting.param_index(0);
    orbit_problem(system, Box::new(shooting), first_param, params)
}

/// Floquet multipliers of `orbit` from cached segment linearisations, if the cache holds every
/// segment at exactly this orbit's start states, durations and parameters (else `None`).
///
/// # Errors
/// Eigenvalue failures.
pub fn monodromy_from_cache<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    cache: &LinearizationCache,
) -> Result<Option<Floquet>> {
    let c = cache.borrow();
    if c.len() != orbit.segment_count() {
        return Ok(None);
    }
    let hit = c.iter().enumerate().all(|(k, seg)| {
        seg.start == orbit.starts[k]
            && seg.duration == orbit.durations[k]
            && seg.params == orbit.params
    });
    if !hit {
        return Ok(None);
    }
    compose_monodromy(
        system,
        orbit,
        c.iter().map(|seg| Ok((seg.end.clone(), seg.phi.clone()))),
    )
    .map(Some)
}

/// Floquet multipliers from each segment's end state $y_k$ and flow Jacobian $\Phi_k$:
/// $M = \prod_k S_k \Phi_k$ (saltation matrices $S_k$ at the segment ends), in segment order.
fn compose_monodromy<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    segments: impl Iterator<Item = Result<(Vec<f64>, Vec<f64>)>>,
) -> Result<Floquet> {
    // M maps the first segment's start (n_0 states) to segment k's; S_k Phi_k is
    // n_{k+1} x n_k (modes of different dimensions: rectangular).
    let n0 = system.mode_dim(orbit.signature.segments()[0].mode);
    let mut m = vec![0.0; n0 * n0];
    for i in 0..n0 {
        m[i + i * n0] = 1.0;
    }
    for (k, seg) in segments.enumerate() {
        let (end, phi) = seg?;
        let (n, n_to) = (end.len(), floquet::next_dim(system, orbit, k));
        let s = floquet::saltation(system, orbit, k, &end);
        m = floquet::matmul_rect(n_to, n, &floquet::matmul_rect(n_to, n, &s, &phi), &m);
    }
    Floquet::from_monodromy(system, &orbit.params, orbit.period(), m)
}

/// Solves for the periodic orbit near `guess` by multiple shooting and Newton's method, and
/// computes its Floquet multipliers.
///
/// # Errors
/// [`crate::Error::NewtonFailed`] (with the history) if Newton does not converge,
/// [`crate::Error::Inadmissible`] if the solution leaves its modes' domains
/// ([`check_admissible`]), or an integration error.
pub fn solve_shooting<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: ShootingSettings,
    newton_settings: &NewtonSettings,
) -> Result<OrbitSolution> {
    guess.validate(system)?;
    refuse_half_orbit(guess, "solve_symmetric_shooting")?;
    let mut problem = shooting_problem(system, guess, settings)?;
    let sol = newton(&mut problem, &pack(guess), newton_settings)?;
    let orbit = solved_orbit(guess, &sol.u, newton_settings);
    check_admissible(system, &orbit)?;
    let floquet = monodromy_by_shooting(system, &orbit, settings)?;
    Ok(OrbitSolution {
        orbit,
        floquet,
        newton: sol.history,
        residual: sol.residual,
    })
}

/// The orbit of `like`'s layout that a shooting Newton solve converged to at `u`, with its
/// zero-length segments settled ([`settle_zero_durations`] at the solve's
/// resolution).
pub(crate) fn solved_orbit(
    like: &PeriodicOrbit,
    u: &[f64],
    newton_settings: &NewtonSettings,
) -> PeriodicOrbit {
    let mut orbit = unpack(like, u);
    settle_zero_durations(&mut orbit.durations, newton_settings.resolution(u));
    orbit
}

/// Refuses a half orbit ([`Closure::Symmetric`]) where a full orbit is solved: its
/// multipliers would be those of the half monodromy, not the orbit's.
pub(crate) fn refuse_half_orbit(guess: &PeriodicOrbit, instead: &str) -> Result<()> {
    if guess.signature.closure() == Closure::Symmetric {
        return Err(Error::InvalidSignature {
            segment: 0,
            reason: format!(
                "a half orbit (symmetric closure) is solved by solve_orbit or {instead}, which \
                 report the full orbit's and the half map's multipliers"
            ),
        });
    }
    Ok(())
}

/// Floquet multipliers of `orbit` from its segments' flow Jacobians and saltation matrices.
///
/// # Errors
/// Integration or eigenvalue failures.
pub fn monodromy_by_shooting<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    settings: ShootingSettings,
) -> Result<Floquet> {
    let mut sim = Simulator::new(
        SimulationSettings::default()
            .rtol(settings.rtol)
            .atol(settings.atol)
            .record_events(false),
    )?;
    let segments = orbit
        .signature
        .segments()
        .iter()
        .enumerate()
        .map(|(k, seg)| {
            // Negative durations (past a segment's collapse) flow backward.
            let flow = if orbit.durations[k] >= 0.0 {
                SegmentFlow::plain(system, seg.mode)
            } else {
                SegmentFlow::backward(system, seg.mode)
            };
            let traj = sim.run_with_sensitivities(
                &flow,
                Mode(0),
                0.0,
                &orbit.starts[k],
                &orbit.params,
                orbit.durations[k].abs(),
                Sensitivities::State,
            )?;
            let phi = traj.sensitivities.expect("requested").state;
            Ok((traj.state_final, phi))
        });
    compose_monodromy(system, orbit, segments)
}
