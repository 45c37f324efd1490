//! The primary structure: its mass matrix (lumped masses, or a general symmetric positive
//! definite matrix such as a reduced finite-element model's), its stiffness and its fixed
//! damping matrix (docs/model.md sections 1 and 5).

use nalgebra::{DMatrix, DVector};

use super::modes::symmetric_modes;

/// Standard gravity, m/s^2 (docs/model.md section 1).
pub const GRAVITY: f64 = 9.806_65;

/// How the fixed damping matrix `C` of the bare structure is specified.
#[derive(Debug, Clone, PartialEq)]
pub enum Damping {
    /// Modal damping ratios `zeta_i`, one per mode of the bare structure:
    /// `C = M0 Phi diag(2 zeta_i omega_i) Phi^T M0`, Phi mass-normalised.
    ModalRatios(Vec<f64>),
    /// Rayleigh damping `C = alpha M0 + beta K` (paper Eq. 12).
    Rayleigh {
        /// Mass-proportional coefficient, 1/s.
        alpha: f64,
        /// Stiffness-proportional coefficient, s.
        beta: f64,
    },
}

/// The bare primary structure: `M0 xddot + C xdot + K x = f`.
#[derive(Clone, PartialEq)]
pub struct Structure {
    /// The diagonal of `M0`, kg: the lumped masses `m_1..m_n`, or a full mass matrix's
    /// diagonal (what reports list and mass ratios refer to).
    pub masses: Vec<f64>,
    /// The whole of `M0` when it is not diagonal (a reduced finite-element model), its
    /// diagonal equal to `masses`; `None` for lumped masses (the paper's). Build it with
    /// [`Structure::from_mass_matrix`].
    pub coupled_mass: Option<DMatrix<f64>>,
    /// Stiffness matrix, N/m.
    pub stiffness: DMatrix<f64>,
    /// Damping matrix, N s/m (fixed: damper masses never change it).
    pub damping: DMatrix<f64>,
    /// How `damping` was specified (for reports).
    pub damping_spec: Damping,
    /// How the coordinates follow moving supports when that is not every coordinate
    /// translating with them (a reduced finite-element model); `None`: they do (a chain).
    pub supports: Option<std::sync::Arc<super::base::Supports>>,
    /// A reduced model's physical coordinates (its points) come first: this many; the rest
    /// are modal. `None`: every coordinate is a mass's displacement.
    pub points: Option<usize>,
}

/// Lists the fields; `coupled_mass` only when there is one, so that a lumped structure reads
/// as it always has (stored design answers fingerprint this text).
impl std::fmt::Debug for Structure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("Structure");
        d.field("masses", &self.masses);
        if let Some(m) = &self.coupled_mass {
            d.field("coupled_mass", m);
        }
        d.field("stiffness", &self.stiffness).field("damping", &self.damping).field("damping_spec", &self.damping_spec);
        if let Some(s) = &self.supports {
            d.field("supports", s);
        }
        if let Some(p) = &self.points {
            d.field("points", p);
        }
        d.finish()
    }
}

impl Structure {
    /// The highest undamped natural frequency, Hz (0 for an empty structure): what sets the
    /// event search's steps and the lowest forcing frequency worth simulating.
    pub fn highest_natural_frequency_hz(&self) -> f64 {
        let modes = symmetric_modes(&self.mass_matrix(), &self.stiffness);
        modes.omegas.last().copied().unwrap_or(0.0) / (2.0 * std::f64::consts::PI)
    }

    /// Builds the chain ground - k_1 - m_1 - k_2 - m_2 - ... - k_n - m_n.
    ///
    /// Inputs are assumed validated (positive masses and stiffnesses, matching lengths).
    pub fn chain(masses: &[f64], stiffnesses: &[f64], damping: Damping) -> Structure {
        let k = chain_stiffness(stiffnesses);
        Structure::from_matrices(masses, k, damping)
    }

    /// Builds a structure from a symmetric positive definite stiffness matrix.
    pub fn from_matrices(masses: &[f64], stiffness: DMatrix<f64>, damping: Damping) -> Structure {
        let m0 = DMatrix::from_diagonal(&DVector::from_column_slice(masses));
        Structure::assemble(m0, None, stiffness, damping)
    }

    /// Builds a structure from a symmetric positive definite mass matrix and a symmetric
    /// stiffness matrix (inputs assumed validated). A diagonal mass matrix gives the lumped
    /// structure of [`Structure::from_matrices`], bit for bit.
    pub fn from_mass_matrix(mass: DMatrix<f64>, stiffness: DMatrix<f64>, damping: Damping) -> Structure {
        let n = mass.nrows();
        let coupled = (0..n).any(|i| (0..n).any(|j| i != j && mass[(i, j)] != 0.0));
        if !coupled {
            let masses: Vec<f64> = mass.diagonal().iter().copied().collect();
            return Structure::from_matrices(&masses, stiffness, damping);
        }
        Structure::assemble(mass.clone(), Some(mass), stiffness, damping)
    }

