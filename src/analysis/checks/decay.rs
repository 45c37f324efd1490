//! Checks of impulse analyses: the early history against a reference history, envelope
//! decay times against those of a reference history (the same estimator on both), and the
//! paper's claim that three dampers decay faster, as a number.

use crate::checks::reference::Curve as RefCurve;
use crate::checks::{fmt_num, status, CheckOutcome, Source};
use crate::experiment::CheckSpec;
use crate::reference::values::{Quantity, ValueFile};

use super::super::evidence::Decay;
use super::super::impulse::decay_times;

fn provenance(spec: &CheckSpec) -> String {
    format!("independent solver: {} (reference/independent-solver/PROVENANCE.md)", spec.reference_file)
}

/// x, v and a of every mass over the first `window` seconds: the largest difference of each
/// column relative to that column's largest magnitude in the window.
pub fn history(spec: &CheckSpec, r: &RefCurve, d: &Decay, window: f64) -> CheckOutcome {
    let s = &d.run.samples;
    let Some(t_ref) = r.column("t") else { return CheckOutcome::missing(spec, "the reference has no column t") };
    let n = d.envelopes.len();
    let dt = s.times.get(1).map_or(f64::NAN, |t1| t1 - s.times[0]);
    let rows: Vec<(usize, usize)> = t_ref
        .iter()
        .enumerate()
        .filter(|(_, t)| **t <= window + 1e-12)
        .filter_map(|(k, &t)| {
            let i = (t / dt).round() as usize;
            (i < s.x.len() && (s.times[i] - t).abs() < 1e-9).then_some((k, i))
        })
        .collect();
    let wanted = t_ref.iter().filter(|t| **t <= window + 1e-12).count();
    let mut worst: Option<(f64, String, f64)> = None; // (relative, column, time)
    let mut columns = 0;
    for (name, pick) in [("x", 0), ("v", 1), ("a", 2)] {
        for m in 0..n {
            let col = format!("{name}{}", m + 1);
            let Some(theirs) = r.column(&col) else { continue };
            columns += 1;
            let scale = rows.iter().map(|&(k, _)| theirs[k].abs()).fold(0.0, f64::max);
            for &(k, i) in &rows {
                let ours = [&s.x, &s.v, &s.a][pick][i][m];
                let rel = (ours - theirs[k]).abs() / scale.max(f64::MIN_POSITIVE);
                if worst.as_ref().is_none_or(|w| rel > w.0) {
                    worst = Some((rel, col.clone(), t_ref[k]));
                }
            }
        }
    }
    let ok =
        rows.len() == wanted && wanted > 0 && columns > 0 && worst.as_ref().is_some_and(|w| w.0 <= spec.tolerance.rel);
    let mut detail = format!("{} reference samples in the first {} s, {columns} columns", rows.len(), fmt_num(window));
    if let Some((rel, col, t)) = &worst {
        detail += &format!("; worst: {col} at t = {} s ({rel:.2e} of the column's largest magnitude)", fmt_num(*t));
    }
    if rows.len() < wanted {
        detail += &format!("; {} reference times not sampled (sample rate differs)", wanted - rows.len());
    }
    let rel = worst.as_ref().map_or(f64::NAN, |w| w.0);
    CheckOutcome {
        settled: None,
        id: None,
        values: Vec::new(),
        name: format!("{} history vs {}", d.id, spec.reference_file),
        description: format!(
            "x, v, a of every mass of case {} ({}) over the first {} s",
            d.id,
            d.label,
            fmt_num(window)
        ),
        computed: rel,
        expected: 0.0,
        unit: "(largest relative difference)".into(),
        abs_diff: rel,
        rel_diff: rel,
        tolerance: format!("{} of each column's largest magnitude", fmt_num(spec.tolerance.rel)),
        status: status(ok, spec.known_deviation.is_some()),
        provenance: provenance(spec),
        source: Source::IndependentSolver,
        reason: spec.known_deviation.clone(),
        detail: Some(detail),
    }
}

