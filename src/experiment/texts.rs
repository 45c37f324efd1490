//! Placeholders in an experiment's texts (`experiment.deviation`, `experiment.notes`, each
//! check's `known_deviation`): a number a text quotes from the computation is written as a
//! placeholder and filled when the report is written, so it cannot drift from what was computed
//! (docs/experiment-format.md, "Numbers in texts").
//!
//! ```text
//! {ratio}                          check `ratio` of this experiment, this model: its computed value
//! {ratio:2}                        ... with 2 decimals
//! {ratio.f:1}                      ... one of its named values (here: the frequency of the peak)
//! {coil/ratio:2}                   ... on model `coil`
//! {fig05_low_damping#ratio:1}      a check of another experiment (this model)
//! {rise:1%}                        a ratio as a signed change in per cent: 1.037 -> +3.7
//! {@fig05_clearance_scan.best_clearance_mm:2}    an exported value, as `@` in the file
//! ```
//!
//! This module parses and validates; the values are looked up where the results are
//! (output::texts).

use std::path::Path;

use super::{CheckSpec, Meta};
use crate::error::file::TextError;
use crate::error::{Error, Result};

/// How a value is printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// The report's usual rounding (`fmt_num`).
    Default,
    /// Fixed decimals.
    Fixed(usize),
    /// A ratio r as the signed change 100 (r - 1), with fixed decimals: "+3.7", "-11".
    Change(usize),
}

/// What a placeholder names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A check (by its `id`) and a value of it: `computed`, `expected` or one of its named
    /// values.
    Check {
        /// The experiment (None: the text's own).
        experiment: Option<String>,
        /// The check's id.
        id: String,
        /// `computed`, `expected` or a named value.
        field: String,
    },
    /// An exported value of an experiment.
    Export {
        /// The experiment's id.
        experiment: String,
        /// The exported value's name.
        name: String,
    },
}

/// One placeholder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Placeholder {
    /// As written, braces included.
    pub text: String,
    /// The model of the run it reads (`None`: the text's own).
    pub model: Option<String>,
    /// What it names.
    pub target: Target,
    /// How the value is written.
    pub format: Format,
}

/// A text cut into literal pieces and placeholders.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Piece {
    /// Text as written.
    Literal(String),
    /// A placeholder.
    Value(Placeholder),
}

use super::fields::is_identifier as name_ok;

fn placeholder(inner: &str) -> std::result::Result<Placeholder, TextError> {
    let text = format!("{{{inner}}}");
    let bad = |why: &'static str| Err(TextError::Placeholder { text: text.clone(), why });
    let (body, format) = match inner.split_once(':') {
        None => (inner, Format::Default),
        Some((body, f)) => {
            let (digits, change) = match f.strip_suffix('%') {
                Some(d) => (d, true),
                None => (f, false),
            };
            let Ok(n) = digits.parse::<usize>() else { return bad("the format after ':' is a number of decimals") };
            if n > 12 {
                return bad("at most 12 decimals");
            }
            (body, if change { Format::Change(n) } else { Format::Fixed(n) })
        }
    };
    let (model, rest) = match body.split_once('/') {
        Some((m, r)) => (Some(m.to_string()), r),
        None => (None, body),
    };
    if model.as_deref().is_some_and(|m| !name_ok(m)) {
        return bad("the model before '/' is a model id");
    }
    let target = if let Some(export) = rest.strip_prefix('@') {
        let Some((experiment, name)) = export.split_once('.') else {
            return bad("an export is @EXPERIMENT.NAME");
        };
        if !(name_ok(experiment) && name_ok(name)) {
            return bad("an export is @EXPERIMENT.NAME");
        }
        Target::Export { experiment: experiment.into(), name: name.into() }
    } else {
        let (experiment, check) = match rest.split_once('#') {
            Some((e, c)) => (Some(e.to_string()), c),
            None => (None, rest),
        };
        let (id, field) = check.split_once('.').unwrap_or((check, "computed"));
        if !(name_ok(id) && name_ok(field) && experiment.as_deref().is_none_or(name_ok)) {
            return bad("a check is named by its id");
        }
        Target::Check { experiment, id: id.into(), field: field.into() }
    };
    Ok(Placeholder { text, model, target, format })
}

/// The pieces of a text. Braces only open placeholders; an unclosed one is an error.
pub fn parse(text: &str) -> std::result::Result<Vec<Piece>, TextError> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find('{') {
        if open > 0 {
            out.push(Piece::Literal(rest[..open].to_string()));
        }
        let Some(close) = rest[open..].find('}') else {
            return Err(TextError::Unclosed(rest[open..].to_string()));
        };
        out.push(Piece::Value(placeholder(&rest[open + 1..open + close])?));
        rest = &rest[open + close + 1..];
    }
    if rest.contains('}') {
        return Err(TextError::Unopened(rest.to_string()));
    }
    if !rest.is_empty() {
        out.push(Piece::Literal(rest.to_string()));
    }
    Ok(out)
}

