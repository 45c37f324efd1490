//! The paper's 3rd-mode design problem (Fig. 5's setting) searched with shotdamp's design
//! module: which masses of the stated chain carry a container, how 0.209 kg of shot (the
//! paper's mu = 0.1 on every mass) is split among them, and one shared clearance in
//! 0.05-2 mm, to lower the largest compliance of m2 over 44-56 Hz (continuation up and down,
//! the worse of the two). Prints the best layout of each placement and the paper's own layout.
//!
//!     cargo run --release --example design_third_mode

use shotdamp::design::search::{optimise, placements, Options, Space};
use shotdamp::design::{bare, evaluate, Band, Combine, Layout, Measure, Problem, Sweep};
use shotdamp::model::{Damping, Structure};
use shotdamp::sim::SteadyOptions;

fn main() {
    let masses = [0.74, 0.71, 0.64];
    let structure = Structure::chain(&masses, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let freq_hz: Vec<f64> = (0..=48).map(|i| 44.0 + 0.25 * i as f64).collect();
    let problem = Problem {
        structure,
        driven: 0,
        force: 2.6,
        bands: vec![Band { name: "mode 3 (44-56 Hz)".into(), freq_hz, masses: vec![1] }],
        measure: Measure::Peak,
        sweeps: vec![Sweep::Up, Sweep::Down],
        steady: SteadyOptions { follow: true, max_periods: 500, ..SteadyOptions::default() },
        scenarios: Vec::new(),
        combine: Combine::Worst,
        direction: shotdamp::model::Direction::Vertical,
        supports: false,
        suite: None,
    };
    let shot: f64 = masses.iter().map(|m| 0.1 * m).sum();
    let started = std::time::Instant::now();
    let b = bare(&problem);
    println!("bare structure: peak compliance of m2 over 44-56 Hz {:.4e} m/N", b[0][0]);
    let paper = Layout {
        hosts: vec![0, 1, 2],
        masses_kg: masses.iter().map(|m| 0.1 * m).collect(),
        clearances_mm: vec![0.3; 3],
    };
    let e = evaluate(&problem, &b, &paper);
    println!("paper's layout (mu = 0.1 on m1, m2, m3, d = 0.3 mm): {:.4} of the bare peak", e.objective);
    let space = Space {
        placements: placements(&[0, 1, 2], 3),
        shot_kg: shot,
        clearance_mm: (0.05, 2.0),
        shared_clearance: true,
    };
    let found = optimise(&problem, &b, &space, &Options::default());
    for f in &found {
        let hosts: Vec<String> = f.layout.hosts.iter().map(|h| format!("m{}", h + 1)).collect();
        let kg: Vec<String> = f.layout.masses_kg.iter().map(|m| format!("{m:.4}")).collect();
        println!(
            "{:<12} shot kg [{}], d = {:.3} mm: {:.4} of the bare peak ({} evaluations, {} unsettled points)",
            hosts.join(" "),
            kg.join(", "),
            f.layout.clearances_mm[0],
            f.evaluation.objective,
            f.evaluations,
            f.evaluation.unsettled
        );
    }
    println!("{:.1} s", started.elapsed().as_secs_f64());
    // How the objective of one container varies with its clearance.
    for host in 0..3 {
        let row: Vec<String> = [0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0]
            .iter()
            .map(|&d| {
                let l = Layout { hosts: vec![host], masses_kg: vec![shot], clearances_mm: vec![d] };
                format!("{d}: {:.4}", evaluate(&problem, &b, &l).objective)
            })
            .collect();
        println!("m{} alone, by clearance (mm): {}", host + 1, row.join(", "));
    }
}
