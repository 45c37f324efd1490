//! What reviewers and CI rely on: digitised curves in, the regression baseline, checks.json and
//! JUnit XML, exit codes, and the comparison of two reports.

use crate::common;

use std::path::{Path, PathBuf};

use common::{experiments, repo, shotdamp};
use shotdamp::reference::digitised::{import_wpd_json, ImportInfo};

/// A WebPlotDigitizer 4 project: X1 (100, 500) = 10 Hz, X2 (600, 500) = 60 Hz; Y1 (100, 500) =
/// 1e-6, Y2 (100, 100) = 1e-3 (log if `y_log`, else 0 and 1e-3); two points of one dataset.
fn project(y_log: bool) -> String {
    let (y1, y2) = if y_log { ("1e-6", "1e-3") } else { ("0", "1e-3") };
    format!(
        r#"{{"version":[4,2],"axesColl":[{{"name":"XY","type":"XYAxes","isLogX":false,"isLogY":{y_log},"noRotation":false,
"calibrationPoints":[{{"px":100,"py":500,"dx":"10","dy":"0","dz":null}},{{"px":600,"py":500,"dx":"60","dy":"0","dz":null}},
{{"px":100,"py":500,"dx":"0","dy":"{y1}","dz":null}},{{"px":100,"py":100,"dx":"0","dy":"{y2}","dz":null}}]}}],
"datasetColl":[{{"name":"D m1","axesName":"XY","metadataKeys":[],"colorRGB":[200,0,0,255],
"data":[{{"x":350,"y":300,"value":[35,0]}},{{"x":600,"y":100,"value":[60,0]}}]}}],"measurementColl":[]}}"#
    )
}

#[test]
fn webplotdigitizer_json_imports_to_hand_computed_values() {
    let info = ImportInfo { figure: "Fig. 8".into(), ..ImportInfo::default() };
    // Linear x, log y: (350, 300) is 10 + 250/500 * 50 = 35 Hz and 10^(-6 + 200/400 * 3) = 10^-4.5.
    let f = import_wpd_json("t.json", &project(true), &info).unwrap();
    let c = &f.curve[0];
    assert_eq!(c.name, "D m1");
    assert!((c.x[0] - 35.0).abs() < 1e-12 && (c.x[1] - 60.0).abs() < 1e-12, "{:?}", c.x);
    assert!((c.y[0] / 10f64.powf(-4.5) - 1.0).abs() < 1e-12, "{}", c.y[0]);
    assert!((c.y[1] / 1e-3 - 1.0).abs() < 1e-12, "{}", c.y[1]);
    // One pixel: 50 Hz / 500 px along x; 3 decades / 400 px along y, as a relative size.
    assert!((f.meta.x_pixel - 0.1).abs() < 1e-12);
    assert!((f.meta.y_pixel - (10f64.powf(3.0 / 400.0) - 1.0)).abs() < 1e-12);
    assert!(f.meta.y_log && !f.meta.x_log);
    // Linear both: (350, 300) is y = 200/400 * 1e-3 = 5e-4; one pixel is 2.5e-6 along y.
    let f = import_wpd_json("t.json", &project(false), &info).unwrap();
    assert!((f.curve[0].y[0] - 5e-4).abs() < 1e-15);
    assert!((f.meta.y_pixel - 2.5e-6).abs() < 1e-18);
}

#[test]
fn reference_import_writes_a_digitised_file_with_provenance() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("fig8.json");
    std::fs::write(&json, project(true)).unwrap();
    let out = dir.path().join("fig8.toml");
    let run = shotdamp()
        .args(["reference", "import"])
        .arg(&json)
        .args(["--figure", "Fig. 8", "--by", "a reviewer", "--from", "page 5 of the proceedings", "--map", "D m1=D:1"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let f = shotdamp::reference::digitised::load(&out).unwrap();
    assert_eq!(f.meta.provenance, "digitised figure");
    assert_eq!(f.meta.digitised_by, "a reviewer");
    assert_eq!(f.meta.imported_from, "fig8.json");
    assert_eq!((f.curve[0].case.as_deref(), f.curve[0].mass), (Some("D"), Some(1)));
    // A bad mapping is an input error.
    let bad = shotdamp()
        .args(["reference", "import"])
        .arg(&json)
        .args(["--figure", "F", "--by", "b", "--from", "c", "--map", "D m1"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("DATASET=CASE:MASS"));
}

/// What `reference import` would write but the loader refuses is an input error naming the
/// export's line and column (or the flag), and nothing is written: a value that is not
/// finite, zero on a log axis, a pixel that is not positive, a value beyond the datasets the
/// header names.
#[test]
fn an_export_the_loader_would_refuse_is_not_imported() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "nan.csv",
            "x,y\n1,2\n3,nan\n",
            &["--y-pixel", "0.1"][..],
            "nan.csv: line 3, column 2: \"nan\" is not a finite number",
        ),
        ("inf.csv", "x,y\n1e400,2\n", &["--y-pixel", "0.1"][..], "line 2, column 1: \"1e400\" is not a finite number"),
        (
            "log.csv",
            "x,y\n1,2\n3,0\n",
            &["--y-pixel", "0.1", "--y-log"][..],
            "line 3, column 2: \"0\" is not a positive finite number (log axis)",
        ),
        (
            "pixel.csv",
            "x,y\n1,2\n",
            &["--y-pixel=-1"][..],
            "--y-pixel -1: the size of one pixel must be a positive number",
        ),
        (
            "wide.csv",
            "a,\nX,Y\n1,2,3,4\n",
            &["--y-pixel", "0.1"][..],
            "line 3: a value in column 3, beyond the 2 column(s) of the 1 dataset(s)",
        ),
    ];
    for (name, text, flags, said) in cases {
        let csv = dir.path().join(name);
        std::fs::write(&csv, text).unwrap();
        let out = dir.path().join(format!("{name}.toml"));
        let run = shotdamp()
            .args(["reference", "import"])
            .arg(&csv)
            .args(["--figure", "Fig. 8", "--by", "r", "--from", "p", "--x-pixel", "0.1"])
            .args(flags)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(said), "{name}: expected \"{said}\" in: {err}");
        assert!(!out.exists(), "{name}: nothing is written");
    }
}

