//! Studies through the binary: sharded runs merge to the unsharded table byte for byte, a
//! killed shard resumes, a one-point study gives the experiment's own check values, and bad
//! input is named.

use crate::common;

use std::path::{Path, PathBuf};

use common::{csv_rows, repo, shotdamp};

/// A small study: Fig. 5 on the stated chain at 2 damping ratios x 3 clearances, 31 frequencies.
fn small_study(dir: &Path, damping: &[f64]) -> PathBuf {
    let file = dir.join("small.toml");
    let experiment = repo().join("experiments/fig05_third_mode.toml");
    std::fs::write(
        &file,
        format!(
            r#"[study]
id = "small"
title = "Fig. 5, small"
experiment = "{}"
models = ["stated"]

[study.set]
"analysis.freq_hz" = {{ start = 45.0, stop = 51.0, step = 0.2 }}

[[vary]]
name = "damping"
key = "structure.damping.modal_ratios"
values = {damping:?}

[[vary]]
name = "clearance_mm"
key = "cases[*].dampers[*].clearance_mm"
range = {{ start = 0.2, stop = 0.4, count = 3 }}
"#,
            experiment.display()
        ),
    )
    .unwrap();
    file
}

fn study(args: &[&str]) -> std::process::Output {
    shotdamp().arg("study").args(args).output().unwrap()
}

fn ok(out: &std::process::Output) -> String {
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_eq!(out.status.code(), Some(0), "{text}");
    text
}

