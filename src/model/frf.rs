//! Exact linear frequency response (docs/model.md section 3, "Linear references").

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::structure::Structure;

/// Relative size of the smallest eigenvalue of an undamped dynamic stiffness below which the
/// response counts as unbounded (a few hundred roundings of its largest).
pub const UNBOUNDED: f64 = 1e-13;

/// Complex receptance `(K - omega^2 M + i omega C)^-1 e_k` of all masses, m/N.
///
/// `mass` is the mass matrix to use: `M0` for the bare structure, `M_all` for the
/// "stuck" structure with damper masses rigidly added. Returns `None` when the response is
/// unbounded: an undamped structure at a natural frequency, where the dynamic stiffness is
/// singular to within rounding (its smallest eigenvalue below `UNBOUNDED` times its largest);
/// a solve there would return a number set by rounding alone.
pub fn receptance(structure: &Structure, mass: &DMatrix<f64>, driven: usize, omega: f64) -> Option<DVector<Complex64>> {
    let mut load = DVector::zeros(structure.dof());
    load[driven] = 1.0;
    response(structure, mass, &load, omega)
}

/// The complex response `(K - omega^2 M + i omega C)^-1 l` to a real load vector `l`;
/// `None` where it is unbounded (as [`receptance`]).
pub fn response(
    structure: &Structure,
    mass: &DMatrix<f64>,
    load: &DVector<f64>,
    omega: f64,
) -> Option<DVector<Complex64>> {
    let n = structure.dof();
    if structure.damping.iter().all(|c| *c == 0.0) {
        let d = &structure.stiffness - mass * (omega * omega);
        let eig = d.clone().symmetric_eigen().eigenvalues;
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), e| (lo.min(e.abs()), hi.max(e.abs())));
        if lo <= UNBOUNDED * hi {
            return None;
        }
    }
    let z = DMatrix::<Complex64>::from_fn(n, n, |i, j| {
        Complex64::new(structure.stiffness[(i, j)] - omega * omega * mass[(i, j)], omega * structure.damping[(i, j)])
    });
    let rhs = DVector::<Complex64>::from_fn(n, |i, _| Complex64::new(load[i], 0.0));
    z.lu().solve(&rhs)
}

/// The load vector of supports that accelerate with unit amplitude: `M r` when every
/// coordinate translates with them, else the structure's own `L` plus the stuck masses'
/// `(M - M_0) r`; and `r`.
fn support_load(structure: &Structure, mass: &DMatrix<f64>) -> (DVector<f64>, DVector<f64>) {
    match &structure.supports {
        None => {
            let r = DVector::from_element(structure.dof(), 1.0);
            (mass * &r, r)
        }
        Some(s) => {
            let r = DVector::from_column_slice(&s.follow);
            (DVector::from_column_slice(&s.load) + (mass - structure.mass_matrix()) * &r, r)
        }
    }
}

/// Per frequency (rad/s), on supports that accelerate as `A sin(omega t)`: each storey's
/// drift amplitude `|u_i - u_(i-1)| / A` (s^2; the first storey's `|u_1| / A`; empty when the
/// structure is not a chain, [`Structure::is_chain`]) and each physical coordinate's absolute
/// acceleration amplitude `|uddot_i + r_i a_g| / A` (dimensionless). With `u = -h A`, `h` the
/// response to the load ([`support_compliance_curve`]), the absolute acceleration is
/// `A |omega^2 h_i + r_i|`. Infinities where unbounded.
pub fn support_peaks_curve(structure: &Structure, mass: &DMatrix<f64>, omegas: &[f64]) -> Vec<(Vec<f64>, Vec<f64>)> {
    let (load, r) = support_load(structure, mass);
    let physical = structure.physical();
    let storeys = if structure.is_chain() { physical } else { 0 };
    omegas
        .iter()
        .map(|&w| match response(structure, mass, &load, w) {
            Some(h) => (
                (0..storeys).map(|i| if i == 0 { h[0].norm() } else { (h[i] - h[i - 1]).norm() }).collect(),
                (0..physical).map(|i| (h[i] * (w * w) + r[i]).norm()).collect(),
            ),
            None => (vec![f64::INFINITY; storeys], vec![f64::INFINITY; physical]),
        })
        .collect()
}

