//! The forced (particular) response of a configuration to `F sin(omega t)` at one mass, or to a
//! harmonic load vector (moving supports), and its derivative in the forcing frequency: on the
//! stack up to [`INLINE_MASSES`] masses, by nalgebra's LU above.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::buf::INLINE_MASSES;

/// The forced response of one configuration at one mass: `x_p = P cos(omega t) + Q sin(omega
/// t)` about the static offset.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Forced {
    /// Cosine coefficient `P`, m.
    pub p: f64,
    /// Sine coefficient `Q`, m.
    pub q: f64,
    /// Derivative of `P` in the forcing frequency, m s.
    pub dp: f64,
    /// Derivative of `Q` in the forcing frequency, m s.
    pub dq: f64,
    /// `sqrt(P^2 + Q^2)`.
    pub amp: f64,
}

/// What drives a configuration at one frequency.
#[derive(Debug, Clone, Copy)]
pub(in crate::sim) enum Drive<'a> {
    /// `F sin(omega t)` on one mass: the mass (0-based) and `F`, N.
    Point(usize, f64),
    /// A load `f(t) = Im(F e^{i omega t})` on every coordinate: the phasors `F` and their
    /// derivatives in `omega`.
    Load(&'a [Complex64], &'a [Complex64]),
}

/// The forced response `X` of one configuration (`Z X = F`, `Z = K - omega^2 M + i omega C`)
/// and its frequency derivative (`Z dX/domega = dF/domega - (dZ/domega) X`, `dZ/domega = -2
/// omega M + i C`), written into `out`: on the stack up to [`INLINE_MASSES`] masses, by
/// nalgebra's LU above; `None` when `Z` is singular.
pub(in crate::sim) fn forced_into(
    k: &DMatrix<f64>,
    c: &DMatrix<f64>,
    mass: &DMatrix<f64>,
    omega: f64,
    drive: Drive,
    out: &mut [Forced],
) -> Option<()> {
    let mut put = |i: usize, x: Complex64, dx: Complex64| {
        out[i] = Forced { p: x.im, q: x.re, dp: dx.im, dq: dx.re, amp: x.im.hypot(x.re) };
    };
    if k.nrows() <= INLINE_MASSES {
        let (x, dx) = forced_small(k, c, mass, omega, drive)?;
        (0..k.nrows()).for_each(|i| put(i, x[i], dx[i]));
    } else {
        let (x, dx) = forced_large(k, c, mass, omega, drive)?;
        (0..k.nrows()).for_each(|i| put(i, x[i], dx[i]));
    }
    Some(())
}

/// [`forced_into`] of any size, by nalgebra's LU with partial pivoting.
fn forced_large(
    k: &DMatrix<f64>,
    c: &DMatrix<f64>,
    mass: &DMatrix<f64>,
    omega: f64,
    drive: Drive,
) -> Option<(DVector<Complex64>, DVector<Complex64>)> {
    let n = k.nrows();
    let z = DMatrix::from_fn(n, n, |i, j| Complex64::new(k[(i, j)] - omega * omega * mass[(i, j)], omega * c[(i, j)]));
    let lu = z.lu();
    if !lu.is_invertible() {
        return None;
    }
    let mut f = DVector::zeros(n);
    let dz = DMatrix::from_fn(n, n, |i, j| Complex64::new(-2.0 * omega * mass[(i, j)], c[(i, j)]));
    let (x, dx) = match drive {
        Drive::Point(driven, force) => {
            f[driven] = Complex64::new(force, 0.0);
            let x = lu.solve(&f)?;
            let dx = lu.solve(&(-(dz * &x)))?;
            (x, dx)
        }
        Drive::Load(load, d_load) => {
            f.iter_mut().zip(load).for_each(|(f, l)| *f = *l);
            let x = lu.solve(&f)?;
            let dx = lu.solve(&(DVector::from_column_slice(d_load) - dz * &x))?;
            (x, dx)
        }
    };
    Some((x, dx))
}

