//! The report's bottom line (the index, above the verdict matrix): from each joint study the
//! report runs (docs/studies.md, "Joint studies"), whether one setup of the values the paper
//! leaves unstated reproduces every claim of its figures at once; if none does, the most that
//! hold together and where, the claims that fail at every setup, and the claims that each hold
//! somewhere but never together. Every number comes from this run's rows.

use serde::Serialize;

use crate::analysis::study::ClaimRow;
use crate::analysis::study_samples::{best, per_sample, SampleSummary};
use crate::number::fmt_num;

use super::manifest::StudyRun;

/// One joint study's bottom line.
#[derive(Debug, Serialize)]
pub struct BottomLine {
    /// The study's id and title.
    pub id: String,
    /// Its title.
    pub title: String,
    /// The sentences.
    pub sentences: Vec<String>,
    /// The setups where the most claims hold at once: values in words, the count, the claims
    /// that fail there.
    pub best: Vec<BestRow>,
    /// Links to its tables (file name, path).
    pub tables: Vec<(String, String)>,
    /// How the report ran it, in words (the whole study, or a stored answer's best samples).
    pub how: String,
}

/// One setup of [`BottomLine::best`].
#[derive(Debug, Serialize)]
pub struct BestRow {
    /// The model and the values, in words.
    pub setup: String,
    /// The model's label alone, and the values to two significant digits (the front page's
    /// table, read at a glance; `setup` has them in full).
    pub model: String,
    /// The values, short.
    pub values: String,
    /// "10 of 13".
    pub holds: String,
    /// The failing claims, each with its value and bound.
    pub failing: String,
    /// The experiments whose claims each hold at some setup of this model but never at the
    /// same one, each pair once ("fig05_third_mode / fig08_number_of_dampers"; empty when none
    /// or not known).
    pub apart: String,
}

impl BestRow {
    /// The row of one sample of `run`.
    fn of(run: &StudyRun, s: &SampleSummary) -> BestRow {
        let model = run.manifest.models.iter().find(|m| m.0 == s.model).map_or(s.model.clone(), |m| m.1.clone());
        let values: Vec<String> = run
            .manifest
            .vary
            .iter()
            .zip(&s.values)
            .map(|(a, v)| format!("{} {}", a.name, crate::number::fmt_sig(*v, 2)))
            .collect();
        BestRow {
            setup: setup(run, s),
            model,
            values: values.join(", "),
            holds: format!("{} of {}", s.holds, s.evaluable),
            failing: s.failing.join("; "),
            apart: String::new(),
        }
    }
}

/// Links to a joint study's tables in the report: (file name, path).
fn tables(study: &str, file_dir: &str) -> Vec<(String, String)> {
    [format!("{study}.csv"), format!("{study}_samples.csv")]
        .into_iter()
        .map(|f| (f.clone(), format!("{file_dir}/{f}")))
        .collect()
}

/// The setup of a sample in words.
fn setup(run: &StudyRun, s: &SampleSummary) -> String {
    let model = run.manifest.models.iter().find(|m| m.0 == s.model).map_or(s.model.clone(), |m| m.1.clone());
    let values: Vec<String> =
        run.manifest.vary.iter().zip(&s.values).map(|(a, v)| format!("{} {}", a.name, fmt_num(*v))).collect();
    if model.is_empty() {
        values.join(", ")
    } else {
        format!("{model}: {}", values.join(", "))
    }
}

/// The range of `values` in words.
fn range(values: impl Iterator<Item = f64>) -> String {
    let v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    if v.is_empty() {
        "no value".into()
    } else if lo == hi {
        fmt_num(lo)
    } else {
        format!("{}-{}", fmt_num(lo), fmt_num(hi))
    }
}

/// Where a claim holds, per varied key (`names`): the range of the values of the samples where
/// it does.
fn where_holds(names: &[String], rows: &[&ClaimRow]) -> String {
    let held: Vec<&&ClaimRow> = rows.iter().filter(|r| r.holds()).collect();
    let words: Vec<String> =
        names.iter().enumerate().map(|(k, n)| format!("{n} {}", range(held.iter().map(|r| r.values[k])))).collect();
    format!("holds at {}", words.join(", "))
}

/// Claims, by their position, with the rows of each.
fn by_claim(rows: &[ClaimRow]) -> Vec<(String, String, Vec<&ClaimRow>)> {
    let mut out: Vec<(String, String, Vec<&ClaimRow>)> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|c| c.0 == r.claim) {
            Some(c) => c.2.push(r),
            None => out.push((r.claim.clone(), r.bound.clone(), vec![r])),
        }
    }
    out
}

