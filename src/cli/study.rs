//! `shotdamp study`: runs a study (or a deterministic share of it) into a folder, and merges
//! the shards' parts into the long table, summary and heat maps.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::experiment::study::{self, Design, Study};
use crate::output::manifest::{Manifest, Shard};
use crate::output::study as folder;
use crate::runner::study as shards;

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
    /// Once the study is merged, store its answer (the samples where the most claims hold,
    /// per model) as reference/studies/ID.json, which `shotdamp report` runs again for a study
    /// marked `stored = true`.
    #[arg(long)]
    pub store: bool,
}

/// Subcommands of `shotdamp study`.
#[derive(Debug, clap::Subcommand)]
pub enum StudyCommand {
    /// Merge the parts of every shard of a study folder; write the long table (CSV, Parquet),
    /// the summary and the heat maps.
    Merge {
        /// The study folder (--out of the shards).
        dir: PathBuf,
        /// Store the merged study's answer as reference/studies/ID.json (see `study --store`).
        #[arg(long)]
        store: bool,
    },
}

/// Runs `shotdamp study`.
pub fn dispatch(args: &StudyArgs, project: &crate::runner::ReportInputs) -> anyhow::Result<bool> {
    let reference = project.reference.as_path();
    if let Some(StudyCommand::Merge { dir, store }) = &args.command {
        let merged = shards::merge(dir)?;
        print_merged(&merged);
        if *store {
            say!("stored: {}", shards::store(reference, &merged)?.display());
        }
        return Ok(true);
    }
    let Some(file) = &args.file else {
        return Err(Error::invalid("(command line)", "FILE", "(missing)", "give a study file, or `merge DIR`").into());
    };
    let study = study::load(file, reference)?;
    let out = args.out.clone().unwrap_or_else(|| shards::default_out(&study));
    shards::refuse_overlap(&study, reference, &out)?;
    project.refuse_overlap(&out)?;
    let manifest = Manifest::of(&study, &file.display().to_string());
    let shard = shard(args, &out, &manifest)?;
    let pool = crate::runner::pool(args.jobs)?;
    let threads = pool.current_num_threads();
    let mine = study.samples.iter().filter(|s| shard.owns(s.index)).count();
    let points = shards::estimate(&study, reference, shard, &pool)?;
    let estimate = points as f64 * SECONDS_PER_POINT / threads as f64;
    let dependent = !study.parts().flat_map(|p| &p.base).all(|e| e.dependencies().is_empty());
    say!(
        "study {}: {} samples ({}; {}), {} claims each; shard {shard}: {} samples, {points} simulated points, roughly {} on {threads} threads{}",
        study.id,
        study.samples.len(),
        size_words(&study),
        study.design.name(),
        study.parts().map(|p| crate::analysis::study::claims(&p.base[0]).len()).sum::<usize>(),
        mine,
        duration(estimate),
        if dependent { " (plus the experiments it takes values from, once per model and structure)" } else { "" }
    );
    if args.dry_run {
        print_samples(&study, shard);
        return Ok(true);
    }
    let told = Told::new(&study.id, shard, &out, mine);
    let (end, merged) = shards::run_shard(&study, reference, &out, shard, &pool, &told)?;
    told.finish();
    match end {
        shards::ShardEnd::AlreadyComplete => say!("shard {shard} is already complete in {}", out.display()),
        shards::ShardEnd::Written(part) => say!("shard {shard}: {}", part.display()),
    }
    match merged {
        Some(m) => {
            print_merged(&m);
            if args.store {
                say!("stored: {}", shards::store(reference, &m)?.display());
            }
        }
        None if args.store => {
            say!("when every shard is done: shotdamp study merge {} --store (this shard stores nothing)", out.display())
        }
        None => say!("when every shard is done: shotdamp study merge {}", out.display()),
    }
    Ok(true)
}

/// The shard from the command line or the job's environment. On Slurm the array task id is
/// the shard's index; the number of shards comes from `--shards`, else from the study folder
/// (recorded by its first shard: `sbatch --array=3` reruns shard 3 of the folder's 7), else
/// from an array numbered 0 to N-1 (`SLURM_ARRAY_TASK_MIN`, `_MAX`, `_STEP`, `_COUNT`).
fn shard(args: &StudyArgs, out: &Path, manifest: &Manifest) -> anyhow::Result<Shard> {
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
    // The count the folder was started with, when it is this study's.
    let recorded = || {
        folder::read_manifest(out)
            .ok()
            .filter(|m| m.fingerprint == manifest.fingerprint && m.shards > 0)
            .map(|m| m.shards.to_string())
    };
    // The number of shards from --shards, else from the folder.
    let count = || args.shards.map(|n| n.to_string()).or_else(recorded);
    if let Some(i) = env("SLURM_ARRAY_TASK_ID") {
        let n = match count() {
            Some(n) => n,
            None => {
                let (min, max, step, total) = (
                    env("SLURM_ARRAY_TASK_MIN"),
                    env("SLURM_ARRAY_TASK_MAX"),
                    env("SLURM_ARRAY_TASK_STEP"),
                    env("SLURM_ARRAY_TASK_COUNT"),
                );
                let whole = min.as_deref().is_none_or(|m| m.trim() == "0")
                    && step.as_deref().is_none_or(|s| s.trim() == "1")
                    && match (&max, &total) {
                        (Some(m), Some(t)) => m.trim().parse::<usize>().ok().map(|m| m + 1) == t.trim().parse().ok(),
                        _ => true,
                    };
                match total {
                    Some(t) if whole => t,
                    _ => {
                        return Err(bad(
                            "SLURM_ARRAY_TASK_*",
                            &format!(
                                "min {}, max {}, step {}, count {}",
                                min.as_deref().unwrap_or("-"),
                                max.as_deref().unwrap_or("-"),
                                step.as_deref().unwrap_or("-"),
                                total.as_deref().unwrap_or("-")
                            ),
                            "the array is not 0 to N-1 in steps of 1 and the study folder records no number of shards: give it with --shards N (the sbatch script's third argument)",
                        )
                        .into())
                    }
                }
            }
        };
        return parse("SLURM_ARRAY_TASK_ID/shards", &i, &n);
    }
    if let Some(i) = env("JOB_COMPLETION_INDEX") {
        let Some(n) = count() else {
            return Err(bad(
                "--shards",
                "(missing)",
                "JOB_COMPLETION_INDEX is set: give the number of shards (the Job's completions)",
            )
            .into());
        };
        return parse("JOB_COMPLETION_INDEX/--shards", &i, &n);
    }
    if args.shards.is_some() {
        return Err(bad(
            "--shards",
            "(given)",
            "only with SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX; otherwise use --shard I/N",
        )
        .into());
    }
    Ok(Shard::WHOLE)
}

