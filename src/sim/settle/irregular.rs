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
//! The record is cut and judged by [`super::statistic`] (MSER-5, batch quantiles). It grows in steps of [`STEP`] periods from
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

use super::statistic::{batch_mean, batch_quantile, mser5, Measured, Motion, ALIGN, MIN_PERIODS, PERCENTILE, STEP};
use super::steady::{EnergyBalance, Steady, SteadyOptions};
use crate::sim::motion::engine::{Engine, State, Stop};
use crate::sim::motion::observe::{stored_energy, Both, Energy, Extrema};
use crate::sim::motion::period_record::PeriodExtrema;
use crate::sim::motion::system::Dynamics;
use crate::sim::orbits::tangent::Tangent;

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

/// `st`, a point with no certified orbit, measured from its final state ([`super::statistic::Measure`]): its
/// amplitudes become the statistic (the impacts, flights and energy terms are those of the
/// whole measured record), with the measurement and the class. Returns `st` unchanged when
/// it settled, stopped, or no measurement is asked for.
pub fn measure(d: &Dynamics, st: Steady, opts: &SteadyOptions) -> Steady {
    measure_within(d, st, opts, opts.measure.budget(opts.max_periods), false).0
}

/// [`measure`] with a budget of `budget` periods, and whether the point goes back to the
/// search. `leave`: end as soon as the exponent's interval (over the record after the
/// alignment) lies below 0, or when the interval met is that of a motion judged a transient
/// ([`handed_over`]); the point then goes back.
pub(super) fn measure_within(
    d: &Dynamics,
    st: Steady,
    opts: &SteadyOptions,
    budget: usize,
    leave: bool,
) -> (Steady, bool) {
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
    let mut record = PeriodExtrema::observing(d, opts.observe);
    let mut peaks = opts.peaks.then(|| super::steady::peaks_of(d));
    let mut series = Series { amplitude: vec![Vec::new(); n], log_stretch: Vec::new() };
    let mut stop: Option<Stop> = None;
    let mut judged: Option<Measured> = None;
    let mut next = MIN_PERIODS;
    let mut k = (s.t / period).round();
    while series.log_stretch.len() < budget {
        crate::sim::motion::cancel::check();
        k += 1.0;
        let run = engine.advance(
            &mut s,
            k * period,
            &mut Both(&mut Both(&mut record, &mut peaks), &mut Both(&mut energy, &mut tangent)),
        );
        if let Err(e) = run {
            stop = Some(e);
            break;
        }
        let per = record.finish(d);
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
        peaks: peaks.map(|p| p.values()),
        ..st
    };
    (st, back)
}
