//! The bed as a column of grains (docs/model.md, "Bed models"): a plastic column is the
//! paper's single mass, a one-grain column is the single bed with the same restitution, every
//! joule is accounted for, and a column dropped into its container comes to rest after a
//! bounded number of events.

use std::f64::consts::PI;

use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::bed::ImpactLaw;
use shotdamp::sim::{steady_state, Dynamics, Engine, EventKind, Quiet, State, SteadyMethod, SteadyOptions, System};

fn paper() -> Structure {
    Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]))
}

/// Fig. 5's containers: mu = 0.1 on the masses given, clearance `d` m.
fn fig5(hosts: &[usize], d: f64) -> System {
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&h| Damper { host: h, mass: 0.1 * m[h], clearance: d }).collect();
    System::plastic(paper(), dampers, 0, 2.6)
}

fn transient() -> SteadyOptions {
    SteadyOptions { method: SteadyMethod::Transient, record_periods: 10, ..SteadyOptions::default() }
}

#[test]
fn a_plastic_column_is_the_single_plastic_mass() {
    for hosts in [vec![2], vec![0, 1, 2]] {
        let single = fig5(&hosts, 0.35e-3);
        let column = single.clone().with_grains(&vec![5; hosts.len()]);
        let (ds, dc) = (Dynamics::unforced(&single).unwrap(), Dynamics::unforced(&column).unwrap());
        for f in [40.0, 44.0, 47.0, 50.0, 54.0] {
            let w = 2.0 * PI * f;
            let a = steady_state(&ds.at_omega(w).unwrap(), State::at_rest(&ds.at_omega(w).unwrap()), &transient());
            let b = steady_state(&dc.at_omega(w).unwrap(), State::at_rest(&dc.at_omega(w).unwrap()), &transient());
            for i in 0..3 {
                let rel = (a.amplitude[i] - b.amplitude[i]).abs() / a.amplitude[i];
                println!("{hosts:?} {f} Hz m{}: {:.6e} vs {:.6e} rel {rel:.1e}", i + 1, a.amplitude[i], b.amplitude[i]);
                assert!(rel < 1e-9, "{hosts:?} {f} Hz m{}: {} vs {}", i + 1, a.amplitude[i], b.amplitude[i]);
            }
        }
    }
}

/// Bed `j` of `sys` as a column of one grain (the column code path, one grain).
fn one_grain_columns(mut sys: System) -> System {
    sys.columns = (0..sys.dampers.len()).map(|j| j..j + 1).collect();
    sys
}

#[test]
fn a_column_of_one_grain_is_the_single_bed_with_its_restitution() {
    for e in [0.0, 0.3, 0.6] {
        let law = ImpactLaw { restitution: e, stick_speed: if e > 0.0 { 1e-3 } else { 0.0 } };
        let single = fig5(&[0, 1, 2], 0.35e-3).with_law(law);
        let column = one_grain_columns(single.clone());
        for f in [44.0, 47.0, 50.0] {
            let ds = Dynamics::new(&single, 2.0 * PI * f).unwrap();
            let dc = Dynamics::new(&column, 2.0 * PI * f).unwrap();
            let mut a = State::at_rest(&ds);
            let mut b = State::at_rest(&dc);
            Engine::new(&ds).advance(&mut a, 40.0 / f, &mut Quiet).unwrap();
            Engine::new(&dc).advance(&mut b, 40.0 / f, &mut Quiet).unwrap();
            let dist = (&a.x - &b.x).amax() / a.x.amax();
            assert!(dist < 1e-9, "e = {e}, {f} Hz: 40 periods apart by {dist:.1e}");
        }
    }
}

/// Every event of a run with its losses, and the stored energy at both ends.
struct Ledger {
    events: Vec<shotdamp::sim::Event>,
    order_kept: bool,
}

impl shotdamp::sim::Observer for Ledger {
    fn event(&mut self, ev: &shotdamp::sim::Event, after: &State) {
        self.events.push(*ev);
        let _ = after;
    }
}

fn ordered(d: &Dynamics, s: &State) -> bool {
    d.system.columns.iter().all(|c| {
        let y: Vec<f64> = c.clone().map(|j| s.bed_motion(d, j).0).collect();
        let host = d.system.dampers[c.start].host;
        let (lo, hi) = (s.x[host], s.x[host] + d.system.dampers[c.start].clearance);
        let tol = 1e-12;
        y.windows(2).all(|w| w[1] >= w[0] - tol) && y.iter().all(|&v| v >= lo - tol && v <= hi + tol)
    })
}

