//! The sentences of a study in the report and on the command line: where each claim holds, in
//! words, and how far a claim moves from the paper's bed. `analysis::study` computes the
//! numbers; this room writes them.

use crate::analysis::study::{deviations, ClaimRow, ClaimSummary};

/// The box around the samples where the claim holds, e.g. "damping 0.003-0.006,
/// clearance_mm 0.25-0.55" (`names`: the varied keys).
pub fn region_box(s: &ClaimSummary, names: &[String]) -> String {
    let fmt = crate::number::fmt_num;
    names
        .iter()
        .zip(&s.region)
        .map(
            |(n, (lo, hi))| {
                if lo == hi {
                    format!("{n} {}", fmt(*lo))
                } else {
                    format!("{n} {}-{}", fmt(*lo), fmt(*hi))
                }
            },
        )
        .collect::<Vec<_>>()
        .join(", ")
}

/// Where the claim holds, in words: "holds at 12/112 (damping 0.003-0.006, clearance_mm
/// 0.25-0.55)", "holds everywhere (9/9)", "holds nowhere (0/9; value 1.1-1.9)"; the counts
/// are of the samples where it can be evaluated on settled points, the others named after
/// them ("; 3 not evaluable; 1 on an unsettled point").
pub fn words(s: &ClaimSummary, names: &[String]) -> String {
    let fmt = crate::number::fmt_num;
    let n = s.evaluable();
    let mut apart = if s.not_evaluable > 0 { format!("; {} not evaluable", s.not_evaluable) } else { String::new() };
    if s.unsettled > 0 {
        apart += &format!(
            "; {} on {}",
            s.unsettled,
            if s.unsettled == 1 { "an unsettled point" } else { "unsettled points" }
        );
    }
    if n == 0 && s.unsettled > 0 {
        format!("not evaluable on settled points at any of {} samples{apart}", s.samples)
    } else if n == 0 {
        format!("not evaluable at any of {} samples", s.samples)
    } else if s.holds == n && apart.is_empty() {
        format!("holds everywhere ({}/{n})", s.holds)
    } else if s.holds == n {
        format!("holds wherever evaluable ({}/{n}{apart})", s.holds)
    } else if s.holds == 0 {
        format!("holds nowhere (0/{n}; value {}-{}{apart})", fmt(s.min), fmt(s.max))
    } else {
        format!("holds at {}/{n} ({}{apart})", s.holds, region_box(s, names))
    }
}

/// One sentence per claim over every model, e.g. "peak ratio single / triple, m2 (within
/// [2.5, 4]): stated chain: holds at 2/9 (damping 0.005, clearance_mm 0.3-0.4); ...".
/// `models`: (id, label) in order; `names`: the varied keys.
pub fn claim_sentences(models: &[(String, String)], names: &[String], summaries: &[ClaimSummary]) -> Vec<String> {
    let n_checks = summaries.iter().map(|s| s.check + 1).max().unwrap_or(0);
    (0..n_checks)
        .filter_map(|check| {
            let of: Vec<&ClaimSummary> = summaries.iter().filter(|s| s.check == check).collect();
            let first = of.first()?;
            let parts: Vec<String> = of
                .iter()
                .map(|s| {
                    let label = models.iter().find(|m| m.0 == s.model).map_or(s.model.as_str(), |m| m.1.as_str());
                    format!("{label}: {}", words(s, names))
                })
                .collect();
            Some(format!("{} ({}): {}", first.claim, first.bound, parts.join("; ")))
        })
        .collect()
}

/// A relative move in words: "3.5 %", "0.05 %" (the smallest shown).
fn percent(x: f64) -> String {
    format!("{} %", crate::number::fmt_num((1000.0 * x.max(5e-4)).round() / 10.0))
}

/// "up to 3.5 %", or "less than 0.05 %".
fn up_to(x: f64) -> String {
    if x < 5e-4 {
        "less than 0.05 %".into()
    } else {
        format!("up to {}", percent(x))
    }
}

