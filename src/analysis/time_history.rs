//! Time histories (`kind = "time_history"`): every case under every recorded ground motion,
//! exact between samples (`sim::record`), with each storey's peak drift, floor acceleration
//! and displacement, their RMS values, the energies and the beds' impacts, per record and
//! over the suite (mean and worst), and the shot's effect against the bare case.

use rayon::prelude::*;

use crate::checks::fmt_num;
use crate::checks::reference::ReferenceStore;
use crate::experiment::ground::Record;
use crate::experiment::Experiment;
use crate::model::GRAVITY;
use crate::sim::record::{respond, RecordOptions, RecordResponse, RecordStop};
use crate::table::Table;

use super::curves;
use super::kind::{Input, Kind, Output};
use super::time_history_figures as figures;
use super::time_history_runs::{find, over_suite, Run};

/// A time history: the records and, for drift ratios, the storeys' heights.
pub(crate) struct TimeHistory<'a> {
    pub(crate) records: &'a [Record],
    pub(crate) storey_heights_m: Option<&'a [f64]>,
}

impl Kind for TimeHistory<'_> {
    fn work(&self, exp: &Experiment, _refs: &ReferenceStore) -> u64 {
        (self.records.len() * exp.cases.len()) as u64
    }

    fn run(&self, i: &Input<'_>) -> Output {
        page(i.exp, self.records, self.storey_heights_m, i.tick)
    }
}

/// Every case of `exp` under every record: the tables, the figures of its plots, the answer
/// against its bare case (also the page of a design against records, on its layouts).
pub(crate) fn page(exp: &Experiment, records: &[Record], heights: Option<&[f64]>, tick: &(dyn Fn() + Sync)) -> Output {
    let pairs: Vec<(usize, usize)> =
        (0..records.len()).flat_map(|r| (0..exp.cases.len()).map(move |c| (r, c))).collect();
    // Each run is independent and deterministic: the same numbers for any thread count.
    let results: Vec<_> = pairs
        .par_iter()
        .map(|&(r, c)| {
            let sys = curves::system(exp, &exp.cases[c]);
            let out = respond(&sys, &records[r].motion, RecordOptions::default());
            tick();
            (r, c, out)
        })
        .collect();
    let mut runs = Vec::new();
    let mut skipped = Vec::new();
    let mut warnings = Vec::new();
    for (r, c, out) in results {
        let (record, case) = (&records[r], &exp.cases[c]);
        match out {
            Ok(response) => {
                if let RecordStop::Events { t_s } = response.stop {
                    warnings.push(format!(
                        "case {} under {}: stopped at {} s of {} s after {} events (a bed chattering without end): its peaks, RMS values and energies are over the time run only",
                        case.id,
                        record.name,
                        fmt_num(t_s),
                        fmt_num(record.motion.duration_s()),
                        response.events
                    ));
                }
                runs.push(Run { record, case: c, response });
            }
            Err(e) => skipped.push(format!("case {} cannot be run under {}: {e}", case.id, record.name)),
        }
    }
    let bare = exp.cases.iter().position(|c| c.beds.is_empty());
    let chain = exp.structure.is_chain();
    let mut out = Output {
        tables: vec![
            peaks_table(exp, &runs, bare, chain, heights),
            energy_table(exp, &runs),
            beds_table(exp, &runs),
            suite_table(exp, records, &runs, bare, chain),
        ],
        figures: figures::figures(exp, records, &runs, chain, heights),
        warnings,
        answer: answer(exp, records, &runs, bare, chain),
        ..Output::default()
    };
    out.missing_cases(exp, skipped);
    out
}

/// What each row of a storey table counts: storeys for a chain, coordinates otherwise.
fn row_name(chain: bool) -> &'static str {
    if chain {
        "storey"
    } else {
        "coordinate"
    }
}

