//! The discretisation of an orbit's boundary-value problem as data: the method and the layout
//! of its unknowns, enough to turn a point's unknowns back into an orbit, to rebuild the
//! problem (restarts, branch switching, curves) and to compute multipliers. Serialisable, so
//! that saved runs of either method can be restarted.
//!
//! Unknowns of both methods: the segment states first (shooting: each segment's start;
//! collocation: each segment's `ntst * ncol + 1` node states), then the $K$ durations, then the
//! parameters.

use super::collocation::{
    Collocation, CollocationSettings, Mesh, collocation_floquet, collocation_floquet_factorised,
    collocation_pack, collocation_unpack, initial_nodes,
};
use super::shooting::{LinearizationCache, Shooting, ShootingSettings};
use super::{Floquet, PeriodicOrbit, monodromy_by_shooting, monodromy_from_cache, pack, unpack};
use crate::error::Result;
use crate::problem::{Activity, NewtonSettings, Problem, UnknownMonitor, ZeroFunction};
use crate::system::{HybridJacobians, HybridSystem, Z2Symmetry};
use serde::{Deserialize, Serialize};

/// How to discretise an orbit's boundary-value problem (the user's choice; see
/// [`Discretisation`] for the resulting layout).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum OrbitMethod {
    /// Multiple shooting on the variational equations.
    Shooting(ShootingSettings),
    /// Orthogonal collocation (the mesh is adapted when the orbit is first solved).
    Collocation(CollocationSettings),
}

impl Default for OrbitMethod {
    /// Shooting with default settings.
    fn default() -> Self {
        OrbitMethod::Shooting(ShootingSettings::default())
    }
}

/// A discretised orbit problem's layout.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Discretisation {
    /// Multiple shooting: unknowns are the segment starts, durations and parameters.
    Shooting(ShootingSettings),
    /// Collocation on these meshes (one per segment) with polynomials of degree `ncol`.
    Collocation {
        /// One mesh per segment.
        meshes: Vec<Mesh>,
        /// Collocation points per interval.
        ncol: usize,
    },
}

/// The equations of a discretised orbit problem: a [`ZeroFunction`] over the unknowns of
/// [`Discretisation`], closing the last segment onto the first (periodic or symmetric).
pub trait OrbitEquations: ZeroFunction {
    /// Positions, in the Jacobian's values, of the closure's coupling of the last segment's end
    /// conditions to the first segment's start ($-I$, or $-S$ for a half orbit). Scaling them by
    /// $c$ gives the Jacobian of the problem closed by $x_K = c\,x_0$ ($c\,S x_0$): $c = -1$ is
    /// singular where a multiplier is $-1$.
    fn closure_entries(&self) -> Vec<usize>;
    /// Local index of the first parameter (segment states and durations come before).
    fn first_parameter(&self) -> usize;
}

/// A problem over `part`'s unknowns, with every parameter held by an inactive monitor named
/// after it (the first parameter at local index `first_param`).
///
/// # Errors
/// If the part's unknowns cannot be indexed.
pub fn orbit_problem<'a, S: HybridSystem + ?Sized>(
    system: &S,
    part: Box<dyn ZeroFunction + 'a>,
    first_param: usize,
    params: &[f64],
) -> Result<Problem<'a>> {
    let nu = part.unknowns();
    let mut problem = Problem::new(nu);
    problem.add_part(part, (0..nu).collect())?;
    for (q, name) in system.parameter_names().iter().enumerate() {
        problem.add_monitor(
            name,
            Box::new(UnknownMonitor),
            vec![first_param + q],
            Activity::Inactive(params[q]),
        )?;
    }
    Ok(problem)
}

impl Discretisation {
    /// The discretisation of `orbit` by `method` with the starting unknowns and the orbit they
    /// hold: shooting packs the orbit as it is (the first continuation step solves it);
    /// collocation solves it (adapting the mesh) and keeps the mesh.
    ///
    /// # Errors
    /// Invalid settings, or a collocation solve that fails.
    pub fn prepare<S: HybridJacobians + ?Sized>(
        method: &OrbitMethod,
        system: &S,
        orbit: &PeriodicOrbit,
    ) -> Result<(Self, PeriodicOrbit, Vec<f64>)> {
        orbit.validate(system)?;
        match *method {
            OrbitMethod::Shooting(settings) => {
                Ok((Self::Shooting(settings), orbit.clone(), pack(orbit)))
            }
            OrbitMethod::Collocation(settings) => {
                // The continuation watches admissibility along the branch (or is asked not to).
                // (Its multipliers are not needed: the continuation analyses its points.)
                let sol = super::collocation::solve_collocation_nodes(
                    system,
                    orbit,
                    settings,
                    &NewtonSettings::default(),
                )?;
                let u = sol.unknowns();
                Ok((
                    Self::Collocation {
                        meshes: sol.meshes,
                        ncol: settings.ncol,
                    },
                    sol.orbit,
                    u,
                ))
            }
        }
    }

