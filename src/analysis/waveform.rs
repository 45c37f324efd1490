//! Waveforms (Fig. 6 style): the steady motion of hosts and beds against forcing phase, with
//! contact visible where a bed's line runs on its host's, and the motion type of each bed.

use std::f64::consts::PI;

use crate::checks::fmt_num;
use crate::checks::reference::ReferenceStore;
use crate::experiment::{Experiment, Number, PlotKind};
use crate::figure::{Corner, Dash, Figure, Panel, Series};
use crate::sim::motion::observe::Sampler;
use crate::sim::{steady_from_rest, Dynamics, Engine, EventKind, SteadyOptions};
use crate::table::Table;

use super::curves;
use super::evidence::MotionTypes;
use super::kind::{Input, Kind, Output};
use super::result::Tick;

/// Samples drawn per forcing period.
const SAMPLES_PER_PERIOD: usize = 360;

/// One recorded frequency of one case.
struct Record {
    case: String,
    label: String,
    freq_hz: f64,
    phase_deg: Vec<f64>,
    sampler: Sampler,
    types: Vec<String>,
    settled: bool,
}

/// The motion type of the bed in container `beds` (one bed, or a column's grains) from the
/// events of the record (paper section 2.2).
fn motion_type(s: &Sampler, beds: std::ops::Range<usize>, periods: usize, finite: bool, horizontal: bool) -> String {
    let (mut lift, mut bottom, mut top_stick, mut top_bounce) = (0, 0, 0, 0);
    let grains = beds.len();
    for e in s.events.iter().filter(|e| beds.contains(&e.bed)) {
        match e.kind {
            EventKind::LiftOff { top: false } => lift += 1,
            EventKind::Impact { top: false, .. } => bottom += 1,
            EventKind::Impact { top: true, attached: true, .. } => top_stick += 1,
            EventKind::Impact { top: true, attached: false, .. } => top_bounce += 1,
            EventKind::LiftOff { top: true } | EventKind::Collision { .. } => {}
        }
    }
    let per = |k: usize| fmt_num(k as f64 / periods as f64);
    if horizontal {
        // The paper's types are those of a vertical bed; a horizontal one is told by the
        // walls it hits (docs/model.md section 2.2).
        let second = top_stick + top_bounce;
        return match (bottom > 0, second > 0) {
            (false, false) if lift == 0 => "rides on a wall (no flight)".into(),
            (false, false) => "flies without hitting a wall".into(),
            (true, true) => format!(
                "hits both walls; per period {} impacts on the first and {} on the second",
                per(bottom),
                per(second)
            ),
            (true, false) => format!("hits the first wall only; per period {} impacts", per(bottom)),
            (false, true) => format!("hits the second wall only; per period {} impacts", per(second)),
        };
    }
    if lift == 0 && bottom == 0 && top_stick + top_bounce == 0 {
        return "rests on the bottom (no flight)".into();
    }
    let kind = if top_stick > 0 {
        "Type I (rests on the top)"
    } else if top_bounce > 0 {
        "Type II (hits the top, falls at once)"
    } else if finite {
        "Type III (never reaches the top)"
    } else {
        "Type III (no top)"
    };
    let of = if grains > 1 { format!(" (all {grains} grains)") } else { String::new() };
    format!("{kind}; per period {} bottom and {} top impacts{of}", per(bottom), per(top_stick + top_bounce))
}

/// Whether a case of `exp` has a column of grains (its events tables then name the container
/// and the grain of each bed).
fn has_columns(exp: &Experiment) -> bool {
    exp.cases.iter().any(|c| c.beds.iter().map(|b| &b.grains).any(|&g| g > 1))
}

/// The bed columns of an events table in words, for its description.
pub fn bed_words(exp: &Experiment) -> &'static str {
    if has_columns(exp) {
        "bed (1-based; a column's grains are beds of their own, bottom grain first), its container and grain (1-based)"
    } else {
        "bed (1-based)"
    }
}

