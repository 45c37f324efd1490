//! Designs against a suite of recorded ground motions (docs/design.md, "Against
//! earthquakes"): a layout's objective is the structure's largest peak storey drift (or
//! absolute floor acceleration) under each record with the layout's beds, combined over the
//! suite (the largest, or the mean), over the bare structure's combined the same way.
//! Each response is exact between samples (`sim::record`) and deterministic, so an objective
//! has no interval. No I/O.

use rayon::prelude::*;

use super::{Combine, Evaluation, Layout, Motion, Problem, Scenario};
use crate::model::ground::{GroundMotion, Record};
use crate::sim::record::{respond, RecordOptions, RecordResponse, RecordStop};
use crate::sim::settle::statistic::ClassCounts;

/// What a design against records measures of each response.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Response {
    /// The largest peak inter-storey drift over the storeys, m.
    Drift,
    /// The largest peak absolute floor acceleration over the floors, m/s^2.
    Acceleration,
}

impl Response {
    /// The names a design file uses (`design.response`).
    pub const NAMES: &'static str = "\"drift\" (the largest peak storey drift, the default) or \"acceleration\" (the largest peak absolute floor acceleration)";

    /// The response named `name` in a design file.
    pub fn from_name(name: &str) -> Option<Response> {
        match name {
            "drift" => Some(Response::Drift),
            "acceleration" => Some(Response::Acceleration),
            _ => None,
        }
    }

    /// Its name in words, for tables and pages.
    pub fn words(self) -> &'static str {
        match self {
            Response::Drift => "largest peak storey drift",
            Response::Acceleration => "largest peak floor acceleration",
        }
    }

    /// Its unit.
    pub fn unit(self) -> &'static str {
        match self {
            Response::Drift => "m",
            Response::Acceleration => "m/s^2",
        }
    }

    /// This measure of `r` and the 0-based storey (or floor) where it is largest.
    pub fn of(self, r: &RecordResponse) -> (f64, usize) {
        let list = match self {
            Response::Drift => &r.peak_drift,
            Response::Acceleration => &r.peak_accel,
        };
        list.iter()
            .enumerate()
            .fold((f64::NAN, 0), |(best, at), (i, &v)| if best.is_nan() || v > best { (v, i) } else { (best, at) })
    }
}

/// How a suite's peaks combine into one number (the bare building's the same way, and the
/// objective is the ratio of the two).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Over {
    /// The largest over the records (the envelope a design is checked against).
    Largest,
    /// The mean over the records (as building codes take a suite of seven records or more).
    Mean,
}

impl Over {
    /// The names a design file uses (`design.over_records`).
    pub const NAMES: &'static str =
        "\"largest\" (the default: the largest peak over the records) or \"mean\" (the mean of the records' peaks)";

    /// The way named `name` in a design file.
    pub fn from_name(name: &str) -> Option<Over> {
        match name {
            "largest" => Some(Over::Largest),
            "mean" => Some(Over::Mean),
            _ => None,
        }
    }

    /// In words, for tables and pages.
    pub fn words(self) -> &'static str {
        match self {
            Over::Largest => "the largest over the records",
            Over::Mean => "the mean over the records",
        }
    }

    /// The records' `values` combined (NaN where one is).
    pub fn of(self, values: &[f64]) -> f64 {
        if values.iter().any(|v| v.is_nan()) || values.is_empty() {
            return f64::NAN;
        }
        match self {
            Over::Largest => values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Over::Mean => values.iter().sum::<f64>() / values.len() as f64,
        }
    }
}

/// A design's records and what it measures under them (`[design] ground_motions`).
#[derive(Debug, Clone, PartialEq)]
pub struct Suite {
    /// The records, in the file's order.
    pub records: Vec<Record>,
    /// What each response is measured by.
    pub response: Response,
    /// How the records' peaks combine: the largest, or the mean.
    pub over: Over,
    /// The storeys' heights, m, for drift ratios on the page (not part of the objective).
    pub storey_heights_m: Option<Vec<f64>>,
}

impl Problem {
    /// A design problem against `suite` on `structure` (its supports driven by the records),
    /// every container moving along `direction`: no bands, sweeps or scenarios.
    pub fn against_records(
        structure: crate::model::Structure,
        direction: crate::model::Direction,
        suite: Suite,
    ) -> Problem {
        Problem {
            structure,
            driven: 0,
            force: 1.0,
            bands: Vec::new(),
            measure: super::Measure::Peak,
            sweeps: Vec::new(),
            steady: crate::sim::SteadyOptions::default(),
            scenarios: Vec::new(),
            combine: Combine::Worst,
            direction,
            supports: true,
            suite: Some(suite),
        }
    }
}