#[test]
fn sharded_runs_merge_to_the_unsharded_table() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), &[0.005, 0.01]);
    let f = file.to_str().unwrap();
    let whole = dir.path().join("whole");
    ok(&study(&[f, "--out", whole.to_str().unwrap()]));
    let expected = std::fs::read(whole.join("small.csv")).unwrap();
    let rows = csv_rows(&String::from_utf8_lossy(&expected));
    assert_eq!(rows.len(), 1 + 6 * 3, "6 samples x 3 readings");
    assert!(whole.join("figures/small_check-0.png").is_file());
    for n in [1usize, 3, 7] {
        let out = dir.path().join(format!("n{n}"));
        for i in 0..n {
            // Separate processes, one thread each, as on a cluster.
            ok(&study(&[f, "--shard", &format!("{i}/{n}"), "--out", out.to_str().unwrap(), "--jobs", "1"]));
        }
        ok(&study(&["merge", out.to_str().unwrap()]));
        assert_eq!(std::fs::read(out.join("small.csv")).unwrap(), expected, "N = {n}");
        assert_eq!(
            std::fs::read(out.join("small_summary.csv")).unwrap(),
            std::fs::read(whole.join("small_summary.csv")).unwrap()
        );
    }
    // The environment of a Slurm array task and of a Kubernetes Indexed Job pick the shard.
    let slurm = dir.path().join("slurm");
    for i in 0..2 {
        let out = shotdamp()
            .env("SLURM_ARRAY_TASK_ID", i.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .args(["study", f, "--out", slurm.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(ok(&out).contains(&format!("shard {i}/2")));
    }
    let k8s = dir.path().join("k8s");
    for i in 0..2 {
        let out = shotdamp()
            .env("JOB_COMPLETION_INDEX", i.to_string())
            .args(["study", f, "--shards", "2", "--out", k8s.to_str().unwrap()])
            .output()
            .unwrap();
        ok(&out);
    }
    for d in [&slurm, &k8s] {
        ok(&study(&["merge", d.to_str().unwrap()]));
        assert_eq!(std::fs::read(d.join("small.csv")).unwrap(), expected);
    }
}

#[test]
fn a_missing_shard_is_named_and_a_killed_shard_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), &[0.003, 0.005, 0.008, 0.01]);
    let f = file.to_str().unwrap();
    let whole = dir.path().join("whole");
    ok(&study(&[f, "--out", whole.to_str().unwrap(), "--jobs", "2"]));
    let expected = std::fs::read(whole.join("small.csv")).unwrap();

    let out = dir.path().join("parts");
    let o = out.to_str().unwrap();
    // Shard 1/2 only: the merge names shard 0/2.
    ok(&study(&[f, "--shard", "1/2", "--out", o, "--jobs", "1"]));
    let m = study(&["merge", o]);
    let err = String::from_utf8_lossy(&m.stderr);
    assert_eq!(m.status.code(), Some(2), "{err}");
    assert!(err.contains("6 of 12 samples are missing") && err.contains("shards 0/2 have not finished"), "{err}");

    // Shard 0/2 (6 samples, batches of 4 with one thread): killed once its first batch is on
    // disk, then run again.
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("shotdamp"))
        .current_dir(repo())
        .args(["study", f, "--shard", "0/2", "--out", o, "--jobs", "1"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Its batches go to parts/shard-0000-of-0002-FINGERPRINT/.
    let batches = || {
        std::fs::read_dir(out.join("parts"))
            .ok()?
            .filter_map(|e| e.ok())
            .find(|e| e.file_name().to_string_lossy().starts_with("shard-0000-of-0002-"))
            .map(|e| e.path())
    };
    let started = std::time::Instant::now();
    let written = || {
        batches()
            .and_then(|b| std::fs::read_dir(b).ok())
            .map(|d| d.filter_map(|e| e.ok()).any(|e| !e.file_name().to_string_lossy().starts_with('.')))
            .unwrap_or(false)
    };
    while !written() && started.elapsed().as_secs() < 120 {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let finished_alone = child.try_wait().unwrap().is_some();
    child.kill().ok();
    child.wait().unwrap();
    assert!(!finished_alone, "the shard finished before its first batch was seen: nothing was resumed");
    let text = ok(&study(&[f, "--shard", "0/2", "--out", o, "--jobs", "1"]));
    assert!(text.contains("resuming: 4 of 6 samples already written"), "{text}");
    ok(&study(&["merge", o]));
    assert_eq!(std::fs::read(out.join("small.csv")).unwrap(), expected);
    // A finished shard run again does nothing.
    assert!(ok(&study(&[f, "--shard", "1/2", "--out", o])).contains("already complete"));
}

#[test]
fn a_one_point_study_gives_the_experiments_own_check_values() {
    let dir = tempfile::tempdir().unwrap();
    // Fig. 5 on the stated chain at its own values: the clearance comes from the clearance
    // scan, which the study runs as the experiment does.
    let file = dir.path().join("one.toml");
    let experiment = repo().join("experiments/fig05_third_mode.toml");
    std::fs::write(
        &file,
        format!(
            "[study]\nid = \"one\"\ntitle = \"t\"\nexperiment = \"{}\"\nmodels = [\"stated\"]\n[[vary]]\nname = \"force_n\"\nkey = \"excitation.force_n\"\nvalues = [2.6]\n",
            experiment.display()
        ),
    )
    .unwrap();
    let st = dir.path().join("st");
    ok(&study(&[file.to_str().unwrap(), "--out", st.to_str().unwrap()]));
    let rows = csv_rows(&std::fs::read_to_string(st.join("one.csv")).unwrap());
    let col = |n: &str| rows[0].iter().position(|h| h == n).unwrap();

    let run = dir.path().join("run");
    let out = shotdamp()
        .args(["run", "experiments/fig05_clearance_scan.toml", "experiments/fig05_third_mode.toml", "--out"])
        .arg(&run)
        .output()
        .unwrap();
    assert!(out.status.code().is_some_and(|c| c <= 1), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(run.join("checks.json")).unwrap()).unwrap();
    let own: Vec<&serde_json::Value> = json["checks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["experiment"] == "fig05_third_mode" && c["model"] == "stated")
        .collect();
    assert_eq!(rows.len() - 1, 3);
    for r in &rows[1..] {
        let c = own.iter().find(|c| c["name"].as_str() == Some(r[col("claim")].as_str())).unwrap();
        let v: f64 = r[col("value")].parse().unwrap();
        // Exactly: the same run, the same f64.
        assert_eq!(v, c["computed"].as_f64().unwrap(), "{}", r[col("claim")]);
        let passes = matches!(c["status"].as_str(), Some("pass" | "known_deviation_passes"));
        assert_eq!(r[col("outcome")] == "holds", passes);
        assert_eq!(r[col("outcome")] == "not evaluable", !v.is_finite());
    }
}

#[test]
fn bad_studies_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), &[0.01]);
    let text = std::fs::read_to_string(&file).unwrap();
    for (from, to, expect) in [
        ("structure.damping.modal_ratios", "structure.dampin.modal_ratios", "no key \"dampin\""),
        ("values = [0.01]", "values = []", "vary[0].values"),
        (
            "cases[*].dampers[*].clearance_mm",
            "cases[two].dampers[*].clearance_mm",
            "no element of \"cases\" has id \"two\"",
        ),
        ("values = [0.01]", "values = [-0.5]", "sample 0"),
        ("models = [\"stated\"]", "models = [\"measured\"]", "study.models"),
        ("id = \"small\"", "id = \"small\"\ndesign = \"sobol\"", "needs the number of samples"),
    ] {
        let bad = dir.path().join("bad.toml");
        std::fs::write(&bad, text.replace(from, to)).unwrap();
        let out = study(&[bad.to_str().unwrap(), "--out", dir.path().join("x").to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{to}: {err}");
        assert!(err.contains(expect) && err.contains("bad.toml"), "{to}: {err}");
        assert!(!dir.path().join("x").exists(), "nothing written for bad input");
    }
    let f = file.to_str().unwrap();
    for shard in ["3/3", "1", "a/b"] {
        let out = study(&[f, "--shard", shard]);
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains("--shard"));
    }
    // --dry-run lists the samples and writes nothing.
    let st = dir.path().join("st");
    let listed = ok(&study(&[f, "--out", st.to_str().unwrap(), "--dry-run", "--shard", "1/2"]));
    assert!(listed.contains("3 samples") && listed.contains("shard 1/2: 1 samples"), "{listed}");
    assert_eq!(listed.lines().filter(|l| l.contains("stated")).count(), 3, "{listed}");
    assert!(!st.exists());
    // A folder of another study is refused.
    ok(&study(&[f, "--out", st.to_str().unwrap()]));
    std::fs::create_dir_all(dir.path().join("o")).unwrap();
    let other = small_study(&dir.path().join("o"), &[0.005]);
    let out = study(&[other.to_str().unwrap(), "--out", st.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("holds parts of another study"), "{err}");
}

#[test]
fn the_experiments_own_values_are_read_from_its_file_and_the_exports_it_uses() {
    let root = repo();
    let s =
        shotdamp::experiment::study::load(&root.join("studies/fig05_report.toml"), &root.join("reference")).unwrap();
    // Damping from the model file; the clearance from the scan's export on the same model.
    let mut exports = shotdamp::experiment::Exports::new();
    exports.insert("fig05_clearance_scan/fitted".into(), [("best_clearance_mm".to_string(), 0.35)].into());
    assert_eq!(s.assumed("fitted", &exports), vec![Some(0.01), Some(0.35)]);
    // The scan of another model does not stand in for this one's.
    assert_eq!(s.assumed("stated", &exports), vec![Some(0.01), None]);
    assert_eq!(s.assumed("no such model", &exports), vec![None, None]);
}