/// How a figure's experiment fares at a joint study's best setup on one model (the sample
/// where the most claims of every experiment hold at once): for the verdict matrix's cells.
#[derive(Debug, Clone, PartialEq)]
pub struct AtJointSetup {
    /// The joint study's id.
    pub study: String,
    /// Claims of every experiment of the study that hold at that setup.
    pub total: usize,
    /// The experiment's id.
    pub experiment: String,
    /// The model's id.
    pub model: String,
    /// Its claims that hold there on settled points.
    pub holds: usize,
    /// Its claims in the joint study.
    pub claims: usize,
    /// The setup, in words.
    pub setup: String,
}

/// Every experiment of a joint study at its best setup, per model: the first sample (in
/// sample order) among those of the model where the most claims hold at once.
pub fn at_joint_setup(run: &StudyRun) -> Vec<AtJointSetup> {
    let samples = per_sample(&run.rows);
    let mut out = Vec::new();
    for (model, _) in &run.manifest.models {
        let mine: Vec<SampleSummary> = samples.iter().filter(|s| &s.model == model).cloned().collect();
        let Some(b) = best(&mine).into_iter().next() else { continue };
        for id in &run.manifest.joint {
            let prefix = format!("{id}: ");
            let rows: Vec<&ClaimRow> =
                run.rows.iter().filter(|r| r.sample == b.sample && r.claim.starts_with(&prefix)).collect();
            if rows.is_empty() {
                continue;
            }
            out.push(AtJointSetup {
                study: run.manifest.study.clone(),
                total: b.holds,
                experiment: id.clone(),
                model: model.clone(),
                holds: rows.iter().filter(|r| r.holds()).count(),
                claims: rows.len(),
                setup: setup(run, b),
            });
        }
    }
    out
}

/// The pairs of claims of different experiments that each hold on settled points at some
/// sample of `rows` but never at the same one, in claim order.
pub fn apart_pairs(rows: &[ClaimRow]) -> Vec<(String, String)> {
    let claims = by_claim(rows);
    let holding: Vec<&(String, String, Vec<&ClaimRow>)> =
        claims.iter().filter(|(_, _, rs)| rs.iter().any(|r| r.holds())).collect();
    let mut out = Vec::new();
    for (i, a) in holding.iter().enumerate() {
        for b in &holding[i + 1..] {
            let together = a.2.iter().any(|ra| ra.holds() && b.2.iter().any(|rb| rb.sample == ra.sample && rb.holds()));
            let other_figure = a.0.split(':').next() != b.0.split(':').next();
            if !together && other_figure {
                out.push((a.0.clone(), b.0.clone()));
            }
        }
    }
    out
}

/// What the rows of a joint study (one model's) say beyond the best setup, as sentences: the
/// claims that fail wherever they can be evaluated on settled points, and the pairs of claims
/// of different figures that each hold at some sample but never at the same one, with where
/// each holds (`names`: the varied keys).
pub fn findings(names: &[String], rows: &[ClaimRow]) -> Vec<String> {
    let claims = by_claim(rows);
    let mut sentences = Vec::new();
    // Claims that fail wherever they can be evaluated on settled points.
    let never: Vec<String> = claims
        .iter()
        .filter(|(_, _, rs)| {
            let settled: Vec<&&ClaimRow> =
                rs.iter().filter(|r| r.outcome != crate::analysis::study::Verdict::NotEvaluable && r.settled).collect();
            !settled.is_empty() && settled.iter().all(|r| !r.holds())
        })
        .map(|(c, bound, rs)| format!("{c} ({} against {bound})", range(rs.iter().map(|r| r.value))))
        .collect();
    if !never.is_empty() {
        sentences.push(format!("Failing at every setup where it can be evaluated: {}.", never.join("; ")));
    }
    // Claims that each hold somewhere but never together: the figures that pull apart.
    let apart: Vec<String> = apart_pairs(rows)
        .iter()
        .map(|(a, b)| {
            let of = |c: &str| claims.iter().find(|x| x.0 == c).map(|x| where_holds(names, &x.2)).unwrap_or_default();
            format!("\"{a}\" ({}) and \"{b}\" ({})", of(a), of(b))
        })
        .collect();
    if !apart.is_empty() {
        let shown: Vec<String> = apart.iter().take(3).cloned().collect();
        sentences.push(format!(
            "Claims that each hold on settled points at some setup but never at the same one{}: {}.",
            if apart.len() > 3 { format!(" ({} pairs; the first three)", apart.len()) } else { String::new() },
            shown.join("; ")
        ));
    }
    sentences
}

