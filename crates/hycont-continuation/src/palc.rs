//! Pseudo-arclength continuation (PALC) over a one-dimensional atlas of charts.
//!
//! A chart is a solution $u$ of $F(u) = 0$ ($F: \mathbb{R}^N \to \mathbb{R}^{N-1}$) with its unit
//! tangent $t$ ($J t = 0$, oriented along the run). From chart $(u_a, t_a)$ a step $h$ predicts
//! by extrapolating the cubic Hermite interpolant of the previous chart and $(u_a, t_a)$ (the
//! tangent predictor $u_a + h t_a$ at the start and after a rejected step) and corrects on the
//! hyperplane $\langle t_a, u - u_a \rangle_W = h$ with chord Newton on the augmented system
//! $[F; \langle t_a, u - u_a \rangle_W - h]$, Jacobian $A = [J; (W t_a)^\top]$, where
//! $\langle \cdot, \cdot \rangle_W$ is the arclength inner product with the problem's unknown
//! weights (see [`crate::ContinuationProblem::unknown_weights`]; tangents have unit $W$-norm).
//! The new tangent solves $A x = e_N$. Test functions are evaluated at every chart; a sign change between two charts is
//! located on the first chart's hyperplanes, $s \mapsto$ the solution at arclength
//! $s \in (0, h)$, by the ITP method until the bracket in $s$ is below the location tolerance.
//! A fold test change beside a located branch point in the same step is the branch point's.

use crate::branch::{Branch, BranchPoint, EndReason, RunStatistics, SpecialKind, SpecialPoint};
use crate::error::{Error, Result};
use crate::observe::Observer;
use crate::quantity::Quantity;
use crate::settings::{BoundOn, ContinuationSettings};
use crate::{ContinuationProblem, PointInfo};
use hycont_core::ParamId;
use hycont_core::linalg::SparsePattern;
use hycont_core::problem::JacobianUse;

/// A solved chart with everything the test functions need.
#[derive(Debug, Clone)]
struct Chart {
    u: Vec<f64>,
    t: Vec<f64>,
    info: PointInfo,
    iterations: usize,
    /// Sign and log|det| of the augmented Jacobian at `u` (with the chart's reference row).
    det: (f64, f64),
}

/// Test-function values at a chart, one per slot of [`Palc::slots`], in that order.
#[derive(Debug, Clone)]
struct Tests {
    values: Vec<f64>,
}

/// Where an event's or bound's value is read.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Source {
    /// The continuation parameter's unknown (no analysis needed).
    Continued,
    /// `info.params[i]`.
    Param(usize),
    /// `info.monitors[i]`.
    Monitor(usize),
}

/// What each test-function slot means.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Slot {
    Fold,
    BranchPoint,
    PeriodDoubling,
    Torus,
    Event {
        kind: SpecialKind,
        level: f64,
        source: Source,
        on: Quantity,
        terminal: bool,
    },
    Bound {
        source: Source,
        on: Quantity,
        level: f64,
    },
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Product over non-trivial multipliers of $(1 + \lambda)$: changes sign when a real
/// multiplier crosses $-1$.
fn pd_test(info: &PointInfo) -> f64 {
    crate::shifted_product(&info.multipliers, &info.trivial, 1.0)
}

/// Product over pairs of non-trivial multipliers of $(\lambda_i \lambda_j - 1)$, real part: changes
/// sign when a complex pair crosses the unit circle (also at neutral saddles, which are filtered
/// out after location).
fn tr_test(info: &PointInfo) -> f64 {
    let nt: Vec<(f64, f64)> = info
        .multipliers
        .iter()
        .zip(&info.trivial)
        .filter(|(_, t)| !**t)
        .map(|(m, _)| *m)
        .collect();
    let mut acc = 1.0;
    for i in 0..nt.len() {
        for j in i + 1..nt.len() {
            let (a, b) = (nt[i], nt[j]);
            // Complex conjugate pair: |lambda|^2 - 1; real pairs: lambda_i lambda_j - 1.
            let re = a.0 * b.0 - a.1 * b.1;
            acc *= re - 1.0;
        }
    }
    acc
}

/// A fixed, generic unit vector of length `n`.
fn generic(n: usize) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n)
        .map(|i| ((i as f64 + 1.0) * 0.618_033_988_7).fract() - 0.5)
        .collect();
    let norm = dot(&v, &v).sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    v
}

