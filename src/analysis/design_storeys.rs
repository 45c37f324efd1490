//! A design on moving supports: each storey's drift and each floor's absolute acceleration
//! over the bands, bare and with the best layout (docs/design.md, "Storey drift and floor
//! acceleration"): what an engineer checks on a building besides the displacements the
//! objective measures. The bare structure's are exact ([`crate::model::frf::support_peaks_curve`]);
//! the best layout's are simulated over the design's sweeps, the largest of them at each
//! frequency (one evaluation of the layout, after the search).

use crate::design::{Problem, Spec};
use crate::figure::{Dash, Figure, Marker, Panel, Series};
use crate::number::fmt_sig;
use crate::sim::settle::sweep::{self, Direction, SweepPoint};
use crate::sim::SteadyOptions;
use crate::table::Table;

/// Per frequency: each storey's drift amplitude and each floor's absolute acceleration
/// amplitude over the drive (NaN where a point could not be computed).
type Peaks = Vec<(Vec<f64>, Vec<f64>)>;

/// A row of the table: layout, band, frequency (Hz), the storeys' drifts, the floors'
/// accelerations (per unit drive).
type Row = (String, String, f64, Vec<f64>, Vec<f64>);

/// The table `design_storeys`, its figure and a sentence for the answer (the largest drift
/// in mm and floor acceleration in g, with the shot and bare) for the best layout (`label`,
/// `dampers`) when the design's supports move; `None` under a force.
pub fn storeys(
    p: &Problem,
    spec: &Spec,
    label: &str,
    dampers: Vec<crate::model::Damper>,
    figure: &str,
) -> Option<(Table, Figure, String)> {
    if !p.supports {
        return None;
    }
    let sc = &p.cases()[0];
    let bare_sys = p.system(sc, Vec::new());
    let with = p.system(sc, dampers);
    let steady = SteadyOptions { peaks: true, ..p.steady };
    let mut rows: Vec<Row> = Vec::new();
    let mass = bare_sys.structure.mass_matrix();
    for band in &spec.bands {
        let omegas: Vec<f64> = band.freq_hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
        let bare = crate::model::frf::support_peaks_curve(&bare_sys.structure, &mass, &omegas);
        let best = simulated(&with, &band.freq_hz, &p.sweeps, &steady, sc.force);
        for (layout, peaks) in [("bare", &bare), (label, &best)] {
            for (&f, (d, a)) in band.freq_hz.iter().zip(peaks) {
                rows.push((layout.to_string(), band.name.clone(), f, d.clone(), a.clone()));
            }
        }
    }
    let storeys = rows.iter().map(|r| r.3.len()).max().unwrap_or(0);
    let floors = rows.iter().map(|r| r.4.len()).max().unwrap_or(0);
    let a = p.drive().symbol();
    let mut table = Table::new(
        "design_storeys",
        format!(
            "On moving supports, over the bands: each storey's drift amplitude over {a} (drift1..: a floor's displacement less the one below, the first storey's less the ground's; s^2) and each floor's absolute acceleration amplitude over {a} (acc1..; 1: the ground's own), for the bare structure (exact) and the best layout (simulated over the design's sweeps, the largest at each frequency; a point with no certified orbit gives the largest over its measured record). The accelerations are those between impacts: an impact is instantaneous in the model."
        ),
    )
    .str("layout", rows.iter().map(|r| r.0.clone()).collect())
    .str("band", rows.iter().map(|r| r.1.clone()).collect())
    .f64("freq_hz", rows.iter().map(|r| r.2).collect());
    let at = |v: &Vec<f64>, i: usize| v.get(i).copied().unwrap_or(f64::NAN);
    for i in 0..storeys {
        table = table.f64(format!("drift{}", i + 1), rows.iter().map(|r| at(&r.3, i)).collect());
    }
    for i in 0..floors {
        table = table.f64(format!("acc{}", i + 1), rows.iter().map(|r| at(&r.4, i)).collect());
    }
    // The figure: the largest drift over the storeys and the largest acceleration over the
    // floors, against frequency, bare and with the best layout.
    let largest = |v: &Vec<f64>| v.iter().copied().filter(|x| x.is_finite()).fold(f64::NAN, f64::max);
    let lo = spec.bands.iter().flat_map(|b| b.freq_hz.first().copied()).fold(f64::INFINITY, f64::min);
    let hi = spec.bands.iter().flat_map(|b| b.freq_hz.last().copied()).fold(0.0, f64::max);
    let mut panels = Vec::new();
    let mut peak_words = Vec::new();
    for (drift, title, y_label) in [
        (true, "the largest storey drift", format!("drift amplitude / {a} (s^2)")),
        (false, "the largest floor acceleration", format!("absolute acceleration amplitude / {a}")),
    ] {
        if drift && storeys == 0 {
            continue;
        }
        let mut panel = Panel::new(title, "forcing frequency (Hz)", y_label, (lo, hi));
        let mut tops = Vec::new();
        for (k, layout) in ["bare", label].iter().enumerate() {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.0 == *layout).collect();
            let x: Vec<f64> = mine.iter().map(|r| r.2).collect();
            let y: Vec<f64> = mine.iter().map(|r| largest(if drift { &r.3 } else { &r.4 })).collect();
            tops.push(y.iter().copied().filter(|v| v.is_finite()).fold(0.0, f64::max));
            let mut s = Series::line(layout.to_string(), x, y, k);
            if k == 0 {
                s = s.dashed(Dash::Dashed);
            } else {
                s.marker = Marker::Circle;
            }
            panel.series.push(s);
        }
        peak_words.push(format!(
            "the {} {} of the bare structure's",
            if drift { "largest drift" } else { "largest floor acceleration" },
            if tops[0] > 0.0 {
                format!("{} times", fmt_sig(tops[1] / tops[0], 2))
            } else {
                "(no bare value)".to_string()
            }
        ));
        panels.push(panel);
    }
    // The answer's sentence: the largest over the bands, in physical units at the drive.
    let top = |layout: &str, drift: bool| {
        rows.iter()
            .filter(|r| r.0 == layout)
            .flat_map(|r| {
                let v = if drift { &r.3 } else { &r.4 };
                v.iter().enumerate().map(move |(i, x)| (*x, i, r.2))
            })
            .filter(|x| x.0.is_finite())
            .fold((f64::NAN, 0, 0.0), |a, b| if a.0.is_nan() || b.0 > a.0 { b } else { a })
    };
    let force = p.cases()[0].force;
    let said = |x: (f64, usize, f64), drift: bool| {
        if drift {
            format!("{} mm (storey {} at {} Hz)", fmt_sig(1e3 * x.0 * force, 3), x.1 + 1, fmt_sig(x.2, 4))
        } else {
            format!(
                "{} g (floor {} at {} Hz)",
                fmt_sig(x.0 * force / crate::model::GRAVITY, 3),
                x.1 + 1,
                fmt_sig(x.2, 4)
            )
        }
    };
    let mut parts = Vec::new();
    if storeys > 0 {
        parts.push(format!(
            "its largest storey drift is {} against {} bare",
            said(top(label, true), true),
            said(top("bare", true), true)
        ));
    }
    parts.push(format!(
        "its largest absolute floor acceleration {} against {} bare",
        said(top(label, false), false),
        said(top("bare", false), false)
    ));
    let sentence = format!(" On the moving supports {} (design_storeys).", parts.join(", and "));
    let figure = Figure {
        id: "design_storeys".into(),
        title: format!("{figure}: storey drift and floor acceleration"),
        caption: format!(
            "On moving supports, the largest storey drift and the largest floor acceleration over the bands against frequency: bare (exact, dashed) and with the best layout ({label}; simulated, the largest over the design's sweeps). Over the bands the best layout's peak of {} (design_storeys). The accelerations are those between impacts: each impact's velocity jump sets the floors' higher modes going, which shows in the acceleration more than in the drift.",
            peak_words.join(" and ")
        ),
        panels,
    };
    Some((table, figure, sentence))
}