/// The columns of an events table after its leading ones: bed, its container and grain (when
/// a case has a column), kind, relative speed (of an impact or a collision) and loss. `ev`:
/// each event with its case's id.
pub fn event_columns(t: Table, exp: &Experiment, ev: &[(&str, &crate::sim::Event)]) -> Table {
    let mut t = t.i64("bed", ev.iter().map(|(_, e)| e.bed as i64 + 1).collect());
    if has_columns(exp) {
        let places: Vec<(i64, i64)> = ev.iter().map(|(case, e)| curves::place(exp, case, e.bed)).collect();
        t = t.i64("container", places.iter().map(|p| p.0).collect()).i64("grain", places.iter().map(|p| p.1).collect());
    }
    t.str("kind", ev.iter().map(|(_, e)| event_words(&e.kind)).collect())
        .f64(
            "speed",
            ev.iter()
                .map(|(_, e)| match e.kind {
                    EventKind::Impact { speed, .. } | EventKind::Collision { speed, .. } => speed,
                    EventKind::LiftOff { .. } => 0.0,
                })
                .collect(),
        )
        .f64("loss", ev.iter().map(|(_, e)| e.loss).collect())
}

/// An event kind in words, for tables.
pub fn event_words(kind: &EventKind) -> String {
    match *kind {
        EventKind::LiftOff { top } => format!("lift-off from {}", if top { "top" } else { "bottom" }),
        EventKind::Impact { top, attached, .. } => {
            format!(
                "impact on {}{}",
                if top { "top" } else { "bottom" },
                if attached { ", stays" } else { ", separates" }
            )
        }
        EventKind::Collision { lower, stuck, .. } => {
            format!("hits grain {}{}", lower + 1, if stuck { ", sticks" } else { ", bounces" })
        }
    }
}

/// A waveform analysis (`kind = "waveform"`): its frequencies (resolved values), their
/// labels, the periods drawn and the steady-state settings.
pub(crate) struct Waveform<'a> {
    pub(crate) frequencies: &'a [Number],
    pub(crate) labels: &'a [String],
    pub(crate) periods: usize,
    pub(crate) steady: &'a SteadyOptions,
}

impl Kind for Waveform<'_> {
    fn work(&self, exp: &Experiment, _refs: &ReferenceStore) -> u64 {
        (exp.cases.iter().filter(|c| !c.beds.is_empty()).count() * self.frequencies.len()) as u64
    }

    fn run(&self, i: &Input<'_>) -> Output {
        let (tables, figures, motion_types, skipped) =
            run(i.exp, self.frequencies, self.labels, self.periods, self.steady, i.tick);
        let mut out = Output { tables, figures, motion_types, ..Output::default() };
        out.missing_cases(i.exp, skipped);
        out
    }
}

/// Runs the waveform analysis. Frequencies are resolved values.
fn run(
    exp: &Experiment,
    frequencies: &[Number],
    labels: &[String],
    periods: usize,
    steady: &SteadyOptions,
    tick: &Tick,
) -> (Vec<Table>, Vec<Figure>, MotionTypes, Vec<String>) {
    let mut skipped = Vec::new();
    let freqs: Vec<f64> = frequencies.iter().map(|f| if let Number::Value(v) = f { *v } else { f64::NAN }).collect();
    let mut records = Vec::new();
    for case in exp.cases.iter().filter(|c| !c.beds.is_empty()) {
        let sys = curves::system(exp, case);
        for (f, label) in freqs.iter().zip(labels) {
            let omega = 2.0 * PI * f;
            let d = match Dynamics::new(&sys, omega) {
                Ok(d) => d,
                Err(e) => {
                    skipped.push(format!(
                        "case {} at {} Hz cannot be simulated: {e}",
                        case.id,
                        crate::number::fmt_num(*f)
                    ));
                    continue;
                }
            };
            let st = steady_from_rest(&d, steady);
            let mut s = st.final_state.clone();
            let t0 = s.t;
            let period = 2.0 * PI / omega;
            let m = SAMPLES_PER_PERIOD * periods;
            let times: Vec<f64> = (0..=m).map(|k| t0 + period * periods as f64 * k as f64 / m as f64).collect();
            let mut sampler = Sampler::new(times.clone());
            let _ = Engine::new(&d).advance(&mut s, t0 + period * periods as f64, &mut sampler);
            let types = curves::bed_ranges(case)
                .into_iter()
                .enumerate()
                .map(|(k, beds)| {
                    let d = &case.beds[k].damper;
                    let horizontal = d.direction == crate::model::Direction::Horizontal;
                    motion_type(&sampler, beds, periods, d.clearance.is_bounded(), horizontal)
                })
                .collect();
            records.push(Record {
                case: case.id.clone(),
                label: label.clone(),
                freq_hz: *f,
                phase_deg: times.iter().map(|t| (t - t0) * omega * 180.0 / PI).collect(),
                sampler,
                types,
                settled: st.converged,
            });
            tick();
        }
    }
    let mut types = MotionTypes::new();
    for r in &records {
        let list = types.entry(r.case.clone()).or_default();
        for t in &r.types {
            list.push(short_type(t));
        }
    }
    (tables(exp, &records), figures(exp, &records, periods), types, skipped)
}

