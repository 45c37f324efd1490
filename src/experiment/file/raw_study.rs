//! Raw study files: serde structs that mirror the TOML exactly (docs/studies.md); the study
//! room (`crate::experiment::study`) checks them.

use serde::Deserialize;

/// A study file: `[study]` and its `[[vary]]` entries.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(in crate::experiment) struct RawFile {
    pub(in crate::experiment) study: RawStudy,
    #[serde(default)]
    pub(in crate::experiment) vary: Vec<RawVary>,
}

/// `[study]`: what it runs, how its samples are drawn, where it is shown.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(in crate::experiment) struct RawStudy {
    pub(in crate::experiment) id: String,
    pub(in crate::experiment) title: String,
    #[serde(default)]
    pub(in crate::experiment) experiment: Option<String>,
    #[serde(default)]
    pub(in crate::experiment) experiments: Option<Vec<String>>,
    #[serde(default)]
    pub(in crate::experiment) description: Option<String>,
    #[serde(default)]
    pub(in crate::experiment) models: Option<Vec<String>>,
    #[serde(default)]
    pub(in crate::experiment) design: Option<String>,
    #[serde(default)]
    pub(in crate::experiment) samples: Option<i64>,
    #[serde(default)]
    pub(in crate::experiment) seed: Option<i64>,
    #[serde(default)]
    pub(in crate::experiment) levels: Option<i64>,
    #[serde(default)]
    pub(in crate::experiment) refine: Option<toml::Value>,
    #[serde(default)]
    pub(in crate::experiment) map: Option<Vec<String>>,
    #[serde(default)]
    pub(in crate::experiment) report: bool,
    #[serde(default)]
    pub(in crate::experiment) stored: bool,
    #[serde(default)]
    pub(in crate::experiment) section: Option<String>,
    #[serde(default)]
    pub(in crate::experiment) set: toml::Table,
}

/// One `[[vary]]` entry: a key path and the values it takes.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(in crate::experiment) struct RawVary {
    pub(in crate::experiment) name: String,
    pub(in crate::experiment) key: String,
    #[serde(default)]
    pub(in crate::experiment) label: Option<String>,
    #[serde(default)]
    pub(in crate::experiment) values: Option<Vec<f64>>,
    #[serde(default)]
    pub(in crate::experiment) range: Option<RawRange>,
    #[serde(default)]
    pub(in crate::experiment) experiments: Option<Vec<String>>,
}

/// A varied key's range: `start`, `stop`, a `count` and a `scale`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(in crate::experiment) struct RawRange {
    pub(in crate::experiment) start: f64,
    pub(in crate::experiment) stop: f64,
    #[serde(default)]
    pub(in crate::experiment) count: Option<i64>,
    #[serde(default)]
    pub(in crate::experiment) scale: Option<String>,
}