/// The sign that says which way a tangent `t` goes: its parameter component, or, where that
/// vanishes (to `1e-9`), its component along a fixed generic vector, so that the two ways from
/// a start are always opposite.
fn orientation(t: &[f64], pi: usize) -> f64 {
    if t[pi].abs() > 1e-9 {
        t[pi]
    } else {
        dot(t, &generic(t.len()))
    }
}

/// The cubic Hermite interpolant at $x$ of values `u0`, `u1` at $x = 0, 1$ with derivatives
/// `c0 * d0`, `c1 * d1` (in $x$), e.g. charts `width` apart in arclength with tangents scaled to
/// arclength derivatives. $x$ outside $[0, 1]$ extrapolates.
fn hermite(
    u0: &[f64],
    (c0, d0): (f64, &[f64]),
    u1: &[f64],
    (c1, d1): (f64, &[f64]),
    x: f64,
) -> Vec<f64> {
    let h00 = (1.0 + 2.0 * x) * (1.0 - x) * (1.0 - x);
    let h10 = x * (1.0 - x) * (1.0 - x);
    let h01 = x * x * (3.0 - 2.0 * x);
    let h11 = x * x * (x - 1.0);
    (0..u0.len())
        .map(|i| h00 * u0[i] + h10 * c0 * d0[i] + h01 * u1[i] + h11 * c1 * d1[i])
        .collect()
}

/// The predictor of a step `h` from chart $(u_a, t_a)$ reached by a step `h_p` from
/// $(u_p, t_p)$: the cubic Hermite interpolant of the two charts (unit tangents as derivatives in
/// arclength) extrapolated to `h` beyond $u_a$. Its error is $O(h^3)$ against the tangent
/// predictor's $O(h^2)$, so the corrector starts closer (fewer chord iterations).
fn extrapolate(u_p: &[f64], t_p: &[f64], h_p: f64, u_a: &[f64], t_a: &[f64], h: f64) -> Vec<f64> {
    hermite(u_p, (h_p, t_p), u_a, (h_p, t_a), 1.0 + h / h_p)
}

/// The continuation driver for one problem.
pub(crate) struct Palc<'p, 'a, P: ContinuationProblem<'a> + ?Sized> {
    p: &'p mut P,
    settings: ContinuationSettings,
    n: usize,
    k: usize,
    pattern: SparsePattern,
    values: Vec<f64>,
    res: Vec<f64>,
    /// Arclength weights of the unknowns (see [`ContinuationProblem::unknown_weights`]).
    w: Vec<f64>,
    slots: Vec<Slot>,
    stats: RunStatistics,
    /// Whether evaluations count as location work.
    locating: bool,
    _marker: std::marker::PhantomData<&'a ()>,
}

