//! The motion between and at events: the structure and its beds (`system`, `bed`, `state`),
//! the closed form of each configuration (`eigen`, `schur`, `forced`, `segment`, and its modal coordinates, `modal`), the certified
//! event search (`roots`, `coarse`, `single`), accelerations at a state (`contact`, with the
//! rows per host it reads in `host_rows`), contact resolution (`column`, `soft`), and the
//! engine that runs them (`engine`, `observe`, `period_record`, `peaks`, `impulse`). Imports nothing else of `sim`.

pub mod bed;
pub mod buf;
pub mod cancel;
pub mod coarse;
pub mod column;
pub mod contact;
pub mod eigen;
pub mod engine;
pub mod forced;
pub mod host_rows;
pub mod impulse;
pub mod modal;
pub mod observe;
pub mod peaks;
pub mod period_record;
pub mod roots;
pub mod schur;
pub mod segment;
pub(in crate::sim) mod single;
pub mod soft;
pub mod state;
pub mod system;
