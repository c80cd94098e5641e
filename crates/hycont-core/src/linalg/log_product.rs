//! Sign and logarithm of a product of many factors (a determinant from its pivots), without
//! overflow or underflow and without a logarithm per factor.

/// Sign and $\ln|\prod_k p_k|$ of a product of factors (pivots), accumulated as a mantissa
/// in $[1, 2)$ and a binary exponent: one multiplication per factor instead of a logarithm,
/// without overflow or underflow.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogProduct {
    sign: f64,
    mantissa: f64,
    exponent: i64,
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
    pub(crate) fn push(&mut self, p: f64) {
        self.sign *= p.signum();
        let mut m = self.mantissa * p.abs();
        if !(m.is_finite() && m > 0.0) {
            self.mantissa = m;
            return;
        }
        if m < f64::MIN_POSITIVE {
            // Subnormal: scale into the normal range first (2^54 is exact).
            m *= 18_014_398_509_481_984.0;
            self.exponent -= 54;
        }
        let bits = m.to_bits();
        let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
        self.exponent += e;
        self.mantissa = f64::from_bits((bits & !(0x7ff << 52)) | (1023 << 52));
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
        (
            self.sign,
            self.mantissa.ln() + self.exponent as f64 * std::f64::consts::LN_2,
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
