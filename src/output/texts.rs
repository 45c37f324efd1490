//! Fills the placeholders of every experiment's texts (its deviation, notes and each check's
//! known deviation) with the values the run computed (syntax: experiment::texts), once every
//! result is in, before any page is written.

use std::collections::BTreeMap;

use crate::analysis::ExperimentResult;
use crate::checks::CheckOutcome;
use crate::error::{Error, Result};
use crate::experiment::texts::{format, parse, Piece, Placeholder, Target};

/// What to do with a placeholder whose experiment is not among the results (`shotdamp run` of
/// some experiments): in a report every experiment runs, so it is an error there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Missing {
    /// An error naming the experiment.
    Error,
    /// A remark in the text that the value is not in this run.
    Say,
}

/// Results by (experiment id, model id).
struct Index<'a> {
    runs: BTreeMap<(String, Option<String>), &'a ExperimentResult>,
}

impl<'a> Index<'a> {
    fn new(results: &'a [ExperimentResult]) -> Index<'a> {
        let runs = results
            .iter()
            .map(|r| ((r.experiment.meta.id.clone(), r.experiment.model.as_ref().map(|m| m.id.clone())), r))
            .collect();
        Index { runs }
    }

    /// The run of experiment `id` on `model` (an experiment with one structure of its own
    /// runs on every model).
    fn get(&self, id: &str, model: Option<&str>) -> Option<&'a ExperimentResult> {
        let own = self.runs.get(&(id.to_string(), model.map(String::from)));
        own.or_else(|| self.runs.get(&(id.to_string(), None))).copied()
    }

    fn has(&self, id: &str) -> bool {
        self.runs.keys().any(|(e, _)| e == id)
    }
}

/// The values every check has, besides its named ones.
const FIELDS: [&str; 6] = ["computed", "expected", "ratio", "rel_diff", "hz", "expected_hz"];

fn field(o: &CheckOutcome, name: &str) -> Option<f64> {
    let tau = std::f64::consts::TAU;
    match name {
        "computed" => Some(o.computed),
        "expected" => Some(o.expected),
        "ratio" => Some(o.computed / o.expected),
        "rel_diff" => Some(o.rel_diff),
        "hz" => Some(o.computed / tau),
        "expected_hz" => Some(o.expected / tau),
        _ => o.values.iter().find(|(n, _)| n == name).map(|(_, v)| *v),
    }
}

/// Why a placeholder has no value (the caller names the file, the key and the placeholder).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum ValueError {
    /// Its experiment ran, not on this model.
    #[error("experiment {experiment} did not run on model {model}")]
    NotOnModel { experiment: String, model: String },
    /// No check of that id.
    #[error("{run} has no check with id \"{id}\"; its ids are {ids:?}")]
    NoCheck { run: String, id: String, ids: Vec<String> },
    /// The check has no such value.
    #[error("check {id} has no value \"{name}\"; it has {names:?}")]
    NoField { id: String, name: String, names: Vec<String> },
    /// The experiment exports no such value.
    #[error("{run} exports no \"{name}\"; it exports {names:?}")]
    NoExport { run: String, name: String, names: Vec<String> },
}

/// The value of one placeholder in a text of `r`: `Ok(None)` when its experiment did not run.
fn value(index: &Index, r: &ExperimentResult, p: &Placeholder) -> std::result::Result<Option<f64>, ValueError> {
    let model = p.model.as_deref().or(r.experiment.model.as_ref().map(|m| m.id.as_str()));
    let experiment = match &p.target {
        Target::Check { experiment, .. } => experiment.as_deref().unwrap_or(&r.experiment.meta.id),
        Target::Export { experiment, .. } => experiment.as_str(),
    };
    if !index.has(experiment) {
        return Ok(None);
    }
    let Some(run) = index.get(experiment, model) else {
        return Err(ValueError::NotOnModel {
            experiment: experiment.to_string(),
            model: model.unwrap_or("(none)").to_string(),
        });
    };
    match &p.target {
        Target::Check { id, field: name, .. } => {
            let Some(o) = run.checks.iter().find(|c| c.id.as_deref() == Some(id)) else {
                let ids = run.checks.iter().filter_map(|c| c.id.clone()).collect();
                return Err(ValueError::NoCheck { run: run.experiment.key(), id: id.clone(), ids });
            };
            field(o, name).map(Some).ok_or_else(|| ValueError::NoField {
                id: id.clone(),
                name: name.clone(),
                names: FIELDS.into_iter().map(String::from).chain(o.values.iter().map(|(n, _)| n.clone())).collect(),
            })
        }
        Target::Export { name, .. } => run.exports.get(name).copied().map(Some).ok_or_else(|| ValueError::NoExport {
            run: run.experiment.key(),
            name: name.clone(),
            names: run.exports.keys().cloned().collect(),
        }),
    }
}

/// A text of `r` (at `key` of its file) with its placeholders filled.
fn fill_text(index: &Index, r: &ExperimentResult, key: &str, text: &str, missing: Missing) -> Result<String> {
    let path = &r.experiment.path;
    let pieces = parse(text).map_err(|e| Error::refused(path, key, "(the text)", e))?;
    let mut out = String::with_capacity(text.len());
    for piece in pieces {
        match piece {
            Piece::Literal(s) => out.push_str(&s),
            Piece::Value(p) => match value(index, r, &p) {
                Ok(Some(v)) => out.push_str(&format(v, p.format)),
                Ok(None) if missing == Missing::Say => {
                    out.push_str(&format!("[{}: its experiment is not in this run]", p.text))
                }
                Ok(None) => {
                    return Err(Error::invalid(path, key, &p.text, "names an experiment that is not in the report"))
                }
                Err(why) => return Err(Error::invalid(path, key, &p.text, why.to_string())),
            },
        }
    }
    Ok(out)
}

/// Every result's texts with their placeholders filled from `results`.
pub fn fill(results: &mut [ExperimentResult], missing: Missing) -> Result<()> {
    type Filled = (Option<String>, Vec<String>, Vec<Option<String>>);
    let filled: Vec<Filled> = {
        let index = Index::new(results);
        results
            .iter()
            .map(|r| {
                let meta = &r.experiment.meta;
                let deviation = match &meta.deviation {
                    Some(d) => Some(fill_text(&index, r, "experiment.deviation", d, missing)?),
                    None => None,
                };
                let notes = meta
                    .notes
                    .iter()
                    .enumerate()
                    .map(|(i, n)| fill_text(&index, r, &format!("experiment.notes[{i}]"), n, missing))
                    .collect::<Result<Vec<_>>>()?;
                let reasons = r
                    .checks
                    .iter()
                    .map(|c| match &c.reason {
                        Some(t) => {
                            let key = format!("known_deviation of check {}", c.id.as_deref().unwrap_or(&c.name));
                            fill_text(&index, r, &key, t, missing).map(Some)
                        }
                        None => Ok(None),
                    })
                    .collect::<Result<Vec<_>>>()?;
                Ok((deviation, notes, reasons))
            })
            .collect::<Result<_>>()?
    };
    for (r, (deviation, notes, reasons)) in results.iter_mut().zip(filled) {
        r.experiment.meta.deviation = deviation;
        r.experiment.meta.notes = notes;
        for (c, reason) in r.checks.iter_mut().zip(reasons) {
            c.reason = reason;
        }
    }
    Ok(())
}
