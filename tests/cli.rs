//! The binary end to end: bad input gives a clear message and exit code 2; a valid set
//! gives a report whose links all resolve.

use crate::common;

use std::path::{Path, PathBuf};

use common::{experiments, repo, shotdamp};

/// A copy of the Fig. 4(b) file with one replacement, in a temporary folder that also
/// holds the shared structure file.
fn variant(from: &str, to: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("tempdir");
    common::copy_shared(dir.path());
    let text = std::fs::read_to_string(repo().join("experiments/fig04b_no_damper.toml")).unwrap();
    assert!(text.contains(from), "fixture text {from:?} not found");
    let path = dir.path().join("x.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    (dir, path)
}

fn fails_with(from: &str, to: &str, expected: &[&str]) {
    let (_dir, path) = variant(from, to);
    super::common::modal_refuses(&path, expected);
}

#[test]
fn toml_syntax_error_shows_line_and_column() {
    fails_with("kind = \"linear_frf\"", "kind = \"linear_frf", &["TOML syntax error", "line"]);
}

#[test]
fn unknown_key_is_named() {
    fails_with(
        "kind = \"linear_frf\"",
        "kind = \"linear_frf\"\nfrequency = 3",
        &["analysis", "unknown field `frequency`"],
    );
}

#[test]
fn negative_mass() {
    fails_with(
        "[analysis]",
        "[structure]\nmasses_kg = [0.74, 0.71, -0.64]\n\n[analysis]",
        &["structure.masses_kg[2] = -0.64", "positive"],
    );
}

#[test]
fn zero_mass() {
    fails_with(
        "[analysis]",
        "[structure]\nmasses_kg = [0.0, 0.71, 0.64]\n\n[analysis]",
        &["structure.masses_kg[0] = 0", "positive"],
    );
}

#[test]
fn zero_stiffness() {
    fails_with(
        "[analysis]",
        "[structure]\nchain_stiffness_n_per_m = [24.3e3, 0.0, 19.8e3]\n\n[analysis]",
        &["chain_stiffness_n_per_m[1] = 0", "positive"],
    );
}

#[test]
fn reversed_frequency_range() {
    fails_with(
        "start = 2.0, stop = 60.0",
        "start = 60.0, stop = 2.0",
        &["analysis.freq_hz.stop = 2", "greater than start"],
    );
}

#[test]
fn damper_on_missing_mass() {
    fails_with(
        "dampers = []",
        "dampers = [{ mass = 4, mass_ratio = 0.1, clearance_mm = \"inf\" }]",
        &["cases[0].dampers[0].mass = 4", "1 to 3"],
    );
}

#[test]
fn negative_clearance() {
    fails_with(
        "dampers = []",
        "dampers = [{ mass = 1, mass_ratio = 0.1, clearance_mm = -1.0 }]",
        &["cases[0].dampers[0].clearance_mm = -1", ">= 0"],
    );
}

#[test]
fn more_beds_than_the_simulator_decomposes() {
    // 2^15 configurations: refused before any is decomposed, with the limit named.
    let beds = vec!["{ mass = 1, mass_ratio = 0.01, clearance_mm = \"inf\" }"; 15].join(", ");
    fails_with("dampers = []", &format!("dampers = [{beds}]"), &["cases[0].dampers = 15 dampers", "at most 14"]);
    // Three columns of 30 grains: 31^3 configurations.
    let beds = ["{ mass = 1, mass_ratio = 0.01, clearance_mm = 0.3, bed = \"column\", grains = 30 }"; 3].join(", ");
    fails_with(
        "dampers = []",
        &format!("dampers = [{beds}]"),
        &[
            "cases[0].dampers = 3 dampers with grains [30, 30, 30] (29791 configurations)",
            "at most 16384 configurations",
        ],
    );
}

#[test]
fn missing_reference_file() {
    fails_with(
        "reference = \"paper-text.toml#omega_1\"",
        "reference = \"nowhere.toml#omega_1\"",
        &["checks[1].reference", "no such reference file"],
    );
}

#[test]
fn unknown_reference_id() {
    fails_with(
        "reference = \"paper-text.toml#omega_1\"",
        "reference = \"paper-text.toml#omega_9\"",
        &["no quantity with id \"omega_9\""],
    );
}

#[test]
fn missing_experiment_file_is_an_io_error() {
    let out = shotdamp().args(["modal", "experiments/does-not-exist.toml"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does-not-exist.toml"));
}

#[test]
fn modal_prints_the_frequencies() {
    let out = shotdamp().args(["modal", "experiments/fig04b_no_damper.toml"]).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    for w in ["81.91", "218.51", "312.04"] {
        assert!(stdout.contains(w), "{w} in {stdout}");
    }
}

/// Every `href` and `src` of a page points at a file that exists.
fn assert_links_resolve(page: &Path) {
    let html = std::fs::read_to_string(page).unwrap();
    let base = page.parent().unwrap();
    let mut n = 0;
    for attr in ["href=\"", "src=\""] {
        for part in html.split(attr).skip(1) {
            let target = part.split('"').next().unwrap();
            if target.starts_with("http") || target.starts_with('#') {
                continue;
            }
            let path = base.join(target);
            assert!(path.is_file(), "{}: link {target} -> {} missing", page.display(), path.display());
            n += 1;
            if target.ends_with(".html") && target != "../index.html" && !target.starts_with("..") {
                assert_links_resolve(&path);
            }
        }
    }
    assert!(n > 0, "{} has no links", page.display());
}

#[test]
fn report_of_linear_experiment_links_only_existing_files() {
    let dir = tempfile::tempdir().unwrap();
    let exps = experiments(dir.path(), &["fig04b_no_damper.toml"]);
    let out_dir = dir.path().join("report");
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&out_dir).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert_links_resolve(&out_dir.join("index.html"));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out_dir.join("checks.json")).unwrap()).unwrap();
    let checks = json["checks"].as_array().unwrap();
    assert!(checks.iter().any(|c| c["name"] == "omega_2" && c["status"] == "known_deviation"));
    assert!(checks.iter().any(|c| c["name"] == "omega_1" && c["status"] == "pass"));
    // No staging folder is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn failed_run_leaves_previous_report_intact() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("report");
    std::fs::create_dir_all(&out_dir).unwrap();
    std::fs::write(out_dir.join("index.html"), "previous").unwrap();
    let (_d, bad) = variant("[analysis]", "[excitation]\nforce_n = -2.6\n\n[analysis]");
    let exps = bad.parent().unwrap().to_path_buf();
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&out_dir).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("excitation.force_n = -2.6"));
    assert_eq!(std::fs::read_to_string(out_dir.join("index.html")).unwrap(), "previous");
}

