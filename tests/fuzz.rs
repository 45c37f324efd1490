//! Property-based fuzzing of every loader with mutated versions of the real files: deleted,
//! duplicated and swapped lines, numbers replaced by huge, tiny, non-finite, negative or
//! wrongly typed values, truncation, invalid UTF-8. The property: a loader returns a value or
//! an error that names the file, and never panics. `PROPTEST_CASES=20000 cargo test --release
//! --locked --test all -- fuzz::` runs a longer campaign (docs/reliability.md).

use crate::common;

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use shotdamp::checks::reference::Curve;
use shotdamp::reference::digitised::{import_wpd_csv, import_wpd_json, ImportInfo};
use shotdamp::reference::values::ValueFile;

/// One change to a file.
#[derive(Debug, Clone)]
pub enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    /// Replace the n-th number of the file with one of [`ODD_VALUES`].
    ReplaceNumber(usize, usize),
    Truncate(f64),
    InvalidUtf8(usize),
    /// Multiply the n-th number of the file by one of [`FACTORS`] (a value of the right type,
    /// physically odd: what reaches the solvers and the plots).
    ScaleNumber(usize, usize),
}

pub const FACTORS: [f64; 10] = [1e-9, 1e-3, 0.1, 0.5, 2.0, 10.0, 1e3, 1e6, 1e12, -1.0];

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

