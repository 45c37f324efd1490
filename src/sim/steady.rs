//! Steady state under harmonic forcing (MODEL.md section 3): stroboscopic convergence,
//! period detection, then amplitudes and event counts over recorded periods.

use std::collections::VecDeque;
use std::f64::consts::PI;

use super::engine::{Bed, Engine, Quiet, State, Stop};
use super::observe::{flat, stored_energy, Both, Energy, Extrema};
use super::system::Dynamics;

/// How a steady state is sought.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyOptions {
    /// Relative change of the once-per-period state that counts as settled.
    pub tol: f64,
    /// Settled for this many periods in a row.
    pub consecutive: usize,
    pub min_periods: usize,
    pub max_periods: usize,
    /// Periods recorded once settled (rounded up to a multiple of the motion's period).
    pub record_periods: usize,
    /// Longest subharmonic recognised, in forcing periods.
    pub max_subharmonic: usize,
    /// Also integrate the energy balance over the recorded periods.
    pub energy: bool,
}

impl Default for SteadyOptions {
    fn default() -> Self {
        // The independent solver's settings (reference/independent-solver/PROVENANCE.md).
        SteadyOptions {
            tol: 1e-7,
            consecutive: 5,
            min_periods: 20,
            max_periods: 1500,
            record_periods: 10,
            max_subharmonic: 8,
            energy: false,
        }
    }
}

/// Energy terms over the recorded periods, J.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyBalance {
    pub work: f64,
    pub viscous: f64,
    pub impact: f64,
    /// Stored energy at the end minus at the start of the record.
    pub stored_change: f64,
}

impl EnergyBalance {
    /// `|work - viscous - impact - stored_change| / |work|`.
    pub fn relative_residual(&self) -> f64 {
        (self.work - self.viscous - self.impact - self.stored_change).abs() / self.work.abs().max(f64::MIN_POSITIVE)
    }
}

/// The steady state of one forcing frequency.
#[derive(Debug, Clone)]
pub struct Steady {
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Settled within `max_periods`.
    pub converged: bool,
    /// Periods simulated before recording.
    pub transient_periods: usize,
    /// Period of the motion in forcing periods (1, or a subharmonic); 0 when none was found.
    pub period: usize,
    /// Half peak-to-peak displacement of each mass, m.
    pub amplitude: Vec<f64>,
    /// Per bed, per forcing period: bottom impacts, top impacts, lift-offs.
    pub bottom_impacts: Vec<f64>,
    pub top_impacts: Vec<f64>,
    pub liftoffs: Vec<f64>,
    /// Highest flight of each bed above its bottom over the record, m.
    pub max_flight: Vec<f64>,
    /// Periods recorded.
    pub recorded_periods: usize,
    pub energy: Option<EnergyBalance>,
    /// Set when the simulation stopped early (chatter).
    pub stop: Option<Stop>,
    /// The state at the end of the record (to continue a sweep from).
    pub final_state: State,
}

/// How much larger than the tolerance the period-1 change must stay for a subharmonic.
const SUBHARMONIC_GAP: f64 = 1e3;

/// Distance of two flat states relative to `scale`, or infinity when bed states differ.
fn distance(a: &(Vec<Bed>, nalgebra::DVector<f64>), b: &(Vec<Bed>, nalgebra::DVector<f64>), scale: f64) -> f64 {
    let same = a.0.iter().zip(&b.0).all(|(x, y)| std::mem::discriminant(x) == std::mem::discriminant(y));
    if !same {
        return f64::INFINITY;
    }
    (&a.1 - &b.1).amax() / scale
}

/// Runs from `start` to a steady state and records it.
pub fn steady_state(d: &Dynamics, start: State, opts: &SteadyOptions) -> Steady {
    let engine = Engine::new(d);
    let period = 2.0 * PI / d.omega;
    let mut s = start;
    // Align the start to a multiple of the period.
    let k0 = (s.t / period).ceil();
    let mut k = k0 as usize;
    let n = d.system.dof();
    let nb = d.system.dampers.len();
    let all = (1usize << nb) - 1;
    let rest = &d.configs[all].offset;
    let keep = opts.max_subharmonic + opts.consecutive + 1;
    let mut history: VecDeque<(Vec<Bed>, nalgebra::DVector<f64>)> = VecDeque::with_capacity(keep + 1);
    let mut streak = vec![0usize; opts.max_subharmonic + 1];
    // A slowly decaying transient sampled once per period can nearly repeat after a few
    // periods (aliasing); a subharmonic is accepted only while the motion is clearly not
    // period-1, i.e. successive samples differ by far more than the tolerance.
    let mut not_period_one = 0usize;
    let mut found = 0;
    let mut stop = None;
    let mut simulated = 0;
    while simulated < opts.max_periods {
        if let Err(e) = engine.advance(&mut s, k as f64 * period, &mut Quiet) {
            stop = Some(e);
            break;
        }
        let z = flat(d, &s);
        let scale = (0..n).map(|i| (s.x[i] - rest[i]).hypot(s.v[i] / d.omega)).fold(1e-15, f64::max);
        history.push_front((s.beds.clone(), z));
        history.truncate(keep);
        for (p, st) in streak.iter_mut().enumerate().skip(1) {
            if history.len() > p && distance(&history[0], &history[p], scale) < opts.tol {
                *st += 1;
            } else {
                *st = 0;
            }
        }
        if history.len() > 1 && distance(&history[0], &history[1], scale) > SUBHARMONIC_GAP * opts.tol {
            not_period_one += 1;
        } else {
            not_period_one = 0;
        }
        simulated += 1;
        k += 1;
        if simulated >= opts.min_periods {
            let settled =
                |p: usize| streak[p] >= opts.consecutive * p && (p == 1 || not_period_one >= opts.consecutive * p);
            if let Some(p) = (1..=opts.max_subharmonic).find(|&p| settled(p)) {
                found = p;
                break;
            }
        }
    }
    let converged = found > 0;
    let period_mult = found.max(1);
    let record = opts.record_periods.div_ceil(period_mult) * period_mult;
    let mut ext = Extrema::new(n, nb);
    let mut energy = Energy::default();
    let e0 = stored_energy(d, &s);
    if stop.is_none() {
        let t_end = (k - 1 + record) as f64 * period;
        let result = if opts.energy {
            engine.advance(&mut s, t_end, &mut Both(&mut ext, &mut energy))
        } else {
            engine.advance(&mut s, t_end, &mut ext)
        };
        if let Err(e) = result {
            stop = Some(e);
        }
    }
    let per = |v: &[usize]| v.iter().map(|&c| c as f64 / record as f64).collect::<Vec<_>>();
    Steady {
        omega: d.omega,
        converged: converged && stop.is_none(),
        transient_periods: simulated,
        period: found,
        amplitude: ext.amplitudes(),
        bottom_impacts: per(&ext.bottom_impacts),
        top_impacts: per(&ext.top_impacts),
        liftoffs: per(&ext.liftoffs),
        max_flight: ext.max_flight.clone(),
        recorded_periods: record,
        energy: opts.energy.then(|| EnergyBalance {
            work: energy.work,
            viscous: energy.viscous,
            impact: energy.impact,
            stored_change: stored_energy(d, &s) - e0,
        }),
        stop,
        final_state: s,
    }
}
