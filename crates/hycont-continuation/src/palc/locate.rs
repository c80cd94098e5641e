//! Locating special points in a step: charts at a given arclength on a chart's hyperplanes, the
//! ITP root bracket on a test function, and folds beside a branch point.

use super::predict::{GraphNode, hermite_graph};
use super::slots::{Slot, Source};
use super::{Chart, Palc};
use crate::ContinuationProblem;
use crate::error::Result;

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// The chart at arclength `s` on chart `a`'s hyperplanes, with `a`'s tangent as reference row
    /// (so that the determinant is continuous in `s`). With `analyse == false` the point's
    /// analysis (multipliers, monitors) is copied from `a` (enough for the fold and branch-point
    /// tests, which use the tangent and the determinant only).
    ///
    /// The predictor interpolates the bracket's charts `lo` (at `s_lo`) and `hi` (at `s_hi`) as
    /// a graph over `a`'s tangent line (cubic Hermite in $s$ with slopes
    /// $t / \langle t_a, t \rangle_W$, see [`hermite_graph`]), which keeps it on the hyperplane
    /// and makes it accurate to $O(w^4)$ in the bracket width $w$, so that late in a location
    /// the predictor is already a solution; linear where a slope is unreliable (the tangent
    /// turns away from $t_a$, e.g. next to a branch point).
    pub(super) fn chart_at(
        &mut self,
        a: &Chart,
        (lo, s_lo): (&Chart, f64),
        (hi, s_hi): (&Chart, f64),
        s: f64,
        analyse: bool,
    ) -> Result<Chart> {
        let pred = self.bracket_predictor(a, (lo, s_lo), (hi, s_hi), s);
        let row = self.row_of(&a.t);
        let (u, it) = self.correct(pred, &row, &a.u, s, true)?;
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

    /// The predictor of [`Palc::chart_at`]: the bracket's charts interpolated at arclength `s`.
    pub(super) fn bracket_predictor(
        &self,
        a: &Chart,
        (lo, s_lo): (&Chart, f64),
        (hi, s_hi): (&Chart, f64),
        s: f64,
    ) -> Vec<f64> {
        let x = (s - s_lo) / (s_hi - s_lo);
        let (d_lo, d_hi) = (self.wdot(&a.t, &lo.t), self.wdot(&a.t, &hi.t));
        if d_lo > 0.5 && d_hi > 0.5 {
            let nodes = [(lo, s_lo, d_lo), (hi, s_hi, d_hi)].map(|(c, sigma, along)| GraphNode {
                sigma,
                u: &c.u,
                t: &c.t,
                along,
            });
            hermite_graph(&nodes, s)
        } else {
            lo.u.iter()
                .zip(&hi.u)
                .map(|(p, q)| p + x * (q - p))
                .collect()
        }
    }

    /// Locates the zero of test slot `slot` between the charts `lo` and `hi` at arclengths
    /// `s_lo < s_hi` on chart `a`'s hyperplanes, by the ITP method (Oliveira and Takahashi,
    /// 2020: regula falsi, truncated towards the midpoint and projected into a shrinking
    /// interval around it; once trials shrink the bracket fast, inverse quadratic interpolation
    /// through three points in place of regula falsi, see [`Itp::trial`]). It converges
    /// superlinearly for smooth test functions, from both sides (the truncation steps over the
    /// root, so the bracket, not just one end, shrinks),
    /// and never needs more than one evaluation beyond bisection's
    /// $\lceil \log_2 (w_0 / \mathrm{tol}) \rceil$. A trial whose corrector fails (next to a
    /// branch point the augmented Jacobian is singular) is retried at the midpoint. Returns the
    /// chart, whether the bracket in `s` reached the tolerance, and the final bracket width; on
    /// failure, the better bracket end.
    pub(super) fn locate(
        &mut self,
        a: &Chart,
        (lo_chart, s_lo): (&Chart, f64),
        (hi_chart, s_hi): (&Chart, f64),
        slot: usize,
    ) -> (Chart, bool, f64) {
        if let Some(found) = self.locate_level(a, (lo_chart, s_lo), (hi_chart, s_hi), slot) {
            return found;
        }
        let det_ref = a.det.1;
        let tol = self.settings.locate_tol;
        let (mut lo, mut hi) = (s_lo, s_hi);
        let mut glo = self.tests(lo_chart, det_ref).values[slot];
        let mut ghi = self.tests(hi_chart, det_ref).values[slot];
        let (mut c_lo, mut c_hi) = (lo_chart.clone(), hi_chart.clone());
        let itp = Itp::new(hi - lo, tol);
        let mut j = 0.0;
        let mut bisect_next = false;
        // The point the last trial displaced from the bracket, while trials shrink it fast.
        let mut third = None;
        let needs_analysis = self.needs_analysis(a, slot);
        for _ in 0..200 {
            let width = hi - lo;
            if width <= tol {
                break;
            }
            let s = if bisect_next || glo == ghi {
                0.5 * (lo + hi)
            } else {
                itp.trial((lo, glo), (hi, ghi), j, third)
            };
            // Strictly inside the bracket (the projection allows its ends in exact arithmetic).
            let margin = (0.25 * itp.eps).min(0.25 * width);
            let s = s.clamp(lo + margin, hi - margin);
            j += 1.0;
            let Ok(c) = self.chart_at(a, (&c_lo, lo), (&c_hi, hi), s, needs_analysis) else {
                third = None;
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
            let displaced = if gs.signum() == glo.signum() {
                c_lo = c;
                let old = (lo, glo);
                (lo, glo) = (s, gs);
                old
            } else {
                c_hi = c;
                let old = (hi, ghi);
                (hi, ghi) = (s, gs);
                old
            };
            third = (hi - lo <= Itp::FAST * width).then_some(displaced);
        }
        let width = hi - lo;
        let located = width <= tol;
        // The bracket end nearer the zero by the test function's magnitude; for an event that
        // ends the run (e.g. an orbit leaving its domain), the end before the crossing, so that
        // a branch's last point is still on the admissible side.
        let terminal = matches!(self.slots[slot], Slot::Event { terminal: true, .. });
        let mut best = if (terminal && located) || glo.abs() <= ghi.abs() {
            c_lo
        } else {
            c_hi
        };
        if !needs_analysis && let Ok(info) = self.analyse(&best.u) {
            best.info = info;
        }
        (best, located, width)
    }

    /// Whether the trial points of a location of `slot` need the analysis: fold and
    /// branch-point tests do not, unless the branch-point test has a factor from the analysis;
    /// events and bounds do unless they are on the continued parameter.
    fn needs_analysis(&self, a: &Chart, slot: usize) -> bool {
        match self.slots[slot] {
            Slot::Fold | Slot::Cusp { .. } => false,
            Slot::BranchPoint => a.info.branch_point_factor.is_some(),
            Slot::Event { source, .. } | Slot::Bound { source, .. } => source != Source::Continued,
            _ => true,
        }
    }

    /// Locates a fold in a step that has a located branch point at `s_bp`, outside a window
    /// of half-width $\Delta = 0.05 h$ around it, or returns `None` when the fold test changes
    /// sign only across the window. Next to a branch point the augmented Jacobian is nearly
    /// singular and the tangent (whose parameter component is the fold test) is dominated by
    /// error; and on a branch through a pitchfork (the asymmetric branch at a symmetry-breaking
    /// point) the parameter does turn at the branch point itself. Neither is a saddle-node.
    /// The window's ends are predicted from the step's ends (the tangent at the branch point
    /// is unreliable).
    pub(super) fn locate_fold_beside(
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
}

/// The ITP method's constants for a bracket of width `w0` and tolerance `tol`: $\epsilon$ =
/// tol / 2 (stop when the bracket is at most tol), $\kappa_1 = 0.02 / w_0$, $\kappa_2 = 2$,
/// $n_0 = 1$; the truncation is at least $\epsilon / 100$.
///
/// The small $\kappa_1$ keeps the early trials near the regula falsi point (5 to 6 corrector
/// solves per located point on the rocking block's branches with regula falsi alone, against 7
/// to 8 with the paper's $0.2 / w_0$; 4 to 5 with the three-point interpolation). Once the
/// interpolation is accurate the overshoot $\kappa_1 w^2$ falls to roundoff; the floor keeps
/// trials off the interpolated zero itself (where the augmented Jacobian of a branch point can
/// be exactly singular: a symmetry-breaking point at parameter 0 to the last bit), far below
/// the tolerance.
struct Itp {
    eps: f64,
    kappa1: f64,
    n_max: f64,
}

impl Itp {
    /// A trial that left at most this share of the bracket lets the next one interpolate
    /// through three points (see [`Itp::trial`]).
    const FAST: f64 = 0.35;
    /// The truncation after such a trial, as a share of the interpolations' difference.
    const GAMMA: f64 = 0.3;

    fn new(w0: f64, tol: f64) -> Self {
        let eps = 0.5 * tol;
        Self {
            eps,
            kappa1: 0.02 / w0,
            n_max: (w0 / (2.0 * eps)).log2().ceil().max(0.0) + 1.0,
        }
    }

    /// Trial `j` (from 0) in the bracket `[lo, hi]` with the function's values there: regula
    /// falsi, truncated towards the midpoint by $\max(\kappa_1 w^2, \epsilon / 100)$, projected
    /// into the interval of radius $\epsilon 2^{n_{\max} - j} - w / 2$ around the midpoint.
    ///
    /// With `third`, the point the last trial displaced from the bracket when that trial left
    /// at most [`Itp::FAST`] of it (the interpolation is working), the estimate is inverse
    /// quadratic interpolation through the three points (where it falls inside the bracket),
    /// and the truncation at most [`Itp::GAMMA`] times its distance from regula falsi's, a
    /// measure of the cruder estimate's error: the trial lands just past the zero instead of
    /// $\kappa_1 w^2$ past it, and the bracket closes in fewer trials (4 to 5 instead of 5 to 6
    /// on the rocking block's test functions). A slow trial returns to regula falsi; the
    /// projection bounds the trials as before.
    fn trial(
        &self,
        (lo, glo): (f64, f64),
        (hi, ghi): (f64, f64),
        j: f64,
        third: Option<(f64, f64)>,
    ) -> f64 {
        let width = hi - lo;
        let mid = 0.5 * (lo + hi);
        let r = (self.eps * 2f64.powf(self.n_max - j) - 0.5 * width).max(0.0);
        let x_f = (ghi * lo - glo * hi) / (ghi - glo);
        let truncation = self.kappa1 * width * width;
        let (x_e, delta) = match third.and_then(|p| inverse_quadratic((lo, glo), (hi, ghi), p)) {
            Some(x_q) => (x_q, truncation.min(Self::GAMMA * (x_q - x_f).abs())),
            None => (x_f, truncation),
        };
        let delta = delta.max(0.01 * self.eps);
        let sigma = (mid - x_e).signum();
        let x_t = if delta <= (mid - x_e).abs() {
            x_e + sigma * delta
        } else {
            mid
        };
        if (x_t - mid).abs() <= r {
            x_t
        } else {
            mid - sigma * r
        }
    }
}

/// The zero of the quadratic in $g$ through three points $(x, g)$ (inverse quadratic
/// interpolation), if their values differ and it lies strictly inside `(lo, hi)`.
fn inverse_quadratic(
    (lo, glo): (f64, f64),
    (hi, ghi): (f64, f64),
    (p, gp): (f64, f64),
) -> Option<f64> {
    if glo == ghi || gp == glo || gp == ghi {
        return None;
    }
    let x = lo * ghi * gp / ((glo - ghi) * (glo - gp))
        + hi * glo * gp / ((ghi - glo) * (ghi - gp))
        + p * glo * ghi / ((gp - glo) * (gp - ghi));
    (x > lo && x < hi).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::Itp;

    /// Brackets the zero of `f` in $[0, 1]$ to `tol` as [`super::Palc::locate`] does (trials
    /// kept strictly inside the bracket), calling `on_trial` with each trial; returns the final
    /// bracket and the number of trials.
    fn bracket(f: impl Fn(f64) -> f64, tol: f64, on_trial: impl FnMut(f64)) -> (f64, f64, f64) {
        bracket_on(f, (0.0, 1.0), tol, true, on_trial)
    }

    /// [`bracket`] on `(a, b)`, with the three-point interpolation or (`interpolate == false`)
    /// regula falsi only.
    fn bracket_on(
        f: impl Fn(f64) -> f64,
        (a, b): (f64, f64),
        tol: f64,
        interpolate: bool,
        mut on_trial: impl FnMut(f64),
    ) -> (f64, f64, f64) {
        let (mut lo, mut hi) = (a, b);
        let (mut glo, mut ghi) = (f(lo), f(hi));
        let itp = Itp::new(hi - lo, tol);
        let (mut j, mut third) = (0.0, None);
        while hi - lo > tol && j <= 100.0 {
            let width = hi - lo;
            let margin = (0.25 * itp.eps).min(0.25 * width);
            let x = itp
                .trial((lo, glo), (hi, ghi), j, third.filter(|_| interpolate))
                .clamp(lo + margin, hi - margin);
            on_trial(x);
            let g = f(x);
            let displaced = if g.signum() == glo.signum() {
                let old = (lo, glo);
                (lo, glo) = (x, g);
                old
            } else {
                let old = (hi, ghi);
                (hi, ghi) = (x, g);
                old
            };
            third = (hi - lo <= Itp::FAST * width).then_some(displaced);
            j += 1.0;
        }
        (lo, hi, j)
    }

    /// ITP brackets the root of a smooth function to the tolerance in no more evaluations
    /// than bisection's $\lceil \log_2(w_0 / \mathrm{tol}) \rceil$ plus one (its guarantee),
    /// and far fewer for a smooth one: $x^3 - 0.3$ on $[0, 1]$ (root $0.3^{1/3}$), to 1e-12.
    #[test]
    fn itp_converges_within_bisections_bound() {
        let (lo, hi, j) = bracket(|x| x * x * x - 0.3, 1e-12, |_| {});
        assert!(j <= 41.0, "more than bisection's 40 + 1 evaluations");
        let root = 0.3f64.cbrt();
        assert!(lo <= root + 1e-15 && root <= hi + 1e-15, "{lo} {hi} {root}");
        assert!(j < 15.0, "superlinear: {j} evaluations");
    }

    /// Where the interpolation is exact (a linear function, zero at 0.3 on $[0, 1]$), no
    /// trial is the zero itself: each stays about $\epsilon / 100$ = tol / 200 away or more (at
    /// a branch point the augmented Jacobian can be exactly singular there). Regula falsi alone
    /// overshoots the zero by $\kappa_1 w^2$ on alternate sides, so the bracket shrinks as
    /// $w \mapsto \kappa_1 w^2$: 1, 0.32, 0.022, 2e-3, 1e-5, 8e-8, then below the tolerance
    /// (6 trials). With three points the interpolations agree, the truncation falls to its
    /// floor and the bracket closes in 3.
    #[test]
    fn trials_keep_off_an_exactly_interpolated_zero() {
        let (root, tol) = (0.3, 1e-10);
        for (interpolate, most) in [(false, 6.0), (true, 3.0)] {
            let (lo, hi, j) = bracket_on(
                |x| x - root,
                (0.0, 1.0),
                tol,
                interpolate,
                |x| assert!((x - root).abs() >= 0.004 * tol, "trial {x} at the zero"),
            );
            assert!(lo <= root && root <= hi, "{lo} {hi}");
            assert!(j <= most, "{j} trials (interpolation {interpolate})");
        }
    }

    /// Test functions like the rocking block's (fold, branch-point, grazing and bound tests
    /// over a step of 0.1, to its location tolerance 1e-10): $g(s) = d + C d^2 + C^2 d^3$ with
    /// $d = s - s^*$, their zeros $s^*$ and relative curvatures $C$ (from the regula falsi
    /// error on the whole step, $C \approx e / ((s^* - s_{lo})(s_{hi} - s^*))$). The
    /// three-point interpolation closes each bracket in at most 5 trials and saves at least
    /// five in all against regula falsi alone (5, 5, 5, 4, 4 trials against 7, 5, 6, 6, 6).
    #[test]
    fn three_points_close_smooth_brackets_sooner() {
        let cases = [
            (0.081_027, 1.56),
            (0.097_423_9, 0.055),
            (0.058_975_8, 0.04),
            (0.026_107_4, 0.0057),
            (0.015_391_5, 0.0024),
        ];
        let (mut with, mut without) = (0.0, 0.0);
        for (root, c) in cases {
            let g = |s: f64| {
                let d = s - root;
                d + c * d * d + c * c * d * d * d
            };
            let (lo, hi, j) = bracket_on(g, (0.0, 0.1), 1e-10, true, |_| {});
            assert!(lo <= root && root <= hi + 1e-15, "{lo} {hi} {root}");
            assert!(j <= 5.0, "{j} trials for C = {c}");
            with += j;
            without += bracket_on(g, (0.0, 0.1), 1e-10, false, |_| {}).2;
        }
        assert!(with <= without - 5.0, "{with} trials against {without}");
    }

    /// Where the interpolation misleads (a zero where the derivative is infinite, $\sqrt{|d|}$,
    /// or a step, $\arctan(10^4 d)$), the bracket still closes within bisection's bound plus
    /// one ($\lceil \log_2(0.1 / 10^{-10}) \rceil + 1 = 31$).
    #[test]
    fn misleading_interpolation_keeps_the_bound() {
        let cases: [(&dyn Fn(f64) -> f64, f64); 2] = [
            (
                &|s: f64| (s - 0.037).signum() * (s - 0.037).abs().sqrt(),
                0.037,
            ),
            (&|s: f64| (1e4 * (s - 0.0333)).atan(), 0.0333),
        ];
        for (g, root) in cases {
            let (lo, hi, j) = bracket_on(g, (0.0, 0.1), 1e-10, true, |_| {});
            assert!(lo <= root + 1e-15 && root <= hi + 1e-15, "{lo} {hi} {root}");
            assert!(
                hi - lo <= 1e-10 && j <= 31.0,
                "{j} trials, width {}",
                hi - lo
            );
        }
    }
}
