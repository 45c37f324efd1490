//! Running a study's samples: each sample's experiment (and the experiments it takes values
//! from, at the same structure and excitation) with its claim checks only; one row per claim.
//! No I/O: the study's tables and references arrive loaded.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Mutex;

use crate::checks::reference::ReferenceStore;
use crate::checks::Status;
use crate::error::Result;
use crate::experiment::study::{is_claim, Sample, Study};
use crate::experiment::{CheckKind, Experiment, Exports};
use crate::table::Table;

/// One claim at one sample.
#[derive(Debug, Clone, PartialEq)]
pub struct ClaimRow {
    pub sample: usize,
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
    Holds,
    Fails,
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

/// A sample's experiment ready to run: built from the study with the sample's values, its
/// exports resolved from its dependencies (run at the sample, cached), only its claim checks.
/// Errors name the sample and its values.
pub fn prepare(
    study: &Study,
    sample: &Sample,
    refs: &ReferenceStore,
    reference_dir: &Path,
    cache: &DependencyCache,
) -> Result<Experiment> {
    let exp = study.experiment(sample, reference_dir)?;
    let exports =
        dependency_exports(study, &exp, sample, refs, reference_dir, cache).map_err(|e| study.at_sample(e, sample))?;
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
    reference_dir: &Path,
    cache: &DependencyCache,
) -> Result<Vec<Experiment>> {
    use rayon::prelude::*;
    let all: Vec<Result<Experiment>> =
        samples.par_iter().map(|s| prepare(study, s, refs, reference_dir, cache)).collect();
    all.into_iter().collect()
}

/// Evaluates one sample: its claim rows, in check order.
pub fn run_sample(
    study: &Study,
    sample: &Sample,
    refs: &ReferenceStore,
    reference_dir: &Path,
    cache: &DependencyCache,
) -> Result<Vec<ClaimRow>> {
    let exp = prepare(study, sample, refs, reference_dir, cache)?;
    run_prepared(&exp, sample, refs)
}

/// Evaluates one prepared sample ([`prepare`]): its claim rows, in check order.
pub fn run_prepared(exp: &Experiment, sample: &Sample, refs: &ReferenceStore) -> Result<Vec<ClaimRow>> {
    let result = super::run(exp, refs, &|| {})?;
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
                check,
                claim: outcome.name.clone(),
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
    reference_dir: &Path,
    cache: &DependencyCache,
) -> Result<Exports> {
    let mut exports = Exports::new();
    for id in exp.dependencies() {
        let key = format!("{id}/{}/{:?}", sample.model, study.dependency_values(sample));
        let known = cache.runs.lock().ok().and_then(|m| m.get(&key).cloned());
        let values = match known {
            Some(v) => v,
            None => {
                let dep = study.dependency(&id, sample, reference_dir)?;
                let inner = dependency_exports(study, &dep, sample, refs, reference_dir, cache)?;
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
/// same rows whatever the number of threads.
pub fn run_all(study: &Study, refs: &ReferenceStore, reference_dir: &Path) -> Result<Vec<ClaimRow>> {
    use rayon::prelude::*;
    let cache = DependencyCache::default();
    let samples: Vec<&Sample> = study.samples.iter().collect();
    let exps = prepare_all(study, &samples, refs, reference_dir, &cache)?;
    let rows: Vec<Result<Vec<ClaimRow>>> =
        exps.par_iter().zip(&samples).map(|(e, s)| run_prepared(e, s, refs)).collect();
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
    pub model: String,
    pub check: usize,
    pub claim: String,
    pub bound: String,
    pub samples: usize,
    /// Samples where the claim holds on settled points.
    pub holds: usize,
    /// Samples where the claim cannot be evaluated (counted apart: neither holds nor fails).
    pub not_evaluable: usize,
    /// Samples where the claim's value rests on a point that did not settle (counted apart,
    /// whatever their outcome).
    pub unsettled: usize,
    pub min: f64,
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

    /// The box around the samples where the claim holds, e.g. "damping 0.003-0.006,
    /// clearance_mm 0.25-0.55" (`names`: the varied keys).
    pub fn region_box(&self, names: &[String]) -> String {
        let fmt = crate::number::fmt_num;
        names
            .iter()
            .zip(&self.region)
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
    pub fn words(&self, names: &[String]) -> String {
        let fmt = crate::number::fmt_num;
        let n = self.evaluable();
        let mut apart =
            if self.not_evaluable > 0 { format!("; {} not evaluable", self.not_evaluable) } else { String::new() };
        if self.unsettled > 0 {
            apart += &format!(
                "; {} on {}",
                self.unsettled,
                if self.unsettled == 1 { "an unsettled point" } else { "unsettled points" }
            );
        }
        if n == 0 && self.unsettled > 0 {
            format!("not evaluable on settled points at any of {} samples{apart}", self.samples)
        } else if n == 0 {
            format!("not evaluable at any of {} samples", self.samples)
        } else if self.holds == n && apart.is_empty() {
            format!("holds everywhere ({}/{n})", self.holds)
        } else if self.holds == n {
            format!("holds wherever evaluable ({}/{n}{apart})", self.holds)
        } else if self.holds == 0 {
            format!("holds nowhere (0/{n}; value {}-{}{apart})", fmt(self.min), fmt(self.max))
        } else {
            format!("holds at {}/{n} ({}{apart})", self.holds, self.region_box(names))
        }
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
                    format!("{label}: {}", s.words(names))
                })
                .collect();
            Some(format!("{} ({}): {}", first.claim, first.bound, parts.join("; ")))
        })
        .collect()
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
