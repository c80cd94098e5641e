//! The error type of `hycont-sample`.

/// What can go wrong in sampling studies.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The study is inconsistent.
    #[error("invalid study: {reason}")]
    InvalidStudy {
        /// What is wrong.
        reason: String,
    },
    /// An error of the numerical core (invalid input to a simulation, integration failure).
    #[error(transparent)]
    Core(#[from] hycont_core::Error),
    /// A trial needed more integration steps than the classifier's budget (e.g. chattering
    /// that the simulator resolves impact by impact at vanishing velocities).
    #[error(
        "the trial needed more than {steps} integration steps in {periods} forcing periods (from t = {t})"
    )]
    StepBudget {
        /// The budget of the simulated piece (`max_steps_per_period` times its periods).
        steps: u64,
        /// Forcing periods of the piece (one in the first chunk, which runs period by period).
        periods: usize,
        /// Where the piece started.
        t: f64,
    },
    /// Count tables cannot be merged.
    #[error("cannot merge counts: {reason}")]
    IncompatibleCounts {
        /// Why.
        reason: String,
    },
}

/// Shorthand for `Result<T, hycont_sample::Error>`.
pub type Result<T> = std::result::Result<T, Error>;
