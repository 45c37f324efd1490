//! The live explorer (`shotdamp explore FILE`, docs/explore.md): one experiment file's cases
//! and models, the values the paper leaves unstated and the design variables as controls, and
//! every change recomputed by the library and answered as data for the page to draw.
//!
//! A request is a set of values at key paths of the experiment file (the study files' paths,
//! [`KeyPath`]), a model, a band and how the sweep starts. Only the paths of
//! [`ALLOWED`] may be set and only to numbers (or a bed law's name), so no request reaches
//! the file system; the experiment is then read and validated by the same code as a file, so
//! a bad value gets a file's message. No I/O here but reading the file at the start
//! ([`Session::open`]); the server is [`http`].

pub mod http;
pub mod keys;
mod page;
mod point;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::Deserialize;
use serde_json::{json, Value};

use crate::analysis::{self, curves};
use crate::checks::reference::{BaselineMode, ReferenceStore};
use crate::error::{Error, Result};
use crate::experiment::study::KeyPath;
use crate::experiment::{self, Case, CurveId, Experiment, Exports, Linear};

use crate::reference::files::Files;
use keys::{allowed, Allowed, ALLOWED, LAWS};

pub use point::PointRequest;

/// Most frequencies one request may simulate (a band of 0.01 Hz steps over 20 Hz).
pub const MAX_POINTS: usize = 2001;

/// Longest time one request may compute before it is abandoned.
pub const MAX_TIME: Duration = Duration::from_secs(30);

/// One model of the file: its id, label and merged table.
#[derive(Debug, Clone)]
struct Model {
    id: String,
    label: String,
    table: toml::Table,
    /// Its table as the last request set it, validated ([`experiment::loader::Varying`]).
    varying: experiment::loader::Varying,
    /// The curves the file's checks compare with on this model (independent solver,
    /// digitised), as markers.
    references: Vec<Value>,
}

/// An open experiment file: its models, the values its export references take (computed once
/// by running the experiments they come from) and the page's controls.
#[derive(Debug)]
pub struct Session {
    path: PathBuf,
    models: Vec<Model>,
    exports: Exports,
    files: Files,
    refs: ReferenceStore,
    setup: Value,
}

/// A sweep asked for by the page.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Request {
    /// Index of the model (0 when the file has none).
    #[serde(default)]
    pub model: usize,
    /// Values set in order: `[path, value]`.
    #[serde(default)]
    pub set: Vec<(String, Value)>,
    /// The band, Hz.
    pub band: Band,
    /// `"rest"` or `"continuation"`.
    pub start: String,
    /// The page's number for the request, increasing (0: none): a sweep stops when one with a
    /// higher number arrives, and one lower than the highest seen is refused.
    #[serde(default)]
    pub seq: u64,
}

/// A band of frequencies.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Band {
    /// First frequency, Hz.
    pub start: f64,
    /// Last frequency, Hz.
    pub stop: f64,
    /// Step, Hz.
    pub step: f64,
}

/// An input error of a request (the page shows the message).
fn bad(key: impl Into<String>, value: impl std::fmt::Display, message: impl Into<String>) -> Error {
    Error::invalid(Path::new("request"), key.into(), value, message.into())
}

