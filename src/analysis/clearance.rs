//! Clearance studies: for each case, the highest flight of its beds without a top (the
//! clearance beyond which no bed reaches the top, so the damper behaves as d = inf), then the
//! peak compliance of a mass against clearance, and the clearance that minimises it.

use std::collections::BTreeMap;

use crate::checks::fmt_num;
use crate::checks::reference::ReferenceStore;
use crate::experiment::{Case, CurveId, Experiment, PlotKind};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series, VLine};
use crate::model::Clearance;
use crate::sim::settle::sweep;
use crate::sim::SteadyOptions;
use crate::table::Table;

use super::curves::{self, Curve};
use super::kind::{Input, Kind, Output};
use super::result::Tick;
use super::sweep::check_frequencies;

/// The settings of a study.
pub struct Study<'a> {
    pub freq_hz: &'a [f64],
    pub clearances_mm: Option<&'a [f64]>,
    pub points: usize,
    pub objective_mass: usize,
    pub objective_case: &'a str,
    pub steady: &'a SteadyOptions,
}

impl Kind for Study<'_> {
    fn work(&self, exp: &Experiment, _refs: &ReferenceStore) -> u64 {
        work(exp, self)
    }

    fn run(&self, i: &Input<'_>) -> Output {
        run(i.exp, i.refs, self, i.tick)
    }
}

/// Simulated points a study will run when its clearances are listed (for progress).
pub fn work(exp: &Experiment, study: &Study) -> u64 {
    let cases = exp.cases.iter().filter(|c| !c.beds.is_empty()).count();
    let clearances = study.clearances_mm.map(|c| c.len()).unwrap_or(study.points);
    (cases * (clearances + 1) * study.freq_hz.len()) as u64
}

fn with_clearance(case: &Case, d: Clearance) -> Case {
    let mut c = case.clone();
    for bed in &mut c.beds {
        bed.damper.clearance = d;
    }
    c
}

/// Runs a clearance study.
pub fn run(exp: &Experiment, refs: &ReferenceStore, study: &Study, tick: &Tick) -> Output {
    let n = exp.structure.dof();
    let m = study.objective_mass;
    let force = exp.excitation.force;
    let cases: Vec<&Case> = exp.cases.iter().filter(|c| !c.beds.is_empty()).collect();
    // Beds without a top: how high they fly decides the useful clearances.
    let unbounded: Vec<Curve> = cases
        .iter()
        .map(|case| {
            let sys = curves::system(exp, &with_clearance(case, Clearance::NO_TOP));
            let pts = sweep::from_rest(&sys, study.freq_hz, study.steady, tick);
            curves::from_sweep(
                CurveId::clearance(&case.id, f64::INFINITY),
                &format!("{}, d = inf", case.label),
                pts,
                force,
                &case.grains(),
                n,
            )
        })
        .collect();
    let limits_mm: Vec<f64> = unbounded.iter().map(|c| 1e3 * c.highest_flight()).collect();
    let max_limit = limits_mm.iter().copied().fold(0.0, f64::max);
    let clearances: Vec<f64> = match study.clearances_mm {
        Some(list) => list.to_vec(),
        None => (1..=study.points)
            .map(|k| crate::experiment::round_hz(max_limit * 1.2 * k as f64 / study.points as f64))
            .collect(),
    };
    let mut scanned: Vec<Curve> = Vec::new();
    for case in &cases {
        for &mm in &clearances {
            let key = CurveId::clearance(&case.id, mm);
            let grid = curves::union_grid(study.freq_hz, &check_frequencies(exp, refs, &key));
            let sys = curves::system(exp, &with_clearance(case, Clearance::from_mm(mm)));
            let pts = sweep::from_rest(&sys, &grid, study.steady, tick);
            scanned.push(curves::from_sweep(
                key,
                &format!("{}, d = {} mm", case.label, fmt_num(mm)),
                pts,
                force,
                &case.grains(),
                n,
            ));
        }
    }
    let rows = peak_rows(&scanned, m);
    let (exports, best) = scan_exports(&cases, &unbounded, &limits_mm, &rows, study);
    let table = scan_table(exp, &rows, m);
    let limits = Table::new("flight_limits", "Highest flight of the beds of each case above their bottoms over the band with no top (mm): larger clearances are never reached")
        .str("case", cases.iter().map(|c| c.id.clone()).collect())
        .f64("limit_mm", limits_mm.clone());
    let all: Vec<&Curve> = unbounded.iter().chain(scanned.iter()).collect();
    let beds = cases.iter().map(|c| c.beds.len()).max().unwrap_or(0);
    let curves_table = curves::table(
        "compliance",
        &format!(
            "Steady-state compliance ({}) of every scanned curve (CASE@d), as in sweeps",
            exp.excitation.per_unit()
        ),
        &all,
        n,
        beds,
    );

    let figures = exp
        .plots
        .iter()
        .filter(|p| p.kind == PlotKind::ClearanceScan)
        .map(|p| {
            let lo = clearances.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = clearances.iter().copied().fold(0.0, f64::max);
            // Clearances far beyond every flight add nothing to see: they are in the table.
            let x_hi = hi.min(1.3 * max_limit.max(lo)).max(lo * 1.1);
            let mut series = Vec::new();
            let mut vlines = Vec::new();
            for (ci, case) in cases.iter().enumerate() {
                let pts: Vec<&PeakRow> = rows.iter().filter(|r| r.0 == case.id).collect();
                let mut s = Series::line(case.label.clone(), pts.iter().map(|r| r.1).collect(), pts.iter().map(|r| r.2).collect(), ci);
                s.marker = Marker::Circle;
                series.push(s);
                if let Some((_, v)) = unbounded[ci].peak(m) {
                    series.push(Series::line(format!("{}, d = inf", case.label), vec![0.0, x_hi], vec![v, v], ci).dashed(Dash::Dashed));
                }
                vlines.push(VLine { x: limits_mm[ci], label: format!(" {}: top out of reach > {:.3} mm", case.id, limits_mm[ci]) });
            }
            if let Some(b) = &best {
                vlines.push(VLine { x: b.1, label: format!(" best for {}: {} mm", study.objective_case, fmt_num(b.1)) });
            }
            let title = p.title.clone().unwrap_or_else(|| format!("{}: peak compliance against clearance", exp.meta.figure));
            Figure {
                id: p.id.clone(),
                title: title.clone(),
                caption: format!(
                    "Peak compliance of m{} over {}-{} Hz against the clearance of every damper of a case; dashed: the same case with no top (d = inf); vertical lines: the highest flight without top (larger clearances behave as d = inf) and the best clearance.",
                    m + 1,
                    fmt_num(study.freq_hz[0]),
                    fmt_num(study.freq_hz[study.freq_hz.len() - 1])
                ),
                panels: vec![Panel {
                    title,
                    x_label: "clearance d (mm)".into(),
                    y_label: format!("peak compliance of m{} ({})", m + 1, exp.excitation.per_unit()),
                    x_range: (0.0, x_hi),
                    x_log: false,
                    y_log: false,
                    y_range: None,
                    legend: Corner::UpperRight,
                    series,
                    vlines,
                }],
            }
        })
        .collect();
    let mut curves_out = unbounded;
    curves_out.extend(scanned);
    Output { tables: vec![table, limits, curves_table], figures, curves: curves_out, exports, ..Output::default() }
}

