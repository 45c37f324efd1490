//! Long computations: run without the interpreter lock on a worker thread, stopped by Ctrl-C,
//! with optional progress, and every error or panic turned into a Python exception.

use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// A library error as a Python exception with the command line's message: bad input (a value
/// refused, a lower layer's refusal of one) is a `ValueError`, a file that cannot be read or
/// written an `OSError`, anything else a `RuntimeError`.
pub fn error(e: shotdamp::Error) -> PyErr {
    let text = e.to_string();
    match e {
        shotdamp::Error::Invalid { .. } | shotdamp::Error::Refused { .. } | shotdamp::Error::Parse { .. } => {
            PyValueError::new_err(text)
        }
        shotdamp::Error::Io { .. } | shotdamp::Error::Destination { .. } => PyOSError::new_err(text),
        shotdamp::Error::Table { .. } | shotdamp::Error::Render { .. } | shotdamp::Error::Domain(_) => {
            PyRuntimeError::new_err(text)
        }
    }
}

/// The payload a cancelled computation unwinds with (never through the panic hook: nothing
/// is printed).
struct Cancelled;

/// What a computation sees: whether to stop, and a counter of finished points.
#[derive(Clone, Default)]
pub struct Ticker {
    cancel: Arc<AtomicBool>,
    done: Arc<AtomicU64>,
    total: Arc<AtomicU64>,
}

impl Ticker {
    /// One more finished point; unwinds out of the computation once Ctrl-C was pressed (its
    /// staging folders are removed on the way, as dropping them does).
    pub fn tick(&self) {
        self.check();
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    /// Unwinds out of the computation once Ctrl-C was pressed, counting nothing.
    pub fn check(&self) {
        if self.cancel.load(Ordering::Relaxed) {
            resume_unwind(Box::new(Cancelled));
        }
    }

    /// Adds `n` points to the total shown by the progress callback.
    pub fn expect(&self, n: u64) {
        self.total.fetch_add(n, Ordering::Relaxed);
    }
}

impl shotdamp::analysis::Progress for Ticker {
    fn start(&self, _id: &str, total: u64) -> Box<shotdamp::analysis::Tick<'static>> {
        self.expect(total);
        let me = self.clone();
        if total == 0 {
            // A counter of unknown total (a report's studies): it only listens for Ctrl-C.
            return Box::new(move || me.check());
        }
        Box::new(move || me.tick())
    }
}

impl shotdamp::runner::study::StudyProgress for Ticker {
    fn point(&self) {
        self.check();
    }

    fn sample(&self) {
        self.tick();
    }
}

/// How often the waiting thread looks for Ctrl-C and reports progress.
const POLL: Duration = Duration::from_millis(50);

/// Least time between two calls of the progress callback.
const PROGRESS_EVERY: Duration = Duration::from_millis(200);

/// `jobs=` of a call: `None` (one thread per core) or 1 to `shotdamp.runner::max_jobs()`
/// worker threads; another whole number, however large, is a `ValueError` (never an
/// `OverflowError`), anything else a `TypeError`.
pub fn jobs(jobs: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let max = shotdamp::runner::max_jobs();
    let Some(value) = jobs else { return Ok(None) };
    if value.is_none() {
        return Ok(None);
    }
    if !value.is_instance_of::<pyo3::types::PyInt>() || value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "jobs = {}: a whole number of worker threads, or None",
            value.repr().map(|r| r.to_string()).unwrap_or_default()
        )));
    }
    match value.extract::<i64>() {
        Ok(j) if j >= 1 && j as u64 <= max as u64 => Ok(Some(j as usize)),
        _ => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "jobs = {value}: give 1 to {max} worker threads (up to {} per core, and never fewer than 16: more only add switching), or None for one per core",
            shotdamp::runner::JOBS_PER_CORE
        ))),
    }
}

/// Runs `work` on a pool of `jobs` threads (`None`: one per core) without the interpreter
/// lock. The calling thread waits, runs Python's signal handlers (Ctrl-C raises
/// `KeyboardInterrupt` once the computation has stopped at its next simulated period) and
/// calls `progress(done, total)` when given.
pub fn run<T: Send>(
    py: Python<'_>,
    jobs: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Ticker) -> Result<T, shotdamp::Error> + Send,
) -> PyResult<T> {
    let pool = shotdamp::runner::pool(jobs).map_err(error)?;
    run_on(py, &pool, progress, work)
}

/// [`run`] on a pool the caller built (and may hand to `work` as well).
pub fn run_on<T: Send>(
    py: Python<'_>,
    pool: &rayon::ThreadPool,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Ticker) -> Result<T, shotdamp::Error> + Send,
) -> PyResult<T> {
    let ticker = Ticker::default();
    let progress = progress.map(|p| p.clone().unbind());
    let (outcome, interrupt, shown) = py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel();
            let ticker = &ticker;
            s.spawn(move || {
                // Every worker thread stops at its next simulated period once Ctrl-C was
                // pressed (the simulator's cancellation check), not only at its next point: a
                // design's layout on a large model takes minutes.
                let cancel = Arc::clone(&ticker.cancel);
                let hook: shotdamp::sim::motion::cancel::Hook = Arc::new(move || {
                    if cancel.load(Ordering::Relaxed) {
                        resume_unwind(Box::new(Cancelled));
                    }
                });
                pool.broadcast(|_| shotdamp::sim::motion::cancel::replace(Some(Arc::clone(&hook))));
                let r = catch_unwind(AssertUnwindSafe(|| pool.install(|| work(ticker))));
                pool.broadcast(|_| shotdamp::sim::motion::cancel::replace(None));
                let _ = tx.send(r);
            });
            let mut interrupt: Option<PyErr> = None;
            let mut shown: Result<(), PyErr> = Ok(());
            let mut last = (Instant::now(), u64::MAX);
            loop {
                match rx.recv_timeout(POLL) {
                    Ok(r) => return (r, interrupt, shown),
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        let gone: std::thread::Result<Result<T, shotdamp::Error>> =
                            Err(Box::new("the worker thread ended without a result"));
                        return (gone, interrupt, shown);
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                }
                if interrupt.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        ticker.cancel.store(true, Ordering::Relaxed);
                        interrupt = Some(e);
                    }
                }
                if let (Some(p), true) = (&progress, shown.is_ok()) {
                    let done = ticker.done.load(Ordering::Relaxed);
                    if done != last.1 && last.0.elapsed() >= PROGRESS_EVERY {
                        last = (Instant::now(), done);
                        let total = ticker.total.load(Ordering::Relaxed);
                        shown = Python::attach(|py| p.call1(py, (done, total)).map(drop));
                        if shown.is_err() {
                            ticker.cancel.store(true, Ordering::Relaxed);
                        }
                    }
                }
            }
        })
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    shown?;
    match outcome {
        Ok(Ok(value)) => {
            if let Some(p) = &progress {
                let (done, total) = (ticker.done.load(Ordering::Relaxed), ticker.total.load(Ordering::Relaxed));
                p.call1(py, (done, total))?;
            }
            Ok(value)
        }
        Ok(Err(e)) => Err(error(e)),
        Err(payload) if payload.is::<Cancelled>() => Err(PyKeyboardInterrupt::new_err("interrupted")),
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(no message)".into());
            Err(PyRuntimeError::new_err(format!("shotdamp internal error (please report it): {what}")))
        }
    }
}