impl Session {
    /// Reads `path` (and the experiments in its folder whose values it uses, which are run
    /// once here) with the reference data in `reference`.
    pub fn open(path: &Path, reference: &Path) -> Result<Session> {
        let files = Files::new(reference);
        let exps = experiment::loader::load_with(path, &files)?;
        let Some(first) = exps.first() else {
            return Err(Error::invalid(path, "(file)", "", "the file defines no experiment"));
        };
        if first.analysis.design().is_some() {
            return Err(Error::invalid(
                path,
                "analysis.kind",
                "\"design\"",
                "the explorer takes an experiment file (a sweep, a clearance study, ...): open a design's layout as an experiment file",
            ));
        }
        let exports = dependencies(&exps, &files, reference)?;
        let store = ReferenceStore::load(reference, &exps)?;
        let models = experiment::read_models(path)?
            .into_iter()
            .zip(&exps)
            .map(|((_, table), e)| Model {
                id: e.model.as_ref().map_or_else(|| "structure".to_string(), |m| m.id.clone()),
                label: e.model.as_ref().map_or_else(|| "the file's structure".to_string(), |m| m.label.clone()),
                table,
                varying: Default::default(),
                references: references(e, &store),
            })
            .collect();
        let mut refs = ReferenceStore::default();
        refs.baseline_mode = BaselineMode::Off;
        let mut s = Session { path: path.to_path_buf(), models, exports, files, refs, setup: Value::Null };
        let resolved = first.resolve(&s.exports)?;
        s.setup = setup(&resolved, &s.models);
        Ok(s)
    }

    /// What the page needs to draw its controls: the experiment's title, models, cases (with
    /// each container), the controls with their ranges and starting values, the band.
    pub fn setup(&self) -> &Value {
        &self.setup
    }

    /// The experiment a request describes: the model's table with the request's values set,
    /// run as a sweep over its band without the file's checks and plots, validated as a file
    /// (its structure taken from the model's last request where `[structure]` is unchanged,
    /// [`experiment::loader::vary`]), its export references resolved.
    pub fn experiment(&self, req: &Request) -> Result<Experiment> {
        let (model, table) = self.table(req)?;
        model
            .varying
            .validate(&self.path, table, &self.files)
            .and_then(|e| e.resolve(&self.exports))
            .map_err(|e| self.of_request(e, req))
    }

    /// A validation error of a request's experiment, named as the request's: the file itself
    /// was validated when it was opened, so what fails now is what the request set (its
    /// values, its band or its start).
    fn of_request(&self, e: Error, req: &Request) -> Error {
        let set: Vec<String> = req.set.iter().enumerate().map(|(i, (k, v))| format!("set[{i}] {k} = {v}")).collect();
        let origin = format!(
            "request (on {}, model {}; {})",
            self.path.display(),
            req.model,
            if set.is_empty() { "its band and start".to_string() } else { format!("values set: {}", set.join(", ")) }
        );
        e.in_file(|_| origin)
    }

    /// The experiment file of a request: the model's table with its values set, standalone
    /// (the model merged in, files it names made absolute), as TOML text. `shotdamp run` on it
    /// computes the curves the page shows.
    pub fn export(&self, req: &Request) -> Result<String> {
        let (model, mut table) = self.table(req)?;
        let exp = model.varying.validate(&self.path, table.clone(), &self.files)?.resolve(&self.exports)?;
        resolve_exports(&mut table, &exp);
        absolute_files(&mut table, &self.path);
        let text = toml::to_string(&table).map_err(|e| bad("(export)", "", e.to_string()))?;
        Ok(format!(
            "# Exported by `shotdamp explore {}`: the setup shown on the page.\n# Run it with `shotdamp run THIS_FILE`.\n{text}",
            self.path.display()
        ))
    }

    /// The request's model and its table with the request's band, start and values.
    fn table(&self, req: &Request) -> Result<(&Model, toml::Table)> {
        let model = self.models.get(req.model).ok_or_else(|| {
            bad("model", req.model, format!("a model index from 0 to {}", self.models.len().saturating_sub(1)))
        })?;
        let mut table = model.table.clone();
        as_sweep(&mut table, req)?;
        for (i, (key, value)) in req.set.iter().enumerate() {
            let (path, value) =
                allowed(key, value).map_err(|m| bad(format!("set[{i}] \"{key}\""), value, m.to_string()))?;
            path.set(&mut table, &value).map_err(|m| bad(format!("set[{i}] \"{key}\""), &value, m.to_string()))?;
        }
        Ok((model, table))
    }

