//! What a run shows while it runs and how it ends early: progress bars on a terminal, lines
//! in a log, and the interrupt handler (Ctrl-C or SIGTERM) that removes an unfinished report
//! or, for a design, first stops its searches so that their best so far is written.

use std::path::PathBuf;

use super::study;
use crate::analysis::{Progress, Tick};

/// On Ctrl-C (SIGINT) or SIGTERM: removes the staging folder of the report being written
/// and exits with 128 + the signal number (the previous report stays as it was). With
/// `interrupt` (a design run), the first signal only raises that flag: the searches stop and
/// the report of their best layouts so far is written; a second signal abandons the run.
pub(super) fn remove_on_interrupt(staging: PathBuf, interrupt: Option<Interrupt>) {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else { return };
    std::thread::spawn(move || {
        for sig in signals.forever() {
            if let Some(i) = &interrupt {
                if i.signal.load(std::sync::atomic::Ordering::Relaxed) == 0 {
                    i.signal.store(sig, std::sync::atomic::Ordering::Relaxed);
                    i.flag.store(true, std::sync::atomic::Ordering::Relaxed);
                    eprintln!(
                        "interrupted: the searches stop at their next evaluation and the report of their best layouts so far is written (marked incomplete); interrupt again to abandon it"
                    );
                    continue;
                }
            }
            let committed = crate::output::destination::commit_lock();
            if *committed {
                // The new report is in place: the run ends by itself in a moment.
                return;
            }
            eprintln!("interrupted: removing {}", staging.display());
            // Workers may still be writing into it (they cannot recreate it once it is gone):
            // retry while a removal races with a file being created.
            for _ in 0..100 {
                if std::fs::remove_dir_all(&staging).is_ok() || !staging.exists() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(2));
            }
            std::process::exit(128 + sig);
        }
    });
}

/// A design run's interrupt: the flag its searches watch and the signal that raised it (0:
/// none yet).
#[derive(Clone, Default)]
pub(super) struct Interrupt {
    pub(super) flag: std::sync::Arc<std::sync::atomic::AtomicBool>,
    pub(super) signal: std::sync::Arc<std::sync::atomic::AtomicI32>,
}

/// Progress bars on a terminal (one per experiment), nothing otherwise.
pub(super) struct Bars {
    pub(super) multi: Option<indicatif::MultiProgress>,
}

impl Bars {
    /// Prints a line of the run's log (when `log`) above the bars, or to stderr without them.
    pub(super) fn log(&self, log: bool, msg: String) {
        if !log {
            return;
        }
        match &self.multi {
            Some(m) => {
                let _ = m.println(msg);
            }
            None => eprintln!("{msg}"),
        }
    }
}

/// Seconds between two progress lines in a log.
const LOG_EVERY_S: f64 = 5.0;

/// Progress as lines in a log (standard error not a terminal): every [`LOG_EVERY_S`] seconds
/// the points done, the time taken and an estimate of what is left (from the points done so
/// far; a total of 0 is not known ahead, as a design search's evaluations: then the count
/// alone). A run shorter than that prints nothing.
fn log_lines(id: &str, total: u64) -> Box<Tick<'static>> {
    log_search(id, total, 0, None)
}

/// Seconds without a line after which a design's log says what it is doing (a phase
/// of few, long evaluations ticks seldom).
const HEARTBEAT_S: u64 = 20;

