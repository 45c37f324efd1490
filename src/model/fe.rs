//! A finite-element model as read from a finite-element program's files, and its reduction
//! at the points where the shot acts (docs/fe-models.md): the reduced model is an ordinary
//! [`super::Structure`] whose first coordinates are those points' displacements, each
//! measured upward where it is vertical.

use std::sync::Arc;

use super::reduction::Reduced;
use super::sparse::SymSparse;

/// A degree of freedom of a finite-element model: a node and a direction (1-3 translations
/// along x, y, z; 4-6 rotations).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DofLabel {
    /// Node number.
    pub node: u64,
    /// Direction, 1 to 6.
    pub dof: u8,
}

impl std::fmt::Display for DofLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let axis = ["x", "y", "z", "rotation x", "rotation y", "rotation z"];
        write!(f, "node {} direction {} ({})", self.node, self.dof, axis[usize::from(self.dof.clamp(1, 6)) - 1])
    }
}

/// The full model, in SI units (N/m, kg).
#[derive(Clone)]
pub struct FullModel {
    /// Stiffness.
    pub stiffness: SymSparse,
    /// Mass.
    pub mass: SymSparse,
    /// Each row's node and direction, when the files name them.
    pub labels: Option<Vec<DofLabel>>,
    /// The files it was read from, for the report.
    pub files: String,
}

impl std::fmt::Debug for FullModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FullModel {{ {} degrees of freedom from {} }}", self.mass.n(), self.files)
    }
}

/// A point of the full model kept as a physical coordinate of the reduced one.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Its name in the experiment file.
    pub name: String,
    /// Its row of the full model, 0-based.
    pub row: usize,
    /// Its node and direction, when the files name them.
    pub label: Option<DofLabel>,
    /// Along the upward vertical (a container there is the paper's); otherwise at a right
    /// angle to it, or a rotation.
    pub vertical: bool,
    /// A translation at a right angle to the vertical (a horizontal container may sit
    /// there); without names in the files, every point may carry either.
    pub horizontal: bool,
    /// `-1` when the full model's direction points down (the reduced coordinate is measured
    /// upward), else `1`.
    pub sign: f64,
}

/// A finite-element structure reduced at its points.
#[derive(Debug, Clone)]
pub struct FeStructure {
    /// The full model.
    pub full: Arc<FullModel>,
    /// The points, in the reduced model's order (its coordinates 1 to P).
    pub points: Vec<Point>,
    /// The reduction (its boundary the points' rows, its transform's point columns signed).
    pub reduced: Reduced,
    /// The upward direction as given (`"z"`, `"-y"`, ...).
    pub up: String,
    /// The largest relative difference of the reduced compliance from the full model's
    /// allowed over the analysis' bands.
    pub tolerance: f64,
    /// The full model's mass moving along the vertical (`r^T M r`, `r` one on every
    /// translation along `up`), kg: the physical structure's mass less what its supports
    /// hold (the files leave the supported nodes out).
    pub mass_along_up: f64,
    /// The physical structure's whole mass as the file states it
    /// (`structure.finite_element.mass_kg`), kg.
    pub mass_stated: Option<f64>,
}

impl FeStructure {
    /// The structure's mass a shot mass ratio is taken of, kg, and its words: the stated
    /// mass when the file gives one, else the mass moving along the vertical.
    pub fn mass(&self) -> (f64, String) {
        match self.mass_stated {
            Some(m) => (
                m,
                format!(
                    "mass: {} kg as stated, {} kg of it moving vertically in the model, the rest held by the supports",
                    crate::number::fmt_sig(m, 4),
                    crate::number::fmt_sig(self.mass_along_up, 4)
                ),
            ),
            None => (self.mass_along_up, "mass moving vertically".to_string()),
        }
    }
}
