//! Benchmarks of the simulator: one steady-state point, and the Fig. 8 three-damper sweep.
//! Results and the machine they ran on are recorded in BENCHMARKS.md.

use std::f64::consts::PI;

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::{steady_state, sweep, Dynamics, State, SteadyOptions, System};

fn three_dampers() -> System {
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let m = [0.74, 0.71, 0.64];
    let dampers = (0..3).map(|j| Damper { host: j, mass: 0.1 * m[j], clearance: f64::INFINITY }).collect();
    System::plastic(s, dampers, 0, 2.6)
}

fn point(c: &mut Criterion) {
    let sys = three_dampers();
    c.bench_function("steady point N=3 d=inf 49.5 Hz", |b| {
        b.iter(|| {
            let d = Dynamics::new(&sys, 2.0 * PI * 49.5).expect("dynamics");
            steady_state(&d, State::at_rest(&d), &SteadyOptions::default())
        })
    });
}

fn fig08_sweep(c: &mut Criterion) {
    let sys = three_dampers();
    let freqs: Vec<f64> = (0..=520).map(|i| ((80.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("fig08 N=3 8-60 Hz step 0.1 (521 points)", |b| {
        b.iter(|| sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {}))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's plots need system fonts; the numbers are what BENCHMARKS.md records.
    config = Criterion::default().without_plots();
    targets = point, fig08_sweep
}
criterion_main!(benches);
