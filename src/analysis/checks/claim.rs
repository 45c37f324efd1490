//! Claims of the paper's text about ratios of resonance peaks, each checked as a number with
//! the value shown: a ratio within a range or beyond a bound, and an ordering of two ratios.

use crate::checks::{fmt_num, status, CheckOutcome, Source};
use crate::experiment::{Bound, CheckSpec, Reading};
use crate::reference::values::{Quantity, ValueFile};

use super::super::curves::{not_above, Curves};

fn window_words(w: Option<(f64, f64)>) -> String {
    match w {
        Some((a, b)) => format!(" in {}-{} Hz", fmt_num(a), fmt_num(b)),
        None => String::new(),
    }
}

/// A claimed quantity as read from the curves: its value, in words, and whether it rests only
/// on settled points ([`CheckOutcome::settled`]).
struct Read {
    value: f64,
    words: String,
    settled: bool,
    /// Named values behind it (`{ID.NAME}` in texts).
    values: Vec<(String, f64)>,
}

fn named(v: &[(&str, f64)]) -> Vec<(String, f64)> {
    v.iter().map(|(n, x)| (n.to_string(), *x)).collect()
}

/// The peak of `case` over that of `over` in a window.
fn ratio(curves: &Curves, (case, over): (&str, &str), mass: usize, w: Option<(f64, f64)>) -> Option<Read> {
    let (ca, cb) = (curves.of_case(case)?, curves.of_case(over)?);
    let (a, b) = (ca.peak_in(mass, w)?, cb.peak_in(mass, w)?);
    Some(Read {
        value: a.1 / b.1,
        words: format!(
            "{case}: {} {unit} at {} Hz over {over}: {} {unit} at {} Hz",
            fmt_num(a.1),
            fmt_num(a.0),
            fmt_num(b.1),
            fmt_num(b.0),
            unit = curves.unit()
        ),
        settled: ca.peak_settled(mass, w) && cb.peak_settled(mass, w),
        values: named(&[("f", a.0), ("peak", a.1), ("f_over", b.0), ("peak_over", b.1)]),
    })
}

/// Both curves at the frequency of `case`'s peak. The curves share their grid.
fn at_resonance(curves: &Curves, (case, over): (&str, &str), mass: usize, w: Option<(f64, f64)>) -> Option<Read> {
    let (a, b) = (curves.of_case(case)?, curves.of_case(over)?);
    let (f, peak) = a.peak_in(mass, w)?;
    let j = b.freq_hz.iter().position(|x| *x == f)?;
    let c = b.compliance[j][mass];
    let settled = a.peak_settled(mass, w) && b.regular(j);
    Some(Read {
        value: peak / c,
        words: format!(
            "at {case}'s peak, {} Hz: {case} {} {unit} over {over} {} {unit}{}",
            fmt_num(f),
            fmt_num(peak),
            fmt_num(c),
            if settled { "" } else { " (not settled or not period-1 there)" },
            unit = curves.unit()
        ),
        settled,
        values: named(&[("f", f), ("peak", peak), ("at_over", c)]),
    })
}

/// The largest ratio at one frequency over the band where `case` is at least 1/sqrt(2) of its
/// peak (settled, period-1 points of both). Settled when the points skipped in the band (not
/// settled or not period-1 on either curve) would not raise it.
fn band_max(curves: &Curves, (case, over): (&str, &str), mass: usize, w: Option<(f64, f64)>) -> Option<Read> {
    let (a, b) = (curves.of_case(case)?, curves.of_case(over)?);
    let (_, peak) = a.peak_in(mass, w)?;
    let inside = |f: f64| w.is_none_or(|(lo, hi)| f >= lo && f <= hi);
    let mut ratios: Vec<(f64, f64)> = Vec::new();
    let mut skipped: Vec<(f64, f64)> = Vec::new();
    for (i, &f) in a.freq_hz.iter().enumerate() {
        let ca = a.compliance[i][mass];
        if !(inside(f) && ca >= peak / std::f64::consts::SQRT_2) {
            continue;
        }
        let Some(j) = b.freq_hz.iter().position(|x| *x == f) else { continue };
        let r = (f, ca / b.compliance[j][mass]);
        if a.regular(i) && b.regular(j) {
            ratios.push(r);
        } else {
            skipped.push(r);
        }
    }
    let (lo, hi) = (ratios.first()?.0, ratios.last()?.0);
    let min = ratios.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
    let &(f_max, max) = ratios.iter().max_by(|x, y| x.1.total_cmp(&y.1))?;
    let raised: Vec<&(f64, f64)> = skipped.iter().filter(|r| !not_above(r.1, max)).collect();
    let mut words = format!(
        "{case} over {over} at each of {} frequencies of {case}'s resonance band ({}-{} Hz): {:.2} to {:.2}, largest at {} Hz",
        ratios.len(),
        fmt_num(lo),
        fmt_num(hi),
        min,
        max,
        fmt_num(f_max)
    );
    if let Some(top) = raised.iter().max_by(|x, y| x.1.total_cmp(&y.1)) {
        words += &format!(
            "; {} point(s) of the band skipped as not settled or not period-1 would raise it (to {:.2} at {} Hz)",
            raised.len(),
            top.1,
            fmt_num(top.0)
        );
    }
    Some(Read {
        value: max,
        words,
        settled: a.peak_settled(mass, w) && raised.is_empty(),
        values: named(&[("f", f_max), ("band_lo", lo), ("band_hi", hi), ("min", min)]),
    })
}

