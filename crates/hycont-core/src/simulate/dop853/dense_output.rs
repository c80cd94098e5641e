//! The continuous extension (dense output) of DOP853's accepted steps: Hairer's 7th-order
//! interpolant, built from three extra evaluations per step when asked for.

#[allow(clippy::wildcard_imports)]
use super::super::tableau::*;
use super::{Dop853, NonFiniteEvaluation, stage};

impl Dop853 {
    /// Builds the 7th-order continuous extension of the accepted, pending step (three extra
    /// evaluations; a no-op if already built).
    ///
    /// # Errors
    /// If the right-hand side returns a non-finite value.
    pub fn prepare_dense<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
    ) -> Result<(), NonFiniteEvaluation> {
        if self.dense_ready {
            return Ok(());
        }
        let (t, h) = (self.t, self.h);
        let st = &mut self.stats;
        let (y, f) = (&self.y, &self.f);
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A141, f),
                (A147, &self.k7),
                (A148, &self.k8),
                (A149, &self.k9),
                (A1410, &self.k10),
                (A1411, &self.k11),
                (A1412, &self.k12),
                (A1413, &self.f_new),
            ],
        );
        Self::eval(rhs, st, t + C14 * h, &self.y_tmp, &mut self.k14)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A151, f),
                (A156, &self.k6),
                (A157, &self.k7),
                (A158, &self.k8),
                (A1511, &self.k11),
                (A1512, &self.k12),
                (A1513, &self.f_new),
                (A1514, &self.k14),
            ],
        );
        Self::eval(rhs, st, t + C15 * h, &self.y_tmp, &mut self.k15)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A161, f),
                (A166, &self.k6),
                (A167, &self.k7),
                (A168, &self.k8),
                (A169, &self.k9),
                (A1613, &self.f_new),
                (A1614, &self.k14),
                (A1615, &self.k15),
            ],
        );
        Self::eval(rhs, st, t + C16 * h, &self.y_tmp, &mut self.k16)?;
        for i in 0..self.n {
            let ydiff = self.y_new[i] - y[i];
            let bspl = h * f[i] - ydiff;
            self.cont[0][i] = y[i];
            self.cont[1][i] = ydiff;
            self.cont[2][i] = bspl;
            self.cont[3][i] = ydiff - h * self.f_new[i] - bspl;
            let stages = [
                f[i],
                self.k6[i],
                self.k7[i],
                self.k8[i],
                self.k9[i],
                self.k10[i],
                self.k11[i],
                self.k12[i],
                self.f_new[i],
                self.k14[i],
                self.k15[i],
                self.k16[i],
            ];
            for (row, d) in D.iter().enumerate() {
                let mut acc = 0.0;
                for (dk, sk) in d.iter().zip(stages.iter()) {
                    acc += dk * sk;
                }
                self.cont[4 + row][i] = h * acc;
            }
        }
        self.stats.dense_outputs += 1;
        self.dense_ready = true;
        Ok(())
    }

    /// Whether the dense output of the pending step is built.
    #[must_use]
    pub fn dense_ready(&self) -> bool {
        self.dense_ready
    }

    /// Component `i` of the continuous extension at time `t` (within the pending step).
    ///
    /// Requires [`Dop853::prepare_dense`]; before that it returns the linear interpolant.
    #[must_use]
    pub fn dense_component(&self, i: usize, t: f64) -> f64 {
        let s = (t - self.t) / self.h;
        if !self.dense_ready {
            return self.y[i] + s * (self.y_new[i] - self.y[i]);
        }
        let s1 = 1.0 - s;
        let c = &self.cont;
        c[0][i]
            + s * (c[1][i]
                + s1 * (c[2][i]
                    + s * (c[3][i]
                        + s1 * (c[4][i] + s * (c[5][i] + s1 * (c[6][i] + s * c[7][i]))))))
    }

    /// The time derivative of component `i` of the continuous extension at time `t` (within the
    /// pending step): the nested form of [`Dop853::dense_component`] differentiated in
    /// $s = (t - t_n)/h$, divided by $h$.
    ///
    /// Requires [`Dop853::prepare_dense`]; before that it returns the linear interpolant's slope.
    #[must_use]
    pub fn dense_derivative_component(&self, i: usize, t: f64) -> f64 {
        let h = self.h;
        if !self.dense_ready {
            return (self.y_new[i] - self.y[i]) / h;
        }
        let s = (t - self.t) / h;
        let s1 = 1.0 - s;
        let c = &self.cont;
        // Inside out: v = c6 + s c7, then alternately c_k + s1 v and c_k + s v, carrying dv/ds
        // (ds1/ds = -1).
        let (mut v, mut dv) = (c[6][i] + s * c[7][i], c[7][i]);
        for (k, by_s) in [
            (5, false),
            (4, true),
            (3, false),
            (2, true),
            (1, false),
            (0, true),
        ] {
            if by_s {
                (v, dv) = (c[k][i] + s * v, v + s * dv);
            } else {
                (v, dv) = (c[k][i] + s1 * v, s1 * dv - v);
            }
        }
        dv / h
    }

    /// The first `out.len()` components of the continuous extension at time `t`.
    pub fn dense(&self, t: f64, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.dense_component(i, t);
        }
    }
}
