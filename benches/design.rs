//! Benchmarks of the design search (docs/design.md): one evaluation of the paper's layout on
//! Fig. 5's band (49 frequencies, continuation up and down: 98 certified steady states) on one
//! thread (its two sweeps run side by side on more), the cost per point the design's 50 us
//! target is about; and the whole 3rd-mode search on the stated chain (7 placements, shot
//! split, shared clearance) on all cores.
//! Results and the machine they ran on are recorded in BENCHMARKS.md.

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::design::search::{optimise, placements, Options, Space};
use shotdamp::design::{bare, evaluate, Band, Combine, Layout, Measure, Problem, Sweep};
use shotdamp::model::{Damping, Structure};
use shotdamp::sim::SteadyOptions;

fn problem(steady: SteadyOptions) -> Problem {
    let structure =
        Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    Problem {
        structure,
        driven: 0,
        force: 2.6,
        bands: vec![Band {
            name: "mode 3".into(),
            freq_hz: (0..=48).map(|i| 44.0 + 0.25 * i as f64).collect(),
            masses: vec![1],
        }],
        measure: Measure::Peak,
        sweeps: vec![Sweep::Up, Sweep::Down],
        steady,
        scenarios: Vec::new(),
        combine: Combine::Worst,
        direction: shotdamp::model::Direction::Vertical,
        supports: false,
        suite: None,
    }
}

fn design(c: &mut Criterion) {
    // The steady-state settings of design files: orbits followed from point to point,
    // max_periods 500 (docs/design.md, "Cost").
    let followed = problem(SteadyOptions { follow: true, max_periods: 500, ..SteadyOptions::default() });
    let plain = problem(SteadyOptions::default());
    let b = bare(&followed);
    let p = followed;
    let paper = Layout { hosts: vec![0, 1, 2], masses_kg: vec![0.074, 0.071, 0.064], clearances_mm: vec![0.35; 3] };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    let mut group = c.benchmark_group("design");
    group.sample_size(10);
    group.bench_function("evaluate the paper's layout, Fig. 5 band, up + down (98 points)", |bench| {
        bench.iter(|| one.install(|| evaluate(&p, &b, &paper)))
    });
    group.bench_function("the same without following the orbits (98 points)", |bench| {
        bench.iter(|| one.install(|| evaluate(&plain, &b, &paper)))
    });
    let space = Space {
        placements: placements(&[0, 1, 2], 3),
        shot_kg: 0.209,
        clearance_mm: (0.05, 2.0),
        shared_clearance: true,
    };
    group.bench_function("3rd-mode search, stated chain: 7 placements, split, shared clearance", |bench| {
        bench.iter(|| optimise(&p, &b, &space, &Options::default()))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = design
}
criterion_main!(benches);
