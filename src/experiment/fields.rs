//! Field rules shared by the validators of experiment files: identifiers, mass numbers and
//! the frequencies that can be simulated.
//! A leaf of the experiment room.

use std::path::Path;

use crate::error::{Error, Result};
use crate::model::Structure;

/// Letters, digits, '_' and '-'.
pub fn is_identifier(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The longest id, in characters: an id names a folder or file, with a suffix of its own
/// (`.NAME.tmp-PID`, `_compliance.png`, a model's id after it), within the 255 bytes a file
/// name may have.
pub const MAX_ID: usize = 100;

/// Refuses an id longer than [`MAX_ID`] characters, at `key` of `path`.
pub fn id_length(path: &Path, key: &str, id: &str) -> Result<()> {
    if id.chars().count() > MAX_ID {
        return Err(Error::invalid(
            path,
            key,
            format!("\"{}...\" ({} characters)", id.chars().take(24).collect::<String>(), id.chars().count()),
            format!("at most {MAX_ID} characters: an id names a folder or file of the output"),
        ));
    }
    Ok(())
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

/// Lowest forcing frequency simulated, relative to the structure's highest natural
/// frequency: below it one forcing period holds more than 10^5 oscillations of the fastest
/// mode, which the event search steps through (a point would take minutes, and at 1e-6 Hz
/// on the paper's structure, for ever).
pub const MIN_FREQUENCY_RATIO: f64 = 1e-5;

/// Checks that forcing frequencies (Hz) are positive, finite and at least
/// [`MIN_FREQUENCY_RATIO`] times the structure's highest natural frequency; a bad one is
/// named `{key}[i]`.
pub fn check_frequencies(origin: &str, key: &str, freq_hz: &[f64], structure: &Structure) -> Result<()> {
    let top = structure.highest_natural_frequency_hz();
    let floor = MIN_FREQUENCY_RATIO * top;
    for (i, &f) in freq_hz.iter().enumerate() {
        if !(f.is_finite() && f > 0.0) {
            return Err(Error::invalid(
                origin,
                format!("{key}[{i}]"),
                f,
                "frequencies must be positive and finite (Hz)",
            ));
        }
        if f < floor {
            return Err(Error::invalid(
                origin,
                format!("{key}[{i}]"),
                f,
                format!(
                    "a forcing frequency must be at least {MIN_FREQUENCY_RATIO:e} times the structure's highest natural frequency ({top:.4} Hz), i.e. {floor:.4e} Hz: a longer period holds too many oscillations of the fastest mode to simulate"
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses a list with a repeated value or more than `max` values (`what` names them in the
/// message); a repeat is named by both its places.
pub fn distinct<T: PartialEq + Copy + Shown>(path: &Path, key: &str, list: &[T], max: usize, what: &str) -> Result<()> {
    if list.len() > max {
        return Err(Error::invalid(path, key, format!("{} values", list.len()), format!("at most {max} {what}")));
    }
    for (i, v) in list.iter().enumerate() {
        if let Some(j) = list[..i].iter().position(|w| w == v) {
            return Err(Error::invalid(
                path,
                format!("{key}[{i}]"),
                v.shown(),
                format!("repeats {key}[{j}]: give each value once"),
            ));
        }
    }
    Ok(())
}

/// How a value of a list is quoted in a message.
pub trait Shown {
    /// The value as a message quotes it.
    fn shown(&self) -> String;
}

impl Shown for f64 {
    fn shown(&self) -> String {
        crate::number::fmt_num(*self)
    }
}

impl Shown for i64 {
    fn shown(&self) -> String {
        self.to_string()
    }
}

impl Shown for &str {
    fn shown(&self) -> String {
        format!("\"{self}\"")
    }
}
