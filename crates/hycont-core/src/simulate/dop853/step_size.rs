//! The DOP853 stepper's step-size control: Hairer's initial-step heuristic and the controller
//! of the steps after an attempt.

use super::{Dop853, NonFiniteEvaluation, stage};

/// $\ln 10^{-4}$ (of the `f64` nearest $10^{-4}$): the PI controller's memory
/// $\mathrm{err}_{old}$ is bounded below by $10^{-4}$ (Hairer's `FACOLD`), and starts there.
pub(super) const LN_ERR_OLD_MIN: f64 = -9.210_340_371_976_182;

impl Dop853 {
    /// Hairer's initial step-size heuristic (one extra evaluation), for integrating towards
    /// `direction` (+1 or -1), at most `h_max` in magnitude.
    ///
    /// # Errors
    /// If the right-hand side is not finite at the trial point.
    pub fn initial_step<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        rhs: &mut F,
        direction: f64,
        h_max: f64,
    ) -> Result<f64, NonFiniteEvaluation> {
        let m = self.n_err;
        let (mut dnf, mut dny) = (0.0, 0.0);
        for i in 0..m {
            let sk = self.atol + self.rtol * self.y[i].abs();
            dnf += (self.f[i] / sk).powi(2);
            dny += (self.y[i] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
            1e-6
        } else {
            (dny / dnf).sqrt() * 0.01
        };
        h = h.min(h_max) * direction;
        stage(&mut self.y_tmp, &self.y, h, [(1.0, &self.f)]);
        Self::eval(rhs, &mut self.stats, self.t + h, &self.y_tmp, &mut self.k2)?;
        let mut der2 = 0.0;
        for i in 0..m {
            let sk = self.atol + self.rtol * self.y[i].abs();
            der2 += ((self.k2[i] - self.f[i]) / sk).powi(2);
        }
        let der2 = der2.sqrt() / h.abs();
        let der12 = der2.max(dnf.sqrt());
        let h1 = if der12 <= 1e-15 {
            (h.abs() * 1e-3).max(1e-6)
        } else {
            (0.01 / der12).powf(1.0 / 8.0)
        };
        Ok((100.0 * h.abs()).min(h1).min(h_max) * direction)
    }

    /// The step size to try next after an attempt of size `h` with scaled error `err`.
    #[must_use]
    pub fn next_step_size(&mut self, h: f64, err: f64) -> f64 {
        const SAFE: f64 = 0.9;
        const MIN_FACTOR: f64 = 0.333;
        const MAX_FACTOR: f64 = 6.0;
        let beta = self.controller_beta;
        if err <= 1.0 {
            let mut factor = if err == 0.0 {
                self.ln_err_old = LN_ERR_OLD_MIN;
                MAX_FACTOR
            } else if beta == 0.0 {
                (SAFE * inverse_eighth_root(err)).clamp(MIN_FACTOR, MAX_FACTOR)
            } else {
                // err^-(1/8 - 0.2 beta) err_old^beta with one logarithm and one exponential
                // (two `powf` cost about twice as much).
                let ln_err = err.ln();
                let ln_factor = beta * self.ln_err_old - (1.0 / 8.0 - 0.2 * beta) * ln_err;
                self.ln_err_old = ln_err.max(LN_ERR_OLD_MIN);
                (SAFE * ln_factor.exp()).clamp(MIN_FACTOR, MAX_FACTOR)
            };
            if self.last_rejected {
                factor = factor.min(1.0);
            }
            self.last_rejected = false;
            h * factor
        } else {
            self.last_rejected = true;
            h * (SAFE * inverse_eighth_root(err)).max(MIN_FACTOR)
        }
    }

    /// Records a rejected attempt in the statistics.
    pub fn reject(&mut self) {
        self.stats.rejected_steps += 1;
    }
}

/// $x^{-1/8}$ by three square roots: the controller's factor when $\beta = 0$ (pure I-control),
/// correctly rounded at each root and several times cheaper than `powf`.
#[inline]
fn inverse_eighth_root(x: f64) -> f64 {
    1.0 / x.sqrt().sqrt().sqrt()
}

#[cfg(test)]
mod tests {
    use super::{LN_ERR_OLD_MIN, inverse_eighth_root};
    use crate::simulate::dop853::Dop853;
    use approx::assert_relative_eq;

    #[test]
    fn the_controllers_memory_starts_at_ln_1e_minus_4() {
        assert_eq!(LN_ERR_OLD_MIN, 1e-4f64.ln());
    }

    /// The PI controller's factor against its definition with `powf` (Hairer's
    /// `fac11 = err^expo1; fac = fac11 / facold^beta`): $0.9\,\mathrm{err}^{-(1/8 -
    /// 0.2\beta)}\,\mathrm{err}_{old}^{\beta}$ clamped to $[0.333, 6]$, over a sequence of
    /// accepted errors (each the next one's $\mathrm{err}_{old}$, bounded below by $10^{-4}$),
    /// a rejection (no growth after it) and both controllers.
    #[test]
    fn the_step_size_factor_is_the_controllers_formula() {
        for beta in [0.0, 0.03, 0.08] {
            let mut st = Dop853::new(1);
            st.set_controller_beta(beta);
            let mut err_old: f64 = 1e-4;
            let mut rejected = false;
            for err in [0.3, 1e-7, 0.9, 2.5, 0.02, 0.0, 0.5, 1e-12, 0.99] {
                let h = st.next_step_size(0.1, err);
                let expected = if err > 1.0 {
                    rejected = true;
                    0.1 * (0.9 * err.powf(-0.125)).max(0.333)
                } else {
                    let mut factor = if err == 0.0 {
                        6.0
                    } else {
                        (0.9 * err.powf(-(0.125 - 0.2 * beta)) * err_old.powf(beta))
                            .clamp(0.333, 6.0)
                    };
                    err_old = err.max(1e-4);
                    if rejected {
                        factor = factor.min(1.0);
                    }
                    rejected = false;
                    0.1 * factor
                };
                assert_relative_eq!(h, expected, max_relative = 1e-14);
            }
        }
    }

    /// $x^{-1/8}$ against `powf` over the errors a controller sees (1e-16 to 1e16), and exact
    /// at powers of 256 ($256^{-1/8} = 1/2$).
    #[test]
    fn the_inverse_eighth_root_is_powf_to_rounding() {
        for k in -64..=64 {
            let x = 10f64.powf(f64::from(k) / 4.0) * 1.37;
            assert_relative_eq!(inverse_eighth_root(x), x.powf(-0.125), max_relative = 4e-16);
        }
        for k in -4..=4 {
            let x = 256f64.powi(k);
            assert_eq!(inverse_eighth_root(x), 2f64.powi(-k));
        }
    }
}
