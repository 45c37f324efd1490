//! Runs experiments and studies into a report, as a library call: what `shotdamp run`,
//! `shotdamp design` and `shotdamp report` do, without the command line. [`run_and_write`]
//! loads the references, schedules the experiments on a thread pool as soon as those whose
//! values they use have finished ([`schedule`]), runs the studies beside them, writes the
//! report into a staging folder and renames it into place; it returns the results and the
//! failed checks. Printing, progress bars and the interrupt handler are the caller's.

pub mod damping;
pub mod design_parts;
pub mod designs;
pub mod schedule;
pub mod study;
pub mod study_rounds;
pub mod study_shard;

use std::path::{Path, PathBuf};

use crate::analysis::{self, ExperimentResult, Progress};
use crate::checks::baseline;
use crate::checks::reference::{BaselineMode, ReferenceStore};
use crate::error::{Error, Result};
use crate::experiment::study::{Sample, Study};
use crate::experiment::{self, Experiment};
use crate::output::manifest::{Manifest, StudyRun};
use crate::output::{ReportOptions, ReportWriter};

/// How a run is written.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The reference folder (`reference/`).
    pub reference: PathBuf,
    /// Where the report goes (replaced only when it is a report: see
    /// [`crate::output::destination`]).
    pub out: PathBuf,
    /// Worker threads (`None`: one per core).
    pub jobs: Option<usize>,
    /// How the report is written.
    pub writing: ReportOptions,
    /// Whether each experiment is compared with its blessed baseline.
    pub baseline_mode: BaselineMode,
    /// Write each experiment's baseline sample into `reference/baseline/`.
    pub bless: bool,
}

/// How the whole report is written ([`report`]): the rest of [`Settings`] follows from the
/// report's inputs (the reference folder) and from `bless` (every experiment is compared with
/// its blessed baseline unless the baselines are being written).
#[derive(Debug, Clone)]
pub struct ReportSettings {
    /// Where the report goes (replaced only when it is a report).
    pub out: PathBuf,
    /// Worker threads (`None`: one per core).
    pub jobs: Option<usize>,
    /// How the report is written (`complete` is set by [`report`]).
    pub writing: ReportOptions,
    /// Write each experiment's baseline sample into `reference/baseline/` instead of
    /// comparing with it.
    pub bless: bool,
}

/// What a run produced.
pub struct Finished {
    /// The experiments' results, in the order given.
    pub results: Vec<ExperimentResult>,
    /// The report's folder.
    pub dest: PathBuf,
    /// Checks evaluated.
    pub checks: usize,
    /// One line per failed check: experiment, figure, check, computed, expected, tolerance.
    pub failed: Vec<String>,
    /// Where the baselines were written (`bless`).
    pub blessed: Option<PathBuf>,
}

impl Finished {
    /// True when no check failed.
    pub fn passed(&self) -> bool {
        self.failed.is_empty()
    }
}

/// Most worker threads per core: more threads than this only add switching (the work is
/// CPU-bound) and each takes a stack; results never depend on the count.
pub const JOBS_PER_CORE: usize = 8;

/// The most worker threads `--jobs` (and `jobs=` in Python) may ask for on this machine:
/// [`JOBS_PER_CORE`] per core, and never fewer than 16.
pub fn max_jobs() -> usize {
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    (JOBS_PER_CORE * cores).max(16)
}

/// The number of worker threads `jobs` asks for (`None`: what a default pool takes, one per
/// core unless `RAYON_NUM_THREADS` says otherwise), checked against [`max_jobs`].
pub fn threads(jobs: Option<usize>) -> Result<usize> {
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    match jobs {
        None => Ok(rayon::current_num_threads()),
        Some(j) if j >= 1 && j <= max_jobs() => Ok(j),
        Some(j) => Err(Error::invalid(
            "(command line)",
            "--jobs",
            j,
            format!(
                "give 1 to {} worker threads (up to {JOBS_PER_CORE} per core, here {cores} cores, and never fewer than 16: more only add switching)",
                max_jobs()
            ),
        )),
    }
}

