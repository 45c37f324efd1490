//! Periodic orbits of the motion: shooting on a Poincare section (`periodic`, `strobe`), their
//! Jacobians through every event (`tangent`), and continuation in a parameter
//! (`continuation`). Imports the motion room only.

mod carried;
pub mod continuation;
pub mod periodic;
pub mod strobe;
pub mod tangent;
