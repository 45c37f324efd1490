//! Steady states: from a start to a settled motion (`steady`, `transient`), certified as a
//! periodic orbit (`orbit_search`) or recorded at length where it never settles
//! (`long_record`), and sweeps of them in frequency (`sweep`). Imports the motion and orbit
//! rooms.

pub mod irregular;
pub mod long_record;
pub mod orbit_search;
pub mod rest;
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
/// [`irregular::Measure::hand_over`] the orbit search of the plastic single-mass beds and the
/// measurement share the budget ([`irregular::handed_over`]).
pub fn steady_state(d: &Dynamics, start: State, opts: &SteadyOptions) -> Steady {
    let plain = d.system.columns.is_empty() && !long_record::applies(d);
    if let (Some(h), SteadyMethod::Orbit, true) = (opts.measure.hand_over, opts.method, plain) {
        return irregular::handed_over(d, start, opts, h);
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
