//! What shotdamp guarantees about files, through the binary: it replaces only folders it
//! wrote (or empty ones), never moves or deletes a user's files, cleans up after an interrupt
//! and after dead processes, and names each file and OS error once (docs/reliability.md).

use crate::common;

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

/// An input that is not a regular file (a device that never ends, a folder) is refused at
/// once, named, exit 2: reading /dev/zero filled the memory until the system killed shotdamp.
#[test]
fn an_input_that_is_not_a_regular_file_is_refused_at_once() {
    let zero = Path::new("/dev/zero");
    if !zero.exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for input in [zero, dir.path()] {
        let run = shotdamp().arg("run").arg(input).arg("--out").arg(&out).output().unwrap();
        let err = stderr(&run);
        assert_eq!(run.status.code(), Some(2), "{err}");
        assert!(err.contains(&format!("{}: not a regular file", input.display())), "{err}");
    }
    // A finite-element file named in an experiment.
    let exp = dir.path().join("fe.toml");
    let text = "[experiment]\nid = \"fe\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"/dev/zero\"\nmass = \"/dev/zero\"\nup = \"x\"\npoints = [{ row = 1 }]\nmodes = 0\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 1.0\n[analysis]\nkind = \"modal\"\n";
    std::fs::write(&exp, text).unwrap();
    let run = shotdamp().arg("run").arg(&exp).arg("--out").arg(&out).output().unwrap();
    let err = stderr(&run);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(
        err.contains("structure.finite_element.stiffness = \"/dev/zero\": cannot be read (not a regular file"),
        "{err}"
    );
    // A file an experiment extends.
    std::fs::write(&exp, "extends = \"/dev/zero\"\n").unwrap();
    let run = shotdamp().arg("run").arg(&exp).arg("--out").arg(&out).output().unwrap();
    let err = stderr(&run);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(err.contains("extends = \"/dev/zero\": not a regular file"), "{err}");
}

#[test]
fn a_missing_file_is_named_once_with_its_os_error_once() {
    let out = shotdamp().arg("run").arg("no-such-experiment.toml").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let msg = stderr(&out);
    assert_eq!(msg.matches("no-such-experiment.toml").count(), 1, "{msg}");
    assert_eq!(msg.matches("No such file or directory").count(), 1, "{msg}");
}

/// A copy of `reference/` in `dir` with `file` rewritten by `edit` (rows as CSV cells).
fn corrupted_reference(dir: &Path, file: &str, edit: impl Fn(&mut Vec<Vec<String>>)) -> std::path::PathBuf {
    let refs = dir.join("reference");
    common::copy_tree(&common::repo().join("reference"), &refs);
    let path = refs.join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut rows: Vec<Vec<String>> = text.lines().map(|l| l.split(',').map(str::to_string).collect()).collect();
    edit(&mut rows);
    let out: Vec<String> = rows.iter().map(|r| r.join(",")).collect();
    std::fs::write(&path, out.join("\n") + "\n").unwrap();
    refs
}

/// Runs the Fig. 8 experiment against a reference folder; exit code and stderr.
fn fig08_with(refs: &Path, dir: &Path) -> (Option<i32>, String) {
    let out = shotdamp()
        .arg("--reference")
        .arg(refs)
        .arg("run")
        .arg("experiments/fig08_number_of_dampers.toml")
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    (out.status.code(), stderr(&out))
}

