//! The response of a motion that is not periodic (docs/simulator.md, "Steady state"): when a
//! bed with restitution or a column of grains never settles into a periodic motion, the
//! response is the amplitude of the structure over a long record of stated length, and that
//! record shows whether the number has converged: the amplitudes of its second half must
//! agree with those of the whole record to [`LONG_RECORD_TOL`]. Every table flags such a
//! point (`converged` 0, its `stop` text begins "aperiodic"). The paper's plastic bed is left
//! as it is: its unsettled points keep their short record.

use std::f64::consts::PI;

use super::steady::{EnergyBalance, NoSteady, Steady};
use crate::sim::motion::engine::Engine;
use crate::sim::motion::observe::{stored_energy, Both, Energy, Extrema};
use crate::sim::motion::system::Dynamics;

pub use super::steady::{LONG_RECORD_PERIODS, LONG_RECORD_TOL};

/// Whether a system's unsettled points get the long record: any bed that is not the paper's
/// plastic single mass.
pub fn applies(d: &Dynamics) -> bool {
    !d.system.columns.is_empty() || d.system.laws.iter().any(|l| !l.is_plastic())
}

/// `st` with its record replaced by a long one, when it did not settle and its system is
/// not the paper's; else `st` unchanged.
pub fn extend(d: &Dynamics, st: Steady) -> Steady {
    if st.converged || st.stop.is_some() || !applies(d) {
        return st;
    }
    let (n, nb) = (d.system.dof(), d.system.dampers.len());
    let period = 2.0 * PI / d.omega;
    let mut s = st.final_state.clone();
    let t0 = s.t;
    let half = LONG_RECORD_PERIODS / 2;
    let mut whole = Extrema::new(n, nb);
    let mut second = Extrema::new(n, nb);
    let mut energy = Energy::default();
    let e0 = stored_energy(d, &s);
    let engine = Engine::new(d);
    // The storeys' drifts and floors' accelerations over the whole long record, when the
    // short one had them.
    let mut peaks = st.peaks.as_ref().map(|_| super::steady::peaks_of(d));
    let first =
        engine.advance(&mut s, t0 + half as f64 * period, &mut Both(&mut Both(&mut whole, &mut energy), &mut peaks));
    let rest = first.and_then(|_| {
        engine.advance(
            &mut s,
            t0 + LONG_RECORD_PERIODS as f64 * period,
            &mut Both(&mut Both(&mut Both(&mut whole, &mut second), &mut energy), &mut peaks),
        )
    });
    if let Err(stop) = rest {
        return Steady { stop: Some(stop), ..st };
    }
    let a = whole.amplitudes();
    let b = second.amplitudes();
    let scale = a.iter().copied().fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let spread = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale;
    let per = |v: &[usize]| v.iter().map(|&c| c as f64 / LONG_RECORD_PERIODS as f64).collect::<Vec<_>>();
    Steady {
        failure: Some(NoSteady::Aperiodic { periods: LONG_RECORD_PERIODS, spread, after: st.transient_periods }),
        amplitude: a,
        bottom_impacts: per(&whole.bottom_impacts),
        top_impacts: per(&whole.top_impacts),
        liftoffs: per(&whole.liftoffs),
        max_flight: whole.max_flight.clone(),
        recorded_periods: LONG_RECORD_PERIODS,
        energy: st.energy.map(|_| EnergyBalance {
            work: energy.work,
            viscous: energy.viscous,
            impact: energy.impact,
            stored_change: stored_energy(d, &s) - e0,
        }),
        final_state: s,
        motion: super::statistic::Motion::Aperiodic,
        peaks: peaks.map(|p| p.values()),
        ..st
    }
}