/// What a design run keeps of each response: no histories (the measures are over every sample
/// whatever this is).
const OPTIONS: RecordOptions = RecordOptions { max_events: 2_000_000, max_history: 2 };

/// The response of scenario `sc` with `layout`'s beds to `record` (`None`: no dampers).
pub fn response(
    problem: &Problem,
    sc: &Scenario,
    layout: Option<&Layout>,
    record: &GroundMotion,
) -> Option<RecordResponse> {
    let dampers = layout.map_or_else(Vec::new, |l| l.dampers(problem.direction));
    respond(&problem.system(sc, dampers), record, OPTIONS).ok()
}

/// The measure of every record for the bare structure, per scenario.
pub fn bare(problem: &Problem, suite: &Suite) -> Vec<Vec<f64>> {
    problem
        .cases()
        .iter()
        .map(|sc| {
            suite
                .records
                .par_iter()
                .map(|r| response(problem, sc, None, &r.motion).map_or(f64::NAN, |resp| suite.response.of(&resp).0))
                .collect()
        })
        .collect()
}

/// One scenario's records with a layout.
struct Run {
    /// Per record: the measure, m or m/s^2 (NaN: the record could not be run).
    values: Vec<f64>,
    /// Per record: the storey (floor) of the largest.
    at: Vec<usize>,
    /// Per record: how the beds moved.
    motion: Vec<Motion>,
    /// Records whose run stopped before its end (more events than allowed) or failed.
    stopped: usize,
    /// The records' peaks combined over the bare building's combined the same way.
    relative: f64,
    /// The record with the largest peak.
    worst: usize,
}

fn scenario(problem: &Problem, suite: &Suite, sc: &Scenario, bare: &[f64], layout: &Layout) -> Run {
    let runs: Vec<Option<RecordResponse>> =
        suite.records.par_iter().map(|r| response(problem, sc, Some(layout), &r.motion)).collect();
    let mut run = Run { values: Vec::new(), at: Vec::new(), motion: Vec::new(), stopped: 0, relative: 0.0, worst: 0 };
    for resp in &runs {
        let (v, at) = resp.as_ref().map_or((f64::NAN, 0), |r| suite.response.of(r));
        run.values.push(v);
        run.at.push(at);
        run.stopped += usize::from(resp.as_ref().is_none_or(|r| r.stop != RecordStop::Completed));
        run.motion.push(Motion {
            lifting: usize::from(resp.as_ref().is_some_and(|r| r.events > 0)),
            points: 1,
            flight_m: 0.0,
        });
    }
    let v = &run.values;
    run.worst = v.iter().enumerate().fold(0, |w, (i, x)| if *x > v[w] || x.is_nan() { i } else { w });
    run.relative = suite.over.of(&run.values) / suite.over.of(bare);
    run
}

/// Evaluates one layout against the suite (`bare`: per scenario, each record's measure
/// without dampers, from [`bare`]). The evaluation's `bands` are the records; `worst` gives
/// the record with the largest peak and its storey (frequency 0); its interval is 0 (exact
/// responses).
pub fn evaluate(problem: &Problem, suite: &Suite, bare: &[Vec<f64>], layout: &Layout) -> Evaluation {
    let runs: Vec<Run> =
        problem.cases().iter().zip(bare).map(|(sc, b)| scenario(problem, suite, sc, b, layout)).collect();
    let objectives: Vec<f64> = runs.iter().map(|r| r.relative).collect();
    let worst_scenario =
        objectives.iter().enumerate().fold(0, |w, (i, o)| if *o > objectives[w] || o.is_nan() { i } else { w });
    let objective = match problem.combine {
        Combine::Worst => objectives[worst_scenario],
        Combine::Mean => objectives.iter().sum::<f64>() / objectives.len() as f64,
    };
    let w = &runs[worst_scenario];
    let records = suite.records.len();
    Evaluation {
        bands: w.values.clone(),
        bare: bare[worst_scenario].clone(),
        objective,
        scenarios: objectives,
        worst_scenario,
        worst: (w.worst, 0.0, w.at.get(w.worst).copied().unwrap_or(0)),
        curves: Vec::new(),
        unsettled: runs.iter().map(|r| r.stopped).sum(),
        points: records * runs.len(),
        motion: w.motion.clone(),
        half_width: 0.0,
        bands_half_width: vec![0.0; records],
        classes: ClassCounts::default(),
        measured: 0,
        screened: 0,
        points_class: Vec::new(),
    }
}
