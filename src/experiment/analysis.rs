//! Validation of the `[analysis]` table: kinds, frequency grids, steady-state settings.

use std::path::Path;

use crate::error::{Error, Result};
use crate::sim::SteadyOptions;

use super::raw::{RawAnalysis, RawGrid, RawSteady};
use super::{Analysis, Number, Start};

/// Most grid points a frequency axis may have.
const MAX_GRID_POINTS: usize = 100_000;

/// The analysis kinds, for messages.
const KINDS: &str = "\"modal\", \"linear_frf\", \"sweep\", \"clearance_study\", \"waveform\"";

/// A frequency grid in Hz, validated.
pub fn grid(path: &Path, key: &str, g: &RawGrid) -> Result<Vec<f64>> {
    let bad = |k: &str, v: &dyn std::fmt::Display, msg: &str| Error::invalid(path, format!("{key}.{k}"), v, msg);
    if !(g.start.is_finite() && g.start > 0.0) {
        return Err(bad("start", &g.start, "frequencies must be positive and finite (Hz)"));
    }
    if !(g.stop.is_finite() && g.stop > g.start) {
        return Err(bad("stop", &g.stop, &format!("stop must be greater than start = {}", g.start)));
    }
    let span = g.stop - g.start;
    match (g.points, g.step) {
        (Some(p), None) => {
            if p < 2 || p as usize > MAX_GRID_POINTS {
                return Err(bad("points", &p, &format!("give 2 to {MAX_GRID_POINTS} points")));
            }
            let n = p as usize;
            Ok((0..n).map(|i| g.start + span * i as f64 / (n - 1) as f64).collect())
        }
        (None, Some(s)) => {
            if !(s.is_finite() && s > 0.0 && span / s < MAX_GRID_POINTS as f64) {
                return Err(bad(
                    "step",
                    &s,
                    &format!("the step must be positive and give at most {MAX_GRID_POINTS} points"),
                ));
            }
            // 8..60 step 0.1 includes 60 despite rounding; values print as written.
            let n = (span / s + 1e-9).floor() as usize + 1;
            Ok((0..n).map(|i| round_hz(g.start + s * i as f64)).collect())
        }
        _ => Err(Error::invalid(path, key, "(grid)", "give exactly one of points and step")),
    }
}

/// Grid values from a step are rounded to 1e-9 Hz.
pub fn round_hz(f: f64) -> f64 {
    (f * 1e9).round() / 1e9
}

fn require_grid(path: &Path, a: &RawAnalysis) -> Result<Vec<f64>> {
    match &a.freq_hz {
        Some(g) => grid(path, "analysis.freq_hz", g),
        None => Err(Error::invalid(
            path,
            "analysis.freq_hz",
            "(missing)",
            format!("analysis kind \"{}\" needs a grid: freq_hz = {{ start, stop, points | step }}", a.kind),
        )),
    }
}

fn positive_int(path: &Path, key: &str, v: Option<i64>, default: usize, max: usize) -> Result<usize> {
    match v {
        None => Ok(default),
        Some(x) if x >= 1 && x as usize <= max => Ok(x as usize),
        Some(x) => Err(Error::invalid(path, key, x, format!("give a whole number from 1 to {max}"))),
    }
}

/// Steady-state settings: the defaults of [`SteadyOptions`] with the file's overrides.
fn steady(path: &Path, s: Option<&RawSteady>) -> Result<SteadyOptions> {
    let mut o = SteadyOptions::default();
    let Some(s) = s else { return Ok(o) };
    if let Some(tol) = s.tol {
        if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
            return Err(Error::invalid(path, "analysis.steady.tol", tol, "a relative tolerance in (0, 1)"));
        }
        o.tol = tol;
    }
    o.consecutive = positive_int(path, "analysis.steady.consecutive", s.consecutive, o.consecutive, 1000)?;
    o.min_periods = positive_int(path, "analysis.steady.min_periods", s.min_periods, o.min_periods, 1_000_000)?;
    o.max_periods = positive_int(path, "analysis.steady.max_periods", s.max_periods, o.max_periods, 1_000_000)?;
    o.record_periods =
        positive_int(path, "analysis.steady.record_periods", s.record_periods, o.record_periods, 10_000)?;
    if o.min_periods > o.max_periods {
        return Err(Error::invalid(
            path,
            "analysis.steady.min_periods",
            o.min_periods,
            format!("must not exceed max_periods = {}", o.max_periods),
        ));
    }
    Ok(o)
}

/// Parses `"@EXPERIMENT.KEY"`.
pub fn export_ref(s: &str) -> Option<super::ExportRef> {
    let rest = s.strip_prefix('@')?;
    let (experiment, key) = rest.split_once('.')?;
    if experiment.is_empty() || key.is_empty() {
        return None;
    }
    Some(super::ExportRef { experiment: experiment.to_string(), key: key.to_string() })
}

