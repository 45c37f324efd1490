//! A layout's sweeps, band by band and scenario by scenario: what [`super::evaluate`] and
//! [`super::band_compliance`] gather. No I/O.

use super::*;
use crate::sim::motion::system::{Dynamics, SetupError};
use crate::sim::settle::statistic::{self, ClassCounts, Motion as Class};
use crate::sim::settle::sweep::{self, Direction, SweepPoint};
use crate::sim::{SteadyOptions, System};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A band's sweeps of one layout.
pub(super) struct BandRun {
    /// Per frequency and mass: the largest compliance over the sweeps.
    pub(super) compliance: Vec<Vec<f64>>,
    /// Per frequency and mass: the point that set it.
    pub(super) points: Vec<Vec<Point>>,
    pub(super) unsettled: usize,
    pub(super) motion: Motion,
    pub(super) classes: ClassCounts,
    pub(super) measured: usize,
    /// Points measured over their screen only: they cannot be the band's highest
    /// ([`race::measure_on`]).
    pub(super) screened: usize,
}

/// Where a layout's evaluation may end early: once a certified orbit of a band's mass has a
/// compliance whose ratio to the band's bare measure `bare` is finite and above `objective`
/// (the comparison the evaluation feeds, [`super::evaluate_below`]), the band's peak relative
/// to the bare one, and so the objective, are above it whatever the rest gives (the ratio is
/// formed as the objective's is, so rounding cannot tell them apart); `reached` tells every
/// sweep of the evaluation.
pub(super) struct Over<'a> {
    pub(super) objective: f64,
    pub(super) bare: f64,
    pub(super) reached: &'a AtomicBool,
}

impl Over<'_> {
    /// Whether the sweeps can end after `p`: it or an earlier point of any sweep showed the
    /// objective above the comparison. Only a certified periodic orbit counts (a measured
    /// point's statistic may still move with its measurement).
    fn after(&self, p: &SweepPoint, band: &Band, steady: &SteadyOptions, drive: f64) -> bool {
        if self.reached.load(Ordering::Relaxed) {
            return true;
        }
        let Ok(st) = &p.result else { return false };
        let over = st.converged
            && st.motion == Class::Periodic
            && st.measured.is_none()
            && band.masses.iter().any(|&m| {
                let ratio = |a: &f64| a / drive / self.bare;
                steady.observe.contains(m)
                    && st.amplitude.get(m).map(ratio).is_some_and(|r| r.is_finite() && r > self.objective)
            });
        if over {
            self.reached.store(true, Ordering::Relaxed);
        }
        over
    }
}

