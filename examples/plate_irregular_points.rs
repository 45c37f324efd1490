//! What the plate design's points without an orbit are: the design's stored answer
//! (examples/plate/modes.toml, three containers) on the 46-coordinate model designs/plate.toml
//! judges on, one band (first argument: 0 first bending 33-43 Hz, 1 first torsion 115-140 Hz,
//! 2 second bending 215-255 Hz), continued up and down as the design sweeps it, each point
//! measured twice: as the design measures it (150 periods in all, handed over to the
//! measurement after 100 without an orbit, 5 % intervals) and with a budget of `budget`
//! periods (second argument, default 1500) for the same measurement. Prints, for every point
//! that is not a certified orbit in either, both classes, periods and the free corner's
//! statistic with its half-width; one thread (docs/design.md, "Where an unscreened plate
//! evaluation goes").
//!
//! `cargo run --release --example plate_irregular_points -- 1 1500`

use std::time::Instant;

use shotdamp::design::{HAND_OVER, INTERVAL_TOL};
use shotdamp::sim::motion::observe::Observe;
use shotdamp::sim::settle::statistic::Measure;
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, Steady, SteadyOptions};

include!("../benches/common/plate_answer.rs");

fn grid(a: f64, b: f64, step: f64) -> Vec<f64> {
    let n = ((b - a) / step).round() as usize;
    (0..=n).map(|i| a + step * i as f64).collect()
}

fn words(st: &Steady) -> String {
    let hw = st.measured.as_ref().map_or(0.0, |m| m.half_width[0]);
    let exponent = st
        .measured
        .as_ref()
        .map_or(String::new(), |m| format!(", exponent {:.0} +- {:.0} 1/s", m.lyapunov, m.lyapunov_half_width));
    format!(
        "{:<14} {:>4} periods, {:.4e} +- {:.1e} m{exponent}",
        st.motion.name(),
        st.transient_periods + st.recorded_periods,
        st.amplitude[0],
        hw
    )
}

fn main() {
    let band: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    let budget: usize = std::env::args().nth(2).and_then(|a| a.parse().ok()).unwrap_or(1500);
    let freqs = match band {
        0 => grid(33.0, 43.0, 0.25),
        1 => grid(115.0, 140.0, 0.5),
        _ => grid(215.0, 255.0, 1.0),
    };
    let exp = plate_answer("modes = 41");
    let points = exp.structure.points.unwrap_or(exp.structure.dof());
    let sys = answer_system(&exp);
    let base = Dynamics::unforced(&sys);
    let forced = sweep::forced_at(&base, &freqs);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    // As designs/plate.toml: `steady = { follow = true, max_periods = 150 }`, the five points
    // observed, the design's measurement (design::band).
    let design = SteadyOptions {
        follow: true,
        max_periods: 150,
        observe: Observe::only(0..points),
        measure: Measure::handed_over(HAND_OVER, INTERVAL_TOL),
        ..SteadyOptions::default()
    };
    let long = SteadyOptions { max_periods: budget.max(design.max_periods), ..design };
    for way in [Direction::Up, Direction::Down] {
        let t = Instant::now();
        let a = one.install(|| sweep::continued_at(&forced, way, &design, &|| {}));
        let ta = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let b = one.install(|| sweep::continued_at(&forced, way, &long, &|| {}));
        let tb = t.elapsed().as_secs_f64();
        println!("{way:?}: as the design measures {ta:.1} s; with a budget of {} periods {tb:.1} s", long.max_periods);
        for (p, q) in a.iter().zip(&b) {
            let (Ok(s), Ok(r)) = (&p.result, &q.result) else { continue };
            if s.converged && r.converged {
                continue;
            }
            println!("  {:6.2} Hz  {} | {}", p.freq_hz, words(s), words(r));
        }
    }
}