/// One outcome per level: the decay time of mass `mass`'s acceleration envelope against the
/// same estimator on the reference history.
pub fn decay_time(spec: &CheckSpec, r: &RefCurve, d: &Decay, mass: usize, levels: &[f64]) -> Vec<CheckOutcome> {
    let (Some(t), Some(a)) = (r.column("t"), r.column(&format!("a{}", mass + 1))) else {
        return vec![CheckOutcome::missing(spec, "the reference has no columns t and a")];
    };
    let theirs = decay_times(t, a, levels);
    // Over the reference's span only: "falls for good" depends on how long one looks.
    let end = t.last().copied().unwrap_or(0.0) + 1e-9;
    let ours = {
        let s = &d.run.samples;
        let col: Vec<f64> =
            s.a.iter().zip(&s.times).take_while(|(_, t)| **t <= end).map(|(row, _)| row[mass]).collect();
        decay_times(&s.times[..col.len()], &col, levels)
    };
    levels
        .iter()
        .zip(ours.iter().zip(&theirs))
        .map(|(&l, (o, e))| {
            let (c, x) = (o.unwrap_or(f64::NAN), e.unwrap_or(f64::NAN));
            let abs = (c - x).abs();
            // Not reached within the reference's span on either side is agreement too.
            let within = abs <= spec.tolerance.abs + spec.tolerance.rel * x.abs() || (o.is_none() && e.is_none());
            CheckOutcome {
                settled: None,
                id: None,
                values: Vec::new(),
                name: format!("t_{}% a{} {}", fmt_num(100.0 * l), mass + 1, d.id),
                description: format!(
                    "time for the envelope of |a| at m{} of case {} to fall for good to {} % of its first peak",
                    mass + 1,
                    d.id,
                    fmt_num(100.0 * l)
                ),
                computed: c,
                expected: x,
                unit: "s".into(),
                abs_diff: abs,
                rel_diff: abs / x.abs(),
                tolerance: crate::checks::describe_tolerance(spec.tolerance),
                status: status(within, spec.known_deviation.is_some()),
                provenance: format!("{}; the same envelope estimator applied to its history", provenance(spec)),
                source: Source::IndependentSolver,
                reason: spec.known_deviation.clone(),
                detail: Some(match (o, e) {
                    (None, None) => format!("not reached within the reference's {} s on either side", fmt_num(end)),
                    (Some(_), None) | (None, Some(_)) => {
                        format!("reached within the reference's {} s on one side only", fmt_num(end))
                    }
                    _ => format!("over the reference's {} s", fmt_num(end)),
                }),
            }
        })
        .collect()
}

/// The decay time of `a` over that of `b` against an upper bound from the paper's text. When
/// `b` does not decay that far within the record, the ratio is at most `t_a / duration`.
pub fn ratio(
    spec: &CheckSpec,
    file: &ValueFile,
    bound: &Quantity,
    a: &Decay,
    b: &Decay,
    mass: usize,
    level: f64,
) -> CheckOutcome {
    let s = &a.run.samples;
    let duration = s.times.last().copied().unwrap_or(f64::NAN);
    let time = |d: &Decay| {
        let col: Vec<f64> = d.run.samples.a.iter().map(|row| row[mass]).collect();
        decay_times(&d.run.samples.times[..col.len()], &col, &[level])[0]
    };
    let upper = bound.value.unwrap_or(f64::NAN);
    let (ta, tb) = (time(a), time(b));
    let (value, words) = match (ta, tb) {
        (Some(x), Some(y)) => (x / y, format!("{} s / {} s", fmt_num(x), fmt_num(y))),
        (Some(x), None) => {
            (x / duration, format!("{} s / more than {} s (an upper bound)", fmt_num(x), fmt_num(duration)))
        }
        _ => (f64::NAN, "case did not decay that far within the record".to_string()),
    };
    let within = value <= upper * (1.0 + spec.tolerance.rel);
    CheckOutcome {
        settled: None,
        id: None,
        values: Vec::new(),
        name: format!("decay ratio {} / {}, a{} to {} %", a.id, b.id, mass + 1, fmt_num(100.0 * level)),
        description: format!(
            "time for |a| at m{} to fall to {} % of its first peak with case {} over case {}",
            mass + 1,
            fmt_num(100.0 * level),
            a.id,
            b.id
        ),
        computed: value,
        expected: upper,
        unit: String::new(),
        abs_diff: (value - upper).abs(),
        rel_diff: (value - upper).abs() / upper,
        tolerance: format!("at most {}", fmt_num(upper)),
        status: status(within, spec.known_deviation.is_some()),
        provenance: file.provenance(bound),
        source: Source::from_provenance(&file.meta.provenance),
        reason: spec.known_deviation.clone(),
        detail: Some(format!("{words}: {} takes {:.0} % of the time of {}", a.label, 100.0 * value, b.label)),
    }
}
