//! Steady-state compliance curves: what sweeps produce, what checks and plots consume.

use crate::experiment::{Case, CurveId, Experiment};
use crate::model::damper::added_masses;
use crate::model::frf::{compliance_curve, support_compliance_curve};
use crate::sim::settle::sweep::SweepPoint;
use crate::sim::{Stop, System};
use crate::table::Table;

/// Compliance of every mass at each frequency of one case (or one direction or clearance of
/// it), with how each point ended.
#[derive(Debug, Clone, Default)]
pub struct Curve {
    /// Which curve: its text is the key in tables and legends, e.g. "D", "single:up",
    /// "triple@0.2mm".
    pub id: CurveId,
    /// Legend label.
    pub label: String,
    /// Forcing frequency of each point, Hz.
    pub freq_hz: Vec<f64>,
    /// Per point, per mass, m/N.
    pub compliance: Vec<Vec<f64>>,
    /// Per point: settled (a stable orbit, or the transient died out).
    pub converged: Vec<bool>,
    /// Per point: 1 period-1, k a subharmonic, 0 none found.
    pub period: Vec<usize>,
    /// Per point, per bed, per forcing period.
    pub bottom_impacts: Vec<Vec<f64>>,
    /// Per point, per container, per forcing period: top impacts.
    pub top_impacts: Vec<Vec<f64>>,
    /// Per point, per bed: highest flight above the bottom, m.
    pub max_flight: Vec<Vec<f64>>,
    /// Per point: periods simulated before recording.
    pub transient: Vec<usize>,
    /// Per point: the orbit's fixed-point residual relative to its amplitude scale, and its
    /// largest Floquet multiplier modulus (NaN when the point is not a certified orbit).
    pub residual: Vec<f64>,
    /// Per point: the largest Floquet multiplier modulus (NaN without an orbit).
    pub radius: Vec<f64>,
    /// Per point: why it stopped early, if it did.
    pub stop: Vec<String>,
    /// Per point: what the motion is ([`crate::sim::settle::statistic::Motion::name`]).
    pub motion: Vec<&'static str>,
    /// Per point without a certified orbit: the measurement (statistic's interval, largest
    /// amplitude, Lyapunov exponent; [`crate::sim::settle::irregular`]).
    pub measured: Vec<Option<Measurement>>,
    /// Per point, per storey: the drift amplitude per unit drive (empty where not computed:
    /// drifts and floor accelerations are found on moving supports, a chain's storeys).
    pub drift: Vec<Vec<f64>>,
    /// Per point, per physical coordinate: the absolute acceleration amplitude per unit
    /// drive (empty where not computed).
    pub acceleration: Vec<Vec<f64>>,
}

/// A point's measurement in a curve's units.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// Per mass: the half-width of the compliance's 95 % interval.
    pub half_width: Vec<f64>,
    /// Per mass: the largest per-period compliance over the kept record.
    pub largest: Vec<f64>,
    /// The largest Lyapunov exponent and its interval's half-width, 1/s.
    pub lyapunov: (f64, f64),
    /// Periods kept.
    pub periods: usize,
    /// The interval met its tolerance.
    pub met: bool,
}

impl Measurement {
    fn of(m: &crate::sim::settle::statistic::Measured, force: f64) -> Measurement {
        Measurement {
            half_width: m.half_width.iter().map(|h| h / force).collect(),
            largest: m.largest.iter().map(|h| h / force).collect(),
            lyapunov: (m.lyapunov, m.lyapunov_half_width),
            periods: m.periods,
            met: m.met,
        }
    }
}

