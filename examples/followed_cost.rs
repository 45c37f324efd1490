//! What a followed point costs on a 32-mass chain (the size benchmarks' family, three beds
//! with 0.5 mm of clearance on the last three masses) over its lifting orbits, 41.5-46.5 Hz in
//! 0.25 Hz steps, on one thread: the band's time, and at each point Newton's iterations, the
//! largest multiplier and how much the orbit's response to the frequency is amplified,
//! `max 1 / |1 - mu|` over the multipliers (docs/simulator.md, "Cost per degree of freedom").
//! The first argument sets the number of masses (default 32), the second how many times the
//! band is run (default 3; the times are the mean).
//!
//! `cargo run --release --example followed_cost -- 32 10`

use std::time::Instant;

use num_complex::Complex64;
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, SteadyOptions};

include!("../benches/common/size_family.rs");

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(32).max(3);
    let base = Dynamics::unforced(&refined(n));
    let freqs: Vec<f64> = (0..21).map(|i| 41.5 + 0.25 * i as f64).collect();
    let follow = SteadyOptions { follow: true, ..SteadyOptions::default() };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    let reps: usize = std::env::args().nth(2).and_then(|a| a.parse().ok()).unwrap_or(3).max(1);
    let start = Instant::now();
    let mut points = Vec::new();
    for _ in 0..reps {
        points = one.install(|| sweep::continued_on(&base, &freqs, Direction::Up, &follow, &|| {}));
    }
    let ms = start.elapsed().as_secs_f64() * 1e3 / reps as f64;
    // The first point runs from rest (its transient); the others are followed.
    let start = Instant::now();
    for _ in 0..reps {
        one.install(|| sweep::continued_on(&base, &freqs[..1], Direction::Up, &follow, &|| {}));
    }
    let first = start.elapsed().as_secs_f64() * 1e3 / reps as f64;
    println!("freq_hz,transient_periods,iterations,largest_multiplier,amplification,at_re,at_im");
    for p in &points {
        let Ok(st) = &p.result else { continue };
        let Some(c) = &st.certificate else {
            println!("{},{},,,,,", p.freq_hz, st.transient_periods);
            continue;
        };
        let one = Complex64::new(1.0, 0.0);
        let (amp, at) = c
            .multipliers
            .iter()
            .map(|mu| (1.0 / (one - mu).norm(), *mu))
            .fold((0.0, Complex64::default()), |a, b| if b.0 > a.0 { b } else { a });
        let r = c.spectral_radius();
        println!("{},{},{},{r:.4},{amp:.1},{:.4},{:.4}", p.freq_hz, st.transient_periods, c.iterations, at.re, at.im);
    }
    eprintln!(
        "n = {n}: {ms:.1} ms for {} points, {:.2} ms a point; the first (from rest) {first:.1} ms, the {} followed {:.2} ms a point",
        freqs.len(),
        ms / freqs.len() as f64,
        freqs.len() - 1,
        (ms - first) / (freqs.len() - 1) as f64
    );
}
