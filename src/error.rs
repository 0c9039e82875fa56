//! The library's one error type.
//!
//! Every variant carries the context a user needs to fix the input: the file,
//! the line or field, the offending value and what would have been accepted.
//! Overturning is an *outcome*, never an error.

use std::path::{Path, PathBuf};

/// Errors raised by rockfrag's library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// A file was read but its content is malformed.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number of the fault (0 if the fault is not tied to a line).
        line: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A parameter is out of its accepted range.
    #[error("invalid {field} = {value}: expected {expected}")]
    InvalidParameter {
        /// The parameter's name (a CLI flag or spec field path).
        field: String,
        /// The value given, as text.
        value: String,
        /// The accepted range or values.
        expected: String,
    },
    /// A study spec holds a bad value: the file, the line where the field was
    /// found (0 if it was left at its default), the field path
    /// (e.g. `grid.aspect[2]`), the value and the accepted range.
    #[error("{path}:{line}: invalid {field} = {value}: expected {expected}")]
    Spec {
        /// The spec file.
        path: PathBuf,
        /// 1-based line of the field, 0 if the field is not written in the file.
        line: usize,
        /// Path of the field in the spec, e.g. `grid.friction[1].mu_k`.
        field: String,
        /// The value given, as text.
        value: String,
        /// The accepted range or values.
        expected: String,
    },
    /// An output folder holds a run that cannot be resumed or merged as asked
    /// (another study, another shard, an incomplete shard).
    #[error("{path}: {message}")]
    Conflict {
        /// The folder or file concerned.
        path: PathBuf,
        /// What does not match and what to do.
        message: String,
    },
    /// A ground-motion record is unusable (empty, non-uniform, non-finite).
    #[error("invalid record {name}: {message}")]
    InvalidRecord {
        /// The record's name (file name or ensemble index).
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The solver could not continue (step size underflow, event storm).
    #[error("solver failed at t = {time} s: {message}")]
    Solver {
        /// Time of the failure (s).
        time: f64,
        /// What went wrong.
        message: String,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(field: &str, value: impl std::fmt::Display, expected: &str) -> Self {
        Error::InvalidParameter {
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }

    /// Wraps an I/O error on `path`: `.map_err(Error::io(path))`.
    pub fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
        move |source| Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Result alias used throughout the library.
pub type Result<T> = std::result::Result<T, Error>;