/// A folder with the Fig. 4(b) experiment and a copy of the references without a baseline.
fn workspace() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let exps = experiments(dir.path(), &["fig04b_no_damper.toml"]);
    let refs = dir.path().join("reference");
    std::fs::create_dir_all(refs.join("independent-solver")).unwrap();
    std::fs::copy(repo().join("reference/paper-text.toml"), refs.join("paper-text.toml")).unwrap();
    std::fs::copy(repo().join("reference/independent-solver/P_bare.csv"), refs.join("independent-solver/P_bare.csv"))
        .unwrap();
    (dir, exps, refs)
}

fn report(exps: &Path, refs: &Path, out: &Path, bless: bool) -> std::process::Output {
    let mut c = shotdamp();
    c.arg("--experiments").arg(exps).arg("--reference").arg(refs).arg("report").arg("--out").arg(out);
    if bless {
        c.arg("--bless");
    }
    c.output().unwrap()
}

#[test]
fn bless_then_run_passes_and_a_perturbed_result_fails_naming_the_point() {
    let (dir, exps, refs) = workspace();
    let out = dir.path().join("report");
    // Without a baseline the report fails and says how to bless.
    let none = report(&exps, &refs, &out, false);
    assert_eq!(none.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&none.stdout).contains("--bless"));
    let blessed = report(&exps, &refs, &out, true);
    assert_eq!(blessed.status.code(), Some(0), "{}", String::from_utf8_lossy(&blessed.stderr));
    for model in ["stated", "coil", "fitted"] {
        assert!(refs.join(format!("baseline/fig04b_no_damper/{model}.csv")).is_file());
    }
    let again = report(&exps, &refs, &out, false);
    assert_eq!(again.status.code(), Some(0), "{}", String::from_utf8_lossy(&again.stdout));
    // The force on m2 instead of m1 moves every compliance (and nothing else).
    let file = exps.join("fig04b_no_damper.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let text = text.replace("[analysis]", "[excitation]\nmass = 2\n\n[analysis]");
    std::fs::write(&file, text).unwrap();
    let moved = report(&exps, &refs, &out, false);
    assert_eq!(moved.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&moved.stdout);
    let line = stdout.lines().find(|l| l.contains("baseline")).unwrap_or_else(|| panic!("{stdout}"));
    for word in ["Fig. 4(b)", "table compliance", "bare", "freq_hz=", "now", "blessed"] {
        assert!(line.contains(word), "{word:?} in {line}");
    }
}

