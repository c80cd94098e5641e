//! Solving for an orbit by collocation: the problem over a mesh, node values from a simulated
//! guess, packing and unpacking unknowns, multipliers, and Newton with mesh adaptation.

use super::basis::Basis;
use super::condense::{condensed_floquet, factorised_floquet};
use super::mesh::{
    adapted_mesh, adapted_mesh_of_size, error_estimate, transfer_nodes, uniform_mesh,
};
use super::{Collocation, CollocationSettings, Mesh};
use crate::error::Result;
use crate::orbit::floquet::Floquet;
use crate::orbit::{OrbitSolution, PeriodicOrbit};
use crate::problem::{NewtonSettings, Problem, newton};
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{HybridJacobians, Mode};
use serde::{Deserialize, Serialize};

/// A periodic orbit solved by collocation: the orbit (segment starts and durations read off the
/// collocation solution), the meshes and node values, and multipliers from the condensed
/// collocation Jacobian.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CollocationSolution {
    /// The orbit, multipliers (from the collocation Jacobian) and Newton history.
    pub solution: OrbitSolution,
    /// The final mesh of each segment.
    pub meshes: Vec<Mesh>,
    /// The node states of each segment (`ntst * ncol + 1` states of length $n$, flattened).
    pub nodes: Vec<Vec<f64>>,
    /// The settings used.
    pub settings: CollocationSettings,
}

impl CollocationSolution {
    /// The solution as the unknowns of [`collocation_problem`] (node states of every segment,
    /// durations, parameters).
    #[must_use]
    pub fn unknowns(&self) -> Vec<f64> {
        pack_nodes(&self.nodes, &self.solution.orbit)
    }

    /// Floquet multipliers recomputed from the condensed collocation Jacobian.
    ///
    /// # Errors
    /// Singular blocks or eigenvalue failures.
    pub fn floquet<S: HybridJacobians + ?Sized>(&self, system: &S) -> Result<Floquet> {
        condensed_floquet(
            system,
            &self.solution.orbit,
            &self.meshes,
            &self.nodes,
            self.settings.ncol,
        )
    }
}

/// Node states of each segment of `orbit` on the given meshes, by simulating the segments.
pub(crate) fn initial_nodes<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    ncol: usize,
) -> Result<Vec<Vec<f64>>> {
    let basis_nodes: Vec<f64> = (0..=ncol).map(|i| i as f64 / ncol as f64).collect();
    let mut out = Vec::new();
    for (k, seg) in orbit.signature.segments().iter().enumerate() {
        let n = system.mode_dim(seg.mode);
        let taus: Vec<f64> = meshes[k]
            .windows(2)
            .flat_map(|w| {
                let (a, b) = (w[0], w[1]);
                basis_nodes[..ncol].iter().map(move |z| a + z * (b - a))
            })
            .chain(std::iter::once(1.0))
            .collect();
        // Uniform meshes: one run with the node times as samples (dense output); otherwise
        // integrate from node to node (a zero-length segment: every node is its start).
        let flow = crate::orbit::flow::SegmentFlow::plain(system, seg.mode);
        let uniform = orbit.durations[k] > 0.0
            && meshes[k]
                .windows(2)
                .all(|w| ((w[1] - w[0]) - 1.0 / (meshes[k].len() - 1) as f64).abs() < 1e-14);
        let mut vals = Vec::with_capacity(taus.len() * n);
        if uniform {
            let step = orbit.durations[k] / (taus.len() - 1) as f64;
            let mut sim = Simulator::new(
                SimulationSettings::default()
                    .rtol(1e-12)
                    .atol(1e-14)
                    .samples(crate::simulate::SampleTimes::new(0.0, step)),
            )?;
            let traj = sim.run(
                &flow,
                Mode(0),
                0.0,
                &orbit.starts[k],
                &orbit.params,
                orbit.durations[k],
            )?;
            for (_, _, x) in traj.samples.iter().take(taus.len()) {
                vals.extend_from_slice(x);
            }
            while vals.len() < taus.len() * n {
                vals.extend_from_slice(&traj.state_final);
            }
        } else {
            let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-12).atol(1e-14))?;
            let mut x = orbit.starts[k].clone();
            let mut t_prev = 0.0;
            for &tau in &taus {
                let t = tau * orbit.durations[k];
                if t > t_prev {
                    let traj = sim.run(&flow, Mode(0), t_prev, &x, &orbit.params, t)?;
                    x.clone_from(&traj.state_final);
                    t_prev = t;
                }
                vals.extend_from_slice(&x);
            }
        }
        out.push(vals);
    }
    Ok(out)
}

