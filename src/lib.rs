//! shotdamp replicates Araki et al. (1997), "Impact damper with granular materials for
//! multibody system", figure by figure.
//!
//! Data flows one way:
//! `experiments/*.toml` -> [`experiment`] (load + validate) -> [`analysis`] (run the
//! solvers of [`model`], check against [`checks::reference`]) -> [`output`] (tables,
//! plots, HTML report). Analyses hand results over as [`table::Table`]s and [`figure::Figure`]s,
//! plain data below both. Physics knows nothing of files; rendering knows nothing of physics.

pub mod analysis;
pub mod checks;
pub mod cli;
pub mod design;
pub mod error;
pub mod experiment;
pub mod figure;
pub mod model;
pub mod number;
pub mod output;
pub mod reference;
pub mod runner;
pub mod signal;
pub mod sim;
pub mod table;

pub use error::{Error, Result};