#[test]
fn a_corrupted_reference_curve_is_an_input_error_naming_file_line_column_and_value() {
    let file = "independent-solver/P_dinf_N3.csv";
    type Edit = Box<dyn Fn(&mut Vec<Vec<String>>)>;
    let cases: Vec<(&str, Edit, &[&str])> = vec![
        (
            "a word in c2",
            Box::new(|r| r[10][2] = "abc".into()),
            &["line 11", "column c2", "\"abc\"", "a finite number"],
        ),
        ("nan in c1", Box::new(|r| r[20][1] = "nan".into()), &["line 21", "column c1", "finite"]),
        ("inf in c3", Box::new(|r| r[5][3] = "inf".into()), &["line 6", "column c3", "finite"]),
        ("an empty cell", Box::new(|r| r[7][1] = String::new()), &["line 8", "column c1"]),
        (
            "c2 and c3 deleted",
            Box::new(|r| r.iter_mut().for_each(|row| drop(row.drain(2..4)))),
            &["needs the columns", "c2", "c3"],
        ),
        (
            "a duplicated row",
            Box::new(|r| {
                let dup = r[29].clone();
                r.insert(30, dup)
            }),
            &["line 31", "freq_hz", "increase strictly"],
        ),
        ("converged = 2", Box::new(|r| r[40][4] = "2".into()), &["line 41", "converged", "0 or 1"]),
        ("period 1.5", Box::new(|r| r[40][5] = "1.5".into()), &["line 41", "period", "whole number"]),
    ];
    for (what, edit, words) in cases {
        let dir = tempfile::tempdir().unwrap();
        let refs = corrupted_reference(dir.path(), file, edit);
        let (code, msg) = fig08_with(&refs, dir.path());
        assert_eq!(code, Some(2), "{what}: {msg}");
        assert!(msg.contains("P_dinf_N3.csv"), "{what}: names the file: {msg}");
        for w in words {
            assert!(msg.contains(w), "{what}: says {w:?}: {msg}");
        }
        assert!(!dir.path().join("out").exists(), "{what}: no report is written");
    }
}

#[test]
fn non_finite_paper_values_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let refs = dir.path().join("reference");
    common::copy_tree(&common::repo().join("reference"), &refs);
    let path = refs.join("paper-text.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let (head, tail) = text.split_once("value = ").unwrap();
    let rest = tail.split_once('\n').unwrap().1;
    std::fs::write(&path, format!("{head}value = nan\n{rest}")).unwrap();
    let (code, msg) = fig08_with(&refs, dir.path());
    assert_eq!(code, Some(2), "{msg}");
    assert!(
        msg.contains("paper-text.toml") && msg.contains(".value = NaN") && msg.contains("a finite number"),
        "{msg}"
    );
}

/// An experiment with one bed on m2 over `freq_hz` on the stated chain, with `extra` TOML
/// (structure overrides)
/// and the bed's `mass` and `clearance`.
fn extreme(dir: &Path, id: &str, extra: &str, freq_hz: &str, mass: &str, clearance: &str) -> std::path::PathBuf {
    let exps = experiments(dir, &[]);
    let text = format!(
        "extends = \"shared/paper_structure.toml\"\nmodels = [\"shared/models/stated.toml\"]\n{extra}\n[experiment]\nid = \"{id}\"\ntitle = \"{id}\"\nfigure = \"test\"\ncaption = \"-\"\nclaim = \"-\"\n\n[analysis]\nkind = \"sweep\"\nfreq_hz = {freq_hz}\n\n[[cases]]\nid = \"one\"\nlabel = \"one bed\"\ndampers = [{{ mass = 2, {mass}, clearance_mm = {clearance} }}]\n\n[[plots]]\nid = \"c\"\nkind = \"compliance_panels\"\nmasses = [1, 2]\n"
    );
    std::fs::write(exps.join(format!("{id}.toml")), text).unwrap();
    exps
}