/// The best layout's drifts and accelerations over a band's frequencies: the largest over
/// the design's sweeps at each frequency, per unit drive `per`.
fn simulated(
    sys: &crate::sim::System,
    freq_hz: &[f64],
    sweeps: &[crate::design::Sweep],
    steady: &SteadyOptions,
    per: f64,
) -> Peaks {
    let mut out: Peaks = vec![(Vec::new(), Vec::new()); freq_hz.len()];
    for s in sweeps {
        let points: Vec<SweepPoint> = match s {
            crate::design::Sweep::Rest => sweep::from_rest(sys, freq_hz, steady, &|| {}),
            crate::design::Sweep::Up => sweep::continued(sys, freq_hz, Direction::Up, steady, &|| {}),
            crate::design::Sweep::Down => sweep::continued(sys, freq_hz, Direction::Down, steady, &|| {}),
        };
        for pt in points {
            let Some(i) = freq_hz.iter().position(|f| *f == pt.freq_hz) else { continue };
            let Some(peaks) = pt.result.ok().and_then(|st| st.peaks) else { continue };
            let wider = |have: &mut Vec<f64>, new: &[f64]| {
                have.resize(new.len().max(have.len()), f64::NAN);
                for (h, v) in have.iter_mut().zip(new) {
                    let v = v / per;
                    *h = if h.is_nan() { v } else { h.max(v) };
                }
            };
            wider(&mut out[i].0, &peaks.drift);
            wider(&mut out[i].1, &peaks.acceleration);
        }
    }
    out
}
