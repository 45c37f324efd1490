//! Stated limits of a design file, so that every search it can ask for ends in a time its
//! estimate states (docs/design.md, "Limits and cost").

/// Frequencies of one band.
pub const BAND_POINTS: usize = 1000;
/// Steady-state points of one layout evaluation: every band's frequencies, swept each
/// way asked, in every scenario.
pub const EVALUATION_POINTS: usize = 20_000;
/// Total shot mass ratios of the Pareto front (distinct).
pub const PARETO_RATIOS: usize = 20;
/// Values of each scenario list (`damping`, `force_n`; distinct).
pub const SCENARIO_VALUES: usize = 10;
/// Scenarios of one search (every combination, times the models with `models = true`).
pub const SCENARIOS: usize = 60;
/// Candidate clearances of the paper's SDOF rule (distinct).
pub const SDOF_CLEARANCES: usize = 50;
/// Nelder-Mead iterations per start.
pub const MAX_ITERS: usize = 10_000;
/// Starts per placement.
pub const STARTS: usize = 100;