#[test]
fn check_for_an_unknown_model_is_named() {
    fails_with(
        "models = [\"stated\"]",
        "models = [\"chain\"]",
        &["checks[0].models", "\"stated\", \"coil\", \"fitted\""],
    );
}

#[test]
fn deviation_text_for_an_unknown_model_is_named() {
    fails_with("deviation = { stated =", "deviation = { chained =", &["experiment.deviation", "chained", "model id"]);
}

/// `shotdamp report` over two copies of the Fig. 5 third-mode file, `a` and `b`, whose
/// clearances come from the exports named (each other's, or an experiment that does not run):
/// its exit code and stderr, and whether a report folder was left.
fn report_of_export_pair(a_uses: &str, b_uses: &str) -> (Option<i32>, String, bool) {
    let dir = tempfile::tempdir().expect("tempdir");
    let exps = dir.path().join("experiments");
    common::copy_shared(&exps);
    let text = std::fs::read_to_string(repo().join("experiments/fig05_third_mode.toml")).unwrap();
    for (id, uses) in [("a", a_uses), ("b", b_uses)] {
        let t = text
            .replacen("id = \"fig05_third_mode\"", &format!("id = \"{id}\""), 1)
            .replace("@fig05_clearance_scan", uses);
        std::fs::write(exps.join(format!("{id}.toml")), t).unwrap();
    }
    let out_dir = dir.path().join("r");
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&out_dir).output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned(), out_dir.exists())
}

#[test]
fn experiments_that_use_each_others_exports_are_a_cycle_and_an_input_error() {
    let (code, stderr, left) = report_of_export_pair("@b", "@a");
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("cycle") && stderr.contains("toml"), "{stderr}");
    assert!(!left, "no report folder: {stderr}");
}

#[test]
fn an_export_of_an_experiment_that_does_not_run_is_named() {
    let (code, stderr, _) = report_of_export_pair("@b", "@nowhere");
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("b.toml") && stderr.contains("@nowhere") && stderr.contains("no experiment with id"),
        "{stderr}"
    );
}

