//! The lowest eigenpairs of a sparse `K phi = lambda M phi` (both symmetric, `K` and `M`
//! positive definite) by shift-invert Lanczos at zero: the Krylov space of `K^-1 M` in the
//! `M` inner product, fully reorthogonalised, its largest Ritz values `1 / lambda` first.
//! Certified by Sylvester's inertia: the number of negative pivots of `K - s M` is the number
//! of eigenvalues below `s`, so a run that found fewer than that below its top is continued
//! from a new start, orthogonal to what it found (a repeated eigenvalue shows itself only so).
//! Deterministic (a fixed start sequence). No I/O.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::sparse::{Singular, Skyline, SymSparse};

/// What to find.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Want {
    /// The lowest `n` eigenpairs (fewer if the problem has fewer).
    Count(usize),
    /// Every eigenvalue below this (`omega^2`, rad^2/s^2).
    Below(f64),
}

/// Eigenpairs, ascending.
#[derive(Debug, Clone)]
pub struct Eigen {
    /// `lambda = omega^2`.
    pub values: Vec<f64>,
    /// One column per value, `M`-normalised, its largest entry positive.
    pub vectors: DMatrix<f64>,
}

/// Why no eigenpairs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Failure {
    /// `K - s M` has a zero pivot at this row (a shift on an eigenvalue; `K` singular).
    Singular(Singular),
    /// Fewer eigenvalues were found than the inertia counts below the last one found.
    Missed {
        /// Found.
        found: usize,
        /// Counted.
        counted: usize,
    },
}

/// Relative residual a Ritz pair must reach: `|beta_j s_ji| <= TOL theta_i`.
const TOL: f64 = 1e-13;

