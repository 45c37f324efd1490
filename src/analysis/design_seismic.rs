//! The page of a design against recorded ground motions (`[design] ground_motions`,
//! docs/design.md "Against earthquakes"): after the search, the best layout's objective against
//! one clearance for every container, then the bare building, the file's cases and the best
//! layout under every record as a time history shows them (storey profiles, peaks, energies,
//! beds), and the answer: by how much the best layout lowers the worst storey's peak drift (or
//! floor acceleration), record by record.

use crate::design::seismic::{Response, Suite};
use crate::design::Spec;
use crate::experiment::{Bed, Case, ClearanceSource, Experiment, PlotKind, PlotSpec, Scale};
use crate::number::fmt_sig;
use crate::sim::motion::bed::ImpactLaw;

use super::design_best::{clearance_profile, BestIn, Page};

/// A value of `response` in the page's units: mm for drifts, g for accelerations.
fn in_units(response: Response, v: f64) -> String {
    match response {
        Response::Drift => format!("{} mm", fmt_sig(1e3 * v, 3)),
        Response::Acceleration => format!("{} g", fmt_sig(v / crate::model::GRAVITY, 3)),
    }
}

/// A layout's clearances in words: one when they are all the same.
fn clearance_words(layout: &crate::design::Layout) -> String {
    let c = &layout.clearances_mm;
    if c.windows(2).all(|w| w[0] == w[1]) {
        c.first().map_or(String::new(), |d| fmt_sig(*d, 3))
    } else {
        c.iter().map(|d| fmt_sig(*d, 3)).collect::<Vec<_>>().join(" / ")
    }
}

/// Where a layout's shot is in effect: the hosts of 1 % of the shot or more, in words, when
/// some host has less ("" when every host has more).
fn in_effect(layout: &crate::design::Layout) -> String {
    let shot = layout.shot_kg();
    let kept: Vec<String> = layout
        .hosts
        .iter()
        .zip(&layout.masses_kg)
        .filter(|(_, m)| **m >= 0.01 * shot)
        .map(|(h, _)| format!("m{}", h + 1))
        .collect();
    if kept.len() == layout.hosts.len() {
        String::new()
    } else {
        format!("; in effect on {} alone, the others holding under 1 % of the shot", kept.join(" "))
    }
}

/// The experiment as a time history of the bare building, the file's cases and the best
/// layout (`best`), with one storey-profile plot of them all.
fn layouts_shown(exp: &Experiment, spec: &Spec, i: &BestIn<'_>) -> Experiment {
    let mut shown = exp.clone();
    let mut cases = Vec::new();
    if !exp.cases.iter().any(|c| c.beds.is_empty()) {
        cases.push(Case::bare());
    }
    // The design's layouts have plastic beds: the cases are shown as the design judged them.
    cases.extend(exp.cases.iter().map(|c| Case {
        beds: c.beds.iter().map(|b| Bed { law: ImpactLaw::PLASTIC, ..b.clone() }).collect(),
        ..c.clone()
    }));
    let layout = &i.best.layout;
    cases.push(Case {
        id: "best".into(),
        label: format!("best: {}, d = {} mm", layout.hosts_words(), clearance_words(layout)),
        beds: layout
            .dampers(spec.direction)
            .into_iter()
            .map(|damper| Bed { damper, clearance: ClearanceSource::Fixed, law: ImpactLaw::PLASTIC, grains: 1 })
            .collect(),
    });
    shown.plots = vec![PlotSpec {
        id: "storeys".into(),
        kind: PlotKind::StoreyProfiles,
        title: Some(format!("{}: the best layout under the records", exp.meta.figure)),
        masses: Vec::new(),
        cases: cases.iter().map(|c| c.id.clone()).collect(),
        y_scale: Scale::Linear,
        mark_natural_frequencies: false,
        marks: Vec::new(),
        marks_relative_to: None,
        linear: Vec::new(),
        x_range: None,
    }];
    shown.cases = cases;
    shown
}

