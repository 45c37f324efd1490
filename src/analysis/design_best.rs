//! The best layout's page, shared by a design's (`super::design`) and a design against records'
//! (`super::design_seismic`): the page as it is filled, what the best layout's pages read, the
//! objective's words, and the clearance profile near the optimum.

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::design::search::{self, Found};
use crate::design::{evaluate, Evaluation, Layout, Problem, Spec, PROFILE_POINTS};
use crate::experiment::Experiment;
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series, VLine};
use crate::number::{fmt_num, fmt_sig};
use crate::table::Table;

/// A clearance is in the robust band when its objective is within this factor of the best.
pub const ROBUST: f64 = 1.05;

/// What the objective is, for axes: the worst band's measure over the bare structure's, or
/// against records the response over the bare building's (the worst record or the mean).
pub(super) fn objective_axis(spec: &Spec) -> String {
    match &spec.suite {
        None => "worst band over the bare structure".into(),
        Some(suite) => format!("{} over bare, {}", suite.response.words(), suite.over.words()),
    }
}

pub(super) fn joined(v: &[f64]) -> String {
    v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(" / ")
}

/// A page's tables, figures, exported numbers and warnings, as they are added.
#[derive(Default)]
pub(super) struct Page {
    pub(super) tables: Vec<Table>,
    pub(super) figures: Vec<Figure>,
    pub(super) exports: BTreeMap<String, f64>,
    pub(super) warnings: Vec<String>,
}

/// What the best layout's pages read (`about_the_best` of the design and of a design against
/// records): the judged problem and its bare measures, the screen's,
/// the best layout, the cases' rows, the structure's mass and whether more layouts may be
/// evaluated (the search was not stopped).
pub(super) struct BestIn<'a> {
    pub(super) p: &'a Problem,
    pub(super) judged: search::On<'a>,
    pub(super) screen: Option<search::On<'a>>,
    pub(super) best: &'a Found,
    pub(super) case_rows: &'a [(String, Layout, Evaluation, u64)],
    pub(super) total_mass: Option<(f64, String)>,
    pub(super) more: bool,
    /// Where the search stopped: the sentences that lead the answer, saying what it is.
    pub(super) stopped: Option<&'a str>,
}

/// How the objective of the best layout varies with one clearance for every container, its
/// hosts and shot split held: the table, the figure and the robust band (where the objective is
/// within [`ROBUST`] of the best), when some clearance is in it.
pub(super) fn clearance_profile(
    exp: &Experiment,
    spec: &Spec,
    p: &Problem,
    b: &[Vec<f64>],
    best: &Found,
) -> (Table, Figure, Option<(f64, f64)>) {
    // How the objective varies with the clearance, the best hosts and split held.
    let (lo, hi) = spec.clearance_mm;
    let ds: Vec<f64> =
        (0..PROFILE_POINTS).map(|i| lo * (hi / lo).powf(i as f64 / (PROFILE_POINTS - 1) as f64)).collect();
    let evaluated: Vec<(f64, usize)> = ds
        .par_iter()
        .map(|&d| {
            let l = Layout { clearances_mm: vec![d; best.layout.hosts.len()], ..best.layout.clone() };
            let e = evaluate(p, b, &l);
            (e.objective, e.unsettled)
        })
        .collect();
    let profile: Vec<f64> = evaluated.iter().map(|e| e.0).collect();
    let target = ROBUST * best.evaluation.objective;
    let inside: Vec<f64> = ds.iter().zip(&profile).filter(|(_, o)| **o <= target).map(|(d, _)| *d).collect();
    let (rlo, rhi) = (
        inside.iter().copied().fold(f64::INFINITY, f64::min),
        inside.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let table = Table::new(
            "design_clearance",
            format!(
                "The objective of the best layout ({}, bed kg {}) with one clearance for every container, from {} to {} mm: the robust band is where it is within {} % of the best",
                best.layout.hosts_words(),
                joined(&best.layout.masses_kg),
                fmt_num(lo),
                fmt_num(hi),
                fmt_num(100.0 * (ROBUST - 1.0))
            ),
        )
        .f64("clearance_mm", ds.clone())
        .f64("objective", profile.clone())
        .i64("robust", profile.iter().map(|o| i64::from(*o <= target)).collect())
        .i64("unsettled_points", evaluated.iter().map(|e| e.1 as i64).collect());
    let mut panel = Panel::new(
        "objective against the clearance, best hosts and split held",
        "clearance d (mm)",
        objective_axis(spec),
        (lo, hi),
    )
    .log_x();
    let mut s = Series::line(best.layout.hosts_words(), ds.clone(), profile.clone(), 0);
    s.marker = Marker::Circle;
    panel.series.push(s);
    panel
        .series
        .push(Series::line(format!("best x {ROBUST}"), vec![lo, hi], vec![target, target], 1).dashed(Dash::Dashed));
    if rlo.is_finite() {
        panel.vlines.push(VLine { x: rlo, label: format!(" robust band {}-{} mm", fmt_sig(rlo, 2), fmt_sig(rhi, 2)) });
        panel.vlines.push(VLine { x: rhi, label: String::new() });
    }
    panel.legend = Corner::UpperRight;
    let figure = Figure {
        id: "design_clearance".into(),
        title: format!("{}: the objective near the optimum", exp.meta.figure),
        caption: format!("The objective ({}) against one clearance for every container, with the best layout's hosts and shot split; dashed: 5 % above the best (the robust band).", objective_axis(spec)),
        panels: vec![panel],
    };
    (table, figure, rlo.is_finite().then_some((rlo, rhi)))
}
