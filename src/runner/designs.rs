//! Design files: the designs `shotdamp report` shows (their stored answers evaluated again)
//! and `shotdamp design --store`, which writes the answers (docs/design.md, "In the report").

use std::path::{Path, PathBuf};

use super::{run_and_write, Finished, Settings};
use crate::analysis::Progress;
use crate::checks::reference::BaselineMode;
use crate::experiment::{self, Experiment};
use crate::output::ReportOptions;

/// How `shotdamp design` runs.
#[derive(Debug, Clone)]
pub struct DesignSettings {
    /// The reference folder (stored answers are written below it).
    pub reference: PathBuf,
    /// Where the report goes.
    pub out: PathBuf,
    /// Worker threads (`None`: one per core).
    pub jobs: Option<usize>,
    /// Store each model's answer in `REFERENCE/designs/` ([`store_designs`]).
    pub store: bool,
    /// Seconds after which the searches stop and keep their best layouts so far
    /// ([`crate::design::Spec::halt`]); `None`: no limit.
    pub time_limit: Option<f64>,
    /// A flag that, once raised (the command line raises it on Ctrl-C), stops the searches
    /// likewise.
    pub interrupt: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    /// A folder of a sharded search's parts ([`super::design_parts`]): the designs take what
    /// their searches ended with from there and search nothing.
    pub merge: Option<PathBuf>,
}

/// What `shotdamp design` did.
pub struct DesignRun {
    /// The run and its report.
    pub finished: Finished,
    /// The answers stored (`store`).
    pub stored: Vec<PathBuf>,
}

/// Design files searched as `shotdamp design FILE... [--store]` does: every file must be a
/// design file (`kind = "design"`); their report is written without baselines (the report's
/// baselines sample the replayed designs, not a search); with `store`, each model's answer
/// is written to `REFERENCE/designs/`. The arguments after `settings` are those of
/// [`run_and_write`].
pub fn run(
    files: &[PathBuf],
    settings: &DesignSettings,
    progress: &dyn Progress,
    log: &(dyn Fn(String) + Sync),
    staging: &dyn Fn(PathBuf),
) -> crate::Result<DesignRun> {
    run_loaded(load(files, &settings.reference)?, settings, progress, log, staging)
}

/// The design files of `files`, loaded and validated once (a finite-element model read and
/// reduced once) for [`budgets_of`], [`probe_of`] and [`run_loaded`]; a file that is not a
/// design is refused.
pub fn load(files: &[PathBuf], reference: &Path) -> crate::Result<Vec<Experiment>> {
    let exps = experiment::loader::load_all(files, reference)?;
    designs_only(&exps)?;
    Ok(exps)
}

/// [`run`] of designs already loaded ([`load`]).
pub fn run_loaded(
    mut exps: Vec<Experiment>,
    settings: &DesignSettings,
    progress: &dyn Progress,
    log: &(dyn Fn(String) + Sync),
    staging: &dyn Fn(PathBuf),
) -> crate::Result<DesignRun> {
    designs_only(&exps)?;
    let started = std::time::Instant::now();
    let halt = crate::design::halt::Halt {
        deadline: settings.time_limit.map(|limit| started + std::time::Duration::from_secs_f64(limit)),
        interrupt: settings.interrupt.clone(),
        after: Default::default(),
        outlook: Default::default(),
        search: 0,
    };
    for e in &mut exps {
        if let Some(spec) = e.analysis.design_mut() {
            // One deadline for every design of the run; each plans and paces its own work.
            spec.halt =
                crate::design::halt::Halt { after: Default::default(), outlook: Default::default(), ..halt.clone() };
        }
    }
    if let Some(dir) = &settings.merge {
        super::design_parts::merge_into(&mut exps, dir)?;
    }
    let run = Settings {
        reference: settings.reference.clone(),
        out: settings.out.clone(),
        jobs: settings.jobs,
        writing: ReportOptions::default(),
        baseline_mode: BaselineMode::Off,
        bless: false,
    };
    let finished = run_and_write(&exps, &[], &run, progress, log, staging)?;
    let stored = if settings.store {
        let threads = super::threads(settings.jobs)?;
        let seconds = started.elapsed().as_secs_f64();
        store_designs(&finished.results, &settings.reference, seconds, threads, settings.merge.as_deref())?
    } else {
        Vec::new()
    };
    Ok(DesignRun { finished, stored })
}

