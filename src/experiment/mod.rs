//! Experiment files: one TOML file per paper figure, loaded in two stages
//! (raw serde structs, then validated typed values).

mod analysis;
mod checks;
pub mod curve_id;
mod dampers;
mod design;
mod excitation;
pub mod fe;
mod fields;
pub mod file;
pub mod ground;
mod kind;
pub mod loader;
mod needed;
pub use fe::matrix_market;
mod outputs;
pub mod parts;
mod structure;
pub mod study;
pub mod texts;
mod validate;

use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::model::fit::StiffnessFit;
use crate::model::{Damper, Structure};
use crate::number::Tolerance;
use crate::reference::values::{Quantity, ValueFile};

pub use analysis::round_hz;
pub use curve_id::CurveId;
pub use excitation::{Excitation, MAX_FORCE_G};
pub use file::read::{parse_table, read_merged, read_models};
pub use kind::Analysis;
pub use needed::missing_dependencies;
pub use structure::Kept;
pub use validate::validate;

/// Titles and texts that describe an experiment.
#[derive(Debug, Clone)]
pub struct Meta {
    /// The experiment's id (names its report folder).
    pub id: String,
    /// Title.
    pub title: String,
    /// The paper figure it reproduces, e.g. "Fig. 5".
    pub figure: String,
    /// The paper's caption.
    pub caption: String,
    /// The paper's claim the experiment tests.
    pub claim: String,
    /// Assumptions in words, on top of those derived from the settings.
    pub assumptions: Vec<String>,
    /// Free text shown under the figure.
    pub notes: Vec<String>,
    /// The main deviation from the paper and its likely cause, in a sentence.
    pub deviation: Option<String>,
}

impl Meta {
    /// Whether the experiment reproduces something of the paper: its `figure` names one of
    /// the paper's figures, tables or its conclusion ("Fig. 5", "Table 1", "Conclusion
    /// (3rd mode)"). Anything else ("Example", "Not in the paper": an engineer's own
    /// structure) gets pages headed by its own caption and question, not the paper's.
    pub fn from_paper(&self) -> bool {
        ["Fig.", "Table", "Conclusion"].iter().any(|p| self.figure.starts_with(p))
    }

    /// The page headings of the caption and the claim: the paper's, or the experiment's own
    /// (a design of a structure that is not the paper's asks a design question).
    pub fn headings(&self, design: bool) -> (&'static str, &'static str) {
        match (self.from_paper(), design) {
            (true, _) => ("Paper's caption", "Paper's claim"),
            (false, true) => ("Caption", "Design question"),
            (false, false) => ("Caption", "Question"),
        }
    }
}

/// The structural model an experiment runs on, when its file lists several
/// (`models = [...]`, docs/experiment-format.md).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelInfo {
    /// The model's id, e.g. "stated".
    pub id: String,
    /// Its label.
    pub label: String,
    /// What it is, in words.
    pub description: String,
}

/// A value another experiment exports: `"@EXPERIMENT.KEY"` in a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExportRef {
    /// The experiment's id.
    pub experiment: String,
    /// The name of its exported value.
    pub key: String,
}

impl std::fmt::Display for ExportRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "@{}.{}", self.experiment, self.key)
    }
}

/// A number given in the file or exported by another experiment.
#[derive(Debug, Clone, PartialEq)]
pub enum Number {
    /// A number.
    Value(f64),
    /// A value another experiment exports.
    Export(ExportRef),
}

/// How a damper's clearance is given.
#[derive(Debug, Clone, PartialEq)]
pub enum ClearanceSource {
    /// A number (or no top).
    Fixed,
    /// Scanned by a clearance study.
    Scan,
    /// Exported by another experiment, in mm.
    Export(ExportRef),
}

/// One container of a case (an entry of `[[cases]].dampers`): the damper, how its clearance
/// is given, its bed's impact law and its grains.
#[derive(Debug, Clone)]
pub struct Bed {
    /// Host, shot mass, clearance and direction; a clearance that is scanned or exported is
    /// infinite until resolved.
    pub damper: Damper,
    /// How the clearance is given.
    pub clearance: ClearanceSource,
    /// The bed's impact law (plastic unless the file gives a restitution).
    pub law: crate::sim::motion::bed::ImpactLaw,
    /// Its number of grains: 1 for one mass, more for a column (docs/model.md, "Bed models").
    pub grains: usize,
}