/// [`band_compliance`] of a system already decomposed (`base`, [`Dynamics::unforced`] of
/// `sys`): every band and sweep of one layout shares one decomposition. With `over`, the
/// continued sweeps end where [`Over`] says (their numbers are then not the band's, and
/// `over.reached` says so).
pub(super) fn band_compliance_on(
    base: &Result<Dynamics, SetupError>,
    sys: &System,
    band: &Band,
    sweeps: &[Sweep],
    steady: &SteadyOptions,
    peak: bool,
    over: Option<&Over>,
) -> BandRun {
    let n = sys.dof();
    // A point with no orbit after HAND_OVER periods is measured as irregular motion within the
    // same budget, to the design's tolerance (docs/design.md); steady settings that state a
    // measurement of their own keep it (`Measure::periods(0, _)`: none, the short record).
    // For a peak measure, where the budget leaves room, first over a screen only: the points
    // that may be the band's highest are then measured on ([`race::measure_on`]).
    let stated = steady.measure != statistic::Measure::default();
    let screen = (peak && !stated).then(|| race::screen(HAND_OVER, INTERVAL_TOL, steady.max_periods)).flatten();
    let measure = match (stated, screen) {
        (true, _) => steady.measure,
        (false, Some(m)) => m,
        (false, None) => statistic::Measure::handed_over(HAND_OVER, INTERVAL_TOL),
    };
    let steady = &SteadyOptions { measure, ..*steady };
    // Per unit drive: the force, or on moving supports their acceleration.
    let drive = sys.drive();
    let mut worst = vec![vec![0.0f64; n]; band.freq_hz.len()];
    let mut behind = vec![vec![Point::default(); n]; band.freq_hz.len()];
    // Per frequency and mass: the lowest over the sweeps, and how many sweeps gave a value.
    let mut least = vec![vec![(f64::INFINITY, Class::Periodic, 0.0f64); n]; band.freq_hz.len()];
    let mut given = vec![0usize; band.freq_hz.len()];
    let mut unsettled = 0;
    let mut motion = Motion::default();
    let mut classes = ClassCounts::default();
    let mut measured = 0;
    // The dynamics at each frequency, shared by the continued sweeps; the sweeps run side by
    // side and are gathered in order.
    let forced = sweeps.iter().any(|s| *s != Sweep::Rest).then(|| sweep::forced_at(base, &band.freq_hz));
    let mut swept: Vec<Vec<SweepPoint>> = sweeps
        .par_iter()
        .map(|s| {
            let enough = |p: &SweepPoint| over.is_some_and(|o| o.after(p, band, steady, drive));
            let continued =
                |dir| sweep::continued_until(forced.as_deref().unwrap_or_default(), dir, steady, &|| {}, &enough);
            match s {
                Sweep::Rest => sweep::from_rest_on(base, &band.freq_hz, steady, &|| {}),
                Sweep::Up => continued(Direction::Up),
                Sweep::Down => continued(Direction::Down),
            }
        })
        .collect();
    // Per sweep and point: measured over its screen only.
    // Ended early, nothing here is the band's, so nothing is measured on.
    let ended = over.is_some_and(|o| o.reached.load(Ordering::Relaxed));
    let aside = match (screen.filter(|_| !ended), &forced) {
        (None, _) => swept.iter().map(|s| vec![false; s.len()]).collect(),
        (Some(_), Some(f)) => race::measure_on(f, &mut swept, band, steady),
        (Some(_), None) => race::measure_on(&sweep::forced_at(base, &band.freq_hz), &mut swept, band, steady),
    };
    let screened = aside.iter().flatten().filter(|&&a| a).count();
    for (points, aside) in swept.into_iter().zip(aside) {
        for (p, screened) in points.into_iter().zip(aside) {
            let Some(i) = band.freq_hz.iter().position(|f| *f == p.freq_hz) else { continue };
            motion.points += 1;
            match p.result {
                Ok(st) => {
                    if !st.converged {
                        unsettled += 1;
                    }
                    classes[st.motion.index()] += 1;
                    measured += usize::from(st.measured.is_some());
                    let half = |m: usize| st.measured.as_ref().map_or(0.0, |x| x.half_width[m] / drive);
                    if st.liftoffs.iter().any(|&l| l > 0.0) || st.max_flight.iter().any(|&f| f > 0.0) {
                        motion.lifting += 1;
                    }
                    motion.flight_m = st.max_flight.iter().fold(motion.flight_m, |a, &f| a.max(f));
                    // An amplitude that was never measured (a run stopped by chatter before
                    // its record) counts as a point without a steady state at all.
                    // A mass not measured ([`SteadyOptions::observe`]) has no compliance.
                    given[i] += 1;
                    for (m, (w, a)) in worst[i].iter_mut().zip(&st.amplitude).enumerate() {
                        let was = *w;
                        if steady.observe.contains(m) && a / drive < least[i][m].0 {
                            least[i][m] = (a / drive, st.motion, half(m));
                        }
                        *w = match steady.observe.contains(m) {
                            false => f64::NAN,
                            true if a.is_nan() => f64::INFINITY,
                            true => w.max(a / drive),
                        };
                        if *w != was || (a / drive == *w && st.motion != Class::Periodic) {
                            behind[i][m] =
                                Point { class: st.motion, half_width: half(m), screened, ..Point::default() };
                        }
                    }
                }
                Err(_) => {
                    unsettled += 1;
                    classes[Class::Transient.index()] += 1;
                    worst[i].iter_mut().for_each(|w| *w = f64::INFINITY);
                    behind[i].iter_mut().for_each(|p| *p = Point { class: Class::Transient, ..Point::default() });
                }
            }
        }
    }
    for ((row, low), &k) in behind.iter_mut().zip(&least).zip(&given) {
        for (p, &(v, class, half)) in row.iter_mut().zip(low) {
            if k > 1 && v.is_finite() {
                (p.lowest, p.lowest_class, p.lowest_half_width) = (v, class, half);
            }
        }
    }
    BandRun { compliance: worst, points: behind, unsettled, motion, classes, measured, screened }
}

