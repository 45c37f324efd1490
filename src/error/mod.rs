//! Errors of the library. Every error says where (file, key), what (the value) and what
//! is allowed, so that a user can fix the input without reading code.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::model::damping_fit::DampingFitError;
use crate::model::fit::FitError;
use crate::model::reduction::ReductionError;
use crate::sim::motion::eigen::EigenError;
use crate::sim::motion::system::SetupError;
use crate::sim::orbits::periodic::OrbitError;
use file::{OverrideError, TextError};

pub mod file;

/// Everything that can go wrong before or while producing results.
#[derive(Debug, Error)]
pub enum Error {
    /// A value in an input file is not allowed.
    #[error("{file}: {key} = {}: {}", crate::number::tidy_value(.value), crate::number::tidy_numbers(.message))]
    Invalid {
        /// The file (or the caller, outside files).
        file: String,
        /// The key path, e.g. `structure.masses_kg[1]`.
        key: String,
        /// The value given.
        value: String,
        /// What is allowed.
        message: String,
    },
    /// A value a lower layer refused (its typed [`Cause`]), with the file, key and value it
    /// came from and the words around the cause. The cause is not a `source`: its text is
    /// part of the message, which a chain would print twice.
    #[error("{file}: {key} = {}: {}", crate::number::tidy_value(.value), crate::number::tidy_numbers(&format!("{}{}{}", .around[0], .cause, .around[1])))]
    Refused {
        /// The file (or the caller, outside files).
        file: String,
        /// The key path.
        key: String,
        /// The value given.
        value: String,
        /// The lower layer's error (boxed: the crate's error stays small).
        cause: Box<Cause>,
        /// The words before the cause ("cannot be set in x.toml: ") and after it (what is
        /// allowed).
        around: Box<[String; 2]>,
    },
    /// A lower layer's error where no file or key is at hand (a caller of the library).
    #[error(transparent)]
    Domain(Box<Cause>),
    /// An input file is not valid TOML or does not have the expected shape.
    #[error("{file}: {}", crate::number::tidy_numbers(.message))]
    Parse {
        /// The file.
        file: String,
        /// What is wrong, with the key when known.
        message: String,
    },
    /// Reading or writing a file failed. (The OS error is part of the message, not a
    /// `source`: printed with its chain, it would otherwise appear twice.)
    #[error("{path}: {error}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// An output folder that shotdamp may not replace.
    #[error("{path}: {message}")]
    Destination {
        /// The folder.
        path: PathBuf,
        /// Why it may not be replaced, and what to do.
        message: String,
    },
    /// A data table could not be written or read.
    #[error("{path}: {message}")]
    Table {
        /// The table's file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Rendering a plot or a page failed.
    #[error("rendering {what}: {message}")]
    Render {
        /// What was being rendered.
        what: String,
        /// What went wrong.
        message: String,
    },
}

impl Error {
    /// A value that is not allowed, with the key path and what is allowed.
    pub fn invalid(
        file: impl AsRef<Path>,
        key: impl Into<String>,
        value: impl std::fmt::Display,
        message: impl Into<String>,
    ) -> Error {
        Error::Invalid {
            file: file.as_ref().display().to_string(),
            key: key.into(),
            value: value.to_string(),
            message: message.into(),
        }
    }

    /// A value of `file`'s `key` that a lower layer refused with `cause`.
    pub fn refused(
        file: impl AsRef<Path>,
        key: impl Into<String>,
        value: impl std::fmt::Display,
        cause: impl Into<Cause>,
    ) -> Error {
        Error::refused_in(file, key, value, "", cause, "")
    }

    /// [`Error::refused`] with words before and after the cause.
    pub fn refused_in(
        file: impl AsRef<Path>,
        key: impl Into<String>,
        value: impl std::fmt::Display,
        before: impl Into<String>,
        cause: impl Into<Cause>,
        after: impl Into<String>,
    ) -> Error {
        Error::Refused {
            file: file.as_ref().display().to_string(),
            key: key.into(),
            value: value.to_string(),
            cause: Box::new(cause.into()),
            around: Box::new([before.into(), after.into()]),
        }
    }

    /// The key path of an error about a value ([`Error::Invalid`], [`Error::Refused`]).
    pub fn key(&self) -> Option<&str> {
        match self {
            Error::Invalid { key, .. } | Error::Refused { key, .. } => Some(key),
            _ => None,
        }
    }