/// A thread pool of `jobs` workers (`None`: one per core), at most [`max_jobs`]. Its workers
/// take the cancellation hook of the thread that builds it
/// ([`cancel`](crate::sim::motion::cancel)): a computation stopped from outside (Ctrl-C in
/// Python) stops at its next simulated period on every thread, also on the pools it builds
/// for itself.
pub fn pool(jobs: Option<usize>) -> Result<rayon::ThreadPool> {
    let hook = crate::sim::motion::cancel::current();
    let mut b = rayon::ThreadPoolBuilder::new().start_handler(move |_| {
        crate::sim::motion::cancel::replace(hook.clone());
    });
    if let Some(j) = jobs {
        b = b.num_threads(threads(Some(j))?);
    }
    let shown = jobs.map_or_else(|| "(one per core)".to_string(), |j| j.to_string());
    b.build().map_err(|e| Error::invalid("(command line)", "--jobs", shown, format!("no thread pool: {e}")))
}

/// The references of a study's experiment and of those it takes values from, without the
/// baseline (it holds the experiments' own values, not a sample's).
pub fn study_references(study: &Study, reference: &Path) -> Result<ReferenceStore> {
    let exps: Vec<_> = study.parts().flat_map(|p| p.base.iter().chain(&p.dependencies)).cloned().collect();
    ReferenceStore::load(reference, &exps)
}

/// The stored answer of a study marked `stored = true` (`reference/studies/ID.json`), and
/// whether this version of the study computed it.
fn stored_run(s: &Study, reference: &Path) -> Result<crate::output::manifest::StoredRun> {
    let path = crate::checks::reference::stored_study_path(reference, &s.id);
    if !path.is_file() {
        return Err(Error::invalid(
            &s.path,
            "study.stored",
            "true",
            format!(
                "no stored answer {}: run `shotdamp study {} --store` (or `shotdamp study merge DIR --store` after its shards)",
                path.display(),
                s.path.display()
            ),
        ));
    }
    let text = crate::error::read_to_string(&path)?;
    let answer: crate::experiment::study::stored::StoredStudy = serde_json::from_str(&text)
        .map_err(|e| Error::Parse { file: path.display().to_string(), message: e.to_string() })?;
    let fresh = answer.fingerprint == Manifest::of(s, &s.path.display().to_string()).fingerprint;
    Ok(crate::output::manifest::StoredRun { answer, fresh })
}

/// The studies `shotdamp report` runs: those of `dir` marked `report = true` or `stored = true`
/// (none when the folder does not exist).
pub fn report_studies(dir: &Path, reference: &Path) -> Result<Vec<Study>> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for file in experiment::loader::discover(dir)? {
        let s = experiment::study::load(&file, reference)?;
        if s.report || s.stored {
            out.push(s);
        }
    }
    Ok(out)
}

