//! Field rules shared by the validators of experiment files: identifiers and mass numbers.
//! A leaf of the experiment room.

use std::path::Path;

use crate::error::{Error, Result};

/// Letters, digits, '_' and '-'.
pub fn is_identifier(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// A 1-based mass number to a 0-based index.
pub fn mass_index(path: &Path, key: &str, value: i64, n: usize) -> Result<usize> {
    if value < 1 || value as usize > n {
        return Err(Error::invalid(
            path,
            key,
            value,
            format!("masses are numbered 1 to {n} (the structure has {n} masses)"),
        ));
    }
    Ok(value as usize - 1)
}
