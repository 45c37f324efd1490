//! What each point from rest costs on the paper's three beds without lids (N = 3, d = inf)
//! over 44-56 Hz, on one thread: CPU time (each point run 20 times), the periods its transient
//! ran, what those periods alone cost (the motion from rest run period by period as the search
//! runs it, without the search), Newton's iterations and attempts, and its amplitudes
//! (docs/simulator.md, "Steady state and what is measured"). The first argument sets
//! `min_periods` (default 20).
//!
//! `cargo run --release --example from_rest_cost -- 20`

use std::f64::consts::PI;
use std::time::Instant;

use shotdamp::model::{Clearance, Damper, Damping, Structure};
use shotdamp::sim::motion::observe::EventLog;
use shotdamp::sim::{steady_from_rest, Dynamics, Engine, State, SteadyOptions, System};

/// CPU time of `periods` forcing periods of the motion from rest, one `advance` a period with
/// its events logged (as the search runs them), us.
fn transient_us(d: &Dynamics, periods: usize) -> f64 {
    let engine = Engine::new(d);
    let period = 2.0 * PI / d.omega;
    let reps = 20;
    let start = Instant::now();
    for _ in 0..reps {
        let mut s = State::at_rest(d);
        for k in 1..=periods {
            let mut log = EventLog::default();
            if engine.advance(&mut s, k as f64 * period, &mut log).is_err() {
                break;
            }
        }
    }
    start.elapsed().as_secs_f64() / reps as f64 * 1e6
}

fn main() {
    let min_periods = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(20);
    let opts = SteadyOptions { min_periods, ..SteadyOptions::default() };
    let m = [0.74, 0.71, 0.64];
    let s = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let beds = (0..3).map(|j| Damper::new(j, 0.1 * m[j], Clearance::from_m(f64::INFINITY))).collect();
    let sys = System::plastic(s, beds, 0, 2.6);
    let base = Dynamics::unforced(&sys).expect("the paper's structure decomposes");
    println!("freq_hz,us,transient_periods,transient_us,iterations,attempts,amp_m1,amp_m2,amp_m3");
    let (mut total, mut transients) = (0.0, 0.0);
    let freqs: Vec<f64> = (0..=120).map(|i| ((440.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    for &f in &freqs {
        let d = base.at_omega(2.0 * PI * f).expect("a forced response");
        let reps = 20;
        let start = Instant::now();
        let mut last = None;
        for _ in 0..reps {
            last = Some(steady_from_rest(&d, &opts));
        }
        let us = start.elapsed().as_secs_f64() / reps as f64 * 1e6;
        total += us;
        let Some(st) = last else { continue };
        let (it, att) = st.certificate.as_ref().map_or((0, 0), |c| (c.iterations, c.attempts));
        // A point whose beds ride started on its riding motion, not at rest.
        let lifts = st.liftoffs.iter().any(|&n| n > 0.0);
        let alone = if lifts { transient_us(&d, st.transient_periods) } else { 0.0 };
        transients += alone;
        let a = &st.amplitude;
        println!(
            "{f},{us:.1},{},{alone:.1},{it},{att},{:.12e},{:.12e},{:.12e}",
            st.transient_periods, a[0], a[1], a[2]
        );
    }
    let n = freqs.len() as f64;
    eprintln!(
        "mean {:.1} us a point, of which the transients' periods alone {:.1} us (min_periods {min_periods})",
        total / n,
        transients / n
    );
}
