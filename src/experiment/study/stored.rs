//! A study's stored answer (docs/studies.md, "A stored answer in the report"): per model, the
//! samples where the most claims hold at once, as a whole run of the study found them.
//! `shotdamp study FILE --store` writes it under `reference/studies/ID.json`; `shotdamp report`
//! runs those samples again for a study marked `stored = true` and says whether they still give
//! what was stored. Serialisation only; no I/O.

use serde::{Deserialize, Serialize};

/// Most best samples stored per model.
pub const BEST_STORED: usize = 3;

/// One stored sample and its count.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredSample {
    /// Its index in the study.
    pub sample: usize,
    /// Its values, in the order of the study's varied keys.
    pub values: Vec<f64>,
    /// Claims at the sample.
    pub claims: usize,
    /// Claims evaluable on settled points.
    pub evaluable: usize,
    /// Of those, the claims that hold.
    pub holds: usize,
    /// The claims that fail there, with value and bound.
    pub failing: Vec<String>,
}

/// One model's part of a stored answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredModel {
    /// The model's id (`""` without models).
    pub model: String,
    /// Samples the run computed on it.
    pub samples: usize,
    /// Samples where every claim holds on settled points.
    pub all_hold: usize,
    /// The samples where the most claims hold at once (at most [`BEST_STORED`], in sample
    /// order).
    pub best: Vec<StoredSample>,
    /// What every sample of the model says beyond them, in the report's words: the claims that
    /// fail wherever they can be evaluated, the claims of different figures that never hold
    /// together (written by the run that stored it).
    #[serde(default)]
    pub findings: Vec<String>,
    /// The pairs of claims of different figures that each hold at some sample of the model but
    /// never at the same one.
    #[serde(default)]
    pub apart: Vec<[String; 2]>,
}

/// A study's stored answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredStudy {
    /// The study's id.
    pub study: String,
    /// The fingerprint of the study version that computed it.
    pub fingerprint: String,
    /// Its design, in words (e.g. "sobol, 256 samples per model").
    pub design: String,
    /// The varied keys' names.
    pub vary: Vec<String>,
    /// Per model, in the study's order.
    pub models: Vec<StoredModel>,
    /// The date of the run (UTC, YYYY-MM-DD).
    pub date: String,
}
