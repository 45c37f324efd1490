//! A study's share computed into its folder and a folder's outputs written: what a whole
//! study ([`super::study`]) and an adaptive study's rounds ([`super::study_rounds`]) share.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;

use crate::analysis::study::{self as run, ClaimRow, ClaimSummary, DependencyCache};
use crate::checks::reference::ReferenceStore;
use crate::error::{Error, Result};
use crate::experiment::study::{Sample, Study};
use crate::experiment::Experiment;
use crate::output::heatmap;
use crate::output::manifest::{Manifest, Shard};
use crate::output::study as folder;

/// What a shard's run says as it goes (every method does nothing by default).
pub trait StudyProgress: Sync {
    /// Another live process holds the shard's lock (`holder`); the run waits for it.
    fn waiting(&self, _shard: Shard, _holder: &str) {}
    /// `done` of the shard's `total` samples are in the folder already.
    fn resuming(&self, _done: usize, _total: usize) {}
    /// One more simulated point of a sample (a caller may stop the shard here by unwinding).
    fn point(&self) {}
    /// One more sample computed.
    fn sample(&self) {}
    /// An adaptive study's round `round` starts, with `samples` samples over every shard.
    fn round(&self, _round: u32, _samples: usize) {}
    /// A batch written: `done` of `total`, `seconds` since this run started computing.
    fn batch(&self, _done: usize, _total: usize, _first: usize, _seconds: f64) {}
}

/// Says nothing.
pub struct Quiet;

impl StudyProgress for Quiet {}

/// How a shard's run ended.
#[derive(Debug)]
pub enum ShardEnd {
    /// The folder held the whole shard already.
    AlreadyComplete,
    /// The shard's part, written now.
    Written(PathBuf),
}

/// Computes the share `shard` of `study`'s samples into the folder `out` (created, or resumed
/// when it holds this study's batches).
pub fn compute_shard(
    study: &Study,
    reference: &Path,
    out: &Path,
    shard: Shard,
    pool: &rayon::ThreadPool,
    progress: &dyn StudyProgress,
) -> Result<ShardEnd> {
    let manifest = Manifest::of(study, &study.path.display().to_string());
    let refs = super::study_references(study, reference)?;
    let mine: Vec<&Sample> = study.samples.iter().filter(|s| shard.owns(s.index)).collect();
    // The values the experiments take from others (run at each sample's structure, cached),
    // checked for every sample before any sample runs.
    let cache = DependencyCache::default();
    let prepared = pool.install(|| run::prepare_all(study, &mine, &refs, &cache))?;
    let manifest = folder::prepare(out, &manifest, shard.count)?;
    let _lock = take_lock(out, shard, progress)?;
    let (complete, done) = folder::done(out, &manifest, shard)?;
    let end = if complete {
        ShardEnd::AlreadyComplete
    } else {
        let todo: Vec<(&Sample, &Vec<Experiment>)> =
            mine.iter().copied().zip(&prepared).filter(|(s, _)| done.binary_search(&s.index).is_err()).collect();
        if !done.is_empty() {
            progress.resuming(done.len(), mine.len());
        }
        compute(study, &manifest, &todo, &refs, pool, out, shard, (done.len(), mine.len()), progress)?;
        ShardEnd::Written(folder::finish_shard(out, &manifest, shard, &run::table(study, &[]))?)
    };
    Ok(end)
}

/// Takes the shard's lock, waiting while another live process computes the same shard (a
/// requeued task whose first run still ends, a second terminal): when it ends, this run finds
/// the shard complete, or resumes it.
fn take_lock(out: &Path, shard: Shard, progress: &dyn StudyProgress) -> Result<folder::ShardLock> {
    let mut told = false;
    loop {
        match folder::lock(out, shard)? {
            Ok(lock) => return Ok(lock),
            Err(holder) => {
                if !told {
                    progress.waiting(shard, &holder.to_string());
                    told = true;
                }
                std::thread::sleep(std::time::Duration::from_millis(500));
            }
        }
    }
}

/// Computes `todo` in batches, each written atomically (so a stopped shard resumes).
#[allow(clippy::too_many_arguments)]
fn compute(
    study: &Study,
    manifest: &Manifest,
    todo: &[(&Sample, &Vec<Experiment>)],
    refs: &ReferenceStore,
    pool: &rayon::ThreadPool,
    out: &Path,
    shard: Shard,
    (first, total): (usize, usize),
    progress: &dyn StudyProgress,
) -> Result<()> {
    let batch = 4 * pool.current_num_threads();
    let started = Instant::now();
    let mut done = first;
    for chunk in todo.chunks(batch) {
        let rows: Vec<Result<Vec<ClaimRow>>> = pool.install(|| {
            chunk
                .par_iter()
                .map(|(s, e)| {
                    let r = run::run_prepared(e, s, refs, &|| progress.point()).map_err(|err| study.at_sample(err, s));
                    progress.sample();
                    r
                })
                .collect()
        });
        let rows: Vec<Vec<ClaimRow>> = rows.into_iter().collect::<Result<_>>()?;
        let rows: Vec<ClaimRow> = rows.into_iter().flatten().collect();
        folder::write_batch(out, manifest, shard, chunk[0].0.index, &run::table(study, &rows))?;
        done += chunk.len();
        progress.batch(done, total, first, started.elapsed().as_secs_f64());
    }
    Ok(())
}

/// A merged study folder.
pub struct Merged {
    /// The study folder's manifest.
    pub manifest: Manifest,
    /// Rows of the long table.
    pub rows: usize,
    /// The long table's CSV file.
    pub table: PathBuf,
    /// Where each claim holds, per model.
    pub summaries: Vec<ClaimSummary>,
    /// The varied values' names (what the summaries' words name).
    pub names: Vec<String>,
    /// Per sample: the claims that hold and those that fail.
    pub samples: Vec<crate::analysis::study_samples::SampleSummary>,
    /// Every row of the long table.
    pub claim_rows: Vec<ClaimRow>,
}

/// Writes a study folder's long table (`df`, sorted by sample and check), summary, table per
/// sample and heat maps.
pub fn write_outputs(dir: &Path, manifest: Manifest, mut df: polars::prelude::DataFrame) -> Result<Merged> {
    folder::write_merged(dir, &manifest, &mut df)?;
    let rows = folder::rows(&df, &manifest, dir)?;
    let models: Vec<String> = manifest.models.iter().map(|m| m.0.clone()).collect();
    let summaries = run::summarise(&models, &rows);
    let names: Vec<String> = manifest.vary.iter().map(|a| a.name.clone()).collect();
    folder::write_table(dir, &run::summary_table(&manifest.study, &names, &summaries))?;
    let samples = crate::analysis::study_samples::per_sample(&rows);
    folder::write_table(dir, &crate::analysis::study_samples::table(&manifest.study, &names, &samples))?;
    let figures = dir.join("figures");
    std::fs::create_dir_all(&figures).map_err(|e| Error::io(&figures, e))?;
    for map in heatmap::maps(&manifest, &rows, &[]) {
        heatmap::write(&map, &figures)?;
    }
    let table = dir.join(format!("{}.csv", manifest.study));
    Ok(Merged { rows: df.height(), table, summaries, names, samples, manifest, claim_rows: rows })
}
