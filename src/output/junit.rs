//! Checks as JUnit XML, which CI systems display: one test suite per experiment, one test
//! case per check; a failed check is a failure, a known deviation a skipped test with its
//! reason.

use crate::analysis::ExperimentResult;
use crate::checks::{fmt_num, Status};

/// Escapes text for XML attributes and content.
fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// The JUnit XML of every check.
pub fn render(results: &[ExperimentResult]) -> String {
    let total: usize = results.iter().map(|r| r.checks.len()).sum();
    let count = |s: Status| results.iter().flat_map(|r| &r.checks).filter(|c| c.status == s).count();
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    x += &format!(
        "<testsuites name=\"shotdamp\" tests=\"{total}\" failures=\"{}\" skipped=\"{}\">\n",
        count(Status::Fail),
        count(Status::KnownDeviation)
    );
    for r in results {
        let id = &r.experiment.key();
        let n = |s: Status| r.checks.iter().filter(|c| c.status == s).count();
        x += &format!(
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" skipped=\"{}\">\n",
            esc(id),
            r.checks.len(),
            n(Status::Fail),
            n(Status::KnownDeviation)
        );
        for c in &r.checks {
            x += &format!("    <testcase classname=\"{}\" name=\"{}\">", esc(id), esc(&c.name));
            let numbers = format!(
                "computed {} {}, expected {} {}, tolerance {}; {}: {}{}",
                fmt_num(c.computed),
                c.unit,
                fmt_num(c.expected),
                c.unit,
                c.tolerance,
                c.source.label(),
                c.provenance,
                c.detail.as_ref().map(|d| format!("; {d}")).unwrap_or_default()
            );
            match c.status {
                Status::Fail => {
                    x += &format!("\n      <failure message=\"{}\">{}</failure>\n    ", esc(&c.description), esc(&numbers))
                }
                Status::KnownDeviation => {
                    let why = c.reason.clone().unwrap_or_default();
                    x += &format!("\n      <skipped message=\"known deviation: {}\"/>\n    ", esc(&why))
                }
                Status::KnownDeviationPasses => {
                    x += &format!(
                        "\n      <system-out>declared a known deviation but now within tolerance: revisit; {}</system-out>\n    ",
                        esc(&numbers)
                    )
                }
                Status::Pass => {}
            }
            x += "</testcase>\n";
        }
        x += "  </testsuite>\n";
    }
    x += "</testsuites>\n";
    x
}