/// "Type II (hits the top...); ..." -> "II"; "rests on the bottom ..." -> "rests".
fn short_type(t: &str) -> String {
    match t.strip_prefix("Type ") {
        Some(rest) => rest.split([' ', ';']).next().unwrap_or(rest).to_string(),
        None if t.starts_with("hits both walls") => "both walls".into(),
        None if t.starts_with("hits the") => "one wall".into(),
        None => "rests".into(),
    }
}

fn tables(exp: &Experiment, records: &[Record]) -> Vec<Table> {
    let n = exp.structure.dof();
    let beds =
        exp.cases.iter().map(|c| c.beds.iter().map(|b| &b.grains).map(|g| g.max(&1)).sum::<usize>()).max().unwrap_or(0);
    let rows: Vec<(&Record, usize)> =
        records.iter().flat_map(|r| (0..r.sampler.x.len()).map(move |i| (r, i))).collect();
    let mut t = Table::new(
        "waveforms",
        "Steady motion per case and frequency: forcing phase (deg), displacement of each mass x1..xn (m), position y and state (B bottom, T top, F free) of each bed",
    )
    .str("case", rows.iter().map(|(r, _)| r.case.clone()).collect())
    .str("label", rows.iter().map(|(r, _)| r.label.clone()).collect())
    .f64("freq_hz", rows.iter().map(|(r, _)| r.freq_hz).collect())
    .f64("phase_deg", rows.iter().map(|(r, i)| r.phase_deg[*i]).collect());
    for k in 0..n {
        t = t.f64(format!("x{}", k + 1), rows.iter().map(|(r, i)| r.sampler.x[*i][k]).collect());
    }
    for j in 0..beds {
        t = t
            .f64(
                format!("y{}", j + 1),
                rows.iter().map(|(r, i)| r.sampler.y[*i].get(j).copied().unwrap_or(f64::NAN)).collect(),
            )
            .str(
                format!("state{}", j + 1),
                rows.iter()
                    .map(|(r, i)| r.sampler.state[*i].get(j).map(|c| c.to_string()).unwrap_or_default())
                    .collect(),
            );
    }
    let ev: Vec<(&Record, &crate::sim::Event)> =
        records.iter().flat_map(|r| r.sampler.events.iter().map(move |e| (r, e))).collect();
    let events = Table::new(
        "events",
        format!(
            "Every event of the drawn periods: time (s), {}, kind, relative speed (m/s) and kinetic energy lost (J)",
            bed_words(exp)
        ),
    )
    .str("case", ev.iter().map(|(r, _)| r.case.clone()).collect())
    .str("label", ev.iter().map(|(r, _)| r.label.clone()).collect())
    .f64("t", ev.iter().map(|(_, e)| e.t).collect());
    let ev: Vec<(&str, &crate::sim::Event)> = ev.iter().map(|(r, e)| (r.case.as_str(), *e)).collect();
    let events = event_columns(events, exp, &ev);
    vec![t, events]
}