/// The collocation problem of an orbit on the given meshes: the [`Collocation`] equations with
/// every parameter held by an inactive monitor named after it. Its unknowns are packed as in
/// [`CollocationSolution::unknowns`].
///
/// # Errors
/// Invalid meshes or degree.
pub fn collocation_problem<'a, S: HybridJacobians + ?Sized>(
    system: &'a S,
    orbit: &PeriodicOrbit,
    meshes: Vec<Mesh>,
    ncol: usize,
) -> Result<Problem<'a>> {
    collocation_problem_impl(system, orbit, meshes, ncol).map(|(p, _)| p)
}

fn collocation_problem_impl<'a, S: HybridJacobians + ?Sized>(
    system: &'a S,
    orbit: &PeriodicOrbit,
    meshes: Vec<Mesh>,
    ncol: usize,
) -> Result<(Problem<'a>, usize)> {
    let coll = Collocation::new(system, orbit.signature.clone(), meshes, ncol)?;
    let first_param = coll.param_index(0);
    let problem = crate::orbit::orbit_problem(system, Box::new(coll), first_param, &orbit.params)?;
    Ok((problem, first_param))
}

fn pack_nodes(nodes: &[Vec<f64>], orbit: &PeriodicOrbit) -> Vec<f64> {
    let mut u: Vec<f64> = nodes.iter().flatten().copied().collect();
    u.extend_from_slice(&orbit.durations);
    u.extend_from_slice(&orbit.params);
    u
}

/// Splits the unknowns of a [`collocation_problem`] on `meshes` (degree `ncol`) into each
/// segment's node states and the orbit (segment starts = first nodes, durations, parameters).
#[must_use]
pub fn collocation_unpack(
    like: &PeriodicOrbit,
    meshes: &[Mesh],
    ncol: usize,
    u: &[f64],
) -> (Vec<Vec<f64>>, PeriodicOrbit) {
    let sizes: Vec<usize> = meshes.iter().map(|m| (m.len() - 1) * ncol + 1).collect();
    unpack_nodes(u, like, &sizes)
}

/// `f(nodes, mesh, basis, n)` of each segment of the collocation solution at unknowns `u`.
fn per_segment<T>(
    like: &PeriodicOrbit,
    meshes: &[Mesh],
    ncol: usize,
    u: &[f64],
    f: fn(&[f64], &[f64], &Basis, usize) -> T,
) -> Vec<T> {
    let basis = Basis::shared(ncol);
    // Each segment's nodes, read in place (as `unpack_nodes` lays them out).
    let mut pos = 0;
    meshes
        .iter()
        .zip(&like.starts)
        .map(|(m, start)| {
            let n = start.len();
            let len = ((m.len() - 1) * ncol + 1) * n;
            pos += len;
            f(&u[pos - len..pos], m, &basis, n)
        })
        .collect()
}

/// The estimated largest discretisation error of the collocation solution at unknowns `u`
/// on `meshes`: the largest over segments, intervals and state components of the interior
/// error $C_m h^{m+1} \|x^{(m+1)}\|$ of Gauss collocation with $m = $ `ncol` points ($h$
/// the interval's width and $x^{(m+1)}$ the derivative estimated from jumps of the polynomial's
/// $m$-th derivative, both in each segment's time scaled to $[0, 1]$; $C_m$ from the Gauss
/// points, de Boor and Swartz). In the units of the state: an estimate of
/// $\max |x(t) - p(t)|$ over the orbit.
#[must_use]
pub fn collocation_error_estimate(
    like: &PeriodicOrbit,
    meshes: &[Mesh],
    ncol: usize,
    u: &[f64],
) -> f64 {
    per_segment(like, meshes, ncol, u, error_estimate)
        .into_iter()
        .fold(0.0, f64::max)
}

/// Meshes with the same intervals per segment that equidistribute the error estimate of the
/// solution at unknowns `u` (as the mesh adaptation of [`solve_collocation`]).
#[must_use]
pub fn collocation_adapted_meshes(
    like: &PeriodicOrbit,
    meshes: &[Mesh],
    ncol: usize,
    u: &[f64],
) -> Vec<Mesh> {
    per_segment(like, meshes, ncol, u, adapted_mesh)
}

