//! The DOP853 stepper: Dormand-Prince 8(5,3) with Hairer's error estimator, step-size controller,
//! initial-step heuristic and 7th-order continuous extension (dense output).
//!
//! The stepper owns every buffer it needs; after [`Dop853::new`] no step allocates. It is driven
//! by [`crate::Simulator`] for hybrid systems, and usable on its own for plain ODEs through
//! [`Dop853::integrate`] and [`Dop853::integrate_fixed`].

mod dense_output;
mod step_size;

#[allow(clippy::wildcard_imports)]
use super::tableau::*;

/// Where a right-hand side first returned a non-finite value.
#[derive(Debug, Clone, PartialEq)]
pub struct NonFiniteEvaluation {
    /// Time of the evaluation.
    pub t: f64,
    /// State at which the right-hand side was evaluated.
    pub state: Vec<f64>,
    /// First non-finite component of the result.
    pub index: usize,
    /// Its value.
    pub value: f64,
}

/// Work counters of a [`Dop853`] stepper.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct StepperStats {
    /// Right-hand side evaluations.
    pub rhs_evaluations: u64,
    /// Accepted steps.
    pub accepted_steps: u64,
    /// Rejected step attempts.
    pub rejected_steps: u64,
    /// Steps for which the dense output was built (3 extra evaluations each).
    pub dense_outputs: u64,
}

/// Combination `out = y + h * sum(c_k v_k)` over a fixed number of stages.
#[inline(always)]
fn stage<const K: usize>(out: &mut [f64], y: &[f64], h: f64, terms: [(f64, &[f64]); K]) {
    let n = out.len();
    let y = &y[..n];
    for i in 0..n {
        let mut acc = 0.0;
        for (c, v) in &terms {
            acc += c * v[i];
        }
        out[i] = y[i] + h * acc;
    }
}

/// Combination `out = sum(c_k v_k)`.
#[inline(always)]
fn combine<const K: usize>(out: &mut [f64], terms: [(f64, &[f64]); K]) {
    let n = out.len();
    for i in 0..n {
        let mut acc = 0.0;
        for (c, v) in &terms {
            acc += c * v[i];
        }
        out[i] = acc;
    }
}

/// An explicit Runge-Kutta stepper of order 8 with embedded error estimators of orders 5 and 3
/// and a continuous extension of order 7.
///
/// The error of a step of size $h$ is Hairer's
/// $\mathrm{err} = |h|\, E_5 / \sqrt{n (E_5 + 0.01\, E_3)}$ with $E_5$, $E_3$ the sums of squares
/// of the two embedded estimates (orders 5 and 3) weighted by
/// $a_{tol} + r_{tol} \max(|y_0|, |y_1|)$.
/// A step is accepted when $\mathrm{err} \le 1$; the new step is $h \cdot \min(6, \max(1/3,
/// 0.9\, \mathrm{err}^{-(1/8 - 0.2\beta)}\, \mathrm{err}_{old}^{\beta}))$ (no growth right after a
/// rejection), with the PI parameter $\beta$ of [`Dop853::set_controller_beta`].
///
/// ```
/// use hycont_core::Dop853;
/// // y' = -y, y(0) = 1: y(1) = exp(-1).
/// let mut stepper = Dop853::new(1);
/// let y = stepper
///     .integrate(&mut |_t, y: &[f64], dy: &mut [f64]| dy[0] = -y[0], 0.0, &[1.0], 1.0, 1e-12, 1e-12)
///     .unwrap();
/// assert!((y[0] - (-1.0f64).exp()).abs() < 1e-11);
/// ```
#[derive(Debug, Clone)]
pub struct Dop853 {
    n: usize,
    n_err: usize,
    rtol: f64,
    atol: f64,
    t: f64,
    y: Vec<f64>,
    f: Vec<f64>,
    h: f64,
    y_new: Vec<f64>,
    f_new: Vec<f64>,
    y_tmp: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    k5: Vec<f64>,
    k6: Vec<f64>,
    k7: Vec<f64>,
    k8: Vec<f64>,
    k9: Vec<f64>,
    k10: Vec<f64>,
    k11: Vec<f64>,
    k12: Vec<f64>,
    k14: Vec<f64>,
    k15: Vec<f64>,
    k16: Vec<f64>,
    err5: Vec<f64>,
    err3: Vec<f64>,
    cont: [Vec<f64>; 8],
    dense_ready: bool,
    last_rejected: bool,
    /// $\ln \max(\mathrm{err}_{old}, 10^{-4})$ of the last accepted step (PI control only).
    ln_err_old: f64,
    controller_beta: f64,
    stats: StepperStats,
}

