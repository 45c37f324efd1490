//! What a point that does not settle costs on a finite-element structure: the plate design's
//! stored answer (examples/plate/modes.toml, three containers) on the plate reduced with
//! `modes` fixed-interface modes (first argument, default 41: 46 coordinates, the design's
//! judged model), from rest at `freq` Hz (second argument, default 36: the beds' motion is
//! chaotic there), on one thread: the time, the periods run and what the motion was
//! (docs/simulator.md, "Cost per degree of freedom").
//!
//! `cargo run --release --example irregular_cost -- 41 36`

use std::time::Instant;

use shotdamp::sim::motion::observe::Observe;
use shotdamp::sim::settle::sweep;
use shotdamp::sim::{Dynamics, SteadyOptions};

include!("../benches/common/plate_answer.rs");

fn main() {
    let modes: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(41);
    let freq: f64 = std::env::args().nth(2).and_then(|a| a.parse().ok()).unwrap_or(36.0);
    let sys = answer_system(&plate_answer(&format!("modes = {modes}")));
    let base = Dynamics::unforced(&sys);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    let start = Instant::now();
    // As a sweep does: the points measured, not the modal coordinates.
    let points = sys.structure.points.unwrap_or(sys.dof());
    let opts = SteadyOptions { observe: Observe::only(0..points), ..SteadyOptions::default() };
    let point = one.install(|| sweep::from_rest_on(&base, &[freq], &opts, &|| {}));
    let s = start.elapsed().as_secs_f64();
    match &point[0].result {
        Ok(st) => {
            let periods = st.transient_periods + st.recorded_periods;
            let impacts: f64 = st.bottom_impacts.iter().chain(&st.top_impacts).sum();
            println!(
                "{} coordinates, {freq} Hz: {:?}, {periods} periods ({} transient), {impacts:.1} impacts a period, {s:.2} s, {:.2} ms a period",
                sys.dof(),
                st.motion,
                st.transient_periods,
                s * 1e3 / periods as f64
            );
            if let Some(m) = &st.measured {
                let lead = m.statistic[..points].iter().copied().fold(0.0, f64::max);
                println!(
                    "largest statistic {lead:.4e} m over {} periods, Lyapunov exponent {:.1} +- {:.1} 1/s",
                    m.periods, m.lyapunov, m.lyapunov_half_width
                );
            }
        }
        Err(e) => println!("{e}"),
    }
}