/// The placeholders of a text (none for a text that does not parse).
pub fn placeholders(text: &str) -> Vec<Placeholder> {
    parse(text)
        .unwrap_or_default()
        .into_iter()
        .filter_map(|p| match p {
            Piece::Value(v) => Some(v),
            Piece::Literal(_) => None,
        })
        .collect()
}

/// Checks an experiment's texts: each parses, check ids are unique, and a placeholder that
/// names a check of this experiment on this model names one it has.
pub(super) fn validate(path: &Path, meta: &Meta, checks: &[CheckSpec]) -> Result<()> {
    let mut ids: Vec<&str> = Vec::new();
    for (i, c) in checks.iter().enumerate() {
        if let Some(id) = c.id.as_deref() {
            if ids.contains(&id) {
                return Err(Error::invalid(path, format!("checks[{i}].id"), format!("\"{id}\""), "each check id once"));
            }
            ids.push(id);
        }
    }
    let mut texts: Vec<(String, &str)> = Vec::new();
    texts.extend(meta.deviation.as_deref().map(|d| ("experiment.deviation".to_string(), d)));
    texts.extend(meta.notes.iter().enumerate().map(|(i, n)| (format!("experiment.notes[{i}]"), n.as_str())));
    for (i, c) in checks.iter().enumerate() {
        texts.extend(c.known_deviation.as_deref().map(|d| (format!("checks[{i}].known_deviation"), d)));
    }
    for (key, text) in texts {
        let pieces = parse(text).map_err(|e| Error::refused(path, &key, "(the text)", e))?;
        for p in pieces {
            let Piece::Value(p) = p else { continue };
            if let (None, Target::Check { experiment: None, id, .. }) = (&p.model, &p.target) {
                if !ids.contains(&id.as_str()) {
                    return Err(Error::invalid(
                        path,
                        &key,
                        &p.text,
                        format!("no check of this experiment has id \"{id}\" (on this model); the ids are {ids:?}"),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Prints a value in a format.
pub fn format(v: f64, f: Format) -> String {
    match f {
        Format::Default => crate::number::fmt_num(v),
        Format::Fixed(n) => format!("{v:.n$}"),
        Format::Change(n) => {
            let c = 100.0 * (v - 1.0);
            let s = format!("{c:+.n$}");
            // "-0.0" and "+0.0" both read as no change.
            if s.trim_start_matches(['+', '-']).chars().all(|ch| ch == '0' || ch == '.') {
                s.trim_start_matches(['+', '-']).to_string()
            } else {
                s
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholders_parse() {
        let p =
            parse("a factor {ratio:2}, at {ratio.f:1} Hz ({coil/ratio}; {x#y.expected}; {@scan.best_mm:2}; {r:1%})")
                .unwrap();
        let v: Vec<&Placeholder> = p
            .iter()
            .filter_map(|x| match x {
                Piece::Value(v) => Some(v),
                _ => None,
            })
            .collect();
        assert_eq!(v.len(), 6);
        assert_eq!(v[0].target, Target::Check { experiment: None, id: "ratio".into(), field: "computed".into() });
        assert_eq!(v[0].format, Format::Fixed(2));
        assert_eq!(v[1].target, Target::Check { experiment: None, id: "ratio".into(), field: "f".into() });
        assert_eq!(v[2].model.as_deref(), Some("coil"));
        assert_eq!(
            v[3].target,
            Target::Check { experiment: Some("x".into()), id: "y".into(), field: "expected".into() }
        );
        assert_eq!(v[4].target, Target::Export { experiment: "scan".into(), name: "best_mm".into() });
        assert_eq!(v[5].format, Format::Change(1));
        assert_eq!(p[0], Piece::Literal("a factor ".into()));
    }

    #[test]
    fn bad_placeholders_are_named() {
        for bad in ["{ratio", "x}", "{ratio:two}", "{}", "{a b}", "{@scan}", "{m/}", "{r:13}"] {
            let e = parse(bad).unwrap_err();
            assert!(e.to_string().contains("placeholders {ID}"), "{bad}: {e}");
        }
    }

    #[test]
    fn formats() {
        assert_eq!(format(1.0374, Format::Change(1)), "+3.7");
        assert_eq!(format(0.89, Format::Change(0)), "-11");
        assert_eq!(format(1.00001, Format::Change(1)), "0.0");
        assert_eq!(format(2.254, Format::Fixed(2)), "2.25");
    }
}
