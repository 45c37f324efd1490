//! Fig. 5's sweep with the bed as a column of grains: the paper's three containers (mu = 0.1,
//! d = 0.35 mm), each bed 10 grains with restitution 0.3, 121 frequencies from rest, next to
//! the paper's single plastic mass.
//!
//! `cargo run --release --example column_sweep`

use shotdamp::model::Clearance;
use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::motion::bed::ImpactLaw;
use shotdamp::sim::{settle::sweep, SteadyOptions, System};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let grains: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(10);
    let e: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(0.3);
    let hosts: Vec<usize> = match args.get(3).map(String::as_str) {
        Some("one") => vec![2],
        _ => vec![0, 1, 2],
    };
    let m = [0.74, 0.71, 0.64];
    let structure = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let dampers: Vec<Damper> = hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_m(0.35e-3))).collect();
    let single = System::plastic(structure, dampers, 0, 2.6);
    let law = ImpactLaw::with_restitution(e, 1e-3);
    let column = single.clone().with_law(law).with_grains(&vec![grains; hosts.len()]);
    let freqs: Vec<f64> = (0..121).map(|i| 35.0 + 0.25 * i as f64).collect();
    let opts = SteadyOptions::default();
    let t = std::time::Instant::now();
    let a = sweep::from_rest(&single, &freqs, &opts, &|| {});
    let ta = t.elapsed();
    let t = std::time::Instant::now();
    let b = sweep::from_rest(&column, &freqs, &opts, &|| {});
    let tb = t.elapsed();
    println!(
        "single plastic mass: {:.2} s; {grains}-grain columns, e = {e}: {:.2} s",
        ta.as_secs_f64(),
        tb.as_secs_f64()
    );
    println!("freq_hz  x1/F single  x1/F column  settled  periods");
    for (p, q) in a.iter().zip(&b) {
        let (Ok(s), Ok(c)) = (&p.result, &q.result) else { continue };
        println!(
            "{:6.2}  {:.4e}  {:.4e}  {}  {}",
            p.freq_hz,
            s.amplitude[0] / 2.6,
            c.amplitude[0] / 2.6,
            c.converged,
            c.transient_periods
        );
    }
}
