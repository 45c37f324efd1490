//! Running a study's samples: each sample's experiment (and the experiments it takes values
//! from, at the same structure and excitation) with its claim checks only; one row per claim.
//! No I/O: the study's tables and references arrive loaded.

use std::collections::BTreeMap;
use std::sync::Mutex;

use crate::checks::reference::ReferenceStore;
use crate::checks::Status;
use crate::error::Result;
use crate::experiment::study::{is_claim, Sample, Study};
use crate::experiment::{CheckKind, Experiment, Exports};
use crate::table::Table;

use super::result::Tick;

/// One claim at one sample.
#[derive(Debug, Clone, PartialEq)]
pub struct ClaimRow {
    /// 0-based sample.
    pub sample: usize,
    /// The model of the structure.
    pub model: String,
    /// The sample's values, in the order of the study's `vary`.
    pub values: Vec<f64>,
    /// 0-based position among the experiment's claim checks.
    pub check: usize,
    /// The check's name (it says the reading).
    pub claim: String,
    /// The reading of a ratio claim (`peak_over_peak`, `at_resonance`, `band_max`; empty for
    /// other claims).
    pub reading: String,
    /// The claimed quantity as computed.
    pub value: f64,
    /// What the paper claims, in words (e.g. "within [2.5, 4]").
    pub bound: String,
    /// Whether the claim holds at this sample, or why it cannot be evaluated there.
    pub outcome: Verdict,
    /// Why the claim cannot be evaluated at this sample (empty when it can).
    pub reason: String,
    /// Whether the value rests only on settled steady states (false when it uses a point that
    /// did not settle, or would change with one that was skipped: see
    /// [`crate::checks::CheckOutcome::settled`]). Such a row is counted apart.
    pub settled: bool,
}

impl ClaimRow {
    /// Whether the claim holds at this sample on settled points only.
    pub fn holds(&self) -> bool {
        self.outcome == Verdict::Holds && self.settled
    }

    /// Whether the claim can be evaluated here but its value rests on a point that did not
    /// settle.
    pub fn unsettled(&self) -> bool {
        self.outcome != Verdict::NotEvaluable && !self.settled
    }
}

/// A claim at one sample: it holds, it does not, or it cannot be evaluated there (the claimed
/// quantity is not a number, or the check has nothing to compare it with): never counted as
/// "does not hold".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The claim holds on settled points.
    Holds,
    /// The claim fails.
    Fails,
    /// The claim cannot be evaluated (e.g. no peak in the band).
    NotEvaluable,
}

impl Verdict {
    /// The word in the tables (`outcome` column).
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::Fails => "fails",
            Verdict::NotEvaluable => "not evaluable",
        }
    }

    /// The verdict of a word of the tables.
    pub fn from_word(word: &str) -> Option<Verdict> {
        [Verdict::Holds, Verdict::Fails, Verdict::NotEvaluable].into_iter().find(|v| v.word() == word)
    }
}

/// The verdict of a claim check's outcome, and the reason when it cannot be evaluated.
fn verdict(outcome: &crate::checks::CheckOutcome) -> (Verdict, String) {
    if !outcome.computed.is_finite() || outcome.tolerance.is_empty() {
        let why = outcome.detail.clone().unwrap_or_else(|| outcome.description.clone());
        let why = why.strip_prefix("not evaluable: ").unwrap_or(&why).to_string();
        let what = if outcome.computed.is_finite() { "nothing to compare it with" } else { "no value" };
        return (Verdict::NotEvaluable, format!("{what}: {why}"));
    }
    if matches!(outcome.status, Status::Pass | Status::KnownDeviationPasses) {
        (Verdict::Holds, String::new())
    } else {
        (Verdict::Fails, String::new())
    }
}

/// Exports of dependencies already run, by (experiment id, model, carried-over values).
#[derive(Default)]
pub struct DependencyCache {
    runs: Mutex<BTreeMap<String, BTreeMap<String, f64>>>,
}

