//! Experiment files, the whole report and studies, through the library calls the command line
//! makes (`shotdamp run`, `shotdamp report`, `shotdamp study`, `shotdamp study merge`).

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use shotdamp::analysis::ExperimentResult;
use shotdamp::checks::reference::BaselineMode;
use shotdamp::experiment::{self, Analysis, ClearanceSource};
use shotdamp::output::manifest::Shard;
use shotdamp::output::ReportOptions;
use shotdamp::runner::designs::DesignSettings;
use shotdamp::runner::{self, study as studies, Finished, ReportInputs, ReportSettings, Settings};

use crate::compute::{self, error};
use crate::convert::{array1, columns};
use crate::structure::Structure;
use crate::system::System;

/// One experiment of a file, on one model of the structure.
#[pyclass(module = "shotdamp._native", frozen)]
pub struct Experiment {
    /// The experiment's id.
    #[pyo3(get)]
    id: String,
    /// Its key in reports: the id, with the model for a file run on several models.
    #[pyo3(get)]
    key: String,
    /// The model of the structure (None for a file with one structure).
    #[pyo3(get)]
    model: Option<String>,
    /// Title and the paper's figure.
    #[pyo3(get)]
    title: String,
    #[pyo3(get)]
    figure: String,
    /// The analysis kind ("sweep", "impulse", ...).
    #[pyo3(get)]
    kind: String,
    /// Case ids.
    #[pyo3(get)]
    cases: Vec<String>,
    /// Driven mass (1-based) and force amplitude, N (None when the supports move).
    #[pyo3(get)]
    force_mass: Option<usize>,
    #[pyo3(get)]
    force_n: Option<f64>,
    /// The supports' acceleration amplitude, m/s^2 (None under a force).
    #[pyo3(get)]
    base_acceleration_m_s2: Option<f64>,
    exp: experiment::Experiment,
}

#[pymethods]
impl Experiment {
    /// The structure of this model.
    #[getter]
    fn structure(&self) -> Structure {
        Structure { bare: self.exp.structure.clone(), fe: self.exp.finite_element.clone() }
    }

    /// The frequency grid of a sweep or clearance study, Hz (None for other kinds).
    #[getter]
    fn freq_hz<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray1<f64>>> {
        match &self.exp.analysis {
            Analysis::Sweep { freq_hz, .. } | Analysis::ClearanceStudy { freq_hz, .. } => {
                Some(array1(py, freq_hz.clone()))
            }
            _ => None,
        }
    }

    /// The steady-state settings of a sweep, clearance study or design (the dict
    /// `System.sweep(steady=...)` takes; None for other kinds).
    #[getter]
    fn steady<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let o = match &self.exp.analysis {
            Analysis::Sweep { steady, .. } | Analysis::ClearanceStudy { steady, .. } => steady,
            _ => return Ok(None),
        };
        let d = PyDict::new(py);
        d.set_item("method", o.method.name())?;
        d.set_item("tol", o.tol)?;
        d.set_item("orbit_tol", o.orbit_tol)?;
        d.set_item("max_newton", o.max_newton)?;
        d.set_item("consecutive", o.consecutive)?;
        d.set_item("min_periods", o.min_periods)?;
        d.set_item("max_periods", o.max_periods)?;
        d.set_item("record_periods", o.record_periods)?;
        d.set_item("torus_attempts", o.torus_attempts)?;
        d.set_item("follow", o.follow)?;
        Ok(Some(d))
    }

    /// The simulated system of case `case` (its clearances must be numbers, not a scan or a
    /// value exported by another experiment).
    fn system(&self, case: &str) -> PyResult<System> {
        let origin = self.exp.path.display().to_string();
        let Some(c) = self.exp.cases.iter().find(|c| c.id == case) else {
            return Err(error(shotdamp::Error::invalid(
                &origin,
                "case",
                format!("\"{case}\""),
                format!("one of the file's cases: {}", self.cases.join(", ")),
            )));
        };
        if let Some(i) = c.beds.iter().position(|b| b.clearance != ClearanceSource::Fixed) {
            return Err(error(shotdamp::Error::invalid(
                &origin,
                format!("cases[{case}].dampers[{i}].clearance_mm"),
                "(scan or @EXPERIMENT.KEY)",
                "this clearance is set by a run (a scan or another experiment's value): build the System with a number",
            )));
        }
        Ok(System::from_parts(
            experiment::parts::system(&self.exp.structure, &self.exp.excitation, c),
            c.clone(),
            self.exp.excitation.force,
        ))
    }

    fn __repr__(&self) -> String {
        format!("Experiment(key={:?}, kind={:?}, cases={:?})", self.key, self.kind, self.cases)
    }
}

