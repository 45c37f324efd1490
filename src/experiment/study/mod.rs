//! Study files: an experiment re-run over values the paper leaves unstated (docs/studies.md).
//!
//! A study names an experiment file, the models to run it on, and the keys it varies (lists,
//! ranges, or a quasi-random design over ranges). Each sample is the experiment's merged
//! table with the sample's values set at their key paths, validated like any experiment.

pub mod adaptive;
pub mod design;
mod entries;
mod joint;
pub mod lattice;
pub mod overrides;
pub mod stored;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::file::OverrideError;
use crate::error::{read_to_string, Error, Result};
use crate::reference::files::Files;

use super::file::raw_study::RawFile;
use super::file::read;
use super::loader::Varying;
use super::{CheckKind, Experiment};
pub use design::{Design, Domain, Refine};
use entries::{chosen_models, design_of, map_of, vary_entry};
pub use overrides::KeyPath;

/// Most samples a study may have (the Sobol sequence's limit, and a sane size for one table).
pub const MAX_SAMPLES: usize = 65_536;

/// One varied key.
#[derive(Debug, Clone)]
pub struct Vary {
    /// Column name in the study's table.
    pub name: String,
    /// The key it sets in the experiment file.
    pub key: KeyPath,
    /// Axis label.
    pub label: String,
    /// The values it takes.
    pub domain: Domain,
    /// A joint study's experiments (ids) it is set in; empty: every experiment that has the
    /// key.
    pub experiments: Vec<String>,
}

impl Vary {
    /// Whether its axis is logarithmic.
    pub fn log(&self) -> bool {
        matches!(self.domain, Domain::Range { log: true, .. })
    }
}

/// One point of a study: a model and a value for each varied key.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// 0-based, over the whole study (models outermost).
    pub index: usize,
    /// The model of the structure.
    pub model: String,
    /// One value per varied key, in the order of `vary`.
    pub values: Vec<f64>,
}

/// A validated study.
#[derive(Debug, Clone)]
pub struct Study {
    /// The study file.
    pub path: PathBuf,
    /// Id (names its folder).
    pub id: String,
    /// Title.
    pub title: String,
    /// What it varies and why.
    pub description: Option<String>,
    /// Whether `shotdamp report` runs it (sized for the report's time budget).
    pub report: bool,
    /// Whether `shotdamp report` runs the best samples of its stored answer again
    /// (`reference/studies/ID.json`, [`stored::StoredStudy`]).
    pub stored: bool,
    /// Where the report shows it on the experiment's page.
    pub section: Section,
    /// The experiment file it re-runs.
    pub experiment_path: PathBuf,
    /// The experiment as it stands, once per model studied (for ids, figure, references).
    pub base: Vec<Experiment>,
    /// How the samples are drawn.
    pub design: Design,
    /// The varied keys.
    pub vary: Vec<Vary>,
    /// Values set in every sample (`[study.set]`).
    pub set: Vec<(KeyPath, toml::Value)>,
    /// Indices into `vary` of the heat maps' horizontal and vertical axes.
    pub map: Option<(usize, usize)>,
    /// Every sample, models outermost.
    pub samples: Vec<Sample>,
    /// Merged tables of the experiment, by model id (`""` without models).
    tables: BTreeMap<String, toml::Table>,
    /// Each model's table as the last sample set it, validated (samples vary it without
    /// building its structure again where they leave `[structure]` alone).
    varying: BTreeMap<String, Varying>,
    /// The experiments it takes values from (`"@ID.KEY"`), recursively, at their own values
    /// on every model (for their references).
    pub dependencies: Vec<Experiment>,
    /// Their merged tables, by experiment id and model id, with their files and their tables
    /// as the last sample set them.
    dependency_tables: BTreeMap<(String, String), (PathBuf, toml::Table, Varying)>,
    /// A joint study (`experiments = [...]`, docs/studies.md "Joint studies"): the other
    /// experiments, each a study of its own with the same samples (this one is the first).
    /// Empty for a study of one experiment.
    pub joint: Vec<Study>,
    /// Part of a joint study: a key is set in an experiment only where the experiment has it.
    pub joint_member: bool,
    /// The reference files, each parsed once for the whole study (every sample's experiment
    /// is validated against them).
    files: Arc<Files>,
}

