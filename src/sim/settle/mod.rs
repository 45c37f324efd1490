//! Steady states: from a start to a settled motion (`steady`, `transient`), certified as a
//! periodic orbit (`orbit_search`) or recorded at length where it never settles
//! (`long_record`), and sweeps of them in frequency (`sweep`). Imports the motion and orbit
//! rooms.

pub mod irregular;
pub mod long_record;
pub mod orbit_search;
pub mod rest;
pub mod statistic;
pub mod steady;
pub mod sweep;
pub mod transient;

use super::motion::state::State;
use super::motion::system::Dynamics;
use steady::{Steady, SteadyMethod, SteadyOptions};

/// Runs from `start` to a steady state and records it (a motion of a non-plastic bed that
/// never settles gets a long record, [`long_record`]; the paper's plastic bed's is classified
/// and measured, [`irregular`]). A system with a column of grains is
/// run by the transient method when the orbit method is asked: the linearised flow has no
/// saltation for grain-grain collisions. [`SteadyMethod::Certify`] runs the transient method
/// and then certifies its settled motion as a periodic orbit where it is one, for any bed
/// ([`orbit_search::certify`]; for a column with a Jacobian by central differences). With
/// [`statistic::Measure::hand_over`] the orbit search of the plastic single-mass beds and the
/// measurement share the budget ([`handed_over`]).
pub fn steady_state(d: &Dynamics, start: State, opts: &SteadyOptions) -> Steady {
    let plain = d.system.columns.is_empty() && !long_record::applies(d);
    if let (Some(h), SteadyMethod::Orbit, true) = (opts.measure.hand_over, opts.method, plain) {
        return handed_over(d, start, opts, h);
    }
    let st = match (opts.method, d.system.columns.is_empty()) {
        (SteadyMethod::Orbit, true) => orbit_search::orbit_steady(d, start, opts),
        (SteadyMethod::Orbit, false) | (SteadyMethod::Transient, _) => transient::transient_steady(d, start, opts),
        (SteadyMethod::Certify, _) => orbit_search::certify(d, transient::transient_steady(d, start, opts), opts),
    };
    if long_record::applies(d) {
        long_record::extend(d, st)
    } else {
        irregular::measure(d, st, opts)
    }
}

/// The orbit search and the measurement sharing one budget of `opts.max_periods` periods
/// ([`statistic::Measure::hand_over`]): the search runs at most `hand_over` periods; a point with no
/// orbit by then is measured with the rest of the budget, the measurement judged every
/// [`statistic::STEP`] periods from [`statistic::MIN_PERIODS`] ending as soon as its interval is met, or as soon as
/// the exponent's interval lies below 0 (the motion contracts: a stable orbit is near; looked
/// for every `STEP / 2` periods from `ALIGN + STEP`, before the first judgement). Then
/// the search goes on from where the measurement stopped with what is left, and a point still
/// without an orbit is measured with the rest. A chaotic or quasi-periodic point thus costs
/// `hand_over` + about [`statistic::ALIGN`] + [`statistic::MIN_PERIODS`] periods instead of the whole budget, and an
/// orbit reached later is the one the search alone would reach (the motion is the same one,
/// run on). With [`statistic::Measure::max_periods`] set, each measurement records at most
/// that many periods (a design's screen, docs/design.md). The plastic single-mass beds only
/// ([`steady_state`]).
pub fn handed_over(d: &Dynamics, start: State, opts: &SteadyOptions, hand_over: usize) -> Steady {
    let total = opts.max_periods;
    let cap = |left: usize| opts.measure.max_periods.map_or(left, |m| m.min(left));
    let first = SteadyOptions { max_periods: hand_over.min(total), ..*opts };
    let st = orbit_search::orbit_steady(d, start, &first);
    if st.converged || st.stop.is_some() {
        return st;
    }
    let spent = st.transient_periods + st.recorded_periods;
    let (m, back) = irregular::measure_within(d, st, opts, cap(total.saturating_sub(spent)), true);
    let spent = spent + m.recorded_periods;
    if !back || m.stop.is_some() || spent >= total {
        return m;
    }
    let rest = SteadyOptions { max_periods: total - spent, ..*opts };
    let again = orbit_search::orbit_steady(d, m.final_state, &rest);
    let again = Steady { transient_periods: again.transient_periods + spent, ..again };
    if again.converged || again.stop.is_some() {
        return again;
    }
    let left = total.saturating_sub(again.transient_periods + again.recorded_periods);
    irregular::measure_within(d, again, opts, cap(left), false).0
}
