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

fn sparse(a: &DMatrix<f64>) -> SymSparse {
    let n = a.nrows();
    let e = (0..n).flat_map(|i| (0..=i).map(move |j| (i, j))).filter(|&(i, j)| a[(i, j)] != 0.0);
    SymSparse::from_entries(n, e.map(|(i, j)| (i, j, a[(i, j)])).collect::<Vec<_>>(), true).unwrap()
}

#[test]
fn a_reduction_larger_than_allowed_is_counted_and_refused() {
    let (m, k) = chain(40);
    let b = [0, 37, 38, 39];
    let (ms, ks) = (sparse(&m), sparse(&k));
    // Every mode below the 11th: the inertia counts 10 of them, with the 4 points 14.
    let all = craig_bampton_sparse(&ms, &ks, &b, Keep::Count(36), None).unwrap();
    let w = 0.5 * (all.interior_omegas[9] + all.interior_omegas[10]);
    let refused = craig_bampton_sparse(&ms, &ks, &b, Keep::Below(w), Some(13)).unwrap_err();
    assert_eq!(refused, ReductionError::TooMany { boundary: 4, modes: 10, most: 13 });
    assert!(refused.to_string().contains("4 points and 10 fixed-interface modes make 14 coordinates"));
    let fits = craig_bampton_sparse(&ms, &ks, &b, Keep::Below(w), Some(14)).unwrap();
    assert_eq!(fits.mass.nrows(), 14);
    // A count beyond the interior is the interior's 36 modes.
    let over = craig_bampton_sparse(&ms, &ks, &b, Keep::Count(500), Some(39)).unwrap_err();
    assert_eq!(over, ReductionError::TooMany { boundary: 4, modes: 36, most: 39 });
}

#[test]
fn the_sparse_reduction_is_the_dense_one() {
    let (m, k) = chain(40);
    let b = [0, 37, 38, 39];
    let dense = craig_bampton(&m, &k, &b, 6).unwrap();
    let sp = craig_bampton_sparse(&sparse(&m), &sparse(&k), &b, Keep::Count(6), None).unwrap();
    // The modes' signs are conventions: align the sparse ones to the dense ones.
    let signs = DVector::from_fn(sp.mass.nrows(), |c, _| {
        let col = dense.transform.column(c);
        let i = col.iamax();
        (col[i] * sp.transform[(i, c)]).signum()
    });
    let d = DMatrix::from_diagonal(&signs);
    let (sm, sk) = (&d * &sp.mass * &d, &d * &sp.stiffness * &d);
    assert!((&dense.stiffness - &sk).amax() <= 1e-9 * dense.stiffness.amax());
    assert!((&dense.mass - &sm).amax() <= 1e-9 * dense.mass.amax());
    for (a, c) in dense.interior_omegas.iter().zip(&sp.interior_omegas) {
        assert!((a - c).abs() <= 1e-11 * a);
    }
    assert!((dense.cutoff - sp.cutoff).abs() <= 1e-11 * dense.cutoff);
    // By a cutoff: every mode below it, the next one above.
    let w = 0.5 * (sp.interior_omegas[3] + sp.interior_omegas[4]);
    let by = craig_bampton_sparse(&sparse(&m), &sparse(&k), &b, Keep::Below(w), None).unwrap();
    assert_eq!(by.interior_omegas.len(), 4);
    assert!(by.cutoff > w);
}

