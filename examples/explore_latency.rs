//! What an explorer request costs on a finite-element model, and what validating it again
//! costs now that a reduction is made once a process (docs/extending.md, "One setup, built
//! once"): the plate CalculiX meshed (`examples/plate/plate.toml`), the same session asked
//! for a setup at several clearances; each request's validation (the file read, checked and
//! its model reduced or found reduced) and its whole sweep over a short band are timed. Then
//! a study's samples (Fig. 5's map of damping and clearance, `studies/fig05_damping_clearance.toml`,
//! 336 samples on three models): each sample's experiment validated, timed.
//!
//!     cargo run --release --example explore_latency [-- FILE [STUDY]]

use std::path::PathBuf;
use std::time::Instant;

use shotdamp::experiment::fe::made;
use shotdamp::explore::{Request, Session};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = std::env::args().nth(1).map(PathBuf::from).unwrap_or_else(|| "examples/plate/plate.toml".into());
    let t = Instant::now();
    let session = Session::open(&file, "reference".as_ref())?;
    println!("{}: session opened in {:.1} ms ({} reduction(s) computed)", file.display(), ms(t), made::computed());
    for (k, d) in [2.0, 1.0, 4.0, 2.0].into_iter().enumerate() {
        let req: Request = serde_json::from_value(serde_json::json!({
            "model": 0,
            "set": [["cases[*].dampers[*].clearance_mm", d]],
            "band": {"start": 36.0, "stop": 37.0, "step": 0.5},
            "start": "rest",
        }))?;
        let before = made::computed();
        let t = Instant::now();
        session.experiment(&req)?;
        let validated = ms(t);
        let t = Instant::now();
        session.run(&req, &|| {})?;
        println!(
            "  request {k} (d = {d} mm): validated in {validated:.1} ms ({} reduction(s) computed), answered in {:.1} ms",
            made::computed() - before,
            ms(t)
        );
    }
    let study =
        std::env::args().nth(2).map(PathBuf::from).unwrap_or_else(|| "studies/fig05_damping_clearance.toml".into());
    let t = Instant::now();
    let study = shotdamp::experiment::study::load(&study, "reference".as_ref())?;
    println!("{}: study read in {:.1} ms", study.path.display(), ms(t));
    for round in 0..2 {
        let t = Instant::now();
        for sample in &study.samples {
            study.experiment(sample)?;
        }
        let n = study.samples.len();
        println!(
            "  round {round}: {n} samples validated in {:.1} ms ({:.0} us a sample)",
            ms(t),
            ms(t) * 1e3 / n as f64
        );
    }
    Ok(())
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
