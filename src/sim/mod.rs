//! The exact event-driven simulator of the structure with N shot dampers (docs/model.md
//! sections 2 and 3). Between events the motion is a closed form (one eigendecomposition
//! per configuration, computed once); events are located by a certified search; solvers
//! return data and a stop reason and do no I/O.

pub mod motion;
pub mod orbits;
pub mod record;
pub mod settle;

// The types and entry points most callers need, at the top; every module has one path,
// under its room (`sim::motion::engine`, `sim::orbits::periodic`, `sim::settle::sweep`).
pub use motion::engine::{Bed, Engine, Event, EventKind, Observer, Quiet, State, Stop};
pub use motion::system::{Dynamics, SetupError, System};
pub use settle::rest::steady_from_rest;
pub use settle::steady::{Steady, SteadyMethod, SteadyOptions};
pub use settle::steady_state;
