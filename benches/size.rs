//! Cost per degree of freedom (docs/simulator.md, "Cost per degree of freedom"): chains of
//! n = 3, 8, 16, 32, 64 equal masses refining the paper's structure (2.09 kg in all, series
//! stiffness 7.27 kN/m, Rayleigh damping of 1 % at 14.6 and 73 Hz), three containers of 10 %
//! of their host's mass with 0.5 mm of clearance on the last three masses, driven at the first
//! by the force that gives the first mode the paper's modal force, over the band of its top
//! three modes below 60 Hz (12 points). On one thread: the decomposition of the 8
//! configurations, the band from rest, and the band followed. The family is defined once in
//! benches/common/size_family.rs (tests/size.rs and examples/followed_cost.rs include it too).
//! Results and the machine they ran on are recorded in BENCHMARKS.md.

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, SteadyOptions};

include!("common/size_family.rs");

fn per_dof(c: &mut Criterion) {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    let mut group = c.benchmark_group("size");
    group.sample_size(10);
    for n in [3, 8, 16, 32, 64] {
        let sys = refined(n);
        let freqs = band(&sys);
        group.bench_function(format!("n={n}: decompose 8 configurations"), |b| {
            b.iter(|| Dynamics::unforced(&sys).expect("decomposed"))
        });
        let base = Dynamics::unforced(&sys);
        group.bench_function(format!("n={n}: 12 points from rest"), |b| {
            b.iter(|| one.install(|| sweep::from_rest_on(&base, &freqs, &SteadyOptions::default(), &|| {})))
        });
        let follow = SteadyOptions { follow: true, ..SteadyOptions::default() };
        group.bench_function(format!("n={n}: 12 points followed"), |b| {
            b.iter(|| sweep::continued_on(&base, &freqs, Direction::Up, &follow, &|| {}))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's plots need system fonts; the numbers are what BENCHMARKS.md records.
    config = Criterion::default().without_plots();
    targets = per_dof
}
criterion_main!(benches);
