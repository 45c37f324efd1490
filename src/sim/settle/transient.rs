//! The transient rule (docs/simulator.md, "Steady state"): run until the once-per-period
//! samples of the state settle to a tolerance, recognise subharmonics, then record. Kept to
//! compare with the orbit method; its cost and its error grow as 1/damping.

use std::collections::VecDeque;
use std::f64::consts::PI;

use super::steady::{amplitude_scale, finish, NoSteady, Outcome, Steady, SteadyMethod, SteadyOptions, WholePeriods};
use crate::sim::motion::engine::{Bed, Engine, Quiet, State};
use crate::sim::motion::observe::flat;
use crate::sim::motion::system::Dynamics;

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

/// The transient method: run until the once-per-period samples settle, then record.
pub fn transient_steady(d: &Dynamics, start: State, opts: &SteadyOptions) -> Steady {
    let engine = Engine::new(d);
    let period = 2.0 * PI / d.omega;
    let mut s = start;
    // Align the start to a multiple of the period.
    let k0 = (s.t / period).ceil();
    let mut k = k0 as usize;
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
    let mut whole = WholePeriods::new(&s);
    while simulated < opts.max_periods {
        crate::sim::motion::cancel::check();
        whole.begin(&s);
        let end = k as f64 * period;
        if let Err(e) = engine.advance(&mut s, end, &mut Quiet) {
            stop = Some(e);
            break;
        }
        whole.completed(end);
        let z = flat(d, &s);
        let scale = amplitude_scale(d, &s);
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
    let t_end = (k - 1 + record) as f64 * period;
    let outcome = Outcome {
        method: SteadyMethod::Transient,
        converged,
        certificate: None,
        failure: (!converged && stop.is_none()).then_some(NoSteady::Budget { periods: simulated }),
        transient_periods: simulated,
        period: found,
        record,
        last_whole: whole.last(stop.is_some()),
        stop,
    };
    finish(d, s, t_end, opts, outcome)
}
