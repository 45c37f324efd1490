//! A design's compliance figure: each band's curves of the bare structure, the cases and the
//! best layout, every point marked by its motion's class, the lower of two coexisting
//! motions drawn too, and the words that count them.

use crate::design::search::Found;
use crate::design::{Evaluation, Layout, Point, Problem, Spec};
use crate::experiment::Experiment;
use crate::figure::{Dash, Figure, Marker, Panel, Series};
use crate::sim::settle::statistic::Motion as Class;
use crate::table::Table;

/// The drawn points of the layouts with shot (each band's masses) counted by class, in words.
pub(super) fn drawn_classes(bands: &[crate::design::Band], evaluations: &[Option<&Evaluation>]) -> String {
    let mut count = crate::sim::settle::statistic::ClassCounts::default();
    let mut screened = 0;
    for e in evaluations.iter().flatten() {
        for (band, rows) in bands.iter().zip(&e.points_class) {
            for p in rows.iter().flat_map(|r| band.masses.iter().filter_map(|&m| r.get(m))) {
                count[p.class.index()] += 1;
                screened += usize::from(p.screened);
            }
        }
    }
    let all: usize = count.iter().sum();
    if count[0] == all {
        return "Every point with shot is a periodic orbit.".into();
    }
    let screen = match screened {
        0 => String::new(),
        k => format!(
            " {k} of them were measured over a {}-period screen only, their bar that screen's interval widened {} times: it lies below their band's highest point's, so they cannot set the band's peak (docs/design.md).",
            crate::design::race::SCREEN,
            crate::design::race::SCREEN_WIDEN
        ),
    };
    format!(
        "Of the {all} points with shot drawn (per frequency and band mass), {} periodic, {} quasi-periodic (triangles), {} chaotic (crosses), {} not settled within the budget (squares){}; a point with no certified orbit is the 95th percentile of its per-period amplitudes, the bar its 95 % interval.{screen}",
        count[Class::Periodic.index()],
        count[Class::QuasiPeriodic.index()],
        count[Class::Chaotic.index()],
        all - count[Class::Periodic.index()] - count[Class::QuasiPeriodic.index()] - count[Class::Chaotic.index()],
        crate::analysis::figures::unclassified_words(count[Class::Unclassified.index()])
    )
}

/// What the caption says of the points where the sweeps reached different motions.
pub(super) fn coexisting_words(both: usize, untold: usize, rows: usize) -> String {
    let told = match both {
        0 => "At no point did the sweeps reach motions that differ beyond their intervals".to_string(),
        _ => format!(
            "At {both} of the {rows} points drawn the sweeps reached two motions whose compliances differ beyond their intervals (coexisting attractors: the curve is the higher, the hollow diamond the lower; the table gives both, column `coexisting`)"
        ),
    };
    match untold {
        0 => format!("{told}."),
        _ => format!("{told}; at {untold} more they differ but an interval is not known (too short a record for its batches: `coexisting = cannot tell`)."),
    }
}

/// The lower of two coexisting motions at a design curve's points ([`Point::coexisting`]),
/// drawn as diamonds below the curve, the legend entry once (`labelled`).
fn lower_attractor(at: &[(f64, f64, Point)], color: usize, labelled: &mut Vec<&'static str>) -> Option<Series> {
    let both: Vec<&(f64, f64, Point)> = at.iter().filter(|p| p.2.coexisting(p.1) == Some(true)).collect();
    if both.is_empty() {
        return None;
    }
    const NAME: &str = "the other sweep's motion (coexisting)";
    let label = if labelled.contains(&NAME) {
        ""
    } else {
        labelled.push(NAME);
        NAME
    };
    Some(Series::points(
        label,
        both.iter().map(|p| p.0).collect(),
        both.iter().map(|p| p.2.lowest).collect(),
        color,
        Marker::Diamond,
    ))
}

