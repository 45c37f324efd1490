//! Experiment files: one TOML file per paper figure, loaded in two stages
//! (raw serde structs, then validated typed values).

mod load;
pub mod raw;
mod validate;

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::model::{Damper, Structure};

pub use load::{parse_table, read_merged};
pub use validate::validate;

/// Titles and texts that describe an experiment.
#[derive(Debug, Clone)]
pub struct Meta {
    pub id: String,
    pub title: String,
    pub figure: String,
    pub caption: String,
    pub claim: String,
    pub assumptions: Vec<String>,
    pub notes: Vec<String>,
}

/// The force `F sin(omega t)` on one mass.
#[derive(Debug, Clone, Copy)]
pub struct Excitation {
    /// 0-based driven mass.
    pub mass: usize,
    /// Amplitude, N.
    pub force: f64,
}

/// One curve family of a figure: a set of dampers.
#[derive(Debug, Clone)]
pub struct Case {
    pub id: String,
    pub label: String,
    pub dampers: Vec<Damper>,
}

/// What to compute.
#[derive(Debug, Clone)]
pub enum Analysis {
    /// Modal analysis only.
    Modal,
    /// Exact linear compliance of the bare structure and of each case with its damper
    /// masses rigidly added, on a grid in Hz.
    LinearFrf { freq_hz: Vec<f64> },
}

impl Analysis {
    /// The name used in files.
    pub fn kind(&self) -> &'static str {
        match self {
            Analysis::Modal => "modal",
            Analysis::LinearFrf { .. } => "linear_frf",
        }
    }
}

/// Vertical axis scale of a plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

/// A plot to draw.
#[derive(Debug, Clone)]
pub struct PlotSpec {
    pub id: String,
    pub kind: PlotKind,
    pub title: Option<String>,
    /// 0-based masses.
    pub masses: Vec<usize>,
    /// Case ids (all when the file gives none).
    pub cases: Vec<String>,
    pub y_scale: Scale,
    pub mark_natural_frequencies: bool,
}

/// The kinds of plot an experiment can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotKind {
    /// Compliance against frequency.
    Compliance,
}

/// The kinds of check an experiment can ask for.
#[derive(Debug, Clone, PartialEq)]
pub enum CheckKind {
    /// A natural frequency (rad/s) of the bare structure against a reference value.
    NaturalFrequency { mode: usize },
    /// Each element of a normalised mode shape against a reference vector.
    ModeShape { mode: usize },
    /// The structure's masses, stiffnesses and the force against the paper's values.
    PaperParameters,
}

/// A tolerance: pass when `|computed - expected| <= abs + rel |expected|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    pub rel: f64,
    pub abs: f64,
}

/// A check to make against a reference.
#[derive(Debug, Clone)]
pub struct CheckSpec {
    pub kind: CheckKind,
    /// File under `reference/` and, for values, the id after `#`.
    pub reference_file: String,
    pub reference_id: Option<String>,
    pub tolerance: Tolerance,
    pub known_deviation: Option<String>,
}

/// A validated experiment.
#[derive(Debug, Clone)]
pub struct Experiment {
    /// The file it came from.
    pub path: PathBuf,
    pub meta: Meta,
    pub structure: Structure,
    /// Where the structure's numbers come from.
    pub structure_source: Option<String>,
    /// Why the damping has the values it has.
    pub damping_assumption: Option<String>,
    pub excitation: Excitation,
    pub analysis: Analysis,
    pub cases: Vec<Case>,
    pub plots: Vec<PlotSpec>,
    pub checks: Vec<CheckSpec>,
}

/// Loads and validates one experiment file; references are looked up in `reference_dir`.
pub fn load(path: &Path, reference_dir: &Path) -> Result<Experiment> {
    let raw = load::read_raw(path)?;
    validate(path, raw, reference_dir)
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
