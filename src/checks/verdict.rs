//! Per-figure verdicts in the spirit of ReScience replications: whether the checks against the
//! paper itself (its text, or curves digitised from its figures) pass.

use serde::Serialize;

use super::{CheckOutcome, Status};

/// How far a paper figure is reproduced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every check against the paper passes.
    Reproduced,
    /// Some checks against the paper pass, others differ for a stated reason.
    PartlyReproduced,
    /// A check against the paper fails, or none passes.
    NotReproduced,
    /// Nothing of the paper to compare with yet (only other references).
    NoReference,
}

impl Verdict {
    /// In words.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::PartlyReproduced => "partly reproduced",
            Verdict::NotReproduced => "not reproduced",
            Verdict::NoReference => "no reference yet",
        }
    }

    /// A CSS class.
    pub fn class(self) -> &'static str {
        match self {
            Verdict::Reproduced => "pass",
            Verdict::PartlyReproduced => "known",
            Verdict::NotReproduced => "fail",
            Verdict::NoReference => "none",
        }
    }
}

/// The verdict from the checks of a figure: only those against the paper count.
pub fn verdict<'a>(checks: impl IntoIterator<Item = &'a CheckOutcome>) -> Verdict {
    let (mut pass, mut known, mut fail) = (0, 0, 0);
    for c in checks.into_iter().filter(|c| c.source.is_paper()) {
        match c.status {
            Status::Pass | Status::KnownDeviationPasses => pass += 1,
            Status::KnownDeviation => known += 1,
            Status::Fail => fail += 1,
        }
    }
    match (pass, known, fail) {
        (0, 0, 0) => Verdict::NoReference,
        (_, _, f) if f > 0 => Verdict::NotReproduced,
        (0, _, _) => Verdict::NotReproduced,
        (_, 0, _) => Verdict::Reproduced,
        _ => Verdict::PartlyReproduced,
    }
}

/// The paper figure an experiment belongs to: its figure label up to a parenthesised
/// qualifier ("Fig. 5 (clearance)" belongs to "Fig. 5"; "Fig. 10(a)" stays itself).
pub fn figure_group(figure: &str) -> String {
    match figure.find(" (") {
        Some(i) => figure[..i].to_string(),
        None => figure.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::checks::{compare_scalar, Source, Subject};
    use crate::number::Tolerance;

    fn check(source: Source, computed: f64, known: bool) -> CheckOutcome {
        let tol = Tolerance { rel: 0.01, abs: 0.0 };
        let reason = known.then_some("stated reason");
        compare_scalar(Subject::new("x", "", "", "", source), computed, 1.0, tol, reason)
    }

    #[test]
    fn verdicts_follow_the_paper_checks_only() {
        let pass = check(Source::PaperText, 1.0, false);
        let off = check(Source::PaperText, 1.5, true);
        let fail = check(Source::PaperText, 1.5, false);
        let solver_fail = check(Source::IndependentSolver, 1.5, false);
        assert_eq!(verdict([&pass]), Verdict::Reproduced);
        assert_eq!(verdict([&pass, &off]), Verdict::PartlyReproduced);
        assert_eq!(verdict([&off]), Verdict::NotReproduced);
        assert_eq!(verdict([&pass, &fail]), Verdict::NotReproduced);
        assert_eq!(verdict([&solver_fail]), Verdict::NoReference);
        assert_eq!(figure_group("Fig. 5 (clearance)"), "Fig. 5");
        assert_eq!(figure_group("Fig. 10(a)"), "Fig. 10(a)");
    }
}
