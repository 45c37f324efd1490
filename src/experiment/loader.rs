//! The one loader: an experiment file to its typed, validated setups. It reads the file with
//! its `extends` chain and model files ([`super::file::read`]), turns each model's merged
//! table into an [`Experiment`] by [`super::validate`] (one function from the file layer to
//! the setup; the finite-element reductions validation computes are kept for the process,
//! [`super::fe::made`]), and orders a run's experiments by the exports they use.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use super::file::read;
use super::validate::validate_keeping;
use super::{design, validate, Experiment, Kept, ModelInfo};
use crate::error::{Error, Result};
use crate::reference::files::Files;

/// Which experiments each experiment uses the exports of, as indices into `exps` (each list in
/// the order of first use). Fails on a duplicate run key, an unknown experiment id or a cycle.
pub fn dependency_graph(exps: &[Experiment]) -> Result<Vec<Vec<usize>>> {
    let keys: Vec<String> = exps.iter().map(|e| e.key()).collect();
    let mut graph = Vec::with_capacity(exps.len());
    for (i, e) in exps.iter().enumerate() {
        if let Some(j) = keys.iter().position(|k| *k == keys[i]).filter(|&j| j != i) {
            return Err(Error::invalid(
                &e.path,
                "experiment.id",
                format!("\"{}\"", e.meta.id),
                format!("the same id as {}", exps[j].path.display()),
            ));
        }
        let mut deps = Vec::new();
        for dep in e.dependencies() {
            let Some(j) = keys.iter().position(|k| *k == e.key_of(&dep)) else {
                let on = e.model.as_ref().map(|m| format!(" on model \"{}\"", m.id)).unwrap_or_default();
                return Err(Error::invalid(
                    &e.path,
                    "(export reference)",
                    format!("@{dep}"),
                    format!("no experiment with id \"{dep}\" runs{on}; the runs are {keys:?}"),
                ));
            };
            deps.push(j);
        }
        graph.push(deps);
    }
    // Kahn: whatever cannot be ordered lies on a cycle.
    let mut missing: Vec<usize> = graph.iter().map(Vec::len).collect();
    let mut ready: Vec<usize> = (0..exps.len()).filter(|&i| missing[i] == 0).collect();
    let mut ordered = 0;
    while let Some(i) = ready.pop() {
        ordered += 1;
        for (j, deps) in graph.iter().enumerate() {
            for _ in deps.iter().filter(|&&d| d == i) {
                missing[j] -= 1;
                if missing[j] == 0 {
                    ready.push(j);
                }
            }
        }
    }
    if ordered < exps.len() {
        let stuck = (0..exps.len()).find(|&i| missing[i] > 0).unwrap_or(0);
        return Err(Error::invalid(
            &exps[stuck].path,
            "(export reference)",
            format!("{:?}", exps[stuck].dependencies()),
            "experiments depend on each other in a cycle",
        ));
    }
    Ok(graph)
}

/// Loads and validates one experiment file: one experiment per model it runs on (one when it
/// lists no models); references are looked up in `reference_dir`.
pub fn load(path: &Path, reference_dir: &Path) -> Result<Vec<Experiment>> {
    load_with(path, &Files::new(reference_dir))
}

/// An experiment from a table (one model's, as [`read::read_models`] gives it, possibly changed by a
/// caller such as a study or the explorer): read and validated as a file's would be, its
/// errors naming `path`.
pub fn from_table(path: &Path, table: toml::Table, files: &Files) -> Result<Experiment> {
    read::read_raw(path, table).and_then(|raw| validate(path, raw, files))
}

/// A table of `path` validated as [`from_table`] validates it, its structure taken from
/// `kept` (what an earlier validation of the file's table built) where `[structure]` and the
/// analysis' coordinate limit are unchanged (a damping changed alone is computed on the kept
/// matrices): the same experiment, without building its structure again (no
/// finite-element file read, no reduction). Returns what this validation built, kept for
/// the next.
pub fn vary(path: &Path, table: toml::Table, files: &Files, kept: Option<&Kept>) -> Result<(Experiment, Kept)> {
    read::read_raw(path, table).and_then(|raw| validate_keeping(path, raw, files, kept))
}