impl Dop853 {
    /// A stepper for systems of dimension `n`, all components under error control, with
    /// tolerances `rtol = 1e-10`, `atol = 1e-12`.
    #[must_use]
    pub fn new(n: usize) -> Self {
        let v = || vec![0.0; n];
        Self {
            n,
            n_err: n,
            rtol: 1e-10,
            atol: 1e-12,
            t: 0.0,
            y: v(),
            f: v(),
            h: 0.0,
            y_new: v(),
            f_new: v(),
            y_tmp: v(),
            k2: v(),
            k3: v(),
            k4: v(),
            k5: v(),
            k6: v(),
            k7: v(),
            k8: v(),
            k9: v(),
            k10: v(),
            k11: v(),
            k12: v(),
            k14: v(),
            k15: v(),
            k16: v(),
            err5: v(),
            err3: v(),
            cont: std::array::from_fn(|_| v()),
            dense_ready: false,
            last_rejected: false,
            ln_err_old: step_size::LN_ERR_OLD_MIN,
            controller_beta: 0.0,
            stats: StepperStats::default(),
        }
    }

    /// Dimension of the state.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Sets the tolerances; only the first `error_components` components enter the error norm
    /// (the rest, e.g. sensitivities, are integrated along without controlling the step).
    pub fn set_tolerances(&mut self, rtol: f64, atol: f64, error_components: usize) {
        self.rtol = rtol;
        self.atol = atol;
        self.n_err = error_components.clamp(1, self.n);
    }

    /// Sets the PI step-size controller's $\beta$ (Hairer's `WORK(4)`, `0` = pure I-control, the
    /// stepper's default): $h_{new} = h \cdot 0.9\, \mathrm{err}^{-(1/8 - 0.2\beta)}\,
    /// \mathrm{err}_{old}^{\beta}$. A new $\beta$ starts the controller's memory over (as
    /// [`Dop853::start`] does), with $\mathrm{err}_{old} = 10^{-4}$.
    pub fn set_controller_beta(&mut self, beta: f64) {
        if beta != self.controller_beta {
            self.controller_beta = beta;
            self.ln_err_old = step_size::LN_ERR_OLD_MIN;
        }
    }

    /// Work counters since construction or the last [`Dop853::reset_stats`].
    #[must_use]
    pub fn stats(&self) -> StepperStats {
        self.stats
    }

    /// Continues the work counters of another stepper (of the same run, in a mode of another
    /// dimension).
    pub(crate) fn carry_stats(&mut self, stats: StepperStats) {
        self.stats = stats;
    }

    /// Zeroes the work counters.
    pub fn reset_stats(&mut self) {
        self.stats = StepperStats::default();
    }

    /// Current time.
    #[must_use]
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Current state.
    #[must_use]
    pub fn state(&self) -> &[f64] {
        &self.y
    }

    /// Derivative at the current state.
    #[must_use]
    pub fn derivative(&self) -> &[f64] {
        &self.f
    }

    /// State at the end of the pending (attempted) step.
    #[must_use]
    pub fn new_state(&self) -> &[f64] {
        &self.y_new
    }

    /// Derivative at the end of the accepted, pending step (valid after [`Dop853::accept`]).
    #[must_use]
    pub fn new_derivative(&self) -> &[f64] {
        &self.f_new
    }

    /// Size of the pending (attempted) step.
    #[must_use]
    pub fn step_size(&self) -> f64 {
        self.h
    }

