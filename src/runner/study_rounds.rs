//! An adaptive study as shards (docs/studies.md, "Adaptive refinement"): each round is a study
//! folder of its own under `parts/round-R`, computed as the study's shards; a shard that has
//! finished its share of a round computes the shares of that round no live process holds
//! (every share's rows are the same whoever computes them), so rounds follow each other
//! without a process waiting on one that has not started. When the last round ends, the
//! rounds' rows, numbered on, are the study's long table.

use std::path::{Path, PathBuf};

use crate::analysis::study::{self as run, ClaimRow};
use crate::analysis::study_adaptive;
use crate::error::Result;
use crate::experiment::study::{Sample, Study};
use crate::output::manifest::{Manifest, Shard};
use crate::output::study as folder;

use super::study_shard::{compute_shard, write_outputs, Merged, ShardEnd, StudyProgress};

/// The folder of round `round` in a study folder.
pub fn round_dir(out: &Path, round: u32) -> PathBuf {
    out.join("parts").join(format!("round-{round}"))
}

/// Whether a study folder is an adaptive study's (it has rounds).
pub fn is_adaptive(dir: &Path) -> bool {
    round_dir(dir, 0).is_dir()
}

/// Computes every round of adaptive `study` in `out`, this process's share `shard` first and
/// then any share of the round no other live process holds, and merges the rounds.
pub fn run_shard(
    study: &Study,
    reference: &Path,
    out: &Path,
    shard: Shard,
    pool: &rayon::ThreadPool,
    progress: &dyn StudyProgress,
) -> Result<(ShardEnd, Option<Merged>)> {
    let manifest = Manifest::of(study, &study.path.display().to_string());
    folder::prepare(out, &manifest, shard.count)?;
    let mut wrote = false;
    let mut rounds = 0;
    let (rows, known) = study_adaptive::rounds(study, |r, samples| {
        let first = samples.first().map_or(0, |s| s.index);
        let renumbered: Vec<Sample> = samples.into_iter().enumerate().map(|(i, s)| Sample { index: i, ..s }).collect();
        progress.round(r, renumbered.len());
        let round = study.with_samples(renumbered);
        let dir = round_dir(out, r);
        for k in 0..shard.count {
            let share = Shard { index: (shard.index + k) % shard.count, count: shard.count };
            if let ShardEnd::Written(_) = compute_shard(&round, reference, &dir, share, pool, progress)? {
                wrote = true;
            }
        }
        rounds += 1;
        round_rows(out, r, first)
    })?;
    let total = rows.last().map_or(0, |r| r.sample + 1);
    let manifest = Manifest { samples: total, shards: shard.count, rounds, ..manifest };
    // Rounds in order, each in sample and check order: the long table's order.
    let df = run::table(study, &rows).to_frame().map_err(|e| crate::error::Error::Destination {
        path: out.to_path_buf(),
        message: format!("cannot tabulate the rounds: {e}"),
    })?;
    let text = serde_json::to_string_pretty(&manifest).map_err(|e| crate::error::Error::Destination {
        path: out.to_path_buf(),
        message: format!("cannot write the manifest: {e}"),
    })?;
    folder::write_atomic(&out.join("study.json"), text.as_bytes())?;
    let merged = write_outputs(out, manifest, df)?;
    if let Some(map) = study_adaptive::map_table(study, &known) {
        folder::write_table(out, &map)?;
    }
    let end = if wrote { ShardEnd::Written(out.join(format!("{}.csv", study.id))) } else { ShardEnd::AlreadyComplete };
    Ok((end, Some(merged)))
}

/// The rows of round `round` of a study folder, numbered from `first`.
fn round_rows(out: &Path, round: u32, first: usize) -> Result<Vec<ClaimRow>> {
    let dir = round_dir(out, round);
    let m = folder::read_manifest(&dir)?;
    let df = folder::merge(&dir, &m)?;
    let mut rows: Vec<ClaimRow> = folder::rows(&df, &m, &dir)?;
    for row in &mut rows {
        row.sample += first;
    }
    Ok(rows)
}

/// The merge of an adaptive study's folder whose rounds have all ended (`manifest.rounds`):
/// its rounds' rows again, numbered on, written as the study wrote them. `None` while they
/// have not.
pub fn merge(dir: &Path, manifest: &Manifest) -> Result<Option<Merged>> {
    if manifest.rounds == 0 {
        return Ok(None);
    }
    let mut rows = Vec::new();
    for r in 0..manifest.rounds {
        let first = rows.last().map_or(0, |x: &ClaimRow| x.sample + 1);
        rows.extend(round_rows(dir, r as u32, first)?);
    }
    let names: Vec<String> = manifest.vary.iter().map(|a| a.name.clone()).collect();
    let df =
        run::rows_table(&manifest.study, &names, &rows).to_frame().map_err(|e| crate::error::Error::Destination {
            path: dir.to_path_buf(),
            message: format!("cannot tabulate the rounds: {e}"),
        })?;
    write_outputs(dir, manifest.clone(), df).map(Some)
}
