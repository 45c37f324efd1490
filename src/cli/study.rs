//! `shotdamp study`: runs a study (or a deterministic share of it) into a folder, and merges
//! the shards' parts into the long table, summary and heat maps.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;

use crate::analysis::study::{self as run, ClaimRow, DependencyCache};
use crate::checks::reference::ReferenceStore;
use crate::error::Error;
use crate::experiment::study::{self, Design, Study};
use crate::output::heatmap;
use crate::output::study::{self as folder, Manifest, Shard};

/// Nominal cost of one simulated point on one core, for the estimate printed before a run
/// (BENCHMARKS.md: the Fig. 8 sweep, 521 points in ~0.28 s on 2 cores).
const SECONDS_PER_POINT: f64 = 1.1e-3;

/// Arguments of `shotdamp study`.
#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct StudyArgs {
    #[command(subcommand)]
    pub command: Option<StudyCommand>,
    /// Study file (studies/*.toml).
    pub file: Option<PathBuf>,
    /// Compute only shard I of N (0-based; sample k belongs to shard k mod N). Default: from
    /// SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX with --shards,
    /// else the whole study (then merged at once).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// The number of shards, with the index from JOB_COMPLETION_INDEX (a Kubernetes Indexed Job).
    #[arg(long, value_name = "N")]
    pub shards: Option<usize>,
    /// Study folder (shared by every shard; default study-runs/ID).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Print the samples (and which shard runs each) and the estimate; compute nothing.
    #[arg(long)]
    pub dry_run: bool,
}

/// Subcommands of `shotdamp study`.
#[derive(Debug, clap::Subcommand)]
pub enum StudyCommand {
    /// Merge the parts of every shard of a study folder; write the long table (CSV, Parquet),
    /// the summary and the heat maps.
    Merge {
        /// The study folder (--out of the shards).
        dir: PathBuf,
    },
}

/// Runs `shotdamp study`.
pub fn dispatch(args: &StudyArgs, reference: &Path) -> anyhow::Result<bool> {
    if let Some(StudyCommand::Merge { dir }) = &args.command {
        merge(dir)?;
        return Ok(true);
    }
    let Some(file) = &args.file else {
        return Err(Error::invalid("(command line)", "FILE", "(missing)", "give a study file, or `merge DIR`").into());
    };
    let study = study::load(file, reference)?;
    let shard = shard(args)?;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("study-runs").join(&study.id));
    let pool = super::pool(args.jobs)?;
    let threads = pool.current_num_threads();
    let mine: Vec<&study::Sample> = study.samples.iter().filter(|s| shard.owns(s.index)).collect();
    // Every sample's experiment is built once before anything runs: a bad value stops here.
    let exps =
        pool.install(|| mine.par_iter().map(|s| study.experiment(s, reference)).collect::<crate::Result<Vec<_>>>())?;
    let refs = references(&study, reference)?;
    let points: u64 = exps
        .iter()
        .map(|e| {
            let mut e = e.clone();
            e.checks = run::claims(&e);
            crate::analysis::work(&e, &refs)
        })
        .sum();
    let estimate = points as f64 * SECONDS_PER_POINT / threads as f64;
    say!(
        "study {}: {} samples ({}; {}), {} claims each; shard {shard}: {} samples, {points} simulated points, roughly {} on {threads} threads{}",
        study.id,
        study.samples.len(),
        size_words(&study),
        study.design.name(),
        run::claims(&study.base[0]).len(),
        mine.len(),
        duration(estimate),
        if exps.iter().all(|e| e.dependencies().is_empty()) {
            ""
        } else {
            " (plus the experiments it takes values from, once per model and structure)"
        }
    );
    if args.dry_run {
        print_samples(&study, shard);
        return Ok(true);
    }
    let manifest = Manifest::of(&study, &file.display().to_string());
    folder::prepare(&out, &manifest)?;
    let (complete, done) = folder::done(&out, shard)?;
    if complete {
        say!("shard {shard} is already complete in {}", out.display());
    } else {
        let todo: Vec<&study::Sample> =
            mine.iter().copied().filter(|s| done.binary_search(&s.index).is_err()).collect();
        if !done.is_empty() {
            say!("resuming: {} of {} samples already written", done.len(), mine.len());
        }
        compute(&study, &todo, &refs, reference, &out, shard, &pool, mine.len(), done.len())?;
        let part = folder::finish_shard(&out, shard, &run::table(&study, &[]))?;
        say!("shard {shard}: {}", part.display());
    }
    if shard.count == 1 {
        merge(&out)?;
    } else {
        say!("when every shard is done: shotdamp study merge {}", out.display());
    }
    Ok(true)
}

/// The references of a study's experiment and of those it takes values from, without the
/// baseline (it holds the experiments' own values, not a sample's).
pub(super) fn references(study: &Study, reference: &Path) -> crate::Result<ReferenceStore> {
    ReferenceStore::load(reference, &[study.base.clone(), study.dependencies.clone()].concat())
}

