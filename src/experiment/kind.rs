//! The analysis kinds: what each computes (the variants of [`Analysis`]) and what each one
//! allows, in one room. A new kind adds its variant and its answers here, its reading in
//! `analysis.rs` and its run in `src/analysis/`.

use super::{Number, PlotKind, Start};
use crate::sim::motion::impulse::ImpulseOptions;
use crate::sim::SteadyOptions;

/// What to compute.
#[derive(Debug, Clone)]
pub enum Analysis {
    /// Modal analysis only.
    Modal,
    /// Exact linear compliance of the bare structure and of each case with its damper
    /// masses rigidly added, on a grid in Hz.
    LinearFrf {
        /// The grid, Hz.
        freq_hz: Vec<f64>,
    },
    /// Steady-state compliance by simulation on a grid in Hz.
    Sweep {
        /// The grid, Hz.
        freq_hz: Vec<f64>,
        /// From rest at every point, or by continuation.
        start: Start,
        /// Steady-state settings.
        steady: SteadyOptions,
    },
    /// Peak compliance against clearance, from near 0 to where the beds stop reaching the top.
    ClearanceStudy {
        /// The grid of each sweep, Hz.
        freq_hz: Vec<f64>,
        /// Clearances to scan, mm (`None`: `points` up to the limit found).
        clearances_mm: Option<Vec<f64>>,
        /// Clearances scanned when none are given.
        points: usize,
        /// 0-based mass whose peak compliance is compared.
        objective_mass: usize,
        /// The case whose peak decides the best clearance.
        objective_case: String,
        /// Steady-state settings.
        steady: SteadyOptions,
    },
    /// Time histories at a few frequencies.
    Waveform {
        /// Forcing frequencies, Hz (or exported values).
        frequencies: Vec<Number>,
        /// Their labels, e.g. "a", "b", "c".
        labels: Vec<String>,
        /// Steady periods recorded and drawn.
        periods: usize,
        /// Steady-state settings.
        steady: SteadyOptions,
    },
    /// Periodic orbits of one mode's equivalent SDOF model and of the full structure with one
    /// damper, continued in frequency, with stability; the MDOF simulation beside them.
    SdofPeriodic {
        /// 0-based mode.
        mode: usize,
        /// The band and the simulation grid, Hz.
        freq_hz: Vec<f64>,
        /// Candidate clearances (mm) when the damper's clearance is "scan".
        clearances_mm: Option<Vec<f64>>,
        /// Steady-state settings.
        steady: SteadyOptions,
    },
    /// A design search: placements, shot split and clearances lowering the compliance over
    /// bands (`[design]`, docs/design.md), with the cases as reference layouts.
    Design {
        /// The design problem as the file states it.
        spec: Box<crate::design::Spec>,
        /// Steady-state settings of the sweeps.
        steady: SteadyOptions,
    },
    /// Free decay after an impulse: histories, envelopes, decay times, energy, spectrum.
    Impulse {
        /// The struck mass, the kick, the duration and the sampling.
        options: ImpulseOptions,
        /// Frequencies of the spectrum, Hz.
        spectrum_hz: Vec<f64>,
        /// Envelope levels whose decay times are measured (fractions of the first peak).
        levels: Vec<f64>,
    },
    /// The response of every case to recorded ground motions (docs/model.md section 5):
    /// peaks, RMS values and energies storey by storey, with and without shot.
    TimeHistory {
        /// The records, read and scaled.
        records: Vec<super::ground::Record>,
        /// Each storey's height, m, for drift ratios (a chain's).
        storey_heights_m: Option<Vec<f64>>,
    },
}

/// One analysis kind of experiment files: its name and the keys of `[analysis]` it reads (any
/// other key of `[analysis]` given with it is an input error).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KindSpec {
    /// The name in files (`analysis.kind`).
    pub name: &'static str,
    /// The keys of `[analysis]` it reads.
    pub reads: &'static [&'static str],
    /// Whether it runs the exact simulator (whose limits on degrees of freedom and bed
    /// configurations are checked before anything runs).
    pub simulates: bool,
    /// Whether it answers a design question: its page is headed "Design question", the
    /// command prints its answer in a line per model, and its result is stored and replayed
    /// (`designs/KEY.json`).
    pub answers: bool,
}