/// The claim checks of an experiment (those a study re-evaluates), in file order.
pub fn claims(exp: &Experiment) -> Vec<crate::experiment::CheckSpec> {
    exp.checks.iter().filter(|c| is_claim(&c.kind)).cloned().collect()
}

/// A sample's experiments ready to run (one; a joint study's: each of its experiments, in the
/// file's order): built from the study with the sample's values, their exports resolved from
/// their dependencies (run at the sample, cached), only their claim checks. Errors name the
/// sample and its values.
pub fn prepare(
    study: &Study,
    sample: &Sample,
    refs: &ReferenceStore,
    cache: &DependencyCache,
) -> Result<Vec<Experiment>> {
    study.parts().map(|part| prepare_one(part, sample, refs, cache)).collect()
}

/// [`prepare`] for one experiment of the study.
fn prepare_one(study: &Study, sample: &Sample, refs: &ReferenceStore, cache: &DependencyCache) -> Result<Experiment> {
    let exp = study.experiment(sample)?;
    let exports = dependency_exports(study, &exp, sample, refs, cache).map_err(|e| study.at_sample(e, sample))?;
    let mut exp = exp.resolve(&exports).map_err(|e| study.at_sample(e, sample))?;
    exp.checks = claims(&exp);
    Ok(exp)
}

/// Every sample of `samples` prepared (in parallel, on the caller's pool) before any runs: a
/// bad value, or one that makes an export impossible, stops the study here. The error is that
/// of the first such sample in sample order, whatever the number of threads.
pub fn prepare_all(
    study: &Study,
    samples: &[&Sample],
    refs: &ReferenceStore,
    cache: &DependencyCache,
) -> Result<Vec<Vec<Experiment>>> {
    use rayon::prelude::*;
    let all: Vec<Result<Vec<Experiment>>> = samples.par_iter().map(|s| prepare(study, s, refs, cache)).collect();
    all.into_iter().collect()
}

/// Evaluates one sample: its claim rows, in check order.
pub fn run_sample(
    study: &Study,
    sample: &Sample,
    refs: &ReferenceStore,
    cache: &DependencyCache,
    tick: &Tick,
) -> Result<Vec<ClaimRow>> {
    let exps = prepare(study, sample, refs, cache)?;
    run_prepared(&exps, sample, refs, tick)
}

/// Evaluates one prepared sample ([`prepare`]): its claim rows, in check order (a joint
/// study's: experiment after experiment, numbered on, each claim named `EXPERIMENT: claim`).
/// `tick` is called at every simulated point.
pub fn run_prepared(exps: &[Experiment], sample: &Sample, refs: &ReferenceStore, tick: &Tick) -> Result<Vec<ClaimRow>> {
    let joint = exps.len() > 1;
    let mut rows = Vec::new();
    for exp in exps {
        let first = rows.len();
        rows.extend(rows_of(exp, sample, refs, tick, first, joint)?);
    }
    Ok(rows)
}

/// The claim rows of one experiment of a sample, numbered from `first`.
fn rows_of(
    exp: &Experiment,
    sample: &Sample,
    refs: &ReferenceStore,
    tick: &Tick,
    first: usize,
    joint: bool,
) -> Result<Vec<ClaimRow>> {
    let result = super::run(exp, refs, tick)?;
    Ok(exp
        .checks
        .iter()
        .zip(&result.checks)
        .enumerate()
        .map(|(check, (spec, outcome))| {
            let (verdict, reason) = verdict(outcome);
            ClaimRow {
                sample: sample.index,
                model: sample.model.clone(),
                values: sample.values.clone(),
                check: first + check,
                claim: if joint { format!("{}: {}", exp.meta.id, outcome.name) } else { outcome.name.clone() },
                reading: match &spec.kind {
                    CheckKind::PeakRatio { reading, .. } => reading.name().to_string(),
                    _ => String::new(),
                },
                value: outcome.computed,
                bound: outcome.tolerance.clone(),
                outcome: verdict,
                reason,
                settled: outcome.settled != Some(false),
            }
        })
        .collect())
}

