//! The figures of a time history: per record, the ground's acceleration and the plotted
//! masses' displacement and acceleration against time for every case
//! (`plots.kind = "ground_histories"`); per record and over the suite, each storey's peak
//! drift and floor acceleration against the storey (`"storey_profiles"`). The page shows the
//! suite first, then each record's figures together.

use crate::experiment::ground::Record;
use crate::experiment::{Experiment, PlotKind, PlotSpec};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series};
use crate::model::GRAVITY;
use crate::sim::record::RecordResponse;

use super::time_history_runs::{over_suite, Run};

/// Horizontal resolution of the histories (min/max per bin): a bin of 0.07-0.18 s on the
/// shipped records, fine against the building's periods, and a page inside its budget.
const BINS: usize = 300;

/// Every figure the experiment's plots ask for: the suite's summary first (the storey profiles
/// over every record), then each record's figures together (its histories, its profiles).
pub(super) fn figures(
    exp: &Experiment,
    records: &[Record],
    runs: &[Run],
    chain: bool,
    heights: Option<&[f64]>,
) -> Vec<Figure> {
    let plots: Vec<(&PlotSpec, String, Vec<usize>)> = exp
        .plots
        .iter()
        .map(|p| {
            let title = p.title.clone().unwrap_or_else(|| format!("{}: {}", exp.meta.figure, exp.meta.title));
            let shown: Vec<usize> = (0..exp.cases.len()).filter(|&c| p.cases.contains(&exp.cases[c].id)).collect();
            (p, title, shown)
        })
        .collect();
    let mut out = Vec::new();
    for (p, title, shown) in &plots {
        if p.kind == PlotKind::StoreyProfiles && records.len() > 1 {
            out.push(suite_profiles(exp, p, title, records, runs, shown, chain, heights));
        }
    }
    for rec in records {
        for (p, title, shown) in &plots {
            match p.kind {
                PlotKind::GroundHistories => out.push(histories(exp, p, title, rec, runs, shown)),
                PlotKind::StoreyProfiles => out.push(record_profiles(exp, p, title, rec, runs, shown, chain, heights)),
                _ => {}
            }
        }
    }
    out
}

fn run_of<'a>(runs: &'a [Run], rec: &Record, c: usize) -> Option<&'a RecordResponse> {
    runs.iter().find(|r| r.record.key == rec.key && r.case == c).map(|r| &r.response)
}

/// The ground and each plotted mass against time under one record.
fn histories(exp: &Experiment, p: &PlotSpec, title: &str, rec: &Record, runs: &[Run], shown: &[usize]) -> Figure {
    let m = &rec.motion;
    let span = p.x_range.unwrap_or((0.0, m.duration_s()));
    let times: Vec<f64> = (0..m.accel_m_s2.len()).map(|k| k as f64 * m.dt_s).collect();
    let g: Vec<f64> = m.accel_m_s2.iter().map(|a| a / GRAVITY).collect();
    let mut ground = Panel::new(format!("ground: {} ({})", rec.name, rec.scaling), "time (s)", "a_g (g)", span);
    ground.series.push(Series::dense("ground", &times, &g, 7, BINS));
    let mut panels = vec![ground];
    let masses: Vec<usize> = if p.masses.is_empty() { vec![exp.structure.physical() - 1] } else { p.masses.clone() };
    for &k in &masses {
        let mut disp =
            Panel::new(format!("m{}: displacement relative to the ground", k + 1), "time (s)", "u (mm)", span);
        let mut acc = Panel::new(format!("m{}: absolute acceleration", k + 1), "time (s)", "a (g)", span);
        for &c in shown {
            let Some(r) = run_of(runs, rec, c) else { continue };
            let label = exp.cases[c].label.clone();
            let u: Vec<f64> = r.u.iter().map(|u| 1e3 * u[k]).collect();
            let a: Vec<f64> = r.accel.iter().map(|a| a[k] / GRAVITY).collect();
            disp.series.push(Series::dense(label.clone(), &r.t, &u, c, BINS));
            acc.series.push(Series::dense(label, &r.t, &a, c, BINS));
        }
        panels.push(disp);
        panels.push(acc);
    }
    Figure {
        id: format!("{}_{}", p.id, rec.key),
        title: format!("{title}: {}", rec.name),
        caption: format!(
            "Under {} ({}, {} s at {} s): the ground's acceleration, then each plotted mass's displacement relative to the ground and its absolute acceleration for every case, at the record's samples (the peaks in the tables are found exactly between them).",
            rec.name,
            rec.scaling,
            crate::checks::fmt_num(m.duration_s()),
            crate::checks::fmt_num(m.dt_s)
        ),
        panels,
    }
}

/// A profile panel: a value against the storey, one line per series.
fn profile_panel(title: &str, x_label: &str, lines: Vec<Series>, row: &str) -> Panel {
    let top = lines.iter().flat_map(|s| s.x.iter()).fold(0.0f64, |a, b| a.max(*b));
    let storeys = lines.iter().map(|s| s.y.len()).max().unwrap_or(1) as f64;
    let mut panel = Panel::new(title, x_label, row, (0.0, if top > 0.0 { 1.1 * top } else { 1.0 }));
    // Half a storey beyond the first and the last: the ticks fall on the storeys.
    panel.y_range = Some((0.5, storeys + 0.5));
    panel.legend = Corner::UpperRight;
    panel.series = lines;
    panel
}