/// `shotdamp run` of one file (Fig. 6's, whose markers and clearance come from the Fig. 5
/// third-mode sweep, which takes its clearance from the clearance scan) runs those two first,
/// from its folder, and says so.
#[test]
fn run_of_one_file_runs_the_experiments_whose_exports_it_uses() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exps = dir.path().join("experiments");
    common::copy_shared(&exps);
    for name in ["fig05_clearance_scan", "fig05_third_mode", "fig06_waveforms"] {
        let text = std::fs::read_to_string(repo().join(format!("experiments/{name}.toml"))).unwrap();
        std::fs::write(exps.join(format!("{name}.toml")), text).unwrap();
    }
    let out_dir = dir.path().join("r");
    let out = shotdamp().arg("run").arg(exps.join("fig06_waveforms.toml")).arg("--out").arg(&out_dir).output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_ne!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stdout.contains("also running")
            && stdout.contains("fig05_third_mode (")
            && stdout.contains("fig05_clearance_scan ("),
        "{stdout}"
    );
    for id in ["fig05_clearance_scan", "fig05_third_mode", "fig06_waveforms"] {
        assert!(out_dir.join(id).is_dir(), "{id} in the report: {stdout}");
    }
}

/// A matrix as a TOML array of rows (every digit kept).
fn toml_rows(a: &nalgebra::DMatrix<f64>) -> String {
    let row = |i: usize| format!("[{}]", a.row(i).iter().map(|v| format!("{v:e}")).collect::<Vec<_>>().join(", "));
    format!("[{}]", (0..a.nrows()).map(row).collect::<Vec<_>>().join(", "))
}

/// The stated chain with one container on m2, as lumped masses or (`coupled`) in coordinates
/// `q3 = x3 - 0.4 x1 - 0.3 x2`: a full mass matrix `T^T M T` and stiffness `T^T K T`, the
/// host and the driven mass physical.
fn mass_matrix_sweep(coupled: bool) -> String {
    use nalgebra::DMatrix;
    let (m, k) = ([0.74, 0.71, 0.64], [24.3e3, 21.8e3, 19.8e3]);
    let mm = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(&m));
    let kk = DMatrix::from_row_slice(3, 3, &[k[0] + k[1], -k[1], 0.0, -k[1], k[1] + k[2], -k[2], 0.0, -k[2], k[2]]);
    let mut t = DMatrix::<f64>::identity(3, 3);
    t[(2, 0)] = 0.4;
    t[(2, 1)] = 0.3;
    let structure = if coupled {
        let (mq, kq) = (t.transpose() * &mm * &t, t.transpose() * &kk * &t);
        format!("mass_matrix_kg = {}\nstiffness_matrix_n_per_m = {}", toml_rows(&mq), toml_rows(&kq))
    } else {
        "masses_kg = [0.74, 0.71, 0.64]\nchain_stiffness_n_per_m = [24.3e3, 21.8e3, 19.8e3]".to_string()
    };
    format!(
        "[experiment]\nid = \"mm\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure]\n{structure}\n[structure.damping]\nmodal_ratios = [0.01, 0.01, 0.01]\n[excitation]\nmass = 1\nforce_n = 2.6\n[analysis]\nkind = \"sweep\"\nfreq_hz = {{ start = 44.0, stop = 52.0, step = 2.0 }}\n[[cases]]\nid = \"a\"\nlabel = \"a\"\ndampers = [{{ mass = 2, mass_kg = 0.071, clearance_mm = 0.5 }}]\n"
    )
}

#[test]
fn a_full_mass_matrix_runs_from_an_experiment_file_and_keeps_the_chain_s_motion() {
    let dir = tempfile::tempdir().unwrap();
    let mut tables = Vec::new();
    for coupled in [false, true] {
        let path = dir.path().join(format!("mm{}.toml", u8::from(coupled)));
        std::fs::write(&path, mass_matrix_sweep(coupled)).unwrap();
        let out_dir = dir.path().join(format!("out{}", u8::from(coupled)));
        let out = shotdamp().arg("run").arg(&path).arg("--out").arg(&out_dir).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
        let table = std::fs::read_to_string(out_dir.join("mm/data/compliance.csv")).unwrap();
        tables.push(common::csv_rows(&table));
    }
    let (a, b) = (&tables[0], &tables[1]);
    assert_eq!(a.len(), 6, "a header and five frequencies");
    assert_eq!(a[0], b[0]);
    let col = |name: &str| a[0].iter().position(|c| c == name).unwrap_or_else(|| panic!("{name} in {:?}", a[0]));
    for (ra, rb) in a[1..].iter().zip(&b[1..]) {
        assert_eq!((&ra[col("converged")], &rb[col("converged")]), (&"1".to_string(), &"1".to_string()));
        // The host and the driven mass are the same physical coordinates in both.
        for name in ["c1", "c2"] {
            let (x, y): (f64, f64) = (ra[col(name)].parse().unwrap(), rb[col(name)].parse().unwrap());
            assert!((x - y).abs() <= 1e-9 * x.abs(), "{name} at {}: {x} vs {y}", ra[col("freq_hz")]);
        }
    }
}

