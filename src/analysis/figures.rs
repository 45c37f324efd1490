//! Compliance figures from curves: one panel with every mass, or one panel per mass.
//! Points that did not settle or are not period-1 are drawn with their class's marker
//! (period-k circles, quasi-periodic triangles, chaotic crosses, the rest squares) and the
//! 95 % interval of a measured point as a bar, never hidden.

use crate::experiment::{Experiment, PlotKind, PlotSpec, Scale};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series, VLine};
use crate::model::modal::ModeSummary;

use super::branches::{self, OrbitCurve};
use super::curves::Curve;
use super::overlays::Overlay;

/// Dash patterns in case order.
const DASHES: [Dash; 4] = [Dash::Solid, Dash::Dashed, Dash::DashDot, Dash::Dotted];

/// Linear reference curves for one plot: (curve, label) pairs drawn thin and dotted.
pub struct Extras<'a> {
    pub linear: Vec<&'a Curve>,
    pub marks: Vec<VLine>,
    /// References drawn over the curves, with a residual panel beneath.
    pub overlays: Vec<Overlay>,
    /// Branches of periodic orbits continued in frequency (stable solid, unstable dashed).
    pub branches: Vec<&'a OrbitCurve>,
    /// The analysis grid's range (curves may hold extra points outside it for checks).
    pub range: (f64, f64),
}

/// The points of the curves counted by class, in words, and how the points that are not
/// certified orbits are drawn and measured.
pub fn class_words(curves: &[&Curve]) -> String {
    let all: Vec<&str> = curves.iter().flat_map(|c| c.motion.iter().copied()).collect();
    let count = |name: &str| all.iter().filter(|m| **m == name).count();
    let periodic = count("periodic");
    let (quasi, chaotic) = (count("quasi-periodic"), count("chaotic"));
    let rest = all.len() - periodic - quasi - chaotic;
    if all.len() == periodic {
        return format!("Every one of the {} points is a periodic motion.", all.len());
    }
    format!(
        "Of the {} points, {periodic} periodic (circles where the period is longer than one forcing period), {quasi} quasi-periodic (triangles), {chaotic} chaotic (crosses: largest Lyapunov exponent above 0), {rest} not settled within the budget (squares){}; a point with no certified orbit is the 95th percentile of its per-period amplitudes over a stationary record, the bar its 95 % interval.",
        all.len(),
        unclassified_words(count("unclassified"))
    )
}

/// What a caption adds of the points measured over records too short to classify
/// ([`crate::sim::settle::statistic::Motion::Unclassified`]), counted among the squares.
pub fn unclassified_words(unclassified: usize) -> String {
    match unclassified {
        0 => String::new(),
        k => format!(
            ", {k} of them unclassified (measured over too short a record to tell chaos, a torus and a transient apart: fewer than {} kept periods, no interval, or fewer than {} batches whose interval contains 0)",
            2 * crate::sim::settle::statistic::MIN_BATCH,
            crate::sim::settle::statistic::BATCHES
        ),
    }
}

/// How a point that is not a settled period-1 orbit is drawn: its class's marker and legend
/// entry.
fn class_of(c: &Curve, i: usize) -> (Marker, &'static str) {
    class_marker(c.motion.get(i).copied().unwrap_or(""))
}

/// The marker and legend entry of a motion class ([`crate::sim::settle::statistic::Motion::name`]) drawn
/// as a point that is not a settled period-1 orbit (the design pages' too).
pub fn class_marker(class: &str) -> (Marker, &'static str) {
    match class {
        "periodic" => (Marker::Circle, "periodic, period > 1"),
        "quasi-periodic" => (Marker::Triangle, "quasi-periodic (torus)"),
        "chaotic" => (Marker::Cross, "chaotic (Lyapunov exponent > 0)"),
        _ => (Marker::Square, "not settled (transient, unclassified, chatter, not computed)"),
    }
}

