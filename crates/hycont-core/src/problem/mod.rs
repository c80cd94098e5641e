//! Zero problems composed of parts, COCO-style.
//!
//! A [`Problem`] has unknowns $u \in \mathbb{R}^N$ and equations $F(u) = 0$ assembled from
//! - parts ([`ZeroFunction`]), each owning a list of the problem's unknowns (its local slice,
//!   possibly shared with other parts, e.g. parameters) and a block of equations with a fixed
//!   sparse Jacobian pattern;
//! - monitor functions ([`MonitorFunction`]) $\mu_i = \psi_i(u)$: inactive monitors hold their value
//!   (one equation $\psi_i(u) - \mu_i = 0$ with $\mu_i$ fixed), active monitors are free (their
//!   $\mu_i$ becomes an extra unknown). Parameters enter as monitors of single unknowns.
//!
//! The Jacobian is sparse with a fixed pattern; its symbolic LU is computed once
//! ([`crate::linalg::SparsePattern`]) and reused by every Newton step ([`newton`]).

mod newton;
mod parts;
mod pattern;

pub use newton::{NewtonFailure, NewtonIteration, NewtonSettings, NewtonSolution, newton};
pub use parts::{
    JacobianHints, JacobianUse, LocalBlock, MonitorFunction, UnknownMonitor, ZeroFunction,
};

use crate::error::{Error, Result, check_finite, check_len};
use crate::linalg::SparsePattern;

/// Handle of a part of a [`Problem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PartId(pub usize);

/// Handle of a monitor function of a [`Problem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MonitorId(pub usize);

/// Whether a monitor's value is held fixed or free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Activity {
    /// Held at the given value (adds an equation).
    Inactive(f64),
    /// Free (its value is an extra unknown); the number is the initial value.
    Active(f64),
}

struct Part<'a> {
    function: Box<dyn ZeroFunction + 'a>,
    unknowns: Vec<usize>,
    row: usize,
    /// The number of its Jacobian's entries (the entries themselves are asked of the function
    /// when a pattern is built: a large system's are millions, not kept per part).
    entries: usize,
    /// Where its unknowns are consecutive global ones (e.g. a discretised orbit's), their
    /// range: the part reads them in place instead of gathered.
    span: Option<std::ops::Range<usize>>,
}

struct Monitor<'a> {
    name: String,
    function: Box<dyn MonitorFunction + 'a>,
    unknowns: Vec<usize>,
    activity: Activity,
}

/// A zero problem $F(u) = 0$ composed of parts and monitor functions.
///
/// ```
/// use hycont_core::problem::{Activity, Problem, UnknownMonitor, ZeroFunction, newton, NewtonSettings};
/// // x^2 - l = 0 with the parameter l held at 4 by an inactive monitor.
/// struct Fold;
/// impl ZeroFunction for Fold {
///     fn unknowns(&self) -> usize { 2 }
///     fn equations(&self) -> usize { 1 }
///     fn jacobian_pattern(&self) -> Vec<(usize, usize)> { vec![(0, 0), (0, 1)] }
///     fn evaluate(&mut self, u: &[f64], r: &mut [f64], j: Option<&mut [f64]>) -> hycont_core::Result<()> {
///         r[0] = u[0] * u[0] - u[1];
///         if let Some(j) = j { j[0] = 2.0 * u[0]; j[1] = -1.0; }
///         Ok(())
///     }
/// }
/// let mut problem = Problem::new(2);
/// problem.add_part(Box::new(Fold), vec![0, 1]).unwrap();
/// let l = problem.add_monitor("l", Box::new(UnknownMonitor), vec![1], Activity::Inactive(4.0)).unwrap();
/// let sol = newton(&mut problem, &[1.5, 4.0], &NewtonSettings::default()).unwrap();
/// assert!((sol.u[0] - 2.0).abs() < 1e-9); // tol = 1e-10 on steps and residual
/// assert_eq!(problem.monitor_value(l, &sol.u).unwrap(), 4.0);
/// ```
pub struct Problem<'a> {
    base_unknowns: usize,
    parts: Vec<Part<'a>>,
    monitors: Vec<Monitor<'a>>,
    pattern: Option<SparsePattern>,
    values: Vec<f64>,
    /// Work space: unknowns held by inactive single-unknown monitors (global, then one part's).
    held: Vec<bool>,
    held_local: Vec<bool>,
    /// Work space: a part's or monitor's unknowns gathered, a monitor's gradient.
    local_u: Vec<f64>,
    grad: Vec<f64>,
}

impl std::fmt::Debug for Problem<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Problem")
            .field("unknowns", &self.unknowns())
            .field("equations", &self.equations())
            .field("parts", &self.parts.len())
            .field(
                "monitors",
                &self
                    .monitors
                    .iter()
                    .map(|m| (&m.name, m.activity))
                    .collect::<Vec<_>>(),
            )
            .finish()
    }
}