/// One file's table validated again and again with values set (the explorer's requests, a
/// study's samples): each validation takes the structure the last one built where it can
/// ([`vary`]). Shared between threads; the experiments are the same whichever validation
/// kept what (a kept structure is used only where the inputs it was built from are equal).
#[derive(Default)]
pub struct Varying(Mutex<Option<Kept>>);

impl Varying {
    /// `table` (the file's, values set) validated, errors naming `path`.
    pub fn validate(&self, path: &Path, table: toml::Table, files: &Files) -> Result<Experiment> {
        let kept = self.0.lock().unwrap_or_else(PoisonError::into_inner).clone();
        let (exp, built) = vary(path, table, files, kept.as_ref())?;
        *self.0.lock().unwrap_or_else(PoisonError::into_inner) = Some(built);
        Ok(exp)
    }
}

impl Clone for Varying {
    fn clone(&self) -> Varying {
        Varying(Mutex::new(self.0.lock().unwrap_or_else(PoisonError::into_inner).clone()))
    }
}

impl std::fmt::Debug for Varying {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = self.0.lock().map(|k| k.is_some()).unwrap_or(false);
        f.debug_struct("Varying").field("kept", &kept).finish()
    }
}

/// [`load`] with the reference files parsed so far (each parsed once, [`Files`]).
pub fn load_with(path: &Path, files: &Files) -> Result<Vec<Experiment>> {
    let mut exps = read::read_models(path)?
        .into_iter()
        .map(|(model_file, table)| from_table(path, table, files).map_err(|e| on_model(e, model_file.as_deref())))
        .collect::<Result<Vec<_>>>()?;
    let models: Vec<ModelInfo> = exps.iter().filter_map(|e| e.model.clone()).collect();
    for e in &mut exps {
        e.models = models.clone();
    }
    models_as_scenarios(path, exps)
}

/// A design file with `[design.scenarios] models = true` becomes one experiment (on no single
/// model) whose search takes every model's structure and force as scenarios.
fn models_as_scenarios(path: &Path, mut exps: Vec<Experiment>) -> Result<Vec<Experiment>> {
    let wanted = exps[0].analysis.design().is_some_and(|(spec, _)| spec.scenario_models);
    if !wanted {
        return Ok(exps);
    }
    if exps.len() < 2 || exps.iter().any(|e| e.model.is_none()) {
        return Err(Error::invalid(
            path,
            "design.scenarios.models",
            "true",
            "the file must list two or more models (`models = [...]`) to take them as scenarios",
        ));
    }
    let structures: Vec<(String, crate::model::Structure, f64)> = exps
        .iter()
        .map(|e| {
            (e.model.as_ref().map(|m| m.label.clone()).unwrap_or_default(), e.structure.clone(), e.excitation.force)
        })
        .collect();
    let mut one = exps.swap_remove(0);
    one.model = None;
    if let Some(spec) = one.analysis.design_mut() {
        spec.model_structures = structures;
        design::sized(path, spec)?;
    }
    Ok(vec![one])
}

/// An input error in the structure of an experiment merged with a model file names both
/// files: the bad value may be in either (the model file gives `[structure]`, the experiment
/// may override it).
fn on_model(e: Error, model_file: Option<&Path>) -> Error {
    let Some(m) = model_file else { return e };
    let with = |file: String| format!("{file} (merged with the model file {})", m.display());
    let about_the_model = |s: &str| s.starts_with("structure") || s.starts_with("model");
    let applies = match &e {
        Error::Parse { message, .. } => about_the_model(message),
        e => e.key().is_some_and(about_the_model),
    };
    if applies {
        e.in_file(with)
    } else {
        e
    }
}

/// Loads every experiment of several files (each once per model), each reference file
/// parsed once.
pub fn load_all(paths: &[PathBuf], reference_dir: &Path) -> Result<Vec<Experiment>> {
    let files = Files::new(reference_dir);
    let mut out = Vec::new();
    for p in paths {
        out.extend(load_with(p, &files)?);
    }
    Ok(out)
}

/// The experiment files of a folder (`*.toml` directly inside it), sorted by name.
pub fn discover(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut files = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let path = entry.path();
        if path.is_file() && path.extension().is_some_and(|e| e == "toml") {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}