/// The shard from the command line or the job's environment.
fn shard(args: &StudyArgs) -> anyhow::Result<Shard> {
    let bad = |key: &str, value: &str, msg: &str| Error::invalid("(command line)", key, value, msg);
    let parse = |key: &str, i: &str, n: &str| -> anyhow::Result<Shard> {
        match (i.trim().parse::<usize>(), n.trim().parse::<usize>()) {
            (Ok(index), Ok(count)) if count >= 1 && index < count => Ok(Shard { index, count }),
            _ => Err(bad(key, &format!("{i}/{n}"), "I/N with N >= 1 and 0 <= I < N (shards are 0-based)").into()),
        }
    };
    if let Some(s) = &args.shard {
        let Some((i, n)) = s.split_once('/') else {
            return Err(bad("--shard", s, "I/N, e.g. 0/7 (shards are 0-based)").into());
        };
        return parse("--shard", i, n);
    }
    let env = |k: &str| std::env::var(k).ok();
    if let (Some(i), Some(n)) = (env("SLURM_ARRAY_TASK_ID"), env("SLURM_ARRAY_TASK_COUNT")) {
        return parse("SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT", &i, &n);
    }
    if let Some(i) = env("JOB_COMPLETION_INDEX") {
        let Some(n) = args.shards else {
            return Err(bad(
                "--shards",
                "(missing)",
                "JOB_COMPLETION_INDEX is set: give the number of shards (the Job's completions)",
            )
            .into());
        };
        return parse("JOB_COMPLETION_INDEX/--shards", &i, &n.to_string());
    }
    if args.shards.is_some() {
        return Err(bad("--shards", "(given)", "only with JOB_COMPLETION_INDEX; otherwise use --shard I/N").into());
    }
    Ok(Shard::WHOLE)
}

/// Computes `todo` in batches, each written atomically (so a stopped shard resumes).
#[allow(clippy::too_many_arguments)]
fn compute(
    study: &Study,
    todo: &[&study::Sample],
    refs: &ReferenceStore,
    reference: &Path,
    out: &Path,
    shard: Shard,
    pool: &rayon::ThreadPool,
    total: usize,
    done_before: usize,
) -> anyhow::Result<()> {
    let cache = DependencyCache::default();
    let batch = 4 * pool.current_num_threads();
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(total as u64);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{prefix} [{bar:30}] {pos}/{len} samples, {elapsed} elapsed, ~{eta} left",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_prefix(format!("{} {shard}", study.id));
        bar.set_position(done_before as u64);
        bar
    });
    let started = Instant::now();
    let mut done = done_before;
    for chunk in todo.chunks(batch) {
        let rows: Vec<Vec<ClaimRow>> = pool.install(|| {
            chunk
                .par_iter()
                .map(|s| {
                    let r = run::run_sample(study, s, refs, reference, &cache);
                    if let Some(b) = &bar {
                        b.inc(1);
                    }
                    r
                })
                .collect::<crate::Result<Vec<_>>>()
        })?;
        let rows: Vec<ClaimRow> = rows.into_iter().flatten().collect();
        folder::write_batch(out, shard, chunk[0].index, &run::table(study, &rows))?;
        done += chunk.len();
        if bar.is_none() {
            let per = started.elapsed().as_secs_f64() / (done - done_before) as f64;
            eprintln!(
                "{} {shard}: {done}/{total} samples, {} elapsed, ~{} left",
                study.id,
                duration(started.elapsed().as_secs_f64()),
                duration(per * (total - done) as f64)
            );
        }
    }
    if let Some(b) = bar {
        b.finish();
    }
    Ok(())
}

/// Merges a study folder and writes its outputs; prints where each claim holds.
fn merge(dir: &Path) -> anyhow::Result<()> {
    let manifest = folder::read_manifest(dir)?;
    let mut df = folder::merge(dir, &manifest)?;
    folder::write_merged(dir, &manifest, &mut df)?;
    let rows = folder::rows(&df, &manifest, dir)?;
    let models: Vec<String> = manifest.models.iter().map(|m| m.0.clone()).collect();
    let summaries = run::summarise(&models, &rows);
    let names: Vec<String> = manifest.vary.iter().map(|a| a.name.clone()).collect();
    folder::write_table(dir, &run::summary_table(&manifest.study, &names, &summaries))?;
    let figures = dir.join("figures");
    std::fs::create_dir_all(&figures).map_err(|e| Error::io(&figures, e))?;
    for map in heatmap::maps(&manifest, &rows, &[]) {
        heatmap::write(&map, &figures)?;
    }
    say!(
        "study {} ({}): {} rows in {}",
        manifest.study,
        manifest.figure,
        df.height(),
        dir.join(format!("{}.csv", manifest.study)).display()
    );
    for s in &summaries {
        say!("  {} | {} ({}): {}", s.model, s.claim, s.bound, s.words(&names));
    }
    Ok(())
}

fn size_words(study: &Study) -> String {
    let models = study.models().len();
    let mut parts = vec![format!("{models} model{}", if models == 1 { "" } else { "s" })];
    match study.design {
        Design::Grid => {
            for v in &study.vary {
                parts.push(format!("{} {}", v.domain.grid().map_or(0, |g| g.len()), v.name));
            }
        }
        Design::Sobol { samples, .. } | Design::LatinHypercube { samples, .. } => {
            let names: Vec<&str> = study.vary.iter().map(|v| v.name.as_str()).collect();
            parts.push(format!("{samples} points over {}", names.join(", ")));
        }
    }
    parts.join(" x ")
}

/// The sample list (a pipe closed early, as by `head`, ends the listing quietly).
fn print_samples(study: &Study, shard: Shard) {
    use std::fmt::Write as _;
    let mut text = format!("{:>7} {:>7} {:<8}", "sample", "shard", "model");
    for v in &study.vary {
        let _ = write!(text, " {:>14}", v.name);
    }
    text.push('\n');
    for s in &study.samples {
        let mark = if shard.owns(s.index) { "*" } else { "" };
        let _ = write!(text, "{:>7} {:>6}{mark:1} {:<8}", s.index, s.index % shard.count, s.model);
        for x in &s.values {
            let _ = write!(text, " {:>14}", crate::number::fmt_num(*x));
        }
        text.push('\n');
    }
    let _ = std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes());
}

fn duration(seconds: f64) -> String {
    if seconds < 90.0 {
        format!("{seconds:.0} s")
    } else if seconds < 5400.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}