impl<'a> Problem<'a> {
    /// A problem with `unknowns` base unknowns and no equations yet.
    #[must_use]
    pub fn new(unknowns: usize) -> Self {
        Self {
            base_unknowns: unknowns,
            parts: Vec::new(),
            monitors: Vec::new(),
            pattern: None,
            values: Vec::new(),
            held: Vec::new(),
            held_local: Vec::new(),
            local_u: Vec::new(),
            grad: Vec::new(),
        }
    }

    fn check_indices(&self, what: &'static str, idx: &[usize], expected: usize) -> Result<()> {
        if idx.len() != expected {
            return Err(Error::DimensionMismatch {
                what,
                expected,
                found: idx.len(),
            });
        }
        if let Some(&bad) = idx.iter().find(|&&i| i >= self.base_unknowns) {
            return Err(Error::InvalidSetting {
                name: what,
                value: bad as f64,
                reason: "unknown index out of range",
            });
        }
        Ok(())
    }

    /// Adds a part reading the unknowns `unknowns` (global indices, in the part's local order).
    ///
    /// # Errors
    /// If the index list has the wrong length or an index is out of range.
    pub fn add_part(
        &mut self,
        function: Box<dyn ZeroFunction + 'a>,
        unknowns: Vec<usize>,
    ) -> Result<PartId> {
        self.check_indices("part unknowns", &unknowns, function.unknowns())?;
        let row = self.parts.iter().map(|p| p.function.equations()).sum();
        let entries = function.jacobian_len();
        let first = unknowns.first().copied().unwrap_or(0);
        let span = (unknowns.iter().enumerate().all(|(k, &i)| i == first + k))
            .then(|| first..first + unknowns.len());
        self.parts.push(Part {
            function,
            unknowns,
            row,
            entries,
            span,
        });
        self.pattern = None;
        Ok(PartId(self.parts.len() - 1))
    }

    /// Adds a monitor function $\mu = \psi(u)$ over `unknowns`.
    ///
    /// # Errors
    /// If the index list has the wrong length or an index is out of range, or the value is
    /// not finite.
    pub fn add_monitor(
        &mut self,
        name: &str,
        function: Box<dyn MonitorFunction + 'a>,
        unknowns: Vec<usize>,
        activity: Activity,
    ) -> Result<MonitorId> {
        self.check_indices("monitor unknowns", &unknowns, function.unknowns())?;
        let (Activity::Active(v) | Activity::Inactive(v)) = activity;
        check_finite("monitor value", &[v])?;
        self.monitors.push(Monitor {
            name: name.to_string(),
            function,
            unknowns,
            activity,
        });
        self.pattern = None;
        Ok(MonitorId(self.monitors.len() - 1))
    }

    /// Resolves a monitor by name (do it once, keep the handle).
    #[must_use]
    pub fn monitor_id(&self, name: &str) -> Option<MonitorId> {
        self.monitors
            .iter()
            .position(|m| m.name == name)
            .map(MonitorId)
    }

    fn monitor_index(&self, id: MonitorId) -> Result<usize> {
        if id.0 < self.monitors.len() {
            Ok(id.0)
        } else {
            Err(Error::IndexOutOfRange {
                what: "monitor",
                index: id.0,
                count: self.monitors.len(),
            })
        }
    }

    /// Makes a monitor active or inactive (changes the number of unknowns if its activity changes
    /// kind).
    ///
    /// # Errors
    /// [`Error::IndexOutOfRange`] for a monitor of another problem; [`Error::NonFinite`] for a
    /// non-finite value.
    pub fn set_activity(&mut self, id: MonitorId, activity: Activity) -> Result<()> {
        let i = self.monitor_index(id)?;
        let (Activity::Active(v) | Activity::Inactive(v)) = activity;
        check_finite("monitor value", &[v])?;
        let m = &mut self.monitors[i];
        if std::mem::discriminant(&m.activity) != std::mem::discriminant(&activity) {
            self.pattern = None;
        }
        m.activity = activity;
        Ok(())
    }

    /// The activity of a monitor.
    ///
    /// # Errors
    /// [`Error::IndexOutOfRange`] for a monitor of another problem.
    pub fn activity(&self, id: MonitorId) -> Result<Activity> {
        Ok(self.monitors[self.monitor_index(id)?].activity)
    }

    /// Number of base unknowns (without the active monitors' values).
    #[must_use]
    pub fn base_unknowns(&self) -> usize {
        self.base_unknowns
    }

    /// Total number of unknowns: base unknowns plus one per active monitor.
    #[must_use]
    pub fn unknowns(&self) -> usize {
        self.base_unknowns
            + self
                .monitors
                .iter()
                .filter(|m| matches!(m.activity, Activity::Active(_)))
                .count()
    }