/// The name of a ratio claim under a reading.
fn claim_name(reading: Reading, cases: (&str, &str), mass: usize, window: Option<(f64, f64)>) -> String {
    let (a, b, m, w) = (cases.0, cases.1, mass + 1, window_words(window));
    match reading {
        Reading::PeakOverPeak => format!("peak ratio {a} / {b}, m{m}{w}"),
        Reading::AtResonance => format!("ratio {a} / {b} at {a}'s resonance, m{m}{w}"),
        Reading::BandMax => format!("largest ratio {a} / {b} over {a}'s resonance band, m{m}{w}"),
    }
}

/// A ratio of two responses, read as `reading`, against a bound (a range, at most or at least
/// a value; `rel_tol` is slack).
#[allow(clippy::too_many_arguments)]
pub fn peak_ratio(
    spec: &CheckSpec,
    file: &ValueFile,
    curves: &Curves,
    cases: (&str, &str),
    mass: usize,
    bound: &Bound,
    window: Option<(f64, f64)>,
    reading: Reading,
) -> CheckOutcome {
    let Some(first) = spec.quantity(file) else { return CheckOutcome::missing(spec, "bound not found") };
    let computed = match reading {
        Reading::PeakOverPeak => ratio(curves, cases, mass, window),
        Reading::AtResonance => at_resonance(curves, cases, mass, window),
        Reading::BandMax => band_max(curves, cases, mass, window),
    };
    let Some(Read { value: r, words, settled, values }) = computed else {
        // Not evaluable here (a study's sample may have no settled point where the reading
        // looks): named as the claim, with the reason.
        let mut o = CheckOutcome::missing(spec, "");
        o.name = claim_name(reading, cases, mass, window);
        o.description = format!(
            "not evaluable: the reading ({}) needs settled period-1 points of {} and {} at m{}{}, and there are none where it looks",
            reading.name(),
            cases.0,
            cases.1,
            mass + 1,
            window_words(window)
        );
        return o;
    };
    let v = first.value.unwrap_or(f64::NAN);
    let slack = spec.tolerance.rel;
    let (ok, expected, tolerance, paper) = match bound {
        Bound::Within { upper_id } => {
            let Some(hi) = file.get(upper_id).and_then(|q| q.value) else {
                return CheckOutcome::missing(spec, "upper bound not found");
            };
            (
                r >= v * (1.0 - slack) && r <= hi * (1.0 + slack),
                0.5 * (v + hi),
                format!("within [{}, {}]", fmt_num(v), fmt_num(hi)),
                format!("paper: a factor 1/{} to 1/{}; computed 1/{:.2}", fmt_num(v), fmt_num(hi), r),
            )
        }
        Bound::AtMost => (r <= v * (1.0 + slack), v, format!("at most {}", fmt_num(v)), format!("computed {r:.3}")),
        Bound::AtLeast => (r >= v * (1.0 - slack), v, format!("at least {}", fmt_num(v)), format!("computed {r:.3}")),
    };
    let tolerance = if slack > 0.0 { format!("{tolerance} +/- {:.1} %", 100.0 * slack) } else { tolerance };
    let name = claim_name(reading, cases, mass, window);
    let description = match reading {
        Reading::PeakOverPeak => {
            format!("peak compliance of m{}{} (reading: peak over peak): {words}", mass + 1, window_words(window))
        }
        Reading::AtResonance => format!(
            "compliance of m{}{} (reading: both at {}'s resonance): {words}",
            mass + 1,
            window_words(window),
            cases.0
        ),
        Reading::BandMax => format!(
            "compliance of m{}{} (reading: the largest reduction at one frequency around resonance): {words}",
            mass + 1,
            window_words(window)
        ),
    };
    CheckOutcome {
        settled: Some(settled),
        id: None,
        values,
        name,
        description,
        computed: r,
        expected,
        unit: String::new(),
        abs_diff: (r - expected).abs(),
        rel_diff: (r - expected).abs() / expected.abs(),
        tolerance,
        status: status(ok, spec.known_deviation.is_some()),
        provenance: file.provenance(first),
        source: Source::from_provenance(&file.meta.provenance),
        reason: spec.known_deviation.clone(),
        detail: Some(format!("{paper}; \"{}\"", first.quote)),
    }
}