/// Where the report shows a study on its experiment's page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Section {
    /// "Robustness": the claims over values the paper leaves unstated.
    #[default]
    Robustness,
    /// "Does the bed model matter?": the claims over bed models, each compared with the
    /// sample at the first value of every varied key (the paper's bed).
    Bed,
}

/// Whether a check states one of the paper's claims as a number (what a study re-evaluates).
pub fn is_claim(kind: &CheckKind) -> bool {
    matches!(
        kind,
        CheckKind::PeakRatio { .. }
            | CheckKind::RatioOrder { .. }
            | CheckKind::MotionTypes { .. }
            | CheckKind::DecayRatio { .. }
    )
}

/// Loads and validates a study file, with every sample's experiment built once (so that a
/// bad value is reported before anything runs).
pub fn load(path: &Path, reference_dir: &Path) -> Result<Study> {
    let text = read_to_string(path)?;
    let mut table = read::parse_table(path, &text)?;
    table.iter_mut().for_each(|(_, v)| read::whole_floats(v));
    let raw: RawFile = serde_path_to_error::deserialize(table).map_err(|e| {
        let key = e.path().to_string();
        Error::Parse {
            file: path.display().to_string(),
            message: format!("{key}: {}", read::serde_words(e.into_inner().message())),
        }
    })?;
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);
    let files: Vec<(String, String)> = match (&raw.study.experiment, &raw.study.experiments) {
        (Some(e), None) => vec![("study.experiment".into(), e.clone())],
        (None, Some(list)) if !list.is_empty() => {
            list.iter().enumerate().map(|(i, e)| (format!("study.experiments[{i}]"), e.clone())).collect()
        }
        (None, _) => return Err(bad(
            "study.experiment",
            &"(missing)",
            "name the experiment file (`experiment = \"...\"`), or several for a joint study (`experiments = [...]`)",
        )),
        (Some(_), Some(_)) => {
            return Err(bad("study.experiments", &"(given)", "give `experiment` or `experiments`, not both"))
        }
    };
    let joint = raw.study.experiments.is_some();
    let refs = Arc::new(Files::new(reference_dir));
    let mut parts = Vec::with_capacity(files.len());
    for (key, file) in &files {
        parts.push(load_one(path, raw.clone(), key, file, joint, &refs)?);
    }
    let mut study = parts.remove(0);
    if let Some(i) = study.vary.iter().position(|v| !joint && !v.experiments.is_empty()) {
        return Err(bad(
            &format!("vary[{i}].experiments"),
            &"(given)",
            "only a joint study (`experiments = [...]`) names the experiments a key is set in",
        ));
    }
    if joint {
        joint::check(&study, &parts, &files)?;
    }
    study.joint = parts;
    if study.stored && study.joint.is_empty() {
        return Err(bad(
            "study.stored",
            &"true",
            "a stored answer heads the report's bottom line, which a joint study gives (`experiments = [...]`)",
        ));
    }
    if let Design::Adaptive { refine: Refine::Check(k), .. } = study.design {
        let claims: usize = study.parts().map(|p| p.base[0].checks.iter().filter(|c| is_claim(&c.kind)).count()).sum();
        if k >= claims {
            return Err(bad(
                "study.refine",
                &k,
                &format!("the number of a claim in the study's table, 0 to {} (the claims, in file order)", claims - 1),
            ));
        }
    }
    Ok(study)
}

