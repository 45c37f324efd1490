//! Raw ground-motion keys of an experiment file (`ground_motions`, `storey_height_m`): serde
//! types that mirror the TOML exactly, shared by a time history's `[analysis]` ([`super::raw`])
//! and a design's `[design]` ([`super::raw_design`]); `experiment::ground` reads them.

use serde::Deserialize;

/// One recorded ground motion of a time history: its file (relative to the experiment file)
/// and how it is scaled.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawGroundMotion {
    /// The record file: PEER `.AT2`, or CSV of time and acceleration with its unit named.
    pub file: String,
    /// Its name on the page (default: the file's title or name).
    #[serde(default)]
    pub name: Option<String>,
    /// A factor on its accelerations.
    #[serde(default)]
    pub scale: Option<f64>,
    /// Its peak after scaling, g (instead of `scale`).
    #[serde(default)]
    pub peak_g: Option<f64>,
    /// The direction it shakes the supports in, stated: "along" a chain, or a finite-element
    /// model's `base_direction` ("x", "y", "z"); checked against the structure.
    #[serde(default)]
    pub direction: Option<String>,
}

/// Storey heights: one for every storey, or one a storey.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum RawHeights {
    /// The same height for every storey, m.
    One(f64),
    /// Each storey's height from the ground up, m.
    Each(Vec<f64>),
}
