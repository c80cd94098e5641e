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
    /// A file cannot be written (or its directory created).
    #[error("cannot write {path}: {reason}")]
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// What the system said.
        reason: String,
    },
    /// A file cannot be read (missing, unreadable).
    #[error("cannot read {path}: {reason}")]
    Read {
        /// The file.
        path: std::path::PathBuf,
        /// What the system said.
        reason: String,
    },
    /// A file is not what it should be (not a count file of the kind, inconsistent counts,
    /// another study's shard).
    #[error("invalid file {path}: {reason}")]
    InvalidFile {
        /// The file.
        path: std::path::PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A rank of an MPI job failed its share of a run (reported by rank 0).
    #[error("MPI rank {rank}: {reason}")]
    Rank {
        /// The rank.
        rank: u64,
        /// What failed.
        reason: String,
    },
    /// A study's variable or axis given as text does not parse
    /// ([`crate::basin::Distribution`]'s `FromStr`, [`crate::basin::Axis::parse`]).
    #[error("{spec:?}: {reason}")]
    InvalidSpec {
        /// The text.
        spec: String,
        /// What is wrong with it.
        reason: &'static str,
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
