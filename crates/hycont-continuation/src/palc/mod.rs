//! Pseudo-arclength continuation (PALC) over a one-dimensional atlas of charts.
//!
//! A chart is a solution $u$ of $F(u) = 0$ ($F: \mathbb{R}^N \to \mathbb{R}^{N-1}$) with its unit
//! tangent $t$ ($J t = 0$, oriented along the run). From chart $(u_a, t_a)$ a step $h$ predicts
//! by extrapolating the quintic Hermite interpolant of $(u_a, t_a)$ and the two charts before it
//! as a graph over $t_a$'s line (fewer charts at the start and after a rejected step: the
//! tangent predictor $u_a + h t_a$ with none) and corrects on the
//! hyperplane $\langle t_a, u - u_a \rangle_W = h$ with chord Newton on the augmented system
//! $[F; \langle t_a, u - u_a \rangle_W - h]$, Jacobian $A = [J; (W t_a)^\top]$, where
//! $\langle \cdot, \cdot \rangle_W$ is the arclength inner product with the problem's unknown
//! weights (see [`crate::ContinuationProblem::unknown_weights`]; tangents have unit $W$-norm).
//! The new tangent solves $A x = e_N$. Test functions are evaluated at every chart; a sign change between two charts is
//! located on the first chart's hyperplanes, $s \mapsto$ the solution at arclength
//! $s \in (0, h)$, by the ITP method until the bracket in $s$ is below the location tolerance.
//! A fold test change beside a located branch point in the same step is the branch point's.

use crate::branch::{Branch, BranchPoint, EndReason, RunStatistics};
use crate::error::{Error, Result};
use crate::observe::Observer;
use crate::quantity::Quantity;
use crate::settings::{BoundOn, ContinuationSettings};
use crate::{ContinuationProblem, PointInfo};
use hycont_core::ParamId;
use hycont_core::linalg::SparsePattern;

mod adapt;
mod chord;
mod corrector;
pub(crate) mod critical;
mod level;
mod locate;
mod predict;
mod slots;
mod special;
mod start;

pub(crate) use predict::dot;
use predict::{GraphNode, hermite_graph, max_abs_diff};
use slots::{Crossing, Slot, Source};
pub(crate) use slots::{pd_test, tr_test};

/// The charts the stepping predictor interpolates: the current one and the two before it
/// (quintic Hermite, see [`Palc::predictor`]).
const PREDICTOR_CHARTS: usize = 3;

/// The fraction of the largest angle a step is sized to turn by (see [`Palc::next_step`]).
const ANGLE_ROOM: f64 = 0.9;

/// Within this of an event's level (relative to `1 + |level|`), a directed run's start lies
/// on the event: its first step does not locate it again ([`Palc::located_in_step`]).
const START_EVENT_TOL: f64 = 1e-9;

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
    /// The last run's first chart from a start without a direction (its start, discretisation
    /// revision and chart): a run the other way from the same start begins there too.
    first: Option<(Vec<f64>, usize, Chart)>,
    /// Factorisations so far (a held factorisation is valid while this has not changed).
    generation: u64,
    /// The last stepping chart's factorisation, for the next step's chord steps.
    held: Option<chord::Held>,
    /// Chord steps armed for the next corrector call (by [`Palc::step`] only).
    chord: Option<chord::Chord>,
    /// $A^{-1} e_n$ of the last tangent, before normalisation.
    z: Vec<f64>,
    /// Work space: the corrector's step.
    du: Vec<f64>,
    /// Whether the last correction converged by chord steps alone: one of its iterations
    /// counts for the step control's growth what a Newton iteration it replaced does not (a
    /// linear contraction takes one more iteration from the same start; see
    /// [`Palc::next_step`]).
    chord_converged: bool,
    _marker: std::marker::PhantomData<&'a ()>,
}