/// The curves an experiment computed, found by identity, and the unit of their compliance.
#[derive(Debug, Clone)]
pub struct Curves(Vec<Curve>, &'static str);

impl Default for Curves {
    fn default() -> Self {
        Curves(Vec::new(), "m/N")
    }
}

impl Curves {
    /// No curves (compliance in m/N).
    pub fn new() -> Self {
        Self::default()
    }

    /// No curves, their compliance in `unit` (e.g. "m/(m/s^2)" relative to moving supports).
    pub fn per(unit: &'static str) -> Self {
        Curves(Vec::new(), unit)
    }

    /// The unit of the compliance.
    pub fn unit(&self) -> &'static str {
        self.1
    }

    /// The curve with this identity.
    pub fn get(&self, id: &CurveId) -> Option<&Curve> {
        self.0.iter().find(|c| &c.id == id)
    }

    /// The case's only curve (a sweep from rest, or a linear curve).
    pub fn of_case(&self, case: &str) -> Option<&Curve> {
        self.get(&CurveId::whole(case))
    }

    /// Adds curves; one with the identity of a curve already held replaces it.
    pub fn extend(&mut self, curves: impl IntoIterator<Item = Curve>) {
        for c in curves {
            match self.0.iter_mut().find(|old| old.id == c.id) {
                Some(old) => *old = c,
                None => {
                    let key = c.id.to_string();
                    let at = self.0.partition_point(|old| old.id.to_string() <= key);
                    self.0.insert(at, c);
                }
            }
        }
    }

    /// The curves, in the order of their ids' text (as tables and legends list them).
    pub fn iter(&self) -> impl Iterator<Item = &Curve> {
        self.0.iter()
    }
}

impl Curve {
    /// The index of the point at `f` (within 1e-9 Hz).
    pub fn index_of(&self, f: f64) -> Option<usize> {
        self.freq_hz.iter().position(|x| (x - f).abs() < 1e-9)
    }

    /// True when the point is settled and period-1.
    pub fn regular(&self, i: usize) -> bool {
        self.converged[i] && self.period[i] == 1
    }

    /// Frequency and value of the highest compliance of `mass` (settled points if any).
    pub fn peak(&self, mass: usize) -> Option<(f64, f64)> {
        self.peak_in(mass, None)
    }

    /// Frequency and value of the highest compliance of `mass` within `window` (Hz; the whole
    /// curve when `None`), among settled points if any.
    pub fn peak_in(&self, mass: usize, window: Option<(f64, f64)>) -> Option<(f64, f64)> {
        self.peak_index_in(mass, window).map(|i| (self.freq_hz[i], self.compliance[i][mass]))
    }

    /// The index of [`Curve::peak_in`]'s point.
    pub fn peak_index_in(&self, mass: usize, window: Option<(f64, f64)>) -> Option<usize> {
        let inside = |i: usize| window.is_none_or(|(lo, hi)| self.freq_hz[i] >= lo && self.freq_hz[i] <= hi);
        let settled: Vec<usize> = (0..self.freq_hz.len()).filter(|&i| inside(i) && self.converged[i]).collect();
        let pool: Vec<usize> =
            if settled.is_empty() { (0..self.freq_hz.len()).filter(|&i| inside(i)).collect() } else { settled };
        pool.into_iter()
            .filter(|&i| self.compliance[i][mass].is_finite())
            .max_by(|&a, &b| self.compliance[a][mass].total_cmp(&self.compliance[b][mass]))
    }

    /// Whether [`Curve::peak_in`] rests only on settled points: its point settled, and no
    /// point of the window that did not settle higher (so skipping it changed nothing).
    pub fn peak_settled(&self, mass: usize, window: Option<(f64, f64)>) -> bool {
        let Some(p) = self.peak_index_in(mass, window) else { return false };
        let inside = |i: usize| window.is_none_or(|(lo, hi)| self.freq_hz[i] >= lo && self.freq_hz[i] <= hi);
        self.converged[p]
            && (0..self.freq_hz.len()).all(|i| {
                !inside(i) || self.converged[i] || not_above(self.compliance[i][mass], self.compliance[p][mass])
            })
    }

    /// The peak of `mass` refined like a branch's ([`parabola_top`] through the
    /// highest settled point and its two neighbours, when they are settled too); the highest
    /// settled point itself otherwise.
    pub fn refined_peak(&self, mass: usize) -> Option<(f64, f64)> {
        let k = self.peak_index_in(mass, None)?;
        let at = |i: usize| (self.freq_hz[i], self.compliance[i][mass]);
        let refined = (k > 0 && k + 1 < self.freq_hz.len() && self.converged[k - 1] && self.converged[k + 1])
            .then(|| parabola_top([at(k - 1), at(k), at(k + 1)]))
            .flatten();
        Some(refined.unwrap_or(at(k)))
    }