/// One curve family of a figure: a set of dampers.
#[derive(Debug, Clone)]
pub struct Case {
    /// The case's id (unique in the experiment).
    pub id: String,
    /// Legend label.
    pub label: String,
    /// The containers, one row each.
    pub beds: Vec<Bed>,
}

impl Case {
    /// The structure without dampers, as a case (id `bare`), for the linear curves drawn under
    /// a figure whose experiment has no such case.
    pub fn bare() -> Case {
        Case { id: "bare".into(), label: "no damper".into(), beds: Vec::new() }
    }

    /// The dampers, in order.
    pub fn dampers(&self) -> Vec<Damper> {
        self.beds.iter().map(|b| b.damper).collect()
    }

    /// Each bed's impact law, in order.
    pub fn laws(&self) -> Vec<crate::sim::motion::bed::ImpactLaw> {
        self.beds.iter().map(|b| b.law).collect()
    }

    /// Each bed's number of grains, in order.
    pub fn grains(&self) -> Vec<usize> {
        self.beds.iter().map(|b| b.grains).collect()
    }

    /// Whether the case has no container (the bare structure).
    pub fn is_bare(&self) -> bool {
        self.beds.is_empty()
    }
}

/// How the points of a sweep start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// Every point from rest, independently (in parallel).
    Rest,
    /// From rest at the ends, then each point from the previous one, upward and downward.
    Continuation,
}

/// Vertical axis scale of a plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// A linear axis.
    Linear,
    /// A logarithmic axis.
    Log,
}

/// A plot to draw.
#[derive(Debug, Clone)]
pub struct PlotSpec {
    /// File stem of the plot.
    pub id: String,
    /// What is drawn.
    pub kind: PlotKind,
    /// Title (default: from the experiment).
    pub title: Option<String>,
    /// 0-based masses.
    pub masses: Vec<usize>,
    /// Case ids (all when the file gives none).
    pub cases: Vec<String>,
    /// Vertical axis scale.
    pub y_scale: Scale,
    /// Mark the natural frequencies of the bare structure.
    pub mark_natural_frequencies: bool,
    /// Marked frequencies: label and offset from the resonance peak of `marks_relative_to`.
    pub marks: Vec<(String, f64)>,
    /// The case whose resonance peak the marks are relative to.
    pub marks_relative_to: Option<String>,
    /// Linear curves drawn beside.
    pub linear: Vec<Linear>,
    /// The horizontal range drawn (`None`: the analysis's).
    pub x_range: Option<(f64, f64)>,
}

/// A linear reference curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Linear {
    /// The structure without dampers.
    Bare,
    /// The damper masses rigidly added (per case).
    Stuck,
}

/// The kinds of plot an experiment can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotKind {
    /// Compliance against frequency, all masses in one panel.
    Compliance,
    /// Compliance against frequency, one panel per mass.
    CompliancePanels,
    /// Peak compliance against clearance.
    ClearanceScan,
    /// Time histories of masses and beds against forcing phase.
    Waveform,
    /// Impulse response: acceleration of each mass against time, with its envelope.
    Acceleration,
    /// Impulse response: envelopes (log) with the decay levels, and the energy remaining.
    Decay,
    /// Impulse response: magnitude of the spectrum of each mass's acceleration.
    Spectrum,
    /// Impulse response: equivalent damping ratio of each mode against its amplitude.
    Damping,
    /// Periodic orbits: compliance of SDOF and exact branches with the simulation, and the
    /// phases of the SDOF solution below (the paper's right-hand axis).
    Orbits,
    /// Periodic orbits: peak compliance of the SDOF branch against the candidate clearances.
    ClearanceChoice,
    /// Time history: the roof's (the top coordinate's) displacement relative to the ground and
    /// absolute acceleration against time, per record.
    GroundHistories,
    /// Time history: each storey's peak drift and floor acceleration, per record and over the
    /// suite.
    StoreyProfiles,
}