/// The analysis kinds: the one list that validation, its messages and [`Analysis::kind`]'s
/// test read.
pub const KINDS: &[KindSpec] = &[
    KindSpec { name: "modal", reads: &[], simulates: false, answers: false },
    KindSpec { name: "linear_frf", reads: &["freq_hz"], simulates: false, answers: false },
    KindSpec { name: "sweep", reads: &["freq_hz", "start", "steady"], simulates: true, answers: false },
    KindSpec {
        name: "clearance_study",
        reads: &["freq_hz", "steady", "clearances_mm", "clearance_points", "objective_mass", "objective_case"],
        simulates: true,
        answers: false,
    },
    KindSpec {
        name: "waveform",
        reads: &["frequencies_hz", "labels", "periods", "steady"],
        simulates: true,
        answers: false,
    },
    KindSpec {
        name: "impulse",
        reads: &[
            "struck_mass",
            "initial_velocity_m_s",
            "impulse_n_s",
            "duration_s",
            "sample_rate_hz",
            "spectrum_hz",
            "decay_levels",
        ],
        simulates: true,
        answers: false,
    },
    KindSpec {
        name: "sdof_periodic",
        reads: &["mode", "freq_hz", "clearances_mm", "steady"],
        simulates: true,
        answers: false,
    },
    KindSpec { name: "design", reads: &["steady"], simulates: true, answers: true },
    KindSpec { name: "time_history", reads: &["ground_motions", "storey_height_m"], simulates: true, answers: false },
];

/// The kind named `name` in a file.
pub fn kind_spec(name: &str) -> Option<&'static KindSpec> {
    KINDS.iter().find(|k| k.name == name)
}

/// The kinds' names, quoted, for messages.
pub fn kind_names() -> String {
    KINDS.iter().map(|k| format!("\"{}\"", k.name)).collect::<Vec<_>>().join(", ")
}

