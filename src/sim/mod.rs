//! The exact event-driven simulator of the structure with N shot dampers (docs/model.md
//! sections 2 and 3). Between events the motion is a closed form (one eigendecomposition
//! per configuration, computed once); events are located by a certified search; solvers
//! return data and a stop reason and do no I/O.

pub mod bed;
pub mod buf;
pub mod coarse;
pub mod column;
pub mod continuation;
pub mod eigen;
pub mod engine;
pub mod forced;
pub mod impulse;
pub mod long_record;
pub mod observe;
pub mod orbit_search;
pub mod periodic;
pub mod roots;
pub mod schur;
pub mod segment;
mod single;
pub mod soft;
pub mod state;
pub mod steady;
pub mod strobe;
pub mod sweep;
pub mod system;
pub mod tangent;
pub mod transient;

pub use engine::{Bed, Engine, Event, EventKind, Observer, Quiet, State, Stop};
pub use steady::{Steady, SteadyMethod, SteadyOptions};
pub use system::{Dynamics, SetupError, System};

/// Runs from `start` to a steady state and records it (a motion of a non-plastic bed that
/// never settles gets a long record, [`long_record`]). A system with a column of grains is
/// run by the transient method when the orbit method is asked: the linearised flow has no
/// saltation for grain-grain collisions. [`SteadyMethod::Certify`] runs the transient method
/// and then certifies its settled motion as a periodic orbit where it is one, for any bed
/// ([`orbit_search::certify`]; for a column with a Jacobian by central differences).
pub fn steady_state(d: &Dynamics, start: State, opts: &SteadyOptions) -> Steady {
    let st = match (opts.method, d.system.columns.is_empty()) {
        (SteadyMethod::Orbit, true) => orbit_search::orbit_steady(d, start, opts),
        (SteadyMethod::Orbit, false) | (SteadyMethod::Transient, _) => transient::transient_steady(d, start, opts),
        (SteadyMethod::Certify, _) => orbit_search::certify(d, transient::transient_steady(d, start, opts), opts),
    };
    long_record::extend(d, st)
}
