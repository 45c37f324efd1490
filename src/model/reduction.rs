//! Craig-Bampton reduction of a finite-element model to the degrees of freedom where the shot
//! acts (docs/model.md, section 1.5): the boundary degrees of freedom `b` (every container
//! host, the force point, every reported response) stay physical; the interior `i` is
//! represented by its static response to the boundary (constraint modes
//! `Psi = -K_ii^-1 K_ib`) and its lowest fixed-interface modes (`K_ii Phi = M_ii Phi Lambda`).
//! With `T = [[I, 0], [Psi, Phi]]`, `M_r = T^T M T` and `K_r = T^T K T`: a full mass matrix,
//! whose first coordinates are the boundary's displacements. Dense: for models of up to a few
//! thousand degrees of freedom. No I/O.

use nalgebra::DMatrix;

use super::modes::symmetric_modes;

/// A model reduced at its boundary.
#[derive(Debug, Clone)]
pub struct Reduced {
    /// `M_r`: the boundary's coordinates first (in the order given), then one modal coordinate
    /// per kept fixed-interface mode, kg.
    pub mass: DMatrix<f64>,
    /// `K_r`, N/m.
    pub stiffness: DMatrix<f64>,
    /// The full model's degrees of freedom of the boundary, in the reduced model's order.
    pub boundary: Vec<usize>,
    /// Natural frequencies of the kept fixed-interface modes, rad/s, ascending.
    pub interior_omegas: Vec<f64>,
    /// The lowest fixed-interface mode left out, rad/s (infinite when all are kept): the
    /// reduced model is faithful well below it.
    pub cutoff: f64,
    /// `T` (full degrees of freedom x reduced coordinates): the full model's displacements
    /// from the reduced coordinates.
    pub transform: DMatrix<f64>,
}

/// Why a model could not be reduced.
#[derive(Debug, Clone, PartialEq)]
pub enum ReductionError {
    /// The matrices are not square, of one size, and finite.
    Shape,
    /// A matrix is not symmetric at `(row, col)` (0-based).
    NotSymmetric {
        /// Row.
        row: usize,
        /// Column.
        col: usize,
    },
    /// A boundary degree of freedom outside the model, or named twice.
    Boundary {
        /// The degree of freedom (0-based).
        dof: usize,
    },
    /// The interior is not held by the boundary: `K_ii` or `M_ii` is not positive definite
    /// (a rigid-body motion of the interior, or a degree of freedom without mass).
    Interior,
}

impl std::fmt::Display for ReductionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReductionError::Shape => write!(f, "the mass and stiffness matrices must be square, of one size and finite"),
            ReductionError::NotSymmetric { row, col } => {
                write!(f, "the matrix is not symmetric at row {}, column {}", row + 1, col + 1)
            }
            ReductionError::Boundary { dof } => {
                write!(f, "boundary degree of freedom {} is outside the model or named twice", dof + 1)
            }
            ReductionError::Interior => write!(
                f,
                "the interior degrees of freedom are not held by the boundary (K_ii or M_ii not positive definite): a rigid-body motion, or a degree of freedom without mass"
            ),
        }
    }
}

impl std::error::Error for ReductionError {}

/// Symmetric to rounding: `|a_ij - a_ji| <= 1e-10 max |a|`.
fn symmetric(a: &DMatrix<f64>) -> Result<(), ReductionError> {
    let scale = a.amax();
    for i in 0..a.nrows() {
        for j in 0..i {
            if (a[(i, j)] - a[(j, i)]).abs() > 1e-10 * scale {
                return Err(ReductionError::NotSymmetric { row: i, col: j });
            }
        }
    }
    Ok(())
}

