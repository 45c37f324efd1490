//! Property-based fuzzing of every loader with mutated versions of the real files: deleted,
//! duplicated and swapped lines, numbers replaced by huge, tiny, non-finite, negative or
//! wrongly typed values, truncation, invalid UTF-8. The property: a loader returns a value or
//! an error that names the file, and never panics. `PROPTEST_CASES=20000 cargo test --release
//! --locked --test fuzz` runs a longer campaign (docs/reliability.md).

mod common;

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use shotdamp::checks::reference::Curve;
use shotdamp::reference::digitised::{import_wpd_csv, import_wpd_json, ImportInfo};
use shotdamp::reference::values::ValueFile;

/// One change to a file.
#[derive(Debug, Clone)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    /// Replace the n-th number of the file with one of [`ODD_VALUES`].
    ReplaceNumber(usize, usize),
    Truncate(f64),
    InvalidUtf8(usize),
}

const ODD_VALUES: [&str; 14] = [
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "-0",
    "0",
    "-1",
    "99999999999999999999999",
    "\"text\"",
    "true",
    "[]",
    "{ a = 1 }",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::DeleteLine),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        (any::<usize>(), 0..ODD_VALUES.len()).prop_map(|(n, v)| Mutation::ReplaceNumber(n, v)),
        (0.0..1.0f64).prop_map(Mutation::Truncate),
        any::<usize>().prop_map(Mutation::InvalidUtf8),
    ]
}

/// The byte ranges of the numbers in `text` (digits with sign, point and exponent).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) {
            let start = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'e' | b'E' | b'-' | b'+')) {
                j += 1;
            }
            out.push((start, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

fn apply(bytes: &[u8], muts: &[Mutation]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    for m in muts {
        let text = String::from_utf8_lossy(&b).into_owned();
        let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
        b = match *m {
            Mutation::DeleteLine(i) if !lines.is_empty() => {
                let k = i % lines.len();
                lines.remove(k);
                lines.concat().into_bytes()
            }
            Mutation::DuplicateLine(i) if !lines.is_empty() => {
                let k = i % lines.len();
                lines.insert(k, lines[k]);
                lines.concat().into_bytes()
            }
            Mutation::SwapLines(x, y) if !lines.is_empty() => {
                let n = lines.len();
                lines.swap(x % n, y % n);
                lines.concat().into_bytes()
            }
            Mutation::ReplaceNumber(n, v) => {
                let nums = numbers(&text);
                if nums.is_empty() {
                    b
                } else {
                    let (s, e) = nums[n % nums.len()];
                    format!("{}{}{}", &text[..s], ODD_VALUES[v], &text[e..]).into_bytes()
                }
            }
            Mutation::Truncate(f) => {
                let k = (b.len() as f64 * f) as usize;
                b[..k].to_vec()
            }
            Mutation::InvalidUtf8(i) => {
                let k = if b.is_empty() { 0 } else { i % b.len() };
                let mut c = b.clone();
                c.splice(k..k, [0xff, 0xfe, 0xc3]);
                c
            }
            _ => b,
        };
    }
    b
}

/// The error names the file (a loader never answers with a bare message).
fn names(err: &shotdamp::Error, path: &Path) -> bool {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    format!("{err}").contains(&name)
}

fn repo_file(rel: &str) -> Vec<u8> {
    std::fs::read(common::repo().join(rel)).unwrap()
}

/// The experiment files, each beside the shared structure file, in a scratch folder.
fn experiment_files() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(common::repo().join("experiments"))
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    v.sort();
    v
}

fn scratch(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// 96 cases a property in the test run (under a second); `PROPTEST_CASES` sets more.
fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(96);
    ProptestConfig { cases, failure_persistence: None, ..ProptestConfig::default() }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn mutated_experiment_files_load_or_fail_with_their_name(
        pick in 0usize..64,
        which in 0usize..3,
        muts in proptest::collection::vec(mutation(), 1..4),
    ) {
        let files = experiment_files();
        let name = &files[pick % files.len()];
        let dir = tempfile::tempdir().unwrap();
        let exps = common::experiments(dir.path(), &[name.as_str()]);
        // Mutate the experiment itself, the shared file it extends, or a model file.
        let target = match which {
            0 => exps.join(name),
            1 => exps.join("shared/paper_structure.toml"),
            _ => exps.join("shared/models/fitted.toml"),
        };
        let bytes = apply(&std::fs::read(&target).unwrap(), &muts);
        std::fs::write(&target, bytes).unwrap();
        if let Err(e) = shotdamp::experiment::load(&exps.join(name), &common::repo().join("reference")) {
            prop_assert!(names(&e, &target) || names(&e, &exps.join(name)), "{e}");
        }
    }

    #[test]
    fn mutated_study_files_load_or_fail_with_their_name(
        pick in 0usize..64,
        muts in proptest::collection::vec(mutation(), 1..4),
    ) {
        let files = ["fig05_report.toml", "fig08_report.toml", "fig10b_report.toml"];
        let name = files[pick % files.len()];
        let text = String::from_utf8(repo_file(&format!("studies/{name}"))).unwrap();
        let experiments = common::repo().join("experiments");
        let text = text.replace("\"../experiments", &format!("\"{}", experiments.display()));
        let dir = tempfile::tempdir().unwrap();
        let p = scratch(dir.path(), name, &apply(text.as_bytes(), &muts));
        let reference = common::repo().join("reference");
        match shotdamp::experiment::study::load(&p, &reference) {
            Err(e) => prop_assert!(names(&e, &p), "{e}"),
            // Every sample's experiment builds, or the error names the study.
            Ok(study) => {
                for sample in &study.samples {
                    if let Err(e) = study.experiment(sample, &reference) {
                        prop_assert!(names(&e, &p), "{e}");
                    }
                }
            }
        }
    }

    #[test]
    fn mutated_reference_curves_load_or_fail_with_their_name(
        pick in 0usize..64,
        muts in proptest::collection::vec(mutation(), 1..4),
    ) {
        let files = ["P_bare.csv", "P_dinf_N3.csv", "cont_P_m2_d0.5mm_up.csv", "impulse_P_3dampers_dinf_events.csv"];
        let name = files[pick % files.len()];
        let dir = tempfile::tempdir().unwrap();
        let p = scratch(dir.path(), name, &apply(&repo_file(&format!("reference/independent-solver/{name}")), &muts));
        if let Err(e) = Curve::load(&p) {
            prop_assert!(names(&e, &p), "{e}");
        }
    }

    #[test]
    fn mutated_paper_values_load_or_fail_with_their_name(muts in proptest::collection::vec(mutation(), 1..4)) {
        let dir = tempfile::tempdir().unwrap();
        let p = scratch(dir.path(), "paper-text.toml", &apply(&repo_file("reference/paper-text.toml"), &muts));
        if let Err(e) = ValueFile::load(&p) {
            prop_assert!(names(&e, &p), "{e}");
        }
    }

    #[test]
    fn mutated_webplotdigitizer_projects_import_or_fail_with_their_name(
        csv in any::<bool>(),
        muts in proptest::collection::vec(mutation(), 1..4),
    ) {
        let info = ImportInfo { figure: "Fig. 8".into(), ..ImportInfo::default() };
        let (name, text) = if csv {
            ("d.csv", "x,y\n35.0,1e-4\n40.0,2e-4\n60.0,1e-3\n".to_string())
        } else {
            ("p.json", wpd_project())
        };
        let bytes = apply(text.as_bytes(), &muts);
        let text = String::from_utf8_lossy(&bytes);
        let result = if csv { import_wpd_csv(name, &text, &info) } else { import_wpd_json(name, &text, &info) };
        if let Err(e) = result {
            prop_assert!(format!("{e}").contains(name), "{e}");
        }
    }
}

/// A WebPlotDigitizer 4 project with one dataset (as in tests/review.rs).
fn wpd_project() -> String {
    r#"{"version":[4,2],"axesColl":[{"name":"XY","type":"XYAxes","isLogX":false,"isLogY":true,"noRotation":false,
"calibrationPoints":[{"px":100,"py":500,"dx":"10","dy":"0","dz":null},{"px":600,"py":500,"dx":"60","dy":"0","dz":null},
{"px":100,"py":500,"dx":"0","dy":"1e-6","dz":null},{"px":100,"py":100,"dx":"0","dy":"1e-3","dz":null}]}],
"datasetColl":[{"name":"D m1","axesName":"XY","metadataKeys":[],"colorRGB":[200,0,0,255],
"data":[{"x":350,"y":300,"value":[35,0]},{"x":600,"y":100,"value":[60,0]}]}],"measurementColl":[]}"#
        .to_string()
}

