//! `shotdamp design`: searches design files and writes their report, whole or as one shard of
//! a cluster job (`--shard I/N --parts DIR`), whose parts `--merge DIR` gathers into the
//! report the whole search writes.

use std::path::PathBuf;

use super::progress::Interrupt;
use super::Cli;
use crate::runner;
use crate::runner::design_parts::DesignShard;

/// Arguments of `shotdamp design`.
#[derive(Debug, clap::Args)]
pub struct DesignArgs {
    /// Design files.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Report folder.
    #[arg(long, default_value = "design-runs")]
    pub out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Also store each model's answer (the best layouts) under the reference folder's
    /// designs/, where `shotdamp report` evaluates them again instead of searching.
    #[arg(long)]
    pub store: bool,
    /// Print each design's estimate (its counts, a layout evaluation's cost measured on the
    /// layouts of its coarse scans for about 2 s, the wall time such a design usually takes)
    /// and search nothing. A run prints the same line before it searches.
    #[arg(long)]
    pub dry_run: bool,
    /// Stop the searches after this many seconds (of the whole run) and write the best
    /// layouts found so far, marked as such (not stored).
    #[arg(long, value_name = "SECONDS")]
    pub time_limit: Option<f64>,
    /// Run a design whose estimate is over ten times its --time-limit, or over four hours
    /// without one (refused otherwise).
    #[arg(long)]
    pub confirm: bool,
    /// Search only shard I of N (0-based; item k of the placements of every search belongs to
    /// shard k mod N) and write its part into --parts DIR. Default with --parts: from
    /// SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX with --shards.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// The number of shards, with the index from JOB_COMPLETION_INDEX (a Kubernetes Indexed Job)
    /// or SLURM_ARRAY_TASK_ID.
    #[arg(long, value_name = "N")]
    pub shards: Option<usize>,
    /// The folder the shards write their parts into (shared by every shard).
    #[arg(long, value_name = "DIR")]
    pub parts: Option<PathBuf>,
    /// Gather the parts of a sharded search from DIR and write the report (and with --store
    /// the answers) the whole search writes; search nothing.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["shard", "shards", "parts", "dry_run", "time_limit", "confirm"])]
    pub merge: Option<PathBuf>,
}

/// Seconds a design may run past `--time-limit` (the report's writing after the last
/// evaluation), beyond which it says that the limit was too short for it.
pub const LIMIT_MARGIN_S: f64 = 5.0;

/// Runs `shotdamp design`.
pub fn dispatch(args: &DesignArgs, cli: &Cli) -> anyhow::Result<bool> {
    // The time limit counts from here: loading and the estimate's probe are inside it.
    let started = std::time::Instant::now();
    let DesignArgs { files, out, jobs, store, dry_run, time_limit, merge, .. } = args;
    cli.project().refuse_overlap(out)?;
    if let Some(sharded) = sharded(args)? {
        return search_shard(args, cli, sharded);
    }
    if let Some(t) = time_limit.filter(|t| !(t.is_finite() && *t >= 0.0)) {
        return Err(crate::Error::invalid(
            "(command line)",
            "--time-limit",
            t.to_string(),
            "a number of seconds, 0 or more",
        )
        .into());
    }
    let threads = runner::threads(*jobs)?;
    // The files loaded and validated once (a finite-element model reduced once) for the
    // budgets, the dry run's probe and the run.
    let exps = runner::designs::load(files, &cli.reference)?;
    // A merge searches nothing: no budget to print.
    let budgets = if merge.is_some() { Vec::new() } else { runner::designs::budgets_of(&exps) };
    // The estimate: one layout of each design evaluated on one thread at a few frequencies
    // (seconds), times the evaluations such a design usually makes.
    let estimates = if merge.is_some() { Vec::new() } else { estimates(&exps, &budgets, threads)? };
    for e in &estimates {
        say!("{}", e.line);
    }
    if *dry_run {
        return Ok(true);
    }
    refuse_long(&estimates, *time_limit, args.confirm)?;
    let interrupt = Interrupt::default();
    let settings = runner::designs::DesignSettings {
        reference: cli.reference.clone(),
        out: out.clone(),
        jobs: *jobs,
        store: *store,
        time_limit: time_limit.map(|t| (t - started.elapsed().as_secs_f64()).max(0.0)),
        interrupt: Some(interrupt.flag.clone()),
        merge: merge.clone(),
    };
    let mut stored = Vec::new();
    let mut partial = Vec::new();
    let (ok, _) = super::finish_with(Some(interrupt.clone()), |progress, log, staging| {
        let run = runner::designs::run_loaded(exps, &settings, progress, log, staging)?;
        stored = run.stored;
        partial = run.finished.results.iter().filter(|r| r.partial.is_some()).map(|r| r.experiment.key()).collect();
        Ok(run.finished)
    })?;
    for path in stored {
        say!("stored: {}", path.display());
    }
    let sig = interrupt.signal.load(std::sync::atomic::Ordering::Relaxed);
    if sig != 0 {
        // The report of the best so far is in place; the exit status says the run
        // was interrupted, as a shell expects.
        say!("interrupted: the report holds the best layouts found before the interrupt");
        std::process::exit(128 + sig);
    }
    let took = started.elapsed().as_secs_f64();
    if let Some(limit) = time_limit.filter(|l| took > l + LIMIT_MARGIN_S) {
        say!(
            "the time limit ({} s) was shorter than the least this design does besides searching (the cases before, each placement's best for the page and the drive levels after): it ran {:.1} s",
            crate::number::fmt_sig(limit, 3),
            took
        );
    }
    if ok && !partial.is_empty() {
        // Every check passed, but an answer is the best found so far: a script must not take
        // it for a converged one.
        say!(
            "partial: {} stopped at the time limit; the report holds the best layouts found so far",
            partial.join(", ")
        );
        std::process::exit(i32::from(super::PARTIAL));
    }
    Ok(ok)
}