/// The exports `exp` needs, from its dependencies run at the sample (cached: a dependency
/// runs once per model and set of carried-over values).
fn dependency_exports(
    study: &Study,
    exp: &Experiment,
    sample: &Sample,
    refs: &ReferenceStore,
    cache: &DependencyCache,
) -> Result<Exports> {
    let mut exports = Exports::new();
    for id in exp.dependencies() {
        let key = format!("{id}/{}/{:?}", sample.model, study.dependency_values(sample));
        let known = cache.runs.lock().ok().and_then(|m| m.get(&key).cloned());
        let values = match known {
            Some(v) => v,
            None => {
                let dep = study.dependency(&id, sample)?;
                let inner = dependency_exports(study, &dep, sample, refs, cache)?;
                let dep = dep.resolve(&inner)?;
                let v = super::run(&dep, refs, &|| {})?.exports;
                if let Ok(mut m) = cache.runs.lock() {
                    m.insert(key, v.clone());
                }
                v
            }
        };
        exports.insert(exp.key_of(&id), values);
    }
    Ok(exports)
}

/// Every sample of a study, in parallel (on the caller's pool), rows in sample order: the
/// same rows whatever the number of threads. An adaptive study's samples are its round 0:
/// [`super::study_adaptive::run_all`] runs its rounds.
pub fn run_all(study: &Study, refs: &ReferenceStore, tick: &Tick) -> Result<Vec<ClaimRow>> {
    use rayon::prelude::*;
    let cache = DependencyCache::default();
    let samples: Vec<&Sample> = study.samples.iter().collect();
    let exps = prepare_all(study, &samples, refs, &cache)?;
    let rows: Vec<Result<Vec<ClaimRow>>> =
        exps.par_iter().zip(&samples).map(|(e, s)| run_prepared(e, s, refs, tick)).collect();
    let rows: Vec<Vec<ClaimRow>> = rows.into_iter().collect::<Result<_>>()?;
    Ok(rows.into_iter().flatten().collect())
}

/// Column names of a study's long table, in order.
pub fn columns(study: &Study) -> Vec<String> {
    let mut out: Vec<String> = vec!["sample".into(), "model".into()];
    out.extend(study.vary.iter().map(|v| v.name.clone()));
    out.extend(["check", "claim", "reading", "value", "settled", "bound", "outcome", "reason"].map(String::from));
    out
}

/// The long table of some rows of `study`: a row per sample and claim.
pub fn table(study: &Study, rows: &[ClaimRow]) -> Table {
    let names: Vec<String> = study.vary.iter().map(|v| v.name.clone()).collect();
    rows_table(&study.id, &names, rows)
}

/// The long table of study `id` (`names`: its varied keys), in the order of [`columns`].
pub fn rows_table(id: &str, names: &[String], rows: &[ClaimRow]) -> Table {
    let mut t = Table::new(
        id.to_string(),
        format!(
            "study {id}: a row per sample and claim (value: the claimed quantity; settled: 1 when it rests only on settled steady states, 0 when it needs a point that did not settle; outcome: holds, fails or not evaluable, with the reason)"
        ),
    )
    .i64("sample", rows.iter().map(|r| r.sample as i64).collect())
    .str("model", rows.iter().map(|r| r.model.clone()).collect());
    for (k, n) in names.iter().enumerate() {
        t = t.f64(n.clone(), rows.iter().map(|r| r.values[k]).collect());
    }
    t.i64("check", rows.iter().map(|r| r.check as i64).collect())
        .str("claim", rows.iter().map(|r| r.claim.clone()).collect())
        .str("reading", rows.iter().map(|r| r.reading.clone()).collect())
        .f64("value", rows.iter().map(|r| r.value).collect())
        .i64("settled", rows.iter().map(|r| r.settled as i64).collect())
        .str("bound", rows.iter().map(|r| r.bound.clone()).collect())
        .str("outcome", rows.iter().map(|r| r.outcome.word().to_string()).collect())
        .str("reason", rows.iter().map(|r| r.reason.clone()).collect())
}

