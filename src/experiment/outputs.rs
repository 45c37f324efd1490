//! Validation of `[[plots]]`.

use std::path::Path;

use crate::error::{Error, Result};

use super::fields::{is_identifier, mass_index};
use super::file::raw::RawPlot;
use super::{Analysis, Linear, PlotSpec, Scale};

fn case_list(path: &Path, key: &str, cs: &[String], case_ids: &[String]) -> Result<()> {
    let names: Vec<&str> = cs.iter().map(String::as_str).collect();
    super::fields::distinct(path, key, &names, case_ids.len(), "cases (each of the experiment's once)")?;
    for (j, c) in cs.iter().enumerate() {
        if !case_ids.contains(c) {
            return Err(Error::invalid(
                path,
                format!("{key}[{j}]"),
                format!("\"{c}\""),
                format!("no such case; the cases are {case_ids:?}"),
            ));
        }
    }
    Ok(())
}

/// Validates one plot.
pub fn plot(path: &Path, i: usize, p: RawPlot, n: usize, case_ids: &[String], analysis: &Analysis) -> Result<PlotSpec> {
    let key = |k: &str| format!("plots[{i}].{k}");
    if !is_identifier(&p.id) {
        return Err(Error::invalid(
            path,
            key("id"),
            format!("\"{}\"", p.id),
            "use letters, digits, '_' and '-' only (it names the image file)",
        ));
    }
    super::fields::id_length(path, &key("id"), &p.id)?;
    let kinds = analysis.plot_kinds();
    let Some(kind) = kinds.iter().find(|(name, _)| *name == p.kind).map(|(_, k)| *k) else {
        let allowed: Vec<String> = kinds.iter().map(|(name, _)| format!("\"{name}\"")).collect();
        return Err(Error::invalid(
            path,
            key("kind"),
            format!("\"{}\"", p.kind),
            format!(
                "analysis kind \"{}\" draws: {}",
                analysis.kind(),
                if allowed.is_empty() { "no plots".into() } else { allowed.join(", ") }
            ),
        ));
    };
    let masses = match p.masses {
        Some(ms) => {
            super::fields::distinct(path, &key("masses"), &ms, n, "masses (each of the structure's once)")?;
            ms.iter()
                .enumerate()
                .map(|(j, &m)| mass_index(path, &format!("plots[{i}].masses[{j}]"), m, n))
                .collect::<Result<Vec<_>>>()?
        }
        None => (0..n).collect(),
    };
    let cases = match p.cases {
        Some(cs) => {
            case_list(path, &key("cases"), &cs, case_ids)?;
            cs
        }
        None => case_ids.to_vec(),
    };
    let y_scale = match p.y_scale.as_deref() {
        None | Some("log") => Scale::Log,
        Some("linear") => Scale::Linear,
        Some(other) => {
            return Err(Error::invalid(path, key("y_scale"), format!("\"{other}\""), "allowed: \"log\", \"linear\""))
        }
    };
    let marks: Vec<(String, f64)> = p.marks.unwrap_or_default().into_iter().map(|m| (m.label, m.offset_hz)).collect();
    for (j, (_, off)) in marks.iter().enumerate() {
        if !off.is_finite() {
            return Err(Error::invalid(path, format!("plots[{i}].marks[{j}].offset_hz"), off, "a finite offset in Hz"));
        }
    }
    let marks_relative_to = match p.marks_relative_to {
        Some(c) => {
            case_list(path, &key("marks_relative_to"), std::slice::from_ref(&c), case_ids)?;
            Some(c)
        }
        None if !marks.is_empty() => {
            return Err(Error::invalid(
                path,
                key("marks_relative_to"),
                "(missing)",
                "marks are offsets from the resonance peak of a case: name it",
            ));
        }
        None => None,
    };
    let linear = p
        .linear
        .unwrap_or_default()
        .iter()
        .enumerate()
        .map(|(j, l)| match l.as_str() {
            "bare" => Ok(Linear::Bare),
            "stuck" => Ok(Linear::Stuck),
            other => Err(Error::invalid(
                path,
                format!("plots[{i}].linear[{j}]"),
                format!("\"{other}\""),
                "allowed: \"bare\", \"stuck\"",
            )),
        })
        .collect::<Result<Vec<_>>>()?;
    let x_range = match p.x_range.as_deref() {
        None => None,
        Some(&[a, b]) if a.is_finite() && b.is_finite() && a < b => Some((a, b)),
        Some(v) => {
            return Err(Error::invalid(
                path,
                key("x_range"),
                crate::number::fmt_list(v),
                "give [from, to] with from < to, both finite",
            ))
        }
    };
    Ok(PlotSpec {
        x_range,
        id: p.id,
        kind,
        title: p.title,
        masses,
        cases,
        y_scale,
        mark_natural_frequencies: p.mark_natural_frequencies.unwrap_or(false),
        marks,
        marks_relative_to,
        linear,
    })
}
