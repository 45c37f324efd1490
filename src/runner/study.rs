//! Studies as library calls (docs/studies.md): the cost of a shard ([`estimate`]), a shard
//! computed into the study's folder in batches that a stopped run resumes ([`run_shard`]),
//! and the merge of a folder's parts into the long table, summary and heat maps ([`merge`]).
//! Which shard a process is (from the command line or a cluster's environment) and what is
//! printed are the caller's.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::analysis::study::{self as run, ClaimRow};
use crate::error::{Error, Result};
use crate::experiment::study::{Sample, Study};
use crate::experiment::Experiment;
use crate::output::manifest::Shard;
use crate::output::study as folder;

pub use super::study_shard::{compute_shard, write_outputs, Merged, Quiet, ShardEnd, StudyProgress};

/// The simulated points of a study's share `shard`; every sample's experiment is built, so
/// a bad value is an error here, before anything runs.
pub fn estimate(study: &Study, reference: &Path, shard: Shard, pool: &rayon::ThreadPool) -> Result<u64> {
    let refs = super::study_references(study, reference)?;
    let mine: Vec<&Sample> = study.samples.iter().filter(|s| shard.owns(s.index)).collect();
    let built = pool.install(|| {
        mine.par_iter().flat_map_iter(|s| study.parts().map(move |part| part.experiment(s))).collect::<Vec<Result<_>>>()
    });
    let exps: Vec<Experiment> = built.into_iter().collect::<Result<_>>()?;
    Ok(exps
        .iter()
        .map(|e| {
            let mut e = e.clone();
            e.checks = run::claims(&e);
            crate::analysis::work(&e, &refs)
        })
        .sum())
}

/// The folder a study is written to by default: `study-runs/ID`.
pub fn default_out(study: &Study) -> PathBuf {
    PathBuf::from("study-runs").join(&study.id)
}

/// Refuses an output folder that holds, or lies inside, the study's inputs (its file, the
/// reference folder, its experiment files).
pub fn refuse_overlap(study: &Study, reference: &Path, out: &Path) -> Result<()> {
    let mut inputs: Vec<(&str, &Path)> =
        vec![("the study file", study.path.as_path()), ("the reference folder", reference)];
    inputs.extend(study.parts().flat_map(|p| &p.base).map(|e| ("the study's experiment file", e.path.as_path())));
    crate::output::destination::refuse_overlap(out, &inputs)
}

/// Computes the share `shard` of `study` into the folder `out` (created, or resumed when it
/// holds this study's batches), then, when the study has one shard, merges it.
pub fn run_shard(
    study: &Study,
    reference: &Path,
    out: &Path,
    shard: Shard,
    pool: &rayon::ThreadPool,
    progress: &dyn StudyProgress,
) -> Result<(ShardEnd, Option<Merged>)> {
    if study.lattice().is_some() {
        return super::study_rounds::run_shard(study, reference, out, shard, pool, progress);
    }
    let end = compute_shard(study, reference, out, shard, pool, progress)?;
    let merged = if shard.count == 1 { Some(merge(out)?) } else { None };
    Ok((end, merged))
}

/// Merges a study folder's parts and writes the long table, the summary and the heat maps.
pub fn merge(dir: &Path) -> Result<Merged> {
    let manifest = folder::read_manifest(dir)?;
    if super::study_rounds::is_adaptive(dir) {
        if let Some(merged) = super::study_rounds::merge(dir, &manifest)? {
            return Ok(merged);
        }
        return Err(Error::Destination {
            path: dir.to_path_buf(),
            message: format!(
                "is an adaptive study's folder whose rounds have not all ended: each round follows from the one before, and the study merges them when its last round ends: run `shotdamp study {} --out {}` (it finds what is computed and computes the rest)",
                manifest.file,
                dir.display()
            ),
        });
    }
    let df = folder::merge(dir, &manifest)?;
    write_outputs(dir, manifest, df)
}

/// Writes the stored answer of a merged study folder into the reference folder
/// (`reference/studies/ID.json`, atomically): what `shotdamp report` runs again for a study
/// marked `stored = true`.
pub fn store(reference: &Path, merged: &Merged) -> Result<PathBuf> {
    let m = &merged.manifest;
    let models: Vec<String> = m.models.iter().map(|x| x.0.clone()).collect();
    let per_model = merged.samples.len() / models.len().max(1);
    let design = if m.grid {
        format!("a grid of {per_model} samples per model")
    } else {
        format!("{per_model} samples per model")
    };
    let mut answer = crate::analysis::study_samples::stored(
        &m.study,
        &m.fingerprint,
        &design,
        &merged.names,
        &models,
        &merged.samples,
        &crate::output::files::today_utc(),
    );
    // What the rows say beyond the best setups, per model, in the report's words.
    for model in &mut answer.models {
        let rows: Vec<ClaimRow> = merged.claim_rows.iter().filter(|r| r.model == model.model).cloned().collect();
        model.findings = crate::output::bottom_line::findings(&merged.names, &rows);
        model.apart = crate::output::bottom_line::apart_pairs(&rows).into_iter().map(|(a, b)| [a, b]).collect();
    }
    let path = crate::checks::reference::stored_study_path(reference, &m.study);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let text = serde_json::to_string_pretty(&answer)
        .map_err(|e| Error::Destination { path: path.clone(), message: format!("cannot write: {e}") })?;
    folder::write_atomic(&path, format!("{text}\n").as_bytes())?;
    Ok(path)
}