/// A design curve's points that are not certified orbits (frequency, compliance, the point
/// behind it), drawn with their class's marker ([`super::figures::class_marker`]) and their
/// intervals as bars, each legend entry once (`labelled`).
fn class_points(at: &[(f64, f64, Point)], color: usize, labelled: &mut Vec<&'static str>) -> Vec<Series> {
    let mut label = |name: &'static str| {
        if labelled.contains(&name) {
            ""
        } else {
            labelled.push(name);
            name
        }
    };
    let irregular: Vec<&(f64, f64, Point)> = at.iter().filter(|p| p.2.class != Class::Periodic).collect();
    let mut out = Vec::new();
    for class in Class::ALL.iter().skip(1) {
        let mine: Vec<_> = irregular.iter().filter(|p| p.2.class == *class).collect();
        if mine.is_empty() {
            continue;
        }
        let (marker, name) = super::figures::class_marker(class.name());
        out.push(Series::points(
            label(name),
            mine.iter().map(|p| p.0).collect(),
            mine.iter().map(|p| p.1).collect(),
            color,
            marker,
        ));
    }
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (f, v, p) in irregular {
        if v.is_finite() && p.half_width.is_finite() && p.half_width > 0.0 {
            x.extend([*f, *f, f64::NAN]);
            y.extend([v - p.half_width, v + p.half_width, f64::NAN]);
        }
    }
    if !x.is_empty() {
        out.push(Series::line(label("95 % interval"), x, y, color));
    }
    out
}