impl<'p, 'a, P: ContinuationProblem<'a> + ?Sized> Palc<'p, 'a, P> {
    pub(crate) fn new(p: &'p mut P, settings: ContinuationSettings) -> Result<Self> {
        settings.validate()?;
        let problem = p.problem();
        let (pattern, k) = crate::switch::augmented_pattern(problem)?;
        let n = problem.unknowns();
        let mut slots = Vec::new();
        let d = settings.detect;
        if d.fold {
            slots.push(Slot::Fold);
        }
        if d.branch_point {
            slots.push(Slot::BranchPoint);
        }
        if d.period_doubling {
            slots.push(Slot::PeriodDoubling);
        }
        if d.torus {
            slots.push(Slot::Torus);
        }
        if d.monitor_events {
            for ev in p.monitor_events() {
                slots.push(Slot::Event {
                    kind: ev.kind,
                    level: ev.level,
                    source: Self::source(p, ev.on)?,
                    on: ev.on,
                    terminal: ev.terminal,
                });
            }
        }
        for b in &settings.bounds {
            let (source, on) = match b.on {
                BoundOn::ContinuationParameter => (
                    Source::Continued,
                    Quantity::Parameter(ParamId(p.parameter_position())),
                ),
                BoundOn::Quantity(q) => (Self::source(p, q)?, q),
            };
            for level in [b.min, b.max] {
                slots.push(Slot::Bound { source, on, level });
            }
        }
        let w = match p.unknown_weights() {
            Some(w) if w.len() == n && w.iter().all(|&x| x > 0.0 && x.is_finite()) => w,
            Some(w) => {
                return Err(Error::InvalidSetting {
                    name: "unknown_weights",
                    value: w.len() as f64,
                    reason: "need one finite positive weight per unknown",
                });
            }
            None => vec![1.0; n],
        };
        Ok(Self {
            p,
            settings,
            n,
            k,
            pattern,
            values: Vec::new(),
            res: vec![0.0; n],
            w,
            slots,
            stats: RunStatistics::default(),
            locating: false,
            _marker: std::marker::PhantomData,
        })
    }

    /// Where the value of `q` is read, checked against the problem's parameters and monitors.
    fn source(p: &P, q: Quantity) -> Result<Source> {
        match q {
            Quantity::Parameter(id) if id.index() == p.parameter_position() => {
                Ok(Source::Continued)
            }
            Quantity::Parameter(id) => {
                let count = p.parameter_names().len();
                if id.index() < count {
                    Ok(Source::Param(id.index()))
                } else {
                    Err(Error::NoSuchQuantity { quantity: q, count })
                }
            }
            Quantity::Measure(m) => {
                let count = p.monitor_names().len();
                if m.index() < count {
                    Ok(Source::Monitor(m.index()))
                } else {
                    Err(Error::NoSuchQuantity { quantity: q, count })
                }
            }
        }
    }

    /// The weighted inner product $\langle a, b \rangle_W = \sum_i w_i a_i b_i$ of arclength.
    fn wdot(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .zip(&self.w)
            .map(|((x, y), w)| w * x * y)
            .sum()
    }

    fn wnormalize(&self, v: &mut [f64]) {
        let norm = self.wdot(v, v).sqrt();
        if norm > 0.0 {
            v.iter_mut().for_each(|x| *x /= norm);
        }
    }

    /// The augmented Jacobian's last row for the hyperplanes of tangent `t`: $W t$, so that the
    /// row applied to $u - u_a$ is $\langle t, u - u_a \rangle_W$.
    fn row_of(&self, t: &[f64]) -> Vec<f64> {
        t.iter().zip(&self.w).map(|(x, w)| w * x).collect()
    }

    fn parameter(&self, u: &[f64]) -> f64 {
        u[self.p.parameter_index()]
    }

    /// Assembles and factorises $[J(u); r^\top]$ and writes $[F(u); r \cdot (u - u_0) - s]$.
    ///
    /// `purpose` tells the problem whether the Jacobian must be exact (at a solution: tangent,
    /// determinant, multipliers) or only gives chord directions (it may then be computed more
    /// cheaply; the residual is exact either way).
    fn factor(
        &mut self,
        u: &[f64],
        row: &[f64],
        u0: &[f64],
        s: f64,
        purpose: JacobianUse,
    ) -> Result<()> {
        let n = self.n;
        if self.locating {
            self.stats.location_jacobians += 1;
        } else {
            self.stats.jacobians += 1;
        }
        let mut values = std::mem::take(&mut self.values);
        self.p
            .problem()
            .evaluate_for(u, &mut self.res[..n - 1], &mut values, purpose)?;
        values.truncate(self.k);
        values.extend_from_slice(row);
        self.res[n - 1] = dot(row, u) - dot(row, u0) - s;
        let out = self.pattern.factorize(&values);
        self.values = values;
        Ok(out?)
    }

    /// Newton on the augmented system from `u_pred`; returns the solution and the iterations,
    /// and leaves the augmented Jacobian at the solution factorised (with `row` as last row).
    ///
    /// Converged when the residual is below the tolerance after at least one step, or the step
    /// is below the tolerance with a residual of the same order. The residual criterion matters
    /// near branch points, where the augmented Jacobian is nearly singular and evaluation noise
    /// is amplified along the (parameter-free) null direction.
    ///
    /// With `accurate_predictor` (location, where the predictor interpolates two nearby
    /// solutions to high order) the residual is checked before anything is factorised: a
    /// predictor that already solves the equations is accepted after one factorisation there.
    fn correct(
        &mut self,
        u_pred: &[f64],
        row: &[f64],
        u0: &[f64],
        s: f64,
        accurate_predictor: bool,
    ) -> Result<(Vec<f64>, usize)> {
        let ns = self.settings.newton;
        let max_it = 2 * self.settings.target_iterations;
        let n = self.n;
        let mut u = u_pred.to_vec();
        if accurate_predictor {
            self.count_residual();
            self.p
                .problem()
                .evaluate(&u, &mut self.res[..n - 1], None)?;
            self.res[n - 1] = dot(row, &u) - dot(row, u0) - s;
            if max_abs(&self.res) <= ns.residual_tol {
                self.factor(&u, row, u0, s, JacobianUse::Exact)?;
                return Ok((u, 0));
            }
        }
        let mut du = vec![0.0; n];
        let mut last_step = f64::INFINITY;
        let mut last_res = f64::INFINITY;
        // Chord iterations: the Jacobian is factorised at the predictor (and again only if the
        // residual stops contracting fast); the other iterations evaluate the residual only.
        let mut fresh = true;
        self.factor(&u, row, u0, s, JacobianUse::NewtonDirection)?;
        for it in 0..=max_it {
            if !fresh {
                self.count_residual();
                self.p
                    .problem()
                    .evaluate(&u, &mut self.res[..n - 1], None)?;
                self.res[n - 1] = dot(row, &u) - dot(row, u0) - s;
            }
            let res = max_abs(&self.res);
            let scale = 1.0 + max_abs(&u);
            if it > 0
                && (res <= ns.residual_tol
                    || (last_step <= ns.tol * scale && res <= 1e3 * last_step.max(ns.residual_tol)))
            {
                // Converged: factorise at the solution for the tangent and the determinant.
                self.factor(&u, row, u0, s, JacobianUse::Exact)?;
                return Ok((u, it));
            }
            if it == max_it || !res.is_finite() {
                break;
            }
            if !fresh && res > 0.2 * last_res {
                // Slow contraction: refresh the Jacobian.
                self.factor(&u, row, u0, s, JacobianUse::NewtonDirection)?;
            }
            for (d, r) in du.iter_mut().zip(&self.res) {
                *d = -r;
            }
            self.pattern.solve_in_place(&mut du)?;
            last_step = max_abs(&du);
            last_res = res;
            if last_step > 1e3 * scale {
                break;
            }
            for (x, d) in u.iter_mut().zip(&du) {
                *x += d;
            }
            fresh = false;
        }
        Err(Error::Core(hycont_core::Error::NewtonFailed {
            reason: "corrector did not converge".into(),
            history: Vec::new(),
        }))
    }

    fn count_residual(&mut self) {
        if self.locating {
            self.stats.location_residuals += 1;
        } else {
            self.stats.residuals += 1;
        }
    }

    fn analyse(&mut self, u: &[f64]) -> Result<PointInfo> {
        self.stats.analyses += 1;
        Ok(self.p.analyse(u)?)
    }

    /// Tangent at `u` with the current factorisation of $[J(u); row]$ (left by
    /// [`Palc::correct`]), and the determinant of that matrix.
    fn tangent_from_factorization(&mut self) -> Result<(Vec<f64>, (f64, f64))> {
        let det = self.pattern.determinant()?;
        let mut x = vec![0.0; self.n];
        x[self.n - 1] = 1.0;
        self.pattern.solve_in_place(&mut x)?;
        self.wnormalize(&mut x);
        Ok((x, det))
    }

    /// Tangent at a corrected `u` (reference row `row`, orientation `t·row > 0`), with the
    /// determinant of $[J(u); row]$ (factorises afresh).
    fn tangent(&mut self, u: &[f64], row: &[f64]) -> Result<(Vec<f64>, (f64, f64))> {
        let zero = vec![0.0; self.n];
        self.factor(u, row, &zero, dot(row, u), JacobianUse::Exact)?;
        self.tangent_from_factorization()
    }

    /// The chart at a corrected `u`, using the factorisation the corrector left.
    fn chart(&mut self, u: Vec<f64>, _row: &[f64], iterations: usize) -> Result<Chart> {
        let (t, det) = self.tangent_from_factorization()?;
        let info = self.analyse(&u)?;
        Ok(Chart {
            u,
            t,
            info,
            iterations,
            det,
        })
    }

    fn tests(&self, c: &Chart, det_ref: f64) -> Tests {
        let pi = self.p.parameter_index();
        let values = self
            .slots
            .iter()
            .map(|slot| match *slot {
                Slot::Fold => c.t[pi],
                Slot::BranchPoint => {
                    c.det.0
                        * (c.det.1 - det_ref).clamp(-700.0, 700.0).exp()
                        * c.info.branch_point_factor.unwrap_or(1.0)
                }
                Slot::PeriodDoubling => pd_test(&c.info),
                Slot::Torus => tr_test(&c.info),
                Slot::Event { level, source, .. } | Slot::Bound { source, level, .. } => {
                    let value = match source {
                        Source::Continued => c.u[pi],
                        Source::Param(i) => c.info.params[i],
                        Source::Monitor(i) => c.info.monitors[i],
                    };
                    value - level
                }
            })
            .collect();
        Tests { values }
    }

    fn point(&self, c: &Chart, label: usize, step: f64) -> BranchPoint {
        BranchPoint {
            label,
            ..BranchPoint::from_info(&c.info, c.u.clone(), c.t.clone(), c.iterations, step)
        }
    }

    /// The chart at arclength `s` on chart `a`'s hyperplanes, with `a`'s tangent as reference row
    /// (so that the determinant is continuous in `s`). With `analyse == false` the point's
    /// analysis (multipliers, monitors) is copied from `a` (enough for the fold and branch-point
    /// tests, which use the tangent and the determinant only).
    ///
    /// The predictor interpolates the bracket's charts `lo` (at `s_lo`) and `hi` (at `s_hi`):
    /// cubic Hermite in $s$ with slopes $t / \langle t_a, t \rangle_W$, which keeps it on the hyperplane
    /// and makes it accurate to $O(w^4)$ in the bracket width $w$, so that late in a location
    /// the predictor is already a solution; linear where a slope is unreliable (the tangent
    /// turns away from $t_a$, e.g. next to a branch point).
    fn chart_at(
        &mut self,
        a: &Chart,
        (lo, s_lo): (&Chart, f64),
        (hi, s_hi): (&Chart, f64),
        s: f64,
        analyse: bool,
    ) -> Result<Chart> {
        let w = s_hi - s_lo;
        let x = (s - s_lo) / w;
        let (d_lo, d_hi) = (self.wdot(&a.t, &lo.t), self.wdot(&a.t, &hi.t));
        let pred: Vec<f64> = if d_lo > 0.5 && d_hi > 0.5 {
            hermite(&lo.u, (w / d_lo, &lo.t), &hi.u, (w / d_hi, &hi.t), x)
        } else {
            lo.u.iter()
                .zip(&hi.u)
                .map(|(p, q)| p + x * (q - p))
                .collect()
        };
        let row = self.row_of(&a.t);
        let (u, it) = self.correct(&pred, &row, &a.u.clone(), s, true)?;
        if analyse {
            return self.chart(u, &row, it);
        }
        let (t, det) = self.tangent_from_factorization()?;
        Ok(Chart {
            u,
            t,
            info: a.info.clone(),
            iterations: it,
            det,
        })
    }

    /// Locates the zero of test slot `slot` between the charts `lo` and `hi` at arclengths
    /// `s_lo < s_hi` on chart `a`'s hyperplanes, by the ITP method (Oliveira and Takahashi,
    /// 2020: regula falsi, truncated towards the midpoint and projected into a shrinking
    /// interval around it). It converges superlinearly for smooth test functions, from both
    /// sides (the truncation steps over the root, so the bracket, not just one end, shrinks),
    /// and never needs more than one evaluation beyond bisection's
    /// $\lceil \log_2 (w_0 / \mathrm{tol}) \rceil$. A trial whose corrector fails (next to a
    /// branch point the augmented Jacobian is singular) is retried at the midpoint. Returns the
    /// chart, whether the bracket in `s` reached the tolerance, and the final bracket width; on
    /// failure, the better bracket end.
    fn locate(
        &mut self,
        a: &Chart,
        (lo_chart, s_lo): (&Chart, f64),
        (hi_chart, s_hi): (&Chart, f64),
        slot: usize,
    ) -> (Chart, bool, f64) {
        let det_ref = a.det.1;
        let tol = self.settings.locate_tol;
        let (mut lo, mut hi) = (s_lo, s_hi);
        let mut glo = self.tests(lo_chart, det_ref).values[slot];
        let mut ghi = self.tests(hi_chart, det_ref).values[slot];
        let (mut c_lo, mut c_hi) = (lo_chart.clone(), hi_chart.clone());
        // ITP constants: eps = tol / 2 (stop when the bracket is at most tol), kappa1 = 0.2 / w0,
        // kappa2 = 2, n0 = 1.
        let eps = 0.5 * tol;
        let w0 = hi - lo;
        let kappa1 = 0.2 / w0;
        let n_max = (w0 / (2.0 * eps)).log2().ceil().max(0.0) + 1.0;
        let mut j = 0.0;
        let mut bisect_next = false;
        // Fold and branch-point tests need no analysis of the trial points, unless the
        // branch-point test has a factor from the analysis.
        let needs_analysis = match self.slots[slot] {
            Slot::Fold => false,
            Slot::BranchPoint => a.info.branch_point_factor.is_some(),
            Slot::Event { source, .. } | Slot::Bound { source, .. } => source != Source::Continued,
            _ => true,
        };
        for _ in 0..200 {
            let width = hi - lo;
            if width <= tol {
                break;
            }
            let mid = 0.5 * (lo + hi);
            let s = if bisect_next || glo == ghi {
                mid
            } else {
                let r = (eps * 2f64.powf(n_max - j) - 0.5 * width).max(0.0);
                let delta = kappa1 * width * width;
                let x_f = (ghi * lo - glo * hi) / (ghi - glo);
                let sigma = (mid - x_f).signum();
                let x_t = if delta <= (mid - x_f).abs() {
                    x_f + sigma * delta
                } else {
                    mid
                };
                if (x_t - mid).abs() <= r {
                    x_t
                } else {
                    mid - sigma * r
                }
            };
            // Strictly inside the bracket (the projection allows its ends in exact arithmetic).
            let margin = (0.25 * eps).min(0.25 * width);
            let s = s.clamp(lo + margin, hi - margin);
            j += 1.0;
            let Ok(c) = self.chart_at(a, (&c_lo, lo), (&c_hi, hi), s, needs_analysis) else {
                if bisect_next {
                    break; // even the midpoint fails: give up with the bracket so far
                }
                bisect_next = true;
                continue;
            };
            bisect_next = false;
            let gs = self.tests(&c, det_ref).values[slot];
            if gs == 0.0 {
                let mut c = c;
                if !needs_analysis && let Ok(info) = self.analyse(&c.u) {
                    c.info = info;
                }
                return (c, true, 0.0);
            }
            if gs.signum() == glo.signum() {
                lo = s;
                glo = gs;
                c_lo = c;
            } else {
                hi = s;
                ghi = gs;
                c_hi = c;
            }
        }
        let width = hi - lo;
        let located = width <= tol;
        // The bracket end nearer the zero by the test function's magnitude.
        let mut best = if glo.abs() <= ghi.abs() { c_lo } else { c_hi };
        if !needs_analysis && let Ok(info) = self.analyse(&best.u) {
            best.info = info;
        }
        (best, located, width)
    }

    /// Locates a fold in a step that has a located branch point at `s_bp`, outside a window
    /// of half-width $\Delta = 0.05 h$ around it, or returns `None` when the fold test changes
    /// sign only across the window. Next to a branch point the augmented Jacobian is nearly
    /// singular and the tangent (whose parameter component is the fold test) is dominated by
    /// error; and on a branch through a pitchfork (the asymmetric branch at a symmetry-breaking
    /// point) the parameter does turn at the branch point itself. Neither is a saddle-node.
    /// The window's ends are predicted from the step's ends (the tangent at the branch point
    /// is unreliable).
    fn locate_fold_beside(
        &mut self,
        a: &Chart,
        b: &Chart,
        h: f64,
        slot: usize,
        s_bp: f64,
    ) -> Option<(Chart, bool, f64)> {
        let det_ref = a.det.1;
        let delta = 0.05 * h;
        let g = |me: &Self, c: &Chart| me.tests(c, det_ref).values[slot];
        let ga = g(self, a);
        if s_bp - delta > 0.0
            && let Ok(before) = self.chart_at(a, (a, 0.0), (b, h), s_bp - delta, false)
            && ga * g(self, &before) <= 0.0
        {
            return Some(self.locate(a, (a, 0.0), (&before, s_bp - delta), slot));
        }
        let gb = g(self, b);
        if s_bp + delta < h
            && let Ok(after) = self.chart_at(a, (a, 0.0), (b, h), s_bp + delta, false)
            && gb * g(self, &after) <= 0.0
        {
            return Some(self.locate(a, (&after, s_bp + delta), (b, h), slot));
        }
        None
    }

    fn kind_of(slot: Slot) -> SpecialKind {
        match slot {
            Slot::Fold => SpecialKind::Fold,
            Slot::BranchPoint => SpecialKind::BranchPoint,
            Slot::PeriodDoubling => SpecialKind::PeriodDoubling,
            Slot::Torus => SpecialKind::Torus,
            Slot::Event { kind, .. } => kind,
            Slot::Bound { .. } => SpecialKind::EndPoint,
        }
    }

    #[allow(clippy::too_many_lines)]
    pub(crate) fn run(
        &mut self,
        name: &str,
        u0: &[f64],
        initial_tangent: Option<&[f64]>,
        direction: f64,
        observer: &mut dyn Observer,
    ) -> Result<Branch> {
        let n = self.n;
        let pi = self.p.parameter_index();
        // First chart. Without a given direction: correct u0 with the parameter fixed. With one
        // (branch switching, restarts): a predictor step h0 along it first, so that a start at a
        // branch point leaves it along the requested branch.
        let mut a = match initial_tangent {
            Some(t) => {
                let mut dir = t.to_vec();
                self.wnormalize(&mut dir);
                if direction < 0.0 {
                    dir.iter_mut().for_each(|x| *x = -*x);
                }
                let h0 = self.settings.h0;
                let pred: Vec<f64> = u0.iter().zip(&dir).map(|(x, t)| x + h0 * t).collect();
                let row = self.row_of(&dir);
                let (u, it) = self.correct(&pred, &row, u0, h0, false)?;
                let mut c = self.chart(u, &row, it)?;
                if self.wdot(&c.t, &dir) < 0.0 {
                    c.t.iter_mut().for_each(|x| *x = -*x);
                }
                c
            }
            None => {
                // With the parameter fixed; where that fails (a branch that does not move in
                // the parameter there, e.g. a curve perpendicular to it), on a generic
                // hyperplane through the start.
                let mut row = vec![0.0; n];
                row[pi] = 1.0;
                let (row, (u, it)) = match self.correct(u0, &row, u0, 0.0, false) {
                    Ok(x) => (row, x),
                    Err(_) => {
                        let g = generic(n);
                        let x = self.correct(u0, &g, u0, 0.0, false)?;
                        (g, x)
                    }
                };
                let mut c = self.chart(u, &row, it)?;
                if orientation(&c.t, pi) * direction < 0.0 {
                    c.t.iter_mut().for_each(|x| *x = -*x);
                }
                c
            }
        };
        // The determinant with the chart's own oriented tangent as the last row, consistent with
        // the following charts (each uses its predecessor's tangent).
        let own = self.row_of(&a.t);
        a.det = self.tangent(&a.u, &own)?.1;
        let mut label = 1;
        let mut branch = Branch {
            name: name.to_string(),
            parameter: self.p.parameter_name(),
            parameter_index: self.p.parameter_position(),
            parameter_names: self.p.parameter_names(),
            monitor_names: self.p.monitor_names(),
            points: vec![self.point(&a, label, 0.0)],
            special_points: Vec::new(),
            end: EndReason::MaxPoints,
            statistics: RunStatistics::default(),
        };
        observer.point(&branch.points[0], self.parameter(&a.u));
        let start = a.u.clone();
        let mut h = self.settings.h0;
        let mut travelled = 0.0;
        // The chart before `a` and the step from it, for the predictor; `None` after a
        // rejected step (the tangent predictor is then used).
        let mut previous: Option<(Vec<f64>, Vec<f64>, f64)> = None;
        'outer: while branch.points.len() < self.settings.max_points {
            let pred = match &previous {
                Some((u_p, t_p, h_p)) => extrapolate(u_p, t_p, *h_p, &a.u, &a.t, h),
                None => a.u.iter().zip(&a.t).map(|(x, t)| x + h * t).collect(),
            };
            let at = self.row_of(&a.t);
            let au = a.u.clone();
            let corrected = self.correct(&pred, &at, &au, h, false);
            let b = match corrected.and_then(|(u, it)| self.chart(u, &at, it)) {
                Ok(b)
                    if self.wdot(&b.t, &a.t).clamp(-1.0, 1.0).acos() <= self.settings.max_angle
                        || h <= self.settings.h_min =>
                {
                    b
                }
                Ok(_) | Err(_) if h > self.settings.h_min => {
                    self.stats.rejected_steps += 1;
                    previous = None;
                    h = (0.5 * h).max(self.settings.h_min);
                    continue;
                }
                Ok(_) => unreachable!("accepted above at h_min"),
                Err(e) => {
                    branch.end = EndReason::CorrectorFailed(e.to_string());
                    break;
                }
            };
            // Orient the new tangent along the run.
            let mut b = b;
            if self.wdot(&b.t, &a.t) < 0.0 {
                b.t.iter_mut().for_each(|x| *x = -*x);
            }
            // Sign changes of test functions, located and sorted along the step.
            let det_ref = a.det.1;
            let ta = self.tests(&a, det_ref);
            let tb = self.tests(&b, det_ref);
            let changed = |slot: usize| {
                let (ga, gb) = (ta.values[slot], tb.values[slot]);
                ga != 0.0 && ga * gb <= 0.0
            };
            // Branch points first: a fold test change next to one is the branch point's.
            let mut order: Vec<usize> = (0..self.slots.len()).filter(|&k| changed(k)).collect();
            order.sort_by_key(|&k| self.slots[k] != Slot::BranchPoint);
            let mut found: Vec<(f64, usize, Chart, bool, f64)> = Vec::new();
            self.locating = true;
            for slot in order {
                let bp = found
                    .iter()
                    .find(|f| self.slots[f.1] == Slot::BranchPoint && f.3)
                    .map(|f| f.0);
                let result = match (self.slots[slot], bp) {
                    (Slot::Fold, Some(s_bp)) => self.locate_fold_beside(&a, &b, h, slot, s_bp),
                    _ => Some(self.locate(&a, (&a, 0.0), (&b, h), slot)),
                };
                if let Some((c, located, acc)) = result {
                    let s = self.wdot(&a.t, &c.u) - self.wdot(&a.t, &a.u);
                    found.push((s, slot, c, located, acc));
                }
            }
            self.locating = false;
            found.sort_by(|x, y| x.0.total_cmp(&y.0));
            let (pa, pb) = (self.parameter(&a.u), self.parameter(&b.u));
            for (_, slot, c, located, acc) in found {
                let kind = Self::kind_of(self.slots[slot]);
                if kind == SpecialKind::Torus {
                    // Keep true tori only: a complex pair on the unit circle.
                    let complex = c
                        .info
                        .multipliers
                        .iter()
                        .zip(&c.info.trivial)
                        .any(|(m, t)| {
                            !*t && m.1.abs() > 1e-8 && (m.0.hypot(m.1) - 1.0).abs() < 1e-4
                        });
                    if !complex {
                        continue;
                    }
                }
                label += 1;
                let mut c = c;
                // At a branch point the augmented Jacobian is singular and the tangent solved
                // there tends to the other branch's direction: keep this branch's tangent, from
                // the bracketing chart (branch switching needs it). Not where only the problem's
                // branch-point factor changed sign: the Jacobian is regular there.
                if kind == SpecialKind::BranchPoint && a.det.0 != b.det.0 {
                    c.t.clone_from(&a.t);
                }
                let special = SpecialPoint {
                    kind,
                    point: self.point(&c, label, h),
                    bracket: (pa, pb),
                    located,
                    accuracy: acc,
                    on: match self.slots[slot] {
                        Slot::Event { on, .. } | Slot::Bound { on, .. } => Some(on),
                        _ => None,
                    },
                    level: match self.slots[slot] {
                        Slot::Event { level, .. } | Slot::Bound { level, .. } => Some(level),
                        _ => None,
                    },
                };
                observer.special(&special);
                branch.special_points.push(special);
                if self.settings.stop_at.contains(&kind) {
                    branch.end = EndReason::Reached(kind);
                    break 'outer;
                }
                match self.slots[slot] {
                    Slot::Bound { .. } => {
                        branch.end = EndReason::Bound;
                        break 'outer;
                    }
                    Slot::Event {
                        terminal: true,
                        kind,
                        ..
                    } => {
                        branch.end = EndReason::Inadmissible(kind);
                        break 'outer;
                    }
                    _ => {}
                }
            }
            label += 1;
            let point = self.point(&b, label, h);
            observer.point(&point, self.parameter(&b.u));
            branch.points.push(point);
            travelled += h;
            let step = h;
            // Closed branch: back near the start after a long way.
            let dist = max_abs(
                &b.u.iter()
                    .zip(&start)
                    .map(|(x, y)| x - y)
                    .collect::<Vec<_>>(),
            );
            if travelled > 10.0 * self.settings.h_max && dist < 0.5 * h && branch.points.len() > 10
            {
                branch.end = EndReason::Closed;
                break;
            }
            // Step control from the corrector's effort.
            if b.iterations <= 2 {
                h = (h * self.settings.growth).min(self.settings.h_max);
            } else if b.iterations > self.settings.target_iterations {
                h = (0.5 * h).max(self.settings.h_min);
            }
            previous = Some((std::mem::take(&mut a.u), std::mem::take(&mut a.t), step));
            a = b;
        }
        branch.statistics = self.stats;
        Ok(branch)
    }
}