/// The study of one experiment file (`key` names it in the study file): the whole study, or
/// one experiment of a joint one.
fn load_one(path: &Path, raw: RawFile, key: &str, file: &str, joint: bool, files: &Arc<Files>) -> Result<Study> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);
    let s = raw.study;
    if !super::fields::is_identifier(&s.id) {
        return Err(bad("study.id", &format!("\"{}\"", s.id), "use letters, digits, '_' and '-' only"));
    }
    super::fields::id_length(path, "study.id", &s.id)?;
    let experiment_path = path.parent().unwrap_or(Path::new(".")).join(file);
    if !experiment_path.is_file() {
        return Err(bad(
            key,
            &format!("\"{file}\""),
            &format!("no such experiment file: {} (the path is relative to the study file)", experiment_path.display()),
        ));
    }
    let all = super::loader::load_with(&experiment_path, files)?;
    let base = chosen_models(path, all, s.models.as_deref())?;
    if !base[0].checks.iter().any(|c| is_claim(&c.kind)) {
        return Err(bad(
            key,
            &format!("\"{file}\""),
            "the experiment has no claim checks (peak_ratio, ratio_order, motion_types, decay_ratio) to re-evaluate",
        ));
    }

    let mut vary = Vec::new();
    for (i, v) in raw.vary.into_iter().enumerate() {
        vary.push(vary_entry(path, i, v)?);
    }
    for (i, v) in vary.iter().enumerate() {
        if vary[..i].iter().any(|w| w.name == v.name) {
            return Err(bad(&format!("vary[{i}].name"), &format!("\"{}\"", v.name), "each name may be used once"));
        }
    }
    if s.report && s.stored {
        return Err(bad(
            "study.stored",
            &"true",
            "`report = true` runs the whole study with the report; `stored = true` runs the best samples of its stored answer again: give one",
        ));
    }
    let design = design_of(path, &s, &vary)?;
    let mut set = Vec::new();
    for (k, v) in &s.set {
        let key = KeyPath::parse(k).map_err(|m| bad(&format!("study.set.\"{k}\""), &v, &m.to_string()))?;
        set.push((key, v.clone()));
    }
    let map = map_of(path, s.map.as_deref(), &vary)?;

    let domains: Vec<Domain> = vary.iter().map(|v| v.domain.clone()).collect();
    // The size before the samples are made: a grid grows as the product of its keys.
    let per_model = match design {
        Design::Grid => domains.iter().map(|d| d.grid().map_or(0, |g| g.len())).fold(1usize, usize::saturating_mul),
        Design::Sobol { samples, .. } | Design::LatinHypercube { samples, .. } => samples,
        // At most the whole fine grid.
        Design::Adaptive { .. } => {
            domains.iter().map(|d| d.grid().map_or(0, |g| g.len())).fold(1usize, usize::saturating_mul)
        }
    };
    let total = per_model.saturating_mul(base.len());
    if total > MAX_SAMPLES {
        return Err(bad(
            "vary",
            &format!("{total} samples"),
            &format!("a study may have at most {MAX_SAMPLES} samples; split it"),
        ));
    }
    let points = design::points(design, &domains);
    let mut samples = Vec::new();
    for e in &base {
        let model = e.model.as_ref().map(|m| m.id.clone()).unwrap_or_default();
        for p in &points {
            samples.push(Sample { index: samples.len(), model: model.clone(), values: p.clone() });
        }
    }
    let tables: BTreeMap<String, toml::Table> =
        read::read_models(&experiment_path)?.into_iter().map(|(_, t)| (model_of(&t), t)).collect();
    let mut study = Study {
        path: path.to_path_buf(),
        id: s.id,
        title: s.title,
        description: s.description,
        report: s.report,
        stored: s.stored,
        section: match s.section.as_deref() {
            None | Some("robustness") => Section::Robustness,
            Some("bed") => Section::Bed,
            Some(other) => {
                return Err(Error::invalid(
                    path,
                    "study.section",
                    format!("\"{other}\""),
                    "\"robustness\" (the default: values the paper leaves unstated) or \"bed\" (\"Does the bed model matter?\": bed models against the first sample, the paper's bed)",
                ))
            }
        },
        experiment_path,
        base,
        design,
        vary,
        set,
        map,
        samples,
        varying: tables.keys().map(|k| (k.clone(), Varying::default())).collect(),
        tables,
        dependencies: Vec::new(),
        dependency_tables: BTreeMap::new(),
        joint: Vec::new(),
        joint_member: joint,
        files: Arc::clone(files),
    };
    load_dependencies(&mut study)?;
    Ok(study)
}