fn paths(files: &Bound<'_, PyAny>) -> PyResult<Vec<PathBuf>> {
    if let Ok(one) = files.extract::<PathBuf>() {
        return Ok(vec![one]);
    }
    files.extract::<Vec<PathBuf>>()
}

/// The experiments of a file (one per model of the structure), read and validated as
/// `shotdamp run` reads them.
#[pyfunction]
#[pyo3(signature = (path, *, reference=PathBuf::from("reference")))]
pub fn load(path: PathBuf, reference: PathBuf) -> PyResult<Vec<Experiment>> {
    let exps = experiment::loader::load(&path, &reference).map_err(error)?;
    Ok(exps
        .into_iter()
        .map(|e| Experiment {
            id: e.meta.id.clone(),
            key: e.key(),
            model: e.model.as_ref().map(|m| m.id.clone()),
            title: e.meta.title.clone(),
            figure: e.meta.figure.clone(),
            kind: e.analysis.kind().to_string(),
            cases: e.cases.iter().map(|c| c.id.clone()).collect(),
            force_mass: (!e.excitation.supports).then_some(e.excitation.mass + 1),
            force_n: (!e.excitation.supports).then_some(e.excitation.force),
            base_acceleration_m_s2: e.excitation.supports.then_some(e.excitation.force),
            exp: e,
        })
        .collect())
}

/// What a run wrote and found, as a dict.
fn finished<'py>(py: Python<'py>, done: &Finished) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("report", done.dest.clone())?;
    d.set_item("checks", done.checks)?;
    d.set_item("failed", PyList::new(py, &done.failed)?)?;
    d.set_item("passed", done.passed())?;
    let exps = PyList::empty(py);
    for r in &done.results {
        exps.append(result(py, r)?)?;
    }
    d.set_item("experiments", exps)?;
    Ok(d)
}

fn result<'py>(py: Python<'py>, r: &ExperimentResult) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("key", r.experiment.key())?;
    d.set_item("figure", &r.experiment.meta.figure)?;
    d.set_item("passed", r.passed())?;
    let tables = PyDict::new(py);
    for t in &r.tables {
        tables.set_item(&t.name, columns(py, t)?)?;
    }
    d.set_item("tables", tables)?;
    let checks = PyList::empty(py);
    for c in &r.checks {
        let x = PyDict::new(py);
        x.set_item("name", &c.name)?;
        x.set_item("description", &c.description)?;
        x.set_item("computed", c.computed)?;
        x.set_item("expected", c.expected)?;
        x.set_item("unit", &c.unit)?;
        x.set_item("tolerance", &c.tolerance)?;
        x.set_item("status", c.status.label())?;
        x.set_item("provenance", &c.provenance)?;
        x.set_item("detail", c.detail.clone())?;
        checks.append(x)?;
    }
    d.set_item("checks", checks)?;
    d.set_item("exports", r.exports.clone())?;
    // What to read first: the answer in one paragraph (a design) and the warnings.
    d.set_item("summary", r.answer.clone())?;
    d.set_item("warnings", r.warnings.clone())?;
    // Why the answer is partial (a design stopped at its time limit), or None.
    d.set_item("partial", r.partial.clone())?;
    // A design's answer (docs/design.md): the best layout and the reference layouts, as the
    // stored JSON has them.
    let answer = match &r.design {
        Some(a) => {
            let text = a.to_json().map_err(error)?;
            py.import("json")?.call_method1("loads", (text,))?.into_any()
        }
        None => py.None().into_bound(py),
    };
    d.set_item("design", answer)?;
    Ok(d)
}

