//! Sign and logarithm of a product of many factors (a determinant from its pivots), without
//! overflow or underflow and without a logarithm per factor.

/// Sign and $\ln|\prod_k p_k|$ of a product of factors (pivots), accumulated as a scaled
/// product in $[2^{-511}, 2^{512})$ and a binary exponent: one multiplication and a range
/// check per factor instead of a logarithm, without overflow or underflow. The product is
/// renormalised (by exact powers of two) only when it leaves that range, so each factor costs
/// one rounding, as in the plain product.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogProduct {
    sign: f64,
    /// The scaled product (or, once a factor was zero or not finite, 0, inf or NaN).
    mantissa: f64,
    exponent: i64,
}

/// $2^{-511}$ and $2^{512}$: a product of two values in this range is a normal number.
const LOW: f64 = f64::from_bits((1023 - 511) << 52);
const HIGH: f64 = f64::from_bits((1023 + 512) << 52);

/// `x = m 2^e` with `m` in $[1, 2)$, for a finite positive `x` (subnormals included).
fn split(x: f64) -> (f64, i64) {
    let (x, shift) = if x < f64::MIN_POSITIVE {
        (x * 18_014_398_509_481_984.0, -54) // 2^54, exact
    } else {
        (x, 0)
    };
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
    (
        f64::from_bits((bits & !(0x7ff << 52)) | (1023 << 52)),
        e + shift,
    )
}

impl LogProduct {
    pub(crate) fn new() -> Self {
        Self {
            sign: 1.0,
            mantissa: 1.0,
            exponent: 0,
        }
    }

    /// Multiplies by `p` (a zero gives `ln = -inf`, a non-finite factor `inf` or NaN, as the
    /// sum of logarithms would).
    #[inline]
    pub(crate) fn push(&mut self, p: f64) {
        self.sign *= p.signum();
        let m = self.mantissa * p.abs();
        if (LOW..HIGH).contains(&m) {
            self.mantissa = m;
        } else {
            self.push_rescaled(p.abs());
        }
    }

    /// [`LogProduct::push`] of `a = |p|` where the plain product left the range: the product
    /// of the two mantissas in $[1, 2)$, renormalised; or the flag of a zero or non-finite
    /// factor.
    #[cold]
    fn push_rescaled(&mut self, a: f64) {
        let finite = |x: f64| x.is_finite() && x > 0.0;
        if !(finite(self.mantissa) && finite(a)) {
            self.mantissa *= a;
            return;
        }
        let ((mm, em), (ma, ea)) = (split(self.mantissa), split(a));
        let (m, e) = split(mm * ma);
        self.mantissa = m;
        self.exponent += em + ea + e;
    }

    /// The product of `factors`, accumulated in four interleaved partial products that are
    /// merged at the end: four independent chains of multiplications, which the processor
    /// overlaps, instead of one (a determinant's thousands of pivots). The same number of
    /// roundings as [`LogProduct::push`] one by one, in another order.
    pub(crate) fn of(factors: &[f64]) -> Self {
        let mut lanes = [Self::new(); 4];
        let mut chunks = factors.chunks_exact(4);
        for chunk in &mut chunks {
            for (lane, &p) in lanes.iter_mut().zip(chunk) {
                lane.push(p);
            }
        }
        for (lane, &p) in lanes.iter_mut().zip(chunks.remainder()) {
            lane.push(p);
        }
        let [mut all, rest @ ..] = lanes;
        for lane in rest {
            all.sign *= lane.sign;
            all.exponent += lane.exponent;
            all.push(lane.mantissa);
        }
        all
    }

    /// `(sign, ln|product|)`.
    pub(crate) fn finish(self) -> (f64, f64) {
        let (m, e) = if self.mantissa.is_finite() && self.mantissa > 0.0 {
            split(self.mantissa)
        } else {
            (self.mantissa, 0)
        };
        (
            self.sign,
            m.ln() + (self.exponent + e) as f64 * std::f64::consts::LN_2,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::LogProduct;
    use proptest::prelude::*;

    proptest! {
        /// Sign and logarithm of a product agree with the sum of logarithms (to a few units of
        /// roundoff per factor), over magnitudes from subnormal to 1e300 whose product would
        /// overflow or underflow; one by one and in four lanes ([`LogProduct::of`]).
        #[test]
        fn log_product_is_the_sum_of_logarithms(
            factors in proptest::collection::vec((-300.0f64..300.0, any::<bool>()), 1..200),
            subnormal in any::<bool>(),
        ) {
            let mut values: Vec<f64> = factors
                .iter()
                .map(|&(e, neg)| if neg { -(10f64.powf(e)) } else { 10f64.powf(e) })
                .collect();
            if subnormal {
                values.push(1e-310);
            }
            let mut p = LogProduct::new();
            for &v in &values {
                p.push(v);
            }
            let want_sign: f64 = values.iter().map(|v| v.signum()).product();
            let want_log: f64 = values.iter().map(|v| v.abs().ln()).sum();
            let scale: f64 = values.iter().map(|v| v.abs().ln().abs()).sum::<f64>() + 1.0;
            for (sign, log) in [p.finish(), LogProduct::of(&values).finish()] {
                prop_assert_eq!(sign, want_sign);
                prop_assert!((log - want_log).abs() <= 4.0 * f64::EPSILON * scale, "{} vs {}", log, want_log);
            }
        }
    }

    /// The range bounds are the powers of two they stand for.
    #[test]
    fn range_bounds_are_powers_of_two() {
        assert_eq!(super::LOW, 2f64.powi(-511));
        assert_eq!(super::HIGH, 2f64.powi(512));
    }

    /// Products that leave the range either way, many times over, and a factor beside the
    /// largest and smallest magnitudes: the plain sum of logarithms to roundoff.
    #[test]
    fn rescaling_keeps_the_logarithm() {
        let factors = [
            1e300,
            1e300,
            1e-310,
            3.0,
            1e-300,
            1e-300,
            f64::MAX,
            5e-324,
            0.5,
        ];
        let want: f64 = factors.iter().map(|v: &f64| v.ln()).sum();
        for (sign, log) in [
            LogProduct::of(&factors).finish(),
            factors
                .iter()
                .fold(LogProduct::new(), |mut p, &v| {
                    p.push(v);
                    p
                })
                .finish(),
        ] {
            assert_eq!(sign, 1.0);
            assert!(
                (log - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{log} vs {want}"
            );
        }
    }

    #[test]
    fn log_product_of_a_zero_or_non_finite_factor() {
        for (bad, want) in [(0.0, f64::NEG_INFINITY), (f64::INFINITY, f64::INFINITY)] {
            let mut p = LogProduct::new();
            p.push(2.0);
            p.push(bad);
            p.push(3.0);
            assert_eq!(p.finish().1, want);
            // In every lane of `of`, among finite factors.
            for at in 0..6 {
                let mut factors = [2.0, 3.0, 0.5, 7.0, 1.5, 4.0];
                factors[at] = bad;
                assert_eq!(LogProduct::of(&factors).finish().1, want, "{at}");
            }
        }
        let mut p = LogProduct::new();
        p.push(f64::NAN);
        assert!(p.finish().1.is_nan());
    }
}