/// One design's estimate, measured before it runs.
struct Estimate {
    key: String,
    /// Wall seconds, low and high.
    seconds: (f64, f64),
    /// The line printed.
    line: String,
}

/// Each design's estimate: its counts ([`crate::design::Budget`]), the cost of a steady state
/// measured on one layout (the probe, on one thread), and the wall time the evaluations such
/// a design usually makes take at that cost ([`crate::design::Budget::expected_seconds`]).
fn estimates(
    exps: &[crate::experiment::Experiment],
    budgets: &[(String, usize, crate::design::Budget)],
    threads: usize,
) -> anyhow::Result<Vec<Estimate>> {
    let secs = |p: f64| if p < 1.0 { format!("{:.0} ms", p * 1e3) } else { format!("{p:.1} s") };
    let mut out = Vec::new();
    for (probe, (_, _, b)) in runner::designs::probe_of(exps)?.into_iter().zip(budgets) {
        let runner::designs::Probe {
            key,
            layouts,
            seconds_per_evaluation: searched,
            judged_seconds_per_evaluation,
            spends_iterations,
        } = probe;
        let screen = judged_seconds_per_evaluation.map_or(String::new(), |j| {
            format!(
                " on the searched model of [design.screen], {} on the file's model (their ratio on one layout at {} frequencies of each band)",
                secs(j),
                runner::designs::PROBE_FREQUENCIES
            )
        });
        let (low, high) =
            b.expected_seconds(searched, judged_seconds_per_evaluation.unwrap_or(searched), threads, spends_iterations);
        let k = if spends_iterations { 2 } else { 0 };
        let usually = if spends_iterations {
            " (some of its steady states never settle and it has no step_tolerance: its starts are expected to spend their iterations; `tolerance` and `step_tolerance` matched to its intervals end them sooner, docs/design.md \"When a start ends\")"
        } else {
            ""
        };
        let points = exps
            .iter()
            .find(|e| e.key() == key)
            .and_then(|e| e.analysis.design())
            .map_or("steady states", |(spec, _)| spec.point_words());
        let line = format!(
            "design {key}: {} placements x {} search(es), usually {}-{} layout evaluations{usually} (at most {}) of {} {points} each; measured {} a layout evaluation{screen} (the mean of {layouts} layouts of the coarse scans on one thread): about {} on {threads} thread{} (an estimate: docs/design.md gives it against measured runs)",
            b.placements,
            b.searches,
            b.expected[k].0,
            b.expected[k + 1].0,
            b.evaluations,
            b.points,
            secs(searched),
            span(low, high),
            if threads == 1 { "" } else { "s" },
        );
        out.push(Estimate { key, seconds: (low, high), line });
    }
    Ok(out)
}

/// A span of seconds in words, "2-7 min".
fn span(low: f64, high: f64) -> String {
    let (lo, hi) = (super::study::duration(low), super::study::duration(high));
    match (lo.rsplit_once(' '), hi.rsplit_once(' ')) {
        (Some((a, u)), Some((b, v))) if u == v => format!("{a}-{b} {u}"),
        _ => format!("{lo} to {hi}"),
    }
}

/// The most a design may be expected to take, without a time limit, before it is refused
/// unless confirmed (`--confirm`).
pub const CONFIRM_ABOVE_S: f64 = 4.0 * 3600.0;

/// How many times its time limit a design's low estimate may be before it is refused unless
/// confirmed: under a tenth of what such a search usually needs gives a best so far of little
/// worth.
pub const CONFIRM_LIMIT_RATIO: f64 = 10.0;