    /// Runs a request: the curves of every case (sweeps; the bare structure and each case with
    /// its shot stuck as exact linear curves), as data for the page. `stop` is called at every
    /// simulated point and may unwind out of the computation (a newer request, the time limit).
    pub fn run(&self, req: &Request, stop: &(dyn Fn() + Sync)) -> Result<Value> {
        let t0 = Instant::now();
        let exp = self.experiment(req)?;
        let result = analysis::run(&exp, &self.refs, stop)?;
        let freqs = band(req)?;
        let mut out: Vec<Value> = Vec::new();
        for case in &exp.cases {
            for c in result.curves.iter().filter(|c| c.id.drawn_for(&case.id)) {
                out.push(curve_json(c, "sweep"));
            }
        }
        // Continuation's orbit branches, through folds: stable and unstable parts.
        out.extend(result.tables.iter().filter(|t| t.name == "branches").flat_map(branch_curves));
        let bare_id = CurveId::linear("bare", Linear::Bare);
        let bare = curves::linear(&exp, &Case::bare(), bare_id, "no damper (linear)", &freqs, false);
        out.push(curve_json(&bare, "linear"));
        for case in exp.cases.iter().filter(|c| !c.is_bare()) {
            let id = CurveId::linear(&case.id, Linear::Stuck);
            let label = format!("{}, shot stuck (linear)", case.label);
            out.push(curve_json(&curves::linear(&exp, case, id, &label, &freqs, true), "stuck"));
        }
        let model = &self.models[req.model];
        Ok(json!({
            "curves": out,
            "references": model.references,
            "unit": result.curves.unit(),
            "masses": exp.structure.physical(),
            "warnings": result.warnings,
            "ms": t0.elapsed().as_secs_f64() * 1e3,
        }))
    }

    /// One frequency of one case: its steady motion over a period or more, its events, period
    /// and Floquet multipliers (from rest, as the waveform analysis).
    pub fn point(&self, req: &PointRequest) -> Result<Value> {
        let exp = self.experiment(&req.setup)?;
        point::run(&exp, req)
    }
}

/// The frequencies of a request's band (at most [`MAX_POINTS`]).
fn band(req: &Request) -> Result<Vec<f64>> {
    let Band { start, stop, step } = req.band;
    if !(start.is_finite() && stop.is_finite() && step.is_finite() && start > 0.0 && stop > start && step > 0.0) {
        return Err(bad("band", format!("{start} to {stop} step {step}"), "0 < start < stop and a positive step"));
    }
    let n = ((stop - start) / step + 1e-9).floor() as usize + 1;
    if n > MAX_POINTS {
        return Err(bad("band", format!("{n} points"), format!("at most {MAX_POINTS} points: a wider step")));
    }
    Ok((0..n).map(|i| experiment::round_hz(start + step * i as f64)).collect())
}