/// The best layout's pages and the design's answer in words.
pub(super) fn about_the_best(
    exp: &Experiment,
    spec: &Spec,
    suite: &Suite,
    i: &BestIn<'_>,
    page: &mut Page,
    tick: &(dyn Fn() + Sync),
) -> String {
    let best = i.best;
    let e = &best.evaluation;
    page.exports.insert("best_objective".into(), e.objective);
    if spec.shared_clearance {
        page.exports.insert("best_clearance_mm".into(), best.layout.clearances_mm[0]);
    }
    let mut robust = String::new();
    if i.more {
        let (table, figure, band) = clearance_profile(exp, spec, i.judged.0, i.judged.1, best);
        if let Some((lo, hi)) = band {
            page.exports.insert("robust_clearance_min_mm".into(), lo);
            page.exports.insert("robust_clearance_max_mm".into(), hi);
            robust = if fmt_sig(lo, 2) == fmt_sig(hi, 2) {
                format!(
                    " With one clearance for every container, of the clearances sampled only {} mm is within 5 % of the best (the clearance profile): the gain is tuned to the clearance.",
                    fmt_sig(lo, 2)
                )
            } else {
                format!(
                    " With one clearance for every container it stays within 5 % of the best from {} to {} mm (the clearance profile).",
                    fmt_sig(lo, 2),
                    fmt_sig(hi, 2)
                )
            };
        }
        page.tables.push(table);
        page.figures.push(figure);
    }
    let shown = layouts_shown(exp, spec, i);
    let heights = suite.storey_heights_m.as_deref();
    let out = super::time_history::page(&shown, &suite.records, heights, tick);
    page.tables.extend(out.tables);
    // The profiles over the suite (the records' own are in time_history_peaks): the page stays
    // light.
    let suite_only = suite.records.len() > 1;
    page.figures.extend(out.figures.into_iter().filter(|f| !suite_only || f.id.ends_with("_suite")));
    page.warnings.extend(out.warnings);
    let response = suite.response;
    let (worst_record, _, worst_storey) = e.worst;
    let place = match response {
        Response::Drift => format!("storey {}", worst_storey + 1),
        Response::Acceleration => format!("floor {}", worst_storey + 1),
    };
    // The largest drift as a share of its storey's height, where the heights are given.
    let ratio = |v: f64| match (response, heights.and_then(|h| h.get(worst_storey))) {
        (Response::Drift, Some(h)) => format!(" ({} % of the storey's height)", fmt_sig(100.0 * v / h, 3)),
        _ => String::new(),
    };
    let per_record: Vec<String> = suite
        .records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            format!(
                "{}: {} bare, {}{} with it ({:.3})",
                r.name,
                in_units(response, e.bare[k]),
                in_units(response, e.bands[k]),
                if k == worst_record { ratio(e.bands[k]) } else { String::new() },
                e.bands[k] / e.bare[k]
            )
        })
        .collect();
    let shot = best.layout.shot_kg();
    let share = i
        .total_mass
        .as_ref()
        .map_or(String::new(), |(m, what)| format!(" ({} % of the structure's {what})", fmt_sig(100.0 * shot / m, 2)));
    let beds: Vec<String> = best.layout.masses_kg.iter().map(|m| fmt_sig(*m, 3)).collect();
    let mut words = vec![format!(
        "Under {} record{}, the best layout found puts {} kg of shot{share} in containers on {} ({} kg{}, clearance {} mm): its {}, {}, is {} of the bare building's (the largest under {} at {place}). Record by record: {}.{robust}",
        suite.records.len(),
        if suite.records.len() == 1 { "" } else { "s" },
        fmt_sig(shot, 3),
        best.layout.hosts_words(),
        beds.join(" / "),
        in_effect(&best.layout),
        clearance_words(&best.layout),
        response.words(),
        suite.over.words(),
        fmt_sig(e.objective, 3),
        suite.records.get(worst_record).map_or("", |r| r.name.as_str()),
        per_record.join("; ")
    )];
    for (id, _, ce, _) in i.case_rows.iter().filter(|c| !c.1.hosts.is_empty()) {
        words.push(format!("Case {id}: {}.", fmt_sig(ce.objective, 3)));
    }
    // A clearance at an end of the file's range: the range, not the shot, may stop the search.
    let (lo, hi) = spec.clearance_mm;
    let ends: Vec<f64> = best
        .layout
        .clearances_mm
        .iter()
        .copied()
        .filter(|d| (d / lo).ln().abs() < 0.01 || (d / hi).ln().abs() < 0.01)
        .collect();
    if let Some(d) = ends.first() {
        let w = format!(
            "the best clearance ({} mm) is at an end of design.clearance_mm ({}-{} mm): the range may stop the search; widen it",
            fmt_sig(*d, 3),
            fmt_sig(lo, 3),
            fmt_sig(hi, 3)
        );
        words.push(format!("CAUTION: {w}."));
        page.warnings.push(w);
    }
    if e.unsettled > 0 {
        words.push(format!(
            "{} of its record runs stopped before the record's end (more events than allowed): their peaks are over the time run only.",
            e.unsettled
        ));
    }
    if e.scenarios.len() > 1 {
        words.push(
            "The objective is over the design's scenarios; the profiles and tables below are the file's structure's."
                .into(),
        );
    }
    if let Some(stopped) = i.stopped {
        words.push(stopped.to_string());
    }
    words.join(" ")
}