#[test]
fn extreme_physics_ends_every_point_with_a_result_or_a_reason() {
    let band = "{ start = 44.0, stop = 56.0, points = 4 }";
    let cases = [
        (
            "zeta0",
            "[structure.damping]\nmodal_ratios = [0.0, 0.0, 0.0]\nassumption = \"none\"",
            band,
            "mass_ratio = 0.1",
            "0.3",
        ),
        ("heavy", "[structure]\nmasses_kg = [0.74, 1e300, 0.64]", band, "mass_ratio = 0.1", "0.3"),
        ("big_bed", "", band, "mass_ratio = 50.0", "0.3"),
        ("tiny_clearance", "", band, "mass_ratio = 0.1", "1e-9"),
        ("millihertz", "", "{ start = 0.001, stop = 0.004, points = 4 }", "mass_ratio = 0.1", "0.3"),
        ("hundred_khz", "", "{ start = 25000.0, stop = 100000.0, points = 4 }", "mass_ratio = 0.1", "0.3"),
    ];
    for (id, extra, band, mass, clearance) in cases {
        let dir = tempfile::tempdir().unwrap();
        let exps = extreme(dir.path(), id, extra, band, mass, clearance);
        let out_dir = dir.path().join("out");
        let started = std::time::Instant::now();
        let out = shotdamp()
            .arg("--experiments")
            .arg(&exps)
            .arg("run")
            .arg(exps.join(format!("{id}.toml")))
            .arg("--out")
            .arg(&out_dir)
            .output()
            .unwrap();
        // A structure no point of which can be computed is a failed check (exit 1) and a
        // warning that names the configuration and the cause, never a page that passes.
        let want = if id == "heavy" { 1 } else { 0 };
        assert_eq!(out.status.code(), Some(want), "{id}: {}", stderr(&out));
        if id == "heavy" {
            let said = String::from_utf8_lossy(&out.stdout);
            assert!(
                said.contains("no point of the sweep could be computed: configuration 0b0: numerically singular"),
                "{said}"
            );
        }
        assert!(started.elapsed().as_secs() < 60, "{id}: bounded ({:?})", started.elapsed());
        let table = std::fs::read_to_string(out_dir.join(id).join("stated/data/compliance.csv")).unwrap();
        let mut lines = table.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let (c1, conv, stop) = (col("c1"), col("converged"), col("stop"));
        for line in lines {
            let cells: Vec<&str> = line.split(',').collect();
            let c: f64 = cells[c1].parse().unwrap_or(f64::NAN);
            if cells[conv] == "1" {
                assert!(c.is_finite() && c > 0.0 && c < 1.0, "{id}: a result is a plausible compliance: {line}");
            } else {
                assert!(!cells[stop].trim_matches('"').is_empty(), "{id}: an unsettled point says why: {line}");
            }
            if id == "heavy" {
                assert!(line.contains("numerically singular"), "{id}: {line}");
            }
            if id == "millihertz" {
                assert!((c - 4.115e-5).abs() < 1e-7, "{id}: quasi-static compliance {c}");
            }
        }
    }
}

/// `compare A B --out A` (or a folder inside A, or one that contains A) would write into one
/// of its own inputs: refused before anything is written, A left byte for byte.
#[test]
fn no_command_writes_into_its_own_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let exps = linear_experiments(dir.path());
    let a = dir.path().join("a");
    let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&a).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let snapshot = |d: &Path| {
        let mut v: Vec<(String, Vec<u8>)> = Vec::new();
        let mut stack = vec![d.to_path_buf()];
        while let Some(p) = stack.pop() {
            for e in std::fs::read_dir(&p).unwrap() {
                let e = e.unwrap().path();
                if e.is_dir() {
                    stack.push(e);
                } else {
                    v.push((e.display().to_string(), std::fs::read(&e).unwrap()));
                }
            }
        }
        v.sort();
        v
    };
    let before = snapshot(&a);
    let spelled_otherwise = dir.path().join("a/../a");
    for target in [a.clone(), a.join("sub"), spelled_otherwise, dir.path().to_path_buf()] {
        let out = shotdamp().arg("compare").arg(&a).arg(&a).arg("--out").arg(&target).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}: {}", target.display(), stderr(&out));
        assert!(
            stderr(&out).contains("REPORT_A") && stderr(&out).contains("never writes into its own inputs"),
            "{}",
            stderr(&out)
        );
        assert_eq!(snapshot(&a), before, "{} left A as it was", target.display());
    }
    // A report into the experiments folder it reads, or into the reference folder.
    for target in [exps.join("out"), common::repo().join("reference/out")] {
        let out = shotdamp().arg("--experiments").arg(&exps).arg("report").arg("--out").arg(&target).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains("lies inside"), "{}", stderr(&out));
        assert!(!target.exists());
    }
}