/// The kinds of check an experiment can ask for.
#[derive(Debug, Clone, PartialEq)]
pub enum CheckKind {
    /// A natural frequency (rad/s) of the bare structure against a reference value.
    NaturalFrequency {
        /// 0-based mode.
        mode: usize,
    },
    /// Each element of a normalised mode shape against a reference vector.
    /// `elements` (0-based masses) limits the check to some of them, so that a known
    /// deviation can name exactly the elements it is about.
    ModeShape {
        /// 0-based mode.
        mode: usize,
        /// 0-based masses compared.
        elements: Vec<usize>,
    },
    /// The structure's masses, stiffnesses and the force against the paper's values.
    PaperParameters,
    /// A case's compliance curves against a reference curve file, at the reference's own
    /// frequencies: `rel_tol` at `fraction` of the comparable points, `rel_tol_all` at all.
    /// `curve` names the computed curve: the case's own, a continuation sweep's or a scanned
    /// clearance's.
    Curve {
        /// The computed curve.
        curve: CurveId,
        /// Prefix of the reference file's compliance columns (`PREFIXc1`, ...; empty: none).
        columns: String,
        /// Share of points that must lie within `rel_tol`.
        fraction: f64,
        /// Tolerance at every point.
        rel_tol_all: f64,
    },
    /// The ratio of two cases' peak compliances of a mass (within a frequency window, or over
    /// the whole curve) against a bound from a reference: within a range (`reference` is the
    /// lower bound, `range_to` the id of the upper one), at most or at least a value.
    PeakRatio {
        /// The case in the numerator.
        case: String,
        /// The case in the denominator.
        over_case: String,
        /// 0-based mass.
        mass: usize,
        /// How the ratio is bounded.
        bound: Bound,
        /// Frequency window, Hz (None: the whole curve).
        window: Option<(f64, f64)>,
        /// How "around resonance" is read.
        reading: Reading,
    },
    /// A computed curve against a digitised one: every digitised point within `x_px` pixels
    /// along x and `y_px` pixels (plus the check's tolerance) along y of the computed curve.
    Tube {
        /// The case.
        case: String,
        /// 0-based mass.
        mass: usize,
        /// The digitised curve's name.
        curve: String,
        /// Tolerance along x, pixels.
        x_px: f64,
        /// Tolerance along y, pixels.
        y_px: f64,
    },
    /// The resonance peak of a computed curve in a window against the digitised one's:
    /// frequency within `x_px` pixels, height within `y_px` pixels plus the check's tolerance.
    Peak {
        /// The case.
        case: String,
        /// 0-based mass.
        mass: usize,
        /// The digitised curve's name.
        curve: String,
        /// Frequency window, Hz.
        window: (f64, f64),
        /// Tolerance of the peak's frequency, pixels.
        x_px: f64,
        /// Tolerance of its height, pixels.
        y_px: f64,
    },
    /// The motion types of a case's beds at the waveform frequencies include every type of
    /// `present` and none of `absent` ("I", "II", "III", "rests").
    MotionTypes {
        /// The case.
        case: String,
        /// Types that must appear.
        present: Vec<String>,
        /// Types that must not appear.
        absent: Vec<String>,
    },
    /// An ordering claim: the peak ratio of `case` over `over_case` in `window` is smaller than
    /// in `than_window` (e.g. dampers help a higher resonance more than the fundamental).
    RatioOrder {
        /// The case in the numerator.
        case: String,
        /// The case in the denominator.
        over_case: String,
        /// 0-based mass.
        mass: usize,
        /// The window whose ratio must be smaller, Hz.
        window: (f64, f64),
        /// The window it is compared with, Hz.
        than_window: (f64, f64),
    },
    /// An impulse history (x, v, a of every mass) against a reference file over the first
    /// `window` seconds: the largest difference relative to the column's largest value.
    ImpulseHistory {
        /// The case.
        case: String,
        /// Seconds from the kick compared.
        window: f64,
    },
    /// Envelope decay times of a mass's acceleration against those of a reference history,
    /// the same estimator applied to both.
    DecayTime {
        /// The case.
        case: String,
        /// 0-based mass.
        mass: usize,
        /// Envelope levels, fractions of the first peak.
        levels: Vec<f64>,
    },
    /// The decay time of `case` over that of `over_case` at most a reference value.
    DecayRatio {
        /// The case in the numerator.
        case: String,
        /// The case in the denominator.
        over_case: String,
        /// 0-based mass.
        mass: usize,
        /// Envelope level, a fraction of the first peak.
        level: f64,
    },
    /// The exact periodic orbits of the full structure against the simulation of it, at the
    /// simulated points that settled on a period-1 motion on a stable part of the branch.
    OrbitVsSimulation,
    /// The peak compliance of the SDOF solution against that of the simulation of the full
    /// structure (the paper's "close agreement").
    SdofVsSimulation,
    /// The paper's conclusion read on a design (docs/design.md, "The paper's conclusion as a
    /// check"): the best layout found with two containers or more lowers the worst peak of
    /// the bands at least the reference value's factor below the bare structure's.
    DesignConclusion,
}

