//! The reference data an experiment's checks need, loaded once: value files and digitised
//! curves (formats in [`crate::reference`]) and reference curves (CSV). A reference is data +
//! tolerance (given by the check) + provenance.

use std::path::Path;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::reference::digitised::{self, DigitisedFile};
use crate::reference::files::Loaded;
use crate::reference::values::ValueFile;

/// A reference curve file (CSV): every numeric column as f64, by name.
#[derive(Debug, Clone)]
pub struct Curve {
    /// The file's path below the reference folder.
    pub path: String,
    /// Every numeric column, by name.
    pub columns: std::collections::BTreeMap<String, Vec<f64>>,
}

/// Text columns a reference curve may have (event kinds, bed states); every other column is
/// numbers.
fn is_text_column(name: &str) -> bool {
    name == "kind" || name.strip_prefix("state").is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
}

impl Curve {
    /// Reads a CSV reference with a header and validates it as strictly as the experiment
    /// files: every value of every column but the text ones (`kind`, `stateN`) is a finite
    /// number; `freq_hz` strictly increases (no duplicate rows); `t` never decreases;
    /// `converged` is 0 or 1; `period` is a whole number, 0 only where `converged` is 0. An
    /// error names the file, the line, the column and the value.
    pub fn load(path: &Path) -> Result<Curve> {
        use polars::prelude::*;
        let err = |m: String| Error::Table { path: path.to_path_buf(), message: m };
        let bad = |line: usize, name: &str, value: String, what: &str| {
            Error::invalid(path, format!("line {line}, column {name}"), value, what.to_string())
        };
        let df = crate::table::read_csv(path)?;
        if df.height() == 0 {
            return Err(err("no rows: a reference curve needs at least one".into()));
        }
        let mut columns = std::collections::BTreeMap::new();
        for col in df.columns() {
            let name = col.name().to_string();
            if is_text_column(&name) {
                continue;
            }
            if !col.dtype().is_primitive_numeric() {
                // Name the first cell that is not a number.
                let text = col.cast(&DataType::String).map_err(|e| err(format!("column \"{name}\": {e}")))?;
                let cells = text.str().map_err(|e| err(format!("column \"{name}\": {e}")))?;
                for (k, cell) in cells.iter().enumerate() {
                    let cell = cell.unwrap_or("");
                    if cell.trim().parse::<f64>().map_or(true, |v| !v.is_finite()) {
                        return Err(bad(k + 2, &name, format!("\"{cell}\""), "a finite number"));
                    }
                }
                return Err(err(format!("column \"{name}\" is not numeric")));
            }
            let cast = col.cast(&DataType::Float64).map_err(|e| err(format!("column \"{name}\": {e}")))?;
            let mut values = Vec::with_capacity(df.height());
            for (k, v) in cast.f64().map_err(|e| err(format!("column \"{name}\": {e}")))?.iter().enumerate() {
                match v {
                    Some(v) if v.is_finite() => values.push(v),
                    Some(v) => return Err(bad(k + 2, &name, v.to_string(), "a finite number")),
                    None => return Err(bad(k + 2, &name, "(empty)".to_string(), "a finite number")),
                }
            }
            columns.insert(name, values);
        }
        let curve = Curve { path: path.display().to_string(), columns };
        curve.validate(path)?;
        Ok(curve)
    }

