//! Deterministic per-trial random numbers: trial `i` of a study with seed `s` draws from a
//! generator seeded by a hash of `(s, i)`, so results do not depend on how trials are split
//! across threads or shards.

/// SplitMix64: a small, fast, statistically sound generator (Steele, Lea and Flood, 2014), here
/// used to derive independent streams per trial.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator with the given state.
    #[must_use]
    pub fn new(state: u64) -> Self {
        Self(state)
    }

    /// The generator of trial `index` of a study with `seed`.
    #[must_use]
    pub fn for_trial(seed: u64, index: u64) -> Self {
        let mut g = Self(seed ^ 0x9E37_79B9_7F4A_7C15);
        let a = g.next_u64();
        Self(a ^ index.wrapping_mul(0xBF58_476D_1CE4_E5B9).rotate_left(31))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in $[0, 1)$ (53 random bits).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform number in $[lo, hi)$.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}
