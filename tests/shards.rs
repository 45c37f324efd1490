//! Study folders under any interleaving, as clusters start shards: seven shards started at once
//! into one new folder (also each in its own PID namespace, as containers run them), the same
//! shard started twice at once, parts of two versions of a study, shard counts from a Slurm
//! array that reruns one task, and study paths spelled differently (docs/studies.md).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use common::repo;

/// A small Fig. 5 study on the stated chain: 7 samples (damping x clearance would be more),
/// 16 frequencies each.
fn small_study(dir: &Path, clearances: usize) -> PathBuf {
    let file = dir.join("race.toml");
    let experiment = repo().join("experiments/fig05_third_mode.toml");
    std::fs::write(
        &file,
        format!(
            r#"[study]
id = "race"
title = "Fig. 5, shards started together"
experiment = "{}"
models = ["stated"]

[study.set]
"analysis.freq_hz" = {{ start = 46.0, stop = 49.0, step = 0.2 }}

[[vary]]
name = "clearance_mm"
key = "cases[*].dampers[*].clearance_mm"
range = {{ start = 0.2, stop = 0.5, count = {clearances} }}
"#,
            experiment.display()
        ),
    )
    .unwrap();
    file
}

fn spawn(prefix: &[&str], args: &[&str], env: &[(&str, String)]) -> Child {
    let bin = assert_cmd::cargo::cargo_bin("shotdamp");
    let mut c = if prefix.is_empty() {
        Command::new(&bin)
    } else {
        let mut c = Command::new(prefix[0]);
        c.args(&prefix[1..]).arg(&bin);
        c
    };
    c.current_dir(repo()).args(args).stdout(Stdio::piped()).stderr(Stdio::piped());
    for (k, v) in env {
        c.env(k, v);
    }
    c.spawn().unwrap()
}

fn finish(child: Child) -> (Option<i32>, String) {
    let out = child.wait_with_output().unwrap();
    (out.status.code(), format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)))
}

fn whole(dir: &Path, file: &Path) -> Vec<u8> {
    let out = dir.join("whole");
    let (code, text) = finish(spawn(&[], &["study", file.to_str().unwrap(), "--out", out.to_str().unwrap()], &[]));
    assert_eq!(code, Some(0), "{text}");
    std::fs::read(out.join("race.csv")).unwrap()
}

fn merge(out: &Path) -> (Option<i32>, String) {
    finish(spawn(&[], &["study", "merge", out.to_str().unwrap()], &[]))
}

/// `n` shards started at once into `out` (each with `prefix`, e.g. a PID namespace), all must
/// end with exit 0; then the merge equals `expected` byte for byte.
fn round(prefix: &[&str], file: &Path, out: &Path, n: usize, expected: &[u8]) {
    let f = file.to_str().unwrap();
    let o = out.to_str().unwrap();
    let children: Vec<Child> = (0..n)
        .map(|i| spawn(prefix, &["study", f, "--shard", &format!("{i}/{n}"), "--out", o, "--jobs", "1"], &[]))
        .collect();
    for (i, c) in children.into_iter().enumerate() {
        let (code, text) = finish(c);
        assert_eq!(code, Some(0), "shard {i}/{n}: {text}");
    }
    let (code, text) = merge(out);
    assert_eq!(code, Some(0), "{text}");
    assert_eq!(std::fs::read(out.join("race.csv")).unwrap(), expected);
}

#[test]
fn seven_shards_started_together_into_one_new_folder_all_succeed_and_merge_identically() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), 7);
    let expected = whole(dir.path(), &file);
    for r in 0..4 {
        round(&[], &file, &dir.path().join(format!("r{r}")), 7, &expected);
    }
}

/// In containers every process may be PID 1: temporary names and locks must not rest on the
/// process id alone.
#[cfg(target_os = "linux")]
#[test]
fn shards_in_separate_pid_namespaces_do_not_collide() {
    let probe = Command::new("unshare").args(["--pid", "--fork", "--mount-proc", "true"]).status();
    if !probe.is_ok_and(|s| s.success()) {
        eprintln!("skipped: unshare --pid --fork is not allowed here");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), 7);
    let expected = whole(dir.path(), &file);
    for r in 0..3 {
        round(&["unshare", "--pid", "--fork", "--mount-proc"], &file, &dir.path().join(format!("ns{r}")), 7, &expected);
    }
}