/// The points of `c` that are not settled period-1 orbits, one series per class (marker and
/// legend entry: [`class_of`]; a class's entry only where `labelled` does not hold it yet),
/// and the 95 % intervals of the measured ones as vertical bars.
fn irregular_points(c: &Curve, mass: usize, color: usize, labelled: &mut Vec<&'static str>) -> Vec<Series> {
    let idx: Vec<usize> = (0..c.freq_hz.len()).filter(|&i| !c.regular(i)).collect();
    let mut out = Vec::new();
    let mut classes: Vec<(Marker, &'static str)> = idx.iter().map(|&i| class_of(c, i)).collect();
    classes.dedup();
    classes.sort_by_key(|k| k.1);
    classes.dedup();
    for (marker, name) in classes {
        let mine: Vec<usize> = idx.iter().copied().filter(|&i| class_of(c, i).1 == name).collect();
        let label = if labelled.contains(&name) {
            ""
        } else {
            labelled.push(name);
            name
        };
        out.push(Series::points(
            label,
            mine.iter().map(|&i| c.freq_hz[i]).collect(),
            mine.iter().map(|&i| c.compliance[i][mass]).collect(),
            color,
            marker,
        ));
    }
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for &i in &idx {
        let Some(Some(m)) = c.measured.get(i) else { continue };
        let (v, h) = (c.compliance[i][mass], m.half_width[mass]);
        if v.is_finite() && h.is_finite() && h > 0.0 {
            x.extend([c.freq_hz[i], c.freq_hz[i], f64::NAN]);
            y.extend([v - h, v + h, f64::NAN]);
        }
    }
    if !x.is_empty() {
        let label = if labelled.contains(&"95 % interval") {
            ""
        } else {
            labelled.push("95 % interval");
            "95 % interval"
        };
        out.push(Series::line(label, x, y, color));
    }
    out
}

/// The figures of an experiment's compliance plots.
pub fn compliance(
    exp: &Experiment,
    plots: &[&PlotSpec],
    curves: &[&Curve],
    extras: &Extras,
    modes: &[ModeSummary],
) -> Vec<Figure> {
    plots
        .iter()
        .filter(|p| matches!(p.kind, PlotKind::Compliance | PlotKind::CompliancePanels))
        .map(|p| {
            let shown: Vec<&Curve> = curves.iter().copied().filter(|c| p.cases.iter().any(|id| c.id.drawn_for(id))).collect();
            let (lo, hi) = p.x_range.unwrap_or(extras.range);
            let mut vlines: Vec<VLine> = if p.mark_natural_frequencies {
                modes.iter().filter(|m| m.freq_hz >= lo && m.freq_hz <= hi).map(|m| VLine { x: m.freq_hz, label: format!(" f{} = {:.2} Hz", m.number, m.freq_hz) }).collect()
            } else {
                Vec::new()
            };
            vlines.extend(extras.marks.iter().cloned());
            let title = p.title.clone().unwrap_or_else(|| format!("{}: {}", exp.meta.figure, exp.meta.title));
            let panel = |masses: &[usize], panel_title: String, by_mass: bool| {
                let mut series = Vec::new();
                let mut labelled = Vec::new();
                for (ci, c) in shown.iter().enumerate() {
                    for &r in masses {
                        let (color, dash) = if by_mass { (r, DASHES[ci % 4]) } else { (ci, Dash::Solid) };
                        let label = match (by_mass, shown.len() > 1) {
                            (true, true) => format!("m{} — {}", r + 1, c.label),
                            (true, false) => format!("m{}", r + 1),
                            (false, _) => c.label.clone(),
                        };
                        series.push(Series::line(label, c.freq_hz.clone(), c.compliance.iter().map(|row| row[r]).collect(), color).dashed(dash));
                        series.extend(irregular_points(c, r, color, &mut labelled));
                    }
                }
                for (bi, b) in extras.branches.iter().enumerate() {
                    for &r in masses {
                        let color = if by_mass { r } else { shown.len() + bi };
                        series.extend(branches::series(b, r, color, r == masses[0]));
                    }
                }
                // References as small markers in the colour of their curve.
                for o in &extras.overlays {
                    let Some(ci) = shown.iter().position(|c| c.id == o.curve) else { continue };
                    for &r in masses {
                        if o.points[r].is_empty() {
                            continue;
                        }
                        let color = if by_mass { r } else { ci };
                        let (x, y): (Vec<f64>, Vec<f64>) = o.points[r].iter().copied().unzip();
                        let label = if by_mass { format!("m{} — {}: {}", r + 1, shown[ci].label, o.source) } else { format!("{}: {}", shown[ci].label, o.source) };
                        series.push(Series::points(label, x, y, color, Marker::Square).sized(2));
                    }
                }
                for (li, l) in extras.linear.iter().enumerate() {
                    for &r in masses {
                        let color = if by_mass { r } else { 7 };
                        let dash = if li == 0 { Dash::Dotted } else { Dash::DashDot };
                        let label = if by_mass { format!("m{} — {}", r + 1, l.label) } else { l.label.clone() };
                        series.push(Series::line(label, l.freq_hz.clone(), l.compliance.iter().map(|row| row[r]).collect(), color).dashed(dash));
                    }
                }
                Panel {
                    title: panel_title,
                    x_label: "frequency (Hz)".into(),
                    y_label: format!("compliance {} ({})", exp.excitation.ratio(), exp.excitation.per_unit()),
                    x_range: (lo, hi),
                    x_log: false,
                    y_log: p.y_scale == Scale::Log,
                    y_range: None,
                    legend: Corner::UpperRight,
                    series,
                    vlines: vlines.clone(),
                }
            };
            let mut panels: Vec<Panel> = match p.kind {
                PlotKind::CompliancePanels => p.masses.iter().map(|&r| panel(&[r], format!("{title}: m{}", r + 1), false)).collect(),
                _ => vec![panel(&p.masses, title.clone(), true)],
            };
            if let Some(res) = residual_panel(&extras.overlays, &shown, &p.masses, (lo, hi)) {
                panels.push(res);
            }
            Figure {
                id: p.id.clone(),
                title: title.clone(),
                caption: format!(
                    "Compliance amplitude (max - min)/2 / {} with {}{}. {}{}{}",
                    exp.excitation.symbol(),
                    exp.excitation.at(),
                    if exp.excitation.supports { ", displacements relative to the supports" } else { "" },
                    class_words(&shown),
                    if extras.branches.is_empty() {
                        ""
                    } else {
                        " Thin lines: periodic orbits continued in frequency through folds, solid where stable, dashed where unstable; filled squares: folds, turns at a graze and period doublings."
                    },
                    if extras.overlays.is_empty() {
                        ""
                    } else {
                        " Small squares: the reference curves of the checks; bottom panel: the relative difference from them at their points, with the checks' tolerances."
                    }
                ),
                panels,
            }
        })
        .collect()
}

/// The relative difference of the shown curves from their references, with the tolerances.
fn residual_panel(overlays: &[Overlay], shown: &[&Curve], masses: &[usize], range: (f64, f64)) -> Option<Panel> {
    let used: Vec<&Overlay> = overlays.iter().filter(|o| shown.iter().any(|c| c.id == o.curve)).collect();
    if used.is_empty() {
        return None;
    }
    let mut panel = Panel::new(
        "relative difference from the reference at its points (settled, period-1): circles m1, squares m2, triangles m3",
        "frequency (Hz)",
        "|computed - reference| / reference",
        range,
    )
    .log_y();
    let mut tols: Vec<f64> = Vec::new();
    let mut all: Vec<f64> = Vec::new();
    for o in &used {
        let ci = shown.iter().position(|c| c.id == o.curve).unwrap_or(0);
        for &m in masses {
            if o.residual[m].is_empty() {
                continue;
            }
            let (x, y): (Vec<f64>, Vec<f64>) = o.residual[m].iter().copied().unzip();
            all.extend(y.iter().copied().filter(|v| *v > 0.0));
            let marker = [Marker::Circle, Marker::Square, Marker::Triangle][m % 3];
            let label =
                if Some(&m) == masses.first() { format!("{} ({})", shown[ci].label, o.source) } else { String::new() };
            panel.series.push(Series::points(label, x, y, ci, marker).sized(3));
        }
        tols.extend(o.tolerances.iter().copied());
    }
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    for t in &tols {
        panel.series.push(
            Series::line(format!("tolerance {t:.0e}"), vec![range.0, range.1], vec![*t, *t], 7).dashed(Dash::Dashed),
        );
    }
    let lo = all.iter().copied().fold(f64::INFINITY, f64::min).min(tols.first().copied().unwrap_or(1e-3)).max(1e-16);
    let hi = all.iter().copied().fold(0.0, f64::max).max(tols.last().copied().unwrap_or(1e-3));
    panel.y_range = Some((lo / 3.0, hi * 3.0));
    panel.legend = crate::figure::Corner::LowerRight;
    Some(panel)
}
