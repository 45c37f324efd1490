//! The exact event-driven simulator of the structure with N shot dampers (docs/model.md
//! sections 2 and 3). Between events the motion is a closed form (one eigendecomposition
//! per configuration, computed once); events are located by a certified search; solvers
//! return data and a stop reason and do no I/O.

pub mod motion;
pub mod orbits;
pub mod settle;

// The rooms' files at the paths they always had (`sim::engine`, `sim::periodic`, ...).
pub use motion::{
    bed, buf, coarse, column, eigen, engine, forced, impulse, observe, roots, schur, segment, soft, state, system,
};
pub use orbits::{continuation, periodic, strobe, tangent};
pub use rest::steady_from_rest;
pub use settle::{long_record, orbit_search, rest, steady, steady_state, sweep, transient};

pub use engine::{Bed, Engine, Event, EventKind, Observer, Quiet, State, Stop};
pub use steady::{Steady, SteadyMethod, SteadyOptions};
pub use system::{Dynamics, SetupError, System};