/// Runs experiment files (one path or several) into a report folder `out`, as
/// `shotdamp run FILES --out OUT` does; returns the report's folder, the checks and, per
/// experiment, its tables (dicts of columns), checks and exported values.
#[pyfunction]
#[pyo3(signature = (files, *, out=PathBuf::from("runs"), reference=PathBuf::from("reference"), jobs=None, full_csv=false, progress=None))]
pub fn run_experiment<'py>(
    py: Python<'py>,
    files: &Bound<'py, PyAny>,
    out: PathBuf,
    reference: PathBuf,
    jobs: Option<&Bound<'py, PyAny>>,
    full_csv: bool,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jobs = compute::jobs(jobs)?;
    let files = paths(files)?;
    let settings = Settings {
        reference: reference.clone(),
        out,
        jobs,
        writing: ReportOptions { full_csv, ..ReportOptions::default() },
        baseline_mode: BaselineMode::Optional,
        bless: false,
    };
    let done = compute::run(py, jobs, progress, |t| {
        let exps = experiment::loader::load_all(&files, &reference)?;
        runner::run_and_write(&exps, &[], &settings, t, &|_| {}, &|_| {})
    })?;
    finished(py, &done)
}

/// Searches design files (one path or several), as `shotdamp design FILES --out OUT
/// [--store]` does: each must be a design file; returns what `run_experiment` does (each
/// experiment's `design` the answer: best layout, reference layouts, search settings) and,
/// with `store`, the answers' files written under `reference/designs/` (`stored`).
/// `time_limit` (seconds) stops the searches and keeps their best layouts so far, as
/// `--time-limit` does.
#[pyfunction]
#[pyo3(signature = (files, *, out=PathBuf::from("design-runs"), reference=PathBuf::from("reference"), jobs=None, store=false, time_limit=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn design<'py>(
    py: Python<'py>,
    files: &Bound<'py, PyAny>,
    out: PathBuf,
    reference: PathBuf,
    jobs: Option<&Bound<'py, PyAny>>,
    store: bool,
    time_limit: Option<f64>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jobs = compute::jobs(jobs)?;
    let files = paths(files)?;
    if let Some(t) = time_limit.filter(|t| !(t.is_finite() && *t >= 0.0)) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "time_limit = {t}: a number of seconds, 0 or more"
        )));
    }
    let settings = DesignSettings { reference, out, jobs, store, time_limit, interrupt: None, merge: None };
    let run = compute::run(py, jobs, progress, |t| runner::designs::run(&files, &settings, t, &|_| {}, &|_| {}))?;
    let d = finished(py, &run.finished)?;
    d.set_item("stored", PyList::new(py, &run.stored)?)?;
    Ok(d)
}

/// The whole report, as `shotdamp report --out OUT` writes it from the checkout at `root`
/// (its `experiments/`, `reference/`, `studies/` and `designs/`; each may be given apart).
/// The same files, byte for byte, as the command line's.
#[pyfunction]
#[pyo3(signature = (out=PathBuf::from("reports"), *, root=PathBuf::from("."), experiments=None, reference=None, studies=None, designs=None, jobs=None, full_csv=false, bless=false, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn report<'py>(
    py: Python<'py>,
    out: PathBuf,
    root: PathBuf,
    experiments: Option<PathBuf>,
    reference: Option<PathBuf>,
    studies: Option<PathBuf>,
    designs: Option<PathBuf>,
    jobs: Option<&Bound<'py, PyAny>>,
    full_csv: bool,
    bless: bool,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jobs = compute::jobs(jobs)?;
    let at = ReportInputs::at(&root);
    let inputs = ReportInputs {
        experiments: experiments.unwrap_or(at.experiments),
        reference: reference.unwrap_or(at.reference),
        studies,
        designs,
    };
    let settings = ReportSettings { out, jobs, writing: ReportOptions { full_csv, ..ReportOptions::default() }, bless };
    let done = compute::run(py, jobs, progress, |t| runner::report(&inputs, &settings, t, &|_| {}, &|_| {}))?;
    finished(py, &done)
}