/// Makes a model's table a sweep over the request's band, starting as it asks: the file's own
/// analysis settings but its steady-state options go, and so do its checks, plots, words
/// that cite them and the experiment it continues.
fn as_sweep(table: &mut toml::Table, req: &Request) -> Result<()> {
    band(req)?;
    if req.start != "rest" && req.start != "continuation" {
        return Err(bad("start", format!("\"{}\"", req.start), "\"rest\" or \"continuation\""));
    }
    let steady = table.get("analysis").and_then(|a| a.get("steady")).cloned();
    let mut analysis = toml::Table::new();
    analysis.insert("kind".into(), "sweep".into());
    let mut f = toml::Table::new();
    f.insert("start".into(), req.band.start.into());
    f.insert("stop".into(), req.band.stop.into());
    f.insert("step".into(), req.band.step.into());
    analysis.insert("freq_hz".into(), f.into());
    analysis.insert("start".into(), req.start.clone().into());
    if let Some(s) = steady {
        analysis.insert("steady".into(), s);
    }
    table.insert("analysis".into(), analysis.into());
    // `extends` was merged in already (and names a file relative to this one).
    for key in ["checks", "plots", "outputs", "exports", "study", "extends"] {
        table.remove(key);
    }
    if let Some(toml::Value::Table(meta)) = table.get_mut("experiment") {
        meta.retain(|k, _| matches!(k, "id" | "title" | "figure" | "caption" | "claim" | "assumptions"));
        if let Some(toml::Value::String(title)) = meta.get_mut("title") {
            title.push_str(" (explored)");
        }
        // Its own id: not compared with the file's blessed results.
        if let Some(toml::Value::String(id)) = meta.get_mut("id") {
            id.push_str("_explored");
        }
    }
    // Clearances to scan have no value outside a clearance study: the page sets one.
    if let Some(toml::Value::Array(cases)) = table.get_mut("cases") {
        for d in cases.iter_mut().filter_map(|c| c.get_mut("dampers")).filter_map(|d| d.as_array_mut()).flatten() {
            if d.get("clearance_mm").and_then(|v| v.as_str()) == Some("scan") {
                if let Some(t) = d.as_table_mut() {
                    t.insert("clearance_mm".into(), "inf".into());
                }
            }
        }
    }
    Ok(())
}

/// The values of export references (`"@EXPERIMENT.KEY"`) written into an exported table, so
/// that it runs alone: the clearances the request's experiment resolved them to.
fn resolve_exports(table: &mut toml::Table, exp: &Experiment) {
    let Some(toml::Value::Array(cases)) = table.get_mut("cases") else { return };
    for (c, case) in cases.iter_mut().zip(&exp.cases) {
        let Some(toml::Value::Array(dampers)) = c.get_mut("dampers") else { continue };
        for (d, bed) in dampers.iter_mut().zip(case.beds.iter()) {
            let Some(t) = d.as_table_mut() else { continue };
            if t.get("clearance_mm").and_then(|v| v.as_str()).is_some_and(|s| s.starts_with('@')) {
                t.insert("clearance_mm".into(), toml::Value::Float(bed.damper.clearance.mm()));
            }
        }
    }
}

/// Files a finite-element structure names, made absolute (they are relative to the file).
fn absolute_files(table: &mut toml::Table, path: &Path) {
    let dir = path.parent().unwrap_or(Path::new("."));
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    let Some(toml::Value::Table(fe)) = table.get_mut("structure").and_then(|s| s.get_mut("finite_element")) else {
        return;
    };
    for key in ["stiffness", "mass", "dofs", "file"] {
        if let Some(toml::Value::String(p)) = fe.get_mut(key) {
            if Path::new(p.as_str()).is_relative() {
                *p = dir.join(&*p).to_string_lossy().into_owned();
            }
        }
    }
}

/// A curve as the page draws it.
fn curve_json(c: &curves::Curve, kind: &str) -> Value {
    let masses = c.compliance.first().map_or(0, Vec::len);
    let per_mass: Vec<Vec<f64>> = (0..masses).map(|m| c.compliance.iter().map(|row| row[m]).collect()).collect();
    json!({
        "id": c.id.to_string(),
        "label": c.label,
        "kind": kind,
        "freq_hz": c.freq_hz,
        "compliance": per_mass,
        "converged": c.converged,
        "period": c.period,
        "radius": c.radius.iter().map(|r| if r.is_finite() { Some(*r) } else { None }).collect::<Vec<_>>(),
        "stop": c.stop,
        // Each point's class, and for a measured one the half-width of each mass's
        // compliance interval and the largest Lyapunov exponent (null otherwise).
        "motion": c.motion,
        "half_width": c.measured.iter().map(|m| m.as_ref().map(|m| m.half_width.iter().map(|h| number(*h)).collect::<Vec<_>>())).collect::<Vec<_>>(),
        "lyapunov_per_s": c.measured.iter().map(|m| m.as_ref().map(|m| [number(m.lyapunov.0), number(m.lyapunov.1)])).collect::<Vec<_>>(),
    })
}

