//! What measuring a design's irregular points costs and gives, on `designs/six_storey.toml`'s
//! problem (six storeys, horizontal containers, the roof's first two resonances under 5 N,
//! continued sweeps up and down): a few layouts evaluated with the design's measurement (the
//! orbit search hands a point with no orbit after 100 periods to the measurement, which ends
//! at a 5 % interval) and without it (the short record after the whole budget), each timed,
//! and the same layouts' objectives from rest against continued (docs/design.md).
//!
//!     cargo run --release --example design_measured [-- --jobs 1] [--only K] [--max-periods N]
//!
//! K: 0 the design's measurement, 1 the short record, 2 from rest, 3 to a 1 % interval; N: a
//! point's budget of periods (default 1500; a design file's is 500).

use std::time::Instant;

use shotdamp::design::{bare, evaluate, Band, Combine, Evaluation, Layout, Measure, Problem, Sweep};
use shotdamp::model::{Damping, Direction, Structure};
use shotdamp::sim::settle::statistic::Measure as Irregular;
use shotdamp::sim::SteadyOptions;

fn problem(sweeps: Vec<Sweep>, measure: Irregular, max_periods: usize) -> Problem {
    let masses = [2.0, 2.0, 2.0, 2.0, 2.0, 1.5];
    let k = [40e3, 38e3, 36e3, 34e3, 32e3, 30e3];
    let grid = |a: f64, b: f64, step: f64| -> Vec<f64> {
        let n = ((b - a) / step).round() as usize;
        (0..=n).map(|i| a + step * i as f64).collect()
    };
    Problem {
        structure: Structure::chain(&masses, &k, Damping::ModalRatios(vec![0.02; 6])),
        driven: 5,
        force: 5.0,
        bands: vec![
            Band { name: "mode 1".into(), freq_hz: grid(4.4, 6.2, 0.1), masses: vec![5] },
            Band { name: "mode 2".into(), freq_hz: grid(13.5, 16.7, 0.2), masses: vec![5] },
        ],
        measure: Measure::Peak,
        sweeps,
        steady: SteadyOptions { follow: true, measure, max_periods, ..SteadyOptions::default() },
        scenarios: Vec::new(),
        combine: Combine::Worst,
        direction: Direction::Horizontal,
        supports: false,
        suite: None,
    }
}

fn line(p: &Problem, name: &str, e: &Evaluation, seconds: f64) {
    // Band points where the sweeps reached motions that differ beyond their intervals.
    let mut both = 0;
    for (b, band) in p.bands.iter().enumerate() {
        for (row, points) in e.curves[b].iter().zip(&e.points_class[b]) {
            both += band.masses.iter().filter(|&&m| points[m].coexisting(row[m]) == Some(true)).count();
        }
    }
    // Where the objective comes from: the worst band's frequency, and whether the sweeps reached
    // different motions there.
    let (b, f, m) = e.worst;
    let at = p.bands[b].freq_hz.iter().position(|x| *x == f);
    let there = at.and_then(|i| e.points_class.get(b)?.get(i)?.get(m)).map_or("", |pt| {
        match pt.coexisting(e.curves[b][at.unwrap_or(0)][m]) {
            Some(true) => ", coexisting there",
            _ => "",
        }
    });
    println!(
        "  {name:<34} {:.4} +- {:.4} (at {f} Hz{there})  unsettled {:>3} of {:>3} ({}; coexisting at {both}; measured {}, over a screen only {})  {:.1} s",
        e.objective,
        e.half_width,
        e.unsettled,
        e.points,
        e.class_words(),
        e.measured,
        e.screened,
        seconds
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(j) = args.iter().position(|a| a == "--jobs").and_then(|i| args.get(i + 1)).and_then(|j| j.parse().ok())
    {
        rayon::ThreadPoolBuilder::new().num_threads(j).build_global().ok();
    }
    let layouts = [
        ("roof, 20 mm", Layout { hosts: vec![5], masses_kg: vec![1.15], clearances_mm: vec![20.0] }),
        (
            "m5 m6 even, 20 mm",
            Layout { hosts: vec![4, 5], masses_kg: vec![0.575, 0.575], clearances_mm: vec![20.0; 2] },
        ),
        (
            "m5 m6 even, 60 mm",
            Layout { hosts: vec![4, 5], masses_kg: vec![0.575, 0.575], clearances_mm: vec![60.0; 2] },
        ),
        ("m4 m6 1:2, 40 mm", Layout { hosts: vec![3, 5], masses_kg: vec![0.383, 0.767], clearances_mm: vec![40.0; 2] }),
        // The design's best layout (docs/design.md, "A swaying building").
        (
            "best: m4 0.92, m6 0.23 kg, 4.1 mm",
            Layout { hosts: vec![3, 5], masses_kg: vec![0.92, 0.23], clearances_mm: vec![4.1; 2] },
        ),
    ];
    let continued = vec![Sweep::Up, Sweep::Down];
    let runs = [
        ("measured (design default)", continued.clone(), Irregular::default()),
        ("short record (no measurement)", continued.clone(), Irregular::periods(0, 0.01)),
        ("measured, from rest", vec![Sweep::Rest], Irregular::default()),
        // Coexisting motions or intervals too narrow? A 1 % interval (longer records).
        ("measured to 1 %, continued", continued, Irregular::handed_over(100, 0.01)),
    ];
    // A design file's default budget is 500 periods (docs/design.md); the steady state's 1500.
    let budget: usize = args
        .iter()
        .position(|a| a == "--max-periods")
        .and_then(|i| args.get(i + 1))
        .and_then(|j| j.parse().ok())
        .unwrap_or(SteadyOptions::default().max_periods);
    let only: Option<usize> =
        args.iter().position(|a| a == "--only").and_then(|i| args.get(i + 1)).and_then(|j| j.parse().ok());
    for (k, (what, sweeps, measure)) in runs.into_iter().enumerate() {
        if only.is_some_and(|o| o != k) {
            continue;
        }
        let p = problem(sweeps, measure, budget);
        let b = bare(&p);
        println!("{what}:");
        let mut total = 0.0;
        for (name, l) in &layouts {
            let t = Instant::now();
            let e = evaluate(&p, &b, l);
            let s = t.elapsed().as_secs_f64();
            total += s;
            line(&p, name, &e, s);
        }
        println!("  total {total:.1} s");
    }
}
