//! What an explorer request may set: the key paths of [`ALLOWED`] (with their controls'
//! ranges) and a bed's law, each to a number or a law's name; anything else is refused with
//! its reason.

use serde_json::Value;

use crate::error::file::OverrideError;
use crate::experiment::study::KeyPath;

/// The key paths a request may set (a selector `[...]` after `cases` or `dampers` picks one
/// case or container), what each takes and the range the page's control spans. The
/// experiment's validation has the last word on every value.
pub const ALLOWED: &[Allowed] = &[
    Allowed { path: "cases[*].dampers[*].clearance_mm", label: "clearance, mm", min: 0.01, max: 20.0, log: true },
    Allowed { path: "cases[*].dampers[*].mass_ratio", label: "mass ratio", min: 0.005, max: 0.5, log: true },
    Allowed { path: "cases[*].dampers[*].restitution", label: "restitution", min: 0.0, max: 0.95, log: false },
    Allowed { path: "structure.damping.modal_ratios", label: "modal damping ratio", min: 0.0005, max: 0.1, log: true },
    Allowed { path: "excitation.force_n", label: "force, N", min: 0.05, max: 50.0, log: true },
];

/// One settable key path and its control's range.
#[derive(Debug, Clone, Copy)]
pub struct Allowed {
    /// The path with `[*]` where a request may also name one element.
    pub path: &'static str,
    /// The control's label.
    pub label: &'static str,
    /// The control's range (the validation's is wider or equal).
    pub min: f64,
    /// Upper end of the control's range.
    pub max: f64,
    /// Whether the control moves on a logarithmic scale.
    pub log: bool,
}

/// The bed laws a request may choose (`cases[*].dampers[*].bed`).
pub(super) const LAWS: &[&str] = &["plastic", "restitution"];

/// Why one `[path, value]` of a request is refused (the request names it).
#[derive(Debug, thiserror::Error)]
pub(super) enum SetError {
    /// Not a key path, or one the setup cannot take.
    #[error(transparent)]
    Path(#[from] OverrideError),
    /// A bed's law that is not one.
    #[error("a bed law: one of {LAWS:?}")]
    Law,
    /// A key the explorer does not set.
    #[error("not a key the explorer sets; these are (a selector [INDEX] or [ID] may replace [*]): {0:?}")]
    NotSet(Vec<&'static str>),
    /// A value that is not a finite number.
    #[error("a finite number")]
    NotANumber,
}

/// The path and value of one `[path, value]` of a request, when [`ALLOWED`] (or a bed law).
pub(super) fn allowed(key: &str, value: &Value) -> std::result::Result<(KeyPath, toml::Value), SetError> {
    let path = KeyPath::parse(key)?;
    let general = generalise(key);
    if general == "cases[*].dampers[*].bed" {
        let law = value.as_str().filter(|s| LAWS.contains(s)).ok_or(SetError::Law)?;
        return Ok((path, toml::Value::String(law.to_string())));
    }
    if !ALLOWED.iter().any(|a| a.path == general || format!("{}[*]", a.path) == general) {
        return Err(SetError::NotSet(ALLOWED.iter().map(|a| a.path).chain(["cases[*].dampers[*].bed"]).collect()));
    };
    let x = value.as_f64().filter(|x| x.is_finite()).ok_or(SetError::NotANumber)?;
    Ok((path, toml::Value::Float(x)))
}

/// `cases[single].dampers[0].clearance_mm` -> `cases[*].dampers[*].clearance_mm`: every
/// selector replaced by `[*]`.
pub(super) fn generalise(key: &str) -> String {
    let mut out = String::with_capacity(key.len());
    let mut inside = false;
    for ch in key.chars() {
        match ch {
            '[' => {
                inside = true;
                out.push_str("[*]");
            }
            ']' => inside = false,
            _ if inside => {}
            _ => out.push(ch),
        }
    }
    out
}
