//! Raw `[design]` tables of an experiment file: serde structs that mirror the TOML exactly
//! (docs/design.md); [`crate::experiment::validate`] checks them.

use serde::Deserialize;

use super::grid::RawGrid;

/// `[design]`: what a design search may vary and what it lowers (docs/design.md).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawDesign {
    /// 1-based masses that may carry a container.
    pub candidates: Vec<i64>,
    /// Most containers in one layout (default: every candidate).
    #[serde(default)]
    pub max_beds: Option<i64>,
    /// The shot budget: total shot mass over the structure's total mass ...
    #[serde(default)]
    pub shot_mass_ratio: Option<f64>,
    /// ... or in kg.
    #[serde(default)]
    pub shot_kg: Option<f64>,
    /// Bounds of the clearance, mm: `[min, max]`.
    pub clearance_mm: Vec<f64>,
    /// Forces (N) at which the best layout and the cases are evaluated after the search, to
    /// draw the reduction against the drive level (not part of the objective).
    #[serde(default)]
    pub drive_levels_n: Option<Vec<f64>>,
    /// `"nominal"` (default: the objective at the file's force) or
    /// `"worst_over_drive_levels"` (the worst over `drive_levels_n`).
    #[serde(default)]
    pub objective: Option<String>,
    /// The direction every container's bed moves in: "vertical" (default, the paper's) or
    /// "horizontal".
    #[serde(default)]
    pub direction: Option<String>,
    /// One clearance for every container (default) or one each.
    #[serde(default)]
    pub shared_clearance: Option<bool>,
    /// "peak" (default) or "rms".
    #[serde(default)]
    pub measure: Option<String>,
    /// Sweeps whose worst value counts: any of "rest", "up", "down" (default ["up", "down"]).
    #[serde(default)]
    pub sweeps: Option<Vec<String>>,
    /// Nelder-Mead starts per placement (default 3), iterations per start (default 100).
    #[serde(default)]
    pub starts: Option<i64>,
    #[serde(default)]
    /// Nelder-Mead iterations per start (default 100).
    pub max_iters: Option<i64>,
    /// A start ends when the standard deviation of its simplex's objectives falls below this
    /// (default 1e-6).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// A start also ends when its simplex has shrunk below this in every free coordinate (the
    /// search's coordinates; default 0: never).
    #[serde(default)]
    pub step_tolerance: Option<f64>,
    #[serde(default)]
    /// Seed of the starts (default 1).
    pub seed: Option<i64>,
    /// Total shot mass ratios of the Pareto front (optional).
    #[serde(default)]
    pub pareto_mass_ratios: Option<Vec<f64>>,
    /// `shotdamp report` shows this design (its stored answer evaluated again); default false.
    #[serde(default)]
    pub report: Option<bool>,
    /// The bands whose response is lowered (none with `ground_motions`).
    #[serde(default)]
    pub bands: Vec<RawBand>,
    /// Recorded ground motions the layouts are judged under instead of bands (as
    /// `analysis.ground_motions` of a time history).
    #[serde(default)]
    pub ground_motions: Option<Vec<super::raw_ground::RawGroundMotion>>,
    /// With `ground_motions`: what is lowered, "drift" (default) or "acceleration".
    #[serde(default)]
    pub response: Option<String>,
    /// With `ground_motions`: how the records' peaks combine, "largest" (default) or "mean".
    #[serde(default)]
    pub over_records: Option<String>,
    /// With `ground_motions`: the storeys' heights, m (one for all, or one a storey), for drift
    /// ratios on the page.
    #[serde(default)]
    pub storey_height_m: Option<super::raw_ground::RawHeights>,
    /// Values the objective is taken over (the paper leaves them unstated).
    #[serde(default)]
    pub scenarios: Option<RawScenarios>,
    /// The paper's SDOF technique beside the search.
    #[serde(default)]
    pub sdof: Option<RawDesignSdof>,
    /// `[design.screen]`: search on a coarser reduction of a finite-element structure.
    #[serde(default)]
    pub screen: Option<RawScreen>,
}

/// `[design.screen]`: the reduction the search runs on (fixed-interface modes kept, as
/// `[structure.finite_element]`'s keys); each placement's best is then evaluated on the
/// file's own.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScreen {
    /// Fixed-interface modes kept (instead of `cutoff_hz`).
    #[serde(default)]
    pub modes: Option<i64>,
    /// Keep every fixed-interface mode below this, Hz (instead of `modes`).
    #[serde(default)]
    pub cutoff_hz: Option<f64>,
    /// Forcing periods a steady state of the search may run (default: `steady.max_periods`).
    #[serde(default)]
    pub max_periods: Option<i64>,
}

/// `[design.sdof]`: the mode and the candidate clearances of the SDOF rule (Fig. 9).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawDesignSdof {
    /// 1-based mode.
    pub mode: i64,
    /// Candidate clearances, mm.
    pub clearances_mm: Vec<f64>,
}

/// `[design.scenarios]`: every combination of the lists.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScenarios {
    /// Modal damping ratio of every mode.
    #[serde(default)]
    pub damping: Option<Vec<f64>>,
    /// Force amplitudes, N.
    #[serde(default)]
    pub force_n: Option<Vec<f64>>,
    /// The file's models as scenarios of one search (instead of a search per model).
    #[serde(default)]
    pub models: Option<bool>,
    /// "worst" (default) or "mean".
    #[serde(default)]
    pub combine: Option<String>,
}

/// One band of `[design]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBand {
    /// The band's name.
    pub name: String,
    /// Its frequency grid.
    pub freq_hz: RawGrid,
    /// 1-based masses whose compliance counts.
    pub masses: Vec<i64>,
}
