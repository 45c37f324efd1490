//! The structure with its beds under a recorded ground motion (docs/model.md section 5,
//! "Recorded ground motions"), exact between samples: the ground's acceleration is linear between
//! samples, so each configuration's motion over an interval is its modes plus a particular
//! solution linear in time (`piece`), a flying bed's a cubic, and impacts, lift-offs and
//! landings are located on that closed form (`run`): no time step. The structure moves
//! relative to its supports (`M_c uddot + C udot + K u = -L_c a_g(t) + w_c`, `L_c` the load
//! per unit ground acceleration with the riding beds, `w_c` their weights); a bed's position is
//! relative to the ground at its host (`yddot = -g_a - r_p a_g` in flight), so its impacts and
//! contact forces are those of the absolute motion. Peaks, RMS values and energies are
//! measured on the closed form (`measure`). No I/O.

mod measure;
mod piece;
mod run;

pub use run::respond;

/// How a run under a record ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RecordStop {
    /// The whole record was run.
    Completed,
    /// More events than [`RecordOptions::max_events`] (a bed chattering without end).
    Events {
        /// The time the run stopped, s.
        t_s: f64,
    },
}

/// What a run under a record keeps and how far it may go.
#[derive(Debug, Clone, Copy)]
pub struct RecordOptions {
    /// Most events (impacts and lift-offs) before the run stops.
    pub max_events: usize,
    /// Most samples of the histories kept ([`RecordResponse::t`]): a longer record keeps every
    /// k-th sample (and the last), so memory stays bounded; peaks, RMS values and energies are
    /// over every sample and between them whatever this is.
    pub max_history: usize,
}

impl Default for RecordOptions {
    fn default() -> Self {
        RecordOptions { max_events: 2_000_000, max_history: 20_000 }
    }
}

/// What one bed did over a record.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BedTally {
    /// Impacts on either end.
    pub impacts: usize,
    /// Lift-offs (a riding bed leaving its end).
    pub lift_offs: usize,
    /// Kinetic energy lost in its impacts, J.
    pub energy_lost: f64,
    /// Its largest impact speed relative to its host, m/s.
    pub peak_impact_speed: f64,
}

/// The response of a structure with its beds to a record.
#[derive(Debug, Clone)]
pub struct RecordResponse {
    /// The sample times reached, s (every one, or every k-th and the last: see
    /// [`RecordOptions::max_history`]).
    pub t: Vec<f64>,
    /// Per sample: each physical coordinate's displacement relative to the supports, m
    /// (every mass of a lumped structure; a reduced model's points, not its modal
    /// coordinates: so every per-coordinate list here).
    pub u: Vec<Vec<f64>>,
    /// Per sample: each physical coordinate's absolute acceleration, m/s^2.
    pub accel: Vec<Vec<f64>>,
    /// The largest magnitude of each coordinate's relative displacement, m.
    pub peak_displacement: Vec<f64>,
    /// The largest magnitude of each storey's drift, m (empty: not a chain).
    pub peak_drift: Vec<f64>,
    /// The largest magnitude of each coordinate's absolute acceleration, m/s^2.
    pub peak_accel: Vec<f64>,
    /// The root mean square over the time run of each coordinate's relative displacement, m.
    pub rms_displacement: Vec<f64>,
    /// ... of each storey's drift, m (empty: not a chain).
    pub rms_drift: Vec<f64>,
    /// ... of each coordinate's absolute acceleration, m/s^2.
    pub rms_accel: Vec<f64>,
    /// The energy the ground put in, `-integral a_g (L_c^T udot + sum m r_p ydot) dt`, J.
    pub energy_input: f64,
    /// The energy the structure's damping took out, `integral udot^T C udot dt`, J.
    pub energy_viscous: f64,
    /// The energy lost in impacts, J.
    pub energy_impacts: f64,
    /// The energy stored at the end less that at the start (kinetic relative to the ground,
    /// strain, and the beds' height), J: the balance is `input - viscous - impacts - stored`.
    pub energy_stored: f64,
    /// Per bed.
    pub beds: Vec<BedTally>,
    /// Events (impacts and lift-offs).
    pub events: usize,
    /// How the run ended.
    pub stop: RecordStop,
}

impl RecordResponse {
    /// What the energy balance leaves over, J (rounding and the quadrature of the energies).
    pub fn balance(&self) -> f64 {
        self.energy_input - self.energy_viscous - self.energy_impacts - self.energy_stored
    }
}

/// Why a record cannot be run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecordError {
    /// The configurations could not be decomposed.
    #[error("{0}")]
    Setup(crate::sim::motion::system::SetupError),
    /// Columns of grains are not run under records.
    #[error("columns of grains are not run under a ground motion: give each container one bed")]
    Columns,
    /// The structure is not held by its supports (its stiffness is singular).
    #[error("the stiffness matrix is singular: the structure is not held by its supports")]
    Unsupported,
    /// The record has fewer than two samples or a step that is not positive.
    #[error("the record needs two samples or more at a positive step (it has {samples} at {dt_s} s)")]
    Record {
        /// Its samples.
        samples: usize,
        /// Its step, s.
        dt_s: f64,
    },
}
