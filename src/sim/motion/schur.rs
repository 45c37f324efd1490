//! The diagonal blocks of the real Schur form's quasi-triangular factor `T`: nalgebra's implicit
//! double-shift QR (`Schur::try_new`, nalgebra 0.35) step for step, without accumulating the
//! orthogonal factor `Q`, which the multipliers of an orbit do not need (it was about a third
//! of the work), and with each sweep's reflections and rotations applied inside the active
//! block only: the rows above it and the columns right of it never enter the eigenvalues
//! (each reflected row or column is updated from itself alone), so they are left as they are
//! (16 % of the time of a 70-square matrix's eigenvalues, the multipliers of a 32-mass chain
//! with three beds). Every operation inside the block is nalgebra's own (its Hessenberg
//! reduction, Householder reflections and Givens rotations, in the same order), so the
//! eigenvalues read off the diagonal blocks are those of
//! `Schur::try_new(..).complex_eigenvalues()` bit for bit (tested in src/sim/motion/eigen.rs,
//! up to 70 square). Outside its diagonal blocks the matrix returned is not `T`.
//!
//! No I/O.

use std::cmp;

use nalgebra::linalg::givens::GivensRotation;
use nalgebra::linalg::{householder, Hessenberg, Schur};
use nalgebra::{Const, DMatrix, DVector, Dyn, Matrix2, Reflection, Unit, Vector2, Vector3};
use num_complex::Complex64;

/// The factor `T` of the real Schur form of `m` on and next to its diagonal (the 1x1 and 2x2
/// blocks: see the module documentation), or `None` after `max_niter` QR sweeps
/// (`0`: no limit), deflating where a subdiagonal element falls below `eps` relative to its
/// neighbours on the diagonal (or `eps^2` absolutely).
pub fn quasi_triangular(m: DMatrix<f64>, eps: f64, max_niter: usize) -> Option<DMatrix<f64>> {
    let dim = m.nrows();
    if dim < 3 {
        return Schur::try_new(m, eps, max_niter).map(|s| s.unpack().1);
    }
    let mut m = m;
    let mut work = DVector::<f64>::zeros(dim);
    let amax_m = m.camax();
    if amax_m != 0.0 {
        m.unscale_mut(amax_m);
    }
    let mut t = Hessenberg::new_with_workspace(m, &mut work).unpack_h();
    let mut niter = 0;
    let (mut start, mut end) = delimit_subproblem(&mut t, eps, dim - 1);
    while end != start {
        let subdim = end - start + 1;
        if subdim > 2 {
            let m = end - 1;
            let n = end;
            let (h11, h12, h21, h22) =
                (t[(start, start)], t[(start, start + 1)], t[(start + 1, start)], t[(start + 1, start + 1)]);
            let h32 = t[(start + 2, start + 1)];
            let (hnn, hmm, hnm, hmn) = (t[(n, n)], t[(m, m)], t[(n, m)], t[(m, n)]);
            let tra = hnn + hmm;
            let det = hnn * hmm - hnm * hmn;
            let mut axis = Vector3::new(h11 * h11 + h12 * h21 - tra * h11 + det, h21 * (h11 + h22 - tra), h21 * h32);
            for k in start..n - 1 {
                let (norm, not_zero) = householder::reflection_axis_mut(&mut axis);
                if not_zero {
                    if k > start {
                        t[(k, k - 1)] = norm;
                        t[(k + 1, k - 1)] = 0.0;
                        t[(k + 2, k - 1)] = 0.0;
                    }
                    let refl = Reflection::new(Unit::new_unchecked(axis), 0.0);
                    let krows = cmp::min(k + 4, end + 1);
                    let mut work = work.rows_mut(0, krows - start);
                    refl.reflect(&mut t.generic_view_mut((k, k), (Const::<3>, Dyn(end + 1 - k))));
                    refl.reflect_rows(&mut t.generic_view_mut((start, k), (Dyn(krows - start), Const::<3>)), &mut work);
                }
                axis.x = t[(k + 1, k)];
                axis.y = t[(k + 2, k)];
                if k < n - 2 {
                    axis.z = t[(k + 3, k)];
                }
            }
            let mut axis = Vector2::new(axis.x, axis.y);
            let (norm, not_zero) = householder::reflection_axis_mut(&mut axis);
            if not_zero {
                let refl = Reflection::new(Unit::new_unchecked(axis), 0.0);
                t[(m, m - 1)] = norm;
                t[(n, m - 1)] = 0.0;
                let mut work = work.rows_mut(0, end + 1 - start);
                refl.reflect(&mut t.generic_view_mut((m, m), (Const::<2>, Dyn(end + 1 - m))));
                refl.reflect_rows(&mut t.generic_view_mut((start, m), (Dyn(end + 1 - start), Const::<2>)), &mut work);
            }
        } else {
            // Decouple the 2x2 block if it has real eigenvalues.
            if let Some(rot) = basis_2x2(&t.fixed_view::<2, 2>(start, start).into_owned()) {
                let inv_rot = rot.inverse();
                inv_rot.rotate(&mut t.generic_view_mut((start, start), (Const::<2>, Dyn(end + 1 - start))));
                rot.rotate_rows(&mut t.generic_view_mut((start, start), (Dyn(end + 1 - start), Const::<2>)));
                t[(end, start)] = 0.0;
            }
            if end > 2 {
                end -= 2;
            } else {
                break;
            }
        }
        (start, end) = delimit_subproblem(&mut t, eps, end);
        niter += 1;
        if niter == max_niter {
            return None;
        }
    }
    t.scale_mut(amax_m);
    Some(t)
}

