//! Checks: a computed quantity against a reference under a stated tolerance, yielding
//! pass, fail, or a known deviation (an expected difference with a written reason).

pub mod baseline;
pub mod reference;
pub mod tube;
pub mod verdict;

use serde::Serialize;

use crate::experiment::CheckSpec;

pub use crate::number::{fmt_num, Tolerance};

/// The verdict of one check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Within tolerance.
    Pass,
    /// Outside tolerance, and not expected: the run fails.
    Fail,
    /// Outside tolerance, as expected for the stated reason.
    KnownDeviation,
    /// Declared a known deviation but now within tolerance: revisit the declaration.
    KnownDeviationPasses,
}

impl Status {
    /// Label for tables.
    pub fn label(self) -> &'static str {
        match self {
            Status::Pass => "pass",
            Status::Fail => "FAIL",
            Status::KnownDeviation => "known deviation",
            Status::KnownDeviationPasses => "known deviation now passes: revisit",
        }
    }

    /// Whether this status fails a run.
    pub fn fails(self) -> bool {
        self == Status::Fail
    }
}

/// Where a check's expected value comes from: what a pass means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// A number or claim stated in the paper's text.
    PaperText,
    /// A curve digitised from one of the paper's figures.
    DigitisedFigure,
    /// A separate implementation of the model (not the paper).
    IndependentSolver,
    /// A second method within the same run (e.g. exact orbits against the simulation).
    Internal,
    /// This project's own blessed results (regression).
    Baseline,
}

impl Source {
    /// The source named by a reference file's provenance.
    pub fn from_provenance(p: &str) -> Source {
        match p {
            "paper text" => Source::PaperText,
            "digitised figure" => Source::DigitisedFigure,
            _ => Source::IndependentSolver,
        }
    }

    /// Whether a check of this source compares with the paper itself.
    pub fn is_paper(self) -> bool {
        matches!(self, Source::PaperText | Source::DigitisedFigure)
    }

    /// In words, for tables.
    pub fn label(self) -> &'static str {
        match self {
            Source::PaperText => "paper text",
            Source::DigitisedFigure => "digitised figure",
            Source::IndependentSolver => "independent solver",
            Source::Internal => "second method",
            Source::Baseline => "baseline",
        }
    }
}

/// The outcome of one check, with every number a reader needs.
#[derive(Debug, Clone, Serialize)]
pub struct CheckOutcome {
    /// Short name, e.g. "omega_2".
    pub name: String,
    /// What was compared.
    pub description: String,
    /// The value computed, in `unit`.
    pub computed: f64,
    /// The reference value, in `unit`.
    pub expected: f64,
    /// Unit of both values.
    pub unit: String,
    /// `|computed - expected|`.
    pub abs_diff: f64,
    /// `|computed - expected| / |expected|`.
    pub rel_diff: f64,
    /// The tolerance in words.
    pub tolerance: String,
    /// Pass, fail or a known deviation.
    pub status: Status,
    /// Where the expected value comes from.
    pub provenance: String,
    /// The kind of reference.
    pub source: Source,
    /// The reason for a known deviation.
    pub reason: Option<String>,
    /// Extra detail (e.g. the worst point of a curve).
    pub detail: Option<String>,
    /// Whether the computed value rests only on settled steady states: `Some(false)` when it
    /// uses a point that did not settle (or is not period-1 where the reading compares two
    /// curves at one frequency), or when such a point, skipped, would change it; `None` when
    /// the check reads no steady state (modes, parameters, impulse histories).
    pub settled: Option<bool>,
    /// The id of the check in the experiment file (`{ID}` in its texts; the k-th further
    /// outcome of one check is `ID[k]`).
    pub id: Option<String>,
    /// Named values a text may quote besides `computed` and `expected` (`{ID.NAME}`), e.g.
    /// the frequency of a peak.
    pub values: Vec<(String, f64)>,
}

impl CheckOutcome {
    /// A failed check with nothing computed (a missing reference or baseline).
    pub fn unavailable(
        name: String,
        description: String,
        provenance: String,
        source: Source,
        detail: Option<String>,
    ) -> CheckOutcome {
        CheckOutcome {
            settled: None,
            id: None,
            values: Vec::new(),
            name,
            description,
            computed: f64::NAN,
            expected: f64::NAN,
            unit: String::new(),
            abs_diff: f64::NAN,
            rel_diff: f64::NAN,
            tolerance: String::new(),
            status: Status::Fail,
            provenance,
            source,
            reason: None,
            detail,
        }
    }