/// The peaks and RMS values per record, case and storey, with the shot's effect against
/// the bare case.
fn peaks_table(exp: &Experiment, runs: &[Run], bare: Option<usize>, chain: bool, heights: Option<&[f64]>) -> Table {
    let n = exp.structure.physical();
    let rows: Vec<(&Run, usize)> = runs.iter().flat_map(|r| (0..n).map(move |i| (r, i))).collect();
    let col =
        |f: &dyn Fn(&RecordResponse, usize) -> f64| rows.iter().map(|(r, i)| f(&r.response, *i)).collect::<Vec<f64>>();
    let vs_bare = |f: &dyn Fn(&RecordResponse, usize) -> f64| {
        rows.iter()
            .map(|(r, i)| {
                let b = bare.and_then(|b| find(runs, r.record, b));
                b.map_or(f64::NAN, |b| f(&r.response, *i) / f(b, *i))
            })
            .collect::<Vec<f64>>()
    };
    let mut t = Table::new(
        "time_history_peaks",
        "Per record, case and storey (coordinate): the largest storey drift, floor (absolute) acceleration and displacement relative to the ground over the record, found exactly between samples, their RMS values, and each peak over the bare case's under the same record.",
    )
    .str("record", rows.iter().map(|(r, _)| r.record.key.clone()).collect())
    .str("case", rows.iter().map(|(r, _)| exp.cases[r.case].id.clone()).collect())
    .i64(row_name(chain), rows.iter().map(|(_, i)| *i as i64 + 1).collect());
    if chain {
        t = t.f64("peak_drift_m", col(&|r, i| r.peak_drift[i]));
        if let Some(h) = heights {
            t = t.f64("peak_drift_ratio", col(&|r, i| r.peak_drift[i] / h[i]));
        }
        t = t.f64("drift_vs_bare", vs_bare(&|r, i| r.peak_drift[i])).f64("rms_drift_m", col(&|r, i| r.rms_drift[i]));
    }
    t.f64("peak_accel_m_s2", col(&|r, i| r.peak_accel[i]))
        .f64("peak_accel_g", col(&|r, i| r.peak_accel[i] / GRAVITY))
        .f64("accel_vs_bare", vs_bare(&|r, i| r.peak_accel[i]))
        .f64("rms_accel_m_s2", col(&|r, i| r.rms_accel[i]))
        .f64("peak_displacement_m", col(&|r, i| r.peak_displacement[i]))
        .f64("rms_displacement_m", col(&|r, i| r.rms_displacement[i]))
}

/// The energies and events per record and case.
fn energy_table(exp: &Experiment, runs: &[Run]) -> Table {
    let col = |f: &dyn Fn(&RecordResponse) -> f64| runs.iter().map(|r| f(&r.response)).collect::<Vec<f64>>();
    Table::new(
        "time_history_energy",
        "Per record and case: the energy the ground put in (relative to the ground), what the structure's damping and the impacts took out, what is stored at the end, what the balance leaves over (rounding and quadrature), the events, and whether the whole record was run.",
    )
    .str("record", runs.iter().map(|r| r.record.key.clone()).collect())
    .str("case", runs.iter().map(|r| exp.cases[r.case].id.clone()).collect())
    .f64("energy_input_j", col(&|r| r.energy_input))
    .f64("energy_viscous_j", col(&|r| r.energy_viscous))
    .f64("energy_impacts_j", col(&|r| r.energy_impacts))
    .f64("energy_stored_j", col(&|r| r.energy_stored))
    .f64("balance_j", col(&|r| r.balance()))
    .i64("impacts", runs.iter().map(|r| r.response.beds.iter().map(|b| b.impacts as i64).sum()).collect())
    .i64("lift_offs", runs.iter().map(|r| r.response.beds.iter().map(|b| b.lift_offs as i64).sum()).collect())
    .f64("time_run_s", col(&|r| r.t.last().copied().unwrap_or(0.0)))
    .str(
        "run",
        runs.iter()
            .map(|r| match r.response.stop {
                RecordStop::Completed => "whole record".to_string(),
                RecordStop::Events { t_s } => format!("stopped at {} s: too many events", fmt_num(t_s)),
            })
            .collect(),
    )
}

/// Each bed's impacts per record and case.
fn beds_table(exp: &Experiment, runs: &[Run]) -> Table {
    let rows: Vec<(&Run, usize)> = runs.iter().flat_map(|r| (0..r.response.beds.len()).map(move |j| (r, j))).collect();
    let bed = |r: &Run, j: usize| r.response.beds[j];
    Table::new(
        "time_history_beds",
        "Per record, case and bed: its host (1-based), impacts, lift-offs, the energy its impacts took out and its fastest impact relative to the host.",
    )
    .str("record", rows.iter().map(|(r, _)| r.record.key.clone()).collect())
    .str("case", rows.iter().map(|(r, _)| exp.cases[r.case].id.clone()).collect())
    .i64("bed", rows.iter().map(|(_, j)| *j as i64 + 1).collect())
    .i64("host", rows.iter().map(|(r, j)| exp.cases[r.case].beds[*j].damper.host as i64 + 1).collect())
    .i64("impacts", rows.iter().map(|(r, j)| bed(r, *j).impacts as i64).collect())
    .i64("lift_offs", rows.iter().map(|(r, j)| bed(r, *j).lift_offs as i64).collect())
    .f64("energy_lost_j", rows.iter().map(|(r, j)| bed(r, *j).energy_lost).collect())
    .f64("peak_impact_speed_m_s", rows.iter().map(|(r, j)| bed(r, *j).peak_impact_speed).collect())
}

