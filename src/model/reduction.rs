//! Craig-Bampton reduction of a finite-element model to the degrees of freedom where the shot
//! acts (docs/model.md, section 1.5): the boundary degrees of freedom `b` (every container
//! host, the force point, every reported response) stay physical; the interior `i` is
//! represented by its static response to the boundary (constraint modes
//! `Psi = -K_ii^-1 K_ib`) and its lowest fixed-interface modes (`K_ii Phi = M_ii Phi Lambda`).
//! With `T = [[I, 0], [Psi, Phi]]`, `M_r = T^T M T` and `K_r = T^T K T`: a full mass matrix,
//! whose first coordinates are the boundary's displacements. Dense: for models of up to a few
//! thousand degrees of freedom. No I/O.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use rayon::prelude::*;

use super::lanczos::{lowest, Eigen, Failure, Want};
use super::modes::symmetric_modes;
use super::sparse::{rcm, Cost, Singular, Skyline, SymSparse};

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
    /// The eigen solver's certificate failed: fewer fixed-interface modes found below the
    /// last one kept than the inertia of `K_ii - s M_ii` counts there.
    Missed {
        /// Found.
        found: usize,
        /// Counted.
        counted: usize,
    },
    /// A matrix of the interior is not positive definite: a zero or negative pivot of its
    /// factor at `row` (0-based, the full model's numbering).
    NotPositive {
        /// Which matrix.
        matrix: Matrix,
        /// The row.
        row: usize,
    },
    /// A reduced matrix is not positive definite: a zero (to 1e-12 of its diagonal) or
    /// negative pivot at reduced coordinate `coordinate` (0-based: the boundary's first, then
    /// the fixed-interface modes). A free-floating part held at one point, or an indefinite
    /// entry at a point.
    ReducedNotPositive {
        /// Which matrix.
        matrix: Matrix,
        /// The coordinate.
        coordinate: usize,
    },
    /// The interior's factor would be larger or costlier than allowed ([`MAX_FACTOR`]),
    /// known before it is allocated.
    TooLarge {
        /// Interior degrees of freedom.
        dofs: usize,
        /// Its cost.
        cost: Cost,
    },
    /// The boundary and the fixed-interface modes asked for make more coordinates than the
    /// caller allows (counted before any mode is computed).
    TooMany {
        /// Boundary degrees of freedom.
        boundary: usize,
        /// Fixed-interface modes the request keeps.
        modes: usize,
        /// The most coordinates allowed.
        most: usize,
    },
}

/// The mass or the stiffness matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Matrix {
    /// `M`.
    Mass,
    /// `K`.
    Stiffness,
}

impl std::fmt::Display for Matrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Matrix::Mass => "mass",
            Matrix::Stiffness => "stiffness",
        })
    }
}