/// Refuses a file that is not a design (`shotdamp design` and its dry run alike).
fn designs_only(exps: &[Experiment]) -> crate::Result<()> {
    match exps.iter().find(|e| e.analysis.design().is_none()) {
        Some(e) => Err(crate::Error::invalid(
            &e.path,
            "analysis.kind",
            format!("\"{}\"", e.analysis.kind()),
            "`shotdamp design` runs design files (kind = \"design\"); run other experiments with `shotdamp run`",
        )),
        None => Ok(()),
    }
}

/// What each design of `files` costs at most, before anything runs: the experiment's key, its
/// structure's number of masses and its [`Budget`](crate::design::Budget) (loading validates
/// the files as [`run`] does).
pub fn budgets(files: &[PathBuf], reference: &Path) -> crate::Result<Vec<(String, usize, crate::design::Budget)>> {
    Ok(budgets_of(&load(files, reference)?))
}

/// [`budgets`] of designs already loaded ([`load`]).
pub fn budgets_of(exps: &[Experiment]) -> Vec<(String, usize, crate::design::Budget)> {
    exps.iter()
        .filter_map(|e| {
            let (spec, _) = e.analysis.design()?;
            Some((e.key(), e.structure.dof(), crate::analysis::design_problem::budget(e, spec)))
        })
        .collect()
}

/// The design files of `dir` marked `report = true` (none when the folder does not exist), set to evaluate the
/// answers their searches stored instead of searching (docs/design.md, "In the report").
pub fn report_designs(dir: &Path, reference: &Path) -> crate::Result<Vec<Experiment>> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut exps = experiment::loader::load_all(&experiment::loader::discover(dir)?, reference)?;
    for e in &mut exps {
        let kind = e.analysis.kind();
        match e.analysis.design_mut() {
            Some(spec) => spec.replay = true,
            None => {
                return Err(crate::Error::invalid(
                    &e.path,
                    "analysis.kind",
                    format!("\"{kind}\""),
                    "\"design\": the designs folder holds design files only",
                ))
            }
        }
    }
    exps.retain(|e| e.analysis.design().is_some_and(|(spec, _)| spec.report));
    Ok(exps)
}

/// `shotdamp design --store`: each model's answer, with how it was computed, as
/// `REFERENCE/designs/ID/MODEL.json` (written atomically); the files written. `merged_from`:
/// the folder of a sharded search's parts the answers were merged from, if so.
pub fn store_designs(
    results: &[crate::analysis::ExperimentResult],
    reference: &Path,
    seconds: f64,
    threads: usize,
    merged_from: Option<&Path>,
) -> crate::Result<Vec<PathBuf>> {
    let mut stored = Vec::new();
    for r in results {
        let Some(answer) = &r.design else { continue };
        let mut answer = answer.clone();
        answer.provenance = format!(
            "searched by `shotdamp design {} --store` (shotdamp {}) on {}; the command ({} design run(s)) took {:.0} s on {} threads",
            r.experiment.path.display(),
            env!("CARGO_PKG_VERSION"),
            crate::output::files::today_utc(),
            results.iter().filter(|r| r.design.is_some()).count(),
            seconds,
            threads
        ) + &merged_from
            .map(|d| format!(" (merging the parts of a sharded search from {})", d.display()))
            .unwrap_or_default();
        let path = crate::checks::reference::stored_design_path(reference, &r.experiment.key());
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| crate::Error::io(dir, e))?;
        }
        let text = answer.to_json()?;
        crate::output::files::write_atomic(&path, text.as_bytes())?;
        stored.push(path);
    }
    Ok(stored)
}

/// One design's measured cost of a layout evaluation ([`probe`]).
#[derive(Debug, Clone)]
pub struct Probe {
    /// The experiment's key.
    pub key: String,
    /// Layouts evaluated on the model the searches run on ...
    pub layouts: usize,
    /// ... and the mean seconds one took on one thread.
    pub seconds_per_evaluation: f64,
    /// Where the searches run on the coarser model of `[design.screen]`: what an evaluation on
    /// the file's model costs on one thread, `seconds_per_evaluation` times the ratio of the
    /// two models' times on one layout at [`PROBE_FREQUENCIES`] frequencies of each band.
    pub judged_seconds_per_evaluation: Option<f64>,
    /// Whether the search's starts are expected to spend their iterations: at least
    /// [`NOISY_SHARE`] of the probed steady states never settled (their statistics make the
    /// objective noisy) and the design has no `step_tolerance` to end a start whose simplex is
    /// small.
    pub spends_iterations: bool,
}

/// Seconds of one thread the probe spends evaluating layouts (at least one).
pub const PROBE_SECONDS: f64 = 2.0;