/// Runs the experiments, each as soon as those whose exports it uses have finished, in
/// parallel, and the studies beside them; writes the report. `staging` is called with the
/// staging folder's path before it exists (the command line removes it on an interrupt);
/// `log` receives one line per finished experiment and study.
pub fn run_and_write(
    exps: &[Experiment],
    studies: &[Study],
    settings: &Settings,
    progress: &dyn Progress,
    log: &(dyn Fn(String) + Sync),
    staging: &dyn Fn(PathBuf),
) -> Result<Finished> {
    let (reference, out) = (settings.reference.as_path(), settings.out.as_path());
    let graph = experiment::loader::dependency_graph(exps)?;
    let mut refs = ReferenceStore::load(reference, exps)?;
    refs.load_baselines(reference, exps, settings.baseline_mode)?;
    refs.load_designs(reference, exps)?;
    let study_refs = studies.iter().map(|s| study_references(s, reference)).collect::<Result<Vec<_>>>()?;
    let mut inputs: Vec<(&str, &Path)> = vec![("the reference folder", reference)];
    inputs.extend(settings.writing.templates.as_deref().map(|t| ("the templates folder", t)));
    inputs.extend(exps.iter().map(|e| ("an experiment file", e.path.as_path())));
    inputs.extend(studies.iter().map(|s| ("a study file", s.path.as_path())));
    crate::output::destination::refuse_overlap(out, &inputs)?;
    // Scans of the paper's figures, when the reviewer keeps some (reference/scans/).
    let writing =
        ReportOptions { scans: crate::output::scan::load_all(&reference.join("scans"))?, ..settings.writing.clone() };
    staging(crate::output::destination::staging_path(out)?);
    let writer = ReportWriter::create(out, &writing)?;
    let pool = pool(settings.jobs)?;
    // Studies need no exports: they run beside the experiments, on the same pool.
    let (results, study_runs) = pool.install(|| {
        rayon::join(
            || schedule::run(exps, &graph, &refs, &writer, &pool, progress, log),
            || run_studies(studies, &study_refs, reference, progress, log),
        )
    });
    let (mut results, mut study_runs) = match (results, study_runs) {
        (Ok(r), Ok(s)) => (r, s),
        (Err(e), _) | (_, Err(e)) => {
            writer.abandon();
            return Err(e);
        }
    };
    // Where the experiments themselves sit on the studies' maps (exported clearances included).
    let exports: experiment::Exports = results.iter().map(|r| (r.experiment.key(), r.exports.clone())).collect();
    for (run, s) in study_runs.iter_mut().zip(studies) {
        run.assumed = run.manifest.models.iter().map(|(model, _)| s.assumed(model, &exports)).collect();
    }
    let dest = writer.finish(&mut results, &study_runs)?;
    let mut blessed = None;
    if settings.bless {
        let dir = reference.join("baseline");
        for r in &results {
            crate::output::write_baseline(&dir, &r.experiment.key(), &baseline::sample(&r.tables))?;
        }
        blessed = Some(dir);
    }
    let failed = results
        .iter()
        .flat_map(|r| {
            r.checks.iter().filter(|c| c.status.fails()).map(move |c| {
                format!(
                    "  {} ({}): {}: computed {} vs expected {} (tolerance {}){}",
                    r.experiment.key(),
                    r.experiment.meta.figure,
                    c.name,
                    crate::checks::fmt_num(c.computed),
                    crate::checks::fmt_num(c.expected),
                    c.tolerance,
                    c.detail.as_ref().map(|d| format!("; {d}")).unwrap_or_default()
                )
            })
        })
        .collect();
    let checks = results.iter().map(|r| r.checks.len()).sum();
    Ok(Finished { results, dest, checks, failed, blessed })
}

/// Where a whole report reads from (`shotdamp report`'s folders).
#[derive(Debug, Clone)]
pub struct ReportInputs {
    /// Folder of experiment files (`experiments/`).
    pub experiments: PathBuf,
    /// Folder of reference data (`reference/`).
    pub reference: PathBuf,
    /// Folder of study files (`None`: `studies/` beside the experiments folder).
    pub studies: Option<PathBuf>,
    /// Folder of design files (`None`: `designs/` beside the experiments folder).
    pub designs: Option<PathBuf>,
}

impl ReportInputs {
    /// The folders of a checkout: `experiments/`, `reference/`, `studies/` and `designs/`
    /// below `root`.
    pub fn at(root: &Path) -> ReportInputs {
        // "." gives the command line's relative paths (they are quoted in the report).
        let under = |name: &str| if root == Path::new(".") { PathBuf::from(name) } else { root.join(name) };
        ReportInputs { experiments: under("experiments"), reference: under("reference"), studies: None, designs: None }
    }

    fn beside(&self, name: &str) -> PathBuf {
        self.experiments.parent().unwrap_or(Path::new("")).join(name)
    }

    /// The studies folder used.
    pub fn studies_dir(&self) -> PathBuf {
        self.studies.clone().unwrap_or_else(|| self.beside("studies"))
    }

    /// The designs folder used.
    pub fn designs_dir(&self) -> PathBuf {
        self.designs.clone().unwrap_or_else(|| self.beside("designs"))
    }

    /// Refuses an output folder that is, contains or lies inside one of these folders (every
    /// command's inputs live there: `run`, `design`, `study` and `report` alike).
    pub fn refuse_overlap(&self, out: &Path) -> Result<()> {
        crate::output::destination::refuse_overlap(
            out,
            &[
                ("the experiments folder", &self.experiments),
                ("the reference folder", &self.reference),
                ("the studies folder", &self.studies_dir()),
                ("the designs folder", &self.designs_dir()),
            ],
        )
    }
}

