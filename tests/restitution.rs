//! Beds with restitution, chosen per container in the experiment file (docs/model.md section
//! 2): the file's law reaches the simulator for each container, the energy balance closes with
//! mixed laws, and bad values are input errors naming the key.

use crate::common;
use crate::common::paper;

use shotdamp::model::Clearance;
use std::f64::consts::PI;

use shotdamp::model::Damper;
use shotdamp::sim::motion::bed::ImpactLaw;
use shotdamp::sim::{settle::sweep, steady_state, Dynamics, State, SteadyOptions, System};

/// Fig. 5's three containers (d = 0.35 mm), the one on m2 with restitution keys `restitution`.
fn experiment_file(dir: &std::path::Path, restitution: &str) -> std::path::PathBuf {
    let analysis = "kind = \"sweep\"\nfreq_hz = { start = 46.0, stop = 50.0, step = 1.0 }";
    common::three_containers(dir, "bounce", analysis, "mixed", ["", restitution, ""])
}

#[test]
fn each_containers_law_reaches_the_simulator() {
    let dir = tempfile::tempdir().unwrap();
    let file = experiment_file(dir.path(), ", restitution = 0.5, stick_speed_m_s = 0.002");
    let exps = shotdamp::experiment::loader::load(&file, &common::repo().join("reference")).unwrap();
    let exp = exps.iter().find(|e| e.model.as_ref().is_none_or(|m| m.id == "stated")).unwrap();
    let case = &exp.cases[0];
    let bounce = ImpactLaw::with_restitution(0.5, 0.002);
    assert_eq!(case.laws(), vec![ImpactLaw::PLASTIC, bounce, ImpactLaw::PLASTIC]);

    // The experiment's system is the structure with those laws, bed by bed.
    let m = [0.74, 0.71, 0.64];
    let dampers: Vec<Damper> = (0..3).map(|h| Damper::new(h, 0.1 * m[h], Clearance::from_m(0.35e-3))).collect();
    let mut by_hand = System::plastic(paper(), dampers, 0, 2.6);
    by_hand.laws = vec![ImpactLaw::PLASTIC, bounce, ImpactLaw::PLASTIC];
    let freqs = [46.0, 48.0, 50.0];
    let opts = SteadyOptions::default();
    let direct = sweep::from_rest(&by_hand, &freqs, &opts, &|| {});
    let plastic = sweep::from_rest(&System { laws: Vec::new(), ..by_hand.clone() }, &freqs, &opts, &|| {});
    let via_file = sweep::from_rest(&shotdamp::analysis::curves::system(exp, case), &freqs, &opts, &|| {});
    let mut moved = 0.0f64;
    for ((a, b), p) in direct.iter().zip(&via_file).zip(&plastic) {
        let (a, b, p) = (a.result.as_ref().unwrap(), b.result.as_ref().unwrap(), p.result.as_ref().unwrap());
        assert_eq!(a.amplitude, b.amplitude);
        moved = moved.max((a.amplitude[1] - p.amplitude[1]).abs() / p.amplitude[1]);
    }
    // The law matters: a bouncing bed is not the plastic one.
    assert!(moved > 1e-3, "{moved}");
}

#[test]
fn the_energy_balance_closes_with_mixed_laws() {
    let m = [0.74, 0.71, 0.64];
    let dampers: Vec<Damper> = (0..3).map(|h| Damper::new(h, 0.1 * m[h], Clearance::from_m(0.35e-3))).collect();
    let mut sys = System::plastic(paper(), dampers, 0, 2.6);
    sys.laws = vec![ImpactLaw::with_restitution(0.3, 1e-3), ImpactLaw::PLASTIC, ImpactLaw::with_restitution(0.6, 1e-3)];
    for f in [44.0, 48.0, 52.0] {
        let d = Dynamics::new(&sys, 2.0 * PI * f).unwrap();
        let st = steady_state(&d, State::at_rest(&d), &SteadyOptions { energy: true, ..SteadyOptions::default() });
        let e = st.energy.unwrap();
        assert!(e.impact > 0.0 && e.relative_residual() < 1e-9, "{f} Hz: {e:?}");
    }
}

#[test]
fn bad_laws_are_input_errors_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (law, key) in [
        (", restitution = 1.0", "cases[0].dampers[1].restitution"),
        (", restitution = -0.1", "cases[0].dampers[1].restitution"),
        (", stick_speed_m_s = 0.001", "cases[0].dampers[1].stick_speed_m_s"),
        (", restitution = 0.5, stick_speed_m_s = 0.0", "cases[0].dampers[1].stick_speed_m_s"),
    ] {
        let file = experiment_file(dir.path(), law);
        let out = common::shotdamp()
            .args(["run", file.to_str().unwrap(), "--out"])
            .arg(dir.path().join("o"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{law}: {err}");
        assert!(err.contains(key), "{law}: {err}");
    }
}