/// [`forced_into`] of at most [`INLINE_MASSES`] masses, by Gaussian elimination with partial
/// pivoting on the stack.
fn forced_small(
    k: &DMatrix<f64>,
    c: &DMatrix<f64>,
    mass: &DMatrix<f64>,
    omega: f64,
    drive: Drive,
) -> Option<([Complex64; INLINE_MASSES], [Complex64; INLINE_MASSES])> {
    let n = k.nrows();
    let zero = Complex64::new(0.0, 0.0);
    let mut z = [[zero; INLINE_MASSES]; INLINE_MASSES];
    for (i, row) in z.iter_mut().enumerate().take(n) {
        for (j, e) in row.iter_mut().enumerate().take(n) {
            *e = Complex64::new(k[(i, j)] - omega * omega * mass[(i, j)], omega * c[(i, j)]);
        }
    }
    // LU in place, the row exchanges in `perm`.
    let mut perm = [0usize; INLINE_MASSES];
    for col in 0..n {
        let pivot = (col..n).max_by(|&a, &b| z[a][col].l1_norm().total_cmp(&z[b][col].l1_norm()))?;
        if z[pivot][col] == zero {
            return None;
        }
        z.swap(col, pivot);
        perm[col] = pivot;
        let (upper, lower) = z.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for row in lower.iter_mut().take(n - col - 1) {
            let f = row[col] / pivot_row[col];
            row[col] = f;
            for (e, u) in row[col + 1..n].iter_mut().zip(&pivot_row[col + 1..n]) {
                *e -= f * u;
            }
        }
    }
    let solve = |b: &mut [Complex64; INLINE_MASSES]| {
        for (col, &p) in perm.iter().enumerate().take(n) {
            b.swap(col, p);
        }
        for col in 0..n {
            let v = b[col];
            for r in col + 1..n {
                b[r] -= z[r][col] * v;
            }
        }
        for col in (0..n).rev() {
            b[col] /= z[col][col];
            let v = b[col];
            for r in 0..col {
                b[r] -= z[r][col] * v;
            }
        }
    };
    let mut x = [zero; INLINE_MASSES];
    match drive {
        Drive::Point(driven, force) => x[driven] = Complex64::new(force, 0.0),
        Drive::Load(load, _) => x[..n].copy_from_slice(&load[..n]),
    }
    solve(&mut x);
    let mut dx = [zero; INLINE_MASSES];
    for (i, d) in dx.iter_mut().enumerate().take(n) {
        let mut acc = zero;
        for (j, xj) in x.iter().enumerate().take(n) {
            acc += Complex64::new(-2.0 * omega * mass[(i, j)], c[(i, j)]) * xj;
        }
        *d = match drive {
            Drive::Point(..) => -acc,
            Drive::Load(_, d_load) => d_load[i] - acc,
        };
    }
    solve(&mut dx);
    Some((x, dx))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The forced response by both ways, which agree (the stack's elimination and nalgebra's
    /// LU pivot alike on these systems).
    fn forced_response(
        k: &DMatrix<f64>,
        c: &DMatrix<f64>,
        m: &DMatrix<f64>,
        omega: f64,
        driven: usize,
        force: f64,
    ) -> Option<(Vec<Complex64>, Vec<Complex64>)> {
        let small = forced_small(k, c, m, omega, Drive::Point(driven, force));
        let large = forced_large(k, c, m, omega, Drive::Point(driven, force));
        let ((xs, dxs), (xl, dxl)) = match (small, large) {
            (Some(s), Some(l)) => (s, l),
            (None, None) => return None,
            (s, l) => panic!("one way singular, the other not: stack {}, LU {}", s.is_some(), l.is_some()),
        };
        let n = k.nrows();
        for i in 0..n {
            assert!((xs[i] - xl[i]).norm() <= 1e-12 * xs.iter().map(|z| z.norm()).fold(0.0, f64::max));
            assert!((dxs[i] - dxl[i]).norm() <= 1e-12 * dxs.iter().map(|z| z.norm()).fold(0.0, f64::max));
        }
        Some((xs[..n].to_vec(), dxs[..n].to_vec()))
    }

    #[test]
    fn forced_response_solves_its_system_and_its_derivative_is_the_difference_quotient() {
        // A 4-mass chain with non-proportional damping and a mass matrix whose largest
        // entries are not on the first rows (the pivoting matters), driven at mass 2.
        let k = DMatrix::from_row_slice(
            4,
            4,
            &[3e4, -2e4, 0.0, 0.0, -2e4, 5e4, -3e4, 0.0, 0.0, -3e4, 4e4, -1e4, 0.0, 0.0, -1e4, 1e4],
        );
        let c = DMatrix::from_row_slice(
            4,
            4,
            &[3.0, -1.0, 0.0, 0.0, -1.0, 2.5, -0.7, 0.0, 0.0, -0.7, 0.9, -0.2, 0.0, 0.0, -0.2, 0.4],
        );
        let m = DMatrix::from_diagonal(&DVector::from_vec(vec![0.5, 0.9, 1.7, 0.3]));
        for omega in [10.0, 150.0, 240.0, 900.0] {
            let (x, dx) = forced_response(&k, &c, &m, omega, 2, 2.6).unwrap();
            // Z X = F e_2, to rounding of the largest term.
            for i in 0..4 {
                let mut r = Complex64::new(if i == 2 { -2.6 } else { 0.0 }, 0.0);
                let mut scale = 2.6;
                for j in 0..4 {
                    let z = Complex64::new(k[(i, j)] - omega * omega * m[(i, j)], omega * c[(i, j)]);
                    r += z * x[j];
                    scale += (z * x[j]).norm();
                }
                assert!(r.norm() < 1e-13 * scale, "omega {omega}: residual {} of {scale}", r.norm());
            }
            // dX/domega against a central difference.
            let h = 1e-5 * omega;
            let (xp, _) = forced_response(&k, &c, &m, omega + h, 2, 2.6).unwrap();
            let (xm, _) = forced_response(&k, &c, &m, omega - h, 2, 2.6).unwrap();
            for i in 0..4 {
                let fd = (xp[i] - xm[i]) / (2.0 * h);
                assert!((fd - dx[i]).norm() <= 1e-6 * dx[i].norm().max(1e-12), "omega {omega}: {fd} vs {}", dx[i]);
            }
        }
        // A singular dynamic stiffness (no damping, at a natural frequency of a single mass).
        let one = DMatrix::from_element(1, 1, 4.0);
        assert!(forced_response(&one, &DMatrix::zeros(1, 1), &DMatrix::from_element(1, 1, 1.0), 2.0, 0, 1.0).is_none());
    }
}
