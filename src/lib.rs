//! shotdamp replicates Araki et al. (1997), "Impact damper with granular materials for
//! multibody system", figure by figure.
//!
//! Data flows one way:
//! `experiments/*.toml` -> [`experiment`] (load + validate) -> [`analysis`] (run the
//! solvers of [`model`], check against [`checks::reference`]) -> [`output`] (tables,
//! plots, HTML report). Analyses hand results over as [`table::Table`]s and [`figure::Figure`]s,
//! plain data below both. Physics knows nothing of files; rendering knows nothing of physics.
//! [`runner`] runs experiment files into a report as the command line does
//! ([`runner::report`]: the whole report); [`experiment::parts`] builds a structure, dampers
//! and settings from the keys of an experiment file, with the files' validation and messages
//! (what the Python package in `python/` calls).
//!
//! # From Rust
//!
//! The paper's structure and its natural frequencies (docs/model.md):
//!
//! ```
//! use shotdamp::model::modal::modal_summary;
//! use shotdamp::model::{Damping, Structure};
//!
//! let paper = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
//! let modes = modal_summary(&paper, &[]);
//! assert_eq!(modes.len(), 3);
//! assert!(modes[0].freq_hz > 10.0 && modes[0].freq_hz < modes[1].freq_hz);
//! ```
//!
//! A steady state as a certified periodic orbit: one bed of 10 % of m2 with a 0.3 mm
//! clearance, 2.6 N on m1 at 48 Hz; with its Floquet multipliers and residual:
//!
//! ```
//! use std::f64::consts::PI;
//! use shotdamp::model::{Clearance, Damper, Damping, Structure};
//! use shotdamp::sim::{steady_state, Dynamics, State, SteadyOptions, System};
//!
//! let paper = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
//! let bed = Damper::new(1, 0.071, Clearance::from_mm(0.3));
//! let system = System::plastic(paper, vec![bed], 0, 2.6);
//! let d = Dynamics::new(&system, 2.0 * PI * 48.0).unwrap();
//! let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
//! let orbit = st.certificate.as_ref().expect("a periodic orbit");
//! assert!(st.converged && orbit.stable && orbit.residual < 1e-10);
//! assert!(orbit.spectral_radius() < 1.0);
//! // Compliance of m1, m/N: half peak-to-peak over the force.
//! let compliance = st.amplitude[0] / 2.6;
//! assert!(compliance > 1e-6 && compliance < 1e-2);
//! ```
//!
//! A sweep from rest (parallel; the same bytes for any number of threads) and a free decay:
//!
//! ```
//! use shotdamp::model::{Clearance, Damper, Damping, Structure};
//! use shotdamp::sim::motion::impulse::{free_response, ImpulseOptions, Kick};
//! use shotdamp::sim::{settle::sweep, SteadyOptions, System};
//!
//! let paper = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
//! let beds = vec![Damper::new(0, 0.074, Clearance::NO_TOP)];
//! let system = System::plastic(paper, beds, 0, 2.6);
//! let points = sweep::from_rest(&system, &[30.0, 40.0, 50.0], &SteadyOptions::default(), &|| {});
//! assert!(points.iter().all(|p| p.result.as_ref().is_ok_and(|s| s.amplitude.len() == 3)));
//!
//! let kick = ImpulseOptions { mass: 0, kick: Kick::Velocity(0.5), duration: 0.2, dt: 1e-3 };
//! let run = free_response(&system, &kick).unwrap();
//! // The energy given = the energy left + the viscous loss + the impact loss.
//! assert!(run.energy_residual() < 1e-9);
//! ```
//!
//! Experiment files run into a report, as `shotdamp run FILE --out DIR` does:
//!
//! ```no_run
//! use std::path::PathBuf;
//! use shotdamp::analysis::NoProgress;
//! use shotdamp::checks::reference::BaselineMode;
//! use shotdamp::runner::{run_and_write, Settings};
//!
//! let files = [PathBuf::from("experiments/fig04b_no_damper.toml")];
//! let reference = PathBuf::from("reference");
//! let exps = shotdamp::experiment::loader::load_all(&files, &reference)?;
//! let settings = Settings {
//!     reference,
//!     out: PathBuf::from("runs"),
//!     jobs: None,
//!     writing: Default::default(),
//!     baseline_mode: BaselineMode::Optional,
//!     bless: false,
//! };
//! let done = run_and_write(&exps, &[], &settings, &NoProgress, &|line| eprintln!("{line}"), &|_| {})?;
//! println!("{} checks, {} failed: {}", done.checks, done.failed.len(), done.dest.display());
//! # Ok::<(), shotdamp::Error>(())
//! ```

// Every public item is documented; the lint keeps it so (clippy -D warnings makes it an error).
#![warn(missing_docs)]

pub mod analysis;
pub mod checks;
pub mod cli;
pub mod design;
pub mod error;
pub mod experiment;
pub mod explore;
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