/// The peak ratio in `window` smaller than in `than`.
pub fn ratio_order(
    spec: &CheckSpec,
    file: &ValueFile,
    curves: &Curves,
    cases: (&str, &str),
    mass: usize,
    window: (f64, f64),
    than: (f64, f64),
) -> CheckOutcome {
    let Some(claim) = spec.quantity(file) else { return CheckOutcome::missing(spec, "claim not found") };
    let (Some(ra), Some(rb)) = (ratio(curves, cases, mass, Some(window)), ratio(curves, cases, mass, Some(than)))
    else {
        return CheckOutcome::missing(spec, "curves not computed");
    };
    let (a, wa, b, wb) = (ra.value, ra.words, rb.value, rb.words);
    CheckOutcome {
        settled: Some(ra.settled && rb.settled),
        id: None,
        values: Vec::new(),
        name: format!(
            "{} / {} at m{}: {}-{} Hz below {}-{} Hz",
            cases.0,
            cases.1,
            mass + 1,
            fmt_num(window.0),
            fmt_num(window.1),
            fmt_num(than.0),
            fmt_num(than.1)
        ),
        description: format!(
            "the peak ratio{} ({wa}) is smaller than{} ({wb})",
            window_words(Some(window)),
            window_words(Some(than))
        ),
        computed: a,
        expected: b,
        unit: "(ratio)".into(),
        abs_diff: (a - b).abs(),
        rel_diff: (a - b).abs() / b.abs(),
        tolerance: format!("smaller than {}", fmt_num(b)),
        status: status(a < b, spec.known_deviation.is_some()),
        provenance: file.provenance(claim),
        source: Source::from_provenance(&file.meta.provenance),
        reason: spec.known_deviation.clone(),
        detail: Some(format!("computed {a:.3} against {b:.3}")),
    }
}

/// The motion types seen in a case's waveforms include every type of `present` and none of
/// `absent`.
pub fn motion_types(
    spec: &CheckSpec,
    file: &ValueFile,
    claim: &Quantity,
    case: &str,
    seen: Option<&Vec<String>>,
    present: &[String],
    absent: &[String],
) -> CheckOutcome {
    let seen = seen.cloned().unwrap_or_default();
    let count = |t: &String| seen.iter().filter(|s| *s == t).count();
    let missing_types: Vec<&String> = present.iter().filter(|t| count(t) == 0).collect();
    let unwanted: Vec<&String> = absent.iter().filter(|t| count(t) > 0).collect();
    let ok = !seen.is_empty() && missing_types.is_empty() && unwanted.is_empty();
    let mut want = Vec::new();
    if !present.is_empty() {
        want.push(format!("Type {} present", present.join(", ")));
    }
    if !absent.is_empty() {
        want.push(format!("Type {} absent", absent.join(", ")));
    }
    let occurrences = present.iter().chain(absent).map(|t| count(t) as f64).sum::<f64>();
    CheckOutcome {
        settled: None,
        id: None,
        values: Vec::new(),
        name: format!("motion types of {case}: {}", want.join("; ")),
        description: format!(
            "the motion types of the beds of case {case} at the waveform frequencies: {}",
            seen.join(", ")
        ),
        computed: occurrences,
        expected: f64::NAN,
        unit: "(occurrences of the types named)".into(),
        abs_diff: f64::NAN,
        rel_diff: f64::NAN,
        tolerance: want.join("; "),
        status: status(ok, spec.known_deviation.is_some()),
        provenance: file.provenance(claim),
        source: Source::from_provenance(&file.meta.provenance),
        reason: spec.known_deviation.clone(),
        detail: Some(format!("seen: {}", seen.join(", "))),
    }
}