impl Analysis {
    /// The name used in files (one of the table `KINDS` of this module).
    pub fn kind(&self) -> &'static str {
        match self {
            Analysis::Modal => "modal",
            Analysis::LinearFrf { .. } => "linear_frf",
            Analysis::Sweep { .. } => "sweep",
            Analysis::ClearanceStudy { .. } => "clearance_study",
            Analysis::Waveform { .. } => "waveform",
            Analysis::Impulse { .. } => "impulse",
            Analysis::SdofPeriodic { .. } => "sdof_periodic",
            Analysis::Design { .. } => "design",
            Analysis::TimeHistory { .. } => "time_history",
        }
    }

    /// Plot kinds it can draw (`[[plots]] kind`), with their names in files.
    pub fn plot_kinds(&self) -> &'static [(&'static str, PlotKind)] {
        match self {
            Analysis::Modal | Analysis::Design { .. } => &[],
            Analysis::LinearFrf { .. } | Analysis::Sweep { .. } => {
                &[("compliance", PlotKind::Compliance), ("compliance_panels", PlotKind::CompliancePanels)]
            }
            Analysis::ClearanceStudy { .. } => {
                &[("clearance_scan", PlotKind::ClearanceScan), ("compliance_panels", PlotKind::CompliancePanels)]
            }
            Analysis::Waveform { .. } => &[("waveform", PlotKind::Waveform)],
            Analysis::SdofPeriodic { .. } => {
                &[("orbits", PlotKind::Orbits), ("clearance_choice", PlotKind::ClearanceChoice)]
            }
            Analysis::Impulse { .. } => &[
                ("acceleration", PlotKind::Acceleration),
                ("decay", PlotKind::Decay),
                ("spectrum", PlotKind::Spectrum),
                ("damping", PlotKind::Damping),
            ],
            Analysis::TimeHistory { .. } => {
                &[("ground_histories", PlotKind::GroundHistories), ("storey_profiles", PlotKind::StoreyProfiles)]
            }
        }
    }

    /// The frequencies the simulator will be driven at, by the key that gives them (a design's
    /// bands whatever its cases; exported waveform frequencies are checked once resolved).
    pub fn simulated_frequencies(&self) -> Vec<(String, Vec<f64>)> {
        match self {
            Analysis::Sweep { freq_hz, .. }
            | Analysis::ClearanceStudy { freq_hz, .. }
            | Analysis::SdofPeriodic { freq_hz, .. } => vec![("analysis.freq_hz".into(), freq_hz.clone())],
            Analysis::Waveform { frequencies, .. } => vec![(
                "analysis.frequencies_hz".into(),
                frequencies
                    .iter()
                    .filter_map(|f| match f {
                        Number::Value(v) => Some(*v),
                        Number::Export(_) => None,
                    })
                    .collect(),
            )],
            Analysis::Design { spec, .. } => spec
                .bands
                .iter()
                .enumerate()
                .map(|(i, b)| (format!("design.bands[{i}].freq_hz"), b.freq_hz.clone()))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// A design's problem and its sweeps' settings, where this is a design: the one way
    /// outside the design's own rooms to reach them (no match on the variant elsewhere).
    pub fn design(&self) -> Option<(&crate::design::Spec, &SteadyOptions)> {
        match self {
            Analysis::Design { spec, steady } => Some((spec, steady)),
            _ => None,
        }
    }

    /// [`Analysis::design`]'s problem, to change (a replay, a shard, a time limit).
    pub fn design_mut(&mut self) -> Option<&mut crate::design::Spec> {
        match self {
            Analysis::Design { spec, .. } => Some(spec),
            _ => None,
        }
    }

    /// Whether it runs the exact simulator (every kind but the modal and the linear ones,
    /// which take a structure of any size).
    pub fn simulates(&self) -> bool {
        kind_spec(self.kind()).is_some_and(|k| k.simulates)
    }

    /// Whether it answers a design question (the `answers` column of its line in `KINDS`).
    pub fn answers(&self) -> bool {
        kind_spec(self.kind()).is_some_and(|k| k.answers)
    }

    /// Whether every damper's clearance is scanned (`clearance_mm = "scan"` required).
    pub fn scans_clearances(&self) -> bool {
        matches!(self, Analysis::ClearanceStudy { .. })
    }

    /// Whether a damper's clearance may be scanned (an SDOF analysis with a list of
    /// candidate clearances).
    pub fn may_scan_clearances(&self) -> bool {
        matches!(self, Analysis::SdofPeriodic { clearances_mm: Some(_), .. })
    }

    /// Whether it models the paper's plastic bed only (no restitution).
    pub fn plastic_only(&self) -> bool {
        matches!(self, Analysis::SdofPeriodic { .. } | Analysis::Design { .. })
    }

    /// Whether a column of grains can run in it: where the motion is simulated (from rest,
    /// or after an impulse); the orbit-based kinds (continuation with its orbit branches,
    /// SDOF orbits, designs) do not model grains yet.
    pub fn runs_columns(&self) -> bool {
        matches!(
            self,
            Analysis::Sweep { start: Start::Rest, .. }
                | Analysis::ClearanceStudy { .. }
                | Analysis::Waveform { .. }
                | Analysis::Impulse { .. }
                | Analysis::LinearFrf { .. }
                | Analysis::Modal
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_listed_once_with_keys_listed_once() {
        for (i, k) in KINDS.iter().enumerate() {
            assert!(KINDS[..i].iter().all(|o| o.name != k.name), "{} twice", k.name);
            for (j, key) in k.reads.iter().enumerate() {
                assert!(!k.reads[..j].contains(key), "{}: {key} twice", k.name);
            }
        }
        assert_eq!(kind_spec("sweep").map(|k| k.reads), Some(&["freq_hz", "start", "steady"][..]));
        assert!(kind_names().starts_with("\"modal\", \"linear_frf\""));
    }
}
