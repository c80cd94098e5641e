//! # hycont-sample
//!
//! Sample-based analysis of hybrid systems, generic over the system and the classifier:
//! brute-force stroboscopic bifurcation diagrams ([`sweep::brute_force`]), attractor
//! classification of periodically forced systems by their stroboscopic map
//! ([`classify::classify`]), and basin stability
//! ([`basin::run`]: Monte-Carlo trials, class counts per grid cell with 95 % Wilson intervals,
//! parallel with rayon, reproducible from a seed whatever the number of threads, shardable and
//! interruptible; [`adaptive::run_cells`]: stratified per cell until every class's 95 % interval
//! is as narrow as asked).
//!
//! ```
//! use hycont_sample::basin::{run, Axis, Classifier, Distribution, Progress, Study};
//! /// Classifies x in [0, 1) as "low" (x < 0.25) or "high".
//! struct Threshold;
//! impl Classifier for Threshold {
//!     fn classes(&self) -> Vec<String> { vec!["low".into(), "high".into()] }
//!     fn classify(&self, v: &[f64]) -> Result<usize, String> { Ok(usize::from(v[0] >= 0.25)) }
//! }
//! let study = Study {
//!     names: vec!["x".into()],
//!     variables: vec![Distribution::Uniform { lo: 0.0, hi: 1.0 }],
//!     axes: vec![],
//!     seed: 7,
//! };
//! let counts = run(&study, &Threshold, 0..10_000, &Progress::default()).unwrap();
//! let (p, lo, hi) = counts.fraction(0, 0);
//! // Within 4 standard errors (sqrt(p (1 - p) / n) = 0.0043) of the true 1/4, and the 95 %
//! // interval around the estimate is narrow.
//! assert!((p - 0.25).abs() < 4.0 * 0.0043);
//! assert!(lo < p && p < hi && hi - lo < 0.02);
//! ```
#![deny(missing_docs)]
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod adaptive;
pub mod basin;
pub mod classify;
pub mod error;
pub mod rng;
mod spec;
mod split;
mod strobe_newton;
pub mod study;
pub mod sweep;

pub use error::{Error, Result};