/// How a claim about the ratio of two responses "around resonance" is read: the paper's words
/// allow more than one reading, each a check of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reading {
    /// The peak of `case` over the peak of `over_case` (each at its own frequency).
    PeakOverPeak,
    /// Both at the frequency of `case`'s peak (e.g. the single damper's resonance).
    AtResonance,
    /// The largest ratio of the two at one frequency, over the band where `case` is at least
    /// 1/sqrt(2) of its peak (its resonance band).
    BandMax,
}

impl Reading {
    /// The name used in files.
    pub fn name(self) -> &'static str {
        match self {
            Reading::PeakOverPeak => "peak_over_peak",
            Reading::AtResonance => "at_resonance",
            Reading::BandMax => "band_max",
        }
    }
}

/// How a ratio is bounded by its reference.
#[derive(Debug, Clone, PartialEq)]
pub enum Bound {
    /// Between the reference value and the value named `upper_id`.
    Within {
        /// Id of the upper bound in the same reference file.
        upper_id: String,
    },
    /// At most the reference value.
    AtMost,
    /// At least the reference value.
    AtLeast,
}

/// A check to make against a reference.
#[derive(Debug, Clone)]
pub struct CheckSpec {
    /// What is checked.
    pub kind: CheckKind,
    /// The name texts quote it by (`{ID}`), unique in the experiment.
    pub id: Option<String>,
    /// File under `reference/` and, for values, the id after `#`.
    pub reference_file: String,
    /// The value's id in a value file (after `#`).
    pub reference_id: Option<String>,
    /// Pass when within it.
    pub tolerance: Tolerance,
    /// An expected difference and its reason (a failure is then a known deviation).
    pub known_deviation: Option<String>,
    /// The value file or digitised file validation parsed for it (the checks take it from
    /// here: a reference file is parsed once); `None` for a CSV curve or no file.
    pub loaded: Option<crate::reference::files::Loaded>,
}

impl CheckSpec {
    /// The quantity of `file` this check names with `FILE#ID`.
    pub fn quantity<'a>(&self, file: &'a ValueFile) -> Option<&'a Quantity> {
        self.reference_id.as_deref().and_then(|id| file.get(id))
    }
}

/// The structure's mass a shot mass is stated against, kg: a lumped structure's masses summed;
/// a finite-element model's mass moving along the vertical
/// ([`crate::model::fe::FeStructure::mass_along_up`], the supports' share excluded: its reduced
/// mass matrix's trace is no mass, its coordinates are modal); `None` for a full mass matrix
/// given as such, whose coordinates are not all displacements.
pub fn structure_mass(structure: &Structure, fe: Option<&crate::model::fe::FeStructure>) -> Option<f64> {
    match fe {
        Some(f) => Some(f.mass().0),
        None => structure.is_lumped().then(|| structure.mass_matrix().trace()),
    }
}