    /// The equations for orbits with `like`'s signature; shooting records its linearisations
    /// into `cache` when given.
    ///
    /// # Errors
    /// Invalid settings or meshes.
    pub fn equations<'a, S: HybridJacobians + ?Sized>(
        &self,
        system: &'a S,
        like: &PeriodicOrbit,
        cache: Option<LinearizationCache>,
    ) -> Result<Box<dyn OrbitEquations + 'a>> {
        Ok(match self {
            Self::Shooting(s) => {
                let eq = Shooting::new(system, like.signature.clone(), *s)?;
                Box::new(match cache {
                    Some(c) => eq.with_cache(c),
                    None => eq,
                })
            }
            Self::Collocation { meshes, ncol } => Box::new(Collocation::new(
                system,
                like.signature.clone(),
                meshes.clone(),
                *ncol,
            )?),
        })
    }

    /// The problem of orbits like `like` (parameters held at `like`'s values by monitors named
    /// after them), with the shooting linearisations recorded into `cache` when given.
    ///
    /// # Errors
    /// As [`Discretisation::equations`].
    pub fn problem<'a, S: HybridJacobians + ?Sized>(
        &self,
        system: &'a S,
        like: &PeriodicOrbit,
        cache: Option<LinearizationCache>,
    ) -> Result<Problem<'a>> {
        let eq = self.equations(system, like, cache)?;
        let first = eq.first_parameter();
        orbit_problem(system, eq, first, &like.params)
    }

    /// The unknowns of `orbit` (collocation: node states by integrating the segments).
    ///
    /// # Errors
    /// An integration failure.
    pub fn pack<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
    ) -> Result<Vec<f64>> {
        match self {
            Self::Shooting(_) => Ok(pack(orbit)),
            Self::Collocation { meshes, ncol } => {
                let nodes = initial_nodes(system, orbit, meshes, *ncol)?;
                Ok(collocation_pack(&nodes, orbit))
            }
        }
    }

    /// The orbit at unknowns `u` (signature and parameter count of `like`).
    #[must_use]
    pub fn unpack(&self, like: &PeriodicOrbit, u: &[f64]) -> PeriodicOrbit {
        match self {
            Self::Shooting(_) => unpack(like, u),
            Self::Collocation { meshes, ncol } => collocation_unpack(like, meshes, *ncol, u).1,
        }
    }

    /// The estimated largest discretisation error of the orbit at unknowns `u`, in the units of
    /// the state (collocation: [`super::collocation_error_estimate`]); `None` for shooting,
    /// whose error is the integrator's tolerance.
    #[must_use]
    pub fn error_estimate(&self, like: &PeriodicOrbit, u: &[f64]) -> Option<f64> {
        match self {
            Self::Shooting(_) => None,
            Self::Collocation { meshes, ncol } => {
                Some(super::collocation_error_estimate(like, meshes, *ncol, u))
            }
        }
    }

    /// The discretisation adapted to the orbit at unknowns `u`, with the same layout (collocation:
    /// meshes with the same intervals equidistributing the error estimate,
    /// [`super::collocation_adapted_meshes`]; shooting: itself).
    #[must_use]
    pub fn adapted(&self, like: &PeriodicOrbit, u: &[f64]) -> Self {
        match self {
            Self::Shooting(_) => self.clone(),
            Self::Collocation { meshes, ncol } => Self::Collocation {
                meshes: super::collocation_adapted_meshes(like, meshes, *ncol, u),
                ncol: *ncol,
            },
        }
    }

    /// [`Discretisation::adapted`], with more intervals where the error estimate at `u`
    /// exceeds `tolerance` (collocation: [`super::collocation_refined_meshes`], which aims at
    /// half the tolerance; the layout then changes).
    #[must_use]
    pub fn refined(&self, like: &PeriodicOrbit, u: &[f64], tolerance: f64) -> Self {
        match self {
            Self::Shooting(_) => self.clone(),
            Self::Collocation { meshes, ncol } => Self::Collocation {
                meshes: super::collocation_refined_meshes(like, meshes, *ncol, u, tolerance),
                ncol: *ncol,
            },
        }
    }

    /// Whether `other` has the same layout of unknowns (and Jacobian pattern): the same
    /// method, and for collocation the same degree and intervals per segment.
    #[must_use]
    pub fn same_layout(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Shooting(_), Self::Shooting(_)) => true,
            (
                Self::Collocation { meshes: a, ncol: p },
                Self::Collocation { meshes: b, ncol: q },
            ) => p == q && a.iter().map(Vec::len).eq(b.iter().map(Vec::len)),
            _ => false,
        }
    }

    /// The largest move of a mesh point from this discretisation to `other` (relative to the
    /// segment's time, so in $[0, 1]$); infinite between different layouts, 0 for shooting.
    #[must_use]
    pub fn distance(&self, other: &Self) -> f64 {
        match (self, other) {
            _ if !self.same_layout(other) => f64::INFINITY,
            (Self::Collocation { meshes: a, .. }, Self::Collocation { meshes: b, .. }) => a
                .iter()
                .zip(b)
                .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs()))
                .fold(0.0, f64::max),
            _ => 0.0,
        }
    }

    /// Unknowns `u` of this discretisation (followed by anything a problem appends) carried over
    /// to `to` (collocation to collocation with the same `ncol` and segments:
    /// [`super::collocation_transfer`], linear in `u`, so tangents carry over too).
    ///
    /// # Errors
    /// [`crate::Error::InvalidSetting`] if the two discretisations are not both collocation
    /// with the same `ncol` and number of segments, or `u` is too short.
    pub fn transfer(&self, to: &Self, like: &PeriodicOrbit, u: &[f64]) -> Result<Vec<f64>> {
        match (self, to) {
            (
                Self::Collocation { meshes, ncol },
                Self::Collocation {
                    meshes: new,
                    ncol: new_ncol,
                },
            ) if ncol == new_ncol
                && meshes.len() == new.len()
                && meshes.len() == like.segment_count()
                && u.len() >= self.segment_values(like) =>
            {
                Ok(super::collocation_transfer(like, meshes, new, *ncol, u))
            }
            _ => Err(crate::Error::InvalidSetting {
                name: "discretisation transfer",
                value: u.len() as f64,
                reason: "needs two collocation discretisations of the same degree and segments, and the first one's unknowns",
            }),
        }
    }

    /// Floquet multipliers at unknowns `u` (shooting: from `cache` when it holds this orbit's
    /// linearisations, else by integrating; collocation: by condensation of the collocation
    /// Jacobian). On a half orbit, the half map's monodromy (before $S$).
    ///
    /// # Errors
    /// Integration, singular blocks or eigenvalue failures.
    pub fn floquet<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        like: &PeriodicOrbit,
        u: &[f64],
        cache: Option<&LinearizationCache>,
    ) -> Result<(PeriodicOrbit, Floquet)> {
        match self {
            Self::Shooting(s) => {
                let orbit = unpack(like, u);
                let cached = match cache {
                    Some(c) => monodromy_from_cache(system, &orbit, c)?,
                    None => None,
                };
                let f = match cached {
                    Some(f) => f,
                    None => monodromy_by_shooting(system, &orbit, *s)?,
                };
                Ok((orbit, f))
            }
            Self::Collocation { meshes, ncol } => {
                let (nodes, orbit) = collocation_unpack(like, meshes, *ncol, u);
                let f = collocation_floquet(system, &orbit, meshes, &nodes, *ncol)?;
                Ok((orbit, f))
            }
        }
    }

    /// [`Discretisation::floquet`] from a factorisation of the problem's Jacobian at `u` that
    /// has condensed collocation's intervals already (see [`collocation_floquet_factorised`]):
    /// `Ok(None)` for shooting or when the factorisation cannot be used.
    ///
    /// # Errors
    /// As [`Discretisation::floquet`].
    pub fn floquet_factorised<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        like: &PeriodicOrbit,
        u: &[f64],
        jacobian: &crate::linalg::SparsePattern,
    ) -> Result<Option<(PeriodicOrbit, Floquet)>> {
        let Self::Collocation { meshes, ncol } = self else {
            return Ok(None);
        };
        let (nodes, orbit) = collocation_unpack(like, meshes, *ncol, u);
        let f = collocation_floquet_factorised(system, &orbit, meshes, &nodes, *ncol, jacobian)?;
        Ok(f.map(|f| (orbit, f)))
    }

    /// The number of unknowns holding segment states (they come first).
    #[must_use]
    pub fn segment_values(&self, like: &PeriodicOrbit) -> usize {
        (0..like.segment_count())
            .map(|k| self.values_of_segment(like, k))
            .sum()
    }

    /// The unknowns of segment `k`'s states: its start (shooting) or its nodes (collocation),
    /// each of its mode's dimension.
    fn values_of_segment(&self, like: &PeriodicOrbit, k: usize) -> usize {
        let n = like.starts[k].len();
        match self {
            Self::Shooting(_) => n,
            Self::Collocation { meshes, ncol } => ((meshes[k].len() - 1) * ncol + 1) * n,
        }
    }

    /// The indices of the unknowns an orbit is read from: the segment starts (collocation: each
    /// segment's first node), the durations and the parameters. A function of the orbit
    /// ([`super::Measure`]) depends on these only.
    #[must_use]
    pub fn orbit_columns(&self, like: &PeriodicOrbit) -> Vec<usize> {
        let kk = like.segment_count();
        let nv = self.segment_values(like);
        let mut cols = Vec::new();
        match self {
            Self::Shooting(_) => cols.extend(0..nv),
            Self::Collocation { meshes, ncol } => {
                let mut off = 0;
                for (m, x) in meshes.iter().zip(&like.starts) {
                    let n = x.len();
                    cols.extend(off..off + n);
                    off += ((m.len() - 1) * ncol + 1) * n;
                }
            }
        }
        cols.extend(nv..nv + kk + like.params.len());
        cols
    }

    /// Arclength weights of the unknowns (see the continuation's weighted norm): collocation
    /// weighs each segment's node values by `copies / nodes` (a mean square, independent of the
    /// mesh), shooting's starts by `copies`; durations weigh `copies`, everything else 1.
    /// `None` when every weight would be 1. `copies` is 2 on a half orbit (its segments stand
    /// for the full orbit's two copies).
    #[must_use]
    pub fn unknown_weights(
        &self,
        like: &PeriodicOrbit,
        copies: f64,
        total: usize,
    ) -> Option<Vec<f64>> {
        let mut w = Vec::with_capacity(total);
        match self {
            Self::Shooting(_) if copies == 1.0 => return None,
            Self::Shooting(_) => w.resize(self.segment_values(like), copies),
            Self::Collocation { meshes, ncol } => {
                for (m, x) in meshes.iter().zip(&like.starts) {
                    let nodes = (m.len() - 1) * ncol + 1;
                    w.extend(std::iter::repeat_n(copies / nodes as f64, nodes * x.len()));
                }
            }
        }
        w.extend(std::iter::repeat_n(copies, like.segment_count()));
        w.resize(total, 1.0);
        Some(w)
    }

    /// The discretisation of an orbit made of `copies` copies of these segments (collocation:
    /// each mesh repeated).
    #[must_use]
    pub fn repeated(&self, copies: usize) -> Self {
        match self {
            Self::Shooting(s) => Self::Shooting(*s),
            Self::Collocation { meshes, ncol } => Self::Collocation {
                meshes: (0..copies).flat_map(|_| meshes.iter().cloned()).collect(),
                ncol: *ncol,
            },
        }
    }

    /// Unknowns (or a tangent) `v` of an orbit like `like` with its segments repeated: the
    /// segment values followed by their images under `image` (each state mapped; `None`: a
    /// plain copy), the durations twice, then the rest. The unknowns of the full orbit of a half
    /// orbit, or of an orbit traversed twice, in [`Discretisation::repeated`]`(2)`.
    #[must_use]
    pub fn repeat_unknowns(
        &self,
        like: &PeriodicOrbit,
        v: &[f64],
        image: Option<&Z2Symmetry>,
    ) -> Vec<f64> {
        let (nv, kk) = (self.segment_values(like), like.segment_count());
        let mut out = Vec::with_capacity(v.len() + nv + kk);
        out.extend_from_slice(&v[..nv]);
        match image {
            Some(sym) => {
                // Segment by segment: its values are states of its mode's dimension, mapped by
                // S's leading block (the sums of `Z2Symmetry::apply`, in its order, from -0).
                let mut at = 0;
                for (k, x0) in like.starts.iter().enumerate() {
                    let (n, len) = (x0.len(), self.values_of_segment(like, k));
                    let s = sym.block_ref(n);
                    let x = &v[at..at + len];
                    // A diagonal S (e.g. -I) maps each component alone: the values of the full
                    // product, whose other terms are exact zeros for finite states (a zero's
                    // sign aside); `-0 + p = p` for every product.
                    let diagonal = (0..n * n).all(|k| k % (n + 1) == 0 || s[k] == 0.0);
                    if diagonal && crate::error::all_finite(x) {
                        out.extend_from_slice(x);
                        scale_by_diagonal(&mut out[nv + at..], &s, n);
                    } else {
                        out.resize(nv + at + len, -0.0);
                        let y = &mut out[nv + at..nv + at + len];
                        for (x, y) in x.chunks_exact(n.max(1)).zip(y.chunks_exact_mut(n.max(1))) {
                            for (col, &xj) in s.chunks_exact(n).zip(x) {
                                for (o, sij) in y.iter_mut().zip(col) {
                                    *o += sij * xj;
                                }
                            }
                        }
                    }
                    at += len;
                }
            }
            None => out.extend_from_slice(&v[..nv]),
        }
        out.extend_from_slice(&v[nv..nv + kk]);
        out.extend_from_slice(&v[nv..nv + kk]);
        out.extend_from_slice(&v[nv + kk..]);
        out
    }

    /// The method this discretisation was made by (collocation: the mesh size of the first
    /// segment, no adaptation).
    #[must_use]
    pub fn method(&self) -> OrbitMethod {
        match self {
            Self::Shooting(s) => OrbitMethod::Shooting(*s),
            Self::Collocation { meshes, ncol } => OrbitMethod::Collocation(CollocationSettings {
                ntst: meshes.first().map_or(1, |m| m.len() - 1),
                ncol: *ncol,
                adapt: 0,
            }),
        }
    }
}