/// A deterministic start vector (a fixed linear congruential sequence).
fn start(n: usize, seed: u64) -> Vec<f64> {
    let mut x = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (0..n)
        .map(|_| {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        })
        .collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `w -= (w . Mv) v` for each `(v, Mv)`.
fn orthogonalise(w: &mut [f64], basis: &[(Vec<f64>, Vec<f64>)]) {
    for (v, mv) in basis {
        let c = dot(w, mv);
        w.iter_mut().zip(v).for_each(|(x, y)| *x -= c * y);
    }
}

/// The lowest eigenpairs of `(k, m)`; `k_factor` is `k`'s factor (positive definite).
pub fn lowest(k: &SymSparse, m: &SymSparse, k_factor: &Skyline, want: Want) -> Result<Eigen, Failure> {
    let n = k.n();
    let mut shifted = Skyline::pattern(k, Some(m), k_factor.order().to_vec());
    let mut count_below = |s: f64| shifted.factor(k, Some((m, s))).map_err(Failure::Singular);
    let target = match want {
        Want::Count(c) => c.min(n),
        Want::Below(s) => count_below(s)?,
    };
    let mut found: Vec<(f64, Vec<f64>, Vec<f64>)> = Vec::new();
    let mut needed = target;
    for round in 0..6u64 {
        if needed == 0 {
            break;
        }
        let locked: Vec<(Vec<f64>, Vec<f64>)> = found.iter().map(|(_, v, mv)| (v.clone(), mv.clone())).collect();
        // Each value the Rayleigh quotient `v^T K v` of its vector (M-normalised): its error is
        // the square of the vector's, where `1 / theta` carries the basis' rounding (2.5e-8
        // relative on the shipped plate's first mode, the quotient within 1e-15).
        found.extend(run(k_factor, m, &locked, needed, round).into_iter().map(|(theta, v, mv)| {
            let mut kv = vec![0.0; n];
            k.mul(&v, &mut kv);
            let rayleigh = dot(&v, &kv);
            (if rayleigh.is_finite() && rayleigh > 0.0 { rayleigh } else { theta }, v, mv)
        }));
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Certificate: as many eigenvalues below a point just above the last one wanted as
        // were found there; every pair found is genuine, the missing ones are looked for from
        // a new start orthogonal to them.
        let Some(top) = found.get(target.min(found.len()).saturating_sub(1)).map(|f| f.0 * (1.0 + 1e-9)) else {
            break;
        };
        let counted = count_below(top)?;
        let have = found.iter().filter(|f| f.0 < top).count();
        needed = if counted > have { counted - have } else { target.saturating_sub(found.len()) };
        if needed > 0 && round == 5 {
            return Err(Failure::Missed { found: have, counted });
        }
    }
    found.truncate(target);
    let mut vectors = DMatrix::zeros(n, found.len());
    for (c, (_, v, _)) in found.iter().enumerate() {
        let big = v.iter().fold(0.0_f64, |a, &x| if x.abs() > a.abs() { x } else { a });
        let sign = if big < 0.0 { -1.0 } else { 1.0 };
        for (r, x) in v.iter().enumerate() {
            vectors[(r, c)] = sign * x;
        }
    }
    Ok(Eigen { values: found.iter().map(|f| f.0).collect(), vectors })
}

/// One Lanczos run from start `seed`, orthogonal to `locked`, until its `needed` largest Ritz
/// values have converged (or the space is exhausted): `(lambda, phi, M phi)` of those.
fn run(
    k_factor: &Skyline,
    m: &SymSparse,
    locked: &[(Vec<f64>, Vec<f64>)],
    needed: usize,
    seed: u64,
) -> Vec<(f64, Vec<f64>, Vec<f64>)> {
    let n = m.n();
    let free = n - locked.len();
    let mut basis: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    let (mut alpha, mut beta) = (Vec::new(), Vec::new());
    let mut q = start(n, seed);
    let mut mq = vec![0.0; n];
    for _ in 0..2 {
        m.mul(&q, &mut mq);
        orthogonalise(&mut q, locked);
    }
    m.mul(&q, &mut mq);
    let norm = dot(&q, &mq).sqrt();
    q.iter_mut().for_each(|x| *x /= norm);
    mq.iter_mut().for_each(|x| *x /= norm);
    let mut ritz: Option<(Vec<f64>, DMatrix<f64>)> = None;
    loop {
        let j = basis.len();
        let mut w = mq.clone();
        k_factor.solve(&mut w);
        let a = dot(&w, &mq);
        basis.push((q, mq));
        alpha.push(a);
        // Full reorthogonalisation, twice (against the run's basis and the locked vectors).
        for _ in 0..2 {
            orthogonalise(&mut w, &basis);
            orthogonalise(&mut w, locked);
        }
        let mut mw = vec![0.0; n];
        m.mul(&w, &mut mw);
        let b = dot(&w, &mw).max(0.0).sqrt();
        let steps = j + 1;
        let exhausted = steps >= free || b <= 1e-14 * a.abs();
        // The space exhausted before `needed` steps holds fewer pairs: all of them.
        if exhausted || (steps >= needed && steps % 4 == 0) {
            let needed = needed.min(steps);
            let t = DMatrix::from_fn(steps, steps, |r, c| match r.abs_diff(c) {
                0 => alpha[r],
                1 => beta[r.min(c)],
                _ => 0.0,
            });
            let e = SymmetricEigen::new(t);
            let mut idx: Vec<usize> = (0..steps).collect();
            idx.sort_by(|&x, &y| e.eigenvalues[y].total_cmp(&e.eigenvalues[x]));
            let top = e.eigenvalues[idx[0]].abs();
            let done = idx.iter().take(needed).all(|&i| (b * e.eigenvectors[(steps - 1, i)]).abs() <= TOL * top);
            if done || exhausted {
                let keep: Vec<usize> = idx.into_iter().take(needed).collect();
                let thetas = keep.iter().map(|&i| e.eigenvalues[i]).collect();
                let s = DMatrix::from_fn(steps, keep.len(), |r, c| e.eigenvectors[(r, keep[c])]);
                ritz = Some((thetas, s));
            }
        }
        if let Some((thetas, s)) = ritz {
            return thetas
                .iter()
                .enumerate()
                .map(|(c, &theta)| {
                    let mut v = vec![0.0; n];
                    let mut mv = vec![0.0; n];
                    for (r, (qr, mqr)) in basis.iter().enumerate() {
                        let sr = s[(r, c)];
                        v.iter_mut().zip(qr).for_each(|(x, y)| *x += sr * y);
                        mv.iter_mut().zip(mqr).for_each(|(x, y)| *x += sr * y);
                    }
                    let norm = dot(&v, &mv).sqrt();
                    v.iter_mut().for_each(|x| *x /= norm);
                    mv.iter_mut().for_each(|x| *x /= norm);
                    (1.0 / theta, v, mv)
                })
                .collect();
        }
        beta.push(b);
        q = w.into_iter().map(|x| x / b).collect();
        mq = mw.into_iter().map(|x| x / b).collect();
    }
}

/// `K phi - lambda M phi` relative to `K phi`: each pair's residual.
pub fn residuals(k: &SymSparse, m: &SymSparse, e: &Eigen) -> Vec<f64> {
    let n = k.n();
    (0..e.values.len())
        .map(|c| {
            let v: Vec<f64> = e.vectors.column(c).iter().copied().collect();
            let (mut kv, mut mv) = (vec![0.0; n], vec![0.0; n]);
            k.mul(&v, &mut kv);
            m.mul(&v, &mut mv);
            let r = DVector::from_iterator(n, kv.iter().zip(&mv).map(|(a, b)| a - e.values[c] * b));
            r.norm() / DVector::from_vec(kv).norm()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::modes::symmetric_modes;
    use crate::model::sparse::rcm;

    /// A plate-like grid: a 2-D Laplacian stiffness with a consistent-looking mass.
    fn grid(w: usize, h: usize) -> (SymSparse, SymSparse) {
        let id = |x: usize, y: usize| x * h + y;
        let (mut k, mut m) = (Vec::new(), Vec::new());
        for x in 0..w {
            for y in 0..h {
                k.push((id(x, y), id(x, y), 4.0e4 * (1.0 + 0.05 * ((x + 2 * y) % 3) as f64)));
                m.push((id(x, y), id(x, y), 1.0 + 0.1 * ((x * y) % 4) as f64));
                if x + 1 < w {
                    k.push((id(x + 1, y), id(x, y), -1.0e4));
                    m.push((id(x + 1, y), id(x, y), 0.05));
                }
                if y + 1 < h {
                    k.push((id(x, y + 1), id(x, y), -1.0e4));
                }
            }
        }
        let n = w * h;
        (SymSparse::from_entries(n, k, true).unwrap(), SymSparse::from_entries(n, m, true).unwrap())
    }

    fn factor(k: &SymSparse) -> Skyline {
        let mut f = Skyline::pattern(k, None, rcm(k));
        f.factor(k, None).unwrap();
        f
    }

    #[test]
    fn the_lowest_pairs_agree_with_dense_eigen() {
        let (k, m) = grid(9, 7);
        let dense = symmetric_modes(&m.to_dense(), &k.to_dense());
        let e = lowest(&k, &m, &factor(&k), Want::Count(10)).unwrap();
        assert_eq!(e.values.len(), 10);
        for (i, l) in e.values.iter().enumerate() {
            let w2 = dense.omegas[i] * dense.omegas[i];
            assert!((l - w2).abs() <= 1e-11 * w2, "mode {i}: {l} vs {w2}");
        }
        for r in residuals(&k, &m, &e) {
            assert!(r < 1e-10, "residual {r}");
        }
        // M-orthonormal.
        let g = e.vectors.transpose() * m.to_dense() * &e.vectors;
        assert!((g - DMatrix::identity(10, 10)).amax() < 1e-11);
    }

    #[test]
    fn asking_for_more_pairs_than_the_problem_has_gives_all_of_them() {
        let (k, m) = grid(5, 4);
        let dense = symmetric_modes(&m.to_dense(), &k.to_dense());
        let e = lowest(&k, &m, &factor(&k), Want::Count(100)).unwrap();
        assert_eq!(e.values.len(), 20);
        for (l, w) in e.values.iter().zip(&dense.omegas) {
            assert!((l - w * w).abs() <= 1e-10 * w * w, "{l} vs {}", w * w);
        }
    }

    #[test]
    fn below_a_cutoff_finds_every_eigenvalue_there_repeated_ones_too() {
        // A square grid of uniform springs and masses: eigenvalues come in equal pairs.
        let n = 8;
        let id = |x: usize, y: usize| x * n + y;
        let (mut ke, mut me) = (Vec::new(), Vec::new());
        for x in 0..n {
            for y in 0..n {
                ke.push((id(x, y), id(x, y), 4.0));
                me.push((id(x, y), id(x, y), 1.0));
                if x + 1 < n {
                    ke.push((id(x + 1, y), id(x, y), -1.0));
                }
                if y + 1 < n {
                    ke.push((id(x, y + 1), id(x, y), -1.0));
                }
            }
        }
        let k = SymSparse::from_entries(n * n, ke, true).unwrap();
        let m = SymSparse::from_entries(n * n, me, true).unwrap();
        let all = k.to_dense().symmetric_eigenvalues();
        let cut = 1.2;
        let expected = all.iter().filter(|&&l| l < cut).count();
        let e = lowest(&k, &m, &factor(&k), Want::Below(cut)).unwrap();
        assert_eq!(e.values.len(), expected);
        let mut sorted: Vec<f64> = all.iter().copied().filter(|&l| l < cut).collect();
        sorted.sort_by(f64::total_cmp);
        for (a, b) in e.values.iter().zip(&sorted) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
        // There are repeated values among them.
        assert!(sorted.windows(2).any(|w| (w[1] - w[0]).abs() < 1e-12));
    }
}
