//! Motion that never settles into a certified orbit, classified and measured
//! (docs/simulator.md, "Irregular motion").
//!
//! Where the orbit search ends without a stable orbit, the motion is run on period by period
//! from where it stopped, recording for every forcing period
//!
//! - each measured mass's amplitude within the period (half its peak-to-peak displacement
//!   over that period), and
//! - the stretch of one tangent vector carried exactly through the period by the linearised
//!   flow ([`Tangent`]: closed-form segments, saltation matrices at impacts), renormalised at
//!   the period's end (Benettin et al. 1980): its logarithm's mean over the record, per
//!   second, is the largest Lyapunov exponent.
//!
//! The record's first [`ALIGN`] periods are cut, and then its start by the MSER-5 rule
//! (White 1997): the truncation that minimises
//! the standard error of the rest of the amplitude series, searched over the record's first
//! half; a record whose best cut falls in its second half is not stationary yet. The
//! statistic of a mass is the 95th percentile of its per-period amplitudes over the kept
//! record, with a 95 % interval from [`BATCHES`] batch percentiles (batch quantiles, Seila
//! 1982; a t quantile on `BATCHES - 1` degrees of freedom); the exponent's interval comes
//! from the same batches' means. The record grows in steps of [`STEP`] periods from
//! [`MIN_PERIODS`] until every measured mass's half-width is at most `tol` of the largest
//! statistic, or the budget ends (then the interval is stated as not met): by default the
//! steady state's own `max_periods`, so that a point costs at most twice its stated budget.
//!
//! Classes: an exponent whose interval lies above 0 is chaos (over the record: a chaotic
//! transient is chaos while it lasts); one whose interval contains 0 a quasi-periodic motion
//! (a torus; its exponent is 0) when the record is stationary; one below 0, or a record
//! that is not stationary, a transient not over (a motion still drawn to a stable orbit, or
//! a periodic motion whose orbit could not be certified). No I/O.

use std::f64::consts::PI;

use nalgebra::DMatrix;

use super::steady::{EnergyBalance, Steady, SteadyOptions};
use crate::sim::motion::engine::{Engine, State, Stop};
use crate::sim::motion::observe::{stored_energy, Both, Energy, Extrema};
use crate::sim::motion::system::Dynamics;
use crate::sim::orbits::tangent::Tangent;

/// Batches of the record for the intervals.
pub const BATCHES: usize = 20;

/// The 0.975 quantile of Student's t on `BATCHES - 1` = 19 degrees of freedom.
pub const T_975_19: f64 = 2.093_024_054;

/// Shortest kept record judged, forcing periods (batches of 20 periods).
pub const MIN_PERIODS: usize = 400;

/// Periods always cut from a record's start (a quarter of a shorter record's): the tangent
/// vector turns towards the most stretched direction over them (its start direction is
/// arbitrary), and the motion leaves the orbit search's end.
pub const ALIGN: usize = 50;

/// The record grows by this many periods between judgements.
pub const STEP: usize = 100;

/// The percentile of the per-period amplitudes that is the compliance of an irregular point.
pub const PERCENTILE: f64 = 0.95;

/// How an irregular motion is measured ([`SteadyOptions::measure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measure {
    /// Most forcing periods recorded; `None`: the steady state's own budget
    /// ([`SteadyOptions::max_periods`], so a point costs at most twice it); `Some(0)`: no
    /// measurement (the point keeps the orbit search's short record).
    pub max_periods: Option<usize>,
    /// Largest half-width of a statistic's 95 % interval, relative to the largest statistic.
    pub tol: f64,
    /// `Some(h)`: the orbit search hands a point with no orbit after `h` periods over to the
    /// measurement, which hands it back when the motion contracts ([`handed_over`]); the
    /// search and the measurement then share the steady state's one budget. `None`: the
    /// measurement starts where the whole search ended (the report's sweeps).
    pub hand_over: Option<usize>,
}

