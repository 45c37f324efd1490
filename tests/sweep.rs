//! Sweeps: bytes independent of the number of threads; continuation shows the coexisting
//! motions of the independent solver's reference.

use shotdamp::analysis::curves::{self, from_sweep};
use shotdamp::experiment::CurveId;
use shotdamp::model::Clearance;
use shotdamp::model::Damper;
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{SteadyOptions, System};
use shotdamp::table::to_csv;

fn system(hosts: &[usize], clearance: f64) -> System {
    let s = crate::common::paper();
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_m(clearance))).collect();
    System::plastic(s, dampers, 0, 2.6)
}

fn csv_with_threads(threads: usize) -> Vec<u8> {
    let sys = system(&[0, 1, 2], 0.2e-3);
    let freqs: Vec<f64> = (0..16).map(|i| 45.0 + 0.5 * i as f64).collect();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let points = pool.install(|| sweep::from_rest(&sys, &freqs, &SteadyOptions::default(), &|| {}));
    let curve = from_sweep(CurveId::whole("triple"), "triple", points, 2.6, &[1, 1, 1], 3);
    to_csv(&curves::table("t", "", &[&curve], 3, 3)).unwrap()
}

#[test]
fn sweep_bytes_do_not_depend_on_threads() {
    let one = csv_with_threads(1);
    let two = csv_with_threads(2);
    assert!(one.len() > 1000);
    assert_eq!(one, two);
}

#[test]
fn continuation_finds_both_motions_at_48_2_hz() {
    // reference/independent-solver/PROVENANCE.md: at 48.2 Hz, continued upward c1 = 8.08e-5
    // with one impact per period; from rest or continued downward c1 = 9.29e-5 with two
    // (its impact counts are bottom and top impacts together).
    let sys = system(&[1], 0.5e-3);
    let freqs: Vec<f64> = (0..=14).map(|i| ((47.6 + 0.2 * i as f64) * 1e9).round() / 1e9).collect();
    let opts = SteadyOptions::default();
    let up = sweep::continued(&sys, &freqs, Direction::Up, &opts, &|| {});
    let down = sweep::continued(&sys, &freqs, Direction::Down, &opts, &|| {});
    let at = |pts: &[sweep::SweepPoint]| {
        let p = pts.iter().find(|p| (p.freq_hz - 48.2).abs() < 1e-9).unwrap();
        let s = p.result.as_ref().unwrap();
        (s.amplitude[0] / 2.6, s.bottom_impacts[0] + s.top_impacts[0])
    };
    let (c_up, n_up) = at(&up);
    let (c_down, n_down) = at(&down);
    assert!((c_up - 8.0795045113e-05).abs() < 1e-3 * c_up, "up: {c_up}");
    assert!((c_down - 9.2922753813e-05).abs() < 1e-3 * c_down, "down: {c_down}");
    assert_eq!((n_up, n_down), (1.0, 2.0));
}

#[test]
fn orbit_continuation_across_the_fold_keeps_both_motions_and_the_unstable_one_between() {
    // Continued by pseudo-arclength downward from the orbit at 50.4 Hz, the branch passes
    // 48.2 Hz three times: the top-reaching motion (stable), the top-reaching orbit between the
    // fold and the graze of the top (unstable), and the bottom-only motion (stable); the stable
    // ones are the two motions of the continuation sweeps.
    let sys = system(&[1], 0.5e-3);
    let d = shotdamp::sim::Dynamics::new(&sys, 2.0 * std::f64::consts::PI * 50.4).unwrap();
    let st = shotdamp::sim::steady_state(&d, shotdamp::sim::State::at_rest(&d), &SteadyOptions::default());
    let b =
        shotdamp::analysis::branches::continue_orbit(CurveId::whole("b"), "b", &sys, 50.4, &st, false, (47.6, 50.4));
    let mut crossings = Vec::new();
    for i in 0..b.freq_hz.len() - 1 {
        let (f0, f1) = (b.freq_hz[i], b.freq_hz[i + 1]);
        if (f0 - 48.2) * (f1 - 48.2) < 0.0 {
            let w = (48.2 - f0) / (f1 - f0);
            let c = b.compliance[i][0] + w * (b.compliance[i + 1][0] - b.compliance[i][0]);
            crossings.push((c, b.stable[i] && b.stable[i + 1], !b.stable[i] && !b.stable[i + 1]));
        }
    }
    assert_eq!(crossings.len(), 3, "{crossings:?}");
    let (hi, mid, lo) = (crossings[0], crossings[1], crossings[2]);
    assert!(lo.1 && mid.2 && hi.1, "stable, unstable, stable: {crossings:?}");
    // Linear interpolation between branch points (steps <= 0.05 Hz) against the sweeps' values.
    assert!((lo.0 - 8.0795045113e-05).abs() < 2e-3 * lo.0, "bottom-only: {}", lo.0);
    assert!((hi.0 - 9.2922753813e-05).abs() < 2e-3 * hi.0, "top-reaching: {}", hi.0);
    assert!(mid.0 > lo.0 && mid.0 < hi.0);
    assert!(b
        .special
        .iter()
        .any(|s| matches!(s, shotdamp::sim::orbits::continuation::Special::Fold { p } if (p - 48.188).abs() < 2e-3)));
}