/// Refuses (bad input, exit 2) a design expected to take far longer than its time limit, or
/// more than [`CONFIRM_ABOVE_S`] without one, unless `confirmed`.
fn refuse_long(estimates: &[Estimate], time_limit: Option<f64>, confirmed: bool) -> anyhow::Result<()> {
    if confirmed {
        return Ok(());
    }
    let low: f64 = estimates.iter().map(|e| e.seconds.0).sum();
    let keys: Vec<&str> = estimates.iter().map(|e| e.key.as_str()).collect();
    let (value, why) = match time_limit {
        Some(limit) if low > CONFIRM_LIMIT_RATIO * limit => (
            format!("{limit} s"),
            format!(
                "{} usually take at least {}, over {CONFIRM_LIMIT_RATIO} times the limit: the searches would stop long before any converged; give a longer limit, a smaller search, or --confirm to run it anyway",
                keys.join(", "),
                super::study::duration(low)
            ),
        ),
        None if low > CONFIRM_ABOVE_S => (
            "(none)".to_string(),
            format!(
                "{} usually take at least {}; give --time-limit SECONDS (the best so far is written when it is reached) or --confirm to run it anyway",
                keys.join(", "),
                super::study::duration(low)
            ),
        ),
        _ => return Ok(()),
    };
    Err(crate::Error::invalid("(command line)", "--time-limit", value, why).into())
}

/// The shard this process searches, when it searches one: `--shard I/N`, else with `--parts`
/// the cluster's environment (a Slurm array task, a Kubernetes Indexed Job's index).
fn sharded(args: &DesignArgs) -> anyhow::Result<Option<DesignShard>> {
    let bad = |key: &str, value: &str, msg: &str| crate::Error::invalid("(command line)", key, value, msg);
    let parse = |key: &str, i: &str, n: &str| -> anyhow::Result<DesignShard> {
        match (i.trim().parse::<usize>(), n.trim().parse::<usize>()) {
            (Ok(index), Ok(count)) if count >= 1 && index < count => Ok(DesignShard { index, count }),
            _ => Err(bad(key, &format!("{i}/{n}"), "I/N with N >= 1 and 0 <= I < N (shards are 0-based)").into()),
        }
    };
    if let Some(s) = &args.shard {
        let Some((i, n)) = s.split_once('/') else {
            return Err(bad("--shard", s, "I/N, e.g. 0/4 (shards are 0-based)").into());
        };
        if args.parts.is_none() {
            return Err(bad("--parts", "(missing)", "a shard writes its part into a folder: give --parts DIR").into());
        }
        return parse("--shard", i, n).map(Some);
    }
    if args.parts.is_none() {
        if args.shards.is_some() {
            return Err(bad(
                "--shards",
                "(without --parts)",
                "a shard writes its part into a folder: give --parts DIR",
            )
            .into());
        }
        return Ok(None);
    }
    let env = |k: &str| std::env::var(k).ok();
    let count = args.shards.map(|n| n.to_string());
    let (key, index, count) = match (env("SLURM_ARRAY_TASK_ID"), env("JOB_COMPLETION_INDEX")) {
        (Some(i), _) => ("SLURM_ARRAY_TASK_ID/shards", i, count.or_else(|| env("SLURM_ARRAY_TASK_COUNT"))),
        (None, Some(i)) => ("JOB_COMPLETION_INDEX/--shards", i, count),
        (None, None) => {
            return Err(bad(
                "--shard",
                "(missing)",
                "with --parts give --shard I/N, or run as a Slurm array task or a Kubernetes Indexed Job",
            )
            .into())
        }
    };
    let Some(count) = count else {
        return Err(bad("--shards", "(missing)", "the number of shards: give --shards N").into());
    };
    parse(key, &index, &count).map(Some)
}

/// Searches one shard and writes its part.
fn search_shard(args: &DesignArgs, cli: &Cli, shard: DesignShard) -> anyhow::Result<bool> {
    let Some(dir) = &args.parts else { return Ok(false) };
    if args.store || args.dry_run || args.time_limit.is_some() {
        return Err(crate::Error::invalid(
            "(command line)",
            "--shard",
            format!("{}/{}", shard.index, shard.count),
            "a shard writes its part only: --store, --dry-run and --time-limit go with the merge or a whole search",
        )
        .into());
    }
    let (total, mine) = runner::design_parts::items(&args.files, &cli.reference, shard)?;
    say!("design shard {}/{}: {mine} of {total} placement searches", shard.index, shard.count);
    let part = runner::design_parts::search_shard(&args.files, &cli.reference, dir, shard, args.jobs, &|| {})?;
    say!("shard {}/{}: {}", shard.index, shard.count, part.display());
    say!("when every shard is done: shotdamp design FILE... --merge {}", dir.display());
    Ok(true)
}