/// A study value that makes an export impossible (m1 = 1e300 kg: every configuration is
/// numerically singular, so the Fig. 5 clearance scan finds no best clearance) stops the study
/// before any sample runs, naming the first such sample and its values, the same for one thread
/// and two. (m1 = 0.2 kg did so until structures with repeated natural frequencies were
/// simulated: it gives the fitted model three equal ones, 37.18 Hz.)
#[test]
fn a_study_value_that_breaks_an_export_is_named_up_front_for_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("masses.toml");
    std::fs::write(
        &file,
        format!(
            r#"[study]
id = "masses"
title = "Fig. 5 over the first mass"
experiment = "{}"
models = ["fitted"]

[study.set]
"analysis.freq_hz" = {{ start = 46.0, stop = 48.0, step = 0.5 }}
"structure.damping.modal_ratios" = 0.003

[[vary]]
name = "m1"
key = "structure.masses_kg[0]"
values = [0.74, 1e300, 0.5]
"#,
            common::repo().join("experiments/fig05_third_mode.toml").display()
        ),
    )
    .unwrap();
    let mut messages = Vec::new();
    for jobs in ["1", "2"] {
        let out_dir = dir.path().join(format!("out{jobs}"));
        let out =
            shotdamp().args(["study", file.to_str().unwrap(), "--jobs", jobs, "--out"]).arg(&out_dir).output().unwrap();
        let msg = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{msg}");
        assert!(msg.contains("sample 1 of study") && msg.contains("m1 1.00000e300"), "{msg}");
        assert!(!out_dir.exists(), "nothing written: {msg}");
        messages.push(msg);
    }
    assert_eq!(messages[0], messages[1]);
}

/// A relative tolerance of 1e300 (a user "disabling" a check) used to hang the plotting of the
/// residuals; tolerances are bounded where they are read.
#[test]
fn absurd_tolerances_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let exps = experiments(dir.path(), &["fig08_number_of_dampers.toml"]);
    let file = exps.join("fig08_number_of_dampers.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    for (from, to, expect) in [
        ("rel_tol = 1e-6", "rel_tol = 1e300", "checks[0].rel_tol = 1.00000e300: a relative tolerance lies in [0, 10]"),
        (
            "rel_tol_all = 1e-2",
            "rel_tol_all = 1e295",
            "rel_tol_all = 1.00000e295: a relative tolerance lies in [0, 10]",
        ),
    ] {
        std::fs::write(&file, text.replacen(from, to, 1)).unwrap();
        let out = shotdamp()
            .arg("--experiments")
            .arg(&exps)
            .args(["run", file.to_str().unwrap(), "--out"])
            .arg(dir.path().join("o"))
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(expect), "{}", stderr(&out));
    }
}

/// Every entry below `dir` with its bytes (files) or nothing (folders), sorted.
fn tree(dir: &Path) -> Vec<(String, Option<Vec<u8>>)> {
    let mut v = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(p) = stack.pop() {
        for e in std::fs::read_dir(&p).unwrap() {
            let e = e.unwrap().path();
            let rel = e.strip_prefix(dir).unwrap().display().to_string();
            if e.is_dir() {
                stack.push(e);
                v.push((rel, None));
            } else {
                v.push((rel, Some(std::fs::read(&e).unwrap())));
            }
        }
    }
    v.sort();
    v
}

/// A file or folder a user puts into a folder shotdamp wrote is never deleted: the next run
/// into it is refused (exit 2, naming what it found) and leaves the folder as it was; once
/// they are moved away, the run replaces the folder. The same for `compare --out`.
#[test]
fn a_users_entry_inside_a_folder_shotdamp_wrote_is_never_deleted() {
    let dir = tempfile::tempdir().unwrap();
    let exps = linear_experiments(dir.path());
    let file = exps.join("fig04b_no_damper.toml");
    let a = dir.path().join("a");
    let run = || shotdamp().arg("run").arg(&file).arg("--out").arg(&a).output().unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    std::fs::write(a.join("mynotes.txt"), "precious").unwrap();
    std::fs::create_dir(a.join("fig04b_no_damper/mine")).unwrap();
    std::fs::write(a.join("fig04b_no_damper/mine/keep.txt"), "x").unwrap();
    let before = tree(&a);
    let out = run();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let msg = stderr(&out);
    assert!(
        msg.contains("2 entries that shotdamp did not write: fig04b_no_damper/mine/, mynotes.txt")
            && msg.contains("never deletes"),
        "{msg}"
    );
    assert_eq!(tree(&a), before, "the folder is left as it was, the user's entries in it");
    // A file put in while nothing else is there: refused as well.
    std::fs::remove_dir_all(a.join("fig04b_no_damper/mine")).unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("1 entry that shotdamp did not write: mynotes.txt"), "{}", stderr(&out));
    std::fs::rename(a.join("mynotes.txt"), dir.path().join("mynotes.txt")).unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // compare A B --out C, with a user's file in C (a comparison written before).
    let c = dir.path().join("c");
    let compare = || shotdamp().arg("compare").arg(&a).arg(&a).arg("--out").arg(&c).output().unwrap();
    assert_eq!(compare().status.code(), Some(0));
    std::fs::write(c.join("review.md"), "my review").unwrap();
    let out = compare();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("review.md"), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(c.join("review.md")).unwrap(), "my review");
    // A report folder of an earlier version (the marker, no list of its files) with more
    // than the marker and the README is refused too, and says why.
    std::fs::remove_file(a.join(".shotdamp-files")).unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("a report of an earlier version"), "{}", stderr(&out));
}

