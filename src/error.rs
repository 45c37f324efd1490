//! Errors of the library. Every error says where (file, key), what (the value) and what
//! is allowed, so that a user can fix the input without reading code.

use std::path::{Path, PathBuf};

use thiserror::Error;

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

    /// An I/O error on `path`.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Error {
        Error::Io { path: path.as_ref().to_path_buf(), error: source }
    }

    /// True for errors caused by the user's input (exit code 2 at the edge, like I/O).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Invalid { .. } | Error::Parse { .. })
    }
}

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