/// The numbers of a design table's rows (text columns kept as they are).
fn design_rows(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("design_five_storey/data/design_placements.csv")).unwrap();
    common::csv_rows(&text)
}

#[test]
fn a_design_on_a_full_mass_matrix_is_the_lumped_frame_s_design() {
    use nalgebra::DMatrix;
    // The 5-storey frame with containers on floors 4 and 5 only, and the same frame in
    // coordinates that mix floors 1-3 with them (q_i = x_i - T_i4 x_4 - T_i5 x_5): a full mass
    // matrix whose design must be the frame's.
    let text = std::fs::read_to_string(repo().join("designs/five_storey.toml"))
        .unwrap()
        .replace("candidates = [1, 2, 3, 4, 5]", "candidates = [4, 5]")
        .replace("shot_mass_ratio = 0.05", "shot_kg = 0.25");
    let chain = "masses_kg = [1.0, 1.0, 1.0, 1.0, 1.0]\nchain_stiffness_n_per_m = [20000.0, 20000.0, 20000.0, 20000.0, 20000.0]";
    assert!(text.contains(chain) && text.contains("shot_kg = 0.25"));
    let n = 5;
    let k = DMatrix::from_fn(n, n, |i, j| match (i, j) {
        _ if i == j => {
            if i + 1 < n {
                40000.0
            } else {
                20000.0
            }
        }
        _ if i.abs_diff(j) == 1 => -20000.0,
        _ => 0.0,
    });
    let mut t = DMatrix::<f64>::identity(n, n);
    for i in 0..3 {
        t[(i, 3)] = 0.2 * (i + 1) as f64;
        t[(i, 4)] = 0.3 - 0.1 * i as f64;
    }
    let (mq, kq) = (t.transpose() * &t, t.transpose() * &k * &t);
    let coupled = text
        .replace(chain, &format!("mass_matrix_kg = {}\nstiffness_matrix_n_per_m = {}", toml_rows(&mq), toml_rows(&kq)));
    let dir = tempfile::tempdir().unwrap();
    let mut tables = Vec::new();
    for (name, body) in [("lumped", &text), ("coupled", &coupled)] {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, body).unwrap();
        let out_dir = dir.path().join(name);
        let out = shotdamp().arg("design").arg(&path).arg("--out").arg(&out_dir).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        tables.push(design_rows(&out_dir));
    }
    // A full mass matrix has no total mass to take a shot mass ratio of.
    let path = dir.path().join("ratio.toml");
    std::fs::write(&path, coupled.replace("shot_kg = 0.25", "shot_mass_ratio = 0.05")).unwrap();
    let out = shotdamp().arg("design").arg(&path).arg("--dry-run").output().unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(said.contains("design.shot_mass_ratio = 0.05: a structure given by a full mass matrix"), "{said}");
    // ... nor Pareto ratios (they were taken of its trace, a sum of no masses).
    std::fs::write(&path, coupled.replace("shot_kg = 0.25", "shot_kg = 0.25\npareto_mass_ratios = [0.05]")).unwrap();
    let out = shotdamp().arg("design").arg(&path).arg("--dry-run").output().unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(said.contains("design.pareto_mass_ratios[0] = 0.05: a structure given by a full mass matrix"), "{said}");
    let (a, b) = (&tables[0], &tables[1]);
    assert_eq!(a.len(), 4, "a header and three placements: {a:?}");
    assert_eq!(a[0], b[0]);
    for (ra, rb) in a[1..].iter().zip(&b[1..]) {
        for (h, (x, y)) in a[0].iter().zip(ra.iter().zip(rb)) {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => assert!((x - y).abs() <= 1e-10 * x.abs().max(1e-12), "{h}: {x} vs {y}"),
                _ => assert_eq!(x, y, "{h}"),
            }
        }
    }
}