/// The compliance over each band of the bare structure, the best layout and the cases (the
/// worst of the sweeps at each frequency): a long table and a figure of one panel per band.
pub(super) fn compliance_figure(
    exp: &Experiment,
    spec: &Spec,
    p: &Problem,
    best: &Found,
    cases: &[(String, Layout, Evaluation, u64)],
    bare: &Vec<Vec<Vec<f64>>>,
) -> (Table, Figure) {
    // The curves the evaluations computed (the first scenario's) and the bare structure's.
    let mut layouts: Vec<(String, &Vec<Vec<Vec<f64>>>)> = vec![("bare".into(), bare)];
    layouts.push((format!("best: {}", best.layout.hosts_words()), &best.evaluation.curves));
    layouts.extend(cases.iter().filter(|c| !c.1.hosts.is_empty()).map(|c| (format!("case {}", c.0), &c.2.curves)));
    // The points behind them (none for the bare structure, whose points are all orbits).
    let mut classes: Vec<Option<&Evaluation>> = vec![None, Some(&best.evaluation)];
    classes.extend(cases.iter().filter(|c| !c.1.hosts.is_empty()).map(|c| Some(&c.2)));
    // (layout, band, frequency, mass, compliance, the point behind it: the bare structure's
    // are certified orbits of a linear motion, one per frequency)
    let mut rows: Vec<(String, String, f64, i64, f64, Point)> = Vec::new();
    for (k, (label, curves)) in layouts.iter().enumerate() {
        for (b, (band, c)) in spec.bands.iter().zip(curves.iter()).enumerate() {
            for (i, (&f, r)) in band.freq_hz.iter().zip(c).enumerate() {
                for &m in &band.masses {
                    let behind = classes.get(k).copied().flatten().and_then(|e| e.points_class.get(b));
                    let point = behind.and_then(|p| p.get(i)).and_then(|p| p.get(m)).copied().unwrap_or_default();
                    rows.push((label.clone(), band.name.clone(), f, m as i64 + 1, r[m], point));
                }
            }
        }
    }
    let coexisting: Vec<Option<bool>> = rows.iter().map(|r| r.5.coexisting(r.4)).collect();
    let table = Table::new(
        "design_compliance",
        if exp.excitation.supports {
            "The compliance over each band (m/(m/s^2): amplitude relative to the supports per m/s^2 of their acceleration, the largest over the sweeps at each frequency; the column keeps its name) of the bare structure, the best layout and the experiment's cases, at each band's masses (1-based); the first scenario's; screened: 1 where a point with no certified orbit was measured over a short screen only (its interval, widened, below its band's highest point's: docs/design.md)"
        } else {
            "The compliance over each band (m/N: amplitude per newton of force amplitude, the largest over the sweeps at each frequency) of the bare structure, the best layout and the experiment's cases, at each band's masses (1-based); the first scenario's; screened: 1 where a point with no certified orbit was measured over a short screen only (its interval, widened, below its band's highest point's: docs/design.md)"
        },
    )
    .str("layout", rows.iter().map(|r| r.0.clone()).collect())
    .str("band", rows.iter().map(|r| r.1.clone()).collect())
    .f64("freq_hz", rows.iter().map(|r| r.2).collect())
    .i64("mass", rows.iter().map(|r| r.3).collect())
    .f64("compliance_m_per_n", rows.iter().map(|r| r.4).collect())
    .str("motion", rows.iter().map(|r| r.5.class.name().to_string()).collect())
    .f64("half_width_m_per_n", rows.iter().map(|r| r.5.half_width).collect())
    .i64("screened", rows.iter().map(|r| i64::from(r.5.screened)).collect())
    .f64("lowest_over_sweeps_m_per_n", rows.iter().map(|r| r.5.lowest).collect())
    .str("lowest_motion", rows.iter().map(|r| if r.5.lowest.is_nan() { String::new() } else { r.5.lowest_class.name().to_string() }).collect())
    .f64("lowest_half_width_m_per_n", rows.iter().map(|r| r.5.lowest_half_width).collect())
    .str(
        "coexisting",
        coexisting
            .iter()
            .map(|c| match c {
                Some(true) => "yes",
                Some(false) => "no",
                None => "cannot tell",
            })
            .map(String::from)
            .collect(),
    );
    let both = coexisting.iter().filter(|c| **c == Some(true)).count();
    let untold = coexisting.iter().filter(|c| c.is_none()).count();
    let panels = spec
        .bands
        .iter()
        .enumerate()
        .map(|(b, band)| {
            let mut panel = Panel::new(
                format!(
                    "{}: compliance of m{}",
                    band.name,
                    band.masses.iter().map(|m| (m + 1).to_string()).collect::<Vec<_>>().join(", m")
                ),
                "frequency (Hz)",
                format!("compliance ({})", exp.excitation.per_unit()),
                (band.freq_hz[0], band.freq_hz[band.freq_hz.len() - 1]),
            )
            .log_y();
            let mut labelled = Vec::new();
            for (k, (label, curves)) in layouts.iter().enumerate() {
                let Some(c) = curves.get(b) else { continue };
                for &m in &band.masses {
                    let y: Vec<f64> = c.iter().map(|r| r[m]).collect();
                    let name = if band.masses.len() > 1 { format!("{label}, m{}", m + 1) } else { label.clone() };
                    let s = Series::line(name, band.freq_hz.clone(), y.clone(), k);
                    panel.series.push(if k == 0 { s.dashed(Dash::Dashed) } else { s });
                    if let Some(points) = classes.get(k).copied().flatten().and_then(|e| e.points_class.get(b)) {
                        let at: Vec<(f64, f64, Point)> =
                            band.freq_hz.iter().zip(&y).zip(points).map(|((f, v), p)| (*f, *v, p[m])).collect();
                        panel.series.extend(class_points(&at, k, &mut labelled));
                        panel.series.extend(lower_attractor(&at, k, &mut labelled));
                    }
                }
            }
            panel
        })
        .collect();
    let first = p.cases()[0].name.clone();
    let figure = Figure {
        id: "design_compliance".into(),
        title: format!("{}: the best layout against the bare structure and the cases", exp.meta.figure),
        caption: format!(
            "Compliance over each band: the largest over the sweeps at each frequency (where motions coexist the structure may sit on either); scenario: {first}. {} {}",
            drawn_classes(&spec.bands, &classes),
            coexisting_words(both, untold, rows.len())
        ),
        panels,
    };
    (table, figure)
}
