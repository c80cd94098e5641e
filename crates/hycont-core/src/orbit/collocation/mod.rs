//! Orthogonal collocation for hybrid periodic orbits (COCO's `coll`, AUTO's scheme).
//!
//! Segment $k$ is rescaled to $\tau \in [0, 1]$, $t = T_k \tau$, and split into `ntst` mesh
//! intervals $[\tau_j, \tau_{j+1}]$ of length $h_j$. On each interval the solution is the
//! polynomial of degree `ncol` through `ncol + 1` equidistant nodes (nodes at interval ends are
//! shared, so the piecewise polynomial is continuous), and it satisfies the ODE at the `ncol`
//! Gauss-Legendre points $z_c$ of the interval:
//! $$\sum_i L_i'(z_c)\, x_{j,i} = h_j T_k\, f\Big(\sum_i L_i(z_c)\, x_{j,i}, p\Big).$$
//! The segment ends satisfy the same event and jump conditions as in [`super::Shooting`].
//! The error at the mesh points is $O(h^{2\,\mathrm{ncol}})$ (superconvergence).

mod basis;
mod condense;
mod mesh;

use super::end_condition::EndConditions;
use super::floquet::Floquet;
use super::signature::Signature;
use super::{OrbitSolution, PeriodicOrbit};
use crate::error::{Error, Result};
use crate::problem::{LocalBlock, NewtonSettings, Problem, ZeroFunction, newton};
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{HybridJacobians, Mode};
use basis::Basis;
pub use basis::gauss_legendre_points;
use condense::condensed_floquet;
use mesh::{adapted_mesh, eval_piecewise, uniform_mesh};
use serde::{Deserialize, Serialize};

/// Settings of the collocation discretisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct CollocationSettings {
    /// Mesh intervals per segment (default 20).
    pub ntst: usize,
    /// Collocation points per interval, the polynomial degree (default 4; 1 to 7).
    pub ncol: usize,
    /// Mesh adaptations after the first solve (default 1): each equidistributes the error
    /// estimate and solves again.
    pub adapt: usize,
}

impl Default for CollocationSettings {
    fn default() -> Self {
        Self {
            ntst: 20,
            ncol: 4,
            adapt: 1,
        }
    }
}

impl CollocationSettings {
    /// Checks the invariants.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for `ntst == 0` or `ncol` outside `1..=7`.
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_NTST).contains(&self.ntst) {
            return Err(Error::InvalidSetting {
                name: "collocation.ntst",
                value: self.ntst as f64,
                reason: "must be in 1..=10000 (memory grows with ntst: about 80 kB per interval for a 4-dimensional system)",
            });
        }
        if !(1..=7).contains(&self.ncol) {
            return Err(Error::InvalidSetting {
                name: "collocation.ncol",
                value: self.ncol as f64,
                reason: "must be in 1..=7",
            });
        }
        Ok(())
    }
}

/// The largest number of mesh intervals per segment [`CollocationSettings::validate`] accepts.
pub const MAX_NTST: usize = 10_000;

/// A collocation mesh of one segment: $0 = \tau_0 < \dots < \tau_{\mathrm{ntst}} = 1$.
pub type Mesh = Vec<f64>;

/// The collocation equations of a hybrid periodic orbit (a [`ZeroFunction`]).
///
/// Local unknowns: for each segment its `ntst * ncol + 1` node states, then the durations, then
/// the parameters.
pub struct Collocation<'a, S: ?Sized> {
    system: &'a S,
    signature: Signature,
    basis: Basis,
    meshes: Vec<Mesh>,
    n: usize,
    np: usize,
    ends: EndConditions,
    // Work space.
    xi: Vec<f64>,
    f: Vec<f64>,
    a: Vec<f64>,
    fp: Vec<f64>,
}