/// Magnitudes `|u_r / A|` (m/(m/s^2)) of the displacements relative to supports that
/// accelerate as `A sin(omega t)`, `M` the mass matrix to use (bare, or with masses stuck),
/// at each frequency (rad/s); infinities where unbounded. The load is `M r` when every
/// coordinate translates with the supports (`r = 1`), else the structure's own `L` plus the
/// stuck masses' `(M - M_0) r` ([`crate::model::base::Supports`]).
pub fn support_compliance_curve(structure: &Structure, mass: &DMatrix<f64>, omegas: &[f64]) -> Vec<Vec<f64>> {
    let (load, _) = support_load(structure, mass);
    omegas
        .iter()
        .map(|&w| match response(structure, mass, &load, w) {
            Some(h) => h.iter().map(|c| c.norm()).collect(),
            None => vec![f64::INFINITY; structure.dof()],
        })
        .collect()
}

/// Compliance magnitudes `|x_r / F|` (m/N) of every mass at each frequency (rad/s).
/// Rows follow `omegas`; an unbounded point ([`receptance`]) gives infinities.
pub fn compliance_curve(structure: &Structure, mass: &DMatrix<f64>, driven: usize, omegas: &[f64]) -> Vec<Vec<f64>> {
    omegas
        .iter()
        .map(|&w| match receptance(structure, mass, driven, w) {
            Some(h) => h.iter().map(|c| c.norm()).collect(),
            None => vec![f64::INFINITY; structure.dof()],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::modal::symmetric_modes;
    use crate::model::structure::{Damping, Structure};

    fn paper() -> Structure {
        Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]))
    }

    #[test]
    fn an_undamped_structure_at_a_natural_frequency_is_unbounded() {
        let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.0; 3]));
        let m = s.mass_matrix();
        let modes = symmetric_modes(&m, &s.stiffness);
        for &wn in &modes.omegas {
            assert!(receptance(&s, &m, 0, wn).is_none(), "unbounded at {wn}");
            assert!(compliance_curve(&s, &m, 0, &[wn])[0].iter().all(|c| c.is_infinite()));
            // 1e-6 off resonance the response is finite and large.
            let h = receptance(&s, &m, 0, wn * (1.0 + 1e-6)).unwrap();
            assert!(h.iter().any(|c| c.norm() > 1.0), "{h}");
        }
    }

    #[test]
    fn zero_frequency_gives_static_compliance() {
        let s = paper();
        let k_inv = s.stiffness.clone().try_inverse().unwrap();
        for driven in 0..3 {
            let h = receptance(&s, &s.mass_matrix(), driven, 1e-9).unwrap();
            for r in 0..3 {
                let st = k_inv[(r, driven)];
                assert!((h[r].re - st).abs() < 1e-12 * st.abs(), "{} vs {st}", h[r].re);
                assert!(h[r].im.abs() < 1e-9 * st.abs());
            }
        }
    }

    #[test]
    fn peaks_sit_at_natural_frequencies() {
        let s = paper();
        let m = s.mass_matrix();
        let modes = symmetric_modes(&m, &s.stiffness);
        for (i, &wn) in modes.omegas.iter().enumerate() {
            let phi = modes.mass_normalised.column(i);
            // Modal damping decouples the modes: the modal coordinate at omega_n is exactly
            // phi_k / (2 i zeta omega_n^2), a quarter period behind the force.
            let h = receptance(&s, &m, 0, wn).unwrap();
            let q: Complex64 = (0..3).map(|r| h[r] * phi[r] * m[(r, r)]).sum();
            let expected = phi[0] / (2.0 * 0.01 * wn * wn);
            assert!(q.re.abs() < 1e-9 * expected.abs(), "mode {i}: {q}");
            assert!((q.im + expected).abs() < 1e-9 * expected.abs(), "mode {i}: {q} vs {expected}");
            // The physical peak of the mass that moves most lies within 0.1 % of omega_n
            // (neighbouring modes shift it slightly).
            let grid: Vec<f64> = (0..=4000).map(|j| wn * (0.98 + 0.04 * j as f64 / 4000.0)).collect();
            let curve = compliance_curve(&s, &m, 0, &grid);
            let col = (0..3).max_by(|&a, &b| phi[a].abs().total_cmp(&phi[b].abs())).unwrap();
            let (ipk, _) = curve.iter().enumerate().max_by(|a, b| a.1[col].total_cmp(&b.1[col])).unwrap();
            assert!((grid[ipk] - wn).abs() / wn < 1e-3, "peak {} vs omega_n {wn}", grid[ipk]);
        }
    }

    #[test]
    fn stuck_with_zero_damper_mass_equals_bare() {
        let s = paper();
        let stuck = s.mass_matrix_with(&[(0, 0.0), (1, 0.0), (2, 0.0)]);
        for w in [10.0, 81.9, 200.0, 312.0, 400.0] {
            let a = receptance(&s, &s.mass_matrix(), 0, w).unwrap();
            let b = receptance(&s, &stuck, 0, w).unwrap();
            assert_eq!(a, b);
        }
    }
}
