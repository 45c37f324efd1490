//! Is the response near the optimal clearance less sensitive to the restitution than away
//! from it (as granular-damper studies report)? Fig. 5's setting on the stated chain (modal
//! damping 0.01, F = 2.6 N on m1): the peak compliance of m2 over 44-56 Hz (0.25 Hz steps)
//! with one container on m2 (mu = 0.1) and with three (m1, m2, m3), against the clearance,
//! for one mass that bounces with restitution e and for a column of 10 grains.
//!
//! `cargo run --release --example bed_sensitivity`

use shotdamp::model::Clearance;
use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::motion::bed::ImpactLaw;
use shotdamp::sim::{settle::sweep, SteadyOptions, System};

fn main() {
    let m = [0.74, 0.71, 0.64];
    let structure = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let freqs: Vec<f64> = (0..=48).map(|i| 44.0 + 0.25 * i as f64).collect();
    let clearances = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8];
    let restitutions = [0.0, 0.1, 0.3, 0.5];
    for (case, hosts) in [("one container on m2", vec![1]), ("three containers", vec![0, 1, 2])] {
        for grains in [1, 10] {
            println!(
                "{case}, {grains} grain(s): peak compliance of m2 (m/N); change against e = 0 in %; * unsettled peak"
            );
            println!("  d (mm)   e = 0       e = 0.1   e = 0.3   e = 0.5");
            for d in clearances {
                let dampers: Vec<Damper> =
                    hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_m(d * 1e-3))).collect();
                let peaks: Vec<(f64, bool)> = restitutions
                    .iter()
                    .map(|&e| {
                        let law = ImpactLaw::with_restitution(e, 1e-3);
                        let sys = System::plastic(structure.clone(), dampers.clone(), 0, 2.6)
                            .with_law(law)
                            .with_grains(&vec![grains; hosts.len()]);
                        sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {})
                            .iter()
                            .filter_map(|p| p.result.as_ref().ok().map(|s| (s.amplitude[1] / 2.6, s.converged)))
                            .fold((0.0, true), |acc, (a, c)| if a > acc.0 { (a, c) } else { acc })
                    })
                    .collect();
                let base = peaks[0].0;
                let rest: Vec<String> = peaks[1..]
                    .iter()
                    .map(|(p, c)| format!("{:+7.1}{}", 100.0 * (p / base - 1.0), if *c { " " } else { "*" }))
                    .collect();
                println!("  {d:5.2}   {base:.3e}  {}", rest.join("  "));
            }
        }
    }
}
