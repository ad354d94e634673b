//! The small set of failures Taut reports to a designer. Every message names what was wrong and,
//! where it helps, where (file, vertex or face index) and what to do about it.

use std::path::PathBuf;

/// A failure in reading, checking or solving a cage.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written at all.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file was read but its contents are not a valid mesh, cage or curve.
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    /// Input values (indices, coordinates, settings) are out of their allowed range.
    #[error("{0}")]
    Input(String),
    /// The connectivity cannot be handled (non-manifold edge, inconsistent orientation, ...).
    #[error("{0}")]
    Topology(String),
    /// The solver could not produce a converged result.
    #[error("{0}")]
    Solver(String),
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io { path: path.into(), source }
    }

    pub(crate) fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::Format { path: path.into(), message: message.into() }
    }
}

/// Result with Taut's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