/// The two profile panels, `under` a record or "over the suite": peak drift (a chain's; else
/// displacement) and peak floor acceleration against the storey (coordinate).
fn profile_panels(
    chain: bool,
    heights: Option<&[f64]>,
    under: &str,
    (first, second): (Vec<Series>, Vec<Series>),
) -> Vec<Panel> {
    let row = if chain { "storey" } else { "coordinate" };
    let first_label = if chain { drift_label(heights) } else { "peak displacement relative to the ground (mm)" };
    vec![
        profile_panel(&format!("{first_label} {under}"), first_label, first, row),
        profile_panel(&format!("peak floor acceleration {under}"), "peak acceleration (g)", second, row),
    ]
}

/// A line through the storeys with a marker at each.
fn through(label: String, values: Vec<f64>, color: usize, dash: Dash) -> Series {
    let storeys: Vec<f64> = (1..=values.len()).map(|i| i as f64).collect();
    let mut s = Series::line(label, values, storeys, color).dashed(dash);
    s.marker = Marker::Circle;
    s
}

/// The drift of storey `i` as the profile shows it: in mm, or as a ratio of the storey's
/// height in %.
fn drift_shown(d: f64, i: usize, heights: Option<&[f64]>) -> f64 {
    heights.map_or(1e3 * d, |h| 100.0 * d / h[i])
}

fn drift_label(heights: Option<&[f64]>) -> &'static str {
    if heights.is_some() {
        "peak drift / storey height (%)"
    } else {
        "peak drift (mm)"
    }
}

/// Each storey's peaks under one record.
#[allow(clippy::too_many_arguments)]
fn record_profiles(
    exp: &Experiment,
    p: &PlotSpec,
    title: &str,
    rec: &Record,
    runs: &[Run],
    shown: &[usize],
    chain: bool,
    heights: Option<&[f64]>,
) -> Figure {
    let row = if chain { "storey" } else { "coordinate" };
    let mut first = Vec::new();
    let mut second = Vec::new();
    for &c in shown {
        let Some(r) = run_of(runs, rec, c) else { continue };
        let label = exp.cases[c].label.clone();
        let d: Vec<f64> = if chain {
            r.peak_drift.iter().enumerate().map(|(i, d)| drift_shown(*d, i, heights)).collect()
        } else {
            r.peak_displacement.iter().map(|d| 1e3 * d).collect()
        };
        first.push(through(label.clone(), d, c, Dash::Solid));
        second.push(through(label, r.peak_accel.iter().map(|a| a / GRAVITY).collect(), c, Dash::Solid));
    }
    Figure {
        id: format!("{}_{}", p.id, rec.key),
        title: format!("{title}: {}", rec.name),
        caption: format!(
            "Under {} ({}): each {row}'s largest {} and floor (absolute) acceleration over the record, found exactly between samples, for every case.",
            rec.name,
            rec.scaling,
            if chain { "drift" } else { "displacement relative to the ground" }
        ),
        panels: profile_panels(chain, heights, &format!("under {}", rec.name), (first, second)),
    }
}

/// Each storey's peaks over the suite: the mean over the records (solid) and the worst
/// (dashed).
#[allow(clippy::too_many_arguments)]
fn suite_profiles(
    exp: &Experiment,
    p: &PlotSpec,
    title: &str,
    records: &[Record],
    runs: &[Run],
    shown: &[usize],
    chain: bool,
    heights: Option<&[f64]>,
) -> Figure {
    let n = exp.structure.physical();
    let row = if chain { "storey" } else { "coordinate" };
    let mut first = Vec::new();
    let mut second = Vec::new();
    for &c in shown {
        let label = &exp.cases[c].label;
        let stat = |f: &dyn Fn(&RecordResponse, usize) -> f64, worst: bool| -> Option<Vec<f64>> {
            (0..n).map(|i| over_suite(records, runs, c, |r| f(r, i)).map(|(m, w)| if worst { w } else { m })).collect()
        };
        let drift = |r: &RecordResponse, i: usize| {
            if chain {
                drift_shown(r.peak_drift[i], i, heights)
            } else {
                1e3 * r.peak_displacement[i]
            }
        };
        let accel = |r: &RecordResponse, i: usize| r.peak_accel[i] / GRAVITY;
        if let (Some(dm), Some(dw), Some(am), Some(aw)) =
            (stat(&drift, false), stat(&drift, true), stat(&accel, false), stat(&accel, true))
        {
            first.push(through(format!("{label}: mean"), dm, c, Dash::Solid));
            first.push(through(format!("{label}: worst"), dw, c, Dash::Dashed));
            second.push(through(format!("{label}: mean"), am, c, Dash::Solid));
            second.push(through(format!("{label}: worst"), aw, c, Dash::Dashed));
        }
    }
    Figure {
        id: format!("{}_suite", p.id),
        title: format!("{title}: over the {} records", records.len()),
        caption: format!(
            "Over the suite of {} records ({}): each {row}'s peak {} and floor acceleration, the mean over the records (solid) and the worst (dashed), for every case.",
            records.len(),
            records.iter().map(|r| r.name.as_str()).collect::<Vec<_>>().join("; "),
            if chain { "drift" } else { "displacement" }
        ),
        panels: profile_panels(chain, heights, "over the suite", (first, second)),
    }
}