#[test]
fn the_same_shard_started_twice_at_once_is_computed_once_and_merges_identically() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), 8);
    let expected = whole(dir.path(), &file);
    let f = file.to_str().unwrap();
    for r in 0..3 {
        let out = dir.path().join(format!("twice{r}"));
        let o = out.to_str().unwrap();
        let both: Vec<Child> =
            (0..2).map(|_| spawn(&[], &["study", f, "--shard", "0/2", "--out", o, "--jobs", "1"], &[])).collect();
        let texts: Vec<String> = both
            .into_iter()
            .map(|c| {
                let (code, text) = finish(c);
                assert_eq!(code, Some(0), "{text}");
                text
            })
            .collect();
        // At most one of them computed; the other found the shard complete (after waiting, or
        // because it came second).
        assert!(texts.iter().any(|t| t.contains("already complete")), "{texts:?}");
        let (code, text) = finish(spawn(&[], &["study", f, "--shard", "1/2", "--out", o, "--jobs", "1"], &[]));
        assert_eq!(code, Some(0), "{text}");
        assert_eq!(merge(&out).0, Some(0));
        assert_eq!(std::fs::read(out.join("race.csv")).unwrap(), expected);
        assert!(
            !std::fs::read_dir(out.join("parts")).unwrap().any(|e| e
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".lock")),
            "locks are released"
        );
    }
}

/// Two versions of the small study (4 and 5 clearances) in `dir`, shard `shards[0]` of the
/// first and `shards[1]` of the second computed into folders of their own: (file, folder) of
/// each.
fn two_versions(dir: &Path, shards: [&str; 2]) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let (a, b) = (dir.join("a"), dir.join("b"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    let (fa, fb) = (small_study(&a, 4), small_study(&b, 5));
    let (oa, ob) = (dir.join("out-a"), dir.join("out-b"));
    for ((f, o), shard) in [(&fa, &oa), (&fb, &ob)].into_iter().zip(shards) {
        let (code, text) =
            finish(spawn(&[], &["study", f.to_str().unwrap(), "--shard", shard, "--out", o.to_str().unwrap()], &[]));
        assert_eq!(code, Some(0), "{text}");
    }
    (fa, oa, fb, ob)
}

#[test]
fn parts_of_two_versions_of_a_study_are_never_merged() {
    let dir = tempfile::tempdir().unwrap();
    let (_, oa, _, ob) = two_versions(dir.path(), ["0/2", "0/2"]);
    // Version b's part 0 copied beside version a's (a user merging folders by hand).
    let part = std::fs::read_dir(ob.join("parts")).unwrap().map(|e| e.unwrap().path()).find(|p| p.is_file()).unwrap();
    std::fs::copy(&part, oa.join("parts").join(part.file_name().unwrap())).unwrap();
    let ma: serde_json::Value = serde_json::from_slice(&std::fs::read(oa.join("study.json")).unwrap()).unwrap();
    let mb: serde_json::Value = serde_json::from_slice(&std::fs::read(ob.join("study.json")).unwrap()).unwrap();
    let (code, text) = merge(&oa);
    assert_eq!(code, Some(2), "{text}");
    for fp in [&ma["fingerprint"], &mb["fingerprint"]] {
        assert!(text.contains(fp.as_str().unwrap()), "names both fingerprints: {text}");
    }
}

#[test]
fn a_part_of_another_version_renamed_to_this_folders_fingerprint_is_never_merged() {
    let dir = tempfile::tempdir().unwrap();
    let (fa, oa, _, ob) = two_versions(dir.path(), ["0/2", "1/2"]);
    let ma: serde_json::Value = serde_json::from_slice(&std::fs::read(oa.join("study.json")).unwrap()).unwrap();
    let mb: serde_json::Value = serde_json::from_slice(&std::fs::read(ob.join("study.json")).unwrap()).unwrap();
    let (fpa, fpb) = (ma["fingerprint"].as_str().unwrap(), mb["fingerprint"].as_str().unwrap());
    // Version b's shard 1 renamed as version a's shard 1 (its name now says version a).
    let part = ob.join("parts").join(format!("part-0001-of-0002-{fpb}.parquet"));
    let renamed = oa.join("parts").join(format!("part-0001-of-0002-{fpa}.parquet"));
    std::fs::copy(&part, &renamed).unwrap();
    let (code, text) = merge(&oa);
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains(&format!("another version (fingerprint {fpb})")) && text.contains(fpa), "{text}");
    assert!(text.contains("part-0001-of-0002") && text.contains("rm '"), "names the file and how to remove it: {text}");
    // Shard 1 of version a, run into the folder, finds the renamed part and refuses it too.
    let (code, text) =
        finish(spawn(&[], &["study", fa.to_str().unwrap(), "--shard", "1/2", "--out", oa.to_str().unwrap()], &[]));
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains(&format!("another version (fingerprint {fpb})")), "{text}");
}

