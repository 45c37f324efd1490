// The family of chains that measures the cost per degree of freedom (docs/simulator.md, "Cost
// per degree of freedom") and its band, one definition for benches/size.rs, tests/size.rs,
// examples/followed_cost.rs and examples/scaling.rs, each of which `include!`s this file.

/// A chain of `n` equal masses refining the paper's structure (2.09 kg in all, series stiffness
/// 7.27 kN/m), Rayleigh damping of 1 % at 14.6 and 73 Hz (its first and third modes as it is
/// refined; growing with frequency above, so that the stiff modes of a fine chain ring down
/// within a few of their periods, as a structure's do), three beds of 10 % of their host's
/// mass with 0.5 mm of clearance on the last three masses, driven at the first by the force
/// that gives the lowest mode the paper's modal force.
fn refined(n: usize) -> shotdamp::sim::System {
    use shotdamp::model::{Clearance, Damper, Damping, Structure};
    use std::f64::consts::PI;
    let m = 2.09 / n as f64;
    let k = 7.27e3 * n as f64;
    let (w1, w3) = (2.0 * PI * 14.6, 2.0 * PI * 73.0);
    let damping = Damping::Rayleigh { alpha: 0.02 * w1 * w3 / (w1 + w3), beta: 0.02 / (w1 + w3) };
    let s = Structure::chain(&vec![m; n], &vec![k; n], damping);
    let dampers = (n - 3..n).map(|h| Damper::new(h, 0.1 * m, Clearance::from_m(0.5e-3))).collect();
    let force = 2.6 * (PI / 6.0).sin() / (PI / (2.0 * n as f64)).sin();
    shotdamp::sim::System::plastic(s, dampers, 0, force)
}

/// 12 frequencies from 0.9 times the lowest to 1.1 times the highest (at most 60 Hz) of the
/// top three modes below 60 Hz of a chain of the family.
#[allow(dead_code)] // not every includer sweeps the band
fn band(sys: &shotdamp::sim::System) -> Vec<f64> {
    use std::f64::consts::PI;
    let modes = shotdamp::model::modes::symmetric_modes(&sys.structure.mass_matrix(), &sys.structure.stiffness);
    let below: Vec<f64> = modes.omegas.iter().map(|w| w / (2.0 * PI)).filter(|&f| f < 60.0).collect();
    let top = &below[below.len().saturating_sub(3)..];
    let (lo, hi) = (0.9 * top[0], (1.1 * top[top.len() - 1]).min(60.0));
    (0..12).map(|i| lo + (hi - lo) * i as f64 / 11.0).collect()
}