/// The whole report, as `shotdamp report` writes it: every experiment file of the folder, the
/// stored answers of the design files, the studies marked `report = true`, each experiment
/// compared with its blessed baseline (or its baseline written, `bless`). The arguments after
/// `settings` are those of [`run_and_write`].
pub fn report(
    inputs: &ReportInputs,
    settings: &ReportSettings,
    progress: &dyn Progress,
    log: &(dyn Fn(String) + Sync),
    staging: &dyn Fn(PathBuf),
) -> Result<Finished> {
    let reference = inputs.reference.as_path();
    let files = experiment::loader::discover(&inputs.experiments)?;
    if files.is_empty() {
        return Err(Error::Parse {
            file: inputs.experiments.display().to_string(),
            message: "no experiment files (*.toml) found".into(),
        });
    }
    let mut exps = experiment::loader::load_all(&files, reference)?;
    let designs_dir = inputs.designs_dir();
    exps.extend(designs::report_designs(&designs_dir, reference)?);
    let studies_dir = inputs.studies_dir();
    let studies = report_studies(&studies_dir, reference)?;
    inputs.refuse_overlap(&settings.out)?;
    let settings = Settings {
        reference: reference.to_path_buf(),
        out: settings.out.clone(),
        jobs: settings.jobs,
        writing: ReportOptions { complete: true, smallest_png: true, ..settings.writing.clone() },
        baseline_mode: if settings.bless { BaselineMode::Off } else { BaselineMode::Required },
        bless: settings.bless,
    };
    run_and_write(&exps, &studies, &settings, progress, log, staging)
}

/// Runs the report's studies, each over its samples in parallel, with its references
/// (`refs`, one store per study, without baselines).
fn run_studies(
    studies: &[Study],
    refs: &[ReferenceStore],
    reference: &Path,
    progress: &dyn Progress,
    log: &(dyn Fn(String) + Sync),
) -> Result<Vec<StudyRun>> {
    let mut out = Vec::new();
    for (s, refs) in studies.iter().zip(refs) {
        let started = std::time::Instant::now();
        // No count of points before the samples are built: a counter of unknown total (the
        // command line draws no bar for it; a caller may stop the run at any point).
        let tick = progress.start(&s.id, 0);
        let stored = if s.stored { Some(stored_run(s, reference)?) } else { None };
        let rows = if let Some(st) = &stored {
            // The best sample of each model, as stored, run again.
            let samples: Vec<Sample> = st
                .answer
                .models
                .iter()
                .filter_map(|m| {
                    let b = m.best.first()?;
                    Some(Sample { index: b.sample, model: m.model.clone(), values: b.values.clone() })
                })
                .collect();
            analysis::study::run_all(&s.with_samples(samples), refs, &*tick)?
        } else if s.lattice().is_some() {
            analysis::study_adaptive::run_all(s, refs, &*tick)?
        } else {
            analysis::study::run_all(s, refs, &*tick)?
        };
        let mut manifest = Manifest::of(s, &s.path.display().to_string());
        // An adaptive study's samples are those its rounds computed (a stored study's: those
        // it ran again).
        manifest.samples = if stored.is_some() {
            rows.iter().map(|r| r.sample).collect::<std::collections::BTreeSet<_>>().len()
        } else {
            rows.last().map_or(0, |r| r.sample + 1)
        };
        log(format!(
            "  ok {:<36} study: {} samples ({:.2} s)",
            s.id,
            manifest.samples,
            started.elapsed().as_secs_f64()
        ));
        out.push(StudyRun {
            manifest,
            description: s.description.clone().unwrap_or_default(),
            rows,
            assumed: Vec::new(),
            stored,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::motion::cancel;
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    #[test]
    fn a_pool_built_under_a_cancellation_hook_calls_it_on_every_worker() {
        let calls = Arc::new(AtomicUsize::new(0));
        let c = Arc::clone(&calls);
        let counting =
            cancel::within(Arc::new(move || _ = c.fetch_add(1, Ordering::SeqCst)), || pool(Some(2))).unwrap();
        // Every worker checks (a broadcast reaches each thread once), the hook counts them.
        counting.broadcast(|_| cancel::check());
        assert_eq!(calls.load(Ordering::SeqCst), 2);
        // And a check deep in a parallel loop stops it: the hook's unwinding reaches the caller.
        let stop = Arc::new(|| std::panic::resume_unwind(Box::new("stopped")));
        let stopping = cancel::within(stop, || pool(Some(2))).unwrap();
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            stopping.install(|| (0..64).into_par_iter().for_each(|_| cancel::check()))
        }));
        assert_eq!(r.err().and_then(|p| p.downcast_ref::<&str>().copied()), Some("stopped"));
        // Built without a hook, a pool's workers have none.
        pool(Some(2)).unwrap().broadcast(|_| assert!(cancel::current().is_none()));
    }
}
