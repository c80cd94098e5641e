//! Multiple shooting for hybrid periodic orbits, on the simulator's variational equations.
//!
//! Unknowns (local order): the segment start states $x_0, \dots, x_{K-1}$ ($n_k$ each, the
//! dimension of segment $k$'s mode), the
//! durations $T_0, \dots, T_{K-1}$, and the parameters $p$. With $y_k = \phi_{m_k}(x_k, T_k; p)$
//! the flow of segment $k$'s mode, the equations of segment $k$ are
//! - for an event end $e$: $g_e(y_k, p) - x_{k+1} = 0$ and $h_e(y_k, p) = 0$;
//! - for an interior end $x_c = v$: $y_k - x_{k+1} = 0$ and $(y_k)_c - v = 0$,
//!
//! with $x_K \equiv x_0$ (or $x_K \equiv S x_0$ for half of a symmetric orbit, see
//! [`Closure`](super::Closure)). The Jacobian uses $\Phi_k = \partial y_k/\partial x_k$,
//! $\partial y_k / \partial p$ and $\partial y_k/\partial T_k = f_{m_k}(y_k)$. Segment $k$ has
//! $n_{k+1} + 1$ equations (the next start's dimension), so a reset between modes of different
//! dimensions enters through its rectangular Jacobian.

use super::end_condition::EndConditions;
use super::signature::{SegmentEnd, Signature};
use crate::error::{Error, Result};
use crate::orbit::flow::SegmentFlow;
use crate::problem::{JacobianHints, JacobianUse, ZeroFunction};
use crate::simulate::{ParamSet, Sensitivities, SimulationSettings, Simulator};
use crate::system::{HybridJacobians, Mode};

/// Settings of the shooting discretisation: integration tolerances of each segment.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShootingSettings {
    /// Relative tolerance (default `1e-12`).
    pub rtol: f64,
    /// Absolute tolerance (default `1e-14`).
    pub atol: f64,
}

impl Default for ShootingSettings {
    fn default() -> Self {
        Self {
            rtol: 1e-12,
            atol: 1e-14,
        }
    }
}

/// The linearisation of one segment at its last Jacobian evaluation: the inputs it was
/// computed for, the end state and the flow Jacobian $\Phi_k$.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CachedSegment {
    /// Start state.
    pub start: Vec<f64>,
    /// Duration.
    pub duration: f64,
    /// Parameters.
    pub params: Vec<f64>,
    /// End state $y_k$.
    pub end: Vec<f64>,
    /// $\Phi_k$, column-major.
    pub phi: Vec<f64>,
}

/// Shared storage of the segments' last linearisations, so that an analysis at a point where
/// the Jacobian was just evaluated (e.g. a converged continuation point) need not integrate
/// again (see [`super::monodromy_from_cache`]).
pub type LinearizationCache = std::rc::Rc<std::cell::RefCell<Vec<CachedSegment>>>;

/// Relative integration tolerance of Jacobians used only as Newton directions
/// ([`JacobianUse::NewtonDirection`]): their error (~1e-6 relative) slows a chord iteration far
/// less than the predictor's distance from the solution does, and it takes about a third of
/// the steps of `1e-10` with DOP853 (order 8).
const DIRECTION_RTOL: f64 = 1e-6;

/// The shooting equations of a hybrid periodic orbit (a [`ZeroFunction`]).
pub struct Shooting<'a, S: ?Sized> {
    system: &'a S,
    signature: Signature,
    /// Per segment: its state's dimension $n_k$.
    dims: Vec<usize>,
    /// Per segment: the index of its start state (the prefix sums of `dims`, then their total).
    offsets: Vec<usize>,
    np: usize,
    sim: Simulator,
    /// The simulator for Jacobians that only give Newton directions (looser tolerances).
    direction_sim: Simulator,
    cache: Option<LinearizationCache>,
    ends: EndConditions,
    // Work space.
    fy: Vec<f64>,
    loose_residual: Vec<f64>,
}

impl<'a, S: HybridJacobians + ?Sized> Shooting<'a, S> {
    /// The shooting equations of orbits with `signature`.
    ///
    /// # Errors
    /// Invalid settings.
    pub fn new(system: &'a S, signature: Signature, settings: ShootingSettings) -> Result<Self> {
        let sim = Simulator::new(
            SimulationSettings::default()
                .rtol(settings.rtol)
                .atol(settings.atol)
                .record_events(false),
        )?;
        let loose = settings.rtol.max(DIRECTION_RTOL);
        let direction_sim = Simulator::new(
            SimulationSettings::default()
                .rtol(loose)
                .atol(settings.atol * loose / settings.rtol)
                .record_events(false),
        )?;
        let np = system.parameter_count();
        let ends = EndConditions::new(system, &signature);
        let dims: Vec<usize> = (signature.segments().iter())
            .map(|seg| system.mode_dim(seg.mode))
            .collect();
        let offsets = std::iter::once(0)
            .chain(dims.iter().scan(0, |acc, d| {
                *acc += d;
                Some(*acc)
            }))
            .collect();
        Ok(Self {
            system,
            signature,
            dims,
            offsets,
            np,
            sim,
            direction_sim,
            cache: None,
            ends,
            fy: vec![0.0; system.state_dim()],
            loose_residual: Vec::new(),
        })
    }

