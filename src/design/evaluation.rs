//! What one layout's evaluation gives: its objective and where it comes from
//! ([`Evaluation`]), each frequency's steady state as the design measures it ([`Point`]) and
//! how its beds moved ([`Motion`]).

use crate::sim::settle::statistic::{ClassCounts, Motion as Class};

/// The objective of one layout and where it comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// Per band: the band's measure (compliance, m/N).
    pub bands: Vec<f64>,
    /// Per band: the measure of the bare structure (the same sweeps without dampers).
    pub bare: Vec<f64>,
    /// The objective: the worst band's measure relative to the bare structure's (1: no gain),
    /// combined over the scenarios (the worst, or the mean).
    pub objective: f64,
    /// Per scenario: its objective. `bands`, `bare` and `worst` are those of the scenario
    /// with the largest.
    pub scenarios: Vec<f64>,
    /// Index of the scenario with the largest objective.
    pub worst_scenario: usize,
    /// The band, frequency (Hz) and mass of the largest compliance of the worst band.
    pub worst: (usize, f64, usize),
    /// The first scenario's compliance per band, frequency and mass (m/N; the nominal
    /// structure when there are no scenarios), for figures.
    pub curves: Vec<Vec<Vec<f64>>>,
    /// Points without a settled stable periodic orbit (their compliance is the statistic of
    /// their measured motion, [`Point`]: see docs/design.md).
    pub unsettled: usize,
    /// Steady states computed.
    pub points: usize,
    /// Per band: how the beds moved (the worst scenario's): the layout's drive level.
    pub motion: Vec<Motion>,
    /// The half-width of the objective's 95 % interval (0 where every point it rests on is
    /// a certified orbit; from the measured points' intervals, [`Point::half_width`]).
    pub half_width: f64,
    /// Per band: the half-width of its measure's interval (the worst scenario's).
    pub bands_half_width: Vec<f64>,
    /// Steady states of each class ([`Class::ALL`]'s order), over every scenario.
    pub classes: ClassCounts,
    /// Steady states measured as irregular motion (a statistic with its interval), over every
    /// scenario.
    pub measured: usize,
    /// Of those, the points measured over a short screen only: their interval (widened) lies
    /// below their band's highest point's, so they cannot set the measure (docs/design.md,
    /// "Points that cannot set the peak").
    pub screened: usize,
    /// The first scenario's points per band, frequency and mass, beside `curves`: the class
    /// of the motion that set each compliance and its interval.
    pub points_class: Vec<Vec<Vec<Point>>>,
}

/// The point behind one compliance of a band's curve: its motion's class and the half-width
/// of its 95 % interval (m/N; 0 for a certified orbit or a point not measured; where the
/// interval did not meet its tolerance, the one the measurement gave).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// The class of the motion.
    pub class: Class,
    /// The half-width of the compliance's 95 % interval, m/N.
    pub half_width: f64,
    /// The lowest compliance over the sweeps at this frequency and mass, m/N (NaN where one
    /// sweep was run, or none gave a value).
    pub lowest: f64,
    /// The class of the motion that gave the lowest.
    pub lowest_class: Class,
    /// The half-width of the lowest's interval, m/N.
    pub lowest_half_width: f64,
    /// The compliance was measured over a short screen only (its interval, widened, lies
    /// below the band's highest point's: docs/design.md, "Points that cannot set the peak").
    pub screened: bool,
}

impl Default for Point {
    fn default() -> Self {
        Point {
            class: Class::Periodic,
            half_width: 0.0,
            lowest: f64::NAN,
            lowest_class: Class::Periodic,
            lowest_half_width: 0.0,
            screened: false,
        }
    }
}

/// Relative difference below which two certified orbits' compliances are the same motion
/// (orbits are certified to far less).
pub const SAME_ORBIT: f64 = 1e-6;

impl Point {
    /// Whether the sweeps reached different motions here: `Some(true)` where the highest
    /// compliance over them (`highest`, the curve's value, with this point's interval) and
    /// the lowest (with its interval) do not overlap, or differ by more than [`SAME_ORBIT`] of
    /// the highest for certified orbits: two attractors coexist (the design counts the
    /// higher, the table gives both). `None` where they differ but an interval is not known
    /// (a measurement too short for its batches): it cannot be told. `Some(false)` otherwise,
    /// and where one sweep was run.
    pub fn coexisting(&self, highest: f64) -> Option<bool> {
        if !(self.lowest.is_finite() && highest.is_finite()) {
            return Some(false);
        }
        let apart = |h: f64, l: f64| highest - h > self.lowest + l + SAME_ORBIT * highest;
        match (self.half_width.is_finite(), self.lowest_half_width.is_finite()) {
            (true, true) => Some(apart(self.half_width, self.lowest_half_width)),
            // Unknown intervals: apart even as points, and no more can be said.
            _ if apart(0.0, 0.0) => None,
            _ => Some(false),
        }
    }
}

impl Evaluation {
    /// The objective's interval, (low, high).
    pub fn interval(&self) -> (f64, f64) {
        (self.objective - self.half_width, self.objective + self.half_width)
    }

    /// Whether this evaluation and `other` are equal within their intervals (an interval not
    /// known, a NaN half-width, counts as its objective alone).
    pub fn overlaps(&self, other: &Evaluation) -> bool {
        let known = |h: f64| if h.is_nan() { 0.0 } else { h };
        let (a, b) = (self.objective, other.objective);
        let (ha, hb) = (known(self.half_width), known(other.half_width));
        a - ha <= b + hb && b - hb <= a + ha
    }

    /// Points measured as irregular motion.
    pub fn measured(&self) -> usize {
        self.measured
    }

    /// Its steady states counted by class, the classes it has, in words ("periodic 208,
    /// chaotic 15, unclassified 43").
    pub fn class_words(&self) -> String {
        let named = Class::ALL.iter().filter(|c| self.classes[c.index()] > 0);
        named.map(|c| format!("{} {}", c.name(), self.classes[c.index()])).collect::<Vec<_>>().join(", ")
    }
}

#[cfg(test)]
impl Evaluation {
    /// An evaluation of one band (the worst at 50 Hz on m2) with this objective, for tests.
    pub fn with_objective(objective: f64, unsettled: usize, points: usize) -> Evaluation {
        Evaluation {
            bands: vec![objective],
            bare: vec![1.0],
            objective,
            scenarios: vec![objective],
            worst_scenario: 0,
            worst: (0, 50.0, 1),
            curves: Vec::new(),
            unsettled,
            points,
            motion: Vec::new(),
            half_width: 0.0,
            bands_half_width: vec![0.0],
            classes: {
                let mut c = ClassCounts::default();
                c[Class::Periodic.index()] = points.saturating_sub(unsettled);
                c[Class::Transient.index()] = unsettled;
                c
            },
            measured: 0,
            screened: 0,
            points_class: Vec::new(),
        }
    }
}

/// How the beds of a layout moved over a band: whether the drive makes them work. Beds that
/// never leave their containers only add mass.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Motion {
    /// Steady states (over the band's frequencies and sweeps) in which some bed left its
    /// container's bottom.
    pub lifting: usize,
    /// Steady states computed.
    pub points: usize,
    /// The highest flight of any bed above its container's bottom, m.
    pub flight_m: f64,
}

impl Motion {
    /// The share of the band's steady states in which the beds lift off.
    pub fn share(&self) -> f64 {
        if self.points == 0 {
            0.0
        } else {
            self.lifting as f64 / self.points as f64
        }
    }
}
