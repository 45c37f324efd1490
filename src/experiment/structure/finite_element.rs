//! A finite-element model (`finite_element`: mass and stiffness files from CalculiX or in
//! Matrix Market), reduced to its points and modal coordinates ([`crate::experiment::fe`]).

use std::path::Path;

use super::{Limit, Matrices, Source};
use crate::error::{Error, Result};
use crate::experiment::file::raw::RawStructure;

/// `finite_element`.
pub struct FiniteElement;

impl Source for FiniteElement {
    fn key(&self) -> &'static str {
        "finite_element"
    }

    fn given(&self, s: &RawStructure) -> bool {
        s.finite_element.is_some()
    }

    fn build(&self, path: &Path, s: &RawStructure, limit: Limit<'_>) -> Result<Matrices> {
        // Its masses and stiffness come from its files: any other source's key is refused.
        let given = [
            ("masses_kg", s.masses_kg.is_some()),
            ("mass_matrix_kg", s.mass_matrix_kg.is_some()),
            ("chain_stiffness_n_per_m", s.chain_stiffness_n_per_m.is_some()),
            ("stiffness_matrix_n_per_m", s.stiffness_matrix_n_per_m.is_some()),
            ("fit", s.fit.is_some()),
            ("ground_stiffness_n_per_m", s.ground_stiffness_n_per_m.is_some()),
        ];
        if let Some((k, _)) = given.iter().find(|g| g.1) {
            return Err(Error::invalid(
                path,
                format!("structure.{k}"),
                "(with finite_element)",
                format!(
                    "a finite-element structure takes its masses and stiffness from its files: leave structure.{k} out"
                ),
            ));
        }
        let Some(raw) = s.finite_element.clone() else {
            return Err(Error::invalid(path, "structure.finite_element", "(missing)", "a table of the model's files"));
        };
        let f = crate::experiment::fe::build(path, raw, limit)?;
        // The full mass matrix; its diagonal stands for the masses elsewhere.
        let masses = f.mass.diagonal().iter().copied().collect();
        Ok(Matrices {
            masses,
            full_mass: Some(f.mass),
            stiffness: f.stiffness,
            fit: None,
            fe: Some((f.fe, f.supports)),
        })
    }
}