/// `extends` chains: a cycle, a chain longer than allowed, a missing parent.
#[test]
fn extends_cycles_and_deep_chains_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.toml"), "extends = \"b.toml\"\n").unwrap();
    std::fs::write(d.join("b.toml"), "extends = \"a.toml\"\n").unwrap();
    let e = shotdamp::experiment::load(&d.join("a.toml"), &common::repo().join("reference")).unwrap_err();
    assert!(format!("{e}").contains("extends") && format!("{e}").contains("cycle"), "{e}");
    for k in 0..40 {
        std::fs::write(d.join(format!("c{k}.toml")), format!("extends = \"c{}.toml\"\n", k + 1)).unwrap();
    }
    std::fs::write(d.join("c40.toml"), "").unwrap();
    let e = shotdamp::experiment::load(&d.join("c0.toml"), &common::repo().join("reference")).unwrap_err();
    assert!(format!("{e}").contains("limited"), "{e}");
    std::fs::write(d.join("m.toml"), "extends = \"nowhere.toml\"\n").unwrap();
    let e = shotdamp::experiment::load(&d.join("m.toml"), &common::repo().join("reference")).unwrap_err();
    assert!(format!("{e}").contains("nowhere.toml"), "{e}");
}

/// Through the binary: a mutated experiment is exit 0 or 2 with a message, never a crash.
#[test]
fn the_binary_answers_bad_experiment_files_with_exit_2_and_a_message() {
    let muts = [
        vec![Mutation::ReplaceNumber(3, 3)],
        vec![Mutation::DeleteLine(7)],
        vec![Mutation::InvalidUtf8(40)],
        vec![Mutation::Truncate(0.5)],
        vec![Mutation::ReplaceNumber(0, 10)],
    ];
    for m in muts {
        let dir = tempfile::tempdir().unwrap();
        let exps = common::experiments(dir.path(), &["fig04b_no_damper.toml"]);
        let target = exps.join("fig04b_no_damper.toml");
        std::fs::write(&target, apply(&std::fs::read(&target).unwrap(), &m)).unwrap();
        let out = common::shotdamp().arg("--experiments").arg(&exps).arg("list").output().unwrap();
        let code = out.status.code();
        assert!(code == Some(0) || code == Some(2), "{m:?}: exit {code:?}");
        if code == Some(2) {
            let msg = String::from_utf8_lossy(&out.stderr);
            assert!(msg.starts_with("error: ") && msg.contains("fig04b_no_damper.toml"), "{m:?}: {msg}");
        }
    }
}
