//! The bed as a column of grains (docs/model.md, "Bed models"): a plastic column is the
//! paper's single mass, a one-grain column is the single bed with the same restitution, every
//! joule is accounted for, and a column dropped into its container comes to rest after a
//! bounded number of events.

use crate::common;
use crate::common::paper;

use shotdamp::model::Clearance;
use std::f64::consts::PI;

use shotdamp::model::Damper;
use shotdamp::sim::motion::bed::ImpactLaw;
use shotdamp::sim::{steady_state, Dynamics, Engine, EventKind, Quiet, State, SteadyMethod, SteadyOptions, System};

/// Fig. 5's containers: mu = 0.1 on the masses given, clearance `d` m.
fn fig5(hosts: &[usize], d: f64) -> System {
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_m(d))).collect();
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
fn a_plastic_column_is_the_single_plastic_mass_on_fig8s_band_without_a_top() {
    // Fig. 8's case D (three beds, d = inf) over its band, both by the transient method (a
    // column always is): the records' amplitudes agree to 1e-9 of the largest.
    let single = fig5(&[0, 1, 2], f64::INFINITY);
    let column = single.clone().with_grains(&[10, 10, 10]);
    let opts = transient();
    let freqs: Vec<f64> = (0..27).map(|i| 8.0 + 2.0 * i as f64).collect();
    let a = shotdamp::sim::settle::sweep::from_rest(&single, &freqs, &opts, &|| {});
    let b = shotdamp::sim::settle::sweep::from_rest(&column, &freqs, &opts, &|| {});
    for (p, q) in a.iter().zip(&b) {
        let (s, c) = (p.result.as_ref().unwrap(), q.result.as_ref().unwrap());
        let scale = s.amplitude.iter().copied().fold(0.0, f64::max);
        let apart = s.amplitude.iter().zip(&c.amplitude).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        assert!(apart <= 1e-9 * scale, "{} Hz: {:?} vs {:?}", p.freq_hz, s.amplitude, c.amplitude);
    }
}

#[test]
fn a_column_of_one_grain_is_the_single_bed_with_its_restitution() {
    for e in [0.0, 0.3, 0.6] {
        let law = ImpactLaw::with_restitution(e, 1e-3);
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
        let (lo, hi) = (s.x[host], s.x[host] + d.system.dampers[c.start].clearance.m());
        let tol = 1e-12;
        y.windows(2).all(|w| w[1] >= w[0] - tol) && y.iter().all(|&v| v >= lo - tol && v <= hi + tol)
    })
}

