//! A study file's entries checked: the models it runs on, its `[[vary]]` keys and their
//! values, the map's axes and how its samples are drawn; every message names the file and the
//! key.

use std::path::Path;

use crate::error::{Error, Result};

use super::super::file::raw_study::{RawStudy, RawVary};
use super::super::Experiment;
use super::{adaptive, Design, Domain, KeyPath, Vary, MAX_SAMPLES};

/// The experiments of the study's `models` (every model when none is listed), each once.
pub(super) fn chosen_models(path: &Path, all: Vec<Experiment>, models: Option<&[String]>) -> Result<Vec<Experiment>> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);
    let known: Vec<String> = all.iter().filter_map(|e| e.model.as_ref().map(|m| m.id.clone())).collect();
    match models {
        None => Ok(all),
        Some(list) => {
            if list.is_empty() || known.is_empty() {
                return Err(bad(
                    "study.models",
                    &format!("{list:?}"),
                    &format!("a non-empty list of the experiment's models {known:?}"),
                ));
            }
            let mut chosen = Vec::new();
            for id in list {
                let Some(e) = all.iter().find(|e| e.model.as_ref().is_some_and(|m| &m.id == id)) else {
                    return Err(bad(
                        "study.models",
                        &format!("\"{id}\""),
                        &format!("one of the experiment's models {known:?}"),
                    ));
                };
                if chosen.iter().any(|c: &Experiment| c.model == e.model) {
                    return Err(bad("study.models", &format!("\"{id}\""), "each model may be listed once"));
                }
                chosen.push(e.clone());
            }
            Ok(chosen)
        }
    }
}

/// The two varied keys a study's map draws (`map`, x then y; the first two by default).
pub(super) fn map_of(path: &Path, names: Option<&[String]>, vary: &[Vary]) -> Result<Option<(usize, usize)>> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);
    Ok(match names {
        None => (vary.len() >= 2).then_some((0, 1)),
        Some(names) => {
            let names_all: Vec<&str> = vary.iter().map(|v| v.name.as_str()).collect();
            let idx: Option<Vec<usize>> = names.iter().map(|n| vary.iter().position(|v| &v.name == n)).collect();
            match idx.as_deref() {
                Some([x, y]) if x != y => Some((*x, *y)),
                _ => {
                    return Err(bad(
                        "study.map",
                        &format!("{names:?}"),
                        &format!("two different names of varied keys, x then y (the names are {names_all:?})"),
                    ))
                }
            }
        }
    })
}

pub(super) fn vary_entry(path: &Path, i: usize, v: RawVary) -> Result<Vary> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| {
        Error::invalid(path, format!("vary[{i}].{key}"), value, msg)
    };
    if !v.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') || v.name.is_empty() {
        return Err(bad("name", &format!("\"{}\"", v.name), "a column name: letters, digits and '_'"));
    }
    if matches!(
        v.name.as_str(),
        "sample" | "model" | "check" | "claim" | "reading" | "value" | "holds" | "bound" | "status"
    ) {
        return Err(bad(
            "name",
            &format!("\"{}\"", v.name),
            "this name is a column of every study table; choose another",
        ));
    }
    let key = KeyPath::parse(&v.key).map_err(|m| bad("key", &format!("\"{}\"", v.key), &m.to_string()))?;
    let domain = match (v.values, v.range) {
        (Some(values), None) => {
            if values.is_empty() || values.iter().any(|x| !x.is_finite()) {
                return Err(bad("values", &crate::number::fmt_list(&values), "a non-empty list of finite numbers"));
            }
            Domain::Values(values)
        }
        (None, Some(r)) => {
            let log = match r.scale.as_deref() {
                None | Some("linear") => false,
                Some("log") => true,
                Some(other) => return Err(bad("range.scale", &format!("\"{other}\""), "\"linear\" or \"log\"")),
            };
            if !(r.start.is_finite() && r.stop.is_finite())
                || r.start == r.stop
                || (log && (r.start <= 0.0 || r.stop <= 0.0))
            {
                return Err(bad(
                    "range",
                    &format!("{} to {}", r.start, r.stop),
                    "two different finite ends (both positive on a log scale)",
                ));
            }
            let count = match r.count {
                None => None,
                Some(c) if (1..=MAX_SAMPLES as i64).contains(&c) => Some(c as usize),
                Some(c) => return Err(bad("range.count", &c, &format!("from 1 to {MAX_SAMPLES}"))),
            };
            Domain::Range { start: r.start, stop: r.stop, count, log }
        }
        (values, _) => {
            return Err(bad(
                "values",
                &if values.is_some() { "(values and range)" } else { "(missing)" },
                "give exactly one of `values = [...]` or `range = { start, stop, count }`",
            ))
        }
    };
    let label = v.label.unwrap_or_else(|| v.name.clone());
    let experiments = v.experiments.unwrap_or_default();
    Ok(Vary { name: v.name, key, label, domain, experiments })
}

pub(super) fn design_of(path: &Path, s: &RawStudy, vary: &[Vary]) -> Result<Design> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);
    let seed = match s.seed {
        None => 1,
        Some(x) if (0..=i64::from(u32::MAX)).contains(&x) => x as u32,
        Some(x) => return Err(bad("study.seed", &x, "a whole number from 0 to 4294967295")),
    };
    let samples = |name: &str| -> Result<usize> {
        match s.samples {
            Some(n) if (1..=MAX_SAMPLES as i64).contains(&n) => Ok(n as usize),
            Some(n) => Err(bad("study.samples", &n, &format!("from 1 to {MAX_SAMPLES}"))),
            None => Err(bad("study.samples", &"(missing)", &format!("a {name} design needs the number of samples"))),
        }
    };
    let design = s.design.as_deref().unwrap_or("grid");
    if design != "adaptive" {
        if let Some(key) = [("study.levels", s.levels.is_some()), ("study.refine", s.refine.is_some())]
            .iter()
            .find_map(|(k, given)| given.then_some(*k))
        {
            return Err(bad(
                key,
                &"(given)",
                "only an adaptive design (`design = \"adaptive\"`) has levels and refine",
            ));
        }
    }
    match design {
        "grid" => {
            if s.samples.is_some() || s.seed.is_some() {
                return Err(bad(
                    "study.samples",
                    &"(given)",
                    "a grid has one sample per combination: give no `samples` or `seed`",
                ));
            }
            if let Some(i) = vary.iter().position(|v| v.domain.grid().is_none()) {
                return Err(bad(
                    &format!("vary[{i}].range.count"),
                    &"(missing)",
                    "a grid needs the number of points of each range",
                ));
            }
            Ok(Design::Grid)
        }
        "sobol" if vary.len() > 256 => Err(bad(
            "vary",
            &format!("{} keys", vary.len()),
            "a Sobol design varies at most 256 keys (use latin_hypercube)",
        )),
        "sobol" => Ok(Design::Sobol { samples: samples("sobol")?, seed }),
        "latin_hypercube" => Ok(Design::LatinHypercube { samples: samples("latin_hypercube")?, seed }),
        "adaptive" => {
            adaptive::design_of(path, s.levels, s.refine.as_ref(), s.samples.is_some() || s.seed.is_some(), vary)
        }
        other => Err(bad(
            "study.design",
            &format!("\"{other}\""),
            "one of \"grid\", \"sobol\", \"latin_hypercube\", \"adaptive\"",
        )),
    }
}