/// Inputs that would make the run unbounded are refused up front with the key, the value
/// and what is allowed: an impulse's kick, `--jobs`, a structure larger than the simulator
/// takes, a design band of 100,000 points, a repeated Pareto ratio.
#[test]
fn unbounded_inputs_are_refused_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let exps = experiments(dir.path(), &["fig10b_impulse.toml", "fig04b_no_damper.toml"]);
    let impulse = exps.join("fig10b_impulse.toml");
    let text = std::fs::read_to_string(&impulse).unwrap();
    for (kick, key) in [
        ("initial_velocity_m_s = 1e200", "analysis.initial_velocity_m_s = 1.00000e200"),
        ("impulse_n_s = 1e160", "analysis.impulse_n_s = 1.00000e160"),
        ("initial_velocity_m_s = 1e-9", "analysis.initial_velocity_m_s = 1.00000e-9"),
    ] {
        std::fs::write(&impulse, text.replace("initial_velocity_m_s = 0.5", kick)).unwrap();
        let out = shotdamp().arg("run").arg(&impulse).arg("--out").arg(dir.path().join("o")).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{kick}: {}", stderr(&out));
        assert!(stderr(&out).contains(key) && stderr(&out).contains("[1e-6, 100] m/s"), "{}", stderr(&out));
    }
    let linear = exps.join("fig04b_no_damper.toml");
    for jobs in ["100000", "0"] {
        let out = shotdamp().arg("run").arg(&linear).arg("--jobs").arg(jobs).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(&format!("--jobs = {jobs}: give 1 to")), "{}", stderr(&out));
    }
    // 257 masses: the simulator's kinds refuse them, the linear ones take them; 64 masses take
    // 9 containers, not 10 (the decompositions of 2^10 configurations of 128 terms).
    let chain = |n: usize, beds: usize, kind: &str| {
        let list = |v: &str| vec![v; n].join(", ");
        let dampers: Vec<String> =
            (0..beds).map(|j| format!("{{ mass = {}, mass_ratio = 0.1, clearance_mm = 1.0 }}", n - j)).collect();
        format!(
            "[experiment]\nid = \"big\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure]\nmasses_kg = [{}]\nchain_stiffness_n_per_m = [{}]\n[structure.damping]\nmodal_ratios = [{}]\n[excitation]\nmass = 1\nforce_n = 2.0\n[analysis]\nkind = \"{kind}\"\nfreq_hz = {{ start = 5.0, stop = 6.0, step = 0.5 }}\n[[cases]]\nid = \"a\"\nlabel = \"a\"\ndampers = [{}]\n",
            list("1.0"),
            list("2e4"),
            list("0.02"),
            dampers.join(", ")
        )
    };
    let big = dir.path().join("big.toml");
    for (n, beds, key, says) in [
        (
            257,
            1,
            "structure.masses_kg = 257 masses",
            "analysis kind \"sweep\" runs the exact simulator, which takes at most 256 degrees of freedom",
        ),
        (
            64,
            10,
            "cases[0].dampers = 10 single beds (1024 configurations)",
            "at most 512 configurations on 64 degrees of freedom",
        ),
    ] {
        std::fs::write(&big, chain(n, beds, "sweep")).unwrap();
        let out = shotdamp().arg("run").arg(&big).arg("--out").arg(dir.path().join("m")).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(&format!("{key}: ")) && stderr(&out).contains(says), "{}", stderr(&out));
        assert!(!dir.path().join("m").exists(), "nothing written");
    }
    std::fs::write(&big, chain(257, 1, "linear_frf")).unwrap();
    let out = shotdamp().arg("run").arg(&big).arg("--out").arg(dir.path().join("m")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // 64 masses with three containers: the simulator runs them (every point a certified orbit).
    std::fs::write(&big, chain(64, 3, "sweep")).unwrap();
    let out = shotdamp().arg("run").arg(&big).arg("--out").arg(dir.path().join("m64")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let table = std::fs::read_to_string(dir.path().join("m64/big/data/compliance.csv")).unwrap();
    let rows = common::csv_rows(&table);
    let col = |name: &str| rows[0].iter().position(|c| c == name).unwrap();
    assert_eq!(rows.len(), 4, "a header and three frequencies");
    assert!(rows[1..].iter().all(|r| r[col("converged")] == "1" && r[col("stop")].is_empty()), "{table}");
    // Designs: a band of 100,000 points, a repeated Pareto ratio; a dry run prints what a
    // search usually costs and the most it can, and searches nothing.
    let design = dir.path().join("five_storey.toml");
    let text = std::fs::read_to_string(common::repo().join("designs/five_storey.toml")).unwrap();
    for (edit, said) in [
        (
            text.replace("start = 5.0, stop = 8.0, step = 0.1", "start = 5.0, stop = 8.0, points = 100000"),
            "design.bands[0].freq_hz = 100000 frequencies: a design band has at most 1000",
        ),
        (
            text.replace("max_beds = 2", "max_beds = 2\npareto_mass_ratios = [0.02, 0.05, 0.02]"),
            "design.pareto_mass_ratios[2] = 0.02: repeats design.pareto_mass_ratios[0]",
        ),
        (
            text.replace("max_beds = 2", "max_beds = 2\nmax_iters = 1e9"),
            "design.max_iters = 1000000000: give a whole number from 1 to 10000",
        ),
        (
            // 64 masses: at most 9 containers at once (2^9 configurations of 64 terms).
            text.replace("[1.0, 1.0, 1.0, 1.0, 1.0]", &format!("[{}]", ["1.0"; 64].join(", ")))
                .replace("[20000.0, 20000.0, 20000.0, 20000.0, 20000.0]", &format!("[{}]", ["20000.0"; 64].join(", ")))
                .replace("[0.02, 0.02, 0.02, 0.02, 0.02]", &format!("[{}]", ["0.02"; 64].join(", ")))
                .replace("candidates = [1, 2, 3, 4, 5]", "candidates = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]")
                .replace("max_beds = 2", "max_beds = 10"),
            "design.max_beds = 10: at most 9 containers at once on 64 degrees of freedom",
        ),
    ] {
        std::fs::write(&design, edit).unwrap();
        let out = shotdamp().arg("design").arg(&design).arg("--dry-run").output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(said), "{}", stderr(&out));
    }
    std::fs::write(&design, &text).unwrap();
    let out =
        shotdamp().arg("design").arg(&design).arg("--dry-run").arg("--out").arg(dir.path().join("d")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("design design_five_storey: 15 placements x 1 search(es), usually")
            // 16752 searched and judged, and 10 for the default drive levels (5 forces, the
            // best layout and the file's one case).
            && said.contains("(at most 16762) of 114 steady states each"),
        "{said}"
    );
    assert!(!dir.path().join("d").exists(), "a dry run writes nothing");
}

