//! Pieces of the report's views shared by its pages: status classes, counts in words, figure
//! files, and which conclusions depend on the model. Pages build on this; it builds on
//! nothing of theirs.

use serde::Serialize;

use crate::analysis::ExperimentResult;
use crate::checks::{CheckOutcome, Status};

/// The CSS class of a status.
pub fn status_class(s: Status) -> &'static str {
    match s {
        Status::Pass => "pass",
        Status::Fail => "fail",
        Status::KnownDeviation => "known",
        Status::KnownDeviationPasses => "revisit",
    }
}

/// A figure with its files.
#[derive(Debug, Default, Serialize)]
pub struct FigureView {
    /// Title above the figure.
    pub title: String,
    /// One sentence under it.
    pub caption: String,
    /// Link to the PNG file ("" when the figure is written as SVG only).
    pub png: String,
    /// Link to the SVG file ("" when the figure is written as PNG only).
    pub svg: String,
}

impl FigureView {
    /// The file the page shows: the PNG when there is one, else the SVG.
    pub fn image(&self) -> &str {
        if self.png.is_empty() {
            &self.svg
        } else {
            &self.png
        }
    }

    /// The file a click opens: the SVG when there is one (it scales), else the PNG.
    pub fn link(&self) -> &str {
        if self.svg.is_empty() {
            &self.png
        } else {
            &self.svg
        }
    }
}

/// Counts of statuses, in words.
pub fn counts(checks: &[CheckOutcome]) -> (String, &'static str, String) {
    let n = |s: Status| checks.iter().filter(|c| c.status == s).count();
    let (pass, fail, known, revisit) =
        (n(Status::Pass), n(Status::Fail), n(Status::KnownDeviation), n(Status::KnownDeviationPasses));
    let words = format!("{pass} pass, {fail} fail, {known} known deviation, {revisit} to revisit");
    let (verdict, class) = if checks.is_empty() {
        ("no checks".to_string(), "none")
    } else if fail > 0 {
        ("FAIL".to_string(), "fail")
    } else if known > 0 || revisit > 0 {
        ("pass, with known deviations".to_string(), "known")
    } else {
        ("pass".to_string(), "pass")
    };
    (verdict, class, words)
}

/// A number to four decimals (three in exponent form below 0.01 or from 1e4).
fn short(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e4) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}

/// True when a check's claim holds (passes, also where a deviation was expected).
fn holds(c: &CheckOutcome) -> bool {
    matches!(c.status, Status::Pass | Status::KnownDeviationPasses)
}

/// Which paper checks pass on some models and not on others, in sentences.
pub fn dependence(runs: &[&ExperimentResult]) -> Vec<String> {
    dependent(runs).into_iter().map(|(_, sentence)| sentence).collect()
}

fn dependent(runs: &[&ExperimentResult]) -> Vec<(String, String)> {
    let mut names: Vec<&str> = Vec::new();
    for r in runs {
        for c in r.checks.iter().filter(|c| c.source.is_paper()) {
            if !names.contains(&c.name.as_str()) {
                names.push(&c.name);
            }
        }
    }
    let label = |r: &ExperimentResult| r.experiment.model.as_ref().map(|m| m.label.clone()).unwrap_or_default();
    names
        .into_iter()
        .filter_map(|name| {
            let outcomes: Vec<(String, &CheckOutcome)> =
                runs.iter().filter_map(|r| r.checks.iter().find(|c| c.name == name).map(|c| (label(r), c))).collect();
            let words = |keep: bool| -> Vec<String> {
                outcomes
                    .iter()
                    .filter(|(_, c)| holds(c) == keep)
                    .map(|(l, c)| {
                        let unit = if c.unit.is_empty() { String::new() } else { format!(" {}", c.unit) };
                        format!("{l} ({}: {}{unit})", c.status.label(), short(c.computed))
                    })
                    .collect()
            };
            let (yes, no) = (words(true), words(false));
            if yes.is_empty() || no.is_empty() {
                return None;
            }
            Some((name.to_string(), format!("{name} holds on {} and not on {}.", yes.join(", "), no.join(", "))))
        })
        .collect()
}
