//! Eigendecomposition of a real, non-symmetric matrix with complex eigenvalues and
//! eigenvectors: eigenvalues from nalgebra's Schur form (its factor `T` alone,
//! src/sim/motion/schur.rs), eigenvectors by inverse iteration,
//! each eigenpair refined and its residual measured.
//!
//! Every call is bounded. nalgebra's implicit double-shift QR has no exceptional shifts and,
//! without a limit, can cycle for ever (a Floquet Jacobian whose zero multipliers carry
//! off-diagonal noise above its absolute deflation threshold did, at one point of Fig. 8's
//! sweep). [`eigenvalues`] runs it with at most [`SWEEPS_PER_ROW`] QR sweeps per row, and when
//! that is not enough on the matrix itself, on two similar matrices whose spectrum is the same
//! (a shift by half the matrix's norm, which moves zero eigenvalues off zero where the relative
//! deflation test works; then a fixed orthogonal reflection), at most
//! `3 * SWEEPS_PER_ROW * n` sweeps in all. When every attempt is used up it says so: the
//! caller then records a stated reason instead of a value.

use nalgebra::{DMatrix, DVector};

use super::schur::{block_eigenvalues, quasi_triangular};
use num_complex::Complex64;

/// QR sweeps allowed per row of the matrix in one attempt (LAPACK's `dlahqr` allows 30; its
/// exceptional shifts make it converge where nalgebra's plain shifts may need more).
pub const SWEEPS_PER_ROW: usize = 60;

/// Why a matrix has no eigenvalues here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EigenError {
    /// An element is NaN or infinite.
    NotFinite,
    /// The QR iteration did not converge within its bound on any of the three similar
    /// matrices: the bound per attempt, in sweeps.
    NoConvergence {
        /// QR sweeps made before giving up.
        sweeps: usize,
    },
}

impl std::fmt::Display for EigenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EigenError::NotFinite => write!(f, "the matrix has a NaN or infinite element"),
            EigenError::NoConvergence { sweeps } => write!(
                f,
                "the eigenvalue iteration did not converge within {sweeps} QR sweeps on the matrix and two similar ones"
            ),
        }
    }
}

impl std::error::Error for EigenError {}

/// The eigenvalues of a square real matrix, in the order the Schur form gives them; bounded
/// (see the module documentation). On a matrix where the first attempt converges (every one
/// met so far but one), the values are those of nalgebra's `complex_eigenvalues` bit for bit.
pub fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<Complex64>, EigenError> {
    let n = a.nrows();
    if a.iter().any(|x| !x.is_finite()) {
        return Err(EigenError::NotFinite);
    }
    let sweeps = SWEEPS_PER_ROW * n.max(1);
    let run = |m: DMatrix<f64>| quasi_triangular(m, f64::EPSILON, sweeps).map(|t| block_eigenvalues(&t));
    if let Some(l) = run(a.clone()) {
        return Ok(l);
    }
    // A shift by half the norm: the spectrum moves by the same amount, and eigenvalues at
    // zero (where the deflation test is absolute, eps^2) come to where it is relative.
    let shift = 0.5 * a.norm().max(f64::MIN_POSITIVE);
    let shifted = a + DMatrix::identity(n, n) * shift;
    if let Some(l) = run(shifted) {
        return Ok(l.into_iter().map(|z| z - shift).collect());
    }
    // A fixed Householder reflection H = I - 2 w w^T / w^T w (H = H^T = H^-1): H A H is similar
    // to A with other rounding and another Hessenberg form.
    let w = DVector::<f64>::from_fn(n, |i, _| 1.0 + (i as f64 * 0.7548776662466927).fract());
    let h = DMatrix::identity(n, n) - &w * w.transpose() * (2.0 / w.norm_squared());
    if let Some(l) = run(&h * a * &h) {
        return Ok(l);
    }
    Err(EigenError::NoConvergence { sweeps })
}