/// The largest factor of a sparse reduction: stored entries (8 bytes each: 400 MB) and
/// floating-point operations (about half a minute on one core of a 2025 machine). Up to three
/// factors of this size are held at once. A supernodal or multifrontal factor (fill-reducing
/// nested dissection) would lift the limit for solid models (docs/fe-models.md).
pub const MAX_FACTOR: Cost = Cost { entries: 50_000_000, flops: 1e11 };

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
                "the interior degrees of freedom are not held by the boundary (K_ii or M_ii not positive definite): a rigid-body motion, a zero-energy (hourglass) mode of reduced-integration elements, or a degree of freedom without mass"
            ),
            ReductionError::Missed { found, counted } => write!(
                f,
                "the eigen solver could not certify the fixed-interface modes asked for: it found {found} below the last where the inertia of K_ii - s M_ii counts {counted} (shift-invert Lanczos resolves the low end of a spectrum, not most of it): keep fewer modes or a lower cutoff"
            ),
            ReductionError::NotPositive { matrix, row } => write!(
                f,
                "the interior's {matrix} matrix is not positive definite: its factor has a zero or negative pivot at row {}",
                row + 1
            ),
            ReductionError::ReducedNotPositive { matrix, coordinate } => write!(
                f,
                "the reduced {matrix} matrix is not positive definite at coordinate {}",
                coordinate + 1
            ),
            ReductionError::TooLarge { dofs, cost } => write!(
                f,
                "the factor of its {dofs} interior degrees of freedom (reverse Cuthill-McKee order) holds {} entries and costs {:.1e} operations, more than the {} entries and {:.0e} operations allowed",
                cost.entries, cost.flops, MAX_FACTOR.entries, MAX_FACTOR.flops
            ),
            ReductionError::TooMany { boundary, modes, most } => write!(
                f,
                "{boundary} points and {modes} fixed-interface modes make {} coordinates, more than the {most} allowed",
                boundary + modes
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

/// The degrees of freedom of `0..n` not in `boundary`, ascending; a boundary degree of freedom
/// outside the model or named twice is an error.
fn interior(n: usize, boundary: &[usize]) -> Result<Vec<usize>, ReductionError> {
    let mut is_boundary = vec![false; n];
    for &b in boundary {
        if b >= n || is_boundary[b] {
            return Err(ReductionError::Boundary { dof: b });
        }
        is_boundary[b] = true;
    }
    Ok((0..n).filter(|&i| !is_boundary[i]).collect())
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
    let interior = interior(n, boundary)?;
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

/// How many fixed-interface modes a reduction keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Keep {
    /// The lowest `n`.
    Count(usize),
    /// Every mode below this natural frequency, rad/s.
    Below(f64),
}

/// [`craig_bampton`] of a sparse model: `K_ii` factored once in envelope storage (reverse
/// Cuthill-McKee order), the constraint modes by its solves, the fixed-interface modes by
/// shift-invert Lanczos certified by inertia counts ([`super::lanczos`]). The same reduced
/// model as the dense function to rounding; `cutoff` is the lowest mode left out (found too).
/// With `most`, a request whose boundary and kept modes make more coordinates is refused
/// ([`ReductionError::TooMany`]) once counted (one factorisation), before any mode is computed.
pub fn craig_bampton_sparse(
    m: &SymSparse,
    k: &SymSparse,
    boundary: &[usize],
    keep: Keep,
    most: Option<usize>,
) -> Result<Reduced, ReductionError> {
    let n = m.n();
    let finite = |a: &SymSparse| (0..a.n()).all(|i| a.row(i).all(|(_, v)| v.is_finite()));
    if k.n() != n || !finite(m) || !finite(k) {
        return Err(ReductionError::Shape);
    }
    let interior = interior(n, boundary)?;
    let (nb, ni) = (boundary.len(), interior.len());
    let (k_ii, m_ii) = (k.principal(&interior), m.principal(&interior));
    let order = rcm(&k_ii);
    // Its size and cost known before anything of them is allocated.
    let cost = Skyline::cost(&k_ii, Some(&m_ii), &order);
    if cost.entries > MAX_FACTOR.entries || cost.flops > MAX_FACTOR.flops {
        return Err(ReductionError::TooLarge { dofs: ni, cost });
    }
    let rows = &interior;
    let not_positive = |matrix| move |e: Singular| ReductionError::NotPositive { matrix, row: rows[e.row] };
    let mut factor = Skyline::pattern(&k_ii, Some(&m_ii), order.clone());
    factor.factor(&k_ii, None).map_err(not_positive(Matrix::Stiffness))?;
    factor.positive().map_err(not_positive(Matrix::Stiffness))?;
    // M_ii may be singular (massless directions of a consistent mass matrix, of infinite
    // frequency) but not indefinite: K_ii + s M_ii is positive definite for every s > 0 then,
    // and has a negative pivot once s passes -lambda of a negative-mass direction (K v =
    // lambda M v, lambda < 0). s = 1e4 times the largest diagonal ratio K_ii / M_ii finds every
    // such direction of a frequency up to 100 times the model's (a factor of a positive
    // definite matrix: stable, where M_ii's own would divide by its zero pivots). Factored in
    // the pattern the shifted factor uses below.
    let s = 1e4 * k_ii.diagonal().iter().zip(m_ii.diagonal()).map(|(k, m)| k / m).fold(0.0, f64::max);
    let mut shifted = Skyline::pattern(&k_ii, Some(&m_ii), order);
    shifted.factor(&k_ii, Some((&m_ii, -s))).map_err(not_positive(Matrix::Mass))?;
    shifted.positive().map_err(not_positive(Matrix::Mass))?;
    let k_ib = k.block(&interior, boundary);
    let mut t = DMatrix::<f64>::zeros(n, nb);
    let mut col = vec![0.0; ni];
    for (c, &b) in boundary.iter().enumerate() {
        col.iter_mut().zip(k_ib.column(c).iter()).for_each(|(x, v)| *x = -v);
        factor.solve(&mut col);
        t[(b, c)] = 1.0;
        for (r, &i) in interior.iter().enumerate() {
            t[(i, c)] = col[r];
        }
    }
    // One mode more than kept: the lowest left out is the cutoff.
    let count = match keep {
        Keep::Count(c) => c,
        Keep::Below(w) => shifted.factor(&k_ii, Some((&m_ii, w * w))).map_err(|_| ReductionError::Interior)?,
    }
    .min(ni);
    drop(shifted);
    if let Some(most) = most.filter(|&most| nb + count > most) {
        return Err(ReductionError::TooMany { boundary: nb, modes: count, most });
    }
    let want = Want::Count((count + 1).min(ni));
    let eig = if ni == 0 {
        None
    } else {
        Some(lowest(&k_ii, &m_ii, &factor, want).map_err(|e| match e {
            Failure::Singular(_) => ReductionError::Interior,
            Failure::Missed { found, counted } => ReductionError::Missed { found, counted },
        })?)
    };
    let (values, vectors) = match &eig {
        Some(e) => (e.values.clone(), e.vectors.clone()),
        None => (Vec::new(), DMatrix::zeros(0, 0)),
    };
    let kept = count.min(values.len());
    let mut t = t.resize_horizontally(nb + kept, 0.0);
    for q in 0..kept {
        for (r, &i) in interior.iter().enumerate() {
            t[(i, nb + q)] = vectors[(r, q)];
        }
    }
    let project = |a: &SymSparse| {
        let mut at = DMatrix::<f64>::zeros(n, t.ncols());
        let mut y = vec![0.0; n];
        for c in 0..t.ncols() {
            let x: Vec<f64> = t.column(c).iter().copied().collect();
            a.mul(&x, &mut y);
            at.column_mut(c).iter_mut().zip(&y).for_each(|(p, v)| *p = *v);
        }
        let r = t.transpose() * at;
        (&r + r.transpose()) * 0.5
    };
    let (mass, stiffness) = (project(m), project(k));
    // The modal block is diagonal and positive (M-orthonormal modes of a positive definite
    // pair: 1 and lambda_q): the reduced matrices are positive definite when the points' block
    // less the modes' part of it is (its Schur complement), checked pivot by pivot.
    for (matrix, a) in [(Matrix::Mass, &mass), (Matrix::Stiffness, &stiffness)] {
        let s = DMatrix::from_fn(nb, nb, |i, j| {
            a[(i, j)] - (nb..a.ncols()).map(|q| a[(i, q)] * a[(j, q)] / a[(q, q)]).sum::<f64>()
        });
        if let Some(coordinate) = first_non_positive_pivot(&s) {
            return Err(ReductionError::ReducedNotPositive { matrix, coordinate });
        }
    }
    Ok(Reduced {
        mass,
        stiffness,
        boundary: boundary.to_vec(),
        interior_omegas: values[..kept].iter().map(|l| l.sqrt()).collect(),
        cutoff: values.get(kept).map_or(f64::INFINITY, |l| l.sqrt()),
        transform: t,
    })
}

/// The first row of a symmetric matrix at which `L D L^T` (no pivoting) has a pivot that is
/// negative or zero to 1e-12 of the row's diagonal entry: the matrix is not positive definite,
/// and the coordinates up to that row already are not.
pub fn first_non_positive_pivot(a: &DMatrix<f64>) -> Option<usize> {
    let n = a.nrows();
    let mut l = DMatrix::<f64>::zeros(n, n);
    let mut d = vec![0.0; n];
    for i in 0..n {
        for j in 0..i {
            let s: f64 = (0..j).map(|k| l[(i, k)] * l[(j, k)] * d[k]).sum();
            l[(i, j)] = (a[(i, j)] - s) / d[j];
        }
        let s: f64 = (0..i).map(|k| l[(i, k)] * l[(i, k)] * d[k]).sum();
        d[i] = a[(i, i)] - s;
        let positive = d[i].is_finite() && d[i] > 1e-12 * a[(i, i)].abs();
        if !positive {
            return Some(i);
        }
    }
    None
}

/// The compliance at the boundary for a unit force at boundary coordinate `force`, at one
/// frequency: the full model's (a sparse direct solve of `K - omega^2 M`, damped by its
/// lowest modes when [`Damped`] is given) and the reduced model's (dense), one value per
/// boundary coordinate, m/N.
#[derive(Debug, Clone, PartialEq)]
pub struct CompliancePair {
    /// rad/s.
    pub omega: f64,
    /// The full model's.
    pub full: Vec<Complex64>,
    /// The reduced model's.
    pub reduced: Vec<Complex64>,
}

/// The damping both models carry in a comparison: the reduced model its own damping matrix
/// (as the simulator does); the full model its lowest modes `Phi`, each with its damping ratio,
/// the rest of its response an exact sparse solve with those modes deflated:
/// `H f = Phi D(w) Phi^T f + (I - Phi Phi^T M) (K - w^2 M)^-1 (I - M Phi Phi^T) f`,
/// `D = diag(1 / (lambda_k - w^2 + 2 i zeta_k omega_k w))` (exact for a full model damped in
/// those modes only; its higher modes stay undamped). Deflated, a frequency a hair from a
/// resonance costs no digits: the solve's rounding along the nearly singular mode, amplified
/// by `1 / (lambda_k - w^2)`, is projected away instead of cancelled against the mode's term.
pub struct Damped<'a> {
    /// The full model's lowest modes (`M`-normalised).
    pub full_modes: &'a Eigen,
    /// Their damping ratios.
    pub zetas: &'a [f64],
    /// The reduced model's damping matrix (its coordinates).
    pub reduced: &'a DMatrix<f64>,
}

