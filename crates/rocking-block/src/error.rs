//! Errors of the rocking-block crate and command line.

use std::path::PathBuf;

/// Everything that can go wrong in `rocking-block`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An error of the numerical core (bad input, integration failure, ...).
    #[error(transparent)]
    Core(#[from] hycont_core::Error),
    /// Continuation failed before a branch could start, or was asked for something a branch
    /// does not have.
    #[error("continuation: {0}")]
    Continuation(hycont_continuation::Error),
    /// A simulation reached its step limit before its end time.
    #[error(
        "the simulation reached its step limit of {steps} steps at t = {t} (of {t_end}); simulate fewer periods"
    )]
    StepLimit {
        /// Where it stopped.
        t: f64,
        /// Where it should have ended.
        t_end: f64,
        /// The limit.
        steps: u64,
    },
    /// No orbit of the kind asked for was found.
    #[error("{0}")]
    NoOrbit(String),
    /// A command-line value is invalid.
    #[error("invalid argument {name} = {value}: {reason}")]
    InvalidArgument {
        /// Name of the argument.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is allowed.
        reason: &'static str,
    },
    /// An input file is not what the command needs (wrong shape, inconsistent counts, ...).
    #[error("invalid file {path}: {reason}")]
    InvalidFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A run was interrupted (or its inputs were incomplete); what it had was kept.
    #[error("interrupted: {detail}")]
    Interrupted {
        /// What was kept and how to go on.
        detail: String,
    },
    /// A rank of an MPI job failed its share of a sampling run (reported by rank 0).
    #[error("MPI rank {rank}: {reason}")]
    Rank {
        /// The rank.
        rank: u64,
        /// What failed.
        reason: String,
    },
    /// Inputs that hold only part of a result (e.g. shards missing from a merge); the part was
    /// kept.
    #[error("incomplete: {detail}")]
    Incomplete {
        /// What was kept and how to go on.
        detail: String,
    },
    /// Reading an input file failed (missing, unreadable).
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Writing a file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Drawing a figure failed.
    #[error("cannot draw {path}: {message}")]
    Plot {
        /// The file.
        path: PathBuf,
        /// What the plotting backend said.
        message: String,
    },
}

impl From<hycont_continuation::Error> for Error {
    /// Errors of the numerical core stay core errors (their classification as usage errors
    /// does not depend on where they surfaced).
    fn from(e: hycont_continuation::Error) -> Self {
        match e {
            hycont_continuation::Error::Core(c) => Error::Core(c),
            other => Error::Continuation(other),
        }
    }
}

impl From<hycont_sample::Error> for Error {
    /// The sampling runner's file and rank errors as the command line's own; a core error
    /// stays one; other sampling errors are an invalid study.
    fn from(e: hycont_sample::Error) -> Self {
        use hycont_sample::Error as S;
        match e {
            S::Core(c) => Error::Core(c),
            S::Io { path, reason } => Error::Io {
                path,
                source: std::io::Error::other(reason),
            },
            S::Read { path, reason } => Error::Read {
                path,
                source: std::io::Error::other(reason),
            },
            S::InvalidFile { path, reason } => Error::InvalidFile { path, reason },
            S::Rank { rank, reason } => Error::Rank { rank, reason },
            other => crate::figures::sampling::sample_err(other),
        }
    }
}

impl Error {
    /// Whether the error is the user's input (exit code 2: bad arguments, input files that
    /// cannot be read or are invalid) rather than a failure (exit code 1).
    #[must_use]
    pub fn is_usage(&self) -> bool {
        use hycont_continuation::Error as C;
        matches!(
            self,
            Error::InvalidArgument { .. }
                | Error::InvalidFile { .. }
                | Error::Read { .. }
                | Error::Continuation(
                    C::NoSuchLabel { .. }
                        | C::NotASpecialPoint { .. }
                        | C::ForeignHandle { .. }
                        | C::InadmissibleStart { .. }
                        | C::StartOutsideBounds { .. }
                        | C::InvalidSetting { .. }
                        | C::InvalidLabel { .. }
                        | C::NoSuchQuantity { .. }
                        | C::WrongSpecialPoint { .. }
                )
                | Error::Core(
                    hycont_core::Error::ParameterOutOfRange { .. }
                        | hycont_core::Error::NonFinite { .. }
                        | hycont_core::Error::InvalidSetting { .. }
                        | hycont_core::Error::InvalidTimeSpan { .. }
                        | hycont_core::Error::DimensionMismatch { .. }
                )
        )
    }
}

/// Shorthand for `Result<T, rocking_block::Error>`.
pub type Result<T> = std::result::Result<T, Error>;
