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
mod columns;
mod condense;
mod mesh;
mod solve;
mod transfer;

use super::end_condition::EndConditions;
use super::signature::Signature;
use crate::error::{Error, Result};
use crate::problem::{LocalBlock, ZeroFunction};
use crate::system::HybridJacobians;
use basis::Basis;
pub use basis::gauss_legendre_points;
use columns::{NodeColumns, interpolate, interpolate_any, node_of_group};
use serde::{Deserialize, Serialize};
pub use solve::{
    CollocationSolution, collocation_adapted_meshes, collocation_error_estimate,
    collocation_floquet, collocation_floquet_factorised, collocation_pack, collocation_problem,
    collocation_refined_meshes, collocation_transfer, collocation_unpack, solve_collocation,
};
pub(crate) use solve::{initial_nodes, solve_collocation_admissible, solve_collocation_nodes};

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
    /// Per segment: its mode's state dimension $n_k$.
    dims: Vec<usize>,
    np: usize,
    ends: EndConditions,
    // Work space.
    xi: Vec<f64>,
    dx: Vec<f64>,
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
        let dims = (signature.segments().iter())
            .map(|seg| system.mode_dim(seg.mode))
            .collect();
        Ok(Self {
            system,
            signature,
            basis: Basis::shared(ncol).into_owned(),
            meshes,
            dims,
            np,
            ends,
            xi: vec![0.0; n],
            dx: vec![0.0; n],
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
        (0..k).map(|l| self.nodes_in(l) * self.dims[l]).sum()
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

    /// The first equation of segment `k`: each segment has its collocation equations and
    /// the $n_{k+1} + 1$ conditions at its end.
    fn row_offset(&self, k: usize) -> usize {
        (0..k)
            .map(|l| (self.nodes_in(l) - 1) * self.dims[l] + self.next_dim(l) + 1)
            .sum()
    }

    /// The dimension of the state segment `k` ends in (the next segment's).
    fn next_dim(&self, k: usize) -> usize {
        self.dims[(k + 1) % self.dims.len()]
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

    /// Every interval's block is written whole (each collocation point its rows of every
    /// column), and every segment end's rows.
    fn writes_every_entry(&self) -> bool {
        true
    }

    /// The interior nodes of each mesh interval, read only by that interval's `ncol * n`
    /// collocation equations (none for `ncol == 1`).
    fn local_blocks(&self) -> Vec<LocalBlock> {
        let ncol = self.basis.ncol;
        let mut out = Vec::new();
        if ncol < 2 {
            return out;
        }
        for k in 0..self.signature.len() {
            let (off, r0, n) = (self.segment_offset(k), self.row_offset(k), self.dims[k]);
            for j in 0..self.meshes[k].len() - 1 {
                out.push(LocalBlock {
                    equations: r0 + j * ncol * n..r0 + (j + 1) * ncol * n,
                    unknowns: off + (j * ncol + 1) * n..off + (j + 1) * ncol * n,
                });
            }
        }
        out
    }

    /// Each mesh interval's entries in the column-major order of its dense block (its `ncol * n`
    /// equations over the interior nodes, the first and the last node, the duration and the
    /// parameters), so that a condensing factorisation copies them as runs; then each segment's
    /// boundary rows.
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let (np, ncol) = (self.np, self.basis.ncol);
        let kk = self.signature.len();
        // The exact length: a large system's pattern has millions of entries, and a vector
        // grown by doubling would hold up to twice them.
        let len = self.jacobian_len();
        let mut out = Vec::with_capacity(len);
        for k in 0..kk {
            let (n, n_to) = (self.dims[k], self.next_dim(k));
            let off = self.segment_offset(k);
            let r0 = self.row_offset(k);
            let ntst = self.meshes[k].len() - 1;
            for j in 0..ntst {
                let rows = r0 + j * ncol * n..r0 + (j + 1) * ncol * n;
                let node_cols = (0..=ncol)
                    .map(|g| node_of_group(g, ncol))
                    .flat_map(|node| (0..n).map(move |comp| off + (j * ncol + node) * n + comp));
                let cols = node_cols
                    .chain(std::iter::once(self.duration_index(k)))
                    .chain((0..np).map(|q| self.param_index(q)));
                for col in cols {
                    out.extend(rows.clone().map(|row| (row, col)));
                }
            }
            // Boundary rows: n_{k+1} continuity + 1 end condition.
            let rb = r0 + ntst * ncol * n;
            let last = off + (self.nodes_in(k) - 1) * n;
            let next_off = self.segment_offset((k + 1) % kk);
            for i in 0..=n_to {
                for comp in 0..n {
                    out.push((rb + i, last + comp));
                }
                for q in 0..np {
                    out.push((rb + i, self.param_index(q)));
                }
                if i < n_to {
                    if k + 1 == kk && self.ends.symmetric() {
                        for comp in 0..n_to {
                            out.push((rb + i, next_off + comp));
                        }
                    } else {
                        out.push((rb + i, next_off + i));
                    }
                }
            }
        }
        debug_assert_eq!(out.len(), len);
        out
    }

    /// Each interval's dense block ($n_{col} n$ rows over $n_{col} + 1$ nodes, the duration
    /// and the parameters), then each segment's boundary rows.
    fn jacobian_len(&self) -> usize {
        let (np, ncol) = (self.np, self.basis.ncol);
        let kk = self.signature.len();
        (0..kk)
            .map(|k| {
                let (n, n_to) = (self.dims[k], self.next_dim(k));
                let ntst = self.meshes[k].len() - 1;
                let symmetric = k + 1 == kk && self.ends.symmetric();
                ntst * ncol * n * ((ncol + 1) * n + 1 + np)
                    + (n_to + 1) * (n + np)
                    + n_to * if symmetric { n_to } else { 1 }
            })
            .sum()
    }

    fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<()> {
        crate::linalg::dense::vectorized(
            #[inline(always)]
            || self.evaluate_intervals(u, residual, jacobian),
        )
    }
}

impl<S: HybridJacobians + ?Sized> Collocation<'_, S> {
    /// [`ZeroFunction::evaluate`]'s body, which it runs compiled for the widest vectors the
    /// processor has (`linalg::dense::vectorized`: the interpolation and the node columns in
    /// 4-lane operations for 4 states; the same numbers).
    #[inline(always)]
    fn evaluate_intervals(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<()> {
        let (np, ncol) = (self.np, self.basis.ncol);
        let p = &u[self.param_index(0)..self.param_index(0) + np];
        let mut jac = jacobian;
        let mut pos = 0usize;
        for k in 0..self.signature.len() {
            let (n, n_to) = (self.dims[k], self.next_dim(k));
            // An interval's block: `ncol * n` rows by the nodes, the duration, the parameters.
            let block = ncol * n * ((ncol + 1) * n + 1 + np);
            let mode = self.signature.segments()[k].mode;
            let (off, r0) = (self.segment_offset(k), self.row_offset(k));
            let t_k = u[self.duration_index(k)];
            let ntst = self.meshes[k].len() - 1;
            for j in 0..ntst {
                let h = self.meshes[k][j + 1] - self.meshes[k][j];
                let base = off + j * ncol * n;
                let nodes = &u[base..base + (ncol + 1) * n];
                let mut out = jac.as_deref_mut().map(|jv| &mut jv[pos..pos + block]);
                for c in 0..ncol {
                    let row = r0 + (j * ncol + c) * n;
                    let point = Point {
                        mode,
                        n,
                        c,
                        h,
                        t: t_k,
                    };
                    let res = &mut residual[row..row + n];
                    self.collocation_point(point, nodes, p, res, out.as_deref_mut())?;
                }
                if jac.is_some() {
                    pos += block;
                }
            }
            let rb = r0 + ntst * ncol * n;
            self.segment_end(
                k,
                u,
                p,
                &mut residual[rb..=rb + n_to],
                jac.as_deref_mut(),
                &mut pos,
            )?;
        }
        Ok(())
    }
}

/// A collocation point: its segment's mode and state dimension, its index in the interval, the
/// interval's length and the segment's duration.
#[derive(Clone, Copy)]
struct Point {
    mode: crate::system::Mode,
    /// The mode's state dimension.
    n: usize,
    c: usize,
    h: f64,
    t: f64,
}

impl<S: HybridJacobians + ?Sized> Collocation<'_, S> {
    /// The `n` equations at collocation point `at` of the interval with node values `nodes`
    /// (and, with `jac`, their rows of the Jacobian: the nodes, the duration, the parameters).
    ///
    /// # Errors
    /// [`crate::Error::NonFiniteVectorField`] or [`crate::Error::NonFiniteDerivative`] where
    /// the vector field or its Jacobian is not finite at the point (`t` there is the
    /// segment's duration).
    #[inline(always)]
    fn collocation_point(
        &mut self,
        at: Point,
        nodes: &[f64],
        p: &[f64],
        res: &mut [f64],
        jac: Option<&mut [f64]>,
    ) -> Result<()> {
        let (n, np) = (at.n, self.np);
        let (lc, dlc) = (&self.basis.l[at.c], &self.basis.dl[at.c]);
        let (xi, f) = (&mut self.xi[..n], &mut self.f[..n]);
        let (a, fp) = (&mut self.a[..n * n], &mut self.fp[..n * np]);
        let dx = &mut self.dx[..n];
        // xi = p(z_c), dx = p'(z_c) (per unit of the interval's coordinate).
        match n {
            1 => interpolate::<1>(nodes, (lc, dlc), xi, dx),
            2 => interpolate::<2>(nodes, (lc, dlc), xi, dx),
            3 => interpolate::<3>(nodes, (lc, dlc), xi, dx),
            4 => interpolate::<4>(nodes, (lc, dlc), xi, dx),
            5 => interpolate::<5>(nodes, (lc, dlc), xi, dx),
            6 => interpolate::<6>(nodes, (lc, dlc), xi, dx),
            _ => interpolate_any(nodes, (lc, dlc), xi, dx),
        }
        if jac.is_some() {
            (self.system).vector_field_with_jacobian(at.mode, xi, p, f, a, Some(fp));
            let of = || format!("vector field of mode {}", at.mode);
            crate::error::finite_derivative(a, n, ("state", 0), of, xi)?;
            crate::error::finite_derivative(fp, n, ("parameter", 0), of, xi)?;
        } else {
            self.system.vector_field(at.mode, xi, p, f);
        }
        if let Some(index) = f.iter().position(|v| !v.is_finite()) {
            return Err(crate::Error::NonFiniteVectorField {
                t: at.t,
                mode: at.mode,
                index,
                value: f[index],
                state: xi.to_vec(),
            });
        }
        let ht = -at.h * at.t;
        for ((r, f), d) in res.iter_mut().zip(f.iter()).zip(dx.iter()) {
            *r = d + ht * f;
        }
        let Some(block) = jac else {
            return Ok(());
        };
        // Rows (c, i) of the interval's column-major block (`ncol * n` rows): column (node,
        // comp) is L_node'(z_c) e_comp - h T L_node(z_c) A[:, comp] on the point's n rows; then
        // the duration's column -h f and the parameters' -h T f_p.
        let ncol = self.basis.ncol;
        let rows = ncol * n;
        let (h, at) = (at.h, at.c * n);
        let nodes = NodeColumns {
            block: &mut *block,
            rows,
            at,
            a,
            l: lc,
            dl: dlc,
            ht,
        };
        match n {
            1 => nodes.write::<1>(),
            2 => nodes.write::<2>(),
            3 => nodes.write::<3>(),
            4 => nodes.write::<4>(),
            5 => nodes.write::<5>(),
            6 => nodes.write::<6>(),
            _ => nodes.write_any(n),
        }
        let mut rest = block[(ncol + 1) * n * rows..].chunks_exact_mut(rows);
        if let Some(col) = rest.next() {
            for (o, f) in col[at..at + n].iter_mut().zip(f.iter()) {
                *o = -h * f;
            }
        }
        for (col, fp) in rest.zip(fp.chunks_exact(n)) {
            for (o, d) in col[at..at + n].iter_mut().zip(fp) {
                *o = ht * d;
            }
        }
        Ok(())
    }

    /// The `n_{k+1} + 1` conditions at the end of segment `k` (continuity into the next segment and
    /// the end condition) and, with `jac`, their Jacobian entries from `pos` on.
    fn segment_end(
        &mut self,
        k: usize,
        u: &[f64],
        p: &[f64],
        res: &mut [f64],
        jac: Option<&mut [f64]>,
        pos: &mut usize,
    ) -> Result<()> {
        let (np, kk) = (self.np, self.signature.len());
        let (n, n_to) = (self.dims[k], self.next_dim(k));
        let last = self.segment_offset(k) + (self.nodes_in(k) - 1) * n;
        let y = &u[last..last + n];
        let next_off = self.segment_offset((k + 1) % kk);
        let wrap = k + 1 == kk;
        let next = (wrap, &u[next_off..next_off + n_to]);
        let segment = self.signature.segments()[k];
        let end = segment.end;
        (self.ends).residual(self.system, (segment.mode, end), y, p, next, res)?;
        let Some(jac) = jac else {
            return Ok(());
        };
        self.ends.linearise(self.system, end, (y, n_to), p)?;
        for i in 0..=n_to {
            for comp in 0..n {
                jac[*pos] = self.ends.state_derivative(i, comp);
                *pos += 1;
            }
            for q in 0..np {
                jac[*pos] = self.ends.parameter_derivative(i, q);
                *pos += 1;
            }
            if i < n_to {
                self.ends.write_target_entries(i, wrap, jac, pos);
            }
        }
        Ok(())
    }
}

impl<S: HybridJacobians + ?Sized> super::OrbitEquations for Collocation<'_, S> {
    fn closure_entries(&self) -> Vec<usize> {
        let kk = self.signature.len();
        let (n_last, n) = (self.dims[kk - 1], self.dims[0]);
        let ntst = self.meshes[kk - 1].len() - 1;
        let rb = self.row_offset(kk - 1) + ntst * self.basis.ncol * n_last;
        let per_row = if self.ends.symmetric() { n } else { 1 };
        super::end_condition::closure_positions(&self.jacobian_pattern(), rb..rb + n, per_row)
    }
    fn first_parameter(&self) -> usize {
        self.param_index(0)
    }
}

#[cfg(test)]
mod tests;
