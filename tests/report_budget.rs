//! The report's weight page by page (docs/reviewing.md, "Mailing the report"): run by `.ci/run`
//! after `shotdamp report` (`cargo test --release --locked --test all -- --ignored
//! report_budget::`), on the folder it wrote; every page with its figures within
//! `PAGE_BUDGET`, every data folder within `DATA_BUDGET`, each one over named with its
//! largest file; the whole within `REPORT_BUDGET` (15 MB), its heaviest folders named.

use shotdamp::output::weight;

#[test]
#[ignore]
fn every_page_of_the_report_is_within_its_budget() {
    let report = std::env::var_os("SHOTDAMP_REPORT").map_or_else(|| crate::common::repo().join("reports"), Into::into);
    assert!(report.join("index.html").is_file(), "no report at {}: run `shotdamp report` first", report.display());
    let pages = weight::pages(&report).unwrap();
    assert!(pages.len() > 50, "{} folders weighed", pages.len());
    let over: Vec<String> = pages.iter().filter_map(weight::Weight::over).collect();
    assert!(over.is_empty(), "over budget:\n{}", over.join("\n"));
    let (bytes, whole) = weight::total(&report).unwrap();
    assert!(whole.is_none(), "{}", whole.unwrap_or_default());
    println!("the report: {bytes} bytes (budget {})", weight::REPORT_BUDGET);
}
