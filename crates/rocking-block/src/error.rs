//! Errors of the rocking-block crate and command line.

use std::path::PathBuf;

/// Everything that can go wrong in `rocking-block`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An error of the numerical core (bad input, integration failure, ...).
    #[error(transparent)]
    Core(#[from] hycont_core::Error),
    /// Continuation failed before a branch could start.
    #[error("continuation: {0}")]
    Continuation(String),
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

impl Error {
    /// Whether the error is the user's input (exit code 2) rather than a failure (exit code 1).
    #[must_use]
    pub fn is_usage(&self) -> bool {
        matches!(
            self,
            Error::InvalidArgument { .. }
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