/// Messages quote values as a person reads them: no `Some(..)`, no 320-digit decimal, the
/// range of a whole number, the output folder as given.
#[test]
fn messages_quote_values_as_given() {
    let dir = tempfile::tempdir().unwrap();
    let exps =
        experiments(dir.path(), &["fig04b_no_damper.toml", "fig05_clearance_scan.toml", "fig05_hysteresis.toml"]);
    let nowhere = dir.path().join("never-written");
    let fig04 = exps.join("fig04b_no_damper.toml");
    let text = std::fs::read_to_string(&fig04).unwrap();
    std::fs::write(&fig04, text.replace("figure = \"Fig. 4(b)\"", "figure = 1e-320")).unwrap();
    let out = shotdamp().arg("run").arg(&fig04).arg("--out").arg(&nowhere).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("experiment.figure: invalid type: floating point `9.99989e-321`"),
        "{}",
        stderr(&out)
    );
    std::fs::write(&fig04, &text).unwrap();
    let scan = exps.join("fig05_clearance_scan.toml");
    let scan_text = std::fs::read_to_string(&scan).unwrap();
    std::fs::write(&scan, scan_text.replacen("clearance_mm = 0.1\n", "clearance_mm = 0.12\n", 1)).unwrap();
    let out = shotdamp().arg("run").arg(&scan).arg("--out").arg(&nowhere).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("checks[0].clearance_mm = 0.12: name one of the clearances"), "{}", stderr(&out));
    let hysteresis = exps.join("fig05_hysteresis.toml");
    let h = std::fs::read_to_string(&hysteresis).unwrap();
    std::fs::write(&hysteresis, h.replacen("direction = \"up\"\n", "", 1)).unwrap();
    let out = shotdamp().arg("run").arg(&hysteresis).arg("--out").arg(&nowhere).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains(".direction = (missing): a continuation sweep"), "{}", stderr(&out));
    assert!(!nowhere.exists());
    // The output folder as given on the command line (relative), not made absolute.
    std::fs::create_dir(dir.path().join("mine")).unwrap();
    std::fs::write(dir.path().join("mine/notes.txt"), "x").unwrap();
    let reference = common::repo().join("reference");
    let out = shotdamp()
        .current_dir(dir.path())
        .arg("--reference")
        .arg(&reference)
        .arg("run")
        .arg(&fig04)
        .arg("--out")
        .arg("mine")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).starts_with("error: mine: is a folder that shotdamp did not write"), "{}", stderr(&out));
}

