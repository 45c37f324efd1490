//! Helpers shared by the end-to-end tests of the binary.

#![allow(dead_code)]

use shotdamp::model::Clearance;
use std::path::{Path, PathBuf};

use assert_cmd::Command;

/// The paper's chain (0.74, 0.71, 0.64 kg; 24.3, 21.8, 19.8 kN/m) with modal damping `zeta` in
/// every mode.
pub fn paper_with(zeta: f64) -> shotdamp::model::Structure {
    shotdamp::model::Structure::chain(
        &[0.74, 0.71, 0.64],
        &[24.3e3, 21.8e3, 19.8e3],
        shotdamp::model::Damping::ModalRatios(vec![zeta; 3]),
    )
}

/// The paper's chain with the modal damping the report assumes, 0.01 in every mode.
pub fn paper() -> shotdamp::model::Structure {
    paper_with(0.01)
}

/// The six-storey frame of `designs/six_storey.toml` (floors of 2 kg, the roof 1.5 kg;
/// storeys of 40 to 30 kN/m; modal damping 0.02) with all its shot, 1.15 kg, in a horizontal
/// container on the roof at 20 mm, 5 N on the roof at `freq_hz` (at 5.3 Hz a chaotic motion).
pub fn six_storey_roof(freq_hz: f64) -> shotdamp::sim::Dynamics {
    use shotdamp::model::{Damper, Damping, Direction, Structure};
    let frame = Structure::chain(
        &[2.0, 2.0, 2.0, 2.0, 2.0, 1.5],
        &[40e3, 38e3, 36e3, 34e3, 32e3, 30e3],
        Damping::ModalRatios(vec![0.02; 6]),
    );
    let bed = Damper::new(5, 1.15, Clearance::from_mm(20.0)).along(Direction::Horizontal);
    let sys = shotdamp::sim::System::plastic(frame, vec![bed], 5, 5.0);
    shotdamp::sim::Dynamics::new(&sys, 2.0 * std::f64::consts::PI * freq_hz).expect("the frame")
}

/// The repository.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The binary, run from the repository.
pub fn shotdamp() -> Command {
    let mut c = Command::cargo_bin("shotdamp").expect("binary");
    c.current_dir(repo());
    c
}

/// Copies the folder `from` into `to`, files and folders.
pub fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let target = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_tree(&p, &target);
        } else {
            std::fs::copy(&p, &target).unwrap();
        }
    }
}

/// Copies `experiments/shared` (the shared structure file and the model files) into
/// `exps/shared`.
pub fn copy_shared(exps: &Path) {
    let from = repo().join("experiments/shared");
    for sub in ["", "models"] {
        std::fs::create_dir_all(exps.join("shared").join(sub)).unwrap();
        for entry in std::fs::read_dir(from.join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                std::fs::copy(&path, exps.join("shared").join(sub).join(path.file_name().unwrap())).unwrap();
            }
        }
    }
}

/// An experiments folder in `dir` holding the shared structure and model files and copies of
/// `files` (names in `experiments/`).
pub fn experiments(dir: &Path, files: &[&str]) -> PathBuf {
    let exps = dir.join("experiments");
    copy_shared(&exps);
    for f in files {
        std::fs::copy(repo().join("experiments").join(f), exps.join(f)).unwrap();
    }
    exps
}

/// A 1000 kg table driven to amplitude A = Gamma g / omega^2 (10 Hz) with a 1 microgram bed
/// on it, restitution `e`; impacts slower than 1 mm/s stick (so that chattering ends; the
/// orbits of the tests hit at ~1 m/s).
pub fn bouncing_ball(gamma: f64, e: f64) -> Result<shotdamp::sim::Dynamics, shotdamp::sim::SetupError> {
    use shotdamp::model::{frf::receptance, Damper, Damping, Structure, GRAVITY};
    let omega = 2.0 * std::f64::consts::PI * 10.0;
    let host = Structure::chain(&[1000.0], &[1e6], Damping::ModalRatios(vec![0.05]));
    let h = receptance(&host, &host.mass_matrix(), 0, omega).expect("receptance")[0];
    let force = gamma * GRAVITY / (omega * omega) / h.norm();
    let sys = shotdamp::sim::System::plastic(host, vec![Damper::new(0, 1e-9, Clearance::NO_TOP)], 0, force)
        .with_law(shotdamp::sim::motion::bed::ImpactLaw::with_restitution(e, 1e-3));
    shotdamp::sim::Dynamics::new(&sys, omega)
}