impl<'a, S: HybridJacobians + ?Sized> Collocation<'a, S> {
    /// Collocation equations with the given per-segment meshes and degree.
    ///
    /// # Errors
    /// Invalid meshes or degree.
    pub fn new(
        system: &'a S,
        signature: Signature,
        meshes: Vec<Mesh>,
        ncol: usize,
    ) -> Result<Self> {
        CollocationSettings {
            ntst: 1,
            ncol,
            adapt: 0,
        }
        .validate()?;
        if meshes.len() != signature.len()
            || meshes.iter().any(|m| {
                m.len() < 2
                    || m[0] != 0.0
                    || *m.last().expect("len >= 2") != 1.0
                    || m.windows(2).any(|w| !(w[1] > w[0]))
            })
        {
            return Err(Error::InvalidSetting {
                name: "collocation mesh",
                value: meshes.len() as f64,
                reason: "one increasing mesh from 0 to 1 per segment is required",
            });
        }
        let (n, np) = (system.state_dim(), system.parameter_count());
        let ends = EndConditions::new(system, &signature);
        Ok(Self {
            system,
            signature,
            basis: Basis::new(ncol),
            meshes,
            n,
            np,
            ends,
            xi: vec![0.0; n],
            f: vec![0.0; n],
            a: vec![0.0; n * n],
            fp: vec![0.0; n * np],
        })
    }

    fn nodes_in(&self, k: usize) -> usize {
        (self.meshes[k].len() - 1) * self.basis.ncol + 1
    }

    /// Index of the first node value of segment `k` in the local unknowns.
    #[must_use]
    pub fn segment_offset(&self, k: usize) -> usize {
        (0..k).map(|l| self.nodes_in(l) * self.n).sum()
    }

    /// Index of segment `k`'s duration.
    #[must_use]
    pub fn duration_index(&self, k: usize) -> usize {
        self.segment_offset(self.signature.len()) + k
    }

    /// Index of parameter `q`.
    #[must_use]
    pub fn param_index(&self, q: usize) -> usize {
        self.segment_offset(self.signature.len()) + self.signature.len() + q
    }

    fn row_offset(&self, k: usize) -> usize {
        (0..k)
            .map(|l| (self.nodes_in(l) - 1) * self.n + self.n + 1)
            .sum()
    }

    /// The meshes.
    #[must_use]
    pub fn meshes(&self) -> &[Mesh] {
        &self.meshes
    }
}

