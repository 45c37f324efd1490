//! Quasi-periodic points are recognised early (docs/simulator.md, "Steady state", step 6): on
//! Fig. 8's stated chain, where the beds' motion near 33-34 Hz has no stable periodic orbit,
//! a point on a torus ends well inside the budget with its reason stated, and its amplitudes
//! are as close to those of a long record (3000 periods after the whole budget) as the
//! budget's own ten periods are, or closer; a point that is not on a torus is left to the
//! budget.

use crate::common::paper;
use shotdamp::model::Clearance;
use std::f64::consts::PI;

use shotdamp::model::Damper;
use shotdamp::sim::settle::statistic::Measure;
use shotdamp::sim::settle::steady::{NoSteady, TORUS_TOL};
use shotdamp::sim::{steady_state, Dynamics, State, SteadyOptions, System};

fn system(hosts: &[usize]) -> System {
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::NO_TOP)).collect();
    System::plastic(paper(), dampers, 0, 2.6)
}

/// The largest difference of the masses' amplitudes, relative to the largest.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().copied().fold(0.0, f64::max);
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

#[test]
fn a_torus_ends_early_and_its_amplitudes_are_those_of_a_long_record() {
    let cases: [(&str, &[usize], &[f64]); 3] = [
        ("B", &[0], &[33.5, 33.6, 33.7, 33.8, 33.9, 34.0]),
        ("C", &[0, 1], &[33.3, 33.4]),
        ("D", &[0, 1, 2], &[32.9, 33.0, 33.1, 33.2, 33.3]),
    ];
    let (mut tori, mut early_error, mut budget_error, mut periods_spent) = (0, 0.0, 0.0, 0);
    for (case, hosts, freqs) in cases {
        let sys = system(hosts);
        for &f in freqs {
            let d = Dynamics::new(&sys, 2.0 * PI * f).unwrap();
            // The search's rule alone: no measurement of the motion after it (that is
            // tests/irregular.rs's).
            let search = SteadyOptions { measure: Measure::periods(0, 0.01), ..SteadyOptions::default() };
            let now = steady_state(&d, State::at_rest(&d), &search);
            let budget = steady_state(&d, State::at_rest(&d), &SteadyOptions { torus_attempts: 0, ..search });
            let long = steady_state(
                &d,
                State::at_rest(&d),
                &SteadyOptions { torus_attempts: 0, record_periods: 3000, ..search },
            );
            assert!(!now.converged && !long.converged, "{case} {f} Hz settled");
            let e = distance(&now.amplitude, &long.amplitude);
            // Two windows agree to TORUS_TOL; the long record's maxima can only be larger.
            assert!(e <= 2.0 * TORUS_TOL, "{case} {f} Hz: amplitudes {e:.4} from the long record's");
            if let Some(NoSteady::Torus { radius, angle, periods, .. }) = &now.failure {
                tori += 1;
                assert!(*radius > 1.0 && *radius <= 1.05 && *angle > 0.0 && *angle < PI, "{radius} {angle}");
                assert!(*periods <= 1500, "{case} {f} Hz: {periods} periods");
                assert_eq!(now.transient_periods, *periods);
                periods_spent += periods;
                early_error += e;
                budget_error += distance(&budget.amplitude, &long.amplitude);
            } else {
                // Not recognised: the budget's answer, unchanged.
                assert_eq!(now.amplitude, budget.amplitude, "{case} {f} Hz");
            }
        }
    }
    assert!(tori >= 8, "only {tori} points recognised as tori");
    // What the rule is for: the tori cost less than half the budget they spent before.
    assert!(2 * periods_spent <= tori * 1500, "{tori} tori took {periods_spent} periods");
    assert!(early_error <= budget_error, "tori: {early_error:.4} against the budget's {budget_error:.4}");
}

/// The rule's parts: the window is one turn of the torus, bounded.
#[test]
fn a_window_is_one_turn_of_the_torus() {
    use shotdamp::sim::settle::steady::{torus_window, TORUS_WINDOW_MAX};
    assert_eq!(torus_window(0.211, 1, 10), 30);
    assert_eq!(torus_window(0.211, 2, 10), 60);
    assert_eq!(torus_window(2.5, 1, 10), 10);
    assert_eq!(torus_window(1e-6, 1, 10), TORUS_WINDOW_MAX);
}
