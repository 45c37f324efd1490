//! The physical model: structure, dampers, modes and the linear response.

pub mod base;
pub mod clearance;
pub mod damper;
pub mod damping_fit;
pub mod fe;
pub mod fit;
pub mod frf;
pub mod ground;
pub mod ground_response;
pub mod lanczos;
pub mod least_squares;
pub mod modal;
pub mod modes;
pub mod reduction;
pub mod sdof;
pub mod sparse;
pub mod structure;

pub use base::BaseMotion;
pub use clearance::Clearance;
pub use damper::{Damper, Direction};
pub use structure::{Damping, Structure, GRAVITY};
