//! The impulse response against closed forms: the modal solution of the bare structure, the
//! log-decrement estimator, the energy balance, and a bed that never lifts off.

use crate::common::paper;
use nalgebra::{DMatrix, DVector};
use shotdamp::model::modal::symmetric_modes;
use shotdamp::model::Clearance;
use shotdamp::model::{Damper, GRAVITY};
use shotdamp::signal::log_decrements;
use shotdamp::sim::motion::impulse::{free_response, ImpulseOptions, Kick};
use shotdamp::sim::System;

fn opts(v0: f64, duration: f64) -> ImpulseOptions {
    ImpulseOptions { mass: 0, kick: Kick::Velocity(v0), duration, dt: 1e-4 }
}

#[test]
fn bare_free_decay_is_the_modal_solution_and_the_log_decrement_finds_zeta() {
    let s = paper();
    let sys = System::plastic(s.clone(), Vec::new(), 0, 0.0);
    let run = free_response(&sys, &opts(0.5, 1.0)).unwrap();
    let modes = symmetric_modes(&s.mass_matrix(), &s.stiffness);
    let m = s.mass_matrix();
    let v0 = DVector::from_vec(vec![0.5, 0.0, 0.0]);
    // x(t) = sum_i phi_i q_i(t), q_i = qdot_i(0) e^{-zeta w t} sin(w_d t) / w_d.
    let exact = |t: f64| -> DVector<f64> {
        let mut x = DVector::zeros(3);
        for i in 0..3 {
            let phi = modes.mass_normalised.column(i);
            let w = modes.omegas[i];
            let wd = w * (1.0 - 0.01f64 * 0.01).sqrt();
            let qd0 = (phi.transpose() * &m * &v0)[(0, 0)];
            x += phi * (qd0 * (-0.01 * w * t).exp() * (wd * t).sin() / wd);
        }
        x
    };
    let samples = &run.samples;
    let scale = samples.x.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
    for (i, t) in samples.times.iter().enumerate().step_by(97) {
        let e = exact(*t);
        for k in 0..3 {
            assert!(
                (samples.x[i][k] - e[k]).abs() < 1e-9 * scale,
                "t = {t}, m{}: {} vs {}",
                k + 1,
                samples.x[i][k],
                e[k]
            );
        }
    }
    // The estimator on each modal coordinate recovers the modal damping ratio.
    for i in 0..3 {
        let phi = modes.mass_normalised.column(i);
        let q: Vec<f64> = samples.x.iter().map(|x| (0..3).map(|r| phi[r] * m[(r, r)] * x[r]).sum()).collect();
        let dec = log_decrements(&samples.times, &q, 4);
        assert!(dec.len() > 10, "mode {}: {} decrements", i + 1, dec.len());
        let mean = dec.iter().map(|d| d.zeta).sum::<f64>() / dec.len() as f64;
        assert!((mean - 0.01).abs() < 0.01 * 0.01, "mode {}: zeta {mean}", i + 1);
        for d in &dec {
            assert!((d.zeta - 0.01).abs() < 0.01 * 0.01, "mode {}: zeta {} at t = {}", i + 1, d.zeta, d.t);
        }
    }
}

#[test]
fn energy_given_equals_remaining_plus_losses() {
    let masses = [0.74, 0.71, 0.64];
    for (hosts, clearance) in [(vec![0, 1, 2], f64::INFINITY), (vec![1], 0.3e-3), (vec![0], f64::INFINITY)] {
        let dampers = hosts.iter().map(|&h| Damper::new(h, 0.1 * masses[h], Clearance::from_m(clearance))).collect();
        let sys = System::plastic(paper(), dampers, 0, 0.0);
        let run = free_response(&sys, &opts(0.5, 1.0)).unwrap();
        assert!(run.impact_loss > 0.05 * run.initial_energy, "{hosts:?}: the beds must dissipate");
        assert!(run.energy_residual() < 1e-9, "{hosts:?}: residual {}", run.energy_residual());
        // The kinetic energy given: 1/2 (m1 + beds on m1) v0^2.
        let on_m1: f64 = hosts.iter().filter(|&&h| h == 0).map(|_| 0.074).sum();
        let given = 0.5 * (0.74 + on_m1) * 0.25;
        assert!((run.initial_energy - given).abs() < 1e-12 * given);
        // The same kick as an impulse shared by m1 and the beds resting on it.
        let kick = ImpulseOptions { kick: Kick::Impulse(0.5 * (0.74 + on_m1)), ..opts(0.5, 0.01) };
        let by_impulse = free_response(&sys, &kick).unwrap();
        assert!((by_impulse.initial_velocity - 0.5).abs() < 1e-15, "{}", by_impulse.initial_velocity);
    }
}

#[test]
fn a_bed_that_never_lifts_off_gives_the_stuck_structure() {
    // A small kick: m1's acceleration stays far above -g, so the bed on it rests throughout.
    let s = paper();
    let sys = System::plastic(s.clone(), vec![Damper::new(0, 0.074, Clearance::NO_TOP)], 0, 0.0);
    let v0 = 0.02;
    let run = free_response(&sys, &opts(v0, 0.5)).unwrap();
    assert!(run.samples.events.is_empty(), "{:?}", run.samples.events.first());
    let amax = run.samples.a.iter().map(|a| a[0]).fold(f64::INFINITY, f64::min);
    assert!(amax > -GRAVITY, "m1 reaches {amax} m/s^2");
    // The stuck structure about its own static equilibrium, by the matrix exponential.
    let mut m = s.mass_matrix();
    m[(0, 0)] += 0.074;
    let minv = m.clone().try_inverse().unwrap();
    let mut a = DMatrix::<f64>::zeros(6, 6);
    a.view_mut((0, 3), (3, 3)).copy_from(&DMatrix::identity(3, 3));
    a.view_mut((3, 0), (3, 3)).copy_from(&(-&minv * &s.stiffness));
    a.view_mut((3, 3), (3, 3)).copy_from(&(-&minv * &s.damping));
    let z0 = DVector::from_vec(vec![0.0, 0.0, 0.0, v0, 0.0, 0.0]);
    let scale = run
        .samples
        .x
        .iter()
        .flatten()
        .zip(&run.rest.repeat(run.samples.x.len()))
        .fold(0.0f64, |acc, (x, r)| acc.max((x - r).abs()));
    for (i, t) in run.samples.times.iter().enumerate().step_by(211) {
        let z = (&a * *t).exp() * &z0;
        for k in 0..3 {
            let ours = run.samples.x[i][k] - run.rest[k];
            assert!((ours - z[k]).abs() < 1e-8 * scale, "t = {t}, m{}: {ours} vs {}", k + 1, z[k]);
        }
    }
}