impl<'p, 'a, P: ContinuationProblem<'a> + ?Sized> Palc<'p, 'a, P> {
    pub(crate) fn new(p: &'p mut P, settings: ContinuationSettings) -> Result<Self> {
        settings.validate()?;
        let (pattern, k, n, w) = Self::layout(p)?;
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
        if d.codim2
            && let Some(second) = p.cusp_parameter()
        {
            slots.push(Slot::Cusp { second });
        }
        if d.codim2
            && let Some(held) = p.held_multiplier()
        {
            for crossing in [Crossing::Plus, Crossing::Minus, Crossing::Circle] {
                slots.push(Slot::Codim2 {
                    kind: crossing.kind(held),
                    held,
                    crossing,
                });
            }
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
            first: None,
            generation: 0,
            held: None,
            chord: None,
            z: Vec::new(),
            du: Vec::new(),
            chord_converged: false,
            _marker: std::marker::PhantomData,
        })
    }

    /// The augmented Jacobian's pattern and the position of its last row, the number of
    /// unknowns and their arclength weights, for the problem's current discretisation.
    fn layout(p: &mut P) -> Result<(SparsePattern, usize, usize, Vec<f64>)> {
        let problem = p.problem();
        let (pattern, k) = crate::switch::augmented_pattern(problem)?;
        let n = problem.unknowns();
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
        Ok((pattern, k, n, w))
    }

    /// Takes the layout of the problem's discretisation after it changed (a refined mesh has
    /// more unknowns, another pattern and other weights).
    fn relayout(&mut self) -> Result<()> {
        let (pattern, k, n, w) = Self::layout(self.p)?;
        self.pattern = pattern;
        self.generation += 1;
        self.k = k;
        self.n = n;
        self.w = w;
        self.res = vec![0.0; n];
        self.values.clear();
        Ok(())
    }

    /// Returns the problem to discretisation `revision`, and its layout.
    fn restore(&mut self, revision: usize) -> Result<()> {
        if self.p.discretisation_revision() != revision
            && self.p.restore_discretisation(revision)?
        {
            self.relayout()?;
        }
        Ok(())
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
        let n = a.len().min(b.len()).min(self.w.len());
        let (a, b, w) = (&a[..n], &b[..n], &self.w[..n]);
        // Four interleaved partial sums (independent additions), as `predict::dot`.
        let mut s = [0.0f64; 4];
        let (ca, cb, cw) = (a.chunks_exact(4), b.chunks_exact(4), w.chunks_exact(4));
        let tail: f64 = (ca.remainder().iter().zip(cb.remainder()))
            .zip(cw.remainder())
            .map(|((x, y), w)| w * x * y)
            .sum();
        for ((x, y), w) in ca.zip(cb).zip(cw) {
            for l in 0..4 {
                s[l] += w[l] * x[l] * y[l];
            }
        }
        (s[0] + s[1]) + (s[2] + s[3]) + tail
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

    fn point(&self, c: &Chart, label: usize, step: f64) -> BranchPoint {
        BranchPoint {
            label,
            discretisation: self.p.discretisation_revision(),
            ..BranchPoint::from_info(&c.info, c.u.clone(), c.t.clone(), c.iterations, step)
        }
    }

    /// The largest difference between chart `b` and the run's start (its unknowns and
    /// analysis, on discretisation `revision`): of the unknowns on the start's discretisation;
    /// on another one (the unknowns do not compare), of the parameters and monitors.
    fn distance_to_start(&self, b: &Chart, start: &(Vec<f64>, PointInfo), revision: usize) -> f64 {
        if self.p.discretisation_revision() == revision {
            max_abs_diff(&b.u, &start.0)
        } else {
            let params = max_abs_diff(&b.info.params, &start.1.params);
            params.max(max_abs_diff(&b.info.monitors, &start.1.monitors))
        }
    }

    /// The next chart from `a` by a step `h` from the predictor `pred`, with the angle its
    /// tangent turned from `a`'s: `Ok(None)` when the step is rejected (the corrector fails or
    /// the tangent turns by more than the largest angle) and may be retried shorter; an error
    /// when it fails at the smallest step.
    fn step(&mut self, a: &Chart, pred: Vec<f64>, h: f64) -> Result<Option<(Chart, f64)>> {
        let at = self.row_of(&a.t);
        // Chord steps from `a`'s factorisation, if it is still the one factorised.
        let generation = self.generation;
        let chords = self.p.chord_steps();
        self.chord = (self.held.take())
            .filter(|held| chords && held.generation == generation)
            .and_then(|held| chord::Chord::new(held, &at));
        let corrected = self.correct(pred, &at, &a.u, h, false);
        self.chord = None;
        let h_min = self.settings.h_min;
        match corrected.and_then(|(u, it)| self.chart(u, &at, it)) {
            Ok(mut b) => {
                let cos = self.wdot(&b.t, &a.t);
                if h > h_min && cos.clamp(-1.0, 1.0).acos() > self.settings.max_angle {
                    return Ok(None);
                }
                // Orient the new tangent along the run.
                if cos < 0.0 {
                    b.t.iter_mut().for_each(|x| *x = -*x);
                }
                Ok(Some((b, cos.abs().min(1.0).acos())))
            }
            Err(e) if h <= h_min => Err(e),
            Err(_) => Ok(None),
        }
    }

    /// The predictor of a step `h` from chart `a`: the Hermite interpolant of `a` and the
    /// charts before it (`previous`, the latest first) as a graph over `a`'s tangent line
    /// (see [`hermite_graph`]), with the charts before it taken while each lies behind the one
    /// after it and its tangent is within 60 degrees of `a`'s; the tangent predictor
    /// $u_a + h t_a$ without them.
    fn predictor(&self, a: &Chart, previous: &[(Vec<f64>, Vec<f64>)], h: f64) -> Vec<f64> {
        let at_a = self.wdot(&a.t, &a.u);
        let mut nodes = vec![GraphNode {
            sigma: 0.0,
            u: &a.u,
            t: &a.t,
            along: 1.0,
        }];
        for (u, t) in previous {
            let (sigma, along) = (self.wdot(&a.t, u) - at_a, self.wdot(&a.t, t));
            let behind = nodes.last().is_some_and(|last| sigma < last.sigma);
            if !(behind && along > 0.5) {
                break;
            }
            nodes.push(GraphNode { sigma, u, t, along });
        }
        hermite_graph(&nodes, h)
    }

    /// The next step after a corrector that took `iterations`: longer (by the growth factor,
    /// up to the largest step) after at most two, halved (down to the smallest) after more than
    /// the target. A correction by chord steps alone is passed with one iteration less: from the
    /// predictor's residual $r_0$ chord steps contract linearly (by the Jacobian's change over
    /// the step) where Newton's contract quadratically, and they take about one more to the
    /// tolerance.
    ///
    /// Either way no longer than a turn of the tangent by [`ANGLE_ROOM`] of the largest angle, at
    /// `bending` (the turn per unit step expected over the next step): where the branch's
    /// curvature bounds the steps (an easy corrector, as the high-order predictor makes it),
    /// they follow it below the angle instead of growing into a rejection, halving and growing
    /// again.
    fn next_step(&self, h: f64, iterations: usize, bending: f64) -> f64 {
        let s = &self.settings;
        let next = if iterations <= 2 {
            h * s.growth
        } else if iterations > s.target_iterations {
            0.5 * h
        } else {
            h
        };
        next.min(ANGLE_ROOM * s.max_angle / bending)
            .clamp(s.h_min, s.h_max)
    }

    /// The turn of the tangent per unit step expected over the next step, from this step's
    /// (`turned` over `h`) and the one before it (`last`, updated): this step's, times its rise
    /// since the last (a rising curvature rises on), by at most the growth factor.
    fn bending_ahead(&self, turned: f64, h: f64, last: &mut Option<f64>) -> f64 {
        let now = turned / h;
        let trend = match *last {
            Some(before) if before > 0.0 => (now / before).clamp(1.0, self.settings.growth),
            _ => 1.0,
        };
        *last = Some(now);
        now * trend
    }

    pub(crate) fn run(
        &mut self,
        name: &str,
        u0: &[f64],
        initial_tangent: Option<&[f64]>,
        direction: f64,
        observer: &mut dyn Observer,
    ) -> Result<Branch> {
        self.check_start(u0, initial_tangent, direction)?;
        self.stats = RunStatistics::default();
        // A factorisation held from an earlier run (its last chart, far from this start) is
        // not this run's: the first chart holds its own where it makes one.
        self.held = None;
        let revision = self.p.discretisation_revision();
        let mut a = self.first_chart(u0, initial_tangent, direction)?;
        let mut label = 1;
        let mut since_adapted = 0;
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
        // Along a given direction the first chart is a step away from the start: that step
        // is tested like any other (a period doubling just past the one switched at, say).
        if let Some(t) = initial_tangent {
            let z = self.directed_start(u0, t, &a)?;
            let h0 = self.settings.first_step();
            if let Some(end) =
                self.record_special_points((&z, &a), h0, &mut label, &mut branch, observer, true)
            {
                branch.end = end;
                branch.points.clear();
                branch.statistics = self.stats;
                branch.attach_measure_keys();
                return Ok(branch);
            }
        }
        let start = (a.u.clone(), a.info.clone());
        let mut h = self.settings.first_step();
        let mut travelled = 0.0;
        // The charts before `a` (the latest first), for the predictor; cleared after a
        // rejected step (the tangent predictor is then used).
        let mut previous: Vec<(Vec<f64>, Vec<f64>)> = Vec::with_capacity(PREDICTOR_CHARTS);
        // The last step's turn of the tangent per unit step (see `next_step`).
        let mut bending: Option<f64> = None;
        while branch.points.len() < self.settings.max_points {
            let pred = self.predictor(&a, &previous, h);
            let (b, turned) = match self.step(&a, pred, h) {
                Ok(Some(stepped)) => {
                    // `b`'s chart factorised [J(b); W t_a] last: the next step's chords.
                    self.held = Some(chord::Held {
                        generation: self.generation,
                        row: self.row_of(&a.t),
                        z: std::mem::take(&mut self.z),
                    });
                    stepped
                }
                Ok(None) => {
                    self.stats.rejected_steps += 1;
                    previous.clear();
                    h = (0.5 * h).max(self.settings.h_min);
                    continue;
                }
                Err(e) => {
                    branch.end = EndReason::CorrectorFailed(e.to_string());
                    break;
                }
            };
            if let Some(end) =
                self.record_special_points((&a, &b), h, &mut label, &mut branch, observer, false)
            {
                branch.end = end;
                break;
            }
            label += 1;
            let point = self.point(&b, label, h);
            observer.point(&point, self.parameter(&b.u));
            branch.points.push(point);
            if observer.stop() {
                branch.end = EndReason::Stopped;
                break;
            }
            travelled += h;
            // Closed branch: back near the start after a long way.
            let dist = self.distance_to_start(&b, &start, revision);
            if travelled > 10.0 * self.settings.h_max && dist < 0.5 * h && branch.points.len() > 10
            {
                branch.end = EndReason::Closed;
                break;
            }
            let bend = self.bending_ahead(turned, h, &mut bending);
            h = self.next_step(h, b.iterations - usize::from(self.chord_converged), bend);
            previous.truncate(PREDICTOR_CHARTS - 2);
            previous.insert(0, (std::mem::take(&mut a.u), std::mem::take(&mut a.t)));
            a = b;
            since_adapted += 1;
            if self.adaptation_due(&a, since_adapted) {
                since_adapted = 0;
                if let Some(c) = self.rediscretised(&a)? {
                    // The predictor restarts from the tangent: the previous charts are on
                    // the old discretisation.
                    previous.clear();
                    a = c;
                }
            }
        }
        self.restore(revision)?;
        branch.statistics = self.stats;
        branch.attach_measure_keys();
        Ok(branch)
    }
}