impl<S: HybridJacobians + ?Sized> ZeroFunction for Collocation<'_, S> {
    fn unknowns(&self) -> usize {
        self.param_index(0) + self.np
    }

    fn equations(&self) -> usize {
        self.row_offset(self.signature.len())
    }

    /// The interior nodes of each mesh interval, read only by that interval's `ncol * n`
    /// collocation equations (none for `ncol == 1`).
    fn local_blocks(&self) -> Vec<LocalBlock> {
        let (n, ncol) = (self.n, self.basis.ncol);
        let mut out = Vec::new();
        if ncol < 2 {
            return out;
        }
        for k in 0..self.signature.len() {
            let (off, r0) = (self.segment_offset(k), self.row_offset(k));
            for j in 0..self.meshes[k].len() - 1 {
                out.push(LocalBlock {
                    equations: r0 + j * ncol * n..r0 + (j + 1) * ncol * n,
                    unknowns: off + (j * ncol + 1) * n..off + (j + 1) * ncol * n,
                });
            }
        }
        out
    }

    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let (n, np, ncol) = (self.n, self.np, self.basis.ncol);
        let kk = self.signature.len();
        let mut out = Vec::new();
        for k in 0..kk {
            let off = self.segment_offset(k);
            let r0 = self.row_offset(k);
            let ntst = self.meshes[k].len() - 1;
            for j in 0..ntst {
                for c in 0..ncol {
                    for i in 0..n {
                        let row = r0 + (j * ncol + c) * n + i;
                        for node in 0..=ncol {
                            for comp in 0..n {
                                out.push((row, off + (j * ncol + node) * n + comp));
                            }
                        }
                        out.push((row, self.duration_index(k)));
                        for q in 0..np {
                            out.push((row, self.param_index(q)));
                        }
                    }
                }
            }
            // Boundary rows: n continuity + 1 end condition.
            let rb = r0 + ntst * ncol * n;
            let last = off + (self.nodes_in(k) - 1) * n;
            let next_off = self.segment_offset((k + 1) % kk);
            for i in 0..=n {
                for comp in 0..n {
                    out.push((rb + i, last + comp));
                }
                for q in 0..np {
                    out.push((rb + i, self.param_index(q)));
                }
                if i < n {
                    if k + 1 == kk && self.ends.symmetric() {
                        for comp in 0..n {
                            out.push((rb + i, next_off + comp));
                        }
                    } else {
                        out.push((rb + i, next_off + i));
                    }
                }
            }
        }
        out
    }

    fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<()> {
        let (n, np, ncol) = (self.n, self.np, self.basis.ncol);
        let kk = self.signature.len();
        let p = u[self.param_index(0)..self.param_index(0) + np].to_vec();
        let mut jac = jacobian;
        let mut pos = 0usize;
        for k in 0..kk {
            let mode = self.signature.segments()[k].mode;
            let off = self.segment_offset(k);
            let r0 = self.row_offset(k);
            let t_k = u[self.duration_index(k)];
            let ntst = self.meshes[k].len() - 1;
            for j in 0..ntst {
                let h = self.meshes[k][j + 1] - self.meshes[k][j];
                let base = off + j * ncol * n;
                for c in 0..ncol {
                    // xi = p(z_c)
                    for comp in 0..n {
                        self.xi[comp] = (0..=ncol)
                            .map(|node| self.basis.l[c][node] * u[base + node * n + comp])
                            .sum();
                    }
                    if jac.is_some() {
                        self.system.vector_field_with_jacobian(
                            mode,
                            &self.xi,
                            &p,
                            &mut self.f,
                            &mut self.a,
                            Some(&mut self.fp),
                        );
                    } else {
                        self.system.vector_field(mode, &self.xi, &p, &mut self.f);
                    }
                    let row = r0 + (j * ncol + c) * n;
                    for i in 0..n {
                        let dp: f64 = (0..=ncol)
                            .map(|node| self.basis.dl[c][node] * u[base + node * n + i])
                            .sum();
                        residual[row + i] = dp - h * t_k * self.f[i];
                    }
                    if let Some(jac) = jac.as_deref_mut() {
                        for i in 0..n {
                            for node in 0..=ncol {
                                for comp in 0..n {
                                    let mut v =
                                        -h * t_k * self.a[i + comp * n] * self.basis.l[c][node];
                                    if comp == i {
                                        v += self.basis.dl[c][node];
                                    }
                                    jac[pos] = v;
                                    pos += 1;
                                }
                            }
                            jac[pos] = -h * self.f[i];
                            pos += 1;
                            for q in 0..np {
                                jac[pos] = -h * t_k * self.fp[i + q * n];
                                pos += 1;
                            }
                        }
                    }
                }
            }
            // Boundary conditions at the segment's end.
            let rb = r0 + ntst * ncol * n;
            let last = off + (self.nodes_in(k) - 1) * n;
            let y = u[last..last + n].to_vec();
            let next_off = self.segment_offset((k + 1) % kk);
            let wrap = k + 1 == kk;
            let target = self.ends.target(wrap, &u[next_off..next_off + n]);
            let end = self.signature.segments()[k].end;
            self.ends.residual(
                self.system,
                end,
                &y,
                &p,
                &target,
                &mut residual[rb..=rb + n],
            );
            let Some(jac) = jac.as_deref_mut() else {
                continue;
            };
            self.ends.linearise(self.system, end, &y, &p);
            for i in 0..=n {
                for comp in 0..n {
                    jac[pos] = self.ends.state_derivative(i, comp);
                    pos += 1;
                }
                for q in 0..np {
                    jac[pos] = self.ends.parameter_derivative(i, q);
                    pos += 1;
                }
                if i < n {
                    self.ends.write_target_entries(i, wrap, jac, &mut pos);
                }
            }
        }
        Ok(())
    }
}

impl<S: HybridJacobians + ?Sized> super::OrbitEquations for Collocation<'_, S> {
    fn closure_entries(&self) -> Vec<usize> {
        let (n, kk) = (self.n, self.signature.len());
        let ntst = self.meshes[kk - 1].len() - 1;
        let rb = self.row_offset(kk - 1) + ntst * self.basis.ncol * n;
        let per_row = if self.ends.symmetric() { n } else { 1 };
        super::end_condition::closure_positions(&self.jacobian_pattern(), rb..rb + n, per_row)
    }
    fn first_parameter(&self) -> usize {
        self.param_index(0)
    }
}

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
    let n = system.state_dim();
    let basis_nodes: Vec<f64> = (0..=ncol).map(|i| i as f64 / ncol as f64).collect();
    let mut out = Vec::new();
    for (k, seg) in orbit.signature.segments().iter().enumerate() {
        let taus: Vec<f64> = meshes[k]
            .windows(2)
            .flat_map(|w| {
                let (a, b) = (w[0], w[1]);
                basis_nodes[..ncol].iter().map(move |z| a + z * (b - a))
            })
            .chain(std::iter::once(1.0))
            .collect();
        // Uniform meshes: one run with the node times as samples (dense output); otherwise
        // integrate from node to node.
        let flow = super::flow::SegmentFlow::plain(system, seg.mode);
        let uniform = meshes[k]
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
    let problem = super::orbit_problem(system, Box::new(coll), first_param, &orbit.params)?;
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
    unpack_nodes(u, like, &sizes, like.starts[0].len())
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
    condense::factorised_floquet(system, orbit, meshes, nodes, ncol, jacobian)
}