    /// Highest flight of any bed over the curve, m.
    pub fn highest_flight(&self) -> f64 {
        self.max_flight.iter().flatten().copied().fold(0.0, f64::max)
    }
}

/// True when `x` is known not to exceed `top` (a NaN is not known to).
pub fn not_above(x: f64, top: f64) -> bool {
    matches!(x.partial_cmp(&top), Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal))
}

/// Values per bed (a column's grains each) gathered per container: summed (`max`: false, e.g.
/// impacts per period) or the largest (`max`: true, e.g. flight heights). `grains[k]` is the
/// number of beds of container k.
pub fn per_container(values: Vec<f64>, grains: &[usize], max: bool) -> Vec<f64> {
    if grains.iter().all(|&g| g <= 1) {
        return values;
    }
    let mut out = Vec::with_capacity(grains.len());
    let mut j = 0;
    for &g in grains {
        let part = &values[j.min(values.len())..(j + g.max(1)).min(values.len())];
        out.push(if max { part.iter().copied().fold(0.0, f64::max) } else { part.iter().sum() });
        j += g.max(1);
    }
    out
}

/// The curve of sweep points (sorted by frequency); `grains[k]` beds per container `k` (their
/// impacts are summed and their flights maximised per container).
pub fn from_sweep(
    id: CurveId,
    label: &str,
    mut points: Vec<SweepPoint>,
    force: f64,
    grains: &[usize],
    n: usize,
) -> Curve {
    let beds = grains.len();
    points.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
    let mut c = Curve { id, label: label.into(), ..Curve::default() };
    for p in points {
        c.freq_hz.push(p.freq_hz);
        match p.result {
            Ok(s) => {
                c.motion.push(s.motion.name());
                c.measured.push(s.measured.as_ref().map(|m| Measurement::of(m, force)));
                c.stop.push(stop_text(&s));
                c.compliance.push(s.amplitude.iter().map(|a| a / force).collect());
                c.converged.push(s.converged);
                c.period.push(s.period);
                c.bottom_impacts.push(per_container(s.bottom_impacts, grains, false));
                c.top_impacts.push(per_container(s.top_impacts, grains, false));
                c.max_flight.push(per_container(s.max_flight, grains, true));
                c.transient.push(s.transient_periods);
                c.residual.push(s.certificate.as_ref().map_or(f64::NAN, |o| o.residual));
                c.radius.push(s.certificate.as_ref().map_or(f64::NAN, |o| o.spectral_radius()));
                let per_drive = |v: &[f64]| v.iter().map(|a| a / force).collect::<Vec<_>>();
                c.drift.push(s.peaks.as_ref().map_or(Vec::new(), |p| per_drive(&p.drift)));
                c.acceleration.push(s.peaks.as_ref().map_or(Vec::new(), |p| per_drive(&p.acceleration)));
            }
            Err(e) => {
                c.motion.push("not computed");
                c.measured.push(None);
                c.compliance.push(vec![f64::NAN; n]);
                c.converged.push(false);
                c.period.push(0);
                c.bottom_impacts.push(vec![0.0; beds]);
                c.top_impacts.push(vec![0.0; beds]);
                c.max_flight.push(vec![0.0; beds]);
                c.transient.push(0);
                c.residual.push(f64::NAN);
                c.radius.push(f64::NAN);
                c.stop.push(e.to_string());
                c.drift.push(Vec::new());
                c.acceleration.push(Vec::new());
            }
        }
    }
    c
}

/// Why a point stopped early or has no steady state, as the `stop` column says it ("" when
/// it has one).
pub fn stop_text(s: &crate::sim::Steady) -> String {
    match (&s.stop, &s.failure) {
        (Some(Stop::Chatter { t, events }), _) => format!("chatter: {events} events before t = {t:.4} s"),
        (None, Some(why)) => why.to_string(),
        (None, None) => String::new(),
    }
}