#[test]
fn a_column_keeps_its_order_and_every_joule_is_accounted_for() {
    use shotdamp::sim::motion::observe::stored_energy;
    for (e, n) in [(0.3, 10), (0.6, 4), (0.9, 20)] {
        let law = ImpactLaw::with_restitution(e, 1e-3);
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
        let law = ImpactLaw::with_restitution(e, 1e-3);
        let base = System::plastic(paper(), vec![Damper::new(2, 0.064, Clearance::from_m(1e-3))], 0, 0.0);
        let sys = base.with_law(law).with_grains(&[n]);
        let d = Dynamics::new(&sys, 2.0 * PI * 10.0).unwrap();
        let x = d.config(0).modes.offset.clone();
        let drop = x[2] + 0.3e-3;
        let beds = vec![shotdamp::sim::Bed::Free { t0: 0.0, y0: drop, u0: 0.0 }; sys.dampers.len()];
        let mut s = State { t: 0.0, x: x.clone(), v: nalgebra::DVector::zeros(3), beds };
        let e0 = shotdamp::sim::motion::observe::stored_energy(&d, &s);
        let mut ledger = Ledger { events: Vec::new(), order_kept: true };
        let mut energy = shotdamp::sim::motion::observe::Energy::default();
        let engine = Engine::new(&d);
        let mut rest_at = None;
        for k in 1..=200 {
            engine
                .advance(&mut s, k as f64 * 0.01, &mut shotdamp::sim::motion::observe::Both(&mut ledger, &mut energy))
                .unwrap();
            ledger.order_kept &= ordered(&d, &s);
            if rest_at.is_none() && s.beds.iter().all(|b| *b == shotdamp::sim::Bed::Bottom) {
                rest_at = Some(s.t);
            }
        }
        let events = ledger.events.len();
        // Bounces (at the sticking speed or faster) lose at least (1 - e^2) m_g v_s^2 / 4 each;
        // a grain sticks at most once more than it was separated (n at the start, one per
        // bounce): events <= n + 2 E / ((1 - e^2) m_g v_s^2 / 4) for the fall energy E.
        let m_g = 0.064 / n as f64;
        let fall = m_g * n as f64 * 9.80665 * 0.3e-3;
        let bound = n + 2 * (fall / ((1.0 - e * e) * m_g * 1e-6 / 4.0)).ceil() as usize;
        let e1 = shotdamp::sim::motion::observe::stored_energy(&d, &s);
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

/// An experiment file with the given analysis and damper keys (the paper's three containers).
fn experiment_file(dir: &std::path::Path, analysis: &str, keys: &str) -> std::path::PathBuf {
    common::three_containers(dir, "grains", analysis, "triple", [keys; 3])
}

const SWEEP: &str = r#"kind = "sweep"
freq_hz = { start = 47.0, stop = 49.0, step = 1.0 }"#;

#[test]
fn a_column_in_an_experiment_file_is_the_column_of_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let file = experiment_file(dir.path(), SWEEP, r#", bed = "column", grains = 4, restitution = 0.3"#);
    let exps = shotdamp::experiment::loader::load(&file, &common::repo().join("reference")).unwrap();
    let exp = exps.iter().find(|e| e.model.as_ref().is_none_or(|m| m.id == "stated")).unwrap();
    assert_eq!(exp.cases[0].grains(), vec![4, 4, 4]);
    let sys = shotdamp::analysis::curves::system(exp, &exp.cases[0]);
    let by_hand = fig5(&[0, 1, 2], 0.35e-3).with_law(ImpactLaw::with_restitution(0.3, 1e-3)).with_grains(&[4, 4, 4]);
    assert_eq!(sys.dampers, by_hand.dampers);
    assert_eq!(sys.columns, by_hand.columns);
    assert_eq!(sys.laws, by_hand.laws);
    // The sweep's table has one set of impact columns per container, not per grain.
    let out =
        common::shotdamp().args(["run", file.to_str().unwrap(), "--out"]).arg(dir.path().join("o")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.path().join("o/grains/stated/data/compliance.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.contains("impacts_per_period_d3") && !header.contains("impacts_per_period_d4"), "{header}");
}

#[test]
fn bad_bed_models_are_input_errors_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, analysis, key) in [
        (r#", bed = "sand""#, SWEEP, "cases[0].dampers[0].bed"),
        (r#", grains = 0"#, SWEEP, "cases[0].dampers[0].grains"),
        (r#", grains = 2.5"#, SWEEP, "cases[0].dampers[0].grains"),
        (r#", grains = 61"#, SWEEP, "cases[0].dampers[0].grains"),
        (r#", bed = "column""#, SWEEP, "cases[0].dampers[0].grains"),
        (r#", bed = "plastic", restitution = 0.3"#, SWEEP, "cases[0].dampers[0].restitution"),
        (r#", bed = "restitution""#, SWEEP, "cases[0].dampers[0].restitution"),
        (r#", bed = "plastic", grains = 3"#, SWEEP, "cases[0].dampers[0].grains"),
        (
            r#", grains = 3"#,
            "kind = \"sweep\"\nstart = \"continuation\"\nfreq_hz = { start = 47.0, stop = 49.0, step = 1.0 }",
            "cases[0].dampers[0].grains",
        ),
    ] {
        let file = experiment_file(dir.path(), analysis, keys);
        let out = common::shotdamp()
            .args(["run", file.to_str().unwrap(), "--out"])
            .arg(dir.path().join("o"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{keys}: {err}");
        assert!(err.contains(key) && err.contains("grains.toml"), "{keys}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn waveforms_show_every_grain_and_the_events_name_it() {
    let dir = tempfile::tempdir().unwrap();
    let analysis = "kind = \"waveform\"\nfrequencies_hz = [48.5]\nlabels = [\"b\"]\nperiods = 1";
    let file = experiment_file(dir.path(), analysis, r#", grains = 3, restitution = 0.3"#);
    let out =
        common::shotdamp().args(["run", file.to_str().unwrap(), "--out"]).arg(dir.path().join("o")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let data = dir.path().join("o/grains/stated/data");
    let waves = std::fs::read_to_string(data.join("waveforms.csv")).unwrap();
    let header = waves.lines().next().unwrap();
    assert!(header.contains("y9") && header.contains("state9") && !header.contains("y10"), "{header}");
    let events = common::csv_rows(&std::fs::read_to_string(data.join("events.csv")).unwrap());
    let head = &events[0];
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let (bed, container, grain, kind) = (col("bed"), col("container"), col("grain"), col("kind"));
    assert!(events[1..].iter().any(|r| r[kind].starts_with("hits grain")), "no grain-grain collision drawn");
    for r in &events[1..] {
        let b: usize = r[bed].parse().unwrap();
        assert_eq!(r[container], ((b - 1) / 3 + 1).to_string());
        assert_eq!(r[grain], ((b - 1) % 3 + 1).to_string());
    }
}

#[test]
fn a_motion_that_never_settles_gets_a_long_record_whose_halves_are_compared() {
    use shotdamp::sim::motion::observe::Extrema;
    use shotdamp::sim::settle::long_record::{extend, LONG_RECORD_PERIODS};
    use shotdamp::sim::settle::steady::NoSteady;
    // One bouncing mass per container, stopped before it can settle (30 periods).
    let sys = fig5(&[0, 1, 2], 0.35e-3).with_law(ImpactLaw::with_restitution(0.5, 1e-3));
    let d = Dynamics::new(&sys, 2.0 * PI * 48.5).unwrap();
    let short = SteadyOptions { max_periods: 30, min_periods: 25, ..transient() };
    let st = shotdamp::sim::settle::transient::transient_steady(&d, State::at_rest(&d), &short);
    assert!(!st.converged);
    let long = extend(&d, st.clone());
    let Some(NoSteady::Aperiodic { periods, spread, after }) = long.failure.clone() else {
        panic!("expected an aperiodic point: {:?}", long.failure)
    };
    assert_eq!((periods, after, long.recorded_periods), (LONG_RECORD_PERIODS, 30, LONG_RECORD_PERIODS));
    assert!(!long.converged);
    // The same record run again: the whole record's amplitudes, and its second half's.
    let period = 2.0 * PI / d.omega;
    let mut s = st.final_state.clone();
    let t0 = s.t;
    let engine = Engine::new(&d);
    let mut whole = Extrema::new(3, 3);
    engine.advance(&mut s, t0 + 100.0 * period, &mut whole).unwrap();
    let mut second = Extrema::new(3, 3);
    engine.advance(&mut s, t0 + 200.0 * period, &mut second).unwrap();
    let (a, b) = (long.amplitude.clone(), second.amplitudes());
    let scale = a.iter().copied().fold(0.0, f64::max);
    let again = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale;
    assert!((again - spread).abs() < 1e-12, "{again} vs {spread}");
    for i in 0..3 {
        assert!(a[i] >= b[i] && a[i] >= 0.5 * (whole.max[i] - whole.min[i]) - 1e-15);
    }
    // The paper's plastic bed keeps its record.
    let plastic = fig5(&[0, 1, 2], 0.35e-3);
    let dp = Dynamics::new(&plastic, 2.0 * PI * 48.5).unwrap();
    let sp = shotdamp::sim::settle::transient::transient_steady(&dp, State::at_rest(&dp), &short);
    let kept = extend(&dp, sp.clone());
    assert_eq!(kept.amplitude, sp.amplitude);
    assert_eq!(kept.recorded_periods, sp.recorded_periods);
}

#[test]
fn an_impulse_decay_with_columns_accounts_for_every_joule_and_a_plastic_column_is_the_single_mass() {
    use shotdamp::sim::motion::impulse::{free_response, ImpulseOptions, Kick};
    let opts = ImpulseOptions { mass: 0, kick: Kick::Velocity(0.5), duration: 0.5, dt: 1e-3 };
    for (e, n) in [(0.0, 10), (0.3, 10), (0.6, 5)] {
        let sys = fig5(&[0, 1, 2], 0.35e-3).with_law(ImpactLaw::with_restitution(e, 1e-3)).with_grains(&[n, n, n]);
        let run = free_response(&sys, &opts).unwrap();
        assert!(run.stop.is_none(), "e = {e}: {:?}", run.stop);
        let residual = run.energy_residual();
        println!("e = {e}, n = {n}: {} events, energy residual {residual:.1e}", run.samples.events.len());
        assert!(residual < 1e-9, "e = {e}, n = {n}: {residual:e}");
        if e == 0.0 {
            // The plastic column's history is the single plastic mass's.
            let single = free_response(&fig5(&[0, 1, 2], 0.35e-3), &opts).unwrap();
            let scale = single.samples.x.iter().flat_map(|x| x.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
            let apart = run
                .samples
                .x
                .iter()
                .zip(&single.samples.x)
                .flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| (p - q).abs()))
                .fold(0.0, f64::max);
            assert!(apart < 1e-9 * scale, "plastic column vs single mass: {apart:e} of {scale:e}");
        }
    }
}