/// Per model and claim: how many samples, in how many it holds, the range of the value.
#[derive(Debug, Clone, PartialEq)]
pub struct ClaimSummary {
    /// The model of the structure.
    pub model: String,
    /// 0-based position among the experiment's claim checks.
    pub check: usize,
    /// The check's name.
    pub claim: String,
    /// The claim's bound, in words.
    pub bound: String,
    /// Samples evaluated.
    pub samples: usize,
    /// Samples where the claim holds on settled points.
    pub holds: usize,
    /// Samples where the claim cannot be evaluated (counted apart: neither holds nor fails).
    pub not_evaluable: usize,
    /// Samples where the claim's value rests on a point that did not settle (counted apart,
    /// whatever their outcome).
    pub unsettled: usize,
    /// Smallest value of the claimed quantity over the samples.
    pub min: f64,
    /// Largest value of the claimed quantity over the samples.
    pub max: f64,
    /// Per varied key: the smallest and largest value among the samples where the claim
    /// holds (NaN when it holds nowhere): the box around the region.
    pub region: Vec<(f64, f64)>,
}

/// Summaries of rows, by model (in the order of `models`) then check.
pub fn summarise(models: &[String], rows: &[ClaimRow]) -> Vec<ClaimSummary> {
    let mut out: Vec<ClaimSummary> = Vec::new();
    for model in models {
        let mine: Vec<&ClaimRow> = rows.iter().filter(|r| &r.model == model).collect();
        let n_checks = mine.iter().map(|r| r.check + 1).max().unwrap_or(0);
        for check in 0..n_checks {
            let of: Vec<&&ClaimRow> = mine.iter().filter(|r| r.check == check).collect();
            // The claim's name and bound from a sample where it could be evaluated.
            let Some(first) = of.iter().find(|r| r.outcome != Verdict::NotEvaluable).or(of.first()) else { continue };
            let finite = of.iter().map(|r| r.value).filter(|v| v.is_finite());
            out.push(ClaimSummary {
                model: model.clone(),
                check,
                claim: first.claim.clone(),
                bound: first.bound.clone(),
                samples: of.len(),
                holds: of.iter().filter(|r| r.holds()).count(),
                not_evaluable: of.iter().filter(|r| r.outcome == Verdict::NotEvaluable).count(),
                unsettled: of.iter().filter(|r| r.unsettled()).count(),
                min: finite.clone().fold(f64::INFINITY, f64::min),
                max: finite.fold(f64::NEG_INFINITY, f64::max),
                region: (0..first.values.len())
                    .map(|k| {
                        let held = of.iter().filter(|r| r.holds()).map(|r| r.values[k]);
                        let lo = held.clone().fold(f64::INFINITY, f64::min);
                        let hi = held.fold(f64::NEG_INFINITY, f64::max);
                        if lo.is_finite() {
                            (lo, hi)
                        } else {
                            (f64::NAN, f64::NAN)
                        }
                    })
                    .collect(),
            });
        }
    }
    out
}

impl ClaimSummary {
    /// Samples where the claim can be evaluated on settled points.
    pub fn evaluable(&self) -> usize {
        self.samples - self.not_evaluable - self.unsettled
    }

    /// The fraction of the evaluable samples where the claim holds (NaN when none is).
    pub fn fraction(&self) -> f64 {
        if self.evaluable() == 0 {
            f64::NAN
        } else {
            self.holds as f64 / self.evaluable() as f64
        }
    }
}

