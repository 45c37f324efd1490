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

/// What [`forced_modal`] reads of a configuration's decomposition (`super::system::Modes`).
pub(in crate::sim) struct ModalParts<'a> {
    /// The representative eigenvalues.
    pub lambda: &'a [Complex64],
    /// Their rows of `V^-1`.
    pub inverse: &'a DMatrix<Complex64>,
    /// The displacement rows of the eigenvectors by term, real and imaginary parts.
    pub rows: &'a [Vec<f64>; 2],
    /// `M` and `M^-1` of the configuration.
    pub mass: &'a DMatrix<f64>,
    /// `M^-1`.
    pub mass_inv: &'a DMatrix<f64>,
}

/// [`forced_into`] of a configuration from its decomposition (`A = V Lambda V^-1`), for
/// structures above [`super::system::LARGE_ABOVE`] degrees of freedom (the paper's keep
/// [`forced_into`]): `Z^-1 F = sum_k V_k (V^-1 B F)_k / (i omega - lambda_k)` over every
/// eigenvalue (a representative and, for a complex pair, its conjugate, whose eigenvector and
/// row of `V^-1` are the conjugates), `B F = (0, M^-1 F)`, `O(n^2)` against a factorisation's
/// `O(n^3)`. That sum carries the eigenvectors' condition times rounding (3e-9 relative on a
/// reduced plate), so each solve is refined once on its residual `F - Z X` (`Z = K - omega^2
/// M + i omega C`, formed from the matrices): then as exact as the factorisation. The
/// derivative solves `Z dX = dF - (dZ/domega) X` the same way. `None` when `i omega` is an
/// eigenvalue (an undamped resonance).
pub(in crate::sim) fn forced_modal(
    (k, c): (&DMatrix<f64>, &DMatrix<f64>),
    modes: &ModalParts,
    omega: f64,
    drive: Drive,
    out: &mut [Forced],
) -> Option<()> {
    let n = out.len();
    let zero = Complex64::new(0.0, 0.0);
    let iw = Complex64::new(0.0, omega);
    // `1 / (i omega - lambda)` of each representative (the conjugate's is the conjugate of
    // `1 / (-i omega - lambda)`).
    let mut poles = Vec::with_capacity(2 * modes.lambda.len());
    for &l in modes.lambda {
        let (s, t) = ((iw - l).inv(), (iw - l.conj()).inv());
        if !(s.re.is_finite() && s.im.is_finite() && t.re.is_finite() && t.im.is_finite()) {
            return None;
        }
        poles.push((s, t));
    }
    let len = modes.lambda.len();
    let (inverse, stride) = (modes.inverse.as_slice(), modes.inverse.nrows());
    let [v_re, v_im] = modes.rows;
    // A real matrix times a complex vector, as two real products.
    let times = |a: &DMatrix<f64>, x: &[Complex64]| -> (DVector<f64>, DVector<f64>) {
        let (re, im) =
            (DVector::from_iterator(n, x.iter().map(|z| z.re)), DVector::from_iterator(n, x.iter().map(|z| z.im)));
        (a * re, a * im)
    };
    // `sum_k V_k (V^-1 B f)_k / (i omega - lambda_k)`, into `x`: `g = M^-1 f`, then the
    // velocity columns of `V^-1` (contiguous) times `g`, then the eigenvectors' rows by term
    // ([`super::system::Modes::by_term`], contiguous).
    let modal = |f: &[Complex64], x: &mut [Complex64]| {
        let (g_re, g_im) = times(modes.mass_inv, f);
        let (mut b, mut b_conj) = (vec![zero; len], vec![zero; len]);
        for j in 0..n {
            let (g, column) = (Complex64::new(g_re[j], g_im[j]), &inverse[(n + j) * stride..(n + j) * stride + len]);
            for ((b, b_conj), u) in b.iter_mut().zip(b_conj.iter_mut()).zip(column) {
                *b += u * g;
                *b_conj += u.conj() * g;
            }
        }
        x.fill(zero);
        for (r, (&lambda, &(s, t))) in modes.lambda.iter().zip(&poles).enumerate() {
            let pair = lambda.im != 0.0;
            let weight = if pair { 2.0 } else { 1.0 };
            let (c1, c2) = (b[r] * s / weight, if pair { b_conj[r] * t / weight } else { zero });
            // `V c1 + conj(V) c2`, `V = a + i b`: real part `a (c1 + c2).re - b (c1 - c2).im`,
            // imaginary part `a (c1 + c2).im + b (c1 - c2).re`.
            let (sum, diff) = (c1 + c2, c1 - c2);
            let (rows_re, rows_im) = (&v_re[r * n..r * n + n], &v_im[r * n..r * n + n]);
            for ((x, a), bb) in x.iter_mut().zip(rows_re).zip(rows_im) {
                x.re += a * sum.re - bb * diff.im;
                x.im += a * sum.im + bb * diff.re;
            }
        }
    };
    // `Z x`, `Z = K - omega^2 M + i omega C`, by real products.
    let z_times = |x: &[Complex64]| -> Vec<Complex64> {
        let ((kr, ki), (mr, mi), (cr, ci)) = (times(k, x), times(modes.mass, x), times(c, x));
        (0..n)
            .map(|i| {
                Complex64::new(
                    kr[i] - omega * omega * mr[i] - omega * ci[i],
                    ki[i] - omega * omega * mi[i] + omega * cr[i],
                )
            })
            .collect()
    };
    // `Z x = f`: the modal sum, refined once on its residual.
    let solve = |f: &[Complex64]| -> Vec<Complex64> {
        let mut x = vec![zero; n];
        modal(f, &mut x);
        let zx = z_times(&x);
        let r: Vec<Complex64> = f.iter().zip(&zx).map(|(f, z)| f - z).collect();
        let mut dx = vec![zero; n];
        modal(&r, &mut dx);
        x.iter_mut().zip(&dx).for_each(|(x, d)| *x += d);
        x
    };
    let (f, df): (Vec<Complex64>, Vec<Complex64>) = match drive {
        Drive::Point(driven, force) => {
            ((0..n).map(|i| if i == driven { Complex64::new(force, 0.0) } else { zero }).collect(), vec![zero; n])
        }
        Drive::Load(load, d_load) => (load[..n].to_vec(), d_load[..n].to_vec()),
    };
    let x = solve(&f);
    // `dF - (dZ/domega) X`, `dZ/domega = -2 omega M + i C`.
    let ((mr, mi), (cr, ci)) = (times(modes.mass, &x), times(c, &x));
    let rhs: Vec<Complex64> =
        (0..n).map(|i| df[i] - Complex64::new(-2.0 * omega * mr[i] - ci[i], -2.0 * omega * mi[i] + cr[i])).collect();
    let dx = solve(&rhs);
    for (o, (x, dx)) in out.iter_mut().zip(x.iter().zip(&dx)) {
        if !(x.re.is_finite() && x.im.is_finite() && dx.re.is_finite() && dx.im.is_finite()) {
            return None;
        }
        *o = Forced { p: x.im, q: x.re, dp: dx.im, dq: dx.re, amp: x.im.hypot(x.re) };
    }
    Some(())
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
