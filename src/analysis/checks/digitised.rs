//! Checks against curves digitised from the paper's figures: a tube around the digitised
//! curve, and the frequency and height of a resonance peak, with tolerances in pixels of the
//! digitised figure (its calibration gives their size) plus the check's own tolerance.

use crate::checks::tube::{peak, tube, AxisTol};
use crate::checks::{fmt_num, status, CheckOutcome, Source};
use crate::experiment::CheckSpec;
use crate::reference::digitised::{DigitisedCurve, DigitisedFile};

use super::super::curves::Curve;

/// The tolerances of a check: `x_px` and `y_px` pixels, plus the check's tolerance on y.
pub fn tolerances(file: &DigitisedFile, spec: &CheckSpec, x_px: f64, y_px: f64) -> (AxisTol, AxisTol) {
    let m = &file.meta;
    let x = if m.x_log {
        AxisTol { abs: 0.0, rel: x_px * m.x_pixel, log: true }
    } else {
        AxisTol { abs: x_px * m.x_pixel, rel: 0.0, log: false }
    };
    let y = if m.y_log {
        AxisTol { abs: 0.0, rel: y_px * m.y_pixel + spec.tolerance.rel, log: true }
    } else {
        AxisTol { abs: y_px * m.y_pixel + spec.tolerance.abs, rel: spec.tolerance.rel, log: false }
    };
    (x, y)
}

/// The settled, period-1 points of a computed curve for one mass.
pub fn computed_points(c: &Curve, mass: usize) -> Vec<(f64, f64)> {
    (0..c.freq_hz.len()).filter(|&i| c.regular(i)).map(|i| (c.freq_hz[i], c.compliance[i][mass])).collect()
}

fn provenance(file: &DigitisedFile, spec: &CheckSpec, d: &DigitisedCurve) -> String {
    let m = &file.meta;
    format!(
        "digitised figure: {} {}, curve \"{}\", from {} by {} ({}, {})",
        m.figure, spec.reference_file, d.name, m.source, m.digitised_by, m.tool, m.imported_from
    )
}

fn words(t: &AxisTol, unit: &str) -> String {
    if t.log {
        format!("{:.2} %", 100.0 * t.rel)
    } else if t.rel > 0.0 {
        format!("{} {unit} + {:.2} %", fmt_num(t.abs), 100.0 * t.rel)
    } else {
        format!("{} {unit}", fmt_num(t.abs))
    }
}

/// The tube check (settled when every point of the computed curve is settled and period-1:
/// the tube skips the others).
pub fn tube_check(
    spec: &CheckSpec,
    file: &DigitisedFile,
    d: &DigitisedCurve,
    c: &Curve,
    mass: usize,
    x_px: f64,
    y_px: f64,
) -> CheckOutcome {
    let (xt, yt) = tolerances(file, spec, x_px, y_px);
    let reference: Vec<(f64, f64)> = d.x.iter().copied().zip(d.y.iter().copied()).collect();
    let r = tube(&reference, &computed_points(c, mass), xt, yt);
    let worst = r.worst.map_or(f64::NAN, |w| w.excess);
    let mut detail = format!(
        "{} of {} digitised points inside the tube (x within {} = {x_px} px, y within {} = {y_px} px{})",
        r.inside,
        r.total,
        words(&xt, &file.meta.x_unit),
        words(&yt, &file.meta.y_unit),
        if spec.tolerance.rel > 0.0 || spec.tolerance.abs > 0.0 { " plus the check's tolerance" } else { "" }
    );
    if let Some(w) = r.worst {
        detail += &format!(
            "; worst at {} {}: digitised {} {}, computed {} to {} there ({:.2} tolerances out)",
            fmt_num(w.x),
            file.meta.x_unit,
            fmt_num(w.y),
            file.meta.y_unit,
            fmt_num(w.computed.0),
            fmt_num(w.computed.1),
            w.excess
        );
    }
    if r.uncovered > 0 {
        detail += &format!("; {} digitised points outside the computed range", r.uncovered);
    }
    CheckOutcome {
        settled: Some((0..c.freq_hz.len()).all(|i| c.regular(i))),
        id: None,
        values: Vec::new(),
        name: format!("{} m{} vs digitised \"{}\"", c.id, mass + 1, d.name),
        description: format!(
            "compliance of m{} of curve {} ({}) within a tube around the digitised curve",
            mass + 1,
            c.id,
            c.label
        ),
        computed: worst,
        expected: 0.0,
        unit: "(tolerances out, worst point)".into(),
        abs_diff: worst,
        rel_diff: worst,
        tolerance: "every point inside (0 tolerances out)".into(),
        status: status(r.pass(), spec.known_deviation.is_some()),
        provenance: provenance(file, spec, d),
        source: Source::DigitisedFigure,
        reason: spec.known_deviation.clone(),
        detail: Some(detail),
    }
}

/// The peak check: two outcomes, the frequency and the height.
#[allow(clippy::too_many_arguments)]
pub fn peak_check(
    spec: &CheckSpec,
    file: &DigitisedFile,
    d: &DigitisedCurve,
    c: &Curve,
    mass: usize,
    window: (f64, f64),
    x_px: f64,
    y_px: f64,
) -> Vec<CheckOutcome> {
    let (xt, yt) = tolerances(file, spec, x_px, y_px);
    let reference: Vec<(f64, f64)> = d.x.iter().copied().zip(d.y.iter().copied()).collect();
    let (Some(theirs), Some(ours)) =
        (peak(&reference, window.0, window.1), peak(&computed_points(c, mass), window.0, window.1))
    else {
        return vec![CheckOutcome::missing(spec, "no point of a curve in the window")];
    };
    let w = format!("{}-{} Hz", fmt_num(window.0), fmt_num(window.1));
    // The peak of the settled, period-1 points: settled when no other point of the window
    // is higher.
    let settled = (0..c.freq_hz.len()).all(|i| {
        let f = c.freq_hz[i];
        c.regular(i) || f < window.0 || f > window.1 || super::super::curves::not_above(c.compliance[i][mass], ours.1)
    });
    let one = |what: &str, o: f64, e: f64, t: &AxisTol, unit: &str| {
        let (lo, hi) = t.interval(e);
        let ok = o >= lo && o <= hi;
        CheckOutcome {
            settled: Some(settled),
            id: None,
            values: Vec::new(),
            name: format!("{} m{} peak {what} in {w} vs digitised \"{}\"", c.id, mass + 1, d.name),
            description: format!("resonance peak {what} of m{} of curve {} in {w}", mass + 1, c.id),
            computed: o,
            expected: e,
            unit: unit.to_string(),
            abs_diff: (o - e).abs(),
            rel_diff: (o - e).abs() / e.abs(),
            tolerance: format!("within {}", words(t, unit)),
            status: status(ok, spec.known_deviation.is_some()),
            provenance: provenance(file, spec, d),
            source: Source::DigitisedFigure,
            reason: spec.known_deviation.clone(),
            detail: None,
        }
    };
    vec![
        one("frequency", ours.0, theirs.0, &xt, &file.meta.x_unit),
        one("height", ours.1, theirs.1, &yt, &file.meta.y_unit),
    ]
}
