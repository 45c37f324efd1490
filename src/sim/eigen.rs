//! Eigendecomposition of a real, non-symmetric matrix with complex eigenvalues and
//! eigenvectors: eigenvalues from nalgebra's Schur form, eigenvectors by inverse iteration,
//! each eigenpair refined and its residual measured.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// `A = V diag(lambda) V^-1`, with complex eigenvalues in exact conjugate pairs.
#[derive(Debug, Clone)]
pub struct Eigen {
    pub values: Vec<Complex64>,
    /// Eigenvectors as columns.
    pub vectors: DMatrix<Complex64>,
    /// `V^-1`.
    pub inverse: DMatrix<Complex64>,
    /// Largest `||A v - lambda v|| / (||A|| ||v||)` over the eigenpairs.
    pub residual: f64,
    /// Indices of one eigenvalue of each conjugate pair (the one with positive imaginary
    /// part) and of each real eigenvalue, with weight 2 and 1: for a real vector `c`,
    /// `Re sum_k V_k c_k = sum_r w_r Re(V_r c_r)`.
    pub representatives: Vec<(usize, f64)>,
}

/// One eigenpair by inverse iteration from a nearby shift, refined by a Rayleigh quotient.
fn eigenpair(ac: &DMatrix<Complex64>, lambda: Complex64, norm_a: f64) -> Option<(Complex64, DVector<Complex64>, f64)> {
    let n = ac.nrows();
    // A shift just off the eigenvalue keeps the LU factor non-singular while the solve
    // amplifies the eigenvector direction by ~1 / shift.
    let shift = lambda + Complex64::new(1e-10 * norm_a, 1e-10 * norm_a);
    let mut b = ac.clone();
    for i in 0..n {
        b[(i, i)] -= shift;
    }
    let lu = b.lu();
    let mut v = DVector::<Complex64>::from_fn(n, |i, _| Complex64::new(1.0 + 0.1 * i as f64, 0.3 - 0.05 * i as f64));
    for _ in 0..3 {
        v = lu.solve(&v)?;
        let norm = v.norm();
        if !norm.is_finite() || norm == 0.0 {
            return None;
        }
        v /= Complex64::new(norm, 0.0);
    }
    let av = ac * &v;
    let lambda = v.dotc(&av) / v.dotc(&v);
    let r = (&av - &v * lambda).norm() / norm_a;
    // Phase: largest element real and positive (reproducible vectors).
    let (imax, _) =
        v.iter().enumerate().fold((0, 0.0), |acc, (i, c)| if c.norm() > acc.1 { (i, c.norm()) } else { acc });
    let phase = v[imax] / v[imax].norm();
    v /= phase;
    Some((lambda, v, r))
}

/// Decomposes `a`. Returns `None` when `a` is defective (eigenvectors not independent), which
/// a damped mechanical system with distinct modes never is.
pub fn decompose(a: &DMatrix<f64>) -> Option<Eigen> {
    let n = a.nrows();
    let ac: DMatrix<Complex64> = a.map(|v| Complex64::new(v, 0.0));
    let norm_a = a.norm().max(f64::MIN_POSITIVE);
    let mut schur: Vec<Complex64> = a.clone().complex_eigenvalues().iter().copied().collect();
    // Deterministic order: by imaginary part (descending), then real part.
    schur.sort_by(|x, y| y.im.total_cmp(&x.im).then(x.re.total_cmp(&y.re)));
    let mut values = Vec::with_capacity(n);
    let mut columns: Vec<DVector<Complex64>> = Vec::with_capacity(n);
    let mut representatives = Vec::new();
    let mut residual: f64 = 0.0;
    for lambda in schur.iter().copied() {
        let is_complex = lambda.im.abs() > 1e-12 * lambda.norm();
        if is_complex && lambda.im < 0.0 {
            continue; // the conjugate of a pair already taken
        }
        let (mut l, mut v, r) = eigenpair(&ac, lambda, norm_a)?;
        residual = residual.max(r);
        if is_complex {
            representatives.push((values.len(), 2.0));
            values.push(l);
            columns.push(v.clone());
            values.push(l.conj());
            columns.push(v.map(|z| z.conj()));
        } else {
            l = Complex64::new(l.re, 0.0);
            v = v.map(|z| Complex64::new(z.re, 0.0));
            representatives.push((values.len(), 1.0));
            values.push(l);
            columns.push(v);
        }
    }
    if values.len() != n {
        return None;
    }
    let vectors = DMatrix::from_columns(&columns);
    let inverse = vectors.clone().try_inverse()?;
    Some(Eigen { values, vectors, inverse, residual, representatives })
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
            &[46100.0, -21800.0, 0.0, -21800.0, 41600.0, -19800.0, 0.0, -19800.0, 19800.0],
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
