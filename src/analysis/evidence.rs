//! What the kinds compute that the checks read, below both: a waveform's motion types, an
//! impulse's decays, an SDOF analysis's orbits. The kinds fill them in, `checks.rs` compares
//! them and `kind.rs` carries them from one to the other, so none of those imports another.

use num_complex::Complex64;

use crate::experiment::Case;
use crate::model::sdof::EquivalentSdof;
use crate::signal::Decrement;
use crate::sim::motion::impulse::ImpulseRun;
use crate::sim::orbits::continuation::Special;

use super::curves::{parabola_top, Curve};

/// Per case: the motion type of each bed at each frequency, short ("I", "II", "III", or
/// "rests" when the bed does not fly).
pub type MotionTypes = std::collections::BTreeMap<String, Vec<String>>;

/// One case's free decay and what is measured on it.
#[derive(Debug, Clone)]
pub struct Decay {
    /// The case's id.
    pub id: String,
    /// Its label.
    pub label: String,
    /// The free response.
    pub run: ImpulseRun,
    /// Per mass: peaks of |acceleration| (time, m/s^2).
    pub envelopes: Vec<Vec<(f64, f64)>>,
    /// Per mass, per level: time for the envelope to fall there, s (`None`: not reached).
    pub decay_times: Vec<Vec<Option<f64>>>,
    /// Per mode of the bare structure: the log decrements of its modal coordinate.
    pub decrements: Vec<Vec<Decrement>>,
    /// Time of the last lift-off of any bed, s.
    pub last_liftoff: Option<f64>,
    /// Per mass: the magnitude of the spectrum of its acceleration at the analysis's frequencies.
    pub spectra: Vec<Vec<f64>>,
}

/// One periodic orbit as drawn and tabled.
#[derive(Debug, Clone)]
pub struct OrbitPoint {
    /// Forcing frequency, Hz.
    pub freq_hz: f64,
    /// Compliance of each mass of the structure, m/N.
    pub compliance: Vec<f64>,
    /// Impact phase, rad: the lag of the force behind the bottom impact (docs/periodic.md).
    pub phi: f64,
    /// Lift-off from the bottom, rad of forcing phase after the bottom impact (0: at once).
    pub tau0: Option<f64>,
    /// Impact on the top, rad after the bottom impact (None: no top impact).
    pub tau1: Option<f64>,
    /// Release from the top, rad after the bottom impact (None: no top impact).
    pub tau2: Option<f64>,
    /// Motion type ("I", "II", "III", ...).
    pub kind: String,
    /// Every Floquet multiplier inside the unit circle.
    pub stable: bool,
    /// The event sequence survived the difference steps of the Jacobian.
    pub smooth: bool,
    /// Floquet multipliers, largest modulus first.
    pub multipliers: Vec<Complex64>,
}

/// Continued branches of orbits of one system: one segment per seed (a segment ends where the
/// return map has a kink it cannot cross, e.g. where an impact appears or vanishes).
#[derive(Debug, Clone, Default)]
pub struct OrbitBranch {
    /// Key, e.g. "sdof" or "exact".
    pub id: String,
    /// Legend label.
    pub label: String,
    /// Each segment in branch order (increasing arclength), so folds show as turns.
    pub segments: Vec<Vec<OrbitPoint>>,
    /// Folds, period doublings and grazings on the segments.
    pub special: Vec<Special>,
    /// How each end of each segment ended.
    pub ends: Vec<String>,
}

impl OrbitBranch {
    /// Every point of every segment.
    pub fn points(&self) -> impl Iterator<Item = &OrbitPoint> {
        self.segments.iter().flatten()
    }

    /// Frequency and compliance of `mass` at the highest stable point computed.
    pub fn highest(&self, mass: usize) -> Option<(f64, f64)> {
        self.points().filter(|p| p.stable).map(|p| (p.freq_hz, p.compliance[mass])).max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The branch's peak of `mass`: the maximum of the parabola (in frequency) through its
    /// highest stable point and the two points beside it on its segment, when both are stable,
    /// lie on either side in frequency and are not higher (so that the peak does not depend on
    /// where the continuation's steps fell); the highest point itself otherwise (an end of a
    /// segment, a fold, a loss of stability).
    pub fn peak(&self, mass: usize) -> Option<(f64, f64)> {
        let mut best: Option<(usize, usize)> = None;
        for (s, seg) in self.segments.iter().enumerate() {
            for (k, p) in seg.iter().enumerate() {
                if p.stable && best.is_none_or(|(bs, bk)| p.compliance[mass] > self.segments[bs][bk].compliance[mass]) {
                    best = Some((s, k));
                }
            }
        }
        let (s, k) = best?;
        let seg = &self.segments[s];
        let at = |i: usize| (seg[i].freq_hz, seg[i].compliance[mass]);
        let refined = (k > 0 && k + 1 < seg.len() && seg[k - 1].stable && seg[k + 1].stable)
            .then(|| parabola_top([at(k - 1), at(k), at(k + 1)]))
            .flatten();
        Some(refined.unwrap_or(at(k)))
    }

    /// Whether a frequency lies within the span of a segment.
    pub(super) fn covers(&self, f: f64) -> bool {
        self.segments.iter().any(|seg| {
            let lo = seg.iter().map(|p| p.freq_hz).fold(f64::INFINITY, f64::min);
            let hi = seg.iter().map(|p| p.freq_hz).fold(f64::NEG_INFINITY, f64::max);
            f >= lo - 1e-9 && f <= hi + 1e-9
        })
    }
}

/// The clearance study of the SDOF model: one row per candidate.
#[derive(Debug, Clone)]
pub struct ClearanceRow {
    /// The candidate clearance, mm.
    pub clearance_mm: f64,
    /// Frequency (Hz) and compliance (m/N) of the SDOF model's peak (None: no orbit found).
    pub peak: Option<(f64, f64)>,
    /// Motion types of the stable orbits within the resonance (compliance >= peak / sqrt 2).
    pub kinds: Vec<String>,
    /// True when every stable orbit within the resonance is Type II.
    pub only_type_ii: bool,
}

/// An exact orbit solved at a simulated point, against the simulation there.
#[derive(Debug, Clone)]
pub struct OrbitCheckPoint {
    /// The simulated frequency, Hz.
    pub freq_hz: f64,
    /// Largest relative difference of the compliances (NaN when no orbit was found).
    pub rel_diff: f64,
    /// The exact orbit found there is stable.
    pub stable: bool,
    /// What was found, in words.
    pub note: String,
}

/// Everything an SDOF periodic analysis computed.
#[derive(Debug, Clone)]
pub struct OrbitsResult {
    /// 0-based mode.
    pub mode: usize,
    /// Force amplitude of the structure, N.
    pub force: f64,
    /// The case analysed (one damper).
    pub case: Case,
    /// The mode's equivalent SDOF model (Eq. 12-13).
    pub sdof_model: EquivalentSdof,
    /// The clearance study of the SDOF model (empty with a fixed clearance).
    pub clearance_rows: Vec<ClearanceRow>,
    /// How the clearance was chosen, in words.
    pub clearance_note: String,
    /// The SDOF model's branch.
    pub sdof: OrbitBranch,
    /// The full structure's branch of exact orbits.
    pub exact: OrbitBranch,
    /// The full structure simulated from rest at the grid.
    pub simulation: Curve,
    /// Exact orbits solved at simulated points, against the simulation.
    pub checked: Vec<OrbitCheckPoint>,
}
