//! What shotdamp guarantees about files, through the binary: it replaces only folders it
//! wrote (or empty ones), never moves or deletes a user's files, cleans up after an interrupt
//! and after dead processes, and names each file and OS error once (docs/reliability.md).

mod common;

use std::path::Path;

use common::{experiments, shotdamp};

fn linear_experiments(dir: &Path) -> std::path::PathBuf {
    experiments(dir, &["fig04b_no_damper.toml"])
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Every entry of `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

#[test]
fn a_folder_of_the_users_files_is_refused_and_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let exps = linear_experiments(dir.path());
    let user = dir.path().join("thesis");
    std::fs::create_dir(&user).unwrap();
    std::fs::write(user.join("chapter1.tex"), "precious").unwrap();
    let before = entries(dir.path());
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&user).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let msg = stderr(&out);
    assert!(
        msg.contains(&user.display().to_string()) && msg.contains("did not write") && msg.contains("chapter1.tex"),
        "{msg}"
    );
    assert!(msg.contains("--out"), "says how to choose another folder: {msg}");
    assert_eq!(entries(&user), vec!["chapter1.tex"]);
    assert_eq!(std::fs::read_to_string(user.join("chapter1.tex")).unwrap(), "precious");
    assert_eq!(entries(dir.path()), before, "nothing beside it either");
}

#[test]
fn a_path_that_is_a_file_is_refused_and_the_file_kept() {
    let dir = tempfile::tempdir().unwrap();
    let exps = linear_experiments(dir.path());
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "keep me").unwrap();
    let before = entries(dir.path());
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&file).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("is a file"), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
    assert_eq!(entries(dir.path()), before, "no hidden renamed copy, no staging folder");
}

#[test]
fn a_report_replaces_its_own_folder_and_an_empty_one() {
    let dir = tempfile::tempdir().unwrap();
    let exps = linear_experiments(dir.path());
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    for _ in 0..2 {
        let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&empty).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    }
    let got = entries(&empty);
    for f in [".shotdamp-report", "README.md", "index.html", "checks.json", "fig04b_no_damper"] {
        assert!(got.iter().any(|g| g == f), "{f} in {got:?}");
    }
    // The README every report carries is the tracked one, byte for byte.
    let tracked = std::fs::read(common::repo().join("reports/README.md")).unwrap();
    assert_eq!(std::fs::read(empty.join("README.md")).unwrap(), tracked);
    assert_eq!(entries(dir.path()), vec!["empty", "experiments"], "no staging or backup folder left");
}

#[test]
fn stale_staging_folders_of_dead_processes_are_removed_live_ones_kept() {
    let dir = tempfile::tempdir().unwrap();
    let exps = linear_experiments(dir.path());
    let out_dir = dir.path().join("report");
    // A process that no longer runs (pids are below 2^22 on Linux) and this test's own.
    let dead = dir.path().join(".report.tmp-4194999");
    let live = dir.path().join(format!(".report.tmp-{}", std::process::id()));
    for d in [&dead, &live] {
        std::fs::create_dir(d).unwrap();
        std::fs::write(d.join(".shotdamp-report"), "x").unwrap();
    }
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&out_dir).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(!dead.exists(), "the dead process's staging folder is removed");
    assert!(live.exists(), "a live process's staging folder is kept");
}

#[cfg(target_os = "linux")]
#[test]
fn ctrl_c_removes_the_staging_folder_and_keeps_the_previous_report() {
    let dir = tempfile::tempdir().unwrap();
    let exps = experiments(dir.path(), &["fig04b_no_damper.toml", "fig08_number_of_dampers.toml"]);
    let out_dir = dir.path().join("report");
    let first = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&out_dir).output().unwrap();
    assert!(first.status.code().is_some(), "{}", stderr(&first));
    let index = std::fs::read(out_dir.join("index.html")).unwrap();
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("shotdamp"))
        .current_dir(common::repo())
        .arg("--experiments")
        .arg(&exps)
        .arg("report")
        .arg("--out")
        .arg(&out_dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let staging = dir.path().join(format!(".report.tmp-{}", child.id()));
    let started = std::time::Instant::now();
    while !staging.exists() && started.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert!(staging.exists(), "the run writes into a staging folder");
    std::process::Command::new("kill").arg("-INT").arg(child.id().to_string()).status().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "exit 128 + SIGINT");
    assert!(!staging.exists(), "the staging folder is removed");
    assert_eq!(std::fs::read(out_dir.join("index.html")).unwrap(), index, "the previous report is intact");
}

#[test]
fn a_missing_file_is_named_once_with_its_os_error_once() {
    let out = shotdamp().arg("run").arg("no-such-experiment.toml").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let msg = stderr(&out);
    assert_eq!(msg.matches("no-such-experiment.toml").count(), 1, "{msg}");
    assert_eq!(msg.matches("No such file or directory").count(), 1, "{msg}");
}
