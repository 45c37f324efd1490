//! What a Newton-Picard method would have to work with on the size family's chains
//! (docs/simulator.md, "Cost per degree of freedom"): on each followed lifting orbit of the
//! band (41-48 Hz), the Floquet multipliers' moduli (how many directions decay slowly: the
//! subspace Newton would keep, the rest left to plain iteration of the map) and, on one
//! thread, the cost of one return of the period map without its linearised flow, with the
//! whole flow (every coordinate, as Newton's method carries it now) and with the flow of only
//! `k` directions (what Newton on a `k`-dimensional subspace would carry).
//!
//! `cargo run --release --example newton_picard_estimate -- 64`

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::DMatrix;
use shotdamp::sim::motion::engine::Engine;
use shotdamp::sim::orbits::periodic::Section;
use shotdamp::sim::orbits::strobe::{Rest, Strobe};
use shotdamp::sim::orbits::tangent::Tangent;
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, SteadyOptions};

include!("../benches/common/size_family.rs");

/// Median seconds of `reps` runs of `f`.
fn median(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(64);
    let sys = refined(n);
    let base = Dynamics::unforced(&sys);
    // 0.25 Hz steps over the lifting orbits, followed (as examples/followed_cost.rs).
    let freqs: Vec<f64> = (0..=27).map(|i| 41.75 + 0.25 * i as f64).collect();
    let follow = SteadyOptions { follow: true, ..SteadyOptions::default() };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    let points = one.install(|| sweep::continued_on(&base, &freqs, Direction::Up, &follow, &|| {}));
    println!(
        "chain of {n} masses: per followed orbit, multipliers above 0.5 / 0.1 / 0.01 of {{dim}}, and one return (ms)"
    );
    println!("  freq   dim  >0.5 >0.1 >0.01 | no flow | whole flow | k = 8, 16, 32 directions");
    for p in &points {
        let (Ok(st), Ok(d)) =
            (&p.result, base.as_ref().map_err(Clone::clone).and_then(|b| b.at_omega(2.0 * PI * p.freq_hz)))
        else {
            continue;
        };
        let (Some(cert), Some(at)) = (&st.certificate, st.section_state()) else { continue };
        if !st.converged || st.period != 1 || st.liftoffs.iter().all(|&l| l == 0.0) {
            continue;
        }
        let length = st.amplitude.iter().copied().fold(0.0, f64::max).max(1e-12);
        let strobe = Strobe { phase: cert.phase, periods: 1, beds: at.beds.iter().map(Rest::of).collect(), length };
        let Ok(u) = strobe.coordinates(&d, at) else { continue };
        let above = |x: f64| cert.multipliers.iter().filter(|z| z.norm() > x).count();
        let no_flow = median(9, || {
            let _ = strobe.image(&d, &u);
        });
        let whole = median(9, || {
            let _ = strobe.map(&d, &u);
        });
        let full = Tangent::full_dim(&d);
        let partial = |k: usize| {
            median(9, || {
                let mut s = strobe.state(&d, &u);
                let t_end = strobe.end_time(&d, s.t);
                let start = DMatrix::from_fn(full, k, |r, c| if r % k == c { 1.0 } else { 0.0 });
                let mut tangent = Tangent::new(&d, start);
                let _ = Engine::new(&d).advance(&mut s, t_end, &mut tangent);
                let _ = tangent.matrix(&d);
            })
        };
        println!(
            "  {:5.2}  {:>4}  {:>4} {:>4} {:>5} | {:7.3} | {:10.3} | {:.3}, {:.3}, {:.3}",
            p.freq_hz,
            u.len(),
            above(0.5),
            above(0.1),
            above(0.01),
            no_flow * 1e3,
            whole * 1e3,
            partial(8) * 1e3,
            partial(16) * 1e3,
            partial(32) * 1e3
        );
    }
}