/// Reduces `(m, k)` to the degrees of freedom of `boundary` (0-based, kept in that order) and
/// the lowest `modes` fixed-interface modes (fewer when the interior has fewer).
pub fn craig_bampton(
    m: &DMatrix<f64>,
    k: &DMatrix<f64>,
    boundary: &[usize],
    modes: usize,
) -> Result<Reduced, ReductionError> {
    let n = m.nrows();
    if m.shape() != (n, n) || k.shape() != (n, n) || m.iter().chain(k.iter()).any(|v| !v.is_finite()) {
        return Err(ReductionError::Shape);
    }
    symmetric(m)?;
    symmetric(k)?;
    let mut is_boundary = vec![false; n];
    for &b in boundary {
        if b >= n || is_boundary[b] {
            return Err(ReductionError::Boundary { dof: b });
        }
        is_boundary[b] = true;
    }
    let interior: Vec<usize> = (0..n).filter(|&i| !is_boundary[i]).collect();
    let (nb, ni) = (boundary.len(), interior.len());
    let part = |a: &DMatrix<f64>, rows: &[usize], cols: &[usize]| {
        DMatrix::from_fn(rows.len(), cols.len(), |r, c| a[(rows[r], cols[c])])
    };
    let (k_ii, k_ib, m_ii) =
        (part(k, &interior, &interior), part(k, &interior, boundary), part(m, &interior, &interior));
    let chol = k_ii.clone().cholesky().ok_or(ReductionError::Interior)?;
    if ni > 0 && m_ii.clone().cholesky().is_none() {
        return Err(ReductionError::Interior);
    }
    // Constraint modes: the interior's static response to a unit displacement of each
    // boundary degree of freedom.
    let psi = -chol.solve(&k_ib);
    let fixed = symmetric_modes(&m_ii, &k_ii);
    let kept = modes.min(ni);
    let mut t = DMatrix::<f64>::zeros(n, nb + kept);
    for (c, &b) in boundary.iter().enumerate() {
        t[(b, c)] = 1.0;
        for (r, &i) in interior.iter().enumerate() {
            t[(i, c)] = psi[(r, c)];
        }
    }
    for q in 0..kept {
        for (r, &i) in interior.iter().enumerate() {
            t[(i, nb + q)] = fixed.mass_normalised[(r, q)];
        }
    }
    let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
    let mass = sym(t.transpose() * m * &t);
    let stiffness = sym(t.transpose() * k * &t);
    Ok(Reduced {
        mass,
        stiffness,
        boundary: boundary.to_vec(),
        interior_omegas: fixed.omegas[..kept].to_vec(),
        cutoff: fixed.omegas.get(kept).copied().unwrap_or(f64::INFINITY),
        transform: t,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::structure::chain_stiffness;
    use nalgebra::DVector;

    /// A grounded chain of `n` unequal masses.
    fn chain(n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
        let m = DMatrix::from_diagonal(&DVector::from_fn(n, |i, _| 0.5 + 0.1 * (i % 3) as f64));
        let k = chain_stiffness(&(0..n).map(|i| 2e4 + 1e3 * (i % 4) as f64).collect::<Vec<_>>());
        (m, k)
    }

    #[test]
    fn every_interior_mode_kept_is_a_change_of_basis() {
        let (m, k) = chain(12);
        let r = craig_bampton(&m, &k, &[0, 9, 10, 11], 100).unwrap();
        assert_eq!(r.mass.nrows(), 12);
        let (full, red) = (symmetric_modes(&m, &k).omegas, symmetric_modes(&r.mass, &r.stiffness).omegas);
        for (a, b) in full.iter().zip(&red) {
            assert!((a - b).abs() <= 1e-10 * a, "{a} vs {b}");
        }
        assert_eq!(r.cutoff, f64::INFINITY);
    }

    #[test]
    fn the_static_compliance_at_the_boundary_is_exact_without_modes() {
        // Guyan's condensation: K_r = K_bb - K_bi K_ii^-1 K_ib, whose inverse is the full
        // model's static compliance at the boundary.
        let (m, k) = chain(10);
        let b = [7, 2, 9];
        let r = craig_bampton(&m, &k, &b, 0).unwrap();
        let (full, red) = (k.clone().try_inverse().unwrap(), r.stiffness.clone().try_inverse().unwrap());
        for (p, &bp) in b.iter().enumerate() {
            for (q, &bq) in b.iter().enumerate() {
                assert!((full[(bp, bq)] - red[(p, q)]).abs() <= 1e-12 * full.amax(), "({bp}, {bq})");
            }
        }
    }

    #[test]
    fn frequencies_come_from_above_and_converge_as_modes_are_kept() {
        // Rayleigh-Ritz: each reduced frequency bounds the full model's from above, and more
        // interior modes bring the lowest ones closer.
        let (m, k) = chain(30);
        let full = symmetric_modes(&m, &k).omegas;
        let mut last = f64::INFINITY;
        for kept in [0, 2, 5, 10] {
            let r = craig_bampton(&m, &k, &[0, 27, 28, 29], kept).unwrap();
            let red = symmetric_modes(&r.mass, &r.stiffness).omegas;
            for (a, b) in full.iter().zip(&red) {
                assert!(*b >= a * (1.0 - 1e-12), "{kept} modes: {b} below {a}");
            }
            let err = (0..3).map(|i| (red[i] - full[i]) / full[i]).fold(0.0, f64::max);
            assert!(err < last, "{kept} modes: {err} not below {last}");
            last = err;
        }
        assert!(last < 1e-3, "10 interior modes: the lowest three within {last}");
    }

    #[test]
    fn bad_models_are_refused() {
        let (m, k) = chain(4);
        let mut bad = k.clone();
        bad[(0, 1)] += 1.0;
        assert_eq!(craig_bampton(&m, &bad, &[0], 1).unwrap_err(), ReductionError::NotSymmetric { row: 1, col: 0 });
        assert_eq!(craig_bampton(&m, &k, &[0, 0], 1).unwrap_err(), ReductionError::Boundary { dof: 0 });
        assert_eq!(craig_bampton(&m, &k, &[4], 1).unwrap_err(), ReductionError::Boundary { dof: 4 });
        // An interior pair joined to nothing else moves as a rigid body.
        let loose = DMatrix::from_row_slice(
            4,
            4,
            &[2e4, -1e4, 0.0, 0.0, -1e4, 1e4, 0.0, 0.0, 0.0, 0.0, 1e3, -1e3, 0.0, 0.0, -1e3, 1e3],
        );
        assert_eq!(craig_bampton(&m, &loose, &[0, 1], 1).unwrap_err(), ReductionError::Interior);
    }
}