/// The exact linear curve of a case: bare without dampers, damper masses rigidly added
/// ("stuck") otherwise. Every point is settled and period-1 by construction.
pub fn linear(exp: &Experiment, case: &Case, id: CurveId, label: &str, freq_hz: &[f64], stuck: bool) -> Curve {
    let added = if stuck { added_masses(&case.dampers()) } else { Vec::new() };
    let mass = exp.structure.mass_matrix_with(&added);
    let omegas: Vec<f64> = freq_hz.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    let rows = if exp.excitation.supports {
        support_compliance_curve(&exp.structure, &mass, &omegas)
    } else {
        compliance_curve(&exp.structure, &mass, exp.excitation.mass, &omegas)
    };
    let m = freq_hz.len();
    let (drift, acceleration) = if exp.excitation.supports {
        crate::model::frf::support_peaks_curve(&exp.structure, &mass, &omegas).into_iter().unzip()
    } else {
        (vec![Vec::new(); m], vec![Vec::new(); m])
    };
    Curve {
        id,
        label: label.into(),
        freq_hz: freq_hz.to_vec(),
        compliance: rows,
        converged: vec![true; m],
        period: vec![1; m],
        bottom_impacts: vec![Vec::new(); m],
        top_impacts: vec![Vec::new(); m],
        max_flight: vec![Vec::new(); m],
        transient: vec![0; m],
        residual: vec![f64::NAN; m],
        radius: vec![f64::NAN; m],
        stop: vec![String::new(); m],
        motion: vec!["periodic"; m],
        measured: vec![None; m],
        drift,
        acceleration,
    }
}

/// The simulator's beds of each container of a case: one bed, or a column's grains (bottom
/// grain first).
pub fn bed_ranges(case: &crate::experiment::Case) -> Vec<std::ops::Range<usize>> {
    let mut start = 0;
    (0..case.beds.len())
        .map(|k| {
            let n = case.grains().get(k).copied().unwrap_or(1).max(1);
            start += n;
            start - n..start
        })
        .collect()
}

/// Container and grain (both 1-based) of the simulator's bed `bed` in case `case` (0, 0 when
/// the case is not found).
pub fn place(exp: &Experiment, case: &str, bed: usize) -> (i64, i64) {
    let ranges = exp.cases.iter().find(|c| c.id == case).map(bed_ranges).unwrap_or_default();
    ranges.iter().position(|r| r.contains(&bed)).map_or((0, 0), |k| (k as i64 + 1, (bed - ranges[k].start) as i64 + 1))
}

/// The simulated system of a case.
pub fn system(exp: &Experiment, case: &Case) -> System {
    crate::experiment::parts::system(&exp.structure, &exp.excitation, case)
}

/// The sorted union of a grid and extra frequencies (duplicates within 1e-9 Hz dropped).
pub fn union_grid(grid: &[f64], extra: &[f64]) -> Vec<f64> {
    let mut all: Vec<f64> = grid.iter().chain(extra).copied().collect();
    all.sort_by(f64::total_cmp);
    all.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    all
}