impl Default for Measure {
    fn default() -> Self {
        Measure { max_periods: None, tol: 0.01, hand_over: None }
    }
}

impl Measure {
    /// At most this many periods, whatever the steady state's budget.
    pub fn periods(max_periods: usize, tol: f64) -> Measure {
        Measure { max_periods: Some(max_periods), tol, hand_over: None }
    }

    /// Handed over after `hand_over` periods of the orbit search, to an interval of `tol`,
    /// within the steady state's one budget ([`handed_over`]).
    pub fn handed_over(hand_over: usize, tol: f64) -> Measure {
        Measure { max_periods: None, tol, hand_over: Some(hand_over) }
    }

    /// The budget under steady-state options of budget `steady_max`.
    pub fn budget(&self, steady_max: usize) -> usize {
        self.max_periods.unwrap_or(steady_max)
    }
}

/// What a point's motion is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// A certified periodic orbit (its period in the steady state's `period`).
    Periodic,
    /// Quasi-periodic: recognised as a torus, or an exponent indistinguishable from 0.
    QuasiPeriodic,
    /// Chaotic: the largest Lyapunov exponent's interval lies above 0.
    Chaotic,
    /// Not over within the budget: the motion contracts (exponent below 0) or its amplitude
    /// series never became stationary; or it was not measured.
    Transient,
    /// Stopped by chatter (more events in a period than allowed).
    Chatter,
    /// A bed with restitution or a column of grains that never settled: measured by its long
    /// record ([`super::long_record`]).
    Aperiodic,
}

impl Motion {
    /// The class as tables write it.
    pub fn name(&self) -> &'static str {
        match self {
            Motion::Periodic => "periodic",
            Motion::QuasiPeriodic => "quasi-periodic",
            Motion::Chaotic => "chaotic",
            Motion::Transient => "transient",
            Motion::Chatter => "chatter",
            Motion::Aperiodic => "aperiodic",
        }
    }

    /// Every class, in the order pages count them.
    pub const ALL: [Motion; 6] = [
        Motion::Periodic,
        Motion::QuasiPeriodic,
        Motion::Chaotic,
        Motion::Transient,
        Motion::Chatter,
        Motion::Aperiodic,
    ];
}

/// The measurement of an irregular point.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// Per mass: the 95th percentile of the per-period amplitudes over the kept record, m
    /// (NaN for a mass not measured).
    pub statistic: Vec<f64>,
    /// Per mass: the half-width of its 95 % interval, m.
    pub half_width: Vec<f64>,
    /// Per mass: the largest per-period amplitude over the kept record, m.
    pub largest: Vec<f64>,
    /// The largest Lyapunov exponent, 1/s.
    pub lyapunov: f64,
    /// The half-width of its 95 % interval, 1/s.
    pub lyapunov_half_width: f64,
    /// Periods kept (after the cut).
    pub periods: usize,
    /// Periods cut from the record's start ([`ALIGN`], then the transient by MSER-5).
    pub discarded: usize,
    /// The record was stationary by the MSER-5 rule.
    pub stationary: bool,
    /// Every half-width met the tolerance.
    pub met: bool,
}

impl Measured {
    /// The class the exponent gives.
    pub fn class(&self) -> Motion {
        let (lo, hi) = (self.lyapunov - self.lyapunov_half_width, self.lyapunov + self.lyapunov_half_width);
        if !self.lyapunov.is_finite() {
            Motion::Transient
        } else if lo > 0.0 {
            Motion::Chaotic
        } else if hi < 0.0 || !self.stationary {
            Motion::Transient
        } else {
            Motion::QuasiPeriodic
        }
    }

    /// The largest half-width relative to the largest statistic.
    pub fn relative_half_width(&self) -> f64 {
        let top = self.statistic.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
        let hw = self.half_width.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
        if top > 0.0 {
            hw / top
        } else {
            f64::NAN
        }
    }
}