/// One scenario of a layout.
pub(super) struct ScenarioRun {
    /// Per band: its measure.
    pub(super) bands: Vec<f64>,
    /// The worst band's measure relative to the bare structure's.
    pub(super) relative: f64,
    /// Band, frequency (Hz) and mass of the worst band's largest compliance.
    pub(super) worst: (usize, f64, usize),
    pub(super) unsettled: usize,
    pub(super) points: usize,
    /// Per band, frequency and mass: the compliance.
    pub(super) curves: Vec<Vec<Vec<f64>>>,
    /// Per band, frequency and mass: the point behind it.
    pub(super) point_classes: Vec<Vec<Vec<Point>>>,
    /// Per band: how the beds moved.
    pub(super) motion: Vec<Motion>,
    /// Per band: its measure's half-width.
    pub(super) bands_half_width: Vec<f64>,
    /// The half-width of `relative`.
    pub(super) half_width: f64,
    pub(super) classes: ClassCounts,
    pub(super) measured: usize,
    pub(super) screened: usize,
}

/// One scenario of a layout: its bands' measures, its objective, where the worst is. With
/// `over` (an objective and a flag), its sweeps end once a certified orbit shows the objective
/// above it ([`Over`]; the flag then says that the numbers are not the scenario's).
pub(super) fn scenario(
    problem: &Problem,
    sc: &Scenario,
    bare: &[f64],
    layout: &Layout,
    over: Option<(f64, &AtomicBool)>,
) -> ScenarioRun {
    let sys = problem.system(sc, layout.dampers(problem.direction));
    let mut bands = Vec::with_capacity(problem.bands.len());
    let mut worst = (f64::NEG_INFINITY, (0, 0.0, 0));
    let mut unsettled = 0;
    let mut points = 0;
    let mut curves = Vec::with_capacity(problem.bands.len());
    let mut motion = Vec::with_capacity(problem.bands.len());
    let mut all_points = Vec::with_capacity(problem.bands.len());
    let mut bands_half_width = Vec::with_capacity(problem.bands.len());
    let mut half_width = 0.0;
    let mut classes = ClassCounts::default();
    let mut measured = 0;
    let mut screened = 0;
    let base = Dynamics::unforced(&sys);
    // The bands side by side, gathered in order.
    let swept: Vec<_> = problem
        .bands
        .par_iter()
        .zip(bare)
        .map(|(band, &bare)| {
            let over = over.map(|(objective, reached)| Over { objective, bare, reached });
            let peak = problem.measure == Measure::Peak;
            band_compliance_on(&base, &sys, band, &problem.sweeps, &problem.steady, peak, over.as_ref())
        })
        .collect();
    for ((k, band), run) in problem.bands.iter().enumerate().zip(swept) {
        unsettled += run.unsettled;
        motion.push(run.motion);
        classes.iter_mut().zip(run.classes).for_each(|(a, b)| *a += b);
        measured += run.measured;
        screened += run.screened;
        points += band.freq_hz.len() * problem.sweeps.len();
        let (value, i, m) = measure(band, &run.compliance, problem.measure);
        let hw = measure_half_width(band, &run.points, (i, m), problem.measure);
        bands.push(value);
        bands_half_width.push(hw);
        let relative = value / bare[k];
        if relative > worst.0 || relative.is_nan() {
            worst = (relative, (k, band.freq_hz[i], m));
            half_width = hw / bare[k];
        }
        curves.push(run.compliance);
        all_points.push(run.points);
    }
    ScenarioRun {
        bands,
        relative: worst.0,
        worst: worst.1,
        unsettled,
        points,
        curves,
        point_classes: all_points,
        motion,
        bands_half_width,
        half_width,
        classes,
        measured,
        screened,
    }
}