/// Frequencies of each band at which a screened design's probe compares its file's model with
/// its screen (spread evenly over the band, its edges included).
pub const PROBE_FREQUENCIES: usize = 4;

/// The share of the probed steady states that never settle from which a design's objective
/// counts as noisy ([`Probe::spends_iterations`]): most of the six-storey building's (its
/// starts spend their iterations), a few near a fold on the paper's structure (whose starts
/// converge).
pub const NOISY_SHARE: f64 = 0.25;

/// What a layout evaluation of a design costs, measured on one thread: the layouts of the
/// search's coarse scans (every placement at each clearance of the scan, in a shuffled
/// order) evaluated one after another for [`PROBE_SECONDS`], on the model the searches run on;
/// a screened design's file's model from its ratio to the screen's on one layout at a few
/// frequencies. One per design of
/// `files`.
pub fn probe(files: &[PathBuf], reference: &Path) -> crate::Result<Vec<Probe>> {
    probe_of(&load(files, reference)?)
}

/// [`probe`] of designs already loaded ([`load`]).
pub fn probe_of(exps: &[Experiment]) -> crate::Result<Vec<Probe>> {
    use crate::design::search::{coarse_layout, COARSE};
    let one = super::pool(Some(1))?;
    let mut out = Vec::new();
    for e in exps {
        let Some((spec, steady)) = e.analysis.design() else { continue };
        let problem = crate::analysis::design::problem(e, spec, steady);
        let screen = crate::analysis::design::screen(e, spec, steady);
        let space = crate::analysis::design_shards::spaces(e, spec).swap_remove(0);
        // Every (placement, clearance) of the coarse scans, in an order that mixes both.
        let mut samples: Vec<(usize, usize)> =
            (0..space.placements.len()).flat_map(|p| (0..COARSE.len()).map(move |z| (p, z))).collect();
        samples.sort_by_key(|&(p, z)| ((p * COARSE.len() + z) as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let searched = screen.as_ref().unwrap_or(&problem);
        let (layouts, seconds, noisy) = one.install(|| {
            let bare = crate::design::bare(searched);
            let started = std::time::Instant::now();
            let (mut n, mut unsettled, mut points) = (0, 0, 0);
            for &(p, z) in &samples {
                if n > 0 && started.elapsed().as_secs_f64() > PROBE_SECONDS {
                    break;
                }
                let ev =
                    crate::design::evaluate(searched, &bare, &coarse_layout(&space.placements[p], COARSE[z], &space));
                unsettled += ev.unsettled;
                points += ev.points;
                n += 1;
            }
            (n, started.elapsed().as_secs_f64(), unsettled as f64 >= NOISY_SHARE * points as f64 && points > 0)
        });
        // The file's model against the screen's: one layout at a few frequencies of each band
        // on both, the ratio of their times (what the few frequencies miss cancels).
        let judged_seconds_per_evaluation = screen.as_ref().map(|sp| {
            let sliced = |problem: &crate::design::Problem| {
                let mut sliced = problem.clone();
                for b in &mut sliced.bands {
                    let n = b.freq_hz.len();
                    if n > PROBE_FREQUENCIES {
                        let m = PROBE_FREQUENCIES;
                        b.freq_hz = (0..m).map(|i| b.freq_hz[(i * (n - 1) + (m - 1) / 2) / (m - 1)]).collect();
                    }
                }
                sliced
            };
            let hosts = space.placements.last().cloned().unwrap_or_default();
            let layout = coarse_layout(&hosts, 0.0, &space);
            // The mean of as many evaluations as fit in a fifth of a second (at least one): the
            // screen's takes milliseconds.
            let time = |problem: &crate::design::Problem| {
                let problem = sliced(problem);
                one.install(|| {
                    let bare = crate::design::bare(&problem);
                    let started = std::time::Instant::now();
                    let mut n = 0u32;
                    while n == 0 || started.elapsed().as_secs_f64() < 0.2 {
                        crate::design::evaluate(&problem, &bare, &layout);
                        n += 1;
                    }
                    started.elapsed().as_secs_f64() / f64::from(n)
                })
            };
            seconds / layouts.max(1) as f64 * time(&problem) / time(sp).max(1e-9)
        });
        out.push(Probe {
            key: e.key(),
            layouts,
            seconds_per_evaluation: seconds / layouts.max(1) as f64,
            judged_seconds_per_evaluation,
            spends_iterations: noisy && spec.search.step_tolerance == 0.0,
        });
    }
    Ok(out)
}