#[test]
fn a_column_keeps_its_order_and_every_joule_is_accounted_for() {
    use shotdamp::sim::observe::stored_energy;
    for (e, n) in [(0.3, 10), (0.6, 4), (0.9, 20)] {
        let law = ImpactLaw { restitution: e, stick_speed: 1e-3 };
        let sys = fig5(&[0, 1, 2], 0.35e-3).with_law(law).with_grains(&[n, n, n]);
        let f = 47.0;
        let d = Dynamics::new(&fig5(&[0, 1, 2], 0.35e-3), 2.0 * PI * f).and_then(|_| Dynamics::new(&sys, 2.0 * PI * f));
        let d = d.unwrap();
        let mut s = State::at_rest(&d);
        let engine = Engine::new(&d);
        // Run in pieces, checking order, and integrate the energy balance on the last periods.
        let mut ledger = Ledger { events: Vec::new(), order_kept: true };
        for k in 1..=30 {
            engine.advance(&mut s, k as f64 / f, &mut ledger).unwrap();
            ledger.order_kept &= ordered(&d, &s);
        }
        assert!(ledger.order_kept, "e = {e}, n = {n}: grains out of order or outside the container");
        let collisions = ledger.events.iter().filter(|ev| matches!(ev.kind, EventKind::Collision { .. })).count();
        assert!(collisions > 0, "e = {e}, n = {n}: no grain-grain collision in 30 periods");
        let st = steady_state(
            &d,
            s.clone(),
            &SteadyOptions { energy: true, max_periods: 20, min_periods: 1, ..transient() },
        );
        let bal = st.energy.unwrap();
        println!(
            "e = {e}, n = {n}: {collisions} collisions; work {:.4e} J, viscous {:.4e}, impact {:.4e}, stored {:.1e}, residual {:.1e}",
            bal.work,
            bal.viscous,
            bal.impact,
            bal.stored_change,
            bal.relative_residual()
        );
        assert!(bal.relative_residual() < 1e-9, "e = {e}, n = {n}: {bal:?}");
        let _ = stored_energy(&d, &s);
    }
}

#[test]
fn a_column_dropped_into_a_resting_container_comes_to_rest_after_a_bounded_number_of_events() {
    // The paper's structure at rest, no force; a column of n grains released together 0.3 mm
    // above the bottom of the container on m3 (clearance 1 mm).
    for &(n, e) in &[(1, 0.9), (3, 0.9), (20, 0.1), (20, 0.5), (20, 0.9)] {
        let law = ImpactLaw { restitution: e, stick_speed: 1e-3 };
        let base = System::plastic(paper(), vec![Damper { host: 2, mass: 0.064, clearance: 1e-3 }], 0, 0.0);
        let sys = base.with_law(law).with_grains(&[n]);
        let d = Dynamics::new(&sys, 2.0 * PI * 10.0).unwrap();
        let x = d.config(0).modes.offset.clone();
        let drop = x[2] + 0.3e-3;
        let beds = vec![shotdamp::sim::Bed::Free { t0: 0.0, y0: drop, u0: 0.0 }; sys.dampers.len()];
        let mut s = State { t: 0.0, x: x.clone(), v: nalgebra::DVector::zeros(3), beds };
        let e0 = shotdamp::sim::observe::stored_energy(&d, &s);
        let mut ledger = Ledger { events: Vec::new(), order_kept: true };
        let mut energy = shotdamp::sim::observe::Energy::default();
        let engine = Engine::new(&d);
        let mut rest_at = None;
        for k in 1..=200 {
            engine
                .advance(&mut s, k as f64 * 0.01, &mut shotdamp::sim::observe::Both(&mut ledger, &mut energy))
                .unwrap();
            ledger.order_kept &= ordered(&d, &s);
            if rest_at.is_none() && s.beds.iter().all(|b| *b == shotdamp::sim::Bed::Bottom) {
                rest_at = Some(s.t);
            }
        }
        let events = ledger.events.len();
        // Impacts at the sticking speed or faster lose at least (1 - e^2) m_g v_s^2 / 4 each.
        let m_g = 0.064 / n as f64;
        let fall = m_g * n as f64 * 9.80665 * 0.3e-3;
        let bound = 2 * n + (fall / ((1.0 - e * e) * m_g * 1e-6 / 4.0)).ceil() as usize;
        let e1 = shotdamp::sim::observe::stored_energy(&d, &s);
        let residual = (e0 - e1 - energy.viscous - energy.impact).abs() / (e0 - e1);
        println!(
            "n = {n}, e = {e}: at rest after {:?} s, {events} events (bound {bound}); balance {residual:.1e}",
            rest_at
        );
        assert!(ledger.order_kept);
        assert!(rest_at.is_some_and(|t| t < 1.0), "n = {n}, e = {e}: not at rest after 2 s");
        assert!(events <= bound, "n = {n}, e = {e}: {events} events > {bound}");
        assert!(residual < 1e-9, "n = {n}, e = {e}: energy balance {residual:.1e}");
    }
}