/// One sentence per claim of a bed study: on each model, the claim's value with the paper's
/// bed (the first sample) and, per value of the first varied key, how far the other samples
/// move it and where (settled samples and unsettled ones apart).
pub fn deviation_sentences(models: &[(String, String)], names: &[String], rows: &[ClaimRow]) -> Vec<String> {
    let n_checks = rows.iter().map(|r| r.check + 1).max().unwrap_or(0);
    let at = |values: &[f64]| -> String {
        names
            .iter()
            .zip(values)
            .skip(1)
            .map(|(n, v)| format!("{n} {}", crate::number::fmt_num(*v)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    (0..n_checks)
        .filter_map(|check| {
            let claim = rows.iter().find(|r| r.check == check)?.claim.clone();
            let parts: Vec<String> = models
                .iter()
                .map(|(id, label)| match deviations(id, check, rows) {
                    None => format!("{label}: not evaluable with the paper's bed"),
                    Some((base, groups)) => {
                        let moves: Vec<String> = groups
                            .iter()
                            .map(|d| {
                                let mut words = Vec::new();
                                if let Some((x, v)) = &d.settled {
                                    words.push(format!("{} ({})", up_to(*x), at(v)));
                                }
                                if let Some((x, v)) = &d.unsettled {
                                    words.push(format!("{} on a point that did not settle ({})", percent(*x), at(v)));
                                }
                                if d.verdict_changes > 0 {
                                    words.push(format!(
                                        "the verdict changes at {} of {} samples",
                                        d.verdict_changes, d.samples
                                    ));
                                }
                                format!(
                                    "{} {}: {}",
                                    names.first().map_or("", String::as_str),
                                    crate::number::fmt_num(d.group),
                                    words.join(", ")
                                )
                            })
                            .collect();
                        let own = if names.len() > 2 {
                            format!(
                                " at the first sample (each sample against the paper's bed at its own {})",
                                names[2..].join(", ")
                            )
                        } else {
                            String::new()
                        };
                        format!(
                            "{label}: {} with the paper's bed{own}; {}",
                            crate::number::fmt_num(base),
                            moves.join("; ")
                        )
                    }
                })
                .collect();
            Some(format!("{claim}: {}", parts.join(". ")))
        })
        .collect()
}

/// The index's sentence for a bed study: per value of the first varied key, the largest move
/// of any claim on any model from the paper's bed on settled samples (and on unsettled ones
/// when larger).
pub fn deviation_summary(models: &[(String, String)], names: &[String], rows: &[ClaimRow]) -> String {
    let n_checks = rows.iter().map(|r| r.check + 1).max().unwrap_or(0);
    let mut worst: Vec<(f64, Option<f64>, Option<f64>)> = Vec::new(); // group, settled, unsettled
    let mut changes: Vec<(usize, usize)> = Vec::new(); // per group: verdict changes, samples
    for (id, _) in models {
        for check in 0..n_checks {
            let Some((_, groups)) = deviations(id, check, rows) else { continue };
            for d in groups {
                let i = match worst.iter().position(|w| w.0.to_bits() == d.group.to_bits()) {
                    Some(i) => i,
                    None => {
                        worst.push((d.group, None, None));
                        changes.push((0, 0));
                        worst.len() - 1
                    }
                };
                changes[i].0 += d.verdict_changes;
                changes[i].1 += d.samples;
                let max = |a: Option<f64>, b: Option<&(f64, Vec<f64>)>| match (a, b) {
                    (Some(a), Some((b, _))) => Some(a.max(*b)),
                    (a, b) => a.or(b.map(|x| x.0)),
                };
                worst[i].1 = max(worst[i].1, d.settled.as_ref());
                worst[i].2 = max(worst[i].2, d.unsettled.as_ref());
            }
        }
    }
    let name = names.first().map_or("", String::as_str);
    let parts: Vec<String> = worst
        .iter()
        .zip(&changes)
        .map(|((g, s, u), (changed, of))| {
            let settled = s.map_or("no settled sample".to_string(), |s| format!("by {}", up_to(s)));
            let unsettled = match (s, u) {
                (Some(s), Some(u)) if u > s => format!(" ({} on a point that did not settle)", percent(*u)),
                (None, Some(u)) => format!(" ({} on points that did not settle)", percent(*u)),
                _ => String::new(),
            };
            let verdicts = if *changed > 0 {
                format!(", the verdict changes at {changed} of {of} claim samples")
            } else {
                String::new()
            };
            format!("{name} {}: {settled}{unsettled}{verdicts}", crate::number::fmt_num(*g))
        })
        .collect();
    format!("the claims move from their values with the paper's bed: {}", parts.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::study::fixtures::grains_by_restitution;

    #[test]
    fn moves_from_the_paper_s_bed_in_words() {
        let rows = grains_by_restitution();
        let names = vec!["grains".to_string(), "restitution".to_string()];
        let models = vec![("stated".to_string(), "stated chain".to_string())];
        let s = deviation_sentences(&models, &names, &rows);
        assert_eq!(
            s,
            vec!["peak ratio: stated chain: 2 with the paper's bed; grains 1: up to 10 % (restitution 0.3), 50 % on a point that did not settle (restitution 0.6), the verdict changes at 1 of 2 samples; grains 10: up to 0.1 % (restitution 0.3)"]
        );
        assert_eq!(
            deviation_summary(&models, &names, &rows),
            "the claims move from their values with the paper's bed: grains 1: by up to 10 % (50 % on a point that did not settle), the verdict changes at 1 of 2 claim samples; grains 10: by up to 0.1 %"
        );
    }
}