/// [`CompliancePair`]s over `omegas`, undamped or [`Damped`]; `None` at a frequency on a
/// natural frequency of either undamped model (a zero pivot).
pub fn compliance_pairs(
    m: &SymSparse,
    k: &SymSparse,
    r: &Reduced,
    force: usize,
    omegas: &[f64],
    damped: Option<&Damped>,
) -> Vec<Option<CompliancePair>> {
    let n = m.n();
    let pattern = Skyline::pattern(k, Some(m), rcm(k));
    let nb = r.boundary.len();
    let at_force = r.boundary[force];
    // The deflated load `(I - M Phi Phi^T) e_force` and `M Phi`, once.
    let deflation = damped.map(|d| {
        let phi = &d.full_modes.vectors;
        let mut m_phi = DMatrix::zeros(n, phi.ncols());
        let mut col = vec![0.0; n];
        for j in 0..phi.ncols() {
            m.mul(phi.column(j).as_slice(), &mut col);
            m_phi.column_mut(j).copy_from_slice(&col);
        }
        let mut load = vec![0.0; n];
        load[at_force] = 1.0;
        for j in 0..phi.ncols() {
            let c = phi[(at_force, j)];
            load.iter_mut().zip(m_phi.column(j).iter()).for_each(|(x, y)| *x -= c * y);
        }
        (m_phi, load)
    });
    // Frequencies in parallel, each its own factorisation (the order of the results is the
    // order of `omegas` whatever the threads).
    omegas
        .par_iter()
        .map_init(
            || pattern.clone(),
            |factor, &w| {
                factor.factor(k, Some((m, w * w))).ok()?;
                let mut x = match &deflation {
                    Some((_, load)) => load.clone(),
                    None => {
                        let mut e = vec![0.0; n];
                        e[at_force] = 1.0;
                        e
                    }
                };
                factor.solve(&mut x);
                let mut e = nalgebra::DVector::<Complex64>::zeros(r.stiffness.nrows());
                e[force] = Complex64::new(1.0, 0.0);
                let mut a = (&r.stiffness - &r.mass * (w * w)).map(|v| Complex64::new(v, 0.0));
                let mut full: Vec<Complex64> = Vec::with_capacity(nb);
                if let (Some(d), Some((m_phi, _))) = (damped, &deflation) {
                    let phi = &d.full_modes.vectors;
                    // The solve's components along the deflated modes (rounding only) removed,
                    // each mode's damped response added.
                    let along = m_phi.tr_mul(&DVector::from_column_slice(&x));
                    let modal: Vec<Complex64> = d
                        .full_modes
                        .values
                        .iter()
                        .zip(d.zetas)
                        .enumerate()
                        .map(|(j, (&lambda, &zeta))| {
                            Complex64::new(lambda - w * w, 2.0 * zeta * lambda.sqrt() * w).inv() * phi[(at_force, j)]
                        })
                        .collect();
                    for &b in &r.boundary {
                        let mut v = Complex64::new(x[b], 0.0);
                        for j in 0..phi.ncols() {
                            v += modal[j] * phi[(b, j)] - along[j] * phi[(b, j)];
                        }
                        full.push(v);
                    }
                    a += d.reduced.map(|c| Complex64::new(0.0, w * c));
                } else {
                    full.extend(r.boundary.iter().map(|&b| Complex64::new(x[b], 0.0)));
                }
                let y = a.lu().solve(&e)?;
                Some(CompliancePair { omega: w, full, reduced: (0..nb).map(|i| y[i]).collect() })
            },
        )
        .collect()
}

/// The largest difference of the reduced compliance from the full one over `pairs`, relative
/// to the full compliance's largest magnitude there, for each boundary coordinate (a relative
/// error at each frequency would be undefined at the full model's anti-resonances).
pub fn largest_difference(pairs: &[CompliancePair]) -> Vec<f64> {
    peaks(pairs)
        .iter()
        .enumerate()
        .map(|(i, &peak)| {
            let diff = pairs.iter().fold(0.0_f64, |a, p| a.max((p.reduced[i] - p.full[i]).norm()));
            if peak > 0.0 {
                diff / peak
            } else {
                diff
            }
        })
        .collect()
}

/// The full compliance's largest magnitude over `pairs`, for each boundary coordinate.
pub fn peaks(pairs: &[CompliancePair]) -> Vec<f64> {
    let nb = pairs.first().map_or(0, |p| p.full.len());
    (0..nb).map(|i| pairs.iter().fold(0.0_f64, |a, p| a.max(p.full[i].norm()))).collect()
}

#[cfg(test)]
mod tests;