    /// The rules of the named columns.
    fn validate(&self, path: &Path) -> Result<()> {
        let bad = |line: usize, name: &str, value: f64, what: &str| {
            Err(Error::invalid(path, format!("line {line}, column {name}"), value, what.to_string()))
        };
        if let Some(f) = self.column("freq_hz") {
            if let Some(k) = (1..f.len()).find(|&k| f[k] <= f[k - 1]) {
                return bad(
                    k + 2,
                    "freq_hz",
                    f[k],
                    &format!("frequencies increase strictly (the line before has {})", f[k - 1]),
                );
            }
        }
        if let Some(t) = self.column("t") {
            if let Some(k) = (1..t.len()).find(|&k| t[k] < t[k - 1]) {
                return bad(k + 2, "t", t[k], &format!("times never decrease (the line before has {})", t[k - 1]));
            }
        }
        let conv = self.column("converged");
        if let Some(c) = conv {
            if let Some(k) = c.iter().position(|&v| v != 0.0 && v != 1.0) {
                return bad(k + 2, "converged", c[k], "0 or 1");
            }
        }
        if let Some(p) = self.column("period") {
            for (k, &v) in p.iter().enumerate() {
                let settled = conv.is_none_or(|c| c[k] == 1.0);
                if v < 0.0 || v.fract() != 0.0 || (v == 0.0 && settled) {
                    return bad(k + 2, "period", v, "a whole number of forcing periods, 0 only where converged is 0");
                }
            }
        }
        Ok(())
    }

    /// Fails unless every column in `names` is there, saying which check needs them.
    pub fn require(&self, names: &[String], who: &str) -> Result<()> {
        let missing: Vec<&String> = names.iter().filter(|n| self.column(n).is_none()).collect();
        if missing.is_empty() {
            return Ok(());
        }
        let have: Vec<&String> = self.columns.keys().collect();
        Err(Error::invalid(&self.path, "columns", format!("{have:?}"), format!("{who} needs the columns {missing:?}")))
    }

    /// A column by name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns.get(name).map(Vec::as_slice)
    }
}

/// The columns of a reference curve a check reads.
fn needed_columns(kind: &crate::experiment::CheckKind, n: usize) -> Vec<String> {
    use crate::experiment::CheckKind;
    match kind {
        CheckKind::Curve { columns, .. } => {
            std::iter::once("freq_hz".to_string()).chain((1..=n).map(|m| format!("{columns}c{m}"))).collect()
        }
        CheckKind::ImpulseHistory { .. } => std::iter::once("t".to_string())
            .chain(["x", "v", "a"].iter().flat_map(|q| (1..=n).map(move |m| format!("{q}{m}"))))
            .collect(),
        CheckKind::DecayTime { mass, .. } => vec!["t".to_string(), format!("a{}", mass + 1)],
        _ => Vec::new(),
    }
}

/// Whether runs are compared with the blessed baseline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BaselineMode {
    /// Not compared (while blessing a new one).
    #[default]
    Off,
    /// Compared where a baseline exists.
    Optional,
    /// Compared; a missing baseline fails.
    Required,
}

/// Where the stored answer of study `id` lives under the reference folder `dir`.
pub fn stored_study_path(dir: &Path, id: &str) -> std::path::PathBuf {
    dir.join("studies").join(format!("{id}.json"))
}

/// Where the stored answer of the design experiment `key` (`ID/MODEL`) lives under the
/// reference folder `dir`.
pub fn stored_design_path(dir: &Path, key: &str) -> std::path::PathBuf {
    dir.join("designs").join(format!("{key}.json"))
}

/// Reference files loaded once, before any experiment runs (no I/O during analysis).
#[derive(Debug, Clone, Default)]
pub struct ReferenceStore {
    values: std::collections::BTreeMap<String, Arc<ValueFile>>,
    curves: std::collections::BTreeMap<String, Curve>,
    digitised: std::collections::BTreeMap<String, Arc<DigitisedFile>>,
    baselines: std::collections::BTreeMap<String, Vec<super::baseline::Value>>,
    /// Whether experiments are compared with their blessed baselines.
    pub baseline_mode: BaselineMode,
    /// Stored answers of design searches, by experiment key (`dir/designs/ID/MODEL.json`).
    designs: std::collections::BTreeMap<String, crate::design::stored::StoredDesign>,
}