/// The `q` quantile of `v` (linear between order statistics, the "type 7" rule); NaN when
/// empty.
pub fn quantile(v: &[f64], q: f64) -> f64 {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
    if s.is_empty() {
        return f64::NAN;
    }
    s.sort_by(f64::total_cmp);
    let h = q * (s.len() - 1) as f64;
    let (i, f) = (h.floor() as usize, h - h.floor());
    if i + 1 < s.len() {
        s[i] + f * (s[i + 1] - s[i])
    } else {
        s[i]
    }
}

/// The MSER-5 cut of a series: the number of leading values to drop, or `None` when the best
/// cut lies in the second half (the series is not stationary yet).
pub fn mser5(y: &[f64]) -> Option<usize> {
    let z: Vec<f64> = y.chunks_exact(5).map(|c| c.iter().sum::<f64>() / 5.0).collect();
    let m = z.len();
    if m < 4 {
        return None;
    }
    // Suffix sums give each cut's mean and squared deviation in O(m).
    let (mut s1, mut s2) = (vec![0.0; m + 1], vec![0.0; m + 1]);
    for j in (0..m).rev() {
        s1[j] = s1[j + 1] + z[j];
        s2[j] = s2[j + 1] + z[j] * z[j];
    }
    let mut best = (0, f64::INFINITY);
    for d in 0..m - 1 {
        let k = (m - d) as f64;
        let ss = (s2[d] - s1[d] * s1[d] / k).max(0.0);
        let v = ss / (k * k);
        if v < best.1 {
            best = (d, v);
        }
    }
    (best.0 <= m / 2).then_some(5 * best.0)
}

/// The mean of `v` and the half-width of its 95 % interval from [`BATCHES`] batch means
/// (NaN for fewer than [`BATCHES`] values).
pub fn batch_mean(v: &[f64]) -> (f64, f64) {
    let b = v.len() / BATCHES;
    let mean = if v.is_empty() { f64::NAN } else { v.iter().sum::<f64>() / v.len() as f64 };
    if b == 0 {
        return (mean, f64::NAN);
    }
    let means: Vec<f64> = v.chunks_exact(b).take(BATCHES).map(|c| c.iter().sum::<f64>() / b as f64).collect();
    (mean, half_width(&means))
}

/// The `q` quantile of `v` over the whole and the half-width of its 95 % interval from
/// [`BATCHES`] batch quantiles (NaN for fewer than [`BATCHES`] values).
pub fn batch_quantile(v: &[f64], q: f64) -> (f64, f64) {
    let b = v.len() / BATCHES;
    if b == 0 {
        return (quantile(v, q), f64::NAN);
    }
    let qs: Vec<f64> = v.chunks_exact(b).take(BATCHES).map(|c| quantile(c, q)).collect();
    (quantile(v, q), half_width(&qs))
}

/// `t s / sqrt(k)` of `k` = [`BATCHES`] batch values.
fn half_width(batches: &[f64]) -> f64 {
    let k = batches.len() as f64;
    let mean = batches.iter().sum::<f64>() / k;
    let var = batches.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (k - 1.0);
    T_975_19 * (var / k).sqrt()
}

/// The norm of a tangent vector with velocities scaled by `1 / omega` (displacement units
/// throughout; the exponent does not depend on the norm).
fn norm(m: &DMatrix<f64>, n: usize, beds: usize, omega: f64) -> f64 {
    let mut s = 0.0;
    for i in 0..n {
        s += m[(i, 0)].powi(2) + (m[(n + i, 0)] / omega).powi(2);
    }
    for j in 0..beds {
        let r = 2 * n + 2 * j;
        s += m[(r, 0)].powi(2) + (m[(r + 1, 0)] / omega).powi(2);
    }
    s.sqrt()
}