    /// Records every segment's linearisation at each Jacobian evaluation into `cache`.
    #[must_use]
    pub fn with_cache(mut self, cache: LinearizationCache) -> Self {
        self.cache = Some(cache);
        self
    }

    /// Index of segment `k`'s start state in the local unknowns.
    #[must_use]
    pub fn start_index(&self, k: usize) -> usize {
        self.offsets[k]
    }

    /// Index of segment `k`'s duration in the local unknowns.
    #[must_use]
    pub fn duration_index(&self, k: usize) -> usize {
        self.states() + k
    }

    /// Index of parameter `q` in the local unknowns.
    #[must_use]
    pub fn param_index(&self, q: usize) -> usize {
        self.states() + self.signature.len() + q
    }

    /// The number of start-state unknowns, $\sum_k n_k$.
    fn states(&self) -> usize {
        self.offsets[self.signature.len()]
    }

    /// The first equation of segment `k` (each has $n_{k+1} + 1$).
    fn first_row(&self, k: usize) -> usize {
        // Segments 0..k end in the starts of segments 1..=k (k < K: no wrap).
        self.offsets[k + 1] - self.offsets[1] + k
    }

    /// The dimension of the state segment `k` ends in: the next segment's (the first's after
    /// the last).
    fn next_dim(&self, k: usize) -> usize {
        self.dims[(k + 1) % self.dims.len()]
    }

    fn segment_mode(&self, k: usize) -> Mode {
        self.signature.segments()[k].mode
    }
}