#[test]
fn a_slurm_array_reruns_one_shard_of_the_folder_and_never_writes_a_part_of_another_count() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), 7);
    let expected = whole(dir.path(), &file);
    let f = file.to_str().unwrap();
    let out = dir.path().join("array");
    let o = out.to_str().unwrap();
    let task = |id: usize, min: usize, max: usize, count: usize| {
        let env = [
            ("SLURM_ARRAY_TASK_ID", id.to_string()),
            ("SLURM_ARRAY_TASK_MIN", min.to_string()),
            ("SLURM_ARRAY_TASK_MAX", max.to_string()),
            ("SLURM_ARRAY_TASK_STEP", "1".to_string()),
            ("SLURM_ARRAY_TASK_COUNT", count.to_string()),
        ];
        finish(spawn(&[], &["study", f, "--out", o, "--jobs", "1"], &env))
    };
    // --array=0-6 with task 3 missing (cancelled), then --array=3: shard 3 of the folder's 7.
    for i in (0..7).filter(|&i| i != 3) {
        let (code, text) = task(i, 0, 6, 7);
        assert_eq!(code, Some(0), "{text}");
        assert!(text.contains(&format!("shard {i}/7")), "{text}");
    }
    let (code, text) = merge(&out);
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("shards 3/7 have not finished"), "{text}");
    let (code, text) = task(3, 3, 3, 1);
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("shard 3/7"), "{text}");
    // --array=0 alone in a folder of 7 shards: shard 0 of 7 (already complete), never 0/1.
    let (code, text) = task(0, 0, 0, 1);
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("shard 0/7") && text.contains("already complete"), "{text}");
    assert_eq!(merge(&out).0, Some(0));
    assert_eq!(std::fs::read(out.join("race.csv")).unwrap(), expected);
    // A stepped array into a new folder, without --shards: refused, saying what to do.
    let fresh = dir.path().join("fresh");
    let env = [
        ("SLURM_ARRAY_TASK_ID", "2".to_string()),
        ("SLURM_ARRAY_TASK_MIN", "0".to_string()),
        ("SLURM_ARRAY_TASK_MAX", "6".to_string()),
        ("SLURM_ARRAY_TASK_STEP", "2".to_string()),
        ("SLURM_ARRAY_TASK_COUNT", "4".to_string()),
    ];
    let (code, text) = finish(spawn(&[], &["study", f, "--out", fresh.to_str().unwrap()], &env));
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("--shards N"), "{text}");
    // A shard count other than the folder's: refused.
    let (code, text) = finish(spawn(&[], &["study", f, "--shard", "0/3", "--out", o], &[]));
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("computed as 7 shards"), "{text}");
}

#[test]
fn the_fingerprint_does_not_depend_on_how_the_study_path_is_spelled() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), 4);
    let out = dir.path().join("spelled");
    let o = out.to_str().unwrap();
    // Shard 0 by the absolute path from the repository; shard 1 by a relative path with a
    // detour, from the study's folder.
    let (code, text) = finish(spawn(&[], &["study", file.to_str().unwrap(), "--shard", "0/2", "--out", o], &[]));
    assert_eq!(code, Some(0), "{text}");
    let detour = format!("./../{}/race.toml", dir.path().file_name().unwrap().to_str().unwrap());
    let out2 = Command::new(assert_cmd::cargo::cargo_bin("shotdamp"))
        .current_dir(dir.path())
        .args(["--reference", repo().join("reference").to_str().unwrap()])
        .args(["study", &detour, "--shard", "1/2", "--out", o])
        .output()
        .unwrap();
    assert_eq!(out2.status.code(), Some(0), "{}", String::from_utf8_lossy(&out2.stderr));
    assert_eq!(merge(&out).0, Some(0));
}

#[test]
fn a_damaged_batch_is_named_with_the_command_that_removes_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = small_study(dir.path(), 4);
    let out = dir.path().join("damaged");
    let o = out.to_str().unwrap();
    let (code, text) = finish(spawn(&[], &["study", file.to_str().unwrap(), "--shard", "1/2", "--out", o], &[]));
    assert_eq!(code, Some(0), "{text}");
    // A batch of shard 0 left empty by a crash.
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("study.json")).unwrap()).unwrap();
    let batches = out.join("parts").join(format!("shard-0000-of-0002-{}", m["fingerprint"].as_str().unwrap()));
    std::fs::create_dir_all(&batches).unwrap();
    let bad = batches.join("batch-00000000.parquet");
    std::fs::write(&bad, b"").unwrap();
    let (code, text) = finish(spawn(&[], &["study", file.to_str().unwrap(), "--shard", "0/2", "--out", o], &[]));
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("is damaged") && text.contains(&format!("rm '{}'", bad.display())), "{text}");
    std::fs::remove_file(&bad).unwrap();
    let (code, text) = finish(spawn(&[], &["study", file.to_str().unwrap(), "--shard", "0/2", "--out", o], &[]));
    assert_eq!(code, Some(0), "{text}");
    assert_eq!(merge(&out).0, Some(0));
}