/// Loads the experiments that the studied experiment takes values from (in its folder),
/// recursively: their tables (to build them at each sample) and themselves (for references).
fn load_dependencies(study: &mut Study) -> Result<()> {
    let mut wanted: Vec<String> = study.base.iter().flat_map(|e| e.dependencies()).collect();
    if wanted.is_empty() {
        return Ok(());
    }
    let dir = study.experiment_path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut files = BTreeMap::new();
    for file in super::loader::discover(&dir)? {
        let t = read::read_merged(&file)?;
        if let Some(id) = t.get("experiment").and_then(|m| m.get("id")).and_then(|v| v.as_str()) {
            files.insert(id.to_string(), file);
        }
    }
    let mut done: Vec<String> = Vec::new();
    while let Some(id) = wanted.pop() {
        if done.contains(&id) {
            continue;
        }
        let Some(file) = files.get(&id) else {
            return Err(Error::invalid(
                &study.experiment_path,
                "(export reference)",
                format!("@{id}"),
                format!("no experiment with id \"{id}\" in {}", dir.display()),
            ));
        };
        for e in super::loader::load_with(file, &study.files)? {
            wanted.extend(e.dependencies());
            study.dependencies.push(e);
        }
        for (_, t) in read::read_models(file)? {
            study.dependency_tables.insert((id.clone(), model_of(&t)), (file.clone(), t, Varying::default()));
        }
        done.push(id);
    }
    Ok(())
}

/// Whether a varied or set key reaches the experiments the studied one depends on: values of
/// the structure and the excitation do; the rest are the studied experiment's own.
fn carries_over(key: &KeyPath) -> bool {
    matches!(key.root(), "structure" | "excitation" | "model")
}

/// The model id of a merged table (`""` without one).
fn model_of(table: &toml::Table) -> String {
    table.get("model").and_then(|m| m.get("id")).and_then(|v| v.as_str()).unwrap_or("").to_string()
}

impl Study {
    /// The experiment at one sample: the model's merged table with `[study.set]` and the
    /// sample's values set, validated.
    pub fn experiment(&self, sample: &Sample) -> Result<Experiment> {
        let (Some(table), Some(varying)) = (self.tables.get(&sample.model), self.varying.get(&sample.model)) else {
            return Err(Error::invalid(&self.path, "study.models", &sample.model, "not a model of the experiment"));
        };
        self.build(&self.experiment_path, table.clone(), varying, sample, |_| true)
    }

    /// Experiment `id` (a dependency) at one sample: only values under `structure` and
    /// `excitation` carry over (the other keys are the studied experiment's own).
    pub fn dependency(&self, id: &str, sample: &Sample) -> Result<Experiment> {
        let (file, table, varying) =
            self.dependency_tables.get(&(id.to_string(), sample.model.clone())).ok_or_else(|| {
                Error::invalid(
                    &self.experiment_path,
                    "(export reference)",
                    format!("@{id}"),
                    format!("experiment \"{id}\" does not run on model \"{}\"", sample.model),
                )
            })?;
        self.build(file, table.clone(), varying, sample, carries_over)
    }

    /// The values of the sample that reach its dependencies (those of `carries_over` keys).
    pub fn dependency_values(&self, sample: &Sample) -> Vec<f64> {
        self.vary.iter().zip(&sample.values).filter(|(v, _)| carries_over(&v.key)).map(|(_, x)| *x).collect()
    }