/// Meshes equidistributing the error estimate of the solution at unknowns `u` with enough
/// intervals for an estimate of `tolerance / 2`: where the estimate $e$ exceeds `tolerance`,
/// each segment gets $\lceil N (2e/\mathrm{tol})^{1/(m+1)} \rceil$ intervals (the interior
/// error falls like $h^{m+1}$), at most [`super::MAX_NTST`]; otherwise the same number
/// ([`collocation_adapted_meshes`]).
#[must_use]
pub fn collocation_refined_meshes(
    like: &PeriodicOrbit,
    meshes: &[Mesh],
    ncol: usize,
    u: &[f64],
    tolerance: f64,
) -> Vec<Mesh> {
    let estimate = collocation_error_estimate(like, meshes, ncol, u);
    if !(estimate > tolerance) {
        return collocation_adapted_meshes(like, meshes, ncol, u);
    }
    let factor = (2.0 * estimate / tolerance).powf(1.0 / (ncol + 1) as f64);
    let basis = Basis::shared(ncol);
    let (nodes, _) = collocation_unpack(like, meshes, ncol, u);
    nodes
        .iter()
        .zip(meshes)
        .zip(&like.starts)
        .map(|((nd, m), start)| {
            let n = start.len();
            let size = ((((m.len() - 1) as f64) * factor).ceil() as usize).min(super::MAX_NTST);
            adapted_mesh_of_size(nd, m, &basis, n, size)
        })
        .collect()
}

/// The unknowns `u` on `meshes` carried over to `new_meshes` (the same `ncol`, any intervals):
/// each segment's piecewise polynomial evaluated at the new nodes; the unknowns after the
/// segments' node states (durations, parameters and anything a problem appends) are copied.
/// Linear in `u`, so it also carries tangents over.
#[must_use]
pub fn collocation_transfer(
    like: &PeriodicOrbit,
    meshes: &[Mesh],
    new_meshes: &[Mesh],
    ncol: usize,
    u: &[f64],
) -> Vec<f64> {
    let mut out = Vec::with_capacity(u.len());
    let mut pos = 0;
    for ((m, new), start) in meshes.iter().zip(new_meshes).zip(&like.starts) {
        let n = start.len();
        let len = ((m.len() - 1) * ncol + 1) * n;
        out.extend(transfer_nodes(&u[pos..pos + len], m, new, ncol, n));
        pos += len;
    }
    out.extend_from_slice(&u[pos..]);
    out
}

/// Packs node states and an orbit's durations and parameters into collocation unknowns.
#[must_use]
pub fn collocation_pack(nodes: &[Vec<f64>], orbit: &PeriodicOrbit) -> Vec<f64> {
    pack_nodes(nodes, orbit)
}

/// Floquet multipliers of a collocation solution from its condensed Jacobian (see
/// [`CollocationSolution::floquet`]).
///
/// # Errors
/// Singular blocks or eigenvalue failures.
pub fn collocation_floquet<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    nodes: &[Vec<f64>],
    ncol: usize,
) -> Result<Floquet> {
    condensed_floquet(system, orbit, meshes, nodes, ncol)
}

/// [`collocation_floquet`] from the condensation a factorisation of the problem's Jacobian at
/// these nodes has already done (each interval's rows left after eliminating its interior
/// nodes; see [`crate::linalg::SparsePattern::reduced_rows`]): no Jacobian evaluation and no
/// elimination. `jacobian` must be factorised at the unknowns of `nodes` and `orbit`, with the
/// collocation part's blocks first and its unknowns first (as [`collocation_problem`] and
/// continuation build it). `Ok(None)` if the factorisation did not condense (a block was
/// singular on its own) or has another layout.
///
/// # Errors
/// Singular transfer blocks or eigenvalue failures.
pub fn collocation_floquet_factorised<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    meshes: &[Mesh],
    nodes: &[Vec<f64>],
    ncol: usize,
    jacobian: &crate::linalg::SparsePattern,
) -> Result<Option<Floquet>> {
    factorised_floquet(system, orbit, meshes, nodes, ncol, jacobian)
}

/// Each segment's `sizes[k]` nodes of `like`'s segment start's dimension, then the orbit.
fn unpack_nodes(
    u: &[f64],
    like: &PeriodicOrbit,
    sizes: &[usize],
) -> (Vec<Vec<f64>>, PeriodicOrbit) {
    let mut nodes = Vec::new();
    let mut pos = 0;
    for (&m, start) in sizes.iter().zip(&like.starts) {
        let n = start.len();
        nodes.push(u[pos..pos + m * n].to_vec());
        pos += m * n;
    }
    let kk = sizes.len();
    let durations = u[pos..pos + kk].to_vec();
    let params = u[pos + kk..pos + kk + like.params.len()].to_vec();
    let starts = (nodes.iter().zip(&like.starts))
        .map(|(v, start)| v[..start.len()].to_vec())
        .collect();
    (
        nodes,
        PeriodicOrbit {
            signature: like.signature.clone(),
            starts,
            durations,
            params,
        },
    )
}

/// Solves for the periodic orbit near `guess` by collocation (then `settings.adapt` mesh
/// adaptations), with Floquet multipliers from the condensed collocation Jacobian.
///
/// # Errors
/// As [`crate::orbit::solve_shooting`]; invalid settings.
pub fn solve_collocation<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<CollocationSolution> {
    crate::orbit::refuse_half_orbit(guess, "solve_symmetric_collocation")?;
    solve_collocation_admissible(system, guess, settings, newton_settings)
}

