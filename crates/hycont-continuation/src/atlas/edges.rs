//! Boundary charts: locating an edge (a test function's zero) between a chart and a
//! candidate beyond it, and the edge's tangent line as a cut of the boundary chart's polygon.

use super::EdgeCut;
use super::cover::{Candidate, Grower};
use super::polygon::HalfPlane;
use crate::ContinuationProblem;

/// Iterations of the edge location.
const MAX_LOCATE: usize = 80;

impl<'a, P: ContinuationProblem<'a> + ?Sized> Grower<'_, '_, 'a, P> {
    /// The edge point between chart `i` and the candidate `cand` at `s` (which has a negative
    /// test): for each negative test, its zero along the ray from chart `i` (or, where chart
    /// `i` is on that edge already, across the edge from `s`); the nearest located point
    /// with every test non-negative, its distance from chart `i`'s centre in its tangent
    /// coordinates and its test's index.
    pub(super) fn edge_point(
        &mut self,
        i: usize,
        s: [f64; 2],
        cand: &Candidate,
    ) -> Option<(f64, Candidate, usize)> {
        let mut best: Option<(f64, Candidate, usize)> = None;
        let negative: Vec<usize> = (0..cand.values.len())
            .filter(|&k| cand.values[k] < 0.0)
            .collect();
        for k in negative {
            let edge = self.tests[k].edge();
            let chart = &self.atlas.charts[i];
            let located = if chart.edge == Some(edge) && !chart.cuts.is_empty() {
                let n = chart.cuts[0].line.normal;
                let len = n[0].hypot(n[1]);
                self.across(i, s, [-n[0] / len, -n[1] / len], k, cand.values[k])
            } else if chart.tests[k] > 0.0 {
                let g0 = chart.tests[k];
                self.locate(
                    i,
                    k,
                    |t| [t * s[0], t * s[1]],
                    (1.0, cand.values[k]),
                    (0.0, g0),
                    None,
                )
            } else {
                None
            };
            let Some((at, point)) = located else { continue };
            if point.values.iter().all(|&v| v >= 0.0) && best.as_ref().is_none_or(|b| at < b.0) {
                best = Some((at, point, k));
            }
        }
        best
    }

    /// From chart `i` on edge `k`, a candidate at `s` beyond the edge: the edge point on the
    /// line $s + \tau n$ ($n$ the edge's inward normal in chart `i`'s coordinates).
    fn across(
        &mut self,
        i: usize,
        s: [f64; 2],
        n: [f64; 2],
        k: usize,
        g_out: f64,
    ) -> Option<(f64, Candidate)> {
        let r = self.atlas.charts[i].radius;
        let line = |t: f64| [s[0] + t * n[0], s[1] + t * n[1]];
        for tau in [0.25 * r, 0.5 * r, r] {
            let (c, _) = self.solve_at(i, line(tau))?;
            if c.values[k] >= 0.0 {
                let g_in = c.values[k];
                let (_, point) = self.locate(i, k, line, (0.0, g_out), (tau, g_in), Some(c))?;
                // Ordered by the distance along the edge (all are at about one radius).
                return Some((r, point));
            }
        }
        None
    }

    /// The zero of test `k` on the line `line(t)` of chart `i`'s coordinates between
    /// `outside` (negative) and `inside` (non-negative, with its candidate if it is not chart
    /// `i` itself), by the Illinois method to the location tolerance; the inside end of the
    /// last bracket (its position and candidate).
    fn locate(
        &mut self,
        i: usize,
        k: usize,
        line: impl Fn(f64) -> [f64; 2],
        outside: (f64, f64),
        inside: (f64, f64),
        inside_point: Option<Candidate>,
    ) -> Option<(f64, Candidate)> {
        let tol = self.atlas.settings.locate_tol * self.atlas.charts[i].radius;
        let ((mut a, mut ga), (mut b, mut gb)) = (outside, inside);
        let mut best = inside_point;
        let length = |x: f64, y: f64| {
            let (p, q) = (line(x), line(y));
            (p[0] - q[0]).hypot(p[1] - q[1])
        };
        let mut side = 0i8;
        for _ in 0..MAX_LOCATE {
            if length(a, b) <= tol {
                break;
            }
            let t = (a * gb - b * ga) / (gb - ga);
            let t = if t.is_finite() && (t - a) * (t - b) < 0.0 {
                t
            } else {
                0.5 * (a + b)
            };
            let (c, _) = self.solve_at(i, line(t))?;
            let g = c.values[k];
            if g < 0.0 {
                (a, ga) = (t, g);
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                (b, gb) = (t, g);
                best = Some(c);
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        let at = line(b);
        best.map(|c| (at[0].hypot(at[1]), c))
    }

    /// The halfplane of chart `cand` that keeps the inside of test `k`'s zero (linearised:
    /// $g + \nabla g \cdot s \ge 0$; $g \approx 0$ on a boundary chart), with the gradient of the test in the chart's tangent
    /// coordinates from differences over a quarter of the radius `r` (a secant over the
    /// chart's size: the cut stands for the edge across the chart).
    pub(super) fn cut(&mut self, cand: &Candidate, k: usize, r: f64) -> Option<EdgeCut> {
        let h = 0.25 * r;
        let mut grad = [0.0; 2];
        for (a, g) in grad.iter_mut().enumerate() {
            let pred: Vec<f64> = cand
                .u
                .iter()
                .zip(&cand.basis[a])
                .map(|(u, t)| u + h * t)
                .collect();
            let (u, it) = self.solver.project(&pred, &cand.basis).ok()?;
            let c = self.evaluate_at(u, it)?;
            *g = (c.values[k] - cand.values[k]) / h;
        }
        let len = grad[0].hypot(grad[1]);
        (len > 0.0 && len.is_finite()).then(|| EdgeCut {
            line: HalfPlane {
                normal: [-grad[0] / len, -grad[1] / len],
                offset: cand.values[k] / len,
            },
            test: k,
            radius: r,
        })
    }
}
