//! Raw experiment files: serde structs that mirror the TOML exactly.
//!
//! Nothing here is validated; [`crate::experiment::validate`] turns these into typed values
//! once. A design's tables are in [`super::raw_design`].
//! The format is documented in `docs/experiment-format.md`.

use serde::Deserialize;

use super::grid::RawGrid;
use super::raw_design::RawDesign;
use super::raw_ground::{RawGroundMotion, RawHeights};

/// A whole experiment file after `extends` has been merged in.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawExperiment {
    /// Path of a shared file whose tables this file extends (merged before parsing).
    #[serde(default)]
    pub extends: Option<String>,
    /// The model this copy of the experiment runs on (from a model file listed in `models`).
    #[serde(default)]
    pub model: Option<RawModel>,
    /// `[experiment]`: title, figure, caption, claim.
    pub experiment: RawMeta,
    /// `[structure]`.
    pub structure: RawStructure,
    /// `[excitation]` (left out by a time history, which its records drive).
    #[serde(default)]
    pub excitation: RawExcitation,
    /// `[analysis]`.
    pub analysis: RawAnalysis,
    /// The design search of `kind = "design"` (docs/design.md).
    #[serde(default)]
    pub design: Option<RawDesign>,
    #[serde(default)]
    /// `[[cases]]`.
    pub cases: Vec<RawCase>,
    #[serde(default)]
    /// `[[plots]]`.
    pub plots: Vec<RawPlot>,
    #[serde(default)]
    /// `[[checks]]`.
    pub checks: Vec<RawCheck>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[experiment]`: what the experiment reproduces.
pub struct RawMeta {
    /// Id (names the report folder).
    pub id: String,
    /// Title.
    pub title: String,
    /// The paper figure.
    pub figure: String,
    /// The paper's caption.
    pub caption: String,
    /// The paper's claim.
    pub claim: String,
    /// Assumptions in words, on top of those derived from the model settings.
    #[serde(default)]
    pub assumptions: Vec<String>,
    /// Free text shown under the figure (how to read it, what differs from the paper).
    #[serde(default)]
    pub notes: Vec<String>,
    /// One sentence on the main deviation from the paper and its likely cause (for the
    /// summary of verdicts).
    #[serde(default)]
    pub deviation: Option<String>,
}

/// The `[model]` table of a model file (`experiments/shared/models/*.toml`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawModel {
    /// The model's id.
    pub id: String,
    /// Its label.
    pub label: String,
    /// What it is.
    pub description: String,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[structure]`: masses, stiffness, damping.
pub struct RawStructure {
    /// Lumped masses, kg.
    #[serde(default)]
    pub masses_kg: Option<Vec<f64>>,
    /// A general symmetric positive definite mass matrix, rows, kg (instead of `masses_kg`).
    #[serde(default)]
    pub mass_matrix_kg: Option<Vec<Vec<f64>>>,
    /// Chain stiffnesses k_1..k_n (ground - k_1 - m_1 - k_2 - m_2 ...).
    #[serde(default)]
    pub chain_stiffness_n_per_m: Option<Vec<f64>>,
    /// A general symmetric stiffness matrix, rows.
    #[serde(default)]
    pub stiffness_matrix_n_per_m: Option<Vec<Vec<f64>>>,
    /// Measured modal data a stiffness matrix is fitted to.
    #[serde(default)]
    pub fit: Option<RawFit>,
    /// Springs from each mass to ground, added to the stiffness (0: none).
    #[serde(default)]
    pub ground_stiffness_n_per_m: Option<Vec<f64>>,
    /// `[structure.finite_element]`: a finite-element model's matrices, reduced at its points
    /// (instead of masses and stiffness).
    #[serde(default)]
    pub finite_element: Option<RawFiniteElement>,
    /// `[structure.damping]`.
    pub damping: RawDamping,
    #[serde(default)]
    /// Where the numbers come from.
    pub source: Option<String>,
}

impl RawStructure {
    /// Whether `other` gives the same mass and stiffness: every key but `[structure.damping]`
    /// equal (a key added to `[structure]` joins the comparison, or this does not compile).
    pub fn same_matrices(&self, other: &RawStructure) -> bool {
        let RawStructure {
            masses_kg,
            mass_matrix_kg,
            chain_stiffness_n_per_m,
            stiffness_matrix_n_per_m,
            fit,
            ground_stiffness_n_per_m,
            finite_element,
            damping: _,
            source,
        } = self;
        *masses_kg == other.masses_kg
            && *mass_matrix_kg == other.mass_matrix_kg
            && *chain_stiffness_n_per_m == other.chain_stiffness_n_per_m
            && *stiffness_matrix_n_per_m == other.stiffness_matrix_n_per_m
            && *fit == other.fit
            && *ground_stiffness_n_per_m == other.ground_stiffness_n_per_m
            && *finite_element == other.finite_element
            && *source == other.source
    }
}

/// `[structure.finite_element]`: files written by a finite-element program.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFiniteElement {
    /// `"calculix"`, `"matrix-market"` or `"abaqus"`.
    pub format: String,
    /// The stiffness matrix's file, relative to the experiment file.
    pub stiffness: String,
    /// The mass matrix's file.
    pub mass: String,
    /// CalculiX's `.dof` file (required for `calculix`; for `matrix-market`, optional: names
    /// the rows by node and direction in the same format).
    #[serde(default)]
    pub dofs: Option<String>,
    /// `"N-m-kg"` (default) or `"N-mm-t"` (stiffness in N/mm, mass in tonnes).
    #[serde(default)]
    pub units: Option<String>,
    /// The global direction that points up: `"x"`, `"y"`, `"z"`, `"-x"`, `"-y"` or `"-z"`.
    pub up: String,
    /// The global direction moving supports accelerate along (`[excitation]
    /// base_acceleration_m_s2`), as `up`; default: `up` (the ground heaves).
    #[serde(default)]
    pub base_direction: Option<String>,
    /// The points kept as physical coordinates, in order: the structure's coordinates 1 to P
    /// (container hosts, the force, reported responses).
    pub points: Vec<RawPoint>,
    /// Fixed-interface modes kept (instead of `cutoff_hz`).
    #[serde(default)]
    pub modes: Option<i64>,
    /// Keep every fixed-interface mode below this, Hz (instead of `modes`).
    #[serde(default)]
    pub cutoff_hz: Option<f64>,
    /// The largest relative difference of the reduced model's compliance from the full
    /// model's over the analysis' frequencies (default 1e-3).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// The physical structure's whole mass, kg, as stated by the user (the files' matrices
    /// leave out what the supports hold): what a design's `shot_mass_ratio` is taken of.
    #[serde(default)]
    pub mass_kg: Option<f64>,
}

/// A point of a finite-element model: a node and direction, or (a Matrix Market model
/// without names) a row.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPoint {
    /// Its name in reports.
    #[serde(default)]
    pub name: Option<String>,
    /// Node number.
    #[serde(default)]
    pub node: Option<i64>,
    /// Direction 1 to 3 (x, y, z).
    #[serde(default)]
    pub dof: Option<i64>,
    /// The matrix row, 1-based (instead of node and dof).
    #[serde(default)]
    pub row: Option<i64>,
}

/// Measured natural frequencies and mode shapes (model updating).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFit {
    /// Measured natural frequencies, rad/s.
    pub omegas_rad_per_s: Vec<f64>,
    /// One row per mode.
    pub shapes: Vec<Vec<f64>>,
    /// Weight of a relative frequency error against a shape element's (default 100).
    #[serde(default)]
    pub frequency_weight: Option<f64>,
    /// Weight of each shape element (0: not trusted; default 1).
    #[serde(default)]
    pub shape_weights: Option<Vec<Vec<f64>>>,
    #[serde(default)]
    /// Where the measurements come from.
    pub source: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[structure.damping]`: modal ratios, or Rayleigh coefficients.
pub struct RawDamping {
    #[serde(default)]
    /// One damping ratio per mode.
    pub modal_ratios: Option<Vec<f64>>,
    #[serde(default)]
    /// Rayleigh's mass-proportional coefficient, 1/s.
    pub rayleigh_alpha: Option<f64>,
    #[serde(default)]
    /// Rayleigh's stiffness-proportional coefficient, s.
    pub rayleigh_beta: Option<f64>,
    /// Why these values (the paper gives none).
    #[serde(default)]
    pub assumption: Option<String>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[excitation]`: `F sin(omega t)` on one mass, or the supports accelerating as `A sin(omega
/// t)`.
pub struct RawExcitation {
    /// 1-based index of the driven mass.
    #[serde(default)]
    pub mass: Option<i64>,
    /// Force amplitude, N.
    #[serde(default)]
    pub force_n: Option<f64>,
    /// The supports' acceleration amplitude, m/s^2.
    #[serde(default)]
    pub base_acceleration_m_s2: Option<f64>,
    /// The supports' acceleration amplitude, g.
    #[serde(default)]
    pub base_acceleration_g: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[analysis]`: what to compute, and its settings.
pub struct RawAnalysis {
    /// The kind ("sweep", "impulse", ...).
    pub kind: String,
    #[serde(default)]
    /// The frequency grid.
    pub freq_hz: Option<RawGrid>,
    /// Sweeps: "rest" (independent points) or "continuation" (upward and downward).
    #[serde(default)]
    pub start: Option<String>,
    /// Steady-state settings overriding the defaults.
    #[serde(default)]
    pub steady: Option<RawSteady>,
    /// Clearance study: clearances to scan (mm); default: `clearance_points` up to the
    /// highest flight of the beds without top.
    #[serde(default)]
    pub clearances_mm: Option<Vec<f64>>,
    #[serde(default)]
    /// Clearance study: clearances scanned when `clearances_mm` is not given.
    pub clearance_points: Option<i64>,
    /// Clearance study: the mass whose peak compliance is minimised (1-based).
    #[serde(default)]
    pub objective_mass: Option<i64>,
    /// Clearance study: the case whose peak decides the best clearance.
    #[serde(default)]
    pub objective_case: Option<String>,
    /// Waveforms: forcing frequencies (Hz, or "@EXPERIMENT.KEY").
    #[serde(default)]
    pub frequencies_hz: Option<Vec<toml::Value>>,
    /// Waveforms: labels of the frequencies (e.g. "a", "b", "c").
    #[serde(default)]
    pub labels: Option<Vec<String>>,
    /// Waveforms: steady periods to record and draw.
    #[serde(default)]
    pub periods: Option<i64>,
    /// SDOF periodic analysis: the mode (1-based).
    #[serde(default)]
    pub mode: Option<i64>,
    /// Impulse: the struck mass (1-based).
    #[serde(default)]
    pub struck_mass: Option<i64>,
    /// Impulse: the initial velocity given to the struck mass and the beds on it, m/s ...
    #[serde(default)]
    pub initial_velocity_m_s: Option<f64>,
    /// ... or the impulse, N s.
    #[serde(default)]
    pub impulse_n_s: Option<f64>,
    /// Impulse: simulated time, s.
    #[serde(default)]
    pub duration_s: Option<f64>,
    /// Impulse: samples per second.
    #[serde(default)]
    pub sample_rate_hz: Option<f64>,
    /// Impulse: frequencies of the spectrum.
    #[serde(default)]
    pub spectrum_hz: Option<RawGrid>,
    /// Impulse: fractions of the first envelope peak whose decay times are measured.
    #[serde(default)]
    pub decay_levels: Option<Vec<f64>>,
    /// Time history: the recorded ground motions.
    #[serde(default)]
    pub ground_motions: Option<Vec<RawGroundMotion>>,
    /// Time history: the storeys' heights, m (one for all, or one a storey).
    #[serde(default)]
    pub storey_height_m: Option<RawHeights>,
}

/// Steady-state settings (docs/model.md section 3, docs/simulator.md).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSteady {
    /// "orbit" (default) or "transient".
    #[serde(default)]
    pub method: Option<String>,
    #[serde(default)]
    /// Transient: relative change that counts as settled.
    pub tol: Option<f64>,
    #[serde(default)]
    /// Orbit: Newton's tolerance on the relative residual.
    pub orbit_tol: Option<f64>,
    #[serde(default)]
    /// Orbit: most Newton iterations per attempt.
    pub max_newton: Option<i64>,
    #[serde(default)]
    /// Periods in a row (settled, or the pattern repeated).
    pub consecutive: Option<i64>,
    #[serde(default)]
    /// Periods before the motion is judged.
    pub min_periods: Option<i64>,
    #[serde(default)]
    /// Most periods simulated.
    pub max_periods: Option<i64>,
    #[serde(default)]
    /// Periods recorded once settled.
    pub record_periods: Option<i64>,
    /// Attempts in a row that find a torus before the search stops (0: never).
    #[serde(default)]
    pub torus_attempts: Option<i64>,
    /// Continuation sweeps follow a certified orbit by Newton's method before any transient
    /// (default false; true in designs).
    #[serde(default)]
    pub follow: Option<bool>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[[cases]]`: one curve family.
pub struct RawCase {
    /// Id (unique in the file).
    pub id: String,
    /// Legend label.
    pub label: String,
    #[serde(default)]
    /// Its containers.
    pub dampers: Vec<RawDamper>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
/// One container of shot.
pub struct RawDamper {
    /// 1-based host mass, as in the paper.
    pub mass: i64,
    /// `m_d / m_host`.
    #[serde(default)]
    pub mass_ratio: Option<f64>,
    /// `m_d` in kg (alternative to `mass_ratio`).
    #[serde(default)]
    pub mass_kg: Option<f64>,
    /// A number of millimetres, "inf", "scan" (clearance studies), or "@EXPERIMENT.KEY"
    /// (a value another experiment exports).
    pub clearance_mm: toml::Value,
    /// The bed model: "plastic" (the paper's one mass, e = 0), "restitution" (one mass with a
    /// coefficient of restitution) or "column" (`grains` equal grains). Default: "column" when
    /// `grains` is given, "restitution" when a restitution > 0 is, else "plastic".
    #[serde(default)]
    pub bed: Option<String>,
    /// Number of grains of a column bed (total mass unchanged): a whole number (a float such
    /// as 5.0, as studies write it, is taken).
    #[serde(default)]
    pub grains: Option<f64>,
    /// Coefficient of restitution of the bed against the container's ends, and between the
    /// grains of a column (default 0: plastic).
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Relative impact speed below which a bed with restitution sticks, m/s (default 1e-3).
    #[serde(default)]
    pub stick_speed_m_s: Option<f64>,
    /// The direction the bed moves in relative to gravity: "vertical" (the paper's, default)
    /// or "horizontal" (no gravity along the motion: the bed flies between two walls).
    #[serde(default)]
    pub direction: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[[plots]]`: a plot to draw.
pub struct RawPlot {
    /// File stem.
    pub id: String,
    /// The kind of plot.
    pub kind: String,
    #[serde(default)]
    /// Title (default: from the experiment).
    pub title: Option<String>,
    /// 1-based masses to draw.
    #[serde(default)]
    pub masses: Option<Vec<i64>>,
    /// Case ids to draw (default: all).
    #[serde(default)]
    pub cases: Option<Vec<String>>,
    #[serde(default)]
    /// "linear" or "log".
    pub y_scale: Option<String>,
    #[serde(default)]
    /// Mark the natural frequencies.
    pub mark_natural_frequencies: Option<bool>,
    /// Frequencies to mark, relative to the resonance peak of `marks_relative_to`.
    #[serde(default)]
    pub marks: Option<Vec<RawMark>>,
    #[serde(default)]
    /// The case whose resonance peak the marks are relative to.
    pub marks_relative_to: Option<String>,
    /// Linear curves drawn beside: "bare" and/or "stuck".
    #[serde(default)]
    pub linear: Option<Vec<String>>,
    /// The horizontal range drawn, [from, to] (default: the analysis's).
    #[serde(default)]
    pub x_range: Option<Vec<f64>>,
}

/// A marked frequency, `offset_hz` from a resonance peak.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMark {
    /// The mark's label.
    pub label: String,
    /// Offset from the peak, Hz.
    pub offset_hz: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
/// `[[checks]]`: a check against a reference.
pub struct RawCheck {
    /// The kind of check.
    pub kind: String,
    /// A name for the check, unique in the experiment, by which texts quote its values
    /// (`{ID}`, docs/experiment-format.md).
    #[serde(default)]
    pub id: Option<String>,
    /// `FILE#ID` for a value in `reference/FILE`, or `FILE` for a curve.
    #[serde(default)]
    pub reference: Option<String>,
    #[serde(default)]
    /// 1-based mode (modal checks).
    pub mode: Option<i64>,
    #[serde(default)]
    /// Relative tolerance.
    pub rel_tol: Option<f64>,
    #[serde(default)]
    /// Absolute tolerance.
    pub abs_tol: Option<f64>,
    /// An expected difference, with its reason: a failure is then reported as a known
    /// deviation, and a pass as a known deviation that now passes.
    #[serde(default)]
    pub known_deviation: Option<String>,
    /// Curve and ratio checks: the case computed.
    #[serde(default)]
    pub case: Option<String>,
    /// Ratio checks: the case in the denominator.
    #[serde(default)]
    pub over_case: Option<String>,
    /// Ratio checks: the mass (1-based).
    #[serde(default)]
    pub mass: Option<i64>,
    /// Curve checks: `rel_tol` must hold at this fraction of the points ...
    #[serde(default)]
    pub fraction: Option<f64>,
    /// ... and `rel_tol_all` at every point.
    #[serde(default)]
    pub rel_tol_all: Option<f64>,
    /// Curve checks: the column prefix of the reference's curves (default: none).
    #[serde(default)]
    pub columns: Option<String>,
    /// Curve checks of a continuation sweep: "up" or "down".
    #[serde(default)]
    pub direction: Option<String>,
    /// Curve checks of a clearance study: which scanned clearance (mm).
    #[serde(default)]
    pub clearance_mm: Option<f64>,
    /// Ratio checks: the id of the upper bound (`reference` names the lower one).
    #[serde(default)]
    pub range_to: Option<String>,
    /// Ratio checks: how "around resonance" is read: "peak_over_peak" (default),
    /// "at_resonance" (both at `case`'s peak frequency) or "band_max" (the largest ratio at one
    /// frequency over `case`'s resonance band).
    #[serde(default)]
    pub reading: Option<String>,
    /// Ratio checks: "within" (default, with `range_to`), "at_most" or "at_least".
    #[serde(default)]
    pub bound: Option<String>,
    /// Ratio checks: the frequency window of the peak, [from, to] Hz (default: the curve).
    #[serde(default)]
    pub window_hz: Option<Vec<f64>>,
    /// Ordering checks: the window whose ratio must be the larger one.
    #[serde(default)]
    pub than_window_hz: Option<Vec<f64>>,
    /// Motion type checks: types that must appear ("I", "II", "III", "rests") ...
    #[serde(default)]
    pub present: Option<Vec<String>>,
    /// ... and types that must not.
    #[serde(default)]
    pub absent: Option<Vec<String>>,
    /// Tube and peak checks: the digitised curve (its dataset name).
    #[serde(default)]
    pub curve: Option<String>,
    /// Tube and peak checks: tolerances in pixels of the digitised figure.
    #[serde(default)]
    pub x_tol_px: Option<f64>,
    #[serde(default)]
    /// Tolerance along y, pixels.
    pub y_tol_px: Option<f64>,
    /// Impulse history checks: the compared window from t = 0, s.
    #[serde(default)]
    pub window_s: Option<f64>,
    /// Mode shape checks: the elements compared (1-based masses; default all).
    #[serde(default)]
    pub elements: Option<Vec<i64>>,
    /// Decay checks: the envelope level (fraction of the first peak).
    #[serde(default)]
    pub level: Option<f64>,
}

/// The highest frequency an experiment file's analysis asks for, Hz, as written (its grid,
/// its listed frequencies, its design bands), if any: the default cutoff's base.
pub fn highest_analysed(a: &RawAnalysis, d: Option<&RawDesign>) -> Option<f64> {
    let grids = a.freq_hz.iter().chain(d.into_iter().flat_map(|d| d.bands.iter().map(|b| &b.freq_hz)));
    let listed = a.frequencies_hz.iter().flatten().filter_map(toml::Value::as_float);
    grids
        .flat_map(|g| match g {
            RawGrid::Range(r) => vec![r.start, r.stop],
            RawGrid::List(l) => l.clone(),
        })
        .chain(listed)
        .filter(|f| f.is_finite() && *f > 0.0)
        .fold(None, |m: Option<f64>, f| Some(m.map_or(f, |m| m.max(f))))
}