/// The eigenvalues of a quasi-triangular `t` (1x1 and 2x2 diagonal blocks), in order.
pub fn block_eigenvalues(t: &DMatrix<f64>) -> Vec<Complex64> {
    let dim = t.nrows();
    let mut out = Vec::with_capacity(dim);
    let mut m = 0;
    while m + 1 < dim {
        let n = m + 1;
        if t[(n, m)] == 0.0 {
            out.push(Complex64::new(t[(m, m)], 0.0));
            m += 1;
        } else {
            let (hmm, hnm, hmn, hnn) = (t[(m, m)], t[(n, m)], t[(m, n)], t[(n, n)]);
            let val = (hmm - hnn) * 0.5;
            let discr = hnm * hmn + val * val;
            let sqrt_discr = Complex64::new(0.0, (-discr).sqrt());
            let half_tra = (hnn + hmm) * 0.5;
            out.push(Complex64::new(half_tra, 0.0) + sqrt_discr);
            out.push(Complex64::new(half_tra, 0.0) - sqrt_discr);
            m += 2;
        }
    }
    if m + 1 == dim {
        out.push(Complex64::new(t[(m, m)], 0.0));
    }
    out
}

/// Where the active block ends (`end`, going up from it past negligible subdiagonal elements,
/// set to zero) and starts.
fn delimit_subproblem(t: &mut DMatrix<f64>, eps: f64, end: usize) -> (usize, usize) {
    let mut n = end;
    let absolute_threshold = eps * eps;
    while n > 0 {
        let m = n - 1;
        let off_diag_norm = t[(n, m)].abs();
        if off_diag_norm <= absolute_threshold || off_diag_norm <= eps * (t[(n, n)].abs() + t[(m, m)].abs()) {
            t[(n, m)] = 0.0;
        } else {
            break;
        }
        n -= 1;
    }
    if n == 0 {
        return (0, 0);
    }
    let mut new_start = n - 1;
    while new_start > 0 {
        let m = new_start - 1;
        let off_diag = t[(new_start, m)];
        let off_diag_norm = off_diag.abs();
        if off_diag == 0.0
            || off_diag_norm <= absolute_threshold
            || off_diag_norm <= eps * (t[(new_start, new_start)].abs() + t[(m, m)].abs())
        {
            t[(new_start, m)] = 0.0;
            break;
        }
        new_start -= 1;
    }
    (new_start, n)
}

/// The rotation that upper-triangulates a 2x2 block with real eigenvalues (`None` for complex
/// ones or a block already triangular).
fn basis_2x2(m: &Matrix2<f64>) -> Option<GivensRotation<f64>> {
    let h10 = m[(1, 0)];
    if h10 == 0.0 {
        return None;
    }
    let (h00, h01, h11) = (m[(0, 0)], m[(0, 1)], m[(1, 1)]);
    let val = (h00 - h11) * 0.5;
    let discr = h10 * h01 + val * val;
    // nalgebra's `try_sqrt`: no root of a negative (or NaN) discriminant.
    if discr.partial_cmp(&0.0).is_none_or(|o| o == std::cmp::Ordering::Less) {
        return None;
    }
    let sqrt_discr = discr.sqrt();
    let half_tra = (h00 + h11) * 0.5;
    let (eigval1, eigval2) = (half_tra + sqrt_discr, half_tra - sqrt_discr);
    let x1 = eigval1 - h11;
    let x2 = eigval2 - h11;
    if x1.abs() > x2.abs() {
        Some(GivensRotation::new(x1, h10).0)
    } else {
        Some(GivensRotation::new(x2, h10).0)
    }
}