    /// This error with its file named anew by `f` (an error about a value or about a file's
    /// shape: the file of a merged table, a study's sample, an explorer request); others
    /// unchanged.
    pub fn in_file(self, f: impl FnOnce(String) -> String) -> Error {
        match self {
            Error::Invalid { file, key, value, message } => Error::Invalid { file: f(file), key, value, message },
            Error::Refused { file, key, value, cause, around } => {
                Error::Refused { file: f(file), key, value, cause, around }
            }
            Error::Parse { file, message } => Error::Parse { file: f(file), message },
            other => other,
        }
    }

    /// This error with its key named anew by `f` (an error about a value); others unchanged.
    pub fn with_key(self, f: impl FnOnce(String) -> String) -> Error {
        match self {
            Error::Invalid { file, key, value, message } => Error::Invalid { file, key: f(key), value, message },
            Error::Refused { file, key, value, cause, around } => {
                Error::Refused { file, key: f(key), value, cause, around }
            }
            other => other,
        }
    }

    /// The lower layer's error behind this one, typed, where there is one.
    pub fn cause(&self) -> Option<&Cause> {
        match self {
            Error::Refused { cause, .. } | Error::Domain(cause) => Some(cause.as_ref()),
            _ => None,
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Error {
        Error::Io { path: path.as_ref().to_path_buf(), error: source }
    }

    /// True for errors caused by the user's input (exit code 2 at the edge, like I/O).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Invalid { .. } | Error::Refused { .. } | Error::Parse { .. })
    }
}

/// A lower layer's error, typed: each layer's own enum converts into it (`From`), and into
/// the crate's [`enum@Error`] through it ([`Error::Domain`], or [`Error::refused`] with the file
/// and key). Its text is the lower error's, unchanged.
#[derive(Debug, Error)]
pub enum Cause {
    /// A system that cannot be set up ([`SetupError`]).
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A periodic orbit not found ([`OrbitError`]).
    #[error(transparent)]
    Orbit(#[from] OrbitError),
    /// A decomposition that failed ([`EigenError`]).
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// A finite-element model that cannot be reduced ([`ReductionError`]).
    #[error(transparent)]
    Reduction(#[from] ReductionError),
    /// A stiffness fit that failed ([`FitError`]).
    #[error(transparent)]
    Fit(#[from] FitError),
    /// A damping fit that failed ([`DampingFitError`]).
    #[error(transparent)]
    DampingFit(#[from] DampingFitError),
    /// A text whose placeholders do not parse ([`TextError`]).
    #[error(transparent)]
    Text(#[from] TextError),
    /// A key path that cannot be read or set ([`OverrideError`]).
    #[error(transparent)]
    Override(#[from] OverrideError),
}

/// Each layer's error into the crate's, through [`Cause`].
macro_rules! into_error {
    ($($t:ty),*) => {$(
        impl From<$t> for Error {
            fn from(e: $t) -> Error {
                Error::Domain(Box::new(Cause::from(e)))
            }
        }
    )*};
}
impl From<Cause> for Error {
    fn from(c: Cause) -> Error {
        Error::Domain(Box::new(c))
    }
}

into_error!(SetupError, OrbitError, EigenError, ReductionError, FitError, DampingFitError, TextError, OverrideError);

/// Result with the library's error.
pub type Result<T> = std::result::Result<T, Error>;

/// Reads a file to a string, with its path in the error; a path that is not a regular file
/// is refused ([`regular_file`]).
pub fn read_to_string(path: impl AsRef<Path>) -> Result<String> {
    regular_file(path.as_ref())?;
    std::fs::read_to_string(path.as_ref()).map_err(|e| Error::io(path, e))
}

/// Refuses an input path that exists but is not a regular file (a folder, a device such as
/// `/dev/zero`, a named pipe): reading one would fail, never end or fill the memory. A
/// missing path passes: the read that follows names its error.
pub fn regular_file(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(Error::io(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a regular file (a folder, a device or a pipe)"),
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lower layer's error keeps its type inside the crate's and its text in the message,
    /// between the words around it, printed once.
    #[test]
    fn a_refused_value_carries_its_typed_cause_and_the_same_words() {
        let e = Error::refused_in(
            "study.toml",
            "study.set.\"x\"",
            0.5,
            "cannot be set in a.toml: ",
            OverrideError::Syntax,
            "",
        );
        assert!(matches!(e.cause(), Some(Cause::Override(OverrideError::Syntax))));
        assert_eq!(
            e.to_string(),
            format!("study.toml: study.set.\"x\" = 0.5: cannot be set in a.toml: {}", file::PATH_SYNTAX)
        );
        assert!(std::error::Error::source(&e).is_none());
        let d: Error = TextError::Unopened("x}".into()).into();
        assert!(matches!(d.cause(), Some(Cause::Text(_))) && !d.is_input());
        assert_eq!(d.to_string(), TextError::Unopened("x}".into()).to_string());
    }
}