/// The summary table of study `id` (`names`: the varied keys).
pub fn summary_table(id: &str, names: &[String], summaries: &[ClaimSummary]) -> Table {
    let mut t = Table::new(
        format!("{id}_summary"),
        format!("study {id}: per model and claim, the samples where it holds on settled points (unsettled: samples whose value needs a point that did not settle, counted apart) and the range of the claimed quantity"),
    )
    .str("model", summaries.iter().map(|s| s.model.clone()).collect())
    .i64("check", summaries.iter().map(|s| s.check as i64).collect())
    .str("claim", summaries.iter().map(|s| s.claim.clone()).collect())
    .str("bound", summaries.iter().map(|s| s.bound.clone()).collect())
    .i64("samples", summaries.iter().map(|s| s.samples as i64).collect())
    .i64("holds", summaries.iter().map(|s| s.holds as i64).collect())
    .i64("not_evaluable", summaries.iter().map(|s| s.not_evaluable as i64).collect())
    .i64("unsettled", summaries.iter().map(|s| s.unsettled as i64).collect())
    .f64("fraction", summaries.iter().map(|s| s.fraction()).collect())
    .f64("min", summaries.iter().map(|s| s.min).collect())
    .f64("max", summaries.iter().map(|s| s.max).collect());
    for (k, n) in names.iter().enumerate() {
        t = t
            .f64(format!("{n}_holds_min"), summaries.iter().map(|s| s.region[k].0).collect())
            .f64(format!("{n}_holds_max"), summaries.iter().map(|s| s.region[k].1).collect());
    }
    t
}

/// How far one group of samples moves a claim from the paper's bed (see
/// `output::study_words::deviation_sentences`).
#[derive(Debug, Clone, PartialEq)]
pub struct Deviation {
    /// The value of the first varied key the group shares.
    pub group: f64,
    /// Largest `|value / paper's - 1|` over the group's evaluable samples that rest on settled
    /// points, and that sample's values.
    pub settled: Option<(f64, Vec<f64>)>,
    /// The same over samples that rest on a point that did not settle.
    pub unsettled: Option<(f64, Vec<f64>)>,
    /// Evaluable samples of the group, and how many of them have another verdict (holds or
    /// fails) than the paper's bed.
    pub samples: usize,
    /// Of those, samples whose verdict differs from the paper's bed's.
    pub verdict_changes: usize,
}

/// Per value of the first varied key, the largest relative moves of the claim `check` on
/// `model` from the paper's bed, or `None` when the first sample (every key at its first
/// value) is not evaluable. The first two varied keys are the bed's (e.g. grains and
/// restitution); a sample is compared with the sample that has those two at their first
/// values (the paper's bed) and every further key (a clearance, a force) at its own. Samples
/// whose paper's-bed sample is not evaluable, and groups without an evaluable sample, are
/// left out. Returns the first sample's value and the groups.
pub fn deviations(model: &str, check: usize, rows: &[ClaimRow]) -> Option<(f64, Vec<Deviation>)> {
    let of: Vec<&ClaimRow> = rows.iter().filter(|r| r.model == model && r.check == check).collect();
    let first = of.iter().min_by_key(|r| r.sample)?;
    if !first.value.is_finite() || first.value == 0.0 {
        return None;
    }
    let bed_keys = first.values.len().min(2);
    let base_of = |r: &ClaimRow| {
        of.iter().copied().find(|b| {
            b.values.iter().zip(&r.values).enumerate().all(|(k, (bv, rv))| {
                let want = if k < bed_keys { first.values[k] } else { *rv };
                bv.to_bits() == want.to_bits()
            })
        })
    };
    let mut groups: Vec<Deviation> = Vec::new();
    for r in of.iter().filter(|r| r.value.is_finite()) {
        let Some(base) = base_of(r).filter(|b| b.sample != r.sample && b.value.is_finite() && b.value != 0.0) else {
            continue;
        };
        let g = r.values.first().copied().unwrap_or(f64::NAN);
        let moved = (r.value / base.value - 1.0).abs();
        let i = match groups.iter().position(|d| d.group.to_bits() == g.to_bits()) {
            Some(i) => i,
            None => {
                groups.push(Deviation { group: g, settled: None, unsettled: None, samples: 0, verdict_changes: 0 });
                groups.len() - 1
            }
        };
        groups[i].samples += 1;
        if r.outcome != base.outcome {
            groups[i].verdict_changes += 1;
        }
        let slot = if r.settled { &mut groups[i].settled } else { &mut groups[i].unsettled };
        if slot.as_ref().is_none_or(|(x, _)| moved > *x) {
            *slot = Some((moved, r.values.clone()));
        }
    }
    Some((first.value, groups))
}