/// The bottom line of one joint study run with the report (a stored one: its stored answer,
/// whose best sample per model the report ran again).
pub fn of(run: &StudyRun, file_dir: &str) -> BottomLine {
    if let Some(stored) = &run.stored {
        return of_stored(run, stored, file_dir);
    }
    let m = &run.manifest;
    let samples = per_sample(&run.rows);
    let top = best(&samples);
    let claims = by_claim(&run.rows);
    let n = claims.len();
    let mut sentences = Vec::new();
    let all: Vec<&SampleSummary> = samples.iter().filter(|s| s.evaluable == s.claims && s.holds == s.claims).collect();
    let figures = m.figure.clone();
    if !all.is_empty() {
        let words: Vec<String> = all.iter().map(|s| setup(run, s)).collect();
        sentences.push(format!(
            "Every one of the {n} claims of {figures} holds at once, on settled points, at {} of the {} setups studied: {}.",
            all.len(),
            samples.len(),
            words.join("; ")
        ));
    } else {
        match top.first() {
            Some(b) => sentences.push(format!(
                "At none of the {} setups studied do all {n} claims of {figures} hold at once; the most, {} of {} that can be evaluated on settled points, hold at {} setup{} ({}).",
                samples.len(),
                b.holds,
                b.evaluable,
                top.len(),
                if top.len() == 1 { "" } else { "s" },
                setup(run, b)
            )),
            None => sentences.push(format!("No claim of {figures} can be evaluated on settled points at any setup studied.")),
        }
    }
    let names: Vec<String> = m.vary.iter().map(|a| a.name.clone()).collect();
    sentences.extend(findings(&names, &run.rows));
    BottomLine {
        id: m.study.clone(),
        title: m.title.clone(),
        sentences,
        best: top.iter().map(|s| BestRow::of(run, s)).collect(),
        tables: tables(&m.study, file_dir),
        how: "run with this report".into(),
    }
}

