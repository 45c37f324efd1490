//! An adaptive study's rounds (docs/studies.md, "Adaptive refinement"): each round's samples
//! run like any study's, and the answers of its samples (the number of claims that hold, every
//! claim's outcome, or one claim's) choose the next round's samples
//! ([`crate::experiment::study::lattice`]).

use std::collections::BTreeMap;

use crate::checks::reference::ReferenceStore;
use crate::error::Result;
use crate::experiment::study::lattice::{self, Point};
use crate::experiment::study::{Design, Domain, Refine, Sample, Study};
use crate::table::Table;

use super::result::Tick;
use super::study::{ClaimRow, Verdict};

/// What the corners of a cell are compared on: one number per compared claim (holds 1, fails
/// 0, not evaluable -1, unsettled 2), the number of claims that hold, or whether all do.
pub type Answer = Vec<i64>;

/// The lattice points an adaptive study computed, per model, with their answers.
pub type Known = Vec<BTreeMap<Point, Answer>>;

/// The answer of one sample's rows (its claims, in check order) under `refine`.
pub fn answer(rows: &[ClaimRow], refine: Refine) -> Answer {
    let code = |r: &ClaimRow| match r.outcome {
        _ if r.unsettled() => 2,
        Verdict::Holds => 1,
        Verdict::Fails => 0,
        Verdict::NotEvaluable => -1,
    };
    match refine {
        Refine::All => vec![i64::from(!rows.is_empty() && rows.iter().all(ClaimRow::holds))],
        Refine::Count => vec![rows.iter().filter(|r| r.holds()).count() as i64],
        Refine::Outcomes => rows.iter().map(code).collect(),
        Refine::Check(k) => rows.iter().filter(|r| r.check == k).map(code).collect(),
    }
}

/// The answers of rows of consecutive samples, per sample index.
pub fn answers(rows: &[ClaimRow], refine: Refine) -> BTreeMap<usize, Answer> {
    let mut by: BTreeMap<usize, Vec<ClaimRow>> = BTreeMap::new();
    for r in rows {
        by.entry(r.sample).or_default().push(r.clone());
    }
    by.into_iter().map(|(s, rows)| (s, answer(&rows, refine))).collect()
}

/// Runs an adaptive study's rounds with `round`, which computes the rows of a round's samples
/// (numbered on from the rounds before): every round's rows, in sample order, and the lattice
/// points computed per model with their answers (what [`map_table`] maps).
pub fn rounds(
    study: &Study,
    mut round: impl FnMut(u32, Vec<Sample>) -> Result<Vec<ClaimRow>>,
) -> Result<(Vec<ClaimRow>, Known)> {
    let (Some(lattice), Design::Adaptive { refine, .. }) = (study.lattice(), study.design) else {
        return Ok((Vec::new(), Vec::new()));
    };
    let mut all: Vec<ClaimRow> = Vec::new();
    let mut first = 0;
    let known = lattice::run(&lattice, study.models().len(), |r, todo: &[(usize, Point)]| {
        let samples = study.samples_at(todo, first);
        first += samples.len();
        let rows = round(r, samples)?;
        let by = answers(&rows, refine);
        let start = first - todo.len();
        let out = (start..first).map(|s| by.get(&s).cloned().unwrap_or_default()).collect();
        all.extend(rows);
        Ok::<_, crate::error::Error>(out)
    })?;
    Ok((all, known))
}

/// Every round of an adaptive study in this process (as `shotdamp report` runs a study): the
/// rows of every sample computed, in sample order (round after round).
pub fn run_all(study: &Study, refs: &ReferenceStore, tick: &Tick) -> Result<Vec<ClaimRow>> {
    let (rows, _) = rounds(study, |_, samples| super::study::run_all(&study.with_samples(samples), refs, tick))?;
    Ok(rows)
}

/// The fine grid of an adaptive study, per model, every point with its answer, computed or
/// inferred from the corners of the smallest cell around it that agree (`ID_map`): the region
/// where the answer holds at the grid's resolution, from the samples computed.
pub fn map_table(study: &Study, known: &Known) -> Option<Table> {
    let lattice = study.lattice()?;
    let domains: Vec<Domain> = study.vary.iter().map(|v| v.domain.clone()).collect();
    let grids: Vec<Vec<f64>> = domains.iter().map(|d| d.grid().unwrap_or_default()).collect();
    let models = study.models();
    let (mut model, mut answer, mut computed) = (Vec::new(), Vec::new(), Vec::new());
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); grids.len()];
    for (m, k) in known.iter().enumerate() {
        for (p, found) in lattice.infer(k) {
            model.push(models.get(m).cloned().unwrap_or_default());
            for (col, (g, &i)) in values.iter_mut().zip(grids.iter().zip(&p)) {
                col.push(g[i]);
            }
            let (text, how) = match found {
                Some((a, true)) => (words(&a), "computed"),
                Some((a, false)) => (words(&a), "inferred"),
                None => (String::new(), "unknown"),
            };
            answer.push(text);
            computed.push(how.to_string());
        }
    }
    let what = match study.design {
        Design::Adaptive { refine: Refine::All, .. } => "1 where every claim holds, 0 elsewhere",
        Design::Adaptive { refine: Refine::Count, .. } => "the number of claims that hold",
        Design::Adaptive { refine: Refine::Check(_), .. } => {
            "the claim's outcome (1 holds, 0 fails, -1 not evaluable, 2 unsettled)"
        }
        _ => "every claim's outcome in check order (1 holds, 0 fails, -1 not evaluable, 2 unsettled)",
    };
    let mut t = Table::new(
        format!("{}_map", study.id),
        format!(
            "study {}: every point of the adaptive design's fine grid with its answer ({what}): computed, or inferred from the corners of the smallest refined cell around it, which all agree",
            study.id
        ),
    )
    .str("model", model);
    for (v, col) in study.vary.iter().zip(values) {
        t = t.f64(v.name.clone(), col);
    }
    Some(t.str("answer", answer).str("how", computed))
}

fn words(a: &Answer) -> String {
    a.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(" ")
}