/// Claim rows for the tests of this room and of the words written from it.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::{ClaimRow, Verdict};

    /// A claim row of the stated model: the peak ratio, failing its bound unless changed.
    pub(crate) fn row(sample: usize, values: &[f64], value: f64, settled: bool) -> ClaimRow {
        ClaimRow {
            sample,
            model: "stated".into(),
            values: values.to_vec(),
            check: 0,
            claim: "peak ratio".into(),
            reading: String::new(),
            value,
            bound: "within [2.5, 4]".into(),
            outcome: Verdict::Fails,
            reason: String::new(),
            settled,
        }
    }

    /// Grains 1 / 10 x restitution 0 / 0.3 / 0.6, the first sample the paper's bed; the
    /// verdict changes at sample 1, sample 2 does not settle, sample 5 has no value.
    pub(crate) fn grains_by_restitution() -> Vec<ClaimRow> {
        let mut rows = vec![
            row(0, &[1.0, 0.0], 2.0, true),
            row(1, &[1.0, 0.3], 2.2, true),
            row(2, &[1.0, 0.6], 1.0, false),
            row(3, &[10.0, 0.0], 2.0, true),
            row(4, &[10.0, 0.3], 2.002, true),
            row(5, &[10.0, 0.6], f64::NAN, true),
        ];
        rows[1].outcome = Verdict::Holds;
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use super::fixtures::{grains_by_restitution, row};

    #[test]
    fn deviations_are_measured_from_the_first_sample_per_group() {
        let rows = grains_by_restitution();
        let (base, groups) = deviations("stated", 0, &rows).unwrap();
        assert_eq!(base, 2.0);
        assert_eq!(groups.len(), 2);
        let (x, at) = groups[0].settled.clone().unwrap();
        assert!((x - 0.1).abs() < 1e-12 && at == vec![1.0, 0.3]);
        let (x, at) = groups[0].unsettled.clone().unwrap();
        assert!((x - 0.5).abs() < 1e-12 && at == vec![1.0, 0.6]);
        let (x, _) = groups[1].settled.clone().unwrap();
        assert!((x - 0.001).abs() < 1e-12 && groups[1].unsettled.is_none());
    }

    #[test]
    fn further_keys_are_compared_within_their_own_values() {
        // grains x restitution x force: each force has its own paper's bed.
        let rows = vec![
            row(0, &[1.0, 0.0, 1.0], 2.0, true),
            row(1, &[1.0, 0.0, 2.0], 4.0, true),
            row(2, &[1.0, 0.3, 1.0], 2.2, true),
            row(3, &[1.0, 0.3, 2.0], 4.0, true),
        ];
        let (first, groups) = deviations("stated", 0, &rows).unwrap();
        assert_eq!(first, 2.0);
        // Sample 1 is the paper's bed at force 2 (not a move of 100 %); sample 3 does not move.
        let (x, at) = groups[0].settled.clone().unwrap();
        assert!((x - 0.1).abs() < 1e-12 && at == vec![1.0, 0.3, 1.0]);
        assert_eq!(groups[0].samples, 2);
    }
}