/// The series of one record: per period, each mass's amplitude and the log stretch.
struct Series {
    amplitude: Vec<Vec<f64>>,
    log_stretch: Vec<f64>,
}

impl Series {
    /// The exponent's interval over the record after the alignment lies below 0.
    fn contracting(&self) -> bool {
        let (l, h) = batch_mean(&self.log_stretch[ALIGN.min(self.log_stretch.len())..]);
        l + h < 0.0
    }

    /// The measurement over the record so far, cut by MSER-5 on the mass with the largest
    /// mean amplitude.
    fn judge(&self, observed: &[usize], period: f64, tol: f64) -> Measured {
        let n = self.amplitude.len();
        let len = self.log_stretch.len();
        let lead = observed.iter().copied().max_by(|&a, &b| {
            let mean = |i: usize| self.amplitude[i].iter().sum::<f64>();
            mean(a).total_cmp(&mean(b))
        });
        // A record shorter than four alignments (a small stated budget) cuts a quarter.
        let align = ALIGN.min(len / 4);
        let cut = lead.map_or(Some(0), |i| mser5(&self.amplitude[i][align..]));
        let stationary = cut.is_some();
        let from = (align + cut.unwrap_or((len - align) / 2)).min(len);
        let mut statistic = vec![f64::NAN; n];
        let mut half = vec![f64::NAN; n];
        let mut largest = vec![f64::NAN; n];
        for &i in observed {
            let kept = &self.amplitude[i][from..];
            let (s, h) = batch_quantile(kept, PERCENTILE);
            statistic[i] = s;
            half[i] = h;
            largest[i] = kept.iter().copied().fold(f64::NAN, f64::max);
        }
        let (l, lh) = batch_mean(&self.log_stretch[from..]);
        let top = statistic.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
        let met = stationary
            && len - from >= MIN_PERIODS
            && observed.iter().all(|&i| half[i].is_finite() && half[i] <= tol * top);
        Measured {
            statistic,
            half_width: half,
            largest,
            lyapunov: l / period,
            lyapunov_half_width: lh / period,
            periods: len - from,
            discarded: from,
            stationary,
            met,
        }
    }
}

/// `st`, a point with no certified orbit, measured from its final state ([`Measure`]): its
/// amplitudes become the statistic (the impacts, flights and energy terms are those of the
/// whole measured record), with the measurement and the class. Returns `st` unchanged when
/// it settled, stopped, or no measurement is asked for.
pub fn measure(d: &Dynamics, st: Steady, opts: &SteadyOptions) -> Steady {
    measure_within(d, st, opts, opts.measure.budget(opts.max_periods), false).0
}

/// The orbit search and the measurement sharing one budget of `opts.max_periods` periods
/// ([`Measure::hand_over`]): the search runs at most `hand_over` periods; a point with no
/// orbit by then is measured with the rest of the budget, the measurement judged every
/// [`STEP`] periods from [`MIN_PERIODS`] ending as soon as its interval is met, or as soon as
/// the exponent's interval lies below 0 (the motion contracts: a stable orbit is near; looked
/// for every `STEP / 2` periods from `ALIGN + STEP`, before the first judgement). Then
/// the search goes on from where the measurement stopped with what is left, and a point still
/// without an orbit is measured with the rest. A chaotic or quasi-periodic point thus costs
/// `hand_over` + about [`ALIGN`] + [`MIN_PERIODS`] periods instead of the whole budget, and an
/// orbit reached later is the one the search alone would reach (the motion is the same one,
/// run on). The plastic single-mass beds only ([`super::steady_state`]).
pub fn handed_over(d: &Dynamics, start: State, opts: &SteadyOptions, hand_over: usize) -> Steady {
    let total = opts.max_periods;
    let first = SteadyOptions { max_periods: hand_over.min(total), ..*opts };
    let st = super::orbit_search::orbit_steady(d, start, &first);
    if st.converged || st.stop.is_some() {
        return st;
    }
    let spent = st.transient_periods + st.recorded_periods;
    let (m, back) = measure_within(d, st, opts, total.saturating_sub(spent), true);
    let spent = spent + m.recorded_periods;
    if !back || m.stop.is_some() || spent >= total {
        return m;
    }
    let rest = SteadyOptions { max_periods: total - spent, ..*opts };
    let again = super::orbit_search::orbit_steady(d, m.final_state, &rest);
    let again = Steady { transient_periods: again.transient_periods + spent, ..again };
    if again.converged || again.stop.is_some() {
        return again;
    }
    let left = total.saturating_sub(again.transient_periods + again.recorded_periods);
    measure_within(d, again, opts, left, false).0
}

