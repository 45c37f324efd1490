//! Finite-element structures (docs/fe-models.md): loading and reducing the plate CalculiX
//! meshed (examples/plate, 1410 degrees of freedom, four points, fixed-interface modes below
//! 2.5 kHz: a reduced model of 20 coordinates), and a followed band of its first bending
//! mode with shot at both free corners (12 points, one thread). Results and the machine they
//! ran on are recorded in BENCHMARKS.md.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::experiment::Experiment;
use shotdamp::sim::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, SteadyOptions, System};

fn plate() -> Experiment {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/plate/plate.toml");
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("reference");
    shotdamp::experiment::load(&path, &reference).expect("the plate loads").remove(0)
}

fn fe(c: &mut Criterion) {
    let mut group = c.benchmark_group("fe");
    group.sample_size(10);
    group.bench_function("plate 1410 dof: read CalculiX files and reduce to 20 coordinates", |b| b.iter(plate));
    let exp = plate();
    let case = exp.cases.iter().find(|c| c.id == "corners").expect("the corners case");
    let sys = System::plastic(exp.structure.clone(), case.dampers(), exp.excitation.mass, exp.excitation.force);
    let base = Dynamics::unforced(&sys);
    assert!(base.is_ok(), "decomposed");
    let freqs: Vec<f64> = (0..12).map(|i| 30.0 + 0.5 * i as f64).collect();
    let follow = SteadyOptions { follow: true, ..SteadyOptions::default() };
    group.bench_function("plate, 2 containers: 12 points followed 30-35.5 Hz", |b| {
        b.iter(|| sweep::continued_on(&base, &freqs, Direction::Up, &follow, &|| {}))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's plots need system fonts; the numbers are what BENCHMARKS.md records.
    config = Criterion::default().without_plots();
    targets = fe
}
criterion_main!(benches);