/// Each state of `y` (`n` values) multiplied component by component by the diagonal of the
/// column-major `n x n` matrix `s`, in place (`x d` is `d x` to the bit). For the state
/// dimensions of common systems with `n` known at compile time, so that the loop vectorises.
fn scale_by_diagonal(y: &mut [f64], s: &[f64], n: usize) {
    match n {
        2 => scale_fixed::<2>(y, s),
        4 => scale_fixed::<4>(y, s),
        6 => scale_fixed::<6>(y, s),
        8 => scale_fixed::<8>(y, s),
        _ => {
            for state in y.chunks_exact_mut(n.max(1)) {
                for (i, v) in state.iter_mut().enumerate() {
                    *v *= s[i * (n + 1)];
                }
            }
        }
    }
}

/// [`scale_by_diagonal`] with `N` known at compile time.
fn scale_fixed<const N: usize>(y: &mut [f64], s: &[f64]) {
    let d: [f64; N] = std::array::from_fn(|i| s[i * (N + 1)]);
    for state in y.chunks_exact_mut(N) {
        for (v, di) in state.iter_mut().zip(&d) {
            *v *= di;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::scale_by_diagonal;

    /// Every state dimension (those with a compile-time kernel and the others) scales each
    /// state's component `i` by `S[i, i]` alone, to the bit, whatever the off-diagonal entries.
    #[test]
    fn diagonal_scaling_maps_each_component_by_its_entry() {
        for n in 1..=9 {
            let s: Vec<f64> = (0..n * n).map(|k| 0.5 - (k % 7) as f64).collect();
            let states = 5;
            let x: Vec<f64> = (0..states * n).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut y = x.clone();
            scale_by_diagonal(&mut y, &s, n);
            for (i, (yi, xi)) in y.iter().zip(&x).enumerate() {
                let d = s[(i % n) * (n + 1)];
                assert_eq!(yi.to_bits(), (d * xi).to_bits(), "n = {n}, value {i}");
            }
        }
    }
}