/// Per case and storey: the mean and the worst over the records of each peak, and the mean
/// over the bare case's mean.
fn suite_table(exp: &Experiment, records: &[Record], runs: &[Run], bare: Option<usize>, chain: bool) -> Table {
    let n = exp.structure.physical();
    let rows: Vec<(usize, usize)> = (0..exp.cases.len()).flat_map(|c| (0..n).map(move |i| (c, i))).collect();
    let stat = |f: &dyn Fn(&RecordResponse, usize) -> f64, worst: bool| {
        rows.iter()
            .map(|&(c, i)| {
                over_suite(records, runs, c, |r| f(r, i)).map_or(f64::NAN, |(m, w)| if worst { w } else { m })
            })
            .collect::<Vec<f64>>()
    };
    let vs_bare = |f: &dyn Fn(&RecordResponse, usize) -> f64| {
        rows.iter()
            .map(|&(c, i)| {
                let mean = |c| over_suite(records, runs, c, |r| f(r, i)).map(|s| s.0);
                match (mean(c), bare.and_then(mean)) {
                    (Some(a), Some(b)) => a / b,
                    _ => f64::NAN,
                }
            })
            .collect::<Vec<f64>>()
    };
    let mut t = Table::new(
        "time_history_suite",
        "Per case and storey (coordinate), over the suite of records: the mean and the worst of each peak, and the mean over the bare case's mean (NaN where a record could not be run).",
    )
    .str("case", rows.iter().map(|(c, _)| exp.cases[*c].id.clone()).collect())
    .i64(row_name(chain), rows.iter().map(|(_, i)| *i as i64 + 1).collect());
    if chain {
        t = t
            .f64("mean_peak_drift_m", stat(&|r, i| r.peak_drift[i], false))
            .f64("worst_peak_drift_m", stat(&|r, i| r.peak_drift[i], true))
            .f64("mean_drift_vs_bare", vs_bare(&|r, i| r.peak_drift[i]));
    }
    t.f64("mean_peak_accel_m_s2", stat(&|r, i| r.peak_accel[i], false))
        .f64("worst_peak_accel_m_s2", stat(&|r, i| r.peak_accel[i], true))
        .f64("mean_accel_vs_bare", vs_bare(&|r, i| r.peak_accel[i]))
}

/// The largest of a list.
fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, b| a.max(*b))
}

/// The answer in words: per case with shot, the largest storey drift and floor acceleration
/// over the building, mean over the suite, against the bare case's.
fn answer(exp: &Experiment, records: &[Record], runs: &[Run], bare: Option<usize>, chain: bool) -> Option<String> {
    let b = bare?;
    let quantity = |r: &RecordResponse| if chain { largest(&r.peak_drift) } else { largest(&r.peak_displacement) };
    let (bq, bq_worst) = over_suite(records, runs, b, quantity)?;
    let (ba, _) = over_suite(records, runs, b, |r| largest(&r.peak_accel))?;
    let what = if chain { "largest storey drift" } else { "largest displacement relative to the ground" };
    let mut parts = vec![format!(
        "Bare, the {what} is {} mm and the largest floor acceleration {} g, mean over {} record{} (worst {} mm).",
        crate::number::fmt_sig(1e3 * bq, 3),
        crate::number::fmt_sig(ba / GRAVITY, 3),
        records.len(),
        if records.len() == 1 { "" } else { "s" },
        crate::number::fmt_sig(1e3 * bq_worst, 3)
    )];
    for (c, case) in exp.cases.iter().enumerate().filter(|(c, _)| *c != b) {
        let (Some((q, _)), Some((a, _))) =
            (over_suite(records, runs, c, quantity), over_suite(records, runs, c, |r| largest(&r.peak_accel)))
        else {
            parts.push(format!("{}: not run under every record.", case.label));
            continue;
        };
        let shot: f64 = case.beds.iter().map(|b| b.damper.mass).sum();
        let share = exp.structure_mass().map_or(String::new(), |m| {
            format!(", {} % of the structure's mass", crate::number::fmt_sig(100.0 * shot / m, 2))
        });
        parts.push(format!(
            "{} ({} kg of shot{share}): {} mm ({} of bare) and {} g ({} of bare).",
            case.label,
            crate::number::fmt_sig(shot, 3),
            crate::number::fmt_sig(1e3 * q, 3),
            crate::number::fmt_sig(q / bq, 3),
            crate::number::fmt_sig(a / GRAVITY, 3),
            crate::number::fmt_sig(a / ba, 3)
        ));
    }
    Some(parts.join(" "))
}