/// The reference curves an experiment's checks compare with, as markers: an independent
/// solver's curve (`curve` checks: every mass) and digitised curves (`tube` and `peak` checks:
/// their mass), with the computed curve each belongs to.
fn references(exp: &Experiment, store: &ReferenceStore) -> Vec<Value> {
    use experiment::CheckKind;
    let n = exp.structure.dof();
    let mut out: Vec<Value> = Vec::new();
    for c in &exp.checks {
        let file = &c.reference_file;
        match &c.kind {
            CheckKind::Curve { curve, columns, .. } => {
                let Some(r) = store.curve(file) else { continue };
                let Some(freq) = r.columns.get("freq_hz") else { continue };
                let masses: Vec<&Vec<f64>> = (1..).map_while(|m| r.columns.get(&format!("{columns}c{m}"))).collect();
                if !masses.is_empty() {
                    out.push(json!({
                        "label": format!("{file} (reference for {curve}, at the file's setup)"),
                        "curve": curve.to_string(),
                        "freq_hz": freq,
                        "compliance": masses,
                    }));
                }
            }
            CheckKind::Tube { case, mass, curve, .. } | CheckKind::Peak { case, mass, curve, .. } => {
                let Some(d) = store.digitised(file).and_then(|f| f.get(curve)) else { continue };
                let label = format!("{file}: \"{curve}\" (digitised, m{}, at the file's setup)", mass + 1);
                if out.iter().any(|r| r["label"] == label.as_str()) {
                    continue;
                }
                let compliance: Vec<Value> =
                    (0..n).map(|m| if m == *mass { json!(d.y) } else { json!(vec![Value::Null; d.y.len()]) }).collect();
                out.push(json!({ "label": label, "curve": case, "freq_hz": d.x, "compliance": compliance }));
            }
            _ => {}
        }
    }
    out
}