    /// A check whose reference is missing: a failure that says why.
    pub fn missing(spec: &CheckSpec, why: &str) -> CheckOutcome {
        CheckOutcome::unavailable(
            format!("{}#{}", spec.reference_file, spec.reference_id.clone().unwrap_or_default()),
            format!("reference missing: {why}"),
            spec.reference_file.clone(),
            Source::Internal,
            None,
        )
    }
}

/// Formats a tolerance for people.
pub fn describe_tolerance(t: Tolerance) -> String {
    match (t.rel > 0.0, t.abs > 0.0) {
        (true, true) => format!("{} + {:.3} %", fmt_num(t.abs), t.rel * 100.0),
        (true, false) => format!("{:.3} % relative", t.rel * 100.0),
        (false, true) => format!("{} absolute", fmt_num(t.abs)),
        (false, false) => "exact".to_string(),
    }
}

/// What a check compares: its name, meaning, unit and the reference's provenance.
#[derive(Debug, Clone)]
pub struct Subject {
    /// Short name, e.g. "omega_2".
    pub name: String,
    /// What is compared.
    pub description: String,
    /// Unit of the values.
    pub unit: String,
    /// Where the expected value comes from.
    pub provenance: String,
    /// The kind of reference.
    pub source: Source,
}

impl Subject {
    /// A subject from its parts.
    pub fn new(
        name: impl Into<String>,
        description: impl Into<String>,
        unit: impl Into<String>,
        provenance: impl Into<String>,
        source: Source,
    ) -> Subject {
        Subject {
            name: name.into(),
            description: description.into(),
            unit: unit.into(),
            provenance: provenance.into(),
            source,
        }
    }
}

/// Compares a scalar with a reference value.
pub fn compare_scalar(
    subject: Subject,
    computed: f64,
    expected: f64,
    tolerance: Tolerance,
    known_deviation: Option<&str>,
) -> CheckOutcome {
    let abs_diff = (computed - expected).abs();
    let rel_diff = if expected != 0.0 { abs_diff / expected.abs() } else { f64::INFINITY };
    let within = abs_diff <= tolerance.abs + tolerance.rel * expected.abs();
    CheckOutcome {
        settled: None,
        id: None,
        values: Vec::new(),
        name: subject.name,
        description: subject.description,
        computed,
        expected,
        unit: subject.unit,
        abs_diff,
        rel_diff,
        tolerance: describe_tolerance(tolerance),
        status: status(within, known_deviation.is_some()),
        provenance: subject.provenance,
        source: subject.source,
        reason: known_deviation.map(str::to_string),
        detail: None,
    }
}

/// The status from "within tolerance" and "declared a known deviation".
pub fn status(within: bool, known: bool) -> Status {
    match (within, known) {
        (true, false) => Status::Pass,
        (false, false) => Status::Fail,
        (false, true) => Status::KnownDeviation,
        (true, true) => Status::KnownDeviationPasses,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_statuses() {
        let tol = Tolerance { rel: 0.005, abs: 0.0 };
        let pass = compare_scalar(Subject::new("w", "", "rad/s", "", Source::PaperText), 81.91, 81.9, tol, None);
        assert_eq!(pass.status, Status::Pass);
        let fail = compare_scalar(Subject::new("w", "", "rad/s", "", Source::PaperText), 218.5, 243.9, tol, None);
        assert_eq!(fail.status, Status::Fail);
        assert!((fail.rel_diff - 25.4 / 243.9).abs() < 1e-12);
        let known =
            compare_scalar(Subject::new("w", "", "rad/s", "", Source::PaperText), 218.5, 243.9, tol, Some("measured"));
        assert_eq!(known.status, Status::KnownDeviation);
        let revisit =
            compare_scalar(Subject::new("w", "", "rad/s", "", Source::PaperText), 243.9, 243.9, tol, Some("measured"));
        assert_eq!(revisit.status, Status::KnownDeviationPasses);
    }
}