/// Continuation settings of the bouncing-ball tests over `[p_min, p_max]` (Gamma).
pub fn ball_continuation(p_min: f64, p_max: f64) -> shotdamp::sim::orbits::continuation::ContinuationOptions {
    shotdamp::sim::orbits::continuation::ContinuationOptions {
        p_min,
        p_max,
        p_scale: 1.0,
        ds: 0.01,
        ds_min: 1e-6,
        ds_max: 0.02,
        max_points: 400,
        newton: shotdamp::sim::orbits::periodic::NewtonOptions::default(),
        parameter: shotdamp::sim::orbits::continuation::Parameter::Other,
    }
}

/// The rows of a CSV text (fields may be quoted, with commas inside), header first.
pub fn csv_rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .map(|line| {
            let mut fields = Vec::new();
            let mut field = String::new();
            let mut quoted = false;
            let mut chars = line.chars().peekable();
            while let Some(c) = chars.next() {
                match c {
                    '"' if quoted && chars.peek() == Some(&'"') => {
                        field.push('"');
                        chars.next();
                    }
                    '"' => quoted = !quoted,
                    ',' if !quoted => fields.push(std::mem::take(&mut field)),
                    c => field.push(c),
                }
            }
            fields.push(field);
            fields
        })
        .collect()
}

/// An experiment file `ID.toml` in the experiments folder of `dir` (see [`experiments`]) on the
/// paper's structure with the analysis `analysis` and one case `case` of Fig. 5's three
/// containers (mu = 0.1, d = 0.35 mm), each with its extra damper keys (e.g.
/// `", restitution = 0.5"`).
#[allow(dead_code)]
pub fn three_containers(dir: &Path, id: &str, analysis: &str, case: &str, keys: [&str; 3]) -> PathBuf {
    let exps = experiments(dir, &[]);
    let file = exps.join(format!("{id}.toml"));
    let dampers: String = keys
        .iter()
        .enumerate()
        .map(|(i, k)| format!("    {{ mass = {}, mass_ratio = 0.1, clearance_mm = 0.35{k} }},\n", i + 1))
        .collect();
    let text = format!(
        "extends = \"shared/paper_structure.toml\"\n[experiment]\nid = \"{id}\"\ntitle = \"t\"\nfigure = \"-\"\ncaption = \"c\"\nclaim = \"c\"\n[analysis]\n{analysis}\n[[cases]]\nid = \"{case}\"\nlabel = \"{case}\"\ndampers = [\n{dampers}]\n"
    );
    std::fs::write(&file, text).unwrap();
    file
}

/// A shipped file of the repository (`rel`), its records' paths (`../reference/ground-motions/`)
/// made absolute, with one replacement, written to a temporary `x.toml` and checked with
/// `shotdamp modal`: a bad key fails with code 2, names the file and has every word of
/// `expected`, without a panic.
pub fn records_file_fails_with(rel: &str, from: &str, to: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = std::fs::read_to_string(repo().join(rel)).unwrap();
    let text = text
        .replace("../reference/ground-motions/", &format!("{}/", repo().join("reference/ground-motions").display()));
    assert!(text.contains(from), "fixture text {from:?} not found");
    let path = dir.path().join("x.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    modal_refuses(&path, expected);
}

/// `shotdamp modal` refuses the file at `path` (named `x.toml`): code 2, the file named, every
/// word of `expected`, no panic.
pub fn modal_refuses(path: &Path, expected: &[&str]) {
    let out = shotdamp().arg("modal").arg(path).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(stderr.contains("x.toml"), "names the file: {stderr}");
    for e in expected {
        assert!(stderr.contains(e), "expected {e:?} in: {stderr}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}
