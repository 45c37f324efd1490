//! Eigendecomposition of a real, non-symmetric matrix with complex eigenvalues and
//! eigenvectors: eigenvalues from nalgebra's Schur form, eigenvectors by inverse iteration,
//! each eigenpair refined and its residual measured.

use nalgebra::DMatrix;
use num_complex::Complex64;

/// `A = V diag(lambda) V^-1`.
#[derive(Debug, Clone)]
pub struct Eigen {
    pub values: Vec<Complex64>,
    /// Eigenvectors as columns.
    pub vectors: DMatrix<Complex64>,
    /// `V^-1`.
    pub inverse: DMatrix<Complex64>,
    /// Largest `||A v - lambda v|| / (||A|| ||v||)` over the eigenpairs.
    pub residual: f64,
}

/// Decomposes `a`. Returns `None` when `a` is defective (eigenvectors not independent), which
/// a damped mechanical system with distinct modes never is.
pub fn decompose(a: &DMatrix<f64>) -> Option<Eigen> {
    let n = a.nrows();
    let ac: DMatrix<Complex64> = a.map(|v| Complex64::new(v, 0.0));
    let norm_a = a.norm().max(f64::MIN_POSITIVE);
    let mut values: Vec<Complex64> = a.clone().complex_eigenvalues().iter().copied().collect();
    // Deterministic order: by imaginary part, then real part.
    values.sort_by(|x, y| x.im.total_cmp(&y.im).then(x.re.total_cmp(&y.re)));
    let mut vectors = DMatrix::<Complex64>::zeros(n, n);
    let mut residual: f64 = 0.0;
    for (k, lambda) in values.iter_mut().enumerate() {
        // A shift just off the eigenvalue keeps the LU factor non-singular while the solve
        // amplifies the eigenvector direction by ~1 / shift.
        let shift = *lambda + Complex64::new(1e-10 * norm_a, 1e-10 * norm_a);
        let mut b = ac.clone();
        for i in 0..n {
            b[(i, i)] -= shift;
        }
        let lu = b.lu();
        let mut v = nalgebra::DVector::<Complex64>::from_fn(n, |i, _| {
            Complex64::new(1.0 + 0.1 * i as f64, 0.3 - 0.05 * i as f64)
        });
        for _ in 0..3 {
            v = lu.solve(&v)?;
            let norm = v.norm();
            if !norm.is_finite() || norm == 0.0 {
                return None;
            }
            v /= Complex64::new(norm, 0.0);
        }
        // Rayleigh quotient refines the eigenvalue to the vector.
        let av = &ac * &v;
        *lambda = v.dotc(&av) / v.dotc(&v);
        let r = (&av - &v * *lambda).norm() / norm_a;
        residual = residual.max(r);
        // Phase: largest element real and positive (reproducible vectors).
        let (imax, _) =
            v.iter().enumerate().fold(
                (0, 0.0),
                |acc, (i, c)| if c.norm() > acc.1 { (i, c.norm()) } else { acc },
            );
        let phase = v[imax] / v[imax].norm();
        v /= phase;
        vectors.set_column(k, &v);
    }
    let inverse = vectors.clone().try_inverse()?;
    Some(Eigen {
        values,
        vectors,
        inverse,
        residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damped_state_matrix_reconstructs() {
        // A damped 3-mass chain in first-order form, non-proportional damping.
        let m = [0.814, 0.71, 0.704];
        let k = DMatrix::from_row_slice(
            3,
            3,
            &[
                46100.0, -21800.0, 0.0, -21800.0, 41600.0, -19800.0, 0.0, -19800.0, 19800.0,
            ],
        );
        let c = DMatrix::from_row_slice(3, 3, &[3.0, -1.0, 0.0, -1.0, 2.5, -0.7, 0.0, -0.7, 0.9]);
        let mut a = DMatrix::<f64>::zeros(6, 6);
        for i in 0..3 {
            a[(i, i + 3)] = 1.0;
            for j in 0..3 {
                a[(i + 3, j)] = -k[(i, j)] / m[i];
                a[(i + 3, j + 3)] = -c[(i, j)] / m[i];
            }
        }
        let e = decompose(&a).unwrap();
        assert!(e.residual < 1e-12, "residual {}", e.residual);
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(e.values.clone()));
        let back = &e.vectors * d * &e.inverse;
        let err = (back.map(|z| z.re) - &a).norm() / a.norm();
        assert!(err < 1e-12, "reconstruction error {err}");
        assert!(back.map(|z| z.im.abs()).max() < 1e-9 * a.norm());
        for l in &e.values {
            assert!(l.re < 0.0, "damped: {l}");
        }
    }
}