/// A validated experiment.
#[derive(Debug, Clone)]
pub struct Experiment {
    /// The file it came from.
    pub path: PathBuf,
    /// Title, figure, caption, claim and notes.
    pub meta: Meta,
    /// The model this copy runs on (`None`: the file has one structure of its own).
    pub model: Option<ModelInfo>,
    /// Every model the file runs on, in its order (empty without `models`).
    pub models: Vec<ModelInfo>,
    /// The structure of this model.
    pub structure: Structure,
    /// The stiffness fit, when the structure is fitted to measured modes.
    pub fit: Option<StiffnessFit>,
    /// Where the structure's numbers come from.
    pub structure_source: Option<String>,
    /// The finite-element model the structure was reduced from, if any.
    pub finite_element: Option<std::sync::Arc<crate::model::fe::FeStructure>>,
    /// Why the damping has the values it has.
    pub damping_assumption: Option<String>,
    /// The driven mass and the force amplitude.
    pub excitation: Excitation,
    /// What to compute.
    pub analysis: Analysis,
    /// The cases (curve families).
    pub cases: Vec<Case>,
    /// The plots to draw.
    pub plots: Vec<PlotSpec>,
    /// The checks to make.
    pub checks: Vec<CheckSpec>,
}

impl Experiment {
    /// [`structure_mass`] of this experiment's structure.
    pub fn structure_mass(&self) -> Option<f64> {
        structure_mass(&self.structure, self.finite_element.as_deref())
    }

    /// The run's key: the experiment id, with `/MODEL` when it runs on several models. It
    /// names the report folder, the baseline file and the exports.
    pub fn key(&self) -> String {
        self.key_of(&self.meta.id)
    }

    /// The key of experiment `id` on this experiment's model.
    pub fn key_of(&self, id: &str) -> String {
        match &self.model {
            Some(m) => format!("{id}/{}", m.id),
            None => id.to_string(),
        }
    }

    /// Ids of the experiments whose exports this one uses.
    pub fn dependencies(&self) -> Vec<String> {
        let mut ids: Vec<String> = Vec::new();
        let mut add = |r: &ExportRef| {
            if !ids.contains(&r.experiment) {
                ids.push(r.experiment.clone());
            }
        };
        for case in &self.cases {
            for bed in &case.beds {
                if let ClearanceSource::Export(r) = &bed.clearance {
                    add(r);
                }
            }
        }
        if let Analysis::Waveform { frequencies, .. } = &self.analysis {
            for f in frequencies {
                if let Number::Export(r) = f {
                    add(r);
                }
            }
        }
        ids
    }

    /// This experiment with every exported value filled in from `exports` (experiment id ->
    /// key -> value).
    pub fn resolve(&self, exports: &Exports) -> Result<Experiment> {
        let lookup = |r: &ExportRef, key: String| -> Result<f64> {
            let run = self.key_of(&r.experiment);
            exports.get(&run).and_then(|e| e.get(&r.key)).copied().ok_or_else(|| {
                let known: Vec<&String> = exports.get(&run).map(|e| e.keys().collect()).unwrap_or_default();
                Error::invalid(
                    &self.path,
                    key,
                    r,
                    format!("experiment \"{}\" exports no such value (it exports {known:?})", r.experiment),
                )
            })
        };
        let mut out = self.clone();
        for (ci, case) in out.cases.iter_mut().enumerate() {
            for (di, bed) in case.beds.iter_mut().enumerate() {
                if let ClearanceSource::Export(r) = &bed.clearance {
                    let mm = lookup(r, format!("cases[{ci}].dampers[{di}].clearance_mm"))?;
                    bed.damper.clearance = crate::model::Clearance::from_mm(mm);
                    bed.clearance = ClearanceSource::Fixed;
                }
            }
        }
        if let Analysis::Waveform { frequencies, .. } = &mut out.analysis {
            for (i, f) in frequencies.iter_mut().enumerate() {
                if let Number::Export(r) = f {
                    *f = Number::Value(lookup(r, format!("analysis.frequencies_hz[{i}]"))?);
                }
            }
        }
        Ok(out)
    }
}

/// Values experiments export, by run key ([`Experiment::key`]) and value name.
pub type Exports = std::collections::BTreeMap<String, std::collections::BTreeMap<String, f64>>;