/// A shard's progress: a bar on a terminal, a line per batch otherwise.
struct Told<'a> {
    id: &'a str,
    shard: Shard,
    out: &'a Path,
    bar: Option<indicatif::ProgressBar>,
}

impl<'a> Told<'a> {
    fn new(id: &'a str, shard: Shard, out: &'a Path, total: usize) -> Told<'a> {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} [{bar:30}] {pos}/{len} samples, {elapsed} elapsed, ~{eta} left",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_prefix(format!("{id} {shard}"));
            bar
        });
        Told { id, shard, out, bar }
    }

    fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish();
        }
    }
}

impl shards::StudyProgress for Told<'_> {
    fn waiting(&self, shard: Shard, holder: &str) {
        eprintln!(
            "shard {shard} is being computed by another process ({holder}); waiting for it to end (its lock {} is taken over once its process has ended, or after {} s without a heartbeat)",
            self.out.join("parts").display(),
            crate::output::files::STALE_AFTER.as_secs()
        );
    }

    fn resuming(&self, done: usize, total: usize) {
        if let Some(b) = &self.bar {
            b.set_position(done as u64);
        }
        say!("resuming: {done} of {total} samples already written");
    }

    fn sample(&self) {
        if let Some(b) = &self.bar {
            b.inc(1);
        }
    }

    fn round(&self, round: u32, samples: usize) {
        let line = format!("{} round {round}: {samples} samples over every shard", self.id);
        match &self.bar {
            Some(b) => {
                b.println(line);
                b.set_length(samples.div_ceil(self.shard.count) as u64);
                b.set_position(0);
            }
            None => eprintln!("{line}"),
        }
    }

    fn batch(&self, done: usize, total: usize, first: usize, seconds: f64) {
        if self.bar.is_none() {
            let per = seconds / (done - first) as f64;
            eprintln!(
                "{} {}: {done}/{total} samples, {} elapsed, ~{} left",
                self.id,
                self.shard,
                duration(seconds),
                duration(per * (total - done) as f64)
            );
        }
    }
}

/// Where each claim of a merged study holds.
fn print_merged(m: &shards::Merged) {
    say!("study {} ({}): {} rows in {}", m.manifest.study, m.manifest.figure, m.rows, m.table.display());
    for s in &m.summaries {
        say!("  {} | {} ({}): {}", s.model, s.claim, s.bound, crate::output::study_words::words(s, &m.names));
    }
    // The bottom line: the samples where the most claims hold at once.
    let best = crate::analysis::study_samples::best(&m.samples);
    for b in best.iter().take(3) {
        let values: Vec<String> =
            m.names.iter().zip(&b.values).map(|(n, v)| format!("{n} {}", crate::number::fmt_num(*v))).collect();
        let model = if b.model.is_empty() { String::new() } else { format!("model {}, ", b.model) };
        say!(
            "  most claims at once: sample {} ({model}{}): {} of {} evaluable hold{}",
            b.sample,
            values.join(", "),
            b.holds,
            b.evaluable,
            if b.failing.is_empty() { String::new() } else { format!("; fail: {}", b.failing.join("; ")) }
        );
    }
    if best.len() > 3 {
        say!("  ... and {} more samples with as many (the table {}_samples.csv)", best.len() - 3, m.manifest.study);
    }
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
        Design::Adaptive { levels, refine } => {
            let sizes: Vec<String> =
                study.vary.iter().map(|v| format!("{} {}", v.domain.grid().map_or(0, |g| g.len()), v.name)).collect();
            parts.push(format!(
                "a grid of {} refined in {levels} rounds where the {} changes (round 0 below; the rest as the answers come)",
                sizes.join(" x "),
                match refine {
                    study::Refine::All => "answer to \"does every claim hold?\"".to_string(),
                    study::Refine::Count => "number of claims that hold".to_string(),
                    study::Refine::Outcomes => "outcome of any claim".to_string(),
                    study::Refine::Check(k) => format!("outcome of claim {k}"),
                }
            ));
        }
        Design::Sobol { samples, .. } | Design::LatinHypercube { samples, .. } => {
            let names: Vec<&str> = study.vary.iter().map(|v| v.name.as_str()).collect();
            parts.push(format!("{samples} points over {}", names.join(", ")));
        }
    }
    parts.join(" x ")
}

/// The sample list (a pipe closed early, as by `head`, ends the process quietly with exit 2,
/// as every command's closed standard output does).
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
    if std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes()).is_err() {
        std::process::exit(2);
    }
}

pub(super) fn duration(seconds: f64) -> String {
    if seconds < 90.0 {
        format!("{seconds:.0} s")
    } else if seconds < 5400.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}