    fn build(
        &self,
        file: &Path,
        mut table: toml::Table,
        varying: &Varying,
        sample: &Sample,
        applies: impl Fn(&KeyPath) -> bool,
    ) -> Result<Experiment> {
        let on = |key: String, value: &dyn std::fmt::Display, m: OverrideError| {
            Error::refused_in(&self.path, key, value, format!("cannot be set in {}: ", file.display()), m, "")
        };
        // In a joint study a key reaches the experiments that have it (docs/studies.md).
        let here = |k: &KeyPath, t: &toml::Table| !self.joint_member || !k.get(t).is_empty();
        for (i, (k, v)) in self.set.iter().enumerate() {
            if applies(k) && here(k, &table) {
                k.set(&mut table, v).map_err(|m| on(format!("study.set.\"{}\" (entry {i})", k.as_str()), v, m))?;
            }
        }
        for (i, (v, x)) in self.vary.iter().zip(&sample.values).enumerate() {
            let scoped = v.experiments.is_empty() || v.experiments.contains(&self.base[0].meta.id);
            if applies(&v.key) && here(&v.key, &table) && scoped {
                let value = toml::Value::Float(*x);
                v.key
                    .set(&mut table, &value)
                    .map_err(|m| on(format!("vary[{i}].key (\"{}\")", v.key.as_str()), x, m))?;
            }
        }
        let mut exp = varying.validate(file, table, &self.files).map_err(|e| self.at_sample(e, sample))?;
        exp.models = self.base.iter().filter_map(|e| e.model.clone()).collect();
        Ok(exp)
    }

    /// An error of a sample's experiment, with the sample's values.
    pub fn at_sample(&self, e: Error, sample: &Sample) -> Error {
        let values = self.describe(sample);
        e.in_file(|file| format!("{} (sample {} of study {}: {values})", file, sample.index, self.path.display()))
    }

    /// What the study computes from, as text: the merged tables of its experiment on every
    /// model and of the experiments it takes values from (for the fingerprint of its folder;
    /// independent of how any path is spelled).
    pub fn content(&self) -> String {
        let mut text = String::new();
        for (model, table) in &self.tables {
            text.push_str(&format!("[experiment on {model}]\n{}\n", toml::to_string(table).unwrap_or_default()));
        }
        for ((id, model), (_, table, _)) in &self.dependency_tables {
            text.push_str(&format!("[dependency {id} on {model}]\n{}\n", toml::to_string(table).unwrap_or_default()));
        }
        for part in &self.joint {
            text.push_str(&format!("[joint {}]\n{}", part.base[0].meta.id, part.content()));
        }
        text
    }

    /// This study and the other experiments of a joint study, in the file's order: every
    /// sample runs each.
    pub fn parts(&self) -> impl Iterator<Item = &Study> {
        std::iter::once(self).chain(&self.joint)
    }

    /// The sample's model and values in words, e.g. `model stated, damping 0.005`.
    pub fn describe(&self, sample: &Sample) -> String {
        let mut parts = Vec::new();
        if !sample.model.is_empty() {
            parts.push(format!("model {}", sample.model));
        }
        for (v, x) in self.vary.iter().zip(&sample.values) {
            parts.push(format!("{} {}", v.name, crate::number::fmt_num(*x)));
        }
        parts.join(", ")
    }

    /// The experiment's own value of each varied key on `model`, as the report runs it (before
    /// `[study.set]`): `None` where the key has no single value (elements that differ) or takes
    /// it from an experiment missing from `exports`.
    pub fn assumed(&self, model: &str, exports: &super::Exports) -> Vec<Option<f64>> {
        let Some(table) = self.tables.get(model) else { return vec![None; self.vary.len()] };
        let base = self.base.iter().find(|e| e.model.as_ref().map_or("", |m| m.id.as_str()) == model);
        let number = |v: &toml::Value| -> Option<f64> {
            match v {
                toml::Value::Float(x) => Some(*x),
                toml::Value::Integer(i) => Some(*i as f64),
                toml::Value::String(s) => {
                    let r = super::analysis::export_ref(s)?;
                    let run = base.map_or_else(|| r.experiment.clone(), |e| e.key_of(&r.experiment));
                    exports.get(&run)?.get(&r.key).copied()
                }
                _ => None,
            }
        };
        self.vary
            .iter()
            .map(|v| {
                let values: Option<Vec<f64>> = v.key.get(table).into_iter().map(number).collect();
                let values = values?;
                let first = *values.first()?;
                values.iter().all(|x| *x == first).then_some(first)
            })
            .collect()
    }

    /// The model ids studied, in order (`""` when the experiment has none).
    pub fn models(&self) -> Vec<String> {
        self.base.iter().map(|e| e.model.as_ref().map(|m| m.id.clone()).unwrap_or_default()).collect()
    }
}