    /// Total number of equations: the parts' plus one per monitor.
    #[must_use]
    pub fn equations(&self) -> usize {
        self.parts
            .iter()
            .map(|p| p.function.equations())
            .sum::<usize>()
            + self.monitors.len()
    }

    /// Index of each active monitor's value in the unknown vector.
    fn active_slots(&self) -> Vec<Option<usize>> {
        let mut next = self.base_unknowns;
        self.monitors
            .iter()
            .map(|m| match m.activity {
                Activity::Active(_) => {
                    next += 1;
                    Some(next - 1)
                }
                Activity::Inactive(_) => None,
            })
            .collect()
    }

    /// Extends a base unknown vector with the active monitors' initial values.
    #[must_use]
    pub fn initial_unknowns(&self, base: &[f64]) -> Vec<f64> {
        let mut u = base[..self.base_unknowns].to_vec();
        for m in &self.monitors {
            if let Activity::Active(v) = m.activity {
                u.push(v);
            }
        }
        u
    }

    /// Evaluates $F(u)$ and, if asked, the Jacobian values in pattern order.
    ///
    /// Unknowns held at their value by an inactive monitor of that unknown alone (to a relative
    /// $4\varepsilon$; e.g. the parameters not being continued) are *held*: their Jacobian
    /// columns (outside the monitor's own row) may be returned as zeros, because the monitor's
    /// row pins their change to zero in Newton steps and tangents and the determinant does not
    /// depend on them. Parts use this to skip work ([`ZeroFunction::evaluate_hinted`]).
    /// [`Problem::dense_jacobian`] and [`Problem::check_jacobian`] give full columns.
    ///
    /// # Errors
    /// Wrong dimensions, or a failing part or monitor.
    pub fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut Vec<f64>>,
    ) -> Result<()> {
        self.evaluate_impl(u, residual, jacobian, true, JacobianUse::Exact)
    }

    /// Like [`Problem::evaluate`], with the Jacobian for `purpose` (parts may compute a Newton
    /// direction's Jacobian more cheaply, see [`JacobianUse`]). The residual is exact.
    ///
    /// # Errors
    /// As [`Problem::evaluate`].
    pub fn evaluate_for(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: &mut Vec<f64>,
        purpose: JacobianUse,
    ) -> Result<()> {
        self.evaluate_impl(u, residual, Some(jacobian), true, purpose)
    }

    /// Marks in `self.held` the unknowns held at their value by inactive single-unknown
    /// monitors.
    fn mark_held(&mut self, u: &[f64]) -> Result<bool> {
        self.held.clear();
        self.held.resize(u.len(), false);
        let mut any = false;
        for m in &mut self.monitors {
            let (Activity::Inactive(v), &[i]) = (m.activity, m.unknowns.as_slice()) else {
                continue;
            };
            let value = m.function.evaluate(&u[i..=i], None)?;
            if (value - v).abs() <= 4.0 * f64::EPSILON * v.abs().max(1.0) {
                self.held[i] = true;
                any = true;
            }
        }
        Ok(any)
    }

    fn evaluate_impl(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut Vec<f64>>,
        use_held: bool,
        purpose: JacobianUse,
    ) -> Result<()> {
        check_len("unknowns", u, self.unknowns())?;
        check_len("residual", residual, self.equations())?;
        let mut jac = jacobian;
        // The parts' values first (kept from the last evaluation where a part writes them all),
        // then the monitors' gradients, appended.
        if let Some(j) = jac.as_deref_mut() {
            let parts: usize = self.parts.iter().map(|p| p.entries).sum();
            j.truncate(parts);
            // Room for the monitors' gradients too: a vector grown by doubling past millions
            // of entries would hold up to twice them.
            j.reserve_exact(self.pattern_len().saturating_sub(j.len()));
            j.resize(parts, 0.0);
        }
        let any_held = jac.is_some() && use_held && self.mark_held(u)?;
        let hinted = any_held || purpose != JacobianUse::Exact;
        // The work spaces are taken for the evaluation (an error returns without them: the
        // next evaluation makes new ones).
        let mut local_u = std::mem::take(&mut self.local_u);
        let mut start = 0;
        for part in &mut self.parts {
            let local: &[f64] = match &part.span {
                Some(span) => &u[span.clone()],
                None => {
                    local_u.clear();
                    local_u.extend(part.unknowns.iter().map(|&i| u[i]));
                    &local_u
                }
            };
            let rows = part.function.equations();
            let res = &mut residual[part.row..part.row + rows];
            match jac.as_deref_mut() {
                Some(j) => {
                    let at = &mut j[start..start + part.entries];
                    start += part.entries;
                    if !part.function.writes_every_entry() {
                        at.fill(0.0);
                    }
                    let out = Some(at);
                    if hinted {
                        self.held_local.clear();
                        self.held_local
                            .extend(part.unknowns.iter().map(|&i| any_held && self.held[i]));
                        let hints = JacobianHints {
                            held: &self.held_local,
                            purpose,
                        };
                        part.function.evaluate_hinted(local, res, out, hints)?;
                    } else {
                        part.function.evaluate(local, res, out)?;
                    }
                }
                None => part.function.evaluate(local, res, None)?,
            }
        }
        let row0 = residual.len() - self.monitors.len();
        let mut grad = std::mem::take(&mut self.grad);
        // Active monitors' unknowns follow the base unknowns, in the monitors' order.
        let mut slot = self.base_unknowns;
        for (k, m) in self.monitors.iter_mut().enumerate() {
            local_u.clear();
            local_u.extend(m.unknowns.iter().map(|&i| u[i]));
            grad.resize(m.unknowns.len(), 0.0);
            let want = jac.is_some();
            let value = m
                .function
                .evaluate(&local_u, if want { Some(&mut grad) } else { None })?;
            let (target, active) = match m.activity {
                Activity::Inactive(v) => (v, false),
                Activity::Active(_) => {
                    slot += 1;
                    (u[slot - 1], true)
                }
            };
            residual[row0 + k] = value - target;
            if let Some(j) = jac.as_deref_mut() {
                j.extend_from_slice(&grad);
                if active {
                    j.push(-1.0);
                }
            }
        }
        self.local_u = local_u;
        self.grad = grad;
        Ok(())
    }

    /// The value of a monitor at `u`.
    ///
    /// # Errors
    /// [`Error::IndexOutOfRange`] for a monitor of another problem, `u` of the wrong length, or
    /// if the monitor fails.
    pub fn monitor_value(&mut self, id: MonitorId, u: &[f64]) -> Result<f64> {
        let i = self.monitor_index(id)?;
        check_len("unknowns", u, self.unknowns())?;
        let m = &mut self.monitors[i];
        let local: Vec<f64> = m.unknowns.iter().map(|&i| u[i]).collect();
        m.function.evaluate(&local, None)
    }

    /// Factorises the Jacobian at `u` (square problems) and writes the residual; solve with
    /// [`Problem::solve_in_place`].
    ///
    /// # Errors
    /// A failing evaluation or a singular Jacobian.
    pub fn factorize(&mut self, u: &[f64], residual: &mut [f64]) -> Result<()> {
        let mut values = std::mem::take(&mut self.values);
        let out = self
            .evaluate(u, residual, Some(&mut values))
            .and_then(|()| self.pattern()?.factorize(&values));
        self.values = values;
        out
    }

    /// Solves $J x = b$ in place with the last factorisation of the Jacobian.
    ///
    /// # Errors
    /// [`crate::Error::SingularMatrix`] if there is none or it is singular.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<()> {
        self.pattern()?.solve_in_place(b)
    }

    /// Dense Jacobian at `u` (row-major rows of length `unknowns()`), for checks and small
    /// problems.
    ///
    /// # Errors
    /// A failing evaluation.
    pub fn dense_jacobian(&mut self, u: &[f64]) -> Result<Vec<Vec<f64>>> {
        let mut values = Vec::new();
        let mut residual = vec![0.0; self.equations()];
        self.evaluate_impl(
            u,
            &mut residual,
            Some(&mut values),
            false,
            JacobianUse::Exact,
        )?;
        let mut out = vec![vec![0.0; self.unknowns()]; self.equations()];
        for ((r, c), v) in self.global_entries().zip(&values) {
            out[r][c] += v;
        }
        Ok(out)
    }

    /// Compares the assembled Jacobian with central differences of $F$ at `u`; returns the
    /// largest scaled error $|J_{ij} - D_{ij}| / (1 + |D_{ij}|)$ and its position.
    ///
    /// # Errors
    /// A failing evaluation.
    pub fn check_jacobian(&mut self, u: &[f64], rel_step: f64) -> Result<(f64, usize, usize)> {
        let jac = self.dense_jacobian(u)?;
        let m = self.equations();
        let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
        let mut w = u.to_vec();
        let mut worst = (0.0, 0, 0);
        for c in 0..u.len() {
            let h = rel_step * u[c].abs().max(1.0);
            w[c] = u[c] + h;
            self.evaluate(&w, &mut rp, None)?;
            w[c] = u[c] - h;
            self.evaluate(&w, &mut rm, None)?;
            w[c] = u[c];
            for r in 0..m {
                let d = (rp[r] - rm[r]) / (2.0 * h);
                let err = (jac[r][c] - d).abs() / (1.0 + d.abs());
                if err > worst.0 {
                    worst = (err, r, c);
                }
            }
        }
        Ok(worst)
    }
}
