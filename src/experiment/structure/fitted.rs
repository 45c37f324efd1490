//! A chain's stiffness fitted to measured modes (`fit`: natural frequencies and shapes), on
//! lumped masses.

use std::path::Path;

use super::{lumped_or_full, Limit, Matrices, Source};
use crate::error::{Error, Result};
use crate::experiment::file::raw::{RawFit, RawStructure};
use crate::model::fit::{fit_stiffness, ModalData, StiffnessFit, FREQUENCY_WEIGHT};

/// `fit`.
pub struct Fitted;

impl Source for Fitted {
    fn key(&self) -> &'static str {
        "fit"
    }

    fn given(&self, s: &RawStructure) -> bool {
        s.fit.is_some()
    }

    fn build(&self, path: &Path, s: &RawStructure, _: Limit<'_>) -> Result<Matrices> {
        let (masses, full_mass) = lumped_or_full(path, s)?;
        if full_mass.is_some() {
            return Err(Error::invalid(
                path,
                "structure.fit",
                "(with mass_matrix_kg)",
                "fitting a chain's stiffness to measured modes takes lumped masses_kg",
            ));
        }
        let Some(f) = &s.fit else {
            return Err(Error::invalid(path, "structure.fit", "(missing)", "measured frequencies and shapes"));
        };
        let out = fitted(path, &masses, f)?;
        Ok(Matrices { stiffness: out.stiffness.clone(), masses, full_mass, fit: Some(out), fe: None })
    }
}

/// Fits the stiffness to measured modes; bad data is an input error naming `structure.fit`.
fn fitted(path: &Path, masses: &[f64], f: &RawFit) -> Result<StiffnessFit> {
    let n = masses.len();
    let data = ModalData {
        omegas: f.omegas_rad_per_s.clone(),
        shapes: f.shapes.clone(),
        frequency_weight: f.frequency_weight.unwrap_or(FREQUENCY_WEIGHT),
        shape_weights: f.shape_weights.clone().unwrap_or_else(|| vec![vec![1.0; n]; f.shapes.len()]),
    };
    fit_stiffness(masses, &data).map_err(|e| {
        let shown = format!("omegas {:?}, shapes {:?}", f.omegas_rad_per_s, f.shapes);
        let allowed = format!("; the fit needs one positive frequency and one shape of {n} elements per mass, independent shapes and data a positive definite stiffness can match");
        Error::refused_in(path, "structure.fit", shown, "", e, allowed)
    })
}