#[test]
fn with_every_interior_mode_kept_the_compliance_is_the_full_models() {
    let (m, k) = chain(14);
    let b = [0, 11, 12, 13];
    let r = craig_bampton_sparse(&sparse(&m), &sparse(&k), &b, Keep::Count(10), None).unwrap();
    let omegas: Vec<f64> = (1..60).map(|i| 7.3 * i as f64).collect();
    let pairs: Vec<CompliancePair> =
        compliance_pairs(&sparse(&m), &sparse(&k), &r, 0, &omegas, None).into_iter().flatten().collect();
    assert_eq!(pairs.len(), omegas.len());
    for e in largest_difference(&pairs) {
        assert!(e < 1e-10, "{e}");
    }
    // With two modes only the difference shows, and shrinks with more.
    let few = craig_bampton_sparse(&sparse(&m), &sparse(&k), &b, Keep::Count(2), None).unwrap();
    let more = craig_bampton_sparse(&sparse(&m), &sparse(&k), &b, Keep::Count(6), None).unwrap();
    let err = |r: &Reduced| {
        let p: Vec<CompliancePair> =
            compliance_pairs(&sparse(&m), &sparse(&k), r, 0, &omegas, None).into_iter().flatten().collect();
        largest_difference(&p).into_iter().fold(0.0, f64::max)
    };
    let (e2, e6) = (err(&few), err(&more));
    assert!(e2 > 1e-6 && e6 < e2, "{e2} {e6}");
}
/// Damped in every mode, a reduction that keeps every interior mode is the full model: the
/// full model's exact undamped response plus its modal corrections equals the reduced
/// model's direct complex solve with the damping matrix those modes give, at resonance
/// too; and a reduction that keeps fewer modes differs there by far less damped than
/// undamped.
#[test]
fn damped_in_every_mode_the_full_and_the_exact_reduction_agree() {
    let (m, k) = chain(14);
    let b = [0, 11, 12, 13];
    let (ms, ks) = (sparse(&m), sparse(&k));
    let mut factor = Skyline::pattern(&ks, Some(&ms), rcm(&ks));
    factor.factor(&ks, None).unwrap();
    let full_modes = lowest(&ks, &ms, &factor, Want::Count(14)).unwrap();
    let zetas: Vec<f64> = (0..14).map(|i| 0.01 + 0.002 * i as f64).collect();
    let damping_of = |r: &Reduced| {
        let modes = symmetric_modes(&r.mass, &r.stiffness);
        let phi = &modes.mass_normalised;
        let diag = DMatrix::from_diagonal(&DVector::from_fn(r.mass.nrows(), |i, _| 2.0 * zetas[i] * modes.omegas[i]));
        &r.mass * phi * diag * phi.transpose() * &r.mass
    };
    // Every frequency on a grid, and each natural frequency shifted by 1e-7 of itself.
    let mut omegas: Vec<f64> = (1..60).map(|i| 7.3 * i as f64).collect();
    omegas.extend(full_modes.values.iter().map(|l| l.sqrt() * (1.0 + 1e-4)));
    let exact = craig_bampton_sparse(&ms, &ks, &b, Keep::Count(10), None).unwrap();
    let c = damping_of(&exact);
    {
        let v = &full_modes.vectors;
        let g = v.transpose() * &m * v;
        eprintln!("MN diag {:?}", (0..4).map(|i| g[(i, i)]).collect::<Vec<_>>());
        let em = symmetric_modes(&exact.mass, &exact.stiffness);
        eprintln!("full w {:?}", full_modes.values.iter().map(|l| l.sqrt()).collect::<Vec<_>>());
        eprintln!("red  w {:?}", em.omegas);
    }
    let d = Damped { full_modes: &full_modes, zetas: &zetas, reduced: &c };
    let pairs: Vec<CompliancePair> =
        compliance_pairs(&ms, &ks, &exact, 0, &omegas, Some(&d)).into_iter().flatten().collect();
    assert_eq!(pairs.len(), omegas.len());
    for e in largest_difference(&pairs) {
        assert!(e < 1e-9, "{e}");
    }
    // Undamped, at a hair from each resonance, a truncated reduction reads as far off; damped
    // (its own lowest modes carrying the same ratios) it is close.
    let few = craig_bampton_sparse(&ms, &ks, &b, Keep::Count(6), None).unwrap();
    let c = damping_of(&few);
    let d = Damped { full_modes: &full_modes, zetas: &zetas, reduced: &c };
    let near: Vec<f64> = full_modes.values[..4].iter().map(|l| l.sqrt() * (1.0 + 1e-7)).collect();
    let worst = |d: Option<&Damped>| {
        let p: Vec<CompliancePair> = compliance_pairs(&ms, &ks, &few, 0, &near, d).into_iter().flatten().collect();
        largest_difference(&p).into_iter().fold(0.0, f64::max)
    };
    let (undamped, damped) = (worst(None), worst(Some(&d)));
    assert!(undamped > 0.5 && damped < 0.05 * undamped, "undamped {undamped}, damped {damped}");
}
