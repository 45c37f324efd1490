//! What each point from rest costs on the paper's three beds without lids (N = 3, d = inf)
//! over 44-56 Hz, on one thread: CPU time (each point run 20 times), the periods its transient
//! ran, Newton's iterations and attempts, and its amplitudes (docs/simulator.md, "Steady state
//! and what is measured"). The first argument sets `min_periods` (default 20).
//!
//! `cargo run --release --example from_rest_cost -- 20`

use std::f64::consts::PI;
use std::time::Instant;

use shotdamp::model::{Clearance, Damper, Damping, Structure};
use shotdamp::sim::{steady_from_rest, Dynamics, SteadyOptions, System};

fn main() {
    let min_periods = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(20);
    let opts = SteadyOptions { min_periods, ..SteadyOptions::default() };
    let m = [0.74, 0.71, 0.64];
    let s = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let beds = (0..3).map(|j| Damper::new(j, 0.1 * m[j], Clearance::from_m(f64::INFINITY))).collect();
    let sys = System::plastic(s, beds, 0, 2.6);
    let base = Dynamics::unforced(&sys).expect("the paper's structure decomposes");
    println!("freq_hz,us,transient_periods,iterations,attempts,amp_m1,amp_m2,amp_m3");
    let mut total = 0.0;
    let freqs: Vec<f64> = (0..=120).map(|i| ((440.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    for &f in &freqs {
        let d = base.at_omega(2.0 * PI * f).expect("a forced response");
        let reps = 20;
        let start = Instant::now();
        let mut last = None;
        for _ in 0..reps {
            last = Some(steady_from_rest(&d, &opts));
        }
        let us = start.elapsed().as_secs_f64() / reps as f64 * 1e6;
        total += us;
        let Some(st) = last else { continue };
        let (it, att) = st.certificate.as_ref().map_or((0, 0), |c| (c.iterations, c.attempts));
        let a = &st.amplitude;
        println!("{f},{us:.1},{},{it},{att},{:.12e},{:.12e},{:.12e}", st.transient_periods, a[0], a[1], a[2]);
    }
    eprintln!("mean {:.1} us a point (min_periods {min_periods})", total / freqs.len() as f64);
}