/// The bottom line of a stored joint study: what its whole run found on each model, and
/// whether its best samples give the same now.
fn of_stored(run: &StudyRun, stored: &super::manifest::StoredRun, file_dir: &str) -> BottomLine {
    let m = &run.manifest;
    let a = &stored.answer;
    let label = |id: &str| m.models.iter().find(|x| x.0 == id).map_or(id.to_string(), |x| x.1.clone());
    let total: usize = a.models.iter().map(|x| x.samples).sum();
    let now = per_sample(&run.rows);
    let mut sentences = Vec::new();
    let everywhere: Vec<String> = a
        .models
        .iter()
        .filter(|x| x.all_hold > 0)
        .map(|x| format!("{} ({} setups)", label(&x.model), x.all_hold))
        .collect();
    let claims = a.models.iter().flat_map(|x| x.best.first()).map(|b| b.claims).max().unwrap_or(0);
    // The most at once per model (the setups are in the folded table).
    let counts: Vec<(String, usize, usize)> =
        a.models.iter().filter_map(|x| x.best.first().map(|b| (label(&x.model), b.holds, b.evaluable))).collect();
    // The first sentence is read at a glance: the count, whether all ever hold together, how
    // many pairs pull apart; the claims, the ranges and the setups follow in the table and the
    // fold.
    let (count, on) = match counts.as_slice() {
        [(l, h, _)] => (h.to_string(), format!(" on {l}")),
        [(_, h, _), rest @ ..] if rest.iter().all(|c| c.1 == *h) => (h.to_string(), ", on every model".to_string()),
        _ => (counts.iter().map(|(l, h, _)| format!("{h} ({l})")).collect::<Vec<_>>().join(", "), String::new()),
    };
    let head = if everywhere.is_empty() {
        format!(
            "At best {count} of the paper's {claims} claims ({}) hold together{on}: at none of the {total} setups searched do all hold at once",
            m.figure
        )
    } else {
        format!(
            "Every one of the {claims} claims of {} holds at once on {} of the {total} setups searched",
            m.figure,
            everywhere.join(", ")
        )
    };
    // Claims that pull apart on every model searched.
    let common: Vec<&[String; 2]> = a
        .models
        .first()
        .map(|f| f.apart.iter().filter(|p| a.models.iter().all(|x| x.apart.contains(p))).collect())
        .unwrap_or_default();
    let apart = match common.len() {
        0 => String::new(),
        1 => "; on every model one pair of claims each hold somewhere but never together".to_string(),
        n => format!("; on every model {n} pairs of claims each hold somewhere but never together"),
    };
    sentences.push(format!("{head}{apart}."));
    sentences.push(format!(
        "The search: {} over {}; the most at once: {most_of}.",
        a.design,
        a.vary.join(", "),
        most_of = counts.iter().map(|(l, h, e)| format!("{h} of {e} on {l}")).collect::<Vec<_>>().join(", ")
    ));
    // The stored best samples, run again now.
    let mut same = true;
    for x in &a.models {
        let (Some(b), Some(n)) =
            (x.best.first(), now.iter().find(|s| s.sample == x.best[0].sample && s.model == x.model))
        else {
            continue;
        };
        if (n.holds, n.evaluable) != (b.holds, b.evaluable) {
            same = false;
            sentences.push(format!(
                "Run again now, {}'s best setup gives {} of {} (stored: {} of {}): the stored answer is out of date.",
                label(&x.model),
                n.holds,
                n.evaluable,
                b.holds,
                b.evaluable
            ));
        }
    }
    if same {
        sentences.push(format!(
            "Each model's best setup, run again with this report, gives the stored count (the search ran on {}).",
            a.date
        ));
    }
    for x in a.models.iter().filter(|x| !x.findings.is_empty()) {
        sentences.push(format!("On {} (the whole search): {}", label(&x.model), x.findings.join(" ")));
    }
    if !stored.fresh {
        sentences.push(format!(
            "The stored answer was computed by another version of the study {} (its experiments or keys changed since): run `shotdamp study studies/{}.toml --store` again.",
            m.study, m.study
        ));
    }
    BottomLine {
        id: m.study.clone(),
        title: m.title.clone(),
        sentences,
        best: now
            .iter()
            .map(|s| {
                // The experiments whose claims pull apart, each pair once (the claims in full
                // are in the fold's sentences).
                let apart = a.models.iter().find(|x| x.model == s.model).map_or(String::new(), |x| {
                    let exp = |c: &str| c.split(':').next().unwrap_or(c).trim().to_string();
                    let mut pairs: Vec<String> = x.apart.iter().map(|p| format!("{} / {}", exp(&p[0]), exp(&p[1]))).collect();
                    pairs.dedup();
                    let mut seen = Vec::new();
                    pairs.retain(|p| if seen.contains(p) { false } else { seen.push(p.clone()); true });
                    pairs.join("; ")
                });
                BestRow { apart, ..BestRow::of(run, s) }
            })
            .collect(),
        tables: tables(&m.study, file_dir),
        how: format!(
            "searched by a whole run of the study on {} (its answer in reference/studies/{}.json), each model's best setup run again with this report (the tables: those runs)",
            a.date, m.study
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::study::Verdict;
    use crate::output::manifest::{Axis, Manifest};

    fn row(sample: usize, x: f64, claim: &str, holds: bool) -> ClaimRow {
        ClaimRow {
            sample,
            model: "stated".into(),
            values: vec![x],
            check: 0,
            claim: claim.into(),
            reading: String::new(),
            value: if holds { 3.0 } else { 1.0 },
            bound: "at least 2".into(),
            outcome: if holds { Verdict::Holds } else { Verdict::Fails },
            reason: String::new(),
            settled: true,
        }
    }

    fn run(rows: Vec<ClaimRow>) -> StudyRun {
        StudyRun {
            manifest: Manifest {
                study: "j".into(),
                title: "t".into(),
                file: "j.toml".into(),
                experiment: "a".into(),
                figure: "Fig. A, Fig. B".into(),
                fingerprint: String::new(),
                samples: 3,
                columns: Vec::new(),
                vary: vec![Axis { name: "damping".into(), label: "damping".into(), log: false }],
                map: None,
                models: vec![("stated".into(), "stated chain".into())],
                grid: true,
                shards: 0,
                rounds: 0,
                joint: vec!["a".into(), "b".into()],
                section: Default::default(),
            },
            description: String::new(),
            rows,
            assumed: Vec::new(),
            stored: None,
        }
    }

    #[test]
    fn figures_that_pull_apart_are_named_with_where_each_holds() {
        // a:1 holds at low damping, b:1 at high damping, b:2 nowhere.
        let mut rows = Vec::new();
        for (k, x) in [0.002, 0.005, 0.01].into_iter().enumerate() {
            rows.push(row(k, x, "a: one", k < 2));
            rows.push(row(k, x, "b: one", k == 2));
            rows.push(row(k, x, "b: two", false));
        }
        let b = of(&run(rows), "j");
        let text = b.sentences.join(" ");
        assert!(text.starts_with("At none of the 3 setups studied do all 3 claims"), "{text}");
        assert!(text.contains("the most, 1 of 3"), "{text}");
        assert!(
            text.contains("Failing at every setup where it can be evaluated: b: two (1 against at least 2)"),
            "{text}"
        );
        assert!(
            text.contains("\"a: one\" (holds at damping 0.002-0.005) and \"b: one\" (holds at damping 0.01)"),
            "{text}"
        );
        assert_eq!(b.best.len(), 3, "every setup holds one claim");
        // Where everything holds at one setup, that setup is the answer.
        let all = vec![row(0, 0.002, "a: one", false), row(1, 0.005, "a: one", true), row(1, 0.005, "b: one", true)];
        let at = at_joint_setup(&run(all.clone()));
        assert_eq!(at.len(), 2, "{at:?}");
        assert_eq!((at[0].experiment.as_str(), at[0].holds, at[0].claims), ("a", 1, 1));
        assert_eq!((at[1].experiment.as_str(), at[1].holds, at[1].claims), ("b", 1, 1));
        assert_eq!(at[0].setup, "stated chain: damping 0.005");
        let b = of(&run(all), "j");
        assert!(
            b.sentences[0].starts_with("Every one of the 2 claims") && b.sentences[0].contains("damping 0.005"),
            "{:?}",
            b.sentences
        );
    }

    #[test]
    fn a_stored_answer_s_numbers_are_the_stored_ones_and_a_rerun_that_differs_is_named() {
        use crate::experiment::study::stored::{StoredModel, StoredSample, StoredStudy};
        let answer = StoredStudy {
            study: "j".into(),
            fingerprint: "f".into(),
            design: "7 samples per model".into(),
            vary: vec!["damping".into()],
            models: vec![StoredModel {
                model: "stated".into(),
                samples: 7,
                all_hold: 0,
                best: vec![StoredSample {
                    sample: 4,
                    values: vec![0.004],
                    claims: 2,
                    evaluable: 2,
                    holds: 1,
                    failing: vec!["b: one = 1 (at least 2)".into()],
                }],
                findings: Vec::new(),
                apart: Vec::new(),
            }],
            date: "2026-11-27".into(),
        };
        // Run again: sample 4 gives 1 of 2, as stored.
        let mut r = run(vec![row(4, 0.004, "a: one", true), row(4, 0.004, "b: one", false)]);
        r.stored = Some(crate::output::manifest::StoredRun { answer: answer.clone(), fresh: true });
        let b = of(&r, "j");
        // At a glance: the count and whether all ever hold together, under 60 words; how the
        // setups were searched comes next.
        assert_eq!(
            b.sentences[0],
            "At best 1 of the paper's 2 claims (Fig. A, Fig. B) hold together on stated chain: at none of the 7 setups searched do all hold at once."
        );
        assert!(b.sentences[0].split_whitespace().count() <= 60);
        assert_eq!(
            b.sentences[1],
            "The search: 7 samples per model over damping; the most at once: 1 of 2 on stated chain."
        );
        assert!(b.best[0].setup.contains("damping 0.004") && b.best[0].holds == "1 of 2", "{:?}", b.best);
        assert_eq!((b.best[0].model.as_str(), b.best[0].values.as_str()), ("stated chain", "damping 0.004"));
        assert!(b.sentences[2].contains("gives the stored count (the search ran on 2026-11-27)"), "{:?}", b.sentences);
        // Another count now, another version: both said; a pair that pulls apart on every model
        // heads it.
        let mut answer = answer;
        answer.models[0].apart = vec![["a: one".into(), "b: one".into()]];
        let mut r = run(vec![row(4, 0.004, "a: one", true), row(4, 0.004, "b: one", true)]);
        r.stored = Some(crate::output::manifest::StoredRun { answer, fresh: false });
        let b = of(&r, "j");
        let text = b.sentences.join(" ");
        assert!(text.contains("gives 2 of 2 (stored: 1 of 2): the stored answer is out of date"), "{text}");
        assert!(text.contains("another version of the study j"), "{text}");
        assert!(
            b.sentences[0].ends_with("; on every model one pair of claims each hold somewhere but never together."),
            "{:?}",
            b.sentences
        );
        assert_eq!(b.best[0].apart, "a / b", "the pair's experiments, named in the table");
    }
}
