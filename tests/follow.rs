//! Continuation sweeps that follow certified orbits (`steady.follow`, the default of designs)
//! against the same sweeps without it (each point from the previous point's final state by
//! the transient search): the same orbits, to 1e-9, at every point of Fig. 5's band, across
//! the fold of its hysteresis and the clearances where the beds stop reaching the top, and
//! across the grazes where a followed orbit's events per cycle change (a bed starts or stops
//! lifting off or reaching the top).

use crate::common::paper_with as paper;
use shotdamp::design::{bare, evaluate, Band, Combine, Layout, Measure, Problem, Sweep};
use shotdamp::model::Clearance;
use shotdamp::model::Damper;
use shotdamp::sim::settle::sweep::{continued, Direction};
use shotdamp::sim::{SteadyOptions, System};

fn band() -> Vec<f64> {
    (0..=48).map(|i| 44.0 + 0.25 * i as f64).collect()
}

/// Compares the two sweeps point by point; returns how many points were followed, and how
/// many of those have other events per cycle than the point before them.
fn same_sweeps(sys: &System, dir: Direction) -> (usize, usize) {
    let plain = SteadyOptions::default();
    let follow = SteadyOptions { follow: true, ..plain };
    let a = continued(sys, &band(), dir, &plain, &|| {});
    let b = continued(sys, &band(), dir, &follow, &|| {});
    let mut followed = 0;
    let mut grazes = 0;
    let mut before: Option<&shotdamp::sim::Steady> = None;
    for (p, q) in a.iter().zip(&b) {
        assert_eq!(p.freq_hz, q.freq_hz);
        let (p, q) = (p.result.as_ref().unwrap(), q.result.as_ref().unwrap());
        assert_eq!(p.converged, q.converged, "{} Hz", p.omega / std::f64::consts::TAU);
        assert_eq!(p.period, q.period);
        for (x, y) in p.amplitude.iter().zip(&q.amplitude) {
            assert!((x - y).abs() <= 1e-9 * x.abs().max(1e-12), "{} Hz: {x} vs {y}", p.omega / std::f64::consts::TAU);
        }
        if q.converged && q.transient_periods == 0 {
            followed += 1;
            let (cp, cq) = (p.certificate.as_ref().unwrap(), q.certificate.as_ref().unwrap());
            assert!(cq.stable && cq.residual < 1e-11);
            assert_eq!(cp.pattern, cq.pattern);
            for (m, n) in cp.multipliers.iter().zip(&cq.multipliers) {
                assert!((m - n).norm() <= 1e-6, "multipliers {m} vs {n}");
            }
            if before.and_then(|s| s.certificate.as_ref()).is_some_and(|c| c.pattern != cq.pattern) {
                grazes += 1;
            }
        }
        before = Some(q);
    }
    (followed, grazes)
}

#[test]
fn followed_sweeps_equal_the_transient_search_on_fig05s_band() {
    let (mut followed, mut grazes) = (0, 0);
    for (zeta, clearance_mm, hosts) in
        [(0.01, 0.3, vec![0, 1, 2]), (0.005, 0.3, vec![0, 1, 2]), (0.01, 1.0, vec![0, 1, 2]), (0.01, 0.2, vec![1])]
    {
        let masses = [0.74, 0.71, 0.64];
        let dampers: Vec<Damper> =
            hosts.iter().map(|&h| Damper::new(h, 0.1 * masses[h], Clearance::from_m(clearance_mm * 1e-3))).collect();
        let sys = System::plastic(paper(zeta), dampers, 0, 2.6);
        for dir in [Direction::Up, Direction::Down] {
            let (f, g) = same_sweeps(&sys, dir);
            followed += f;
            grazes += g;
        }
    }
    // Most points are followed (the fast path is taken, not skipped), some of them across a
    // graze.
    assert!(followed > 8 * 49 / 2, "{followed} of {} points followed", 8 * 49);
    assert!(grazes >= 10, "{grazes} followed points across a graze");
}

/// The same comparison through the design objective, over Fig. 8's three windows with every
/// mass counted (what `designs/all_modes.toml` evaluates): for the paper's layout at three
/// clearances and the best three-container layout the all-modes search stored (rounded),
/// whose points all settle, the followed sweeps give every band's peak of the transient
/// search's to 1e-9.
#[test]
fn followed_design_evaluations_equal_the_transient_search_over_three_modes() {
    let grid = |a: f64, b: f64| (0..).map(move |i| a + 0.5 * i as f64).take_while(move |f| *f <= b + 1e-9).collect();
    let problem = |follow: bool| Problem {
        structure: paper(0.01),
        driven: 0,
        force: 2.6,
        bands: [(10.0, 16.0), (30.0, 40.0), (44.0, 56.0)]
            .iter()
            .map(|&(a, b)| Band { name: format!("{a}-{b} Hz"), freq_hz: grid(a, b), masses: vec![0, 1, 2] })
            .collect(),
        measure: Measure::Peak,
        sweeps: vec![Sweep::Up, Sweep::Down],
        steady: SteadyOptions { follow, max_periods: 500, ..SteadyOptions::default() },
        scenarios: Vec::new(),
        combine: Combine::Worst,
        direction: shotdamp::model::Direction::Vertical,
        supports: false,
        suite: None,
    };
    let (followed, plain) = (problem(true), problem(false));
    let b = bare(&plain);
    let paper_at =
        |d: f64| Layout { hosts: vec![0, 1, 2], masses_kg: vec![0.074, 0.071, 0.064], clearances_mm: vec![d; 3] };
    let layouts = [
        paper_at(0.2),
        paper_at(0.35),
        paper_at(0.5),
        Layout {
            hosts: vec![0, 1, 2],
            masses_kg: vec![0.016333, 0.112588, 0.080079],
            clearances_mm: vec![2.484838; 3],
        },
    ];
    for l in &layouts {
        let (f, p) = (evaluate(&followed, &b, l), evaluate(&plain, &b, l));
        // Layouts chosen with every point settled (a point that never settles is a record of a
        // motion that does not repeat: docs/design.md, "Reproducibility").
        assert_eq!((f.unsettled, p.unsettled), (0, 0), "{:?}", l.hosts);
        for (x, y) in f.bands.iter().zip(&p.bands) {
            assert!((x - y).abs() <= 1e-9 * y.abs(), "{:?}: {x} followed, {y} by the transient search", l.hosts);
        }
    }
}