impl<S: HybridJacobians + ?Sized> ZeroFunction for Shooting<'_, S> {
    fn unknowns(&self) -> usize {
        self.states() + self.signature.len() + self.np
    }

    fn equations(&self) -> usize {
        self.states() + self.signature.len()
    }

    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let (np, kk) = (self.np, self.signature.len());
        let mut out = Vec::new();
        for k in 0..kk {
            let (r0, n, n_to) = (self.first_row(k), self.dims[k], self.next_dim(k));
            let next = (k + 1) % kk;
            for i in 0..=n_to {
                for j in 0..n {
                    out.push((r0 + i, self.start_index(k) + j));
                }
                out.push((r0 + i, self.duration_index(k)));
                for q in 0..np {
                    out.push((r0 + i, self.param_index(q)));
                }
                if i < n_to {
                    if k + 1 == kk && self.ends.symmetric() {
                        for j in 0..n_to {
                            out.push((r0 + i, self.start_index(0) + j));
                        }
                    } else {
                        out.push((r0 + i, self.start_index(next) + i));
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
        self.evaluate_with(
            u,
            residual,
            jacobian,
            Sensitivities::StateAndParameters,
            false,
        )
    }

    /// Held parameters' sensitivities are not integrated (their columns are left zero); a
    /// Jacobian for a Newton direction integrates the variational equations at relative
    /// tolerance `max(rtol, 1e-6)` (the residual at `rtol`) and is not cached.
    fn evaluate_hinted(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
        hints: JacobianHints<'_>,
    ) -> Result<()> {
        let mut set = Some(ParamSet::EMPTY);
        for q in 0..self.np {
            if !hints.held[self.param_index(q)] {
                set = set.and_then(|s| s.with(q));
            }
        }
        // More than 64 parameters: a set cannot describe them; integrate all.
        let which = set.map_or(
            Sensitivities::StateAndParameters,
            Sensitivities::StateAndSomeParameters,
        );
        match (hints.purpose, jacobian) {
            (JacobianUse::NewtonDirection, Some(jac)) => {
                // The loose integration's residual is not the exact one: keep it aside.
                let mut loose = std::mem::take(&mut self.loose_residual);
                loose.resize(residual.len(), 0.0);
                let out = self.evaluate_with(u, &mut loose, Some(jac), which, true);
                self.loose_residual = loose;
                out?;
                self.evaluate_with(u, residual, None, which, false)
            }
            (_, jac) => self.evaluate_with(u, residual, jac, which, false),
        }
    }
}

impl<S: HybridJacobians + ?Sized> super::OrbitEquations for Shooting<'_, S> {
    fn closure_entries(&self) -> Vec<usize> {
        let (n, kk) = (self.dims[0], self.signature.len());
        let r0 = self.first_row(kk - 1);
        let per_row = if self.ends.symmetric() { n } else { 1 };
        super::end_condition::closure_positions(&self.jacobian_pattern(), r0..r0 + n, per_row)
    }
    fn first_parameter(&self) -> usize {
        self.param_index(0)
    }
}

impl<S: HybridJacobians + ?Sized> Shooting<'_, S> {
    /// Records segment `k`'s linearisation (start `x`, duration `t`, parameters, end `y`,
    /// $\Phi$) in the shared cache, if there is one.
    fn cache_segment(&self, k: usize, (x, t): (&[f64], f64), p: &[f64], y: &[f64], phi: &[f64]) {
        let Some(cache) = self.cache.as_ref() else {
            return;
        };
        let mut c = cache.borrow_mut();
        if c.len() != self.signature.len() {
            c.resize(self.signature.len(), CachedSegment::default());
        }
        c[k] = CachedSegment {
            start: x.to_vec(),
            duration: t,
            params: p.to_vec(),
            end: y.to_vec(),
            phi: phi.to_vec(),
        };
    }

    /// The Jacobian entries of a segment's `n_to + 1` end conditions from `pos` on: their
    /// derivative in the end state `y` applied to the segment's derivatives ($\Phi$, the
    /// vector field at `y` for the duration, $\Phi_p$), plus their direct parameter terms and
    /// the next segment's start.
    fn end_rows(
        &mut self,
        (end, n_to): (SegmentEnd, usize),
        (y, p): (&[f64], &[f64]),
        (phi, phi_p): (&[f64], &[f64]),
        wrap: bool,
        jac: &mut [f64],
        pos: &mut usize,
    ) -> Result<()> {
        let (n, np) = (y.len(), self.np);
        self.ends.linearise(self.system, end, (y, n_to), p)?;
        for i in 0..=n_to {
            let row = |j: usize| self.ends.state_derivative(i, j);
            for j in 0..n {
                jac[*pos] = (0..n).map(|l| row(l) * phi[l + j * n]).sum();
                *pos += 1;
            }
            jac[*pos] = (0..n).map(|l| row(l) * self.fy[l]).sum();
            *pos += 1;
            for q in 0..np {
                let direct = self.ends.parameter_derivative(i, q);
                jac[*pos] = direct + (0..n).map(|l| row(l) * phi_p[l + q * n]).sum::<f64>();
                *pos += 1;
            }
            if i < n_to {
                self.ends.write_target_entries(i, wrap, jac, pos);
            }
        }
        Ok(())
    }

    /// The residual and, if asked, the Jacobian with the parameter sensitivities `which` (the
    /// columns of parameters left out are zero, apart from direct terms); with `loose`, by the
    /// Newton-direction simulator and without updating the cache.
    fn evaluate_with(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
        which: Sensitivities,
        loose: bool,
    ) -> Result<()> {
        let (np, kk) = (self.np, self.signature.len());
        let p = u[self.param_index(0)..self.param_index(0) + np].to_vec();
        let want = jacobian.is_some();
        let mut jac = jacobian;
        let mut pos = 0usize;
        for k in 0..kk {
            let mode = self.segment_mode(k);
            let (n, n_to) = (self.dims[k], self.next_dim(k));
            let x = &u[self.start_index(k)..self.start_index(k) + n];
            let t = u[self.duration_index(k)];
            if !t.is_finite() {
                return Err(Error::InvalidSignature {
                    segment: k,
                    reason: format!("duration {t} is not finite"),
                });
            }
            // A negative duration (reached by a continuation step past a segment's collapse) is
            // integrated backward, so that the equations stay smooth through T = 0 and the
            // collapse can be located; such orbits are not admissible.
            let flow = if t >= 0.0 {
                SegmentFlow::plain(self.system, mode)
            } else {
                SegmentFlow::backward(self.system, mode)
            };
            let which = if want { which } else { Sensitivities::None };
            let sim = if loose {
                &mut self.direction_sim
            } else {
                &mut self.sim
            };
            let traj = sim.run_with_sensitivities(&flow, Mode(0), 0.0, x, &p, t.abs(), which)?;
            let y = &traj.state_final;
            let wrap = k + 1 == kk;
            let next_start = self.start_index((k + 1) % kk);
            let next = (wrap, &u[next_start..next_start + n_to]);
            let r0 = self.first_row(k);
            let end = self.signature.segments()[k].end;
            let rows = &mut residual[r0..=r0 + n_to];
            (self.ends).residual(self.system, (mode, end), y, &p, next, rows)?;
            let Some(jac) = jac.as_deref_mut() else {
                continue;
            };
            self.system.vector_field(mode, y, &p, &mut self.fy[..n]);
            let sens = traj
                .sensitivities
                .as_ref()
                .expect("sensitivities were requested");
            let phi = &sens.state;
            let phi_p = sens
                .params
                .as_ref()
                .expect("parameter sensitivities requested");
            if !loose {
                self.cache_segment(k, (x, t), &p, y, phi);
            }
            self.end_rows((end, n_to), (y, &p), (phi, phi_p), wrap, jac, &mut pos)?;
        }
        Ok(())
    }
}