/// The scan's table: one [`PeakRow`] a row.
fn scan_table(exp: &Experiment, rows: &[PeakRow], m: usize) -> Table {
    Table::new(
        "clearance_scan",
        format!("Peak compliance ({}) of the objective mass over the band per case and clearance (mm), its frequency (Hz), and the top impacts per period of all beds there", exp.excitation.per_unit()),
    )
    .str("case", rows.iter().map(|r| r.0.clone()).collect())
    .f64("clearance_mm", rows.iter().map(|r| r.1).collect())
    .f64(format!("peak_c{}", m + 1), rows.iter().map(|r| r.2).collect())
    .f64("peak_freq_hz", rows.iter().map(|r| r.3).collect())
    .f64("top_impacts_per_period_at_peak", rows.iter().map(|r| r.4).collect())
}

/// A case, a clearance (mm), the objective mass's peak compliance, its frequency (Hz) and the
/// top impacts per period of all beds there.
type PeakRow = (String, f64, f64, f64, f64);

/// The peak compliance of mass `m` on every scanned curve, one [`PeakRow`] each.
fn peak_rows(scanned: &[Curve], m: usize) -> Vec<PeakRow> {
    let mut rows: Vec<PeakRow> = Vec::new();
    for c in scanned {
        let (case, Some(mm)) = (&c.id.case, c.id.clearance_mm()) else { continue };
        if let Some((f, v)) = c.peak(m) {
            let i = c.index_of(f).unwrap_or(0);
            let tops: f64 = c.top_impacts.get(i).map(|t| t.iter().sum()).unwrap_or(0.0);
            rows.push((case.clone(), mm, v, f, tops));
        }
    }
    rows
}

/// What a scan exports (each case's flight limit and peak without top, the best clearance of
/// the objective case and its peak, every other case's largest ratio to it) and its best row.
fn scan_exports(
    cases: &[&Case],
    unbounded: &[Curve],
    limits_mm: &[f64],
    rows: &[PeakRow],
    study: &Study,
) -> (BTreeMap<String, f64>, Option<PeakRow>) {
    let m = study.objective_mass;
    let mut exports = BTreeMap::new();
    for (case, lim) in cases.iter().zip(limits_mm) {
        exports.insert(format!("limit_mm_{}", case.id), *lim);
    }
    for u in unbounded {
        if let Some((f, v)) = u.peak(m) {
            exports.insert(format!("peak_{}_m{}", u.id, m + 1), v);
            exports.insert(format!("peak_hz_{}_m{}", u.id, m + 1), f);
        }
    }
    let best = rows.iter().filter(|r| r.0 == study.objective_case).min_by(|a, b| a.2.total_cmp(&b.2)).cloned();
    if let Some(b) = &best {
        exports.insert("best_clearance_mm".into(), b.1);
        exports.insert("best_peak".into(), b.2);
    }
    // Every other case's peak over the objective case's at the same clearance: the largest
    // ratio of the scan and its clearance.
    for case in cases.iter().filter(|c| c.id != study.objective_case) {
        let ratios = rows.iter().filter(|r| r.0 == case.id).filter_map(|r| {
            let own = rows.iter().find(|o| o.0 == study.objective_case && o.1 == r.1)?;
            Some((r.2 / own.2, r.1))
        });
        if let Some((ratio, mm)) = ratios.max_by(|a, b| a.0.total_cmp(&b.0)) {
            exports.insert(format!("max_ratio_{}", case.id), ratio);
            exports.insert(format!("max_ratio_mm_{}", case.id), mm);
        }
    }
    (exports, best)
}
