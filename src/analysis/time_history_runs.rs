//! A time history's runs (each case under each record) and what is read across them: one
//! case's run under a record, and a quantity's mean and worst over the suite. Shared by the
//! tables ([`super::time_history`]) and the figures ([`super::time_history_figures`]).

use crate::experiment::ground::Record;
use crate::sim::record::RecordResponse;

/// One case's response to one record.
pub(crate) struct Run<'a> {
    pub record: &'a Record,
    pub case: usize,
    pub response: RecordResponse,
}

/// The run of case `c` under `record`.
pub(crate) fn find<'a>(runs: &'a [Run], record: &Record, c: usize) -> Option<&'a RecordResponse> {
    runs.iter().find(|r| r.record.key == record.key && r.case == c).map(|r| &r.response)
}

/// Mean and worst of a quantity over the records a case was run under.
pub(crate) fn over_suite(
    records: &[Record],
    runs: &[Run],
    c: usize,
    f: impl Fn(&RecordResponse) -> f64,
) -> Option<(f64, f64)> {
    let values: Vec<f64> = records.iter().filter_map(|rec| find(runs, rec, c)).map(f).collect();
    (values.len() == records.len() && !values.is_empty())
        .then(|| (values.iter().sum::<f64>() / values.len() as f64, values.iter().fold(f64::MIN, |a, b| a.max(*b))))
}