pub fn mutation() -> impl Strategy<Value = Mutation> {
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

pub fn apply(bytes: &[u8], muts: &[Mutation]) -> Vec<u8> {
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
            Mutation::ScaleNumber(n, f) => {
                let nums = numbers(&text);
                match nums
                    .get(n % nums.len().max(1))
                    .and_then(|&(s, e)| text[s..e].parse::<f64>().ok().map(|v| (s, e, v)))
                {
                    Some((s, e, v)) => {
                        let scaled = v * FACTORS[f];
                        let written = if text[s..e].contains(['.', 'e', 'E']) {
                            format!("{scaled:e}")
                        } else {
                            format!("{}", scaled.round() as i64)
                        };
                        format!("{}{written}{}", &text[..s], &text[e..]).into_bytes()
                    }
                    None => b,
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

pub fn repo_file(rel: &str) -> Vec<u8> {
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
        if let Err(e) = shotdamp::experiment::loader::load(&exps.join(name), &common::repo().join("reference")) {
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
                    if let Err(e) = study.experiment(sample) {
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
    let e = shotdamp::experiment::loader::load(&d.join("a.toml"), &common::repo().join("reference")).unwrap_err();
    assert!(format!("{e}").contains("extends") && format!("{e}").contains("cycle"), "{e}");
    for k in 0..40 {
        std::fs::write(d.join(format!("c{k}.toml")), format!("extends = \"c{}.toml\"\n", k + 1)).unwrap();
    }
    std::fs::write(d.join("c40.toml"), "").unwrap();
    let e = shotdamp::experiment::loader::load(&d.join("c0.toml"), &common::repo().join("reference")).unwrap_err();
    assert!(format!("{e}").contains("limited"), "{e}");
    std::fs::write(d.join("m.toml"), "extends = \"nowhere.toml\"\n").unwrap();
    let e = shotdamp::experiment::loader::load(&d.join("m.toml"), &common::repo().join("reference")).unwrap_err();
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

/// The experiment files another one takes values from (`@EXPERIMENT.KEY`), run beside it.
fn dependencies(name: &str) -> &'static [&'static str] {
    match name {
        "fig05_low_damping.toml" | "fig05_third_mode.toml" | "fig09_third_mode.toml" => &["fig05_clearance_scan.toml"],
        "fig06_waveforms.toml" => &["fig05_clearance_scan.toml", "fig05_third_mode.toml"],
        _ => &[],
    }
}

/// One run of the binary under the campaign's bounds: `(exit code or None when killed, wall
/// seconds, peak resident memory in KiB, stderr)`.
pub fn bounded_run(dir: &Path, args: &[String], seconds: u64, bytes: u64) -> (Option<i32>, f64, u64, String) {
    // SHOTDAMP_BIN: a copy of the binary, so that a long campaign is not changed by a build.
    let bin = std::env::var_os("SHOTDAMP_BIN")
        .map_or_else(|| assert_cmd::cargo::cargo_bin("shotdamp"), std::path::PathBuf::from);
    let started = std::time::Instant::now();
    let out = std::process::Command::new("timeout")
        .args(["-s", "KILL", &seconds.to_string(), "/usr/bin/time", "-f", "peak-kib %M", "prlimit"])
        .arg(format!("--as={bytes}"))
        .arg("--")
        .arg(bin)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let wall = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let peak =
        stderr.lines().rev().find_map(|l| l.strip_prefix("peak-kib ")).and_then(|v| v.trim().parse().ok()).unwrap_or(0);
    // time(1) reports the command's own exit status; a signal shows as "Command terminated".
    let code = if stderr.contains("Command terminated by signal") { None } else { out.status.code() };
    (code, wall, peak, stderr)
}

/// The fuzz campaign of docs/reliability.md, through the binary under a memory limit:
/// `FUZZ_EXPERIMENTS` mutated experiment files (every file of `experiments/`, impulse and plot
/// keys included, each run with the files it takes values from) and `FUZZ_DESIGNS` mutated
/// design files (a small search of the five-storey example), each into a new folder beside a
/// folder of the user's and, every tenth run, into a folder shotdamp wrote that holds a
/// user's file. The property: exit 0, 1 or 2 (2 with a message naming a file or the command
/// line), never a signal, a panic or the memory limit; a design search within its printed
/// bound; nothing of the user's touched. Prints the counts.
///
///     FUZZ_EXPERIMENTS=3000 FUZZ_DESIGNS=300 cargo test --release --locked --test all -- --ignored --nocapture fuzz::campaign
#[test]
#[ignore = "a campaign of hours: run by hand (docs/reliability.md)"]
fn campaign() {
    use proptest::strategy::ValueTree;
    let count = |k: &str, d: usize| std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d);
    let (n_exp, n_des) = (count("FUZZ_EXPERIMENTS", 30), count("FUZZ_DESIGNS", 10));
    const LIMIT: u64 = 4_000_000_000;
    // A run's time limit; a design search whose printed estimate is longer is not run.
    const SECONDS: u64 = 60;
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    for sub in ["experiments", "reference"] {
        common::copy_tree(&common::repo().join(sub), &root.join(sub));
    }
    std::fs::create_dir(root.join("users")).unwrap();
    std::fs::write(root.join("users/thesis.tex"), "precious").unwrap();
    let five = String::from_utf8(repo_file("designs/five_storey.toml")).unwrap();
    let small = five
        .replace("max_beds = 2", "max_beds = 2\nstarts = 1\nmax_iters = 4")
        .replace("step = 0.1 }", "step = 0.5 }")
        .replace("step = 0.2 }", "step = 1.0 }");
    let files = experiment_files();
    // FUZZ_SEED: another deterministic sequence (campaigns run side by side on several cores).
    let seed = count("FUZZ_SEED", 0) as u8;
    let rng = proptest::test_runner::TestRng::from_seed(proptest::test_runner::RngAlgorithm::ChaCha, &[seed; 32]);
    let mut runner = proptest::test_runner::TestRunner::new_with_rng(ProptestConfig::default(), rng);
    // Mostly values of the right type scaled to odd sizes (they reach the solvers and the
    // plots), the rest the loaders' mutations (most of those stop at the parser).
    let scale = (any::<usize>(), 0..FACTORS.len()).prop_map(|(n, f)| Mutation::ScaleNumber(n, f));
    let strategy = proptest::collection::vec(prop_oneof![4 => scale, 1 => mutation()], 1..3);
    let mut tally = std::collections::BTreeMap::<String, usize>::new();
    let (mut peak, mut slowest, mut over) = (0u64, 0.0f64, Vec::new());
    let mut worst_ratio = (0.0f64, String::new());
    let mut failures = Vec::new();
    for i in 0..n_exp + n_des {
        let muts = strategy.new_tree(&mut runner).unwrap().current();
        let design = i >= n_exp;
        let (name, base) = if design {
            ("small_five_storey.toml".to_string(), small.as_bytes().to_vec())
        } else {
            let name = files[i % files.len()].clone();
            let bytes = repo_file(&format!("experiments/{name}"));
            (name, bytes)
        };
        let target = root.join("experiments").join(&name);
        std::fs::write(&target, apply(&base, &muts)).unwrap();
        // Every tenth run writes into a folder shotdamp wrote, with a user's file in it.
        let out = root.join("out");
        let guarded = i % 10 == 9;
        if guarded {
            std::fs::create_dir_all(&out).unwrap();
            std::fs::write(out.join(".shotdamp-report"), "").unwrap();
            std::fs::write(out.join(".shotdamp-files"), ".shotdamp-report\n").unwrap();
            std::fs::write(out.join("mine.txt"), "user").unwrap();
        }
        let mut args: Vec<String> = vec![if design { "design" } else { "run" }.into()];
        if !design {
            args.extend(dependencies(&name).iter().map(|d| format!("experiments/{d}")));
        }
        args.extend([format!("experiments/{name}"), "--out".into(), "out".into(), "--jobs".into(), "1".into()]);
        let budget = if design {
            shotdamp::runner::designs::budgets(std::slice::from_ref(&target), &root.join("reference"))
                .ok()
                .and_then(|b| b.first().map(|(key, n, b)| (key.clone(), b.evaluations, b.nominal_seconds(*n, 1))))
        } else {
            None
        };
        let changed = || {
            let now = std::fs::read_to_string(&target).unwrap_or_default();
            let was = String::from_utf8_lossy(&base).into_owned();
            now.lines().filter(|l| !was.lines().any(|w| w == *l)).map(String::from).collect::<Vec<_>>()
        };
        if let Some((_, _, nominal)) = &budget {
            if *nominal > SECONDS as f64 {
                *tally.entry("design not run: its estimate exceeds the time limit".into()).or_default() += 1;
                std::fs::write(&target, &base).unwrap();
                std::fs::remove_file(&target).unwrap();
                let _ = std::fs::remove_dir_all(&out);
                continue;
            }
        }
        let (code, wall, kib, stderr) = bounded_run(root, &args, SECONDS, LIMIT);
        peak = peak.max(kib);
        slowest = slowest.max(wall);
        if let (Some((key, most, nominal)), Some(0 | 1)) = (&budget, code) {
            // The evaluations the search made (the placements table) within the bound printed
            // before it; the time against the nominal estimate, recorded.
            let table = std::fs::read_to_string(out.join(key).join("data/design_placements.csv")).unwrap_or_default();
            let made: u64 = table.lines().skip(1).filter_map(|l| l.rsplit(',').next()?.parse::<u64>().ok()).sum();
            let changed = changed();
            if made == 0 || made > *most {
                over.push(format!("{name} {changed:?}: {made} evaluations, the bound printed {most}"));
            }
            if wall / nominal > worst_ratio.0 {
                worst_ratio = (wall / nominal, format!("{changed:?}: {wall:.1} s against {nominal:.1} s"));
            }
        }
        let key = match code {
            Some(c @ 0..=2) => format!("exit {c}"),
            Some(c) => format!("exit {c} (unexpected)"),
            None => "killed (signal, time or memory)".into(),
        };
        *tally.entry(key.clone()).or_default() += 1;
        let message = stderr.lines().rev().find(|l| l.starts_with("error: ")).unwrap_or("");
        if std::env::var_os("FUZZ_VERBOSE").is_some() {
            println!("{name}: {key}: {message}");
        }
        let ok = match code {
            Some(0) | Some(1) => !stderr.contains("panicked"),
            Some(2) => message.contains(".toml") || message.contains("(command line)") || message.contains("out:"),
            _ => false,
        };
        if !ok {
            failures.push(format!(
                "{name} {:?}: {key} after {wall:.0} s: {}",
                changed(),
                stderr.lines().take(3).collect::<Vec<_>>().join(" / ")
            ));
        }
        if guarded {
            if std::fs::read_to_string(out.join("mine.txt")).ok().as_deref() != Some("user") {
                failures.push(format!("{name} {muts:?}: the user's file in a folder shotdamp wrote was lost"));
            }
            if code == Some(0) || code == Some(1) {
                failures.push(format!("{name} {muts:?}: ran into a folder holding a user's file"));
            }
        }
        if std::fs::read_to_string(root.join("users/thesis.tex")).ok().as_deref() != Some("precious") {
            failures.push(format!("{name} {muts:?}: the user's folder beside the output changed"));
        }
        let _ = std::fs::remove_dir_all(&out);
        std::fs::write(&target, &base).unwrap();
        if design {
            std::fs::remove_file(&target).unwrap();
        }
        if (i + 1) % 50 == 0 {
            println!(
                "after {} runs: {tally:?}; {} failures; peak {:.0} MiB",
                i + 1,
                failures.len(),
                peak as f64 / 1024.0
            );
        }
    }
    println!(
        "campaign: {n_exp} experiment files, {n_des} design files; {tally:?}; peak memory {:.0} MiB (limit {:.0} MiB); slowest run {slowest:.1} s; design searches past their bound of evaluations: {}; largest ratio of a design run's wall time to its nominal estimate {:.2} ({})",
        peak as f64 / 1024.0,
        LIMIT as f64 / 1048576.0,
        over.len(),
        worst_ratio.0,
        worst_ratio.1
    );
    for f in failures.iter().chain(&over) {
        println!("FAILURE {f}");
    }
    assert!(failures.is_empty() && over.is_empty(), "{} failures, {} past their bound", failures.len(), over.len());
}