fn number(path: &Path, key: &str, v: &toml::Value) -> Result<Number> {
    match v {
        toml::Value::Float(f) if f.is_finite() && *f > 0.0 => Ok(Number::Value(*f)),
        toml::Value::Integer(i) if *i > 0 => Ok(Number::Value(*i as f64)),
        toml::Value::String(s) => export_ref(s).map(Number::Export).ok_or_else(|| {
            Error::invalid(
                path,
                key,
                v,
                "a positive number, or \"@EXPERIMENT.KEY\" for a value another experiment exports",
            )
        }),
        other => Err(Error::invalid(path, key, other, "a positive number, or \"@EXPERIMENT.KEY\"")),
    }
}

/// Validates `[analysis]`; `n` is the number of masses, `case_ids` the cases of the file.
pub fn analysis(path: &Path, a: RawAnalysis, n: usize, case_ids: &[String]) -> Result<Analysis> {
    let steady = steady(path, a.steady.as_ref())?;
    let unused = |key: &str, present: bool| -> Result<()> {
        if present {
            Err(Error::invalid(
                path,
                format!("analysis.{key}"),
                "(given)",
                format!("not used by analysis kind \"{}\"", a.kind),
            ))
        } else {
            Ok(())
        }
    };
    match a.kind.as_str() {
        "modal" => Ok(Analysis::Modal),
        "linear_frf" => {
            unused("steady", a.steady.is_some())?;
            Ok(Analysis::LinearFrf { freq_hz: require_grid(path, &a)? })
        }
        "sweep" => {
            let start = match a.start.as_deref() {
                None | Some("rest") => Start::Rest,
                Some("continuation") => Start::Continuation,
                Some(other) => {
                    return Err(Error::invalid(
                        path,
                        "analysis.start",
                        format!("\"{other}\""),
                        "allowed: \"rest\", \"continuation\"",
                    ));
                }
            };
            Ok(Analysis::Sweep { freq_hz: require_grid(path, &a)?, start, steady })
        }
        "clearance_study" => {
            let clearances_mm = match &a.clearances_mm {
                Some(list) => {
                    for (i, c) in list.iter().enumerate() {
                        if !(c.is_finite() && *c > 0.0) {
                            return Err(Error::invalid(
                                path,
                                format!("analysis.clearances_mm[{i}]"),
                                c,
                                "clearances must be positive and finite (mm)",
                            ));
                        }
                    }
                    Some(list.clone())
                }
                None => None,
            };
            let points = positive_int(path, "analysis.clearance_points", a.clearance_points, 12, 200)?;
            let objective_mass = match a.objective_mass {
                Some(m) if m >= 1 && m as usize <= n => m as usize - 1,
                Some(m) => {
                    return Err(Error::invalid(
                        path,
                        "analysis.objective_mass",
                        m,
                        format!("masses are numbered 1 to {n}"),
                    ))
                }
                None => {
                    return Err(Error::invalid(
                        path,
                        "analysis.objective_mass",
                        "(missing)",
                        "name the mass whose peak compliance is compared (1-based)",
                    ))
                }
            };
            let objective_case = match &a.objective_case {
                Some(c) if case_ids.contains(c) => c.clone(),
                Some(c) => {
                    return Err(Error::invalid(
                        path,
                        "analysis.objective_case",
                        format!("\"{c}\""),
                        format!("no such case; the cases are {case_ids:?}"),
                    ))
                }
                None => {
                    return Err(Error::invalid(
                        path,
                        "analysis.objective_case",
                        "(missing)",
                        "name the case whose peak decides the best clearance",
                    ))
                }
            };
            Ok(Analysis::ClearanceStudy {
                freq_hz: require_grid(path, &a)?,
                clearances_mm,
                points,
                objective_mass,
                objective_case,
                steady,
            })
        }
        "waveform" => {
            let Some(list) = &a.frequencies_hz else {
                return Err(Error::invalid(
                    path,
                    "analysis.frequencies_hz",
                    "(missing)",
                    "list the forcing frequencies (Hz)",
                ));
            };
            let frequencies = list
                .iter()
                .enumerate()
                .map(|(i, v)| number(path, &format!("analysis.frequencies_hz[{i}]"), v))
                .collect::<Result<Vec<_>>>()?;
            let labels = match &a.labels {
                Some(l) if l.len() == frequencies.len() => l.clone(),
                Some(l) => {
                    return Err(Error::invalid(
                        path,
                        "analysis.labels",
                        format!("{} labels", l.len()),
                        format!("give one label per frequency ({})", frequencies.len()),
                    ));
                }
                None => (1..=frequencies.len()).map(|i| i.to_string()).collect(),
            };
            let periods = positive_int(path, "analysis.periods", a.periods, 2, 100)?;
            Ok(Analysis::Waveform { frequencies, labels, periods, steady })
        }
        other => Err(Error::invalid(path, "analysis.kind", format!("\"{other}\""), format!("allowed kinds: {KINDS}"))),
    }
}