/// The log's lines of a count (see [`log_lines`]); for a design search (`outlook`), the lines
/// say what is expected to be left, from the evaluations the design expects still
/// ([`Outlook::left`](crate::design::halt::Outlook::left)) at the pace so far, and a line
/// comes at least every [`HEARTBEAT_S`] seconds however long an evaluation takes.
fn log_search(
    id: &str,
    total: u64,
    ceiling: u64,
    outlook: Option<std::sync::Arc<crate::design::halt::Outlook>>,
) -> Box<Tick<'static>> {
    use std::sync::atomic::{AtomicU64, Ordering};
    struct State {
        id: String,
        start: std::time::Instant,
        done: AtomicU64,
        /// The next line is due at this many milliseconds after the start.
        due: AtomicU64,
        outlook: Option<std::sync::Arc<crate::design::halt::Outlook>>,
        ceiling: u64,
    }
    impl State {
        fn line(&self, n: u64, spent: f64) -> String {
            let id = &self.id;
            let Some(o) = &self.outlook else {
                return format!("{id}: {n} evaluated, {} so far", study::duration(spent));
            };
            let phase = match o.phase() {
                "" => String::new(),
                p => format!("; {p}"),
            };
            let left = match o.left() {
                Some(left) if n > 0 => format!(
                    ", about {} left ({left} more evaluations expected)",
                    study::duration(spent * left as f64 / n as f64)
                ),
                _ => String::new(),
            };
            format!("{id}: {n} evaluated (at most {}), {} so far{left}{phase}", self.ceiling, study::duration(spent))
        }
    }
    let state = std::sync::Arc::new(State {
        id: id.to_string(),
        start: std::time::Instant::now(),
        done: AtomicU64::new(0),
        due: AtomicU64::new((LOG_EVERY_S * 1e3) as u64),
        outlook,
        ceiling,
    });
    if state.outlook.is_some() {
        // The heartbeat: ends with the run (when the counter is dropped).
        let weak = std::sync::Arc::downgrade(&state);
        std::thread::spawn(move || loop {
            std::thread::sleep(std::time::Duration::from_secs(1));
            let Some(st) = weak.upgrade() else { return };
            let ms = st.start.elapsed().as_millis() as u64;
            let next = st.due.load(Ordering::Relaxed);
            let quiet = ms.saturating_sub(next.saturating_sub((LOG_EVERY_S * 1e3) as u64));
            if quiet >= HEARTBEAT_S * 1000
                && st
                    .due
                    .compare_exchange(next, ms + (LOG_EVERY_S * 1e3) as u64, Ordering::Relaxed, Ordering::Relaxed)
                    .is_ok()
            {
                eprintln!("{}", st.line(st.done.load(Ordering::Relaxed), ms as f64 / 1e3));
            }
        });
    }
    Box::new(move || {
        let st = &state;
        let n = st.done.fetch_add(1, Ordering::Relaxed) + 1;
        let elapsed = st.start.elapsed();
        let ms = elapsed.as_millis() as u64;
        let next = st.due.load(Ordering::Relaxed);
        if ms < next || (total > 0 && n >= total) {
            return;
        }
        // One thread prints a given line.
        if st.due.compare_exchange(next, ms + (LOG_EVERY_S * 1e3) as u64, Ordering::Relaxed, Ordering::Relaxed).is_err()
        {
            return;
        }
        let spent = elapsed.as_secs_f64();
        if total == 0 {
            eprintln!("{}", st.line(n, spent));
            return;
        }
        let left = spent * (total - n) as f64 / n as f64;
        eprintln!(
            "{}: {n}/{total} points, {} so far, about {} left",
            st.id,
            study::duration(spent),
            study::duration(left)
        );
    })
}

impl Progress for Bars {
    fn start_search(
        &self,
        id: &str,
        ceiling: u64,
        outlook: std::sync::Arc<crate::design::halt::Outlook>,
    ) -> Box<Tick<'static>> {
        match &self.multi {
            None => log_search(id, 0, ceiling, Some(outlook)),
            Some(multi) => counter(multi, id, &format!(" (at most {ceiling})")),
        }
    }

    fn start(&self, id: &str, total: u64) -> Box<Tick<'static>> {
        let Some(multi) = &self.multi else { return log_lines(id, total) };
        if total == 0 {
            return counter(multi, id, "");
        }
        let bar = multi.add(indicatif::ProgressBar::new(total));
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{prefix:>28} [{bar:30}] {pos}/{len} points, {elapsed}")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_prefix(id.to_string());
        Box::new(move || bar.inc(1))
    }
}

/// A counter of unknown total on a terminal (a design's evaluations, `bound` its bound in
/// words), drawn at its first tick (most experiments of total 0 never tick).
fn counter(multi: &indicatif::MultiProgress, id: &str, bound: &str) -> Box<Tick<'static>> {
    let (multi, id) = (multi.clone(), id.to_string());
    let template = format!("{{prefix:>28}} {{pos}} evaluated{bound}, {{elapsed}}");
    let bar = std::sync::OnceLock::new();
    Box::new(move || {
        bar.get_or_init(|| {
            let bar = multi.add(indicatif::ProgressBar::new_spinner());
            if let Ok(style) = indicatif::ProgressStyle::with_template(&template) {
                bar.set_style(style);
            }
            bar.set_prefix(id.clone());
            bar
        })
        .inc(1)
    })
}