/// The orbit branches of a continuation (the `branches` table: points in the order continued,
/// through folds), one curve each, with each point's stability.
fn branch_curves(t: &crate::table::Table) -> Vec<Value> {
    use crate::table::ColumnData;
    let column = |name: &str| t.columns.iter().find(|(n, _)| n == name).map(|(_, c)| c);
    let (Some(ColumnData::Str(ids)), Some(freq), Some(ColumnData::I64(stable)), Some(radius)) =
        (column("branch"), t.column_f64("freq_hz"), column("stable"), t.column_f64("max_multiplier"))
    else {
        return Vec::new();
    };
    let masses: Vec<&[f64]> = (1..).map_while(|m| t.column_f64(&format!("c{m}"))).collect();
    let mut order: Vec<&String> = Vec::new();
    for id in ids {
        if !order.contains(&id) {
            order.push(id);
        }
    }
    order
        .into_iter()
        .map(|id| {
            let rows: Vec<usize> = (0..ids.len()).filter(|&i| &ids[i] == id).collect();
            json!({
                "id": id,
                "label": format!("{id}: orbit branch"),
                "kind": "orbits",
                "freq_hz": rows.iter().map(|&i| freq[i]).collect::<Vec<_>>(),
                "compliance": masses.iter().map(|c| rows.iter().map(|&i| c[i]).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "stable": rows.iter().map(|&i| stable[i] == 1).collect::<Vec<_>>(),
                "radius": rows.iter().map(|&i| radius[i]).collect::<Vec<_>>(),
                "converged": rows.iter().map(|_| true).collect::<Vec<_>>(),
            })
        })
        .collect()
}

/// The page's controls for an experiment (resolved, on the first model) and the models.
fn setup(exp: &Experiment, models: &[Model]) -> Value {
    let beds: Vec<&experiment::Bed> = exp.cases.iter().flat_map(|c| c.beds.iter()).collect();
    let first_model = &models[0].table;
    let has = |path: &str| KeyPath::parse(path).is_ok_and(|p| !p.get(first_model).is_empty());
    let start_value = |a: &Allowed| -> Option<f64> {
        match a.path {
            "cases[*].dampers[*].clearance_mm" => {
                beds.first().map(|b| b.damper.clearance.mm()).map(|d| if d.is_finite() { d } else { a.max })
            }
            "cases[*].dampers[*].mass_ratio" => has(a.path).then(|| {
                KeyPath::parse(a.path).ok().and_then(|p| p.get(first_model).first().and_then(|v| v.as_float()))
            })?,
            "cases[*].dampers[*].restitution" => (!beds.is_empty()).then_some(0.0),
            "structure.damping.modal_ratios" => {
                KeyPath::parse(a.path).ok().and_then(|p| p.get(first_model).first().and_then(|v| v.as_float()))
            }
            "excitation.force_n" => Some(exp.excitation.force),
            _ => None,
        }
    };
    let controls: Vec<Value> = ALLOWED
        .iter()
        .filter_map(|a| {
            let v = start_value(a)?;
            Some(json!({ "path": a.path, "label": a.label, "min": a.min, "max": a.max, "log": a.log, "value": v }))
        })
        .collect();
    let cases: Vec<Value> = exp
        .cases
        .iter()
        .map(|c| {
            let dampers: Vec<Value> = c
                .beds
                .iter()
                .map(|b| json!({ "host": b.damper.host + 1, "mass_kg": b.damper.mass, "clearance_mm": finite(b.damper.clearance.mm()) }))
                .collect();
            json!({ "id": c.id, "label": c.label, "dampers": dampers })
        })
        .collect();
    let grid = exp.analysis.simulated_frequencies().into_iter().next().map(|(_, f)| f).unwrap_or_default();
    let (start, stop, step) = match grid.as_slice() {
        [first, .., last] => (*first, *last, experiment::round_hz((last - first) / (grid.len() - 1) as f64)),
        _ => (1.0, 60.0, 0.5),
    };
    let continuation =
        matches!(exp.analysis, experiment::Analysis::Sweep { start: experiment::Start::Continuation, .. });
    json!({
        "title": exp.meta.title,
        "figure": exp.meta.figure,
        "masses": exp.structure.physical(),
        "models": models.iter().map(|m| json!({ "id": m.id, "label": m.label })).collect::<Vec<_>>(),
        "cases": cases,
        "controls": controls,
        "laws": LAWS,
        "damping_modes": KeyPath::parse("structure.damping.modal_ratios").map_or(0, |p| p.get(first_model).len()),
        "mass_ratios": has("cases[*].dampers[*].mass_ratio"),
        "band": { "start": start, "stop": stop, "step": step },
        "start": if continuation { "continuation" } else { "rest" },
        "max_points": MAX_POINTS,
    })
}

/// A number, or null where it is not finite (not measured).
fn number(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

fn finite(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        json!("inf")
    }
}

/// The exports an experiment file uses: the experiments of its folder it names (and those
/// they name) run once, in order.
fn dependencies(exps: &[Experiment], files: &Files, reference: &Path) -> Result<Exports> {
    let chosen = experiment::missing_dependencies(exps, files)?;
    if chosen.is_empty() {
        return Ok(Exports::new());
    }
    let graph = experiment::loader::dependency_graph(&chosen)?;
    let mut refs = ReferenceStore::load(reference, &chosen)?;
    refs.baseline_mode = BaselineMode::Off;
    let mut exports = Exports::new();
    let mut done = vec![false; chosen.len()];
    while done.iter().any(|d| !d) {
        let Some(i) = (0..chosen.len()).find(|&i| !done[i] && graph[i].iter().all(|&d| done[d])) else { break };
        let exp = chosen[i].resolve(&exports)?;
        let r = analysis::run(&exp, &refs, &|| {})?;
        exports.insert(exp.key(), r.exports);
        done[i] = true;
    }
    Ok(exports)
}

#[cfg(test)]
mod tests;
