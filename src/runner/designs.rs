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
    };
    for e in &mut exps {
        if let Some(spec) = e.analysis.design_mut() {
            // One deadline for every design of the run; each plans and paces its own work.
            spec.halt = crate::design::halt::Halt { after: Default::default(), ..halt.clone() };
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

/// One design's measured cost of a steady state ([`probe`]).
#[derive(Debug, Clone)]
pub struct Probe {
    /// The experiment's key.
    pub key: String,
    /// The layout evaluated: its hosts (0-based) ...
    pub hosts: Vec<usize>,
    /// ... and its clearance, mm.
    pub clearance_mm: f64,
    /// Seconds one steady state took on one thread.
    pub seconds_per_point: f64,
    /// The same on the model of `[design.screen]` (the searches'), where the design has one.
    pub screen_seconds_per_point: Option<f64>,
}

/// What one steady state of a design costs, measured: one layout evaluated on one thread (the
/// shot split evenly over the last `max_beds` candidates, at the geometric mean of the
/// clearance bounds), its time over its steady states; one per design of `files`.
pub fn probe(files: &[PathBuf], reference: &Path) -> crate::Result<Vec<Probe>> {
    probe_of(&load(files, reference)?)
}

/// [`probe`] of designs already loaded ([`load`]).
pub fn probe_of(exps: &[Experiment]) -> crate::Result<Vec<Probe>> {
    let one = super::pool(Some(1))?;
    let mut out = Vec::new();
    for e in exps {
        let Some((spec, steady)) = e.analysis.design() else { continue };
        let problem = crate::analysis::design::problem(e, spec, steady);
        let k = spec.max_beds.clamp(1, spec.candidates.len().max(1));
        let hosts: Vec<usize> = spec.candidates[spec.candidates.len().saturating_sub(k)..].to_vec();
        let (lo, hi) = spec.clearance_mm;
        let d = (lo * hi).sqrt();
        let layout = crate::design::Layout {
            masses_kg: vec![spec.shot_kg / hosts.len().max(1) as f64; hosts.len()],
            clearances_mm: vec![d; hosts.len()],
            hosts: hosts.clone(),
        };
        let measure = |problem: &crate::design::Problem| {
            one.install(|| {
                let bare = crate::design::bare(problem);
                let start = std::time::Instant::now();
                let ev = crate::design::evaluate(problem, &bare, &layout);
                start.elapsed().as_secs_f64() / ev.points.max(1) as f64
            })
        };
        let seconds_per_point = measure(&problem);
        let screen = crate::analysis::design::screen(e, spec, steady);
        let screen_seconds_per_point = screen.as_ref().map(measure);
        out.push(Probe { key: e.key(), hosts, clearance_mm: d, seconds_per_point, screen_seconds_per_point });
    }
    Ok(out)
}