/// `A = V diag(lambda) V^-1`, with complex eigenvalues in exact conjugate pairs.
#[derive(Debug, Clone)]
pub struct Eigen {
    /// Eigenvalues, largest modulus first.
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

/// Eigenvalues closer than this times the matrix's norm are one cluster: inverse iteration
/// from a shift 1e-10 of the norm away cannot tell them apart (a ratio of 0.99 per step
/// between their amplifications), as with a repeated natural frequency of a symmetric
/// structure (its copies differ by rounding), so each member's vector is kept orthogonal to
/// those of the members found before it: a well-conditioned basis of the cluster's
/// eigenspace, where the plain iteration gave the same vector twice (eigenvector condition
/// 1e17). A wider bound would be wrong for distinct eigenvalues that inverse iteration does
/// separate: the state matrix is not normal, its eigenvectors not orthogonal, and an
/// orthogonalised vector is then no eigenvector.
pub const CLUSTER: f64 = 1e-12;

/// Removes from `v` its components along the orthonormal `others` (twice: classical
/// Gram-Schmidt repeated is as good as modified), then normalises it; `None` when nothing is
/// left (`v` lay in their span).
fn orthogonal_to(v: &mut DVector<Complex64>, others: &[&DVector<Complex64>]) -> Option<()> {
    for _ in 0..2 {
        for o in others {
            let along = o.dotc(v);
            v.axpy(-along, o, Complex64::new(1.0, 0.0));
        }
    }
    let norm = v.norm();
    if !norm.is_finite() || norm == 0.0 {
        return None;
    }
    *v /= Complex64::new(norm, 0.0);
    Some(())
}

/// The start of inverse iteration for the member of a cluster that has `mates` found before
/// it: the same fixed vector for the first (so that distinct eigenvalues get the vectors they
/// always had), then vectors of a fixed pseudo-random sequence, whose components in the
/// cluster's eigenspace are independent of the earlier members' (the fixed vector's, less its
/// part along the first member, would have none left there).
fn start(n: usize, mates: usize) -> DVector<Complex64> {
    if mates == 0 {
        return DVector::from_fn(n, |i, _| Complex64::new(1.0 + 0.1 * i as f64, 0.3 - 0.05 * i as f64));
    }
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64.wrapping_mul(mates as u64 + 1);
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    DVector::from_fn(n, |_, _| Complex64::new(next(), next()))
}

/// The members found before `lambda` of its cluster ([`CLUSTER`]): their unit vectors.
fn mates(found: &[(Complex64, DVector<Complex64>)], lambda: Complex64, norm_a: f64) -> Vec<&DVector<Complex64>> {
    found.iter().filter(|(l, _)| (l - lambda).norm() <= CLUSTER * norm_a).map(|(_, v)| v).collect()
}

/// One eigenpair by inverse iteration from a nearby shift, refined by a Rayleigh quotient;
/// the vector kept orthogonal to `mates` (unit vectors of the same cluster found before).
fn eigenpair(
    ac: &DMatrix<Complex64>,
    lambda: Complex64,
    norm_a: f64,
    mates: &[&DVector<Complex64>],
) -> Option<(Complex64, DVector<Complex64>, f64)> {
    let n = ac.nrows();
    // A shift just off the eigenvalue keeps the LU factor non-singular while the solve
    // amplifies the eigenvector direction by ~1 / shift.
    let shift = lambda + Complex64::new(1e-10 * norm_a, 1e-10 * norm_a);
    let mut b = ac.clone();
    for i in 0..n {
        b[(i, i)] -= shift;
    }
    let lu = b.lu();
    let mut v = start(n, mates.len());
    if !mates.is_empty() {
        orthogonal_to(&mut v, mates)?;
    }
    for _ in 0..3 {
        v = lu.solve(&v)?;
        orthogonal_to(&mut v, mates)?;
    }
    let av = ac * &v;
    let lambda = v.dotc(&av) / v.dotc(&v);
    let r = (&av - &v * lambda).norm() / norm_a;
    unit_phase(&mut v);
    Some((lambda, v, r))
}

/// Turns `v` so that its largest element is real and positive (reproducible vectors).
fn unit_phase(v: &mut DVector<Complex64>) {
    let (imax, _) =
        v.iter().enumerate().fold((0, 0.0), |acc, (i, c)| if c.norm() > acc.1 { (i, c.norm()) } else { acc });
    let phase = v[imax] / v[imax].norm();
    *v /= phase;
}

/// The eigenvalues of `a` ([`eigenvalues`]) in a deterministic order: by imaginary part
/// (descending), then real part.
fn ordered_eigenvalues(a: &DMatrix<f64>) -> Option<Vec<Complex64>> {
    let mut values = eigenvalues(a).ok()?;
    values.sort_by(|x, y| y.im.total_cmp(&x.im).then(x.re.total_cmp(&y.re)));
    Some(values)
}

/// Decomposes `a`. Returns `None` when `a` is defective (eigenvectors not independent), which
/// a damped mechanical system with distinct modes never is, or when its eigenvalues cannot be
/// computed within the bound of [`eigenvalues`].
pub fn decompose(a: &DMatrix<f64>) -> Option<Eigen> {
    let n = a.nrows();
    let ac: DMatrix<Complex64> = a.map(|v| Complex64::new(v, 0.0));
    let norm_a = a.norm().max(f64::MIN_POSITIVE);
    let schur = ordered_eigenvalues(a)?;
    let mut values = Vec::with_capacity(n);
    let mut columns: Vec<DVector<Complex64>> = Vec::with_capacity(n);
    let mut representatives = Vec::new();
    let mut residual: f64 = 0.0;
    // Each representative's Schur eigenvalue and unit vector (before its phase is turned).
    let mut found: Vec<(Complex64, DVector<Complex64>)> = Vec::new();
    for lambda in schur.iter().copied() {
        let is_complex = lambda.im.abs() > 1e-12 * lambda.norm();
        if is_complex && lambda.im < 0.0 {
            continue; // the conjugate of a pair already taken
        }
        let (mut l, mut v, r) = eigenpair(&ac, lambda, norm_a, &mates(&found, lambda, norm_a))?;
        found.push((lambda, v.clone()));
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

/// Decomposes the state matrix `a = [0 I; -M^-1 K -M^-1 C]` of `M x'' + C x' + K x = f`
/// on the second-order problem itself: the eigenvalues from the Schur form of `a` (as
/// [`decompose`], in its order), each eigenpair then by inverse iteration on
/// `Q(l) = l^2 M + l C + K` (three steps from a fixed vector, the eigenvalue after each the
/// root nearest it of `x^H Q(l) x = 0`), each eigenvector written `(x, l x)`.
///
/// The state matrix of a stiff structure is badly scaled (entries 1 beside the square of its
/// fastest rate, 4e9 s^-2 on a reduced plate whose fastest fixed-interface modes are near 8
/// kHz): inverse iteration on it ([`decompose`]) leaves each eigenvector's velocity half off
/// its position half times its rate by up to 1e-5 of its norm on the slow modes (5e-4 on two
/// modes 0.2 % apart), so a segment started from a state reproduced its velocities only to
/// 1e-4 (2e-6 m/s at a plate's container, where the next impact is decided on 1e-9) and its
/// accelerations to 1e-3 m/s^2. On `Q` the slow modes are as well separated as the structure
/// makes them, and `(x, l x)` is a state of that exact form: a segment reproduces its start to
/// the rounding of `V^-1`. Each step factors an `n x n` matrix, not the `2n x 2n` of
/// [`decompose`]. Returns `None` as [`decompose`] does, or where a step's vector vanishes.
pub fn decompose_second_order(a: &DMatrix<f64>, m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> Option<Eigen> {
    let n = m.nrows();
    let cx = |a: &DMatrix<f64>| a.map(|v| Complex64::new(v, 0.0));
    let (mc, cc, kc) = (cx(m), cx(c), cx(k));
    let form = |v: &DVector<Complex64>, a: &DMatrix<Complex64>| v.dotc(&(a * v));
    let schur = ordered_eigenvalues(a)?;
    let norm_a = a.norm().max(f64::MIN_POSITIVE);
    let mut values = Vec::with_capacity(2 * n);
    let mut columns: Vec<DVector<Complex64>> = Vec::with_capacity(2 * n);
    let mut representatives = Vec::new();
    // Each representative's Schur eigenvalue and unit displacement part (the cluster's
    // members are kept orthogonal in it: [`CLUSTER`]).
    let mut found: Vec<(Complex64, DVector<Complex64>)> = Vec::new();
    for lambda in schur.iter().copied() {
        let real = lambda.im.abs() <= 1e-12 * lambda.norm();
        if !real && lambda.im < 0.0 {
            continue;
        }
        let others = mates(&found, lambda, norm_a);
        let mut l = if real { Complex64::new(lambda.re, 0.0) } else { lambda };
        let mut x = start(n, others.len());
        if !others.is_empty() {
            orthogonal_to(&mut x, &others)?;
        }
        for _ in 0..3 {
            let q = &mc * (l * l) + &cc * l + &kc;
            let dq = &mc * (l * 2.0) + &cc;
            x = q.lu().solve(&(dq * &x))?;
            if real {
                x = x.map(|z| Complex64::new(z.re, 0.0));
            }
            orthogonal_to(&mut x, &others)?;
            // The root of a l^2 + b l + c = 0 nearest the current value.
            let (a2, b1, c0) = (form(&x, &mc), form(&x, &cc), form(&x, &kc));
            let root = (b1 * b1 - a2 * c0 * 4.0).sqrt();
            let (r1, r2) = ((-b1 + root) / (a2 * 2.0), (-b1 - root) / (a2 * 2.0));
            l = if (r1 - l).norm() <= (r2 - l).norm() { r1 } else { r2 };
            if real {
                l = Complex64::new(l.re, 0.0);
            }
        }
        found.push((lambda, x.clone()));
        let mut v = DVector::<Complex64>::from_fn(2 * n, |i, _| if i < n { x[i] } else { l * x[i - n] });
        let norm = v.norm();
        v /= Complex64::new(norm, 0.0);
        unit_phase(&mut v);
        representatives.push((values.len(), if real { 1.0 } else { 2.0 }));
        values.push(l);
        columns.push(v.clone());
        if !real {
            values.push(l.conj());
            columns.push(v.map(|z| z.conj()));
        }
    }
    if values.len() != 2 * n {
        return None;
    }
    let vectors = DMatrix::from_columns(&columns);
    let ac: DMatrix<Complex64> = cx(a);
    let residual = columns.iter().zip(&values).map(|(v, &l)| (&ac * v - v * l).norm() / norm_a).fold(0.0, f64::max);
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

    /// A stiff chain's state matrix, mass, damping and stiffness: soft springs at one end,
    /// springs 1e5 times stiffer at the other (slow modes near 30 rad/s, fast ones near 9e4),
    /// non-proportional damping.
    fn stiff_chain(n: usize) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
        let masses: Vec<f64> = (0..n).map(|i| 0.2 + 0.013 * i as f64).collect();
        let springs: Vec<f64> = (0..n).map(|i| if i < n / 2 { 2e3 * (1.0 + 0.1 * i as f64) } else { 2e8 }).collect();
        let mut k = DMatrix::<f64>::zeros(n, n);
        for (i, &s) in springs.iter().enumerate() {
            k[(i, i)] += s;
            if i > 0 {
                k[(i - 1, i - 1)] += s;
                k[(i, i - 1)] -= s;
                k[(i - 1, i)] -= s;
            }
        }
        let m = DMatrix::from_diagonal(&DVector::from_vec(masses));
        let mut c = &k * 2e-6 + &m * 0.5;
        c[(0, 0)] += 0.3;
        (state_matrix(&m, &c, &k), m, c, k)
    }

    /// `[0 I; -M^-1 K -M^-1 C]`.
    pub(super) fn state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
        let n = m.nrows();
        let m_inv = m.clone().try_inverse().unwrap();
        let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
        let (mk, mc) = (-&m_inv * k, -&m_inv * c);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
            for j in 0..n {
                a[(n + i, j)] = mk[(i, j)];
                a[(n + i, n + j)] = mc[(i, j)];
            }
        }
        a
    }

    /// Largest `|v_{n+p} - l v_p| / |v|` over the eigenvectors: how far each is from a state
    /// of the second-order form `(x, l x)`.
    fn mismatch(e: &Eigen, n: usize) -> f64 {
        (0..2 * n)
            .map(|k| {
                let v = e.vectors.column(k);
                (0..n).map(|p| (v[n + p] - e.values[k] * v[p]).norm()).fold(0.0, f64::max) / v.norm()
            })
            .fold(0.0, f64::max)
    }

    /// On a stiff chain the state matrix's eigenvectors are off the second-order form by far
    /// more than rounding; from the second-order problem each is of that form to rounding, solves `Q(l) x = 0` to
    /// rounding of `K`, and the decomposition still reconstructs the state matrix.
    #[test]
    fn second_order_eigenpairs_are_states_of_that_form() {
        let n = 16;
        let (a, m, c, k) = stiff_chain(n);
        let before = mismatch(&decompose(&a).unwrap(), n);
        let e = decompose_second_order(&a, &m, &c, &k).unwrap();
        let after = mismatch(&e, n);
        assert!(before > 1e-9, "the state matrix's own vectors: {before:e}");
        assert!(after < 1e-14, "refined: {after:e} (before {before:e})");
        let cx = |a: &DMatrix<f64>| a.map(|v| Complex64::new(v, 0.0));
        for (kk, &l) in e.values.iter().enumerate() {
            let x: DVector<Complex64> = e.vectors.column(kk).rows(0, n).into_owned();
            let q = cx(&m) * (l * l) + cx(&c) * l + cx(&k);
            let r = (q * &x).norm() / (k.norm() * x.norm());
            assert!(r < 1e-14, "mode {kk} ({l}): residual {r:e}");
        }
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(e.values.clone()));
        let back = &e.vectors * d * &e.inverse;
        let err = (back.map(|z| z.re) - &a).norm() / a.norm();
        assert!(err < 1e-12, "reconstruction error {err}");
        // The state is reproduced: V V^-1 z = z for a state z of velocities near 1 and
        // displacements near 1e-4, its velocities to 1e-12.
        let z = DVector::from_fn(2 * n, |i, _| if i < n { 1e-4 * (i as f64).sin() } else { (0.3 * i as f64).cos() });
        let back = &e.vectors * (&e.inverse * cx(&DMatrix::from_column_slice(2 * n, 1, z.as_slice())));
        let dv = (n..2 * n).map(|i| (back[i].re - z[i]).abs()).fold(0.0, f64::max);
        assert!(dv < 1e-12, "velocities reproduced to {dv:e}");
    }

