//! A stiffness matrix given in full (`stiffness_matrix_n_per_m`, rows), with lumped masses or
//! a mass matrix: any linear structure whose matrices are at hand.

use std::path::Path;

use super::{lumped_or_full, symmetric_positive, Limit, Matrices, Source};
use crate::error::Result;
use crate::experiment::file::raw::RawStructure;

/// `stiffness_matrix_n_per_m`.
pub struct Matrix;

impl Source for Matrix {
    fn key(&self) -> &'static str {
        "stiffness_matrix_n_per_m"
    }

    fn given(&self, s: &RawStructure) -> bool {
        s.stiffness_matrix_n_per_m.is_some()
    }

    fn build(&self, path: &Path, s: &RawStructure, _: Limit<'_>) -> Result<Matrices> {
        let (masses, full_mass) = lumped_or_full(path, s)?;
        let rows = s.stiffness_matrix_n_per_m.as_deref().unwrap_or_default();
        let key = "structure.stiffness_matrix_n_per_m";
        let stiffness = symmetric_positive(path, key, rows, masses.len(), "stiffness")?;
        Ok(Matrices { masses, full_mass, stiffness, fit: None, fe: None })
    }
}
