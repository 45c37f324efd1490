//! The command line: wires loading, running and writing; no physics and no rendering here.
//!
//! Exit codes: 0 every check passed, 1 a check failed, 2 bad input or an I/O error.

/// `println!` that ends the process quietly with exit code 2 (an I/O error) when standard
/// output is closed early (as by `| head`), instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout().lock(), $($arg)*).is_err() {
            std::process::exit(2);
        }
    }};
}

/// `print!` with the same rule as [`say!`].
macro_rules! say_part {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if write!(std::io::stdout().lock(), $($arg)*).is_err() {
            std::process::exit(2);
        }
    }};
}

mod design;
mod explore;
mod modal;
mod progress;
mod study;

use progress::{remove_on_interrupt, Bars, Interrupt};

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::analysis::Progress;
use crate::checks::reference::BaselineMode;
use crate::experiment::study::Study;
use crate::experiment::{self, Experiment};
use crate::output::ReportOptions;
use crate::reference::digitised::ImportInfo;
use crate::runner;

/// Replicates Araki et al. (1997), "Impact damper with granular materials for multibody
/// system", figure by figure, and checks every result against references.
#[derive(Debug, Parser)]
#[command(name = "shotdamp", version, about, long_about = None)]
pub struct Cli {
    /// Folder of experiment files.
    #[arg(long, global = true, default_value = "experiments")]
    pub experiments: PathBuf,
    /// Folder of reference data.
    #[arg(long, global = true, default_value = "reference")]
    pub reference: PathBuf,
    /// Folder of study files (`shotdamp report` runs those marked `report = true`; default:
    /// `studies` beside the experiments folder).
    #[arg(long, global = true)]
    pub studies: Option<PathBuf>,
    /// Folder of design files (`shotdamp report` evaluates the answers their searches stored
    /// under the reference folder; default: `designs` beside the experiments folder).
    #[arg(long, global = true)]
    pub designs: Option<PathBuf>,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

impl Cli {
    /// The project's input folders as the options name them.
    fn project(&self) -> runner::ReportInputs {
        runner::ReportInputs {
            experiments: self.experiments.clone(),
            reference: self.reference.clone(),
            studies: self.studies.clone(),
            designs: self.designs.clone(),
        }
    }
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the experiments and the figures they reproduce.
    List,
    /// Print the modes of an experiment's structure, with the mass ratios of Eq. 13.
    Modal {
        /// Experiment file.
        file: PathBuf,
        /// Case whose dampers give the mass ratios (default: every case with dampers).
        #[arg(long)]
        case: Option<String>,
    },
    /// Calibrate the modal damping ratios of an experiment's structure (each model) against a
    /// digitised compliance of the bare structure (`shotdamp reference import`, datasets mapped
    /// to masses with --map DATASET=bare:MASS).
    Damping {
        /// Experiment file whose structure and excitation are used.
        file: PathBuf,
        /// Digitised reference file (TOML) with the measured bare-structure curves.
        #[arg(long)]
        curve: PathBuf,
        /// Only this model (default: every model of the file).
        #[arg(long)]
        model: Option<String>,
    },
    /// Run some experiments and write their report.
    Run {
        /// Experiment files.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Report folder.
        #[arg(long, default_value = "runs")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// How the report is written.
        #[command(flatten)]
        writing: Writing,
    },
    /// Re-run an experiment's claims over values the paper leaves unstated (a study file),
    /// whole or as one shard of a cluster job; `study merge DIR` joins the shards.
    Study(study::StudyArgs),
    /// Work with reference data.
    Reference {
        /// What to do with reference data.
        #[command(subcommand)]
        command: ReferenceCommand,
    },
    /// Compare two reports: every figure side by side and overlaid, and the checks that changed.
    Compare {
        /// The earlier report folder.
        a: PathBuf,
        /// The later report folder.
        b: PathBuf,
        /// Folder of the comparison page.
        #[arg(long, default_value = "comparison")]
        out: PathBuf,
    },
    /// Run a design file (analysis kind "design", docs/design.md): the best placements, shot
    /// split and clearances, the reference layouts, the clearance profile and the Pareto front,
    /// written as a report.
    Design(design::DesignArgs),
    /// Explore an experiment live: a local page whose controls (clearance, shot, damping,
    /// force, bed model, model of the structure, band) recompute and redraw its curves
    /// (docs/explore.md)
    Explore(explore::ExploreArgs),
    /// Run every experiment and regenerate the whole report.
    Report {
        /// Report folder.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// Store this run's results as the regression baseline (under REFERENCE/baseline/)
        /// instead of comparing with it. Review the diff and commit it with the change.
        #[arg(long)]
        bless: bool,
        /// Worker threads (default: all cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// How the report is written.
        #[command(flatten)]
        writing: Writing,
    },
}

/// How a report is written (`run` and `report`).
#[derive(Debug, clap::Args)]
pub struct Writing {
    /// Folder of templates overriding the embedded ones.
    #[arg(long)]
    templates: Option<PathBuf>,
    /// Write every row of every table as CSV (by default a table longer than
    /// 1 500 rows keeps at most 300 evenly spaced rows in its CSV file, whole in Parquet).
    #[arg(long)]
    full_csv: bool,
    /// Keep every row of every table: a table longer than 10 000 rows (a sampled history)
    /// is written whole as Parquet, and a long table's CSV keeps up to 1 500 evenly spaced
    /// rows. By default a table longer than 10 000 rows has no Parquet file and its CSV holds
    /// at most 300 evenly spaced rows plus each column's smallest and largest value in each
    /// stretch of rows.
    #[arg(long)]
    full_data: bool,
    /// Write every figure as PNG and as SVG (by default each in the smaller of the two).
    #[arg(long)]
    svg: bool,
}

impl Writing {
    fn options(&self) -> ReportOptions {
        ReportOptions {
            templates: self.templates.clone(),
            full_csv: self.full_csv,
            full_data: self.full_data,
            svg: self.svg,
            ..ReportOptions::default()
        }
    }
}

/// The commands on reference data.
#[derive(Debug, Subcommand)]
pub enum ReferenceCommand {
    /// Import a WebPlotDigitizer export (JSON project, version 4, or CSV) as a digitised
    /// reference file (TOML) with its provenance and the size of one pixel in data units.
    Import {
        /// The WebPlotDigitizer file (.json or .csv).
        file: PathBuf,
        /// The paper figure digitised, e.g. "Fig. 8".
        #[arg(long)]
        figure: String,
        /// Who digitised it.
        #[arg(long)]
        by: String,
        /// What it was digitised from (document, page, image).
        #[arg(long)]
        from: String,
        /// Unit of the horizontal axis.
        #[arg(long, default_value = "Hz")]
        x_unit: String,
        /// Unit of the vertical axis.
        #[arg(long, default_value = "m/N")]
        y_unit: String,
        /// A dataset's computed curve: "DATASET=CASE:MASS" (repeatable).
        #[arg(long = "map")]
        map: Vec<String>,
        /// CSV only: one pixel along x, in data units (linear axis) or relative (log axis).
        #[arg(long)]
        x_pixel: Option<f64>,
        /// CSV only: one pixel along y.
        #[arg(long)]
        y_pixel: Option<f64>,
        /// CSV only: the horizontal axis is logarithmic.
        #[arg(long)]
        x_log: bool,
        /// CSV only: the vertical axis is logarithmic.
        #[arg(long)]
        y_log: bool,
        /// The file to write (default: REFERENCE/digitised/STEM.toml).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// The exit code of a run whose checks all passed but whose answer is partial: a design
/// stopped at its time limit, its layouts the best found so far (0 every check passes, 1 a
/// check failed, 2 bad input or I/O, 3 this, 130 / 143 interrupted).
pub const PARTIAL: u8 = 3;

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch(&cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Runs a command; `Ok(false)` when a check failed.
pub fn dispatch(cli: &Cli) -> anyhow::Result<bool> {
    match &cli.command {
        Command::List => {
            for path in experiment::loader::discover(&cli.experiments)? {
                let exps = experiment::loader::load(&path, &cli.reference)?;
                let Some(exp) = exps.first() else { continue };
                let models: Vec<&str> = exps.iter().filter_map(|e| e.model.as_ref().map(|m| m.id.as_str())).collect();
                let on = if models.is_empty() { String::new() } else { format!(" [models: {}]", models.join(", ")) };
                say!("{:<28} {:<12} {:<12} {}{on}", exp.meta.id, exp.meta.figure, exp.analysis.kind(), exp.meta.title);
            }
            Ok(true)
        }
        Command::Modal { file, case } => {
            for exp in experiment::loader::load(file, &cli.reference)? {
                modal::print_modal(&exp, case.as_deref())?;
            }
            Ok(true)
        }
        Command::Damping { file, curve, model } => {
            modal::calibrate_damping(file, curve, model.as_deref(), &cli.reference)?;
            Ok(true)
        }
        Command::Run { files, out, jobs, writing } => {
            cli.project().refuse_overlap(out)?;
            let mut exps = experiment::loader::load_all(files, &cli.reference)?;
            // Experiments whose exports these use run too, from the same folders.
            let needed = experiment::missing_dependencies(&exps, &crate::reference::files::Files::new(&cli.reference))?;
            if !needed.is_empty() {
                let mut ids: Vec<String> =
                    needed.iter().map(|e| format!("{} ({})", e.meta.id, e.path.display())).collect();
                ids.dedup();
                say!("also running, for the exports the files use: {}", ids.join(", "));
            }
            exps.extend(needed);
            Ok(run_and_write(
                &exps,
                &[],
                &cli.reference,
                out,
                *jobs,
                &writing.options(),
                BaselineMode::Optional,
                false,
            )?
            .0)
        }
        Command::Design(args) => design::dispatch(args, cli),
        Command::Explore(args) => explore::run(args, cli),
        Command::Reference { command: ReferenceCommand::Import { .. } } => {
            import(&cli.command, &cli.reference)?;
            Ok(true)
        }
        Command::Study(args) => study::dispatch(args, &cli.project()),
        Command::Compare { a, b, out } => {
            crate::output::destination::refuse_overlap(out, &[("REPORT_A", a), ("REPORT_B", b)])?;
            let dest = crate::output::compare::write(a, b, out)?;
            say!("comparison: {}", dest.display());
            Ok(true)
        }
        Command::Report { out, jobs, writing, bless } => {
            let inputs = cli.project();
            let settings =
                runner::ReportSettings { out: out.clone(), jobs: *jobs, writing: writing.options(), bless: *bless };
            Ok(finish(|progress, log, staging| runner::report(&inputs, &settings, progress, log, staging))?.0)
        }
    }
}

/// `shotdamp reference import`.
fn import(command: &Command, reference: &Path) -> anyhow::Result<()> {
    let Command::Reference {
        command:
            ReferenceCommand::Import { file, figure, by, from, x_unit, y_unit, map, x_pixel, y_pixel, x_log, y_log, out },
    } = command
    else {
        return Ok(());
    };
    let mapping = map.iter().map(|m| crate::reference::import::parse_mapping(m)).collect::<crate::Result<Vec<_>>>()?;
    let info = ImportInfo {
        figure: figure.clone(),
        source: from.clone(),
        digitised_by: by.clone(),
        imported_from: file.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default(),
        x_unit: x_unit.clone(),
        y_unit: y_unit.clone(),
        mapping,
        x_log: *x_log,
        y_log: *y_log,
        x_pixel: *x_pixel,
        y_pixel: *y_pixel,
    };
    let done = crate::reference::import::import_file(file, &info, out.as_deref(), reference)?;
    say!(
        "{}: {} curves, {} points; one pixel = {} along x, {} along y",
        done.dest.display(),
        done.file.curve.len(),
        done.points(),
        crate::checks::fmt_num(done.file.meta.x_pixel),
        crate::checks::fmt_num(done.file.meta.y_pixel)
    );
    Ok(())
}

/// Runs the experiments and studies into a report ([`crate::runner::run_and_write`]) with
/// progress bars on a terminal, and prints a summary.
#[allow(clippy::too_many_arguments)]
fn run_and_write(
    exps: &[Experiment],
    studies: &[Study],
    reference: &Path,
    out: &Path,
    jobs: Option<usize>,
    writing: &ReportOptions,
    baseline_mode: BaselineMode,
    bless: bool,
) -> anyhow::Result<(bool, Vec<crate::analysis::ExperimentResult>)> {
    let settings = runner::Settings {
        reference: reference.to_path_buf(),
        out: out.to_path_buf(),
        jobs,
        writing: writing.clone(),
        baseline_mode,
        bless,
    };
    finish(|progress, log, staging| runner::run_and_write(exps, studies, &settings, progress, log, staging))
}

/// Runs `run` (a [`crate::runner`] call) with progress bars on a terminal and the interrupt
/// handler in place, and prints a summary.
fn finish(
    run: impl FnOnce(&dyn Progress, &(dyn Fn(String) + Sync), &dyn Fn(PathBuf)) -> crate::Result<runner::Finished>,
) -> anyhow::Result<(bool, Vec<crate::analysis::ExperimentResult>)> {
    finish_with(None, run)
}

/// [`finish`] whose first interrupt raises `interrupt` instead of abandoning the run
/// ([`remove_on_interrupt`]).
fn finish_with(
    interrupt: Option<Interrupt>,
    run: impl FnOnce(&dyn Progress, &(dyn Fn(String) + Sync), &dyn Fn(PathBuf)) -> crate::Result<runner::Finished>,
) -> anyhow::Result<(bool, Vec<crate::analysis::ExperimentResult>)> {
    let tty = std::io::stderr().is_terminal();
    let bars = Bars { multi: tty.then(indicatif::MultiProgress::new) };
    let log = tty || std::env::var_os("CI").is_some();
    // The handler is in place before the staging folder exists: an interrupt at any moment
    // removes it.
    let done = run(&bars, &|msg| bars.log(log, msg), &|staging| remove_on_interrupt(staging, interrupt.clone()))?;
    if let Some(dir) = &done.blessed {
        say!("blessed: {} experiments sampled into {} (review the diff, commit it)", done.results.len(), dir.display());
    }
    say!("report: {}", done.dest.join("index.html").display());
    // Designs: the answer in one line per model (the tables have the layouts).
    for r in done.results.iter().filter(|r| r.experiment.analysis.answers()) {
        let e = &r.exports;
        let cases: Vec<String> = e
            .iter()
            .filter_map(|(k, v)| k.strip_prefix("objective_").map(|c| format!("{c} {}", crate::number::fmt_sig(*v, 3))))
            .collect();
        // The clearance to the precision that matters: where the objective is flat, the
        // band within 5 % of the best.
        let sig = |k: &str| e.get(k).map_or("-".to_string(), |v| crate::number::fmt_sig(*v, 2));
        let clearance = match (e.get("robust_clearance_min_mm"), e.get("robust_clearance_max_mm")) {
            (Some(lo), Some(hi)) if sig("robust_clearance_min_mm") == sig("robust_clearance_max_mm") || lo == hi => {
                format!(
                    "clearance {} mm; of the clearances sampled only {} mm is within 5 % of the best",
                    sig("best_clearance_mm"),
                    sig("robust_clearance_min_mm")
                )
            }
            (Some(_), Some(_)) => format!(
                "clearance {} mm; the clearances sampled from {} to {} mm are within 5 % of the best",
                sig("best_clearance_mm"),
                sig("robust_clearance_min_mm"),
                sig("robust_clearance_max_mm")
            ),
            _ => format!("clearance {} mm", sig("best_clearance_mm")),
        };
        let of = r.experiment.analysis.design().map_or_else(String::new, |(spec, _)| spec.objective_words());
        say!(
            "  {}: best {} of {of} ({clearance}); cases: {}",
            r.experiment.key(),
            e.get("best_objective").map_or("-".to_string(), |v| crate::number::fmt_sig(*v, 3)),
            if cases.is_empty() { "none".to_string() } else { cases.join(", ") }
        );
        if e.get("sdof_at_edge") == Some(&1.0) {
            say!(
                "  {}: the SDOF technique picks {} mm, an end of its candidate list (design_sdof.csv): widen the list before trusting that pick",
                r.experiment.key(),
                sig("sdof_clearance_mm")
            );
        }
    }
    for r in &done.results {
        for w in &r.warnings {
            say!("  {}: warning: {w}", r.experiment.key());
        }
    }
    if done.passed() {
        say!("{} checks: none failed", done.checks);
    } else {
        say!("{} checks: {} failed", done.checks, done.failed.len());
        for f in &done.failed {
            say!("{f}");
        }
    }
    Ok((done.passed(), done.results))
}
