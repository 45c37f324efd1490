//! Repeated natural frequencies: the paper's chain beside identical oscillators joined to
//! nothing (a block-diagonal structure whose oscillators share one frequency, as the
//! symmetric structures engineers bring do) is simulated, and its chain moves exactly as the
//! paper's chain alone: the Fig. 5 sweeps of the third mode with three beds reproduced to
//! 1e-10. Before, every point was NaN with "numerically singular (eigenvector condition
//! 3.3e17 ...)".

use nalgebra::DMatrix;
use shotdamp::model::structure::chain_stiffness;
use shotdamp::model::{Clearance, Damper, Damping, Structure};
use shotdamp::sim::settle::sweep;
use shotdamp::sim::{SteadyOptions, System};

/// The paper's chain (modal damping 0.01) beside `k` identical oscillators of 1 kg on 10 kN/m
/// (15.9 Hz, between the chain's first and second modes), the force on m1, a bed of 10 % of
/// each chain mass at 0.2 mm on each chain mass.
fn beside(k: usize) -> System {
    let n = 3 + k;
    let mut stiffness = DMatrix::<f64>::identity(n, n) * 1e4;
    stiffness.view_mut((0, 0), (3, 3)).copy_from(&chain_stiffness(&[24.3e3, 21.8e3, 19.8e3]));
    let masses: Vec<f64> = [0.74, 0.71, 0.64].into_iter().chain(std::iter::repeat_n(1.0, k)).collect();
    let structure = Structure::from_matrices(&masses, stiffness, Damping::ModalRatios(vec![0.01; n]));
    let dampers = (0..3).map(|h| Damper::new(h, 0.1 * masses[h], Clearance::from_m(0.2e-3))).collect();
    System::plastic(structure, dampers, 0, 2.6)
}

fn amplitudes(sys: &System) -> Vec<(f64, Vec<f64>, usize)> {
    let freqs: Vec<f64> = (0..25).map(|i| 44.0 + 0.5 * i as f64).collect();
    sweep::from_rest(sys, &freqs, &SteadyOptions::default(), &|| {})
        .into_iter()
        .map(|p| {
            let s = p.result.unwrap_or_else(|e| panic!("{} Hz: {e}", p.freq_hz));
            (p.freq_hz, s.amplitude, s.period)
        })
        .collect()
}

#[test]
fn the_chain_beside_identical_oscillators_moves_as_the_chain_alone() {
    let alone = amplitudes(&beside(0));
    for k in [2usize, 8, 29] {
        let with = amplitudes(&beside(k));
        let mut worst: f64 = 0.0;
        for ((f, a, pa), (_, b, pb)) in alone.iter().zip(&with) {
            assert_eq!(pa, pb, "{k} oscillators, {f} Hz: period");
            for m in 0..3 {
                let rel = (a[m] - b[m]).abs() / a[m].abs();
                worst = worst.max(rel);
                assert!(rel <= 1e-10, "{k} oscillators, {f} Hz, m{}: {} vs {} ({rel:e})", m + 1, a[m], b[m]);
            }
            // The oscillators are not driven and joined to nothing: they stay at rest.
            for (o, x) in b.iter().enumerate().skip(3) {
                assert!(x.abs() <= 1e-12 * a[0], "{k} oscillators, {f} Hz, oscillator {o}: {x}");
            }
        }
        println!("{k} identical oscillators beside the chain: largest relative difference {worst:e} over 25 points");
    }
}

/// Every configuration of the chain beside two identical oscillators (a repeated pair of
/// eigenvalues of the state matrix, twice: the pair's two conjugates) is decomposed with a
/// well-conditioned basis.
#[test]
fn a_symmetric_structure_with_a_repeated_pair_decomposes_well() {
    let sys = beside(2);
    let d = shotdamp::sim::Dynamics::new(&sys, 2.0 * std::f64::consts::PI * 48.0).expect("decomposes");
    for mask in 0..8 {
        let c = d.config(mask).modes.condition;
        assert!(c < 1e4, "configuration {mask:#b}: eigenvector condition {c:e}");
    }
}