/// [`measure`] with a budget of `budget` periods, and whether the point goes back to the
/// search. `leave`: end as soon as the exponent's interval (over the record after the
/// alignment) lies below 0, or when the interval met is that of a motion judged a transient
/// ([`handed_over`]); the point then goes back.
fn measure_within(d: &Dynamics, st: Steady, opts: &SteadyOptions, budget: usize, leave: bool) -> (Steady, bool) {
    if st.converged || st.stop.is_some() || budget == 0 {
        return (st, false);
    }
    let mut back = false;
    let (n, nb) = (d.system.dof(), d.system.dampers.len());
    let observed: Vec<usize> = (0..n).filter(|&i| opts.observe.contains(i)).collect();
    let period = 2.0 * PI / d.omega;
    let engine = Engine::new(d);
    let mut s: State = st.final_state.clone();
    let full = Tangent::full_dim(d);
    // A start direction with every coordinate in it (fixed: the same record for any thread).
    let start = DMatrix::from_fn(full, 1, |r, _| 1.0 + 0.1 * ((r * 7 + 3) % 11) as f64);
    let mut tangent = Tangent::new(d, start.clone());
    let first = norm(&tangent.m, n, nb, d.omega);
    tangent.m /= first;
    let mut energy = opts.energy.then(Energy::default);
    let e0 = if opts.energy { stored_energy(d, &s) } else { 0.0 };
    // The whole record's counts and flights, gathered from the periods' (its largest
    // amplitude over the kept record is the periods' largest, `Measured::largest`).
    let mut whole = Extrema::observing(n, nb, opts.observe);
    let mut series = Series { amplitude: vec![Vec::new(); n], log_stretch: Vec::new() };
    let mut stop: Option<Stop> = None;
    let mut judged: Option<Measured> = None;
    let mut next = MIN_PERIODS;
    let mut k = (s.t / period).round();
    while series.log_stretch.len() < budget {
        crate::sim::motion::cancel::check();
        k += 1.0;
        let mut per = Extrema::observing(n, nb, opts.observe);
        let run = match &mut energy {
            Some(e) => engine.advance(&mut s, k * period, &mut Both(&mut per, &mut Both(e, &mut tangent))),
            None => engine.advance(&mut s, k * period, &mut Both(&mut per, &mut tangent)),
        };
        if let Err(e) = run {
            stop = Some(e);
            break;
        }
        let a = per.amplitudes();
        for &i in &observed {
            series.amplitude[i].push(a[i]);
        }
        for j in 0..nb {
            whole.bottom_impacts[j] += per.bottom_impacts[j];
            whole.top_impacts[j] += per.top_impacts[j];
            whole.liftoffs[j] += per.liftoffs[j];
            whole.max_flight[j] = whole.max_flight[j].max(per.max_flight[j]);
        }
        let g = norm(&tangent.m, n, nb, d.omega);
        if g.is_finite() && g > 0.0 {
            series.log_stretch.push(g.ln());
            tangent.m /= g;
        } else {
            // The vector was annihilated (a plastic impact's kernel) or blew up (a graze):
            // counted as the strongest contraction or stretch representable, and restarted.
            series.log_stretch.push(if g > 0.0 { f64::MAX.ln() } else { f64::MIN_POSITIVE.ln() });
            tangent = Tangent::new(d, start.clone());
            tangent.m /= first;
        }
        let len = series.log_stretch.len();
        // Handed over: a motion that contracts goes back to the search as soon as it shows
        // (every half step from a step after the alignment), not at the first judgement.
        if leave && len < next && len >= ALIGN + STEP && len % (STEP / 2) == 0 && series.contracting() {
            judged = Some(series.judge(&observed, period, opts.measure.tol));
            back = true;
            break;
        }
        if len >= next || len == budget {
            let m = series.judge(&observed, period, opts.measure.tol);
            back = leave && (series.contracting() || (m.met && m.class() == Motion::Transient));
            let done = m.met || back;
            judged = Some(m);
            if done {
                break;
            }
            next = len + STEP;
        }
    }
    let recorded = series.log_stretch.len();
    if stop.is_some() || recorded == 0 {
        // Chatter during the measurement: the point keeps its short record and says so.
        return (Steady { stop, motion: Motion::Chatter, ..st }, false);
    }
    let measured = judged.unwrap_or_else(|| series.judge(&observed, period, opts.measure.tol));
    let per = |v: &[usize]| v.iter().map(|&c| c as f64 / recorded as f64).collect::<Vec<_>>();
    let motion = measured.class();
    let st = Steady {
        converged: false,
        certificate: None,
        transient_periods: st.transient_periods + st.recorded_periods + measured.discarded,
        period: 0,
        amplitude: measured.statistic.clone(),
        bottom_impacts: per(&whole.bottom_impacts),
        top_impacts: per(&whole.top_impacts),
        liftoffs: per(&whole.liftoffs),
        max_flight: whole.max_flight.clone(),
        recorded_periods: recorded,
        energy: energy.map(|e| EnergyBalance {
            work: e.work,
            viscous: e.viscous,
            impact: e.impact,
            stored_change: stored_energy(d, &s) - e0,
        }),
        stop: None,
        final_state: s,
        motion,
        measured: Some(measured),
        ..st
    };
    (st, back)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_follow_the_type_7_rule() {
        let v = [3.0, 1.0, 2.0, 5.0, 4.0];
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert!((quantile(&v, 0.95) - 4.8).abs() < 1e-12);
    }

    /// MSER-5 cuts a decaying start and keeps a stationary series whole; a trend to the end
    /// is not stationary.
    #[test]
    fn mser5_cuts_the_transient() {
        let noise = |i: usize| ((i * 7919 % 101) as f64 / 101.0 - 0.5) * 0.1;
        let settled: Vec<f64> = (0..500).map(|i| 1.0 + noise(i)).collect();
        assert!(mser5(&settled).is_some_and(|d| d < 50), "{:?}", mser5(&settled));
        let decaying: Vec<f64> = (0..500).map(|i| 1.0 + 5.0 * (-(i as f64) / 30.0).exp() + noise(i)).collect();
        let cut = mser5(&decaying).unwrap();
        assert!((60..=250).contains(&cut), "{cut}");
        let trend: Vec<f64> = (0..500).map(|i| i as f64 + noise(i)).collect();
        assert_eq!(mser5(&trend), None);
    }

    /// Independent normal-ish samples: the batch interval covers the true mean about 95 % of
    /// the time over many records (coverage, not a single draw).
    #[test]
    fn batch_means_cover_the_mean() {
        let mut state = 12345u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut covered = 0;
        for _ in 0..400 {
            // Sum of 12 uniforms minus 6: mean 0, variance 1.
            let v: Vec<f64> = (0..400).map(|_| (0..12).map(|_| uniform()).sum::<f64>() - 6.0).collect();
            let (m, h) = batch_mean(&v);
            covered += (m.abs() <= h) as usize;
        }
        assert!((360..=395).contains(&covered), "{covered} of 400");
    }
}