#[test]
fn checks_json_and_junit_hold_every_check_and_a_failure_exits_1() {
    let (dir, exps, refs) = workspace();
    let out = dir.path().join("report");
    assert_eq!(report(&exps, &refs, &out, true).status.code(), Some(0));
    // Make omega_1 fail: the paper's value as a tolerance of zero.
    let file = exps.join("fig04b_no_damper.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replacen(
            "reference = \"paper-text.toml#omega_1\"\nrel_tol = 0.005",
            "reference = \"paper-text.toml#omega_1\"\nrel_tol = 0.0",
            1,
        ),
    )
    .unwrap();
    let run = report(&exps, &refs, &out, false);
    assert_eq!(run.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("checks.json")).unwrap()).unwrap();
    let checks = json["checks"].as_array().unwrap();
    assert_eq!(json["passed"], false);
    let xml = std::fs::read_to_string(out.join("junit.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let cases: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("testcase")).collect();
    assert_eq!(cases.len(), checks.len());
    for c in checks {
        let name = c["name"].as_str().unwrap();
        assert!(cases.iter().any(|t| t.attribute("name") == Some(name)), "{name} in junit.xml");
    }
    let failed: Vec<_> = cases.iter().filter(|t| t.children().any(|c| c.has_tag_name("failure"))).collect();
    assert_eq!(failed.len(), 1);
    assert_eq!(failed[0].attribute("name"), Some("omega_1"));
    let skipped = cases.iter().filter(|t| t.children().any(|c| c.has_tag_name("skipped"))).count();
    assert_eq!(skipped, checks.iter().filter(|c| c["status"] == "known_deviation").count());
}

#[test]
fn compare_shows_figures_side_by_side_and_the_checks_that_changed() {
    let (dir, exps, refs) = workspace();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    assert_eq!(report(&exps, &refs, &a, true).status.code(), Some(0));
    let file = exps.join("fig04b_no_damper.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, text.replacen("rel_tol = 0.005", "rel_tol = 0.0", 1)).unwrap();
    let _ = report(&exps, &refs, &b, false);
    let out = dir.path().join("cmp");
    let run = shotdamp().arg("compare").arg(&a).arg(&b).arg("--out").arg(&out).output().unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("omega_1") && html.contains("status changed"), "the changed check is listed");
    // Each figure in the smaller of PNG and SVG.
    let figure = |stem: &str| out.join(format!("{stem}.png")).is_file() || out.join(format!("{stem}.svg")).is_file();
    assert!(figure("a/fig04b_no_damper/stated/compliance"));
    assert!(figure("b/fig04b_no_damper/stated/compliance"));
    assert!(figure("b/fig04b_no_damper/models_compliance"), "the models overlaid");
    assert!(html.contains("mix-blend-mode") || html.contains("class=\"top diff\""));
}

/// A digitised file made from the bare structure's reference curve of m1, scaled by `factor`.
fn digitised_from_reference(refs: &Path, factor: f64) -> String {
    let text = std::fs::read_to_string(refs.join("independent-solver/P_bare.csv")).unwrap();
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for line in text.lines().skip(1) {
        let cols: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        x.push(cols[0]);
        y.push(cols[1] * factor);
    }
    let list = |v: &[f64]| v.iter().map(|a| format!("{a:e}")).collect::<Vec<_>>().join(", ");
    format!(
        "[meta]\nprovenance = \"digitised figure\"\nfigure = \"Fig. 4(b)\"\nsource = \"made from P_bare.csv for a test\"\ndigitised_by = \"test\"\ntool = \"hand\"\nimported_from = \"P_bare.csv\"\nx_unit = \"Hz\"\ny_unit = \"m/N\"\nx_log = false\ny_log = true\nx_pixel = 0.05\ny_pixel = 0.01\n\n[[curve]]\nname = \"m1\"\ncase = \"bare\"\nmass = 1\nx = [{}]\ny = [{}]\n",
        list(&x),
        list(&y)
    )
}

#[test]
fn tube_and_peak_checks_against_a_digitised_curve_pass_within_and_fail_beyond() {
    let (dir, exps, refs) = workspace();
    std::fs::create_dir_all(refs.join("digitised")).unwrap();
    let file = exps.join("fig04b_no_damper.toml");
    let text = std::fs::read_to_string(&file).unwrap()
        + "\n[[checks]]\nkind = \"tube\"\nmodels = [\"stated\"]\nreference = \"digitised/fig4b.toml\"\ncurve = \"m1\"\nx_tol_px = 2\ny_tol_px = 2\n\n[[checks]]\nkind = \"peak\"\nmodels = [\"stated\"]\nreference = \"digitised/fig4b.toml\"\ncurve = \"m1\"\nwindow_hz = [40.0, 60.0]\n";
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("report");
    // The digitised curve is made from the stated chain's reference: checked on that model.
    // 1 % off with 2 px of 1 % each on a log axis: inside.
    std::fs::write(refs.join("digitised/fig4b.toml"), digitised_from_reference(&refs, 1.01)).unwrap();
    let ok = report(&exps, &refs, &out, true);
    assert_eq!(ok.status.code(), Some(0), "{}", String::from_utf8_lossy(&ok.stdout));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("checks.json")).unwrap()).unwrap();
    let ours: Vec<&serde_json::Value> =
        json["checks"].as_array().unwrap().iter().filter(|c| c["source"] == "digitised_figure").collect();
    assert_eq!(ours.len(), 3, "a tube check and a peak check (frequency, height)");
    // 5 % off: outside the tube and the peak height.
    std::fs::write(refs.join("digitised/fig4b.toml"), digitised_from_reference(&refs, 1.05)).unwrap();
    let off = report(&exps, &refs, &out, false);
    assert_eq!(off.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&off.stdout);
    assert!(stdout.contains("vs digitised \"m1\""), "{stdout}");
    assert!(stdout.contains("peak height"), "{stdout}");
    assert!(!stdout.contains("peak frequency"), "the frequency still agrees: {stdout}");
    // The figure draws the digitised points and a residual panel.
    let page = std::fs::read_to_string(out.join("fig04b_no_damper/stated/index.html")).unwrap();
    assert!(page.contains("reference curves of the checks"));
}