fn unpack_nodes(
    u: &[f64],
    like: &PeriodicOrbit,
    sizes: &[usize],
    n: usize,
) -> (Vec<Vec<f64>>, PeriodicOrbit) {
    let mut nodes = Vec::new();
    let mut pos = 0;
    for &m in sizes {
        nodes.push(u[pos..pos + m * n].to_vec());
        pos += m * n;
    }
    let kk = sizes.len();
    let durations = u[pos..pos + kk].to_vec();
    let params = u[pos + kk..pos + kk + like.params.len()].to_vec();
    let starts = nodes.iter().map(|v| v[..n].to_vec()).collect();
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
/// As [`super::solve_shooting`]; invalid settings.
pub fn solve_collocation<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<CollocationSolution> {
    let sol = solve_collocation_unchecked(system, guess, settings, newton_settings)?;
    super::check_admissible(system, &sol.solution.orbit)?;
    Ok(sol)
}

/// [`solve_collocation`] without the admissibility check (a continuation that watches
/// admissibility itself, or has it switched off, starts from any solution).
pub(crate) fn solve_collocation_unchecked<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    settings: CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<CollocationSolution> {
    settings.validate()?;
    guess.validate(system)?;
    let n = system.state_dim();
    let kk = guess.segment_count();
    let mut meshes: Vec<Mesh> = (0..kk).map(|_| uniform_mesh(settings.ntst)).collect();
    let mut nodes = initial_nodes(system, guess, &meshes, settings.ncol)?;
    let mut orbit = guess.clone();
    let basis = Basis::new(settings.ncol);
    let sizes = vec![settings.ntst * settings.ncol + 1; kk];
    let mut history = Vec::new();
    let mut residual = 0.0;
    for pass in 0..=settings.adapt {
        if pass > 0 {
            // Move to the adapted meshes, interpolating the current solution.
            let new_meshes: Vec<Mesh> = (0..kk)
                .map(|k| adapted_mesh(&nodes[k], &meshes[k], &basis, n))
                .collect();
            let bn = basis.nodes();
            let mut new_nodes = Vec::new();
            for k in 0..kk {
                let mut vals = Vec::new();
                let mut x = vec![0.0; n];
                for w in new_meshes[k].windows(2) {
                    for z in &bn[..settings.ncol] {
                        eval_piecewise(
                            &nodes[k],
                            &meshes[k],
                            settings.ncol,
                            n,
                            w[0] + z * (w[1] - w[0]),
                            &mut x,
                        );
                        vals.extend_from_slice(&x);
                    }
                }
                vals.extend_from_slice(&nodes[k][nodes[k].len() - n..]);
                new_nodes.push(vals);
            }
            meshes = new_meshes;
            nodes = new_nodes;
        }
        let (mut problem, _) =
            collocation_problem_impl(system, &orbit, meshes.clone(), settings.ncol)?;
        let sol = newton(&mut problem, &pack_nodes(&nodes, &orbit), newton_settings)?;
        let (nd, ob) = unpack_nodes(&sol.u, &orbit, &sizes, n);
        nodes = nd;
        orbit = ob;
        residual = sol.residual;
        history.extend(sol.history);
    }
    let floquet = condensed_floquet(system, &orbit, &meshes, &nodes, settings.ncol)?;
    Ok(CollocationSolution {
        solution: OrbitSolution {
            orbit,
            floquet,
            newton: history,
            residual,
        },
        meshes,
        nodes,
        settings,
    })
}
