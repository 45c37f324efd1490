//! Undamped modes of a symmetric generalised eigenproblem: a leaf that the structure and the
//! modal analysis both use.

use nalgebra::{DMatrix, SymmetricEigen};

/// Undamped modes of `K phi = omega^2 M phi`, sorted by frequency.
#[derive(Debug, Clone)]
pub struct Modes {
    /// Natural frequencies, rad/s, ascending.
    pub omegas: Vec<f64>,
    /// Mode shapes as columns, mass-normalised (`phi^T M phi = 1`).
    pub mass_normalised: DMatrix<f64>,
}

/// Solves the symmetric generalised eigenproblem with a diagonal (or SPD) mass matrix.
///
/// Uses the Cholesky factor `M = L L^T`: `L^-1 K L^-T u = omega^2 u`, `phi = L^-T u`.
/// `SymmetricEigen` does not sort, so the modes are sorted here.
pub fn symmetric_modes(m: &DMatrix<f64>, k: &DMatrix<f64>) -> Modes {
    let n = m.nrows();
    // Mass matrices reaching here are validated positive definite.
    let l = match m.clone().cholesky() {
        Some(c) => c.l(),
        None => DMatrix::from_diagonal(&m.diagonal().map(|v| v.abs().sqrt())),
    };
    let l_inv = l.clone().try_inverse().unwrap_or_else(|| DMatrix::identity(n, n));
    let a = &l_inv * k * l_inv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let eig = SymmetricEigen::new(a);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let mut omegas = Vec::with_capacity(n);
    let mut phi = DMatrix::<f64>::zeros(n, n);
    for (col, &i) in order.iter().enumerate() {
        omegas.push(eig.eigenvalues[i].max(0.0).sqrt());
        let u = eig.eigenvectors.column(i);
        let v = l_inv.transpose() * u;
        phi.set_column(col, &v);
    }
    Modes { omegas, mass_normalised: phi }
}
