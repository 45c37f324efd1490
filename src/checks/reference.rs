//! Reference data: values stated in the paper's text, and curves from other sources.
//! A reference is data + tolerance (given by the check) + provenance.

use std::path::Path;

use serde::Deserialize;

use crate::error::{read_to_string, Error, Result};

/// A file of reference values, such as `reference/paper-text.toml`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValueFile {
    pub meta: ValueFileMeta,
    #[serde(rename = "quantity")]
    pub quantities: Vec<Quantity>,
}

/// Where a value file's numbers come from.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValueFileMeta {
    /// Kind of source: "paper text", "digitised figure", "independent solver".
    pub provenance: String,
    /// The document the numbers come from.
    pub source: String,
}

/// One stated quantity, scalar or vector.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    pub id: String,
    #[serde(default)]
    pub value: Option<f64>,
    #[serde(default)]
    pub values: Option<Vec<f64>>,
    pub unit: String,
    /// Section of the source that states it.
    pub section: String,
    /// The source's words.
    pub quote: String,
    #[serde(default)]
    pub note: Option<String>,
}

impl ValueFile {
    /// The quantity a check names with `FILE#ID`.
    pub fn for_check(&self, spec: &crate::experiment::CheckSpec) -> Option<&Quantity> {
        spec.reference_id.as_deref().and_then(|id| self.get(id))
    }

    /// Reads and parses a value file.
    pub fn load(path: &Path) -> Result<ValueFile> {
        let text = read_to_string(path)?;
        toml::from_str(&text).map_err(|e| Error::Parse {
            file: path.display().to_string(),
            message: e.to_string().trim_end().to_string(),
        })
    }

    /// The quantity with this id.
    pub fn get(&self, id: &str) -> Option<&Quantity> {
        self.quantities.iter().find(|q| q.id == id)
    }

    /// A human-readable provenance line for a quantity.
    pub fn provenance(&self, q: &Quantity) -> String {
        format!("{}: {}, section {} (\"{}\")", self.meta.provenance, self.meta.source, q.section, q.quote)
    }
}

/// A reference curve file (CSV): every numeric column as f64, by name.
#[derive(Debug, Clone)]
pub struct Curve {
    pub path: String,
    pub columns: std::collections::BTreeMap<String, Vec<f64>>,
}

impl Curve {
    /// Reads a CSV file with a header; numeric columns are kept, text columns dropped.
    pub fn load(path: &Path) -> Result<Curve> {
        use polars::prelude::*;
        let err = |m: String| Error::Table { path: path.to_path_buf(), message: m };
        let df = crate::output::table::read_csv(path)?;
        let mut columns = std::collections::BTreeMap::new();
        for col in df.columns() {
            if !col.dtype().is_primitive_numeric() {
                continue;
            }
            let name = col.name().to_string();
            let cast = col.cast(&DataType::Float64).map_err(|e| err(format!("column \"{name}\": {e}")))?;
            let values = cast
                .f64()
                .map_err(|e| err(format!("column \"{name}\": {e}")))?
                .iter()
                .map(|v| v.ok_or_else(|| err(format!("column \"{name}\" has an empty value"))))
                .collect::<Result<Vec<f64>>>()?;
            columns.insert(name, values);
        }
        Ok(Curve { path: path.display().to_string(), columns })
    }

    /// A column by name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns.get(name).map(Vec::as_slice)
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

/// Reference files loaded once, before any experiment runs (no I/O during analysis).
#[derive(Debug, Clone, Default)]
pub struct ReferenceStore {
    values: std::collections::BTreeMap<String, ValueFile>,
    curves: std::collections::BTreeMap<String, Curve>,
    digitised: std::collections::BTreeMap<String, super::digitised::DigitisedFile>,
    baselines: std::collections::BTreeMap<String, Vec<super::baseline::Value>>,
    pub baseline_mode: BaselineMode,
}

impl ReferenceStore {
    /// Loads every value file the experiments' checks name, from `dir`.
    pub fn load(dir: &Path, experiments: &[crate::experiment::Experiment]) -> Result<ReferenceStore> {
        let mut store = ReferenceStore::default();
        for exp in experiments {
            for check in &exp.checks {
                let file = &check.reference_file;
                if matches!(
                    check.kind,
                    crate::experiment::CheckKind::Tube { .. } | crate::experiment::CheckKind::Peak { .. }
                ) {
                    if !store.digitised.contains_key(file) {
                        store.digitised.insert(file.clone(), super::digitised::load(&dir.join(file))?);
                    }
                    continue;
                }
                if file.ends_with(".toml") && !store.values.contains_key(file) {
                    store.values.insert(file.clone(), ValueFile::load(&dir.join(file))?);
                }
                if file.ends_with(".csv") && !store.curves.contains_key(file) {
                    store.curves.insert(file.clone(), Curve::load(&dir.join(file))?);
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
            let path = dir.join("baseline").join(format!("{}.csv", exp.meta.id));
            if path.is_file() {
                self.baselines.insert(exp.meta.id.clone(), super::baseline::load(&path)?);
            }
        }
        Ok(())
    }

    /// The blessed baseline of an experiment.
    pub fn baseline(&self, id: &str) -> Option<&[super::baseline::Value]> {
        self.baselines.get(id).map(Vec::as_slice)
    }

    /// A loaded value file.
    pub fn values(&self, file: &str) -> Option<&ValueFile> {
        self.values.get(file)
    }

    /// A loaded digitised file.
    pub fn digitised(&self, file: &str) -> Option<&super::digitised::DigitisedFile> {
        self.digitised.get(file)
    }

    /// A loaded curve file.
    pub fn curve(&self, file: &str) -> Option<&Curve> {
        self.curves.get(file)
    }

    /// Adds a value file (for tests and tools).
    pub fn insert_values(&mut self, file: impl Into<String>, values: ValueFile) {
        self.values.insert(file.into(), values);
    }
}