    #[test]
    fn eigenvalues_are_nalgebras_bit_for_bit() {
        // Matrices of the sizes the multipliers have (2n + 2 free beds), filled by a fixed
        // pseudo-random sequence: real pairs, complex pairs, a zero row (zero eigenvalues) and a
        // rank-one matrix; the values must be those of nalgebra's Schur form with its Q.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut cases: Vec<DMatrix<f64>> = Vec::new();
        for n in [2usize, 3, 4, 6, 8, 10, 12] {
            for _ in 0..20 {
                cases.push(DMatrix::from_fn(n, n, |_, _| next()));
            }
        }
        // The sizes of 16- and 32-mass chains with three beds, where the problem splits into
        // several active blocks before it ends, and a block-diagonal matrix that splits at once.
        for n in [38usize, 70] {
            for _ in 0..3 {
                cases.push(DMatrix::from_fn(n, n, |_, _| next()));
            }
        }
        let mut blocks = DMatrix::zeros(30, 30);
        for b in 0..3 {
            blocks.view_mut((10 * b, 10 * b), (10, 10)).copy_from(&DMatrix::from_fn(10, 10, |_, _| next()));
        }
        cases.push(blocks);
        let mut zero_row = DMatrix::from_fn(8, 8, |_, _| next());
        zero_row.row_mut(3).fill(0.0);
        cases.push(zero_row);
        let u = DVector::from_fn(6, |_, _| next());
        cases.push(&u * u.transpose());
        for a in cases {
            let n = a.nrows();
            let ours = eigenvalues(&a).unwrap();
            let theirs: Vec<Complex64> = nalgebra::Schur::try_new(a.clone(), f64::EPSILON, SWEEPS_PER_ROW * n)
                .unwrap()
                .complex_eigenvalues()
                .iter()
                .copied()
                .collect();
            assert_eq!(ours.len(), theirs.len());
            for (x, y) in ours.iter().zip(&theirs) {
                assert!(x.re.to_bits() == y.re.to_bits() && x.im.to_bits() == y.im.to_bits(), "{n}x{n}: {x} vs {y}");
            }
        }
    }
}
#[cfg(test)]
mod repeated {
    use super::*;

