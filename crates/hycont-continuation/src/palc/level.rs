//! Levels of the continued parameter (bounds, user points) located directly: the branch's point
//! with the parameter at the level, by one correction with that level as the last equation (as
//! COCO locates events on continuation parameters), instead of a root bracket in arclength.

use super::slots::{Slot, Source};
use super::{Chart, Palc};
use crate::ContinuationProblem;

impl<'a, P: ContinuationProblem<'a> + ?Sized> Palc<'_, 'a, P> {
    /// The point of the bracket `lo` (at arclength `s_lo`) to `hi` (at `s_hi`) on chart `a`'s
    /// hyperplanes where the continued parameter reaches the level of `slot`, when `slot` is a
    /// bound on it or a non-terminal event on it (a terminal event ends the run at the last
    /// point before its level instead); `None` otherwise, or when the correction fails, lands
    /// outside the bracket or is no closer to the level than the location's tolerance in
    /// arclength (next to a fold of the parameter), where the root bracket takes over.
    ///
    /// The predictor is the bracket's interpolant at the arclength where the parameter
    /// interpolates linearly to the level $\mu$; the corrector solves $F(u) = 0$,
    /// $u_\mu = \mu$ on the augmented Jacobian $[J; e_\mu^\top]$. Its null vector is $J$'s, so
    /// the tangent comes from that factorisation; the determinant with `a`'s tangent row $r$
    /// (the row of [`Palc::chart_at`]'s charts, for the branch-point test) is
    /// $\det [J; r] = \det [J; e_\mu^\top]\,(r \cdot z)$, $z = [J; e_\mu^\top]^{-1} e_n$ (a
    /// rank-one change of the last row; $e_\mu \cdot z = 1$). The analysis is read off the
    /// same factorisation. Returns the chart, located, and its arclength uncertainty
    /// $|u_\mu - \mu| / |t_\mu|$.
    pub(super) fn locate_level(
        &mut self,
        a: &Chart,
        (lo, s_lo): (&Chart, f64),
        (hi, s_hi): (&Chart, f64),
        slot: usize,
    ) -> Option<(Chart, bool, f64)> {
        let level = match self.slots[slot] {
            Slot::Bound {
                source: Source::Continued,
                level,
                ..
            }
            | Slot::Event {
                source: Source::Continued,
                terminal: false,
                level,
                ..
            } => level,
            _ => return None,
        };
        let pi = self.p.parameter_index();
        let (p_lo, p_hi) = (lo.u[pi], hi.u[pi]);
        let x = (level - p_lo) / (p_hi - p_lo);
        if !(0.0..=1.0).contains(&x) {
            return None;
        }
        let pred = self.bracket_predictor(a, (lo, s_lo), (hi, s_hi), s_lo + x * (s_hi - s_lo));
        let mut row = vec![0.0; self.n];
        row[pi] = 1.0;
        // The hyperplane u_mu - 0 = level (its reference point the origin).
        let origin = vec![0.0; self.n];
        let (u, iterations) = self.correct(pred, &row, &origin, level, true).ok()?;
        let (mut t, det) = self.tangent_from_factorization().ok()?;
        let (s, slope) = (self.wdot(&a.t, &u) - self.wdot(&a.t, &a.u), t[pi]);
        let accuracy = (u[pi] - level).abs() / slope.abs();
        if !(s_lo..=s_hi).contains(&s) || !(accuracy <= self.settings.locate_tol) {
            return None;
        }
        if self.wdot(&t, &a.t) < 0.0 {
            t.iter_mut().for_each(|v| *v = -*v);
        }
        let det = self.det_with_row(det, &self.row_of(&a.t));
        self.stats.analyses += 1;
        let info = self.p.analyse_factorised(&u, &self.pattern).ok()?;
        let chart = Chart {
            u,
            t,
            info,
            iterations,
            det,
        };
        Some((chart, true, accuracy))
    }
}