impl ReferenceStore {
    /// Every reference file the experiments' checks name: the value files and digitised files
    /// validation parsed (kept by the checks, [`Loaded`]), the CSV curves read from `dir`
    /// once each (and any file a check built in code names without its parse).
    pub fn load(dir: &Path, experiments: &[crate::experiment::Experiment]) -> Result<ReferenceStore> {
        let mut store = ReferenceStore::default();
        for exp in experiments {
            for check in &exp.checks {
                let file = &check.reference_file;
                match &check.loaded {
                    Some(Loaded::Values(v)) => {
                        store.values.entry(file.clone()).or_insert_with(|| Arc::clone(v));
                    }
                    Some(Loaded::Digitised(d)) => {
                        store.digitised.entry(file.clone()).or_insert_with(|| Arc::clone(d));
                    }
                    None => {}
                }
                if matches!(
                    check.kind,
                    crate::experiment::CheckKind::Tube { .. } | crate::experiment::CheckKind::Peak { .. }
                ) {
                    if !store.digitised.contains_key(file) {
                        store.digitised.insert(file.clone(), Arc::new(digitised::load(&dir.join(file))?));
                    }
                    continue;
                }
                if file.ends_with(".toml") && !store.values.contains_key(file) {
                    store.values.insert(file.clone(), Arc::new(ValueFile::load(&dir.join(file))?));
                }
                if file.ends_with(".csv") && !store.curves.contains_key(file) {
                    store.curves.insert(file.clone(), Curve::load(&dir.join(file))?);
                }
                if let Some(curve) = store.curves.get(file) {
                    let who = format!("the check of {} against it", exp.path.display());
                    curve.require(&needed_columns(&check.kind, exp.structure.dof()), &who)?;
                }
            }
        }
        Ok(store)
    }

    /// Loads the blessed baseline of each experiment that has one (`dir/baseline/ID.csv`).
    pub fn load_baselines(
        &mut self,
        dir: &Path,
        experiments: &[crate::experiment::Experiment],
        mode: BaselineMode,
    ) -> Result<()> {
        self.baseline_mode = mode;
        if mode == BaselineMode::Off {
            return Ok(());
        }
        for exp in experiments {
            let key = exp.key();
            let path = dir.join("baseline").join(format!("{key}.csv"));
            if path.is_file() {
                self.baselines.insert(key, super::baseline::load(&path)?);
            }
        }
        Ok(())
    }

    /// Loads the stored answer of each design experiment that has one
    /// (`dir/designs/KEY.json`, KEY = `ID/MODEL`); a file that cannot be read is an error.
    pub fn load_designs(&mut self, dir: &Path, experiments: &[crate::experiment::Experiment]) -> Result<()> {
        for exp in experiments.iter().filter(|e| e.analysis.answers()) {
            let key = exp.key();
            let path = stored_design_path(dir, &key);
            if !path.is_file() {
                continue;
            }
            let text = std::fs::read_to_string(&path).map_err(|e| crate::Error::io(&path, e))?;
            let stored: crate::design::stored::StoredDesign = serde_json::from_str(&text).map_err(|e| {
                crate::Error::invalid(
                    &path,
                    "(file)",
                    format!("{e}"),
                    "a stored design written by `shotdamp design --store`",
                )
            })?;
            self.designs.insert(key, stored);
        }
        Ok(())
    }

    /// The stored answer of a design experiment.
    pub fn design(&self, key: &str) -> Option<&crate::design::stored::StoredDesign> {
        self.designs.get(key)
    }

    /// The blessed baseline of an experiment.
    pub fn baseline(&self, id: &str) -> Option<&[super::baseline::Value]> {
        self.baselines.get(id).map(Vec::as_slice)
    }

    /// A loaded value file.
    pub fn values(&self, file: &str) -> Option<&ValueFile> {
        self.values.get(file).map(Arc::as_ref)
    }

    /// A loaded digitised file.
    pub fn digitised(&self, file: &str) -> Option<&DigitisedFile> {
        self.digitised.get(file).map(Arc::as_ref)
    }

    /// A loaded curve file.
    pub fn curve(&self, file: &str) -> Option<&Curve> {
        self.curves.get(file)
    }

    /// Adds a value file (for tests and tools).
    pub fn insert_values(&mut self, file: impl Into<String>, values: ValueFile) {
        self.values.insert(file.into(), Arc::new(values));
    }
}
