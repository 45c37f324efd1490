//! Finite-element structures (docs/fe-models.md): loading and reducing the plate CalculiX
//! meshed (examples/plate, 1410 degrees of freedom, four points, fixed-interface modes below
//! 2.5 kHz: a reduced model of 20 coordinates), and a followed band of its first bending
//! mode with shot at both free corners (12 points, one thread); the plate design's answer
//! (three containers) followed where it settles, on two reductions. Results and the machine
//! they ran on are recorded in BENCHMARKS.md.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::experiment::Experiment;
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, SteadyOptions, System};

include!("common/plate_answer.rs");

fn plate() -> Experiment {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/plate/plate.toml");
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("reference");
    shotdamp::experiment::loader::load(&path, &reference).expect("the plate loads").remove(0)
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

/// The plate design's stored answer (examples/plate/modes.toml: three containers) on the
/// design's five points, 20 fixed-interface modes (25 coordinates) and modes to 8 kHz (the
/// design's judged model, 46 coordinates), followed up over 33-35.5 Hz (11 points, one thread),
/// where every point is a certified orbit (the beds ride; beyond 35.5 Hz their motion does not
/// settle within 1500 periods).
fn answer_bands(c: &mut Criterion) {
    let mut group = c.benchmark_group("fe");
    group.sample_size(10);
    for (name, reduction) in
        [("20 modes, 25 coordinates", "modes = 20"), ("modes to 8 kHz, 46 coordinates", "cutoff_hz = 8000.0")]
    {
        let exp = plate_answer(reduction);
        let sys = answer_system(&exp);
        let base = Dynamics::unforced(&sys);
        assert!(base.is_ok(), "decomposed");
        let freqs: Vec<f64> = (0..11).map(|i| 33.0 + 0.25 * i as f64).collect();
        let forced = sweep::forced_at(&base, &freqs);
        let follow = SteadyOptions { follow: true, ..SteadyOptions::default() };
        let points = sweep::continued_at(&forced, Direction::Up, &follow, &|| {});
        assert!(points.iter().all(|p| p.result.as_ref().is_ok_and(|s| s.converged)), "every point certified");
        group.bench_function(format!("plate answer, 3 containers, {name}: 11 points followed 33-35.5 Hz"), |b| {
            b.iter(|| sweep::continued_at(&forced, Direction::Up, &follow, &|| {}))
        });
        // Measuring only the masses a design reads (the driven point and the hosts), as the
        // design does on a structure of more than 8 coordinates.
        let read = std::iter::once(exp.excitation.mass).chain(sys.dampers.iter().map(|b| b.host));
        let design = SteadyOptions { observe: shotdamp::sim::motion::observe::Observe::only(read), ..follow };
        group.bench_function(format!("the same, {name}, measuring the 4 masses a design reads"), |b| {
            b.iter(|| sweep::continued_at(&forced, Direction::Up, &design, &|| {}))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's plots need system fonts; the numbers are what BENCHMARKS.md records.
    config = Criterion::default().without_plots();
    targets = fe, answer_bands
}
criterion_main!(benches);
