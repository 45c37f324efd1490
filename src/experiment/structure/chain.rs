//! A chain of lumped masses joined by springs (`chain_stiffness_n_per_m`: the spring below
//! each mass, the first to the ground), the paper's 3-mass structure.

use std::path::Path;

use super::{lumped_or_full, positive_list, Limit, Matrices, Source};
use crate::error::{Error, Result};
use crate::experiment::file::raw::RawStructure;

/// `chain_stiffness_n_per_m`.
pub struct Chain;

impl Source for Chain {
    fn key(&self) -> &'static str {
        "chain_stiffness_n_per_m"
    }

    fn given(&self, s: &RawStructure) -> bool {
        s.chain_stiffness_n_per_m.is_some()
    }

    fn build(&self, path: &Path, s: &RawStructure, _: Limit<'_>) -> Result<Matrices> {
        let (masses, full_mass) = lumped_or_full(path, s)?;
        let k = s.chain_stiffness_n_per_m.as_deref().unwrap_or_default();
        let n = masses.len();
        positive_list(path, "structure.chain_stiffness_n_per_m", k, "stiffness")?;
        if k.len() != n {
            return Err(Error::invalid(
                path,
                "structure.chain_stiffness_n_per_m",
                format!("{} values", k.len()),
                format!("expected {n} stiffnesses, one per mass (the structure has {n})"),
            ));
        }
        let stiffness = crate::model::structure::chain_stiffness(k);
        Ok(Matrices { masses, full_mass, stiffness, fit: None, fe: None })
    }
}
