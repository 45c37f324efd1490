use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::{sweep, SteadyOptions, System};
fn main() {
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let m = [0.74, 0.71, 0.64];
    let dampers: Vec<Damper> = (0..3).map(|j| Damper { host: j, mass: 0.1 * m[j], clearance: f64::INFINITY }).collect();
    let sys = System::plastic(s, dampers, 0, 2.6);
    let freqs: Vec<f64> = (0..=520).map(|i| ((80.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let t = std::time::Instant::now();
    let r = sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {});
    println!("{:?} {}", t.elapsed(), r.len());
}