    /// The structure of mass matrix `m0` (`coupled` when not diagonal).
    fn assemble(
        m0: DMatrix<f64>,
        coupled: Option<DMatrix<f64>>,
        stiffness: DMatrix<f64>,
        damping: Damping,
    ) -> Structure {
        let c = match &damping {
            Damping::Rayleigh { alpha, beta } => &m0 * *alpha + &stiffness * *beta,
            Damping::ModalRatios(zetas) => {
                let modes = symmetric_modes(&m0, &stiffness);
                // Mass-normalised Phi: phi^T M0 phi = 1.
                let n = m0.nrows();
                let mut diag = DMatrix::<f64>::zeros(n, n);
                for i in 0..n {
                    diag[(i, i)] = 2.0 * zetas[i] * modes.omegas[i];
                }
                let phi = &modes.mass_normalised;
                &m0 * phi * diag * phi.transpose() * &m0
            }
        };
        let masses = m0.diagonal().iter().copied().collect();
        Structure {
            masses,
            coupled_mass: coupled,
            stiffness,
            damping: c,
            damping_spec: damping,
            supports: None,
            points: None,
        }
    }

    /// The same mass and stiffness with another damping.
    pub fn with_damping(&self, damping: Damping) -> Structure {
        let s = match &self.coupled_mass {
            Some(m) => Structure::assemble(m.clone(), Some(m.clone()), self.stiffness.clone(), damping),
            None => Structure::from_matrices(&self.masses, self.stiffness.clone(), damping),
        };
        Structure { supports: self.supports.clone(), points: self.points, ..s }
    }

    /// Whether `M0` is diagonal (lumped masses, the paper's structure).
    pub fn is_lumped(&self) -> bool {
        self.coupled_mass.is_none()
    }

    /// Whether it is a chain of storeys: lumped masses joined only to their neighbours (a
    /// tridiagonal stiffness), each storey's drift the displacement of its mass less the one
    /// below.
    pub fn is_chain(&self) -> bool {
        let n = self.dof();
        self.is_lumped() && (0..n).all(|i| (0..n).all(|j| i.abs_diff(j) <= 1 || self.stiffness[(i, j)] == 0.0))
    }

    /// Number of primary masses.
    pub fn dof(&self) -> usize {
        self.masses.len()
    }

    /// How many coordinates are displacements of a point, first in order: a reduced model's
    /// points ([`Structure::points`]; the rest are modal), every mass of a chain. What the
    /// tables, figures and records show.
    pub fn physical(&self) -> usize {
        self.points.unwrap_or(self.dof()).min(self.dof())
    }

    /// The mass matrix `M0` of the bare structure.
    pub fn mass_matrix(&self) -> DMatrix<f64> {
        match &self.coupled_mass {
            Some(m) => m.clone(),
            None => DMatrix::from_diagonal(&DVector::from_column_slice(&self.masses)),
        }
    }

    /// The mass matrix with extra masses rigidly added: `M0 + sum m_dj e_pj e_pj^T`.
    pub fn mass_matrix_with(&self, added: &[(usize, f64)]) -> DMatrix<f64> {
        let mut m = self.mass_matrix();
        for &(host, mass) in added {
            m[(host, host)] += mass;
        }
        m
    }
}

/// The stiffness matrix of a grounded chain of springs.
pub fn chain_stiffness(k: &[f64]) -> DMatrix<f64> {
    let n = k.len();
    let mut m = DMatrix::<f64>::zeros(n, n);
    for i in 0..n {
        m[(i, i)] += k[i];
        if i + 1 < n {
            m[(i, i)] += k[i + 1];
            m[(i, i + 1)] -= k[i + 1];
            m[(i + 1, i)] -= k[i + 1];
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_matrix_matches_hand_assembly() {
        let k = chain_stiffness(&[1.0, 2.0, 3.0]);
        let expected = DMatrix::from_row_slice(3, 3, &[3.0, -2.0, 0.0, -2.0, 5.0, -3.0, 0.0, -3.0, 3.0]);
        assert_eq!(k, expected);
    }

    #[test]
    fn modal_damping_matrix_gives_the_requested_ratios() {
        let s = Structure::chain(
            &[0.74, 0.71, 0.64],
            &[24.3e3, 21.8e3, 19.8e3],
            Damping::ModalRatios(vec![0.01, 0.02, 0.03]),
        );
        let modes = symmetric_modes(&s.mass_matrix(), &s.stiffness);
        for i in 0..3 {
            let phi = modes.mass_normalised.column(i);
            let ci = (phi.transpose() * &s.damping * phi)[(0, 0)];
            let zeta = ci / (2.0 * modes.omegas[i]);
            assert!((zeta - [0.01, 0.02, 0.03][i]).abs() < 1e-12, "mode {i}: {zeta}");
        }
    }
}