/// A shard given as (index, count) or "index/count".
fn shard(v: Option<&Bound<'_, PyAny>>) -> PyResult<Shard> {
    let Some(v) = v.filter(|v| !v.is_none()) else { return Ok(Shard::WHOLE) };
    let (index, count) = match v.extract::<(usize, usize)>() {
        Ok(p) => p,
        Err(_) => {
            let text: String = v.extract()?;
            let parsed = text.split_once('/').and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
            parsed.ok_or_else(|| {
                error(shotdamp::Error::invalid(
                    "shotdamp.study",
                    "shard",
                    format!("\"{text}\""),
                    "INDEX/COUNT with 0 <= INDEX < COUNT, e.g. \"3/7\"",
                ))
            })?
        }
    };
    if count == 0 || index >= count {
        return Err(error(shotdamp::Error::invalid(
            "shotdamp.study",
            "shard",
            format!("{index}/{count}"),
            "INDEX/COUNT with 0 <= INDEX < COUNT, e.g. \"3/7\"",
        )));
    }
    Ok(Shard { index, count })
}

fn merged<'py>(py: Python<'py>, m: &studies::Merged) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("study", &m.manifest.study)?;
    d.set_item("rows", m.rows)?;
    d.set_item("table", m.table.clone())?;
    let sums = PyList::empty(py);
    for s in &m.summaries {
        let x = PyDict::new(py);
        x.set_item("model", &s.model)?;
        x.set_item("claim", &s.claim)?;
        x.set_item("bound", &s.bound)?;
        x.set_item("samples", s.samples)?;
        x.set_item("holds", s.holds)?;
        x.set_item("not_evaluable", s.not_evaluable)?;
        x.set_item("unsettled", s.unsettled)?;
        sums.append(x)?;
    }
    d.set_item("summaries", sums)?;
    Ok(d)
}

/// Runs a study file, whole or one shard (`shard=(i, n)` or `"i/n"`), into `out` (default
/// `study-runs/ID`), as `shotdamp study FILE --shard i/n` does; a whole study (or the last
/// shard of one with one shard) is merged. A stopped run resumes from its written batches.
#[pyfunction]
#[pyo3(signature = (path, *, out=None, reference=PathBuf::from("reference"), shard=None, jobs=None, progress=None))]
pub fn study<'py>(
    py: Python<'py>,
    path: PathBuf,
    out: Option<PathBuf>,
    reference: PathBuf,
    shard: Option<&Bound<'py, PyAny>>,
    jobs: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jobs = compute::jobs(jobs)?;
    let shard = self::shard(shard)?;
    let s = experiment::study::load(&path, &reference).map_err(error)?;
    let out = out.unwrap_or_else(|| studies::default_out(&s));
    studies::refuse_overlap(&s, &reference, &out).map_err(error)?;
    let pool = runner::pool(jobs).map_err(error)?;
    // One pool: the shard's samples run on the pool that hosts the computation.
    let (end, m) = compute::run_on(py, &pool, progress, |t| {
        let mine = s.samples.iter().filter(|x| shard.owns(x.index)).count();
        t.expect(mine as u64);
        studies::run_shard(&s, &reference, &out, shard, &pool, t)
    })?;
    let d = PyDict::new(py);
    d.set_item("out", out.clone())?;
    d.set_item("shard", format!("{}/{}", shard.index, shard.count))?;
    match end {
        studies::ShardEnd::AlreadyComplete => d.set_item("part", py.None())?,
        studies::ShardEnd::Written(p) => d.set_item("part", p)?,
    }
    d.set_item("merged", m.as_ref().map(|m| merged(py, m)).transpose()?)?;
    Ok(d)
}

/// Merges a study folder's shards, as `shotdamp study merge DIR` does.
#[pyfunction]
pub fn study_merge<'py>(py: Python<'py>, dir: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let m = compute::run(py, Some(1), None, |_| studies::merge(Path::new(&dir)))?;
    merged(py, &m)
}