/// `freq_hz = [47.0, 48.0, 50]` is three frequencies (it was read as a table's fields in order:
/// a grid of 50 points from 47 to 48 Hz, silently); a list out of order, or of one, is an input
/// error naming the entry.
#[test]
fn a_list_of_frequencies_is_those_frequencies_not_a_grid() {
    let dir = tempfile::tempdir().unwrap();
    let exps = extreme(dir.path(), "listed", "", "[47.0, 48.0, 50]", "mass_ratio = 0.1", "0.3");
    let out_dir = dir.path().join("out");
    let out = shotdamp()
        .arg("--experiments")
        .arg(&exps)
        .arg("run")
        .arg(exps.join("listed.toml"))
        .arg("--out")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let table = std::fs::read_to_string(out_dir.join("listed/stated/data/compliance.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let (f, case) =
        (header.iter().position(|h| *h == "freq_hz").unwrap(), header.iter().position(|h| *h == "curve").unwrap());
    let hz: Vec<f64> = table
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(case) == Some("one"))
        .map(|l| l.split(',').nth(f).unwrap().parse().unwrap())
        .collect();
    assert_eq!(hz, vec![47.0, 48.0, 50.0]);
    for (list, key, words) in [
        ("[48.0, 47.0]", "analysis.freq_hz[1]", "ascending"),
        ("[48.0]", "analysis.freq_hz", "list 2 to"),
        ("[48.0, \"x\"]", "analysis.freq_hz[1]", "expected a number"),
    ] {
        let d = tempfile::tempdir().unwrap();
        let exps = extreme(d.path(), "bad", "", list, "mass_ratio = 0.1", "0.3");
        let out = shotdamp().arg("--experiments").arg(&exps).arg("run").arg(exps.join("bad.toml")).output().unwrap();
        let msg = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{list}: {msg}");
        assert!(msg.contains(key) && msg.contains(words) && msg.contains("bad.toml"), "{list}: {msg}");
    }
}