    fn eval<F: FnMut(f64, &[f64], &mut [f64])>(
        rhs: &mut F,
        stats: &mut StepperStats,
        t: f64,
        y: &[f64],
        out: &mut [f64],
    ) -> Result<(), NonFiniteEvaluation> {
        rhs(t, y, out);
        stats.rhs_evaluations += 1;
        match out.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(index) => Err(NonFiniteEvaluation {
                t,
                state: y.to_vec(),
                index,
                value: out[index],
            }),
        }
    }

    /// Starts (or restarts, after a jump) at `(t, y)`: evaluates the derivative there.
    ///
    /// # Errors
    /// If the right-hand side is not finite at `(t, y)`.
    pub fn start<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
        t: f64,
        y: &[f64],
    ) -> Result<(), NonFiniteEvaluation> {
        self.t = t;
        self.y.copy_from_slice(y);
        self.dense_ready = false;
        self.last_rejected = false;
        self.ln_err_old = step_size::LN_ERR_OLD_MIN;
        Self::eval(rhs, &mut self.stats, t, &self.y, &mut self.f)
    }

    /// Attempts a step of size `h` from the current point; returns the scaled error estimate
    /// (accept when `<= 1`). The step stays pending until [`Dop853::commit`].
    ///
    /// One function by design: its length is the method's twelve stages and two error
    /// estimates written out in the tableau's order (Hairer's `dp86co`), which reads against
    /// the published coefficients line by line.
    ///
    /// # Errors
    /// If the right-hand side returns a non-finite value at a stage.
    pub fn attempt<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
        h: f64,
    ) -> Result<f64, NonFiniteEvaluation> {
        self.h = h;
        self.dense_ready = false;
        let t = self.t;
        let st = &mut self.stats;
        let (y, f) = (&self.y, &self.f);
        stage(&mut self.y_tmp, y, h, [(A21, f)]);
        Self::eval(rhs, st, t + C2 * h, &self.y_tmp, &mut self.k2)?;
        stage(&mut self.y_tmp, y, h, [(A31, f), (A32, &self.k2)]);
        Self::eval(rhs, st, t + C3 * h, &self.y_tmp, &mut self.k3)?;
        stage(&mut self.y_tmp, y, h, [(A41, f), (A43, &self.k3)]);
        Self::eval(rhs, st, t + C4 * h, &self.y_tmp, &mut self.k4)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [(A51, f), (A53, &self.k3), (A54, &self.k4)],
        );
        Self::eval(rhs, st, t + C5 * h, &self.y_tmp, &mut self.k5)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [(A61, f), (A64, &self.k4), (A65, &self.k5)],
        );
        Self::eval(rhs, st, t + C6 * h, &self.y_tmp, &mut self.k6)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [(A71, f), (A74, &self.k4), (A75, &self.k5), (A76, &self.k6)],
        );
        Self::eval(rhs, st, t + C7 * h, &self.y_tmp, &mut self.k7)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A81, f),
                (A84, &self.k4),
                (A85, &self.k5),
                (A86, &self.k6),
                (A87, &self.k7),
            ],
        );
        Self::eval(rhs, st, t + C8 * h, &self.y_tmp, &mut self.k8)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A91, f),
                (A94, &self.k4),
                (A95, &self.k5),
                (A96, &self.k6),
                (A97, &self.k7),
                (A98, &self.k8),
            ],
        );
        Self::eval(rhs, st, t + C9 * h, &self.y_tmp, &mut self.k9)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A101, f),
                (A104, &self.k4),
                (A105, &self.k5),
                (A106, &self.k6),
                (A107, &self.k7),
                (A108, &self.k8),
                (A109, &self.k9),
            ],
        );
        Self::eval(rhs, st, t + C10 * h, &self.y_tmp, &mut self.k10)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A111, f),
                (A114, &self.k4),
                (A115, &self.k5),
                (A116, &self.k6),
                (A117, &self.k7),
                (A118, &self.k8),
                (A119, &self.k9),
                (A1110, &self.k10),
            ],
        );
        Self::eval(rhs, st, t + C11 * h, &self.y_tmp, &mut self.k11)?;
        stage(
            &mut self.y_tmp,
            y,
            h,
            [
                (A121, f),
                (A124, &self.k4),
                (A125, &self.k5),
                (A126, &self.k6),
                (A127, &self.k7),
                (A128, &self.k8),
                (A129, &self.k9),
                (A1210, &self.k10),
                (A1211, &self.k11),
            ],
        );
        Self::eval(rhs, st, t + h, &self.y_tmp, &mut self.k12)?;
        // 8th-order increment (stored in k4, which is no longer needed).
        combine(
            &mut self.k4,
            [
                (B1, f),
                (B6, &self.k6),
                (B7, &self.k7),
                (B8, &self.k8),
                (B9, &self.k9),
                (B10, &self.k10),
                (B11, &self.k11),
                (B12, &self.k12),
            ],
        );
        stage(&mut self.y_new, y, h, [(1.0, &self.k4)]);
        combine(
            &mut self.err3,
            [
                (1.0, &self.k4),
                (-BHH1, f),
                (-BHH2, &self.k9),
                (-BHH3, &self.k12),
            ],
        );
        combine(
            &mut self.err5,
            [
                (ER1, f),
                (ER6, &self.k6),
                (ER7, &self.k7),
                (ER8, &self.k8),
                (ER9, &self.k9),
                (ER10, &self.k10),
                (ER11, &self.k11),
                (ER12, &self.k12),
            ],
        );
        let m = self.n_err;
        let (mut e5, mut e3) = (0.0, 0.0);
        for i in 0..m {
            let sk = self.atol + self.rtol * self.y[i].abs().max(self.y_new[i].abs());
            e3 += (self.err3[i] / sk).powi(2);
            e5 += (self.err5[i] / sk).powi(2);
        }
        let mut deno = e5 + 0.01 * e3;
        if deno <= 0.0 {
            deno = 1.0;
        }
        let err = h.abs() * e5 * (1.0 / (m as f64 * deno)).sqrt();
        if !err.is_finite() {
            // Non-finite values that escaped the per-evaluation checks (e.g. overflow in the sum).
            let index = self.y_new.iter().position(|v| !v.is_finite()).unwrap_or(0);
            return Err(NonFiniteEvaluation {
                t: t + h,
                state: self.y_new.clone(),
                index,
                value: self.y_new[index],
            });
        }
        Ok(err)
    }

    /// Accepts the pending step: evaluates the derivative at its end (the first stage of the next
    /// step). The step is still pending: the dense output can be built and events located before
    /// [`Dop853::commit`].
    ///
    /// # Errors
    /// If the right-hand side is not finite at the new point.
    pub fn accept<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
    ) -> Result<(), NonFiniteEvaluation> {
        self.stats.accepted_steps += 1;
        Self::eval(
            rhs,
            &mut self.stats,
            self.t + self.h,
            &self.y_new,
            &mut self.f_new,
        )
    }

    /// Makes the pending step's end the current point.
    pub fn commit(&mut self) {
        self.t += self.h;
        std::mem::swap(&mut self.y, &mut self.y_new);
        std::mem::swap(&mut self.f, &mut self.f_new);
        self.dense_ready = false;
    }

    /// Integrates the plain ODE $y' = \mathrm{rhs}(t, y)$ from `t0` to `t1` with adaptive steps.
    ///
    /// # Errors
    /// If the right-hand side returns a non-finite value, or the step size underflows.
    pub fn integrate<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
        t0: f64,
        y0: &[f64],
        t1: f64,
        rtol: f64,
        atol: f64,
    ) -> Result<Vec<f64>, crate::Error> {
        crate::error::check_len("initial state", y0, self.n)?;
        self.set_tolerances(rtol, atol, self.n);
        let nf = |e: NonFiniteEvaluation| crate::Error::NonFiniteVectorField {
            t: e.t,
            mode: crate::Mode(0),
            index: e.index,
            value: e.value,
            state: e.state,
        };
        self.start(rhs, t0, y0).map_err(nf)?;
        if t1 == t0 {
            return Ok(y0.to_vec());
        }
        let dir = (t1 - t0).signum();
        let mut h = self.initial_step(rhs, dir, (t1 - t0).abs()).map_err(nf)?;
        loop {
            let remaining = t1 - self.t;
            let last = (h * 1.01).abs() >= remaining.abs();
            if last {
                h = remaining;
            }
            if h.abs() <= 4.0 * f64::EPSILON * self.t.abs().max(1.0) {
                return Err(crate::Error::StepSizeUnderflow {
                    t: self.t,
                    h,
                    mode: crate::Mode(0),
                });
            }
            let err = self.attempt(rhs, h).map_err(nf)?;
            let h_next = self.next_step_size(h, err);
            if err <= 1.0 {
                self.accept(rhs).map_err(nf)?;
                self.commit();
                if last {
                    self.t = t1;
                    return Ok(self.y.clone());
                }
            } else {
                self.reject();
            }
            h = h_next;
        }
    }

    /// Integrates with `steps` equal steps and no error control (for convergence studies).
    ///
    /// # Errors
    /// If the right-hand side returns a non-finite value.
    pub fn integrate_fixed<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
        t0: f64,
        y0: &[f64],
        t1: f64,
        steps: usize,
    ) -> Result<Vec<f64>, NonFiniteEvaluation> {
        self.start(rhs, t0, y0)?;
        let h = (t1 - t0) / steps.max(1) as f64;
        for k in 0..steps.max(1) {
            self.attempt(rhs, h)?;
            self.accept(rhs)?;
            self.commit();
            self.t = t0 + (k + 1) as f64 * h;
        }
        Ok(self.y.clone())
    }
}
