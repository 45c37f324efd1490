//! A second method for the column of grains (docs/model.md section 2.1): every contact a
//! linear spring-dashpot with the same restitution, small explicit steps, no collision rule.
//! On Fig. 5's structure with one container on m3 (mu = 0.1, d = 0.35 mm), where the grains
//! lift off every period, the soft column approaches the event-driven column as the contact
//! stiffness grows; how close it gets is the size of what the event-driven collision rule
//! decides (measured numbers in docs/model.md).

use shotdamp::model::Clearance;
use std::f64::consts::PI;

use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::motion::bed::ImpactLaw;
use shotdamp::sim::motion::soft::{amplitude, damping_ratio, SoftOptions};
use shotdamp::sim::{steady_state, Dynamics, State, SteadyOptions, System};

fn column(grains: usize, e: f64) -> System {
    let m = [0.74, 0.71, 0.64];
    let structure = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let single = System::plastic(structure, vec![Damper::new(2, 0.064, Clearance::from_m(0.35e-3))], 0, 2.6);
    single.with_law(ImpactLaw::with_restitution(e, 1e-3)).with_grains(&[grains])
}

/// Largest relative difference of the soft column's amplitudes from the event-driven ones at
/// each stiffness.
fn differences(sys: &System, f: f64, stiffness: &[f64]) -> Vec<f64> {
    let w = 2.0 * PI * f;
    let d = Dynamics::new(sys, w).unwrap();
    let ed = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    assert!(ed.converged && ed.liftoffs.iter().all(|&l| l > 0.0), "{f} Hz: the grains must fly");
    stiffness
        .iter()
        .map(|&k| {
            let (soft, _) = amplitude(sys, w, &SoftOptions { stiffness: k, steps_per_contact: 40 }, 600, 100).unwrap();
            soft.iter().zip(&ed.amplitude).map(|(a, b)| ((a - b) / b).abs()).fold(0.0, f64::max)
        })
        .collect()
}

#[test]
fn the_contact_damping_gives_the_restitution() {
    // A grain dropped on a fixed floor of soft contact rebounds with e.
    for e in [0.14, 0.3, 0.6, 0.9] {
        let (m, k, v0): (f64, f64, f64) = (0.01, 1e6, 0.05);
        let c = 2.0 * damping_ratio(e).unwrap() * (k * m).sqrt();
        let (mut y, mut u, dt) = (0.0, -v0, 1e-8);
        while y <= 0.0 || u < 0.0 {
            let f = (-k * y - c * u).max(0.0);
            u += dt * f / m;
            y += dt * u;
            if y > 0.0 && u > 0.0 {
                break;
            }
        }
        assert!((u / v0 - e).abs() < 1e-3, "e = {e}: rebound {}", u / v0);
    }
    assert!(
        damping_ratio(0.1).is_none()
            && (shotdamp::sim::motion::soft::restitution_of(1.0 - 1e-9) - (-2.0f64).exp()).abs() < 1e-4
    );
    // A container whose bed is too inelastic for a contact that never pulls: no soft model,
    // whichever container it is.
    let mut mixed = column(3, 0.3);
    mixed.dampers.push(Damper::new(0, 0.074, Clearance::from_m(0.35e-3)));
    mixed.laws.push(ImpactLaw::with_restitution(0.05, 1e-3));
    let opts = SoftOptions { stiffness: 1e6, steps_per_contact: 40 };
    assert!(amplitude(&mixed, 2.0 * PI * 48.0, &opts, 1, 1).is_none());
}

#[test]
fn the_soft_column_approaches_the_event_driven_column_as_contacts_stiffen() {
    let stiffness = [1e6, 1e7, 1e8];
    for (grains, e, f, last) in [(5, 0.3, 48.0, 0.01), (5, 0.3, 48.5, 0.01), (10, 0.6, 48.5, 0.08)] {
        let diff = differences(&column(grains, e), f, &stiffness);
        println!("{grains} grains, e = {e}, {f} Hz: relative differences {diff:.4?} at k = 1e6, 1e7, 1e8 N/m");
        assert!(diff[2] < last, "{grains} grains, e = {e}, {f} Hz: {diff:?}");
        assert!(diff[2] <= diff[0], "{grains} grains, e = {e}, {f} Hz: no approach {diff:?}");
    }
}
