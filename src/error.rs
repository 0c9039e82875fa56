//! The library's one error type.
//!
//! Every variant carries the context a user needs to fix the input: the file,
//! the line or field, the offending value and what would have been accepted.
//! Overturning is an *outcome*, never an error.
//!
//! Numbers in messages are shown by [`number`] (the shortest text that reads
//! back as the value) or [`fixed`] (a set number of decimals): both switch to
//! an exponent for tiny and huge values, so that `f64::MIN_POSITIVE` or a
//! scale of 1e300 reads as `2.2250738585072014e-308` or `1e300`, not as 300
//! digits. A value given to [`Error::invalid`] is shown through [`Shown`],
//! which applies [`number`] to floats.

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
    #[error("solver failed at t = {} s: {message}", number(*time))]
    Solver {
        /// Time of the failure (s).
        time: f64,
        /// What went wrong.
        message: String,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`]; a number is shown as
    /// [`number`] shows it.
    pub fn invalid(field: &str, value: impl Shown, expected: &str) -> Self {
        Error::InvalidParameter {
            field: field.to_string(),
            value: value.shown(),
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

/// Plain decimals for magnitudes from 1e-4 up to 1e15, and zero; an
/// exponent outside (and `inf`, `NaN` as Rust writes them).
fn plain(a: f64) -> bool {
    a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a)
}

/// The shortest text that reads back as exactly `x`: plain for ordinary
/// magnitudes, with an exponent below 1e-4 or from 1e15 (so that a tail
/// probability of 1e-300 or `f64::MIN_POSITIVE` is not 300 digits). Files
/// write numbers so (`io_util::number`), and messages show them so.
///
/// ```
/// use rockfrag::error::number;
/// assert_eq!(number(0.25), "0.25");
/// assert_eq!(number(1e300), "1e300");
/// assert_eq!(number(f64::MIN_POSITIVE), "2.2250738585072014e-308");
/// ```
pub fn number(x: f64) -> String {
    if plain(x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// `x` with `decimals` decimals, for a console line (`0.300 g`), switching
/// to that many decimals of an exponent where [`number`] does: a PGA of
/// 3e299 g reads `3.058e299`, not 300 digits.
///
/// ```
/// use rockfrag::error::fixed;
/// assert_eq!(fixed(0.29999, 3), "0.300");
/// assert_eq!(fixed(3.0581e299, 3), "3.058e299");
/// assert_eq!(fixed(0.0, 3), "0.000");
/// ```
pub fn fixed(x: f64, decimals: usize) -> String {
    if plain(x.abs()) {
        format!("{x:.decimals$}")
    } else {
        format!("{x:.decimals$e}")
    }
}

/// A value as an error message shows it: numbers by [`number`], text and
/// whole numbers as they are.
pub trait Shown {
    /// The text of the value in a message.
    fn shown(&self) -> String;
}

impl Shown for f64 {
    fn shown(&self) -> String {
        number(*self)
    }
}

impl Shown for f32 {
    fn shown(&self) -> String {
        number(f64::from(*self))
    }
}

impl Shown for str {
    fn shown(&self) -> String {
        self.to_string()
    }
}

impl Shown for String {
    fn shown(&self) -> String {
        self.clone()
    }
}

impl<T: Shown + ?Sized> Shown for &T {
    fn shown(&self) -> String {
        (**self).shown()
    }
}

macro_rules! shown_as_displayed {
    ($($t:ty),*) => {$(
        impl Shown for $t {
            fn shown(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
shown_as_displayed!(
    u8, u16, u32, u64, usize, i8, i16, i32, i64, isize, bool, char
);

/// Result alias used throughout the library.
pub type Result<T> = std::result::Result<T, Error>;
