//! Where one layout evaluation of the plate design goes, on the file's own model (no
//! `[design.screen]`): the design's stored answer (examples/plate/modes.toml, three
//! containers) on the plate reduced with `modes` fixed-interface modes (first argument,
//! default 41: 46 coordinates, the model designs/plate.toml judges on), evaluated as the design
//! evaluates a layout (its three bands, continued up and down, following the orbits, 150
//! periods a point, a point without an orbit after 100 measured as irregular motion), on one
//! thread: the evaluation's time and classes, then the same sweeps point by point with the
//! time each class of point takes (docs/design.md, "Searching on a coarser reduction").
//!
//! `cargo run --release --example plate_evaluation_cost -- 41`

use std::sync::Mutex;
use std::time::Instant;

use shotdamp::design::{bare, evaluate, Band, Combine, Layout, Measure, Problem, Sweep, HAND_OVER, INTERVAL_TOL};
use shotdamp::model::Direction;
use shotdamp::sim::motion::observe::Observe;
use shotdamp::sim::settle::statistic::{Measure as Irregular, Motion};
use shotdamp::sim::settle::sweep::{self, Direction as Way};
use shotdamp::sim::{Dynamics, SteadyOptions};

include!("../benches/common/plate_answer.rs");

fn grid(a: f64, b: f64, step: f64) -> Vec<f64> {
    let n = ((b - a) / step).round() as usize;
    (0..=n).map(|i| a + step * i as f64).collect()
}

fn main() {
    let modes: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(41);
    let exp = plate_answer(&format!("modes = {modes}"));
    let points = exp.structure.points.unwrap_or(exp.structure.dof());
    let bands = vec![
        Band { name: "first bending".into(), freq_hz: grid(33.0, 43.0, 0.25), masses: vec![0] },
        Band { name: "first torsion".into(), freq_hz: grid(115.0, 140.0, 0.5), masses: vec![0] },
        Band { name: "second bending".into(), freq_hz: grid(215.0, 255.0, 1.0), masses: vec![0] },
    ];
    // As designs/plate.toml: `steady = { follow = true, max_periods = 150 }`, the five points
    // observed (bands, candidates and the cases' hosts).
    let steady =
        SteadyOptions { follow: true, max_periods: 150, observe: Observe::only(0..points), ..SteadyOptions::default() };
    let problem = Problem {
        structure: exp.structure.clone(),
        driven: exp.excitation.mass,
        force: exp.excitation.force,
        bands: bands.clone(),
        measure: Measure::Peak,
        sweeps: vec![Sweep::Up, Sweep::Down],
        steady,
        scenarios: Vec::new(),
        combine: Combine::Worst,
        direction: Direction::Vertical,
        supports: false,
        suite: None,
    };
    let case = &exp.cases[0];
    let layout = Layout {
        hosts: case.beds.iter().map(|b| b.damper.host).collect(),
        masses_kg: case.beds.iter().map(|b| b.damper.mass).collect(),
        clearances_mm: case.beds.iter().map(|b| b.damper.clearance.mm()).collect(),
    };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    println!("plate, {} coordinates, layout {}:", exp.structure.dof(), layout.hosts_words());
    let b = one.install(|| bare(&problem));
    let start = Instant::now();
    let e = one.install(|| evaluate(&problem, &b, &layout));
    println!(
        "  the design's evaluation: {:.2} s, objective {:.4} +- {:.4}, {} of {} points unsettled ({})",
        start.elapsed().as_secs_f64(),
        e.objective,
        e.half_width,
        e.unsettled,
        e.points,
        e.class_words()
    );
    // The same sweeps point by point (the measurement the design asks of a point without an
    // orbit: handed over after HAND_OVER periods, to INTERVAL_TOL, within the 150).
    let sys = answer_system(&exp);
    let base = Dynamics::unforced(&sys);
    let opts = SteadyOptions { measure: Irregular::handed_over(HAND_OVER, INTERVAL_TOL), ..steady };
    let mut time = [0.0f64; Motion::ALL.len()];
    let mut count = [0usize; Motion::ALL.len()];
    let mut periods = [0usize; Motion::ALL.len()];
    for band in &bands {
        let forced = sweep::forced_at(&base, &band.freq_hz);
        for way in [Way::Up, Way::Down] {
            let stamps = Mutex::new(vec![Instant::now()]);
            let swept = one.install(|| {
                sweep::continued_at(&forced, way, &opts, &|| {
                    if let Ok(mut s) = stamps.lock() {
                        s.push(Instant::now());
                    }
                })
            });
            let stamps = stamps.into_inner().unwrap_or_default();
            for (i, p) in swept.iter().enumerate() {
                let (Ok(st), Some(t0), Some(t1)) = (&p.result, stamps.get(i), stamps.get(i + 1)) else { continue };
                let k = st.motion.index();
                time[k] += (*t1 - *t0).as_secs_f64();
                count[k] += 1;
                periods[k] += st.transient_periods + st.recorded_periods;
            }
        }
    }
    println!("  the same sweeps point by point, by class: points, periods run, seconds");
    for (k, class) in Motion::ALL.iter().enumerate().filter(|(k, _)| count[*k] > 0) {
        println!("    {:<15} {:>4} {:>8} {:>8.2} s", class.name(), count[k], periods[k], time[k]);
    }
}