/// All curves in one long table: one row per curve and frequency.
pub fn table(name: &str, description: &str, curves: &[&Curve], n: usize, beds: usize) -> Table {
    let rows: Vec<(&Curve, usize)> = curves.iter().flat_map(|c| (0..c.freq_hz.len()).map(move |i| (*c, i))).collect();
    let mut t = Table::new(name, description)
        .str("curve", rows.iter().map(|(c, _)| c.id.to_string()).collect())
        .f64("freq_hz", rows.iter().map(|(c, i)| c.freq_hz[*i]).collect());
    for r in 0..n {
        t = t.f64(format!("c{}", r + 1), rows.iter().map(|(c, i)| c.compliance[*i][r]).collect());
    }
    // On moving supports: each storey's drift and each floor's absolute acceleration.
    let widest =
        |v: fn(&Curve) -> &Vec<Vec<f64>>| curves.iter().flat_map(|c| v(c).iter().map(Vec::len)).max().unwrap_or(0);
    let at = |v: &Vec<Vec<f64>>, i: usize, r: usize| v.get(i).and_then(|p| p.get(r)).copied().unwrap_or(f64::NAN);
    for r in 0..widest(|c| &c.drift) {
        t = t.f64(format!("drift{}", r + 1), rows.iter().map(|(c, i)| at(&c.drift, *i, r)).collect());
    }
    for r in 0..widest(|c| &c.acceleration) {
        t = t.f64(format!("acc{}", r + 1), rows.iter().map(|(c, i)| at(&c.acceleration, *i, r)).collect());
    }
    t = t
        .i64("converged", rows.iter().map(|(c, i)| c.converged[*i] as i64).collect())
        .i64("period", rows.iter().map(|(c, i)| c.period[*i] as i64).collect());
    let get = |v: &Vec<Vec<f64>>, i: usize, j: usize| v[i].get(j).copied().unwrap_or(0.0);
    for j in 0..beds {
        t = t
            .f64(
                format!("impacts_per_period_d{}", j + 1),
                rows.iter().map(|(c, i)| get(&c.bottom_impacts, *i, j)).collect(),
            )
            .f64(
                format!("top_impacts_per_period_d{}", j + 1),
                rows.iter().map(|(c, i)| get(&c.top_impacts, *i, j)).collect(),
            )
            .f64(
                format!("max_flight_mm_d{}", j + 1),
                rows.iter().map(|(c, i)| crate::number::decimal(1e3 * get(&c.max_flight, *i, j))).collect(),
            );
    }
    t = t
        .i64("transient_periods", rows.iter().map(|(c, i)| c.transient[*i] as i64).collect())
        .f64("orbit_residual", rows.iter().map(|(c, i)| c.residual[*i]).collect())
        .f64("max_multiplier", rows.iter().map(|(c, i)| c.radius[*i]).collect())
        .str("motion", rows.iter().map(|(c, i)| c.motion.get(*i).copied().unwrap_or("").to_string()).collect());
    let m = |c: &Curve, i: usize| c.measured.get(i).and_then(|m| m.as_ref()).cloned();
    for r in 0..n {
        t = t
            .f64(
                format!("c{}_half_width", r + 1),
                rows.iter().map(|(c, i)| m(c, *i).map_or(f64::NAN, |m| m.half_width[r])).collect(),
            )
            .f64(
                format!("c{}_largest", r + 1),
                rows.iter().map(|(c, i)| m(c, *i).map_or(f64::NAN, |m| m.largest[r])).collect(),
            );
    }
    t.f64("lyapunov_per_s", rows.iter().map(|(c, i)| m(c, *i).map_or(f64::NAN, |m| m.lyapunov.0)).collect())
        .f64("lyapunov_half_width", rows.iter().map(|(c, i)| m(c, *i).map_or(f64::NAN, |m| m.lyapunov.1)).collect())
        .i64("measured_periods", rows.iter().map(|(c, i)| m(c, *i).map_or(0, |m| m.periods as i64)).collect())
        .i64("interval_met", rows.iter().map(|(c, i)| m(c, *i).map_or(0, |m| m.met as i64)).collect())
        .str("stop", rows.iter().map(|(c, i)| c.stop[*i].clone()).collect())
}

/// The top of the parabola through three points whose middle one is the highest and lies
/// between the others in x; `None` when they do not make such a cap.
pub fn parabola_top(p: [(f64, f64); 3]) -> Option<(f64, f64)> {
    let [(x0, y0), (x1, y1), (x2, y2)] = p;
    if !((x0 - x1) * (x2 - x1) < 0.0 && y1 >= y0 && y1 >= y2) {
        return None;
    }
    // Newton's form y = y0 + d0 (x - x0) + a (x - x0)(x - x1).
    let d0 = (y1 - y0) / (x1 - x0);
    let a = ((y2 - y1) / (x2 - x1) - d0) / (x2 - x0);
    if a.is_nan() || a >= 0.0 {
        return None;
    }
    let x = 0.5 * (x0 + x1) - d0 / (2.0 * a);
    let y = y0 + d0 * (x - x0) + a * (x - x0) * (x - x1);
    (x.is_finite() && y.is_finite()).then_some((x, y))
}
