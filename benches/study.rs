//! Benchmark of a study: the Fig. 5 damping x clearance map on the stated chain (8 damping
//! ratios x 14 clearances = 112 samples, each two cases x 61 frequencies, every point a
//! certified periodic orbit), run on all cores as `shotdamp study` runs it.
//! Results and the machine they ran on are recorded in BENCHMARKS.md.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use shotdamp::analysis::study::run_all;
use shotdamp::checks::reference::ReferenceStore;
use shotdamp::experiment::study;

fn fig05_map(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let reference = root.join("reference");
    let mut s = study::load(&root.join("studies/fig05_damping_clearance.toml"), &reference).expect("study");
    s.samples.retain(|x| x.model == "stated");
    let refs = ReferenceStore::load(&reference, &s.base).expect("references");
    let mut group = c.benchmark_group("study");
    group.sample_size(10);
    group.bench_function("fig05 map stated: 8 damping x 14 clearances x 2 cases x 61 frequencies", |b| {
        b.iter(|| run_all(&s, &refs, &|| {}).expect("rows"))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = fig05_map
}
criterion_main!(benches);