/// [`solve_collocation`] of a full or a half orbit (whose multipliers are then the half
/// monodromy's, for [`crate::orbit::solve_symmetric_collocation`] to complete).
pub(crate) fn solve_collocation_admissible<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<CollocationSolution> {
    let sol = solve_collocation_unchecked(system, guess, settings, newton_settings)?;
    crate::orbit::check_admissible(system, &sol.solution.orbit)?;
    Ok(sol)
}

/// [`solve_collocation`] without the admissibility check.
fn solve_collocation_unchecked<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<CollocationSolution> {
    let solved = solve_collocation_nodes(system, guess, settings, newton_settings)?;
    let floquet = condensed_floquet(
        system,
        &solved.orbit,
        &solved.meshes,
        &solved.nodes,
        settings.ncol,
    )?;
    Ok(CollocationSolution {
        solution: OrbitSolution {
            orbit: solved.orbit,
            floquet,
            newton: solved.newton,
            residual: solved.residual,
        },
        meshes: solved.meshes,
        nodes: solved.nodes,
        settings,
    })
}

/// A collocation solution without its multipliers (what a continuation starts from: it
/// analyses its points itself).
pub(crate) struct SolvedNodes {
    pub(crate) meshes: Vec<Mesh>,
    pub(crate) nodes: Vec<Vec<f64>>,
    pub(crate) orbit: PeriodicOrbit,
    newton: Vec<crate::problem::NewtonIteration>,
    residual: f64,
}

impl SolvedNodes {
    /// The solution as the unknowns of [`collocation_problem`].
    pub(crate) fn unknowns(&self) -> Vec<f64> {
        pack_nodes(&self.nodes, &self.orbit)
    }
}

/// [`solve_collocation_unchecked`] without the multipliers (a continuation that watches
/// admissibility itself, or has it switched off, starts from any solution).
pub(crate) fn solve_collocation_nodes<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<SolvedNodes> {
    settings.validate()?;
    guess.validate(system)?;
    let kk = guess.segment_count();
    let n = |k: usize| guess.starts[k].len();
    let mut meshes: Vec<Mesh> = (0..kk).map(|_| uniform_mesh(settings.ntst)).collect();
    let mut nodes = initial_nodes(system, guess, &meshes, settings.ncol)?;
    let mut orbit = guess.clone();
    let basis = Basis::shared(settings.ncol);
    let sizes = vec![settings.ntst * settings.ncol + 1; kk];
    let mut history = Vec::new();
    let mut residual = 0.0;
    // The adapted meshes have as many intervals: each pass hands its problem's pattern on.
    let mut previous: Option<Problem<'_>> = None;
    for pass in 0..=settings.adapt {
        if pass > 0 {
            // Move to the adapted meshes, interpolating the current solution.
            let new_meshes: Vec<Mesh> = (0..kk)
                .map(|k| adapted_mesh(&nodes[k], &meshes[k], &basis, n(k)))
                .collect();
            let new_nodes: Vec<Vec<f64>> = (0..kk)
                .map(|k| {
                    let (ncol, n) = (settings.ncol, n(k));
                    transfer_nodes(&nodes[k], &meshes[k], &new_meshes[k], ncol, n)
                })
                .collect();
            meshes = new_meshes;
            nodes = new_nodes;
        }
        let (mut problem, _) =
            collocation_problem_impl(system, &orbit, meshes.clone(), settings.ncol)?;
        // The previous problem is dropped here, before the new one's Newton iteration.
        if let Some(mut p) = previous.take() {
            p.hand_pattern_to(&mut problem);
        }
        let sol = newton(&mut problem, &pack_nodes(&nodes, &orbit), newton_settings)?;
        previous = Some(problem);
        let (mut nd, mut ob) = unpack_nodes(&sol.u, &orbit, &sizes);
        crate::orbit::settle_zero_durations(&mut ob.durations, newton_settings.resolution(&sol.u));
        // A segment of zero length has all its nodes at its start.
        for (k, d) in ob.durations.iter().enumerate() {
            if *d == 0.0 {
                let n = ob.starts[k].len();
                let (first, rest) = nd[k].split_at_mut(n);
                rest.chunks_exact_mut(n)
                    .for_each(|x| x.copy_from_slice(first));
            }
        }
        nodes = nd;
        orbit = ob;
        residual = sol.residual;
        history.extend(sol.history);
    }
    Ok(SolvedNodes {
        meshes,
        nodes,
        orbit,
        newton: history,
        residual,
    })
}