    /// The paper's chain (modal damping 0.01) beside eight identical oscillators joined to
    /// nothing: an eigenvalue pair of multiplicity eight, the Schur form's copies 3e-11 apart.
    #[test]
    fn a_repeated_eigenvalue_gets_a_well_conditioned_eigenspace_on_both_paths() {
        let n = 11;
        let mut k = DMatrix::<f64>::identity(n, n) * 1e4;
        k.view_mut((0, 0), (3, 3)).copy_from(&crate::model::structure::chain_stiffness(&[24.3e3, 21.8e3, 19.8e3]));
        let masses: Vec<f64> = [0.74, 0.71, 0.64].into_iter().chain(std::iter::repeat_n(1.0, n - 3)).collect();
        let damping = crate::model::Damping::ModalRatios(vec![0.01; n]);
        let c = crate::model::Structure::from_matrices(&masses, k.clone(), damping).damping;
        let m = DMatrix::from_diagonal(&DVector::from_vec(masses));
        let a = super::tests::state_matrix(&m, &c, &k);
        let condition = |e: &Eigen| {
            e.vectors.iter().map(|z| z.norm()).fold(0.0, f64::max)
                * e.inverse.iter().map(|z| z.norm()).fold(0.0, f64::max)
        };
        for (path, e) in [
            ("state matrix", decompose(&a).unwrap()),
            ("second order", decompose_second_order(&a, &m, &c, &k).unwrap()),
        ] {
            // Before: condition 9e5 and residual 5e-6 on the state matrix, 4e31 on the second
            // order (three of the cluster's vectors converged to the chain's modes).
            assert!(condition(&e) < 1e3, "{path}: condition {:e}", condition(&e));
            assert!(e.residual < 1e-15, "{path}: residual {:e}", e.residual);
            let d = DMatrix::from_diagonal(&DVector::from_vec(e.values.clone()));
            let back = (&e.vectors * d * &e.inverse).map(|z| z.re);
            let err = (back - &a).norm() / a.norm();
            assert!(err < 1e-13, "{path}: reconstruction {err:e}");
            let at_100 = e.values.iter().filter(|l| (l.im.abs() - 99.995).abs() < 1e-2).count();
            assert_eq!(at_100, 16, "{path}: the oscillators' eight pairs");
        }
    }
}
