//! A study's answer per sample (docs/studies.md, "Joint studies"): at each sample, how many of
//! the claims that can be evaluated on settled points hold, and which fail, by how much. For a
//! joint study this is the question a replication asks: under which one setup of the values
//! the paper leaves unstated does the most of the paper hold at once.

use crate::experiment::study::stored::{StoredModel, StoredSample, StoredStudy, BEST_STORED};
use crate::number::fmt_num;
use crate::table::Table;

use super::study::{ClaimRow, Verdict};

/// One sample's count.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleSummary {
    /// 0-based sample.
    pub sample: usize,
    /// Its model.
    pub model: String,
    /// Its values, in the order of the study's `vary`.
    pub values: Vec<f64>,
    /// Claims at the sample.
    pub claims: usize,
    /// Claims that can be evaluated on settled points.
    pub evaluable: usize,
    /// Of those, the claims that hold.
    pub holds: usize,
    /// Claims whose value rests on a point that did not settle (counted apart).
    pub unsettled: usize,
    /// Claims that cannot be evaluated here.
    pub not_evaluable: usize,
    /// The claims that fail on settled points, each with its value and the paper's bound.
    pub failing: Vec<String>,
}

/// Per sample, in sample order (`rows` sorted by sample, as the long table is).
pub fn per_sample(rows: &[ClaimRow]) -> Vec<SampleSummary> {
    let mut out: Vec<SampleSummary> = Vec::new();
    for r in rows {
        if out.last().is_none_or(|s| s.sample != r.sample) {
            out.push(SampleSummary {
                sample: r.sample,
                model: r.model.clone(),
                values: r.values.clone(),
                claims: 0,
                evaluable: 0,
                holds: 0,
                unsettled: 0,
                not_evaluable: 0,
                failing: Vec::new(),
            });
        }
        let Some(s) = out.last_mut() else { continue };
        s.claims += 1;
        if r.outcome == Verdict::NotEvaluable {
            s.not_evaluable += 1;
        } else if r.unsettled() {
            s.unsettled += 1;
        } else {
            s.evaluable += 1;
            if r.holds() {
                s.holds += 1;
            } else {
                s.failing.push(format!("{} = {} ({})", r.claim, fmt_num(r.value), r.bound));
            }
        }
    }
    out
}

/// The samples where the most claims hold (of those evaluable on settled points), in sample
/// order; none when no claim can be evaluated anywhere.
pub fn best(summaries: &[SampleSummary]) -> Vec<&SampleSummary> {
    let most = summaries.iter().filter(|s| s.evaluable > 0).map(|s| s.holds).max();
    match most {
        Some(m) => summaries.iter().filter(|s| s.evaluable > 0 && s.holds == m).collect(),
        None => Vec::new(),
    }
}

/// A study's stored answer from its samples' counts: per model (`models`, in order), the
/// samples where the most claims hold (at most [`BEST_STORED`]) and how many hold every claim.
pub fn stored(
    study: &str,
    fingerprint: &str,
    design: &str,
    names: &[String],
    models: &[String],
    summaries: &[SampleSummary],
    date: &str,
) -> StoredStudy {
    let models = models
        .iter()
        .map(|m| {
            let mine: Vec<SampleSummary> = summaries.iter().filter(|s| &s.model == m).cloned().collect();
            StoredModel {
                model: m.clone(),
                samples: mine.len(),
                all_hold: mine.iter().filter(|s| s.evaluable == s.claims && s.holds == s.claims).count(),
                best: best(&mine)
                    .into_iter()
                    .take(BEST_STORED)
                    .map(|s| StoredSample {
                        sample: s.sample,
                        values: s.values.clone(),
                        claims: s.claims,
                        evaluable: s.evaluable,
                        holds: s.holds,
                        failing: s.failing.clone(),
                    })
                    .collect(),
                findings: Vec::new(),
                apart: Vec::new(),
            }
        })
        .collect();
    StoredStudy {
        study: study.to_string(),
        fingerprint: fingerprint.to_string(),
        design: design.to_string(),
        vary: names.to_vec(),
        models,
        date: date.to_string(),
    }
}

/// The table `ID_samples`: a row per sample.
pub fn table(id: &str, names: &[String], summaries: &[SampleSummary]) -> Table {
    let mut t = Table::new(
        format!("{id}_samples"),
        format!(
            "study {id}: a row per sample (evaluable: claims that can be evaluated on settled points; holds: of those, the claims that hold; failing: the others, with their value and the paper's bound)"
        ),
    )
    .i64("sample", summaries.iter().map(|s| s.sample as i64).collect())
    .str("model", summaries.iter().map(|s| s.model.clone()).collect());
    for (k, n) in names.iter().enumerate() {
        t = t.f64(n.clone(), summaries.iter().map(|s| s.values[k]).collect());
    }
    let count = |f: fn(&SampleSummary) -> usize| summaries.iter().map(|s| f(s) as i64).collect();
    t.i64("claims", count(|s| s.claims))
        .i64("evaluable", count(|s| s.evaluable))
        .i64("holds", count(|s| s.holds))
        .i64("unsettled", count(|s| s.unsettled))
        .i64("not_evaluable", count(|s| s.not_evaluable))
        .str("failing", summaries.iter().map(|s| s.failing.join("; ")).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(sample: usize, claim: &str, outcome: Verdict, settled: bool) -> ClaimRow {
        ClaimRow {
            sample,
            model: "stated".into(),
            values: vec![0.01 * (sample + 1) as f64],
            check: 0,
            claim: claim.into(),
            reading: String::new(),
            value: 2.0,
            bound: "within [2.5, 4]".into(),
            outcome,
            reason: String::new(),
            settled,
        }
    }

    #[test]
    fn each_sample_counts_what_holds_among_what_can_be_evaluated() {
        let rows = [
            row(0, "a", Verdict::Holds, true),
            row(0, "b", Verdict::Fails, true),
            row(0, "c", Verdict::Holds, false),
            row(1, "a", Verdict::Holds, true),
            row(1, "b", Verdict::Holds, true),
            row(1, "c", Verdict::NotEvaluable, true),
        ];
        let s = per_sample(&rows);
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].claims, s[0].evaluable, s[0].holds, s[0].unsettled, s[0].not_evaluable), (3, 2, 1, 1, 0));
        assert_eq!(s[0].failing, vec!["b = 2 (within [2.5, 4])".to_string()]);
        assert_eq!((s[1].evaluable, s[1].holds, s[1].not_evaluable), (2, 2, 1));
        let b = best(&s);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].sample, 1);
        let t = table("j", &["damping".into()], &s);
        assert_eq!(t.height(), 2);
    }
}