fn figures(exp: &Experiment, records: &[Record], periods: usize) -> Vec<Figure> {
    let mut out = Vec::new();
    for p in exp.plots.iter().filter(|p| p.kind == PlotKind::Waveform) {
        for case in exp.cases.iter().filter(|c| p.cases.contains(&c.id) && !c.beds.is_empty()) {
            let recs: Vec<&Record> = records.iter().filter(|r| r.case == case.id).collect();
            let mut panels = Vec::new();
            let mut type_lines = Vec::new();
            for r in &recs {
                let mut series = Vec::new();
                for ((j, dm), beds) in case.beds.iter().map(|b| &b.damper).enumerate().zip(curves::bed_ranges(case)) {
                    let host: Vec<f64> = r.sampler.x.iter().map(|x| 1e3 * x[dm.host]).collect();
                    series.push(Series::line(format!("m{} (host)", dm.host + 1), r.phase_deg.clone(), host.clone(), j));
                    let grains = beds.len();
                    for (g, b) in beds.enumerate() {
                        let bed: Vec<f64> = r.sampler.y.iter().map(|y| 1e3 * y[b]).collect();
                        let label = match (grains, g) {
                            (1, _) => format!("bed on m{}", dm.host + 1),
                            (_, 0) => format!("{grains} grains on m{}", dm.host + 1),
                            _ => String::new(),
                        };
                        series.push(Series::line(label, r.phase_deg.clone(), bed, j).dashed(Dash::Dashed));
                    }
                    if dm.clearance.is_bounded() {
                        let top = host.iter().map(|h| h + dm.clearance.mm()).collect();
                        series.push(
                            Series::line(
                                if dm.direction == crate::model::Direction::Horizontal {
                                    format!("second wall of container on m{}", dm.host + 1)
                                } else {
                                    format!("top of container on m{}", dm.host + 1)
                                },
                                r.phase_deg.clone(),
                                top,
                                j,
                            )
                            .dashed(Dash::Dotted),
                        );
                    }
                    type_lines.push(format!(
                        "{} {} Hz, bed on m{}: {}",
                        r.label,
                        fmt_num(r.freq_hz),
                        dm.host + 1,
                        r.types[j]
                    ));
                }
                let short: Vec<String> = case
                    .dampers()
                    .iter()
                    .zip(&r.types)
                    .map(|(dm, t)| {
                        let name = t.split(" (").next().unwrap_or(t).split(';').next().unwrap_or(t);
                        if case.beds.len() > 1 {
                            format!("m{}: {name}", dm.host + 1)
                        } else {
                            name.to_string()
                        }
                    })
                    .collect();
                panels.push(Panel {
                    title: format!(
                        "({}) {} Hz{}: {}",
                        r.label,
                        fmt_num(r.freq_hz),
                        if r.settled { "" } else { " (did not settle)" },
                        short.join(", ")
                    ),
                    x_label: "forcing phase omega t (deg)".into(),
                    y_label: "displacement (mm)".into(),
                    x_range: (0.0, 360.0 * periods as f64),
                    x_log: false,
                    y_log: false,
                    y_range: None,
                    legend: Corner::UpperRight,
                    series,
                    vlines: Vec::new(),
                });
            }
            let title = p.title.clone().unwrap_or_else(|| format!("{}: waveforms", exp.meta.figure));
            out.push(Figure {
                id: format!("{}_{}", p.id, case.id),
                title: format!("{title}, {}", case.label),
                caption: format!(
                    "Steady motion over {periods} forcing periods (phase 0 at a multiple of the period, {}). Solid: host mass; dashed: bed (on the host line while in contact); dotted: container top (the second wall of a horizontal container). Motion types: {}.",
                    if exp.excitation.supports {
                        "the supports accelerating as A sin(omega t); absolute displacements".to_string()
                    } else {
                        format!("force F sin(omega t) on m{}", exp.excitation.mass + 1)
                    },
                    type_lines.join("; ")
                ),
                panels,
            });
        }
    }
    out
}
