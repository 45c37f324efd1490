//! Joint studies (docs/studies.md, "Joint studies"): several experiments at every sample with
//! the same values. Each experiment's claims are those of its own study at those values, bit
//! for bit; shards merge to the unsharded folder; the answer per sample counts them; bad
//! joint files are named.

use crate::common;

use std::path::{Path, PathBuf};

use common::{csv_rows, repo, shotdamp};

/// A study file `name` in `dir`: `head` under `[study]` (after id and title), then the varied
/// keys.
fn study_file(dir: &Path, name: &str, head: &str, vary: &str) -> PathBuf {
    let file = dir.join(format!("{name}.toml"));
    let text = format!("[study]\nid = \"{name}\"\ntitle = \"t\"\n{head}\nmodels = [\"stated\"]\n\n{vary}");
    std::fs::write(&file, text).unwrap();
    file
}

fn experiment(name: &str) -> String {
    repo().join("experiments").join(format!("{name}.toml")).display().to_string()
}

const DAMPING: &str =
    "[[vary]]\nname = \"damping\"\nkey = \"structure.damping.modal_ratios\"\nvalues = [0.005, 0.01]\n";

fn run(file: &Path, out: &Path, more: &[&str]) -> String {
    let o = shotdamp().arg("study").arg(file).arg("--out").arg(out).args(more).output().unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{text}");
    text
}

#[test]
fn each_experiment_of_a_joint_study_gives_its_own_study_s_claims() {
    let dir = tempfile::tempdir().unwrap();
    let clearance = "[[vary]]\nname = \"clearance_mm\"\nkey = \"cases[*].dampers[*].clearance_mm\"\nvalues = [0.3]\n";
    let joint = study_file(
        dir.path(),
        "joint",
        &format!("experiments = [\"{}\", \"{}\"]", experiment("fig05_third_mode"), experiment("fig10b_impulse")),
        &format!("{DAMPING}\n{clearance}experiments = [\"fig05_third_mode\"]\n"),
    );
    let alone5 = study_file(
        dir.path(),
        "alone5",
        &format!("experiment = \"{}\"", experiment("fig05_third_mode")),
        &format!("{DAMPING}\n{clearance}"),
    );
    let alone10 =
        study_file(dir.path(), "alone10", &format!("experiment = \"{}\"", experiment("fig10b_impulse")), DAMPING);
    let said = run(&joint, &dir.path().join("j"), &[]);
    assert!(said.contains("most claims at once: sample"), "{said}");
    run(&alone5, &dir.path().join("a5"), &[]);
    run(&alone10, &dir.path().join("a10"), &[]);
    let table =
        |d: &str, id: &str| csv_rows(&std::fs::read_to_string(dir.path().join(d).join(format!("{id}.csv"))).unwrap());
    let j = table("j", "joint");
    let col = |n: &str| j[0].iter().position(|h| h == n).unwrap();
    let (claim, value, outcome, sample) = (col("claim"), col("value"), col("outcome"), col("sample"));
    let mut compared = 0;
    for (id, own) in [("fig05_third_mode", table("a5", "alone5")), ("fig10b_impulse", table("a10", "alone10"))] {
        // Each table's own columns (the joint one varies more keys).
        let at = |n: &str| own[0].iter().position(|h| h == n).unwrap();
        for r in &own[1..] {
            let name = format!("{id}: {}", r[at("claim")]);
            let mine = j[1..]
                .iter()
                .find(|x| x[claim] == name && x[sample] == r[at("sample")])
                .expect("the claim in the joint table");
            // The same run at the same values: the same f64, the same verdict.
            assert_eq!(mine[value], r[at("value")], "{name}, sample {}", r[at("sample")]);
            assert_eq!(mine[outcome], r[at("outcome")], "{name}, sample {}", r[at("sample")]);
            compared += 1;
        }
    }
    assert_eq!(compared, j.len() - 1, "every joint row is one of the experiments' own");
    // The answer per sample counts the joint table's rows.
    let s = table("j", "joint_samples");
    let sc = |n: &str| s[0].iter().position(|h| h == n).unwrap();
    for row in &s[1..] {
        let of: Vec<&Vec<String>> = j[1..].iter().filter(|x| x[sample] == row[sc("sample")]).collect();
        assert_eq!(row[sc("claims")], of.len().to_string());
        let holds = of.iter().filter(|x| x[outcome] == "holds" && x[col("settled")] == "1").count();
        assert_eq!(row[sc("holds")], holds.to_string());
    }
    // Shards merge to the unsharded folder, byte for byte.
    let sharded = dir.path().join("s");
    for k in 0..2 {
        run(&joint, &sharded, &["--shard", &format!("{k}/2")]);
    }
    let o = shotdamp().args(["study", "merge"]).arg(&sharded).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["joint.csv", "joint_summary.csv", "joint_samples.csv", "joint.parquet"] {
        let a = std::fs::read(dir.path().join("j").join(f)).unwrap();
        assert!(a == std::fs::read(sharded.join(f)).unwrap(), "{f} differs");
    }
}

#[test]
fn bad_joint_studies_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let (e5, e10) = (experiment("fig05_third_mode"), experiment("fig10b_impulse"));
    let both = format!("experiments = [\"{e5}\", \"{e10}\"]");
    let clearance = "[[vary]]\nname = \"clearance_mm\"\nkey = \"cases[*].dampers[*].clearance_mm\"\nvalues = [0.3]\n";
    for (head, vary, key, words) in [
        (format!("experiment = \"{e5}\"\n{both}"), DAMPING.to_string(), "study.experiments", "not both"),
        (both.clone(), format!("{clearance}experiments = [\"fig99\"]\n"), "vary[0].experiments", "fig99"),
        (both.clone(), DAMPING.replace("structure.damping", "structure.dampin"), "vary[0].key", "reaches none"),
        (both.clone(), format!("[study.set]\n\"structure.nope\" = 1.0\n\n{DAMPING}"), "study.set", "reaches none"),
        (format!("experiments = [\"{e5}\", \"{e5}\"]"), DAMPING.to_string(), "study.experiments[1]", "already"),
        (
            format!("experiment = \"{e5}\""),
            format!("{clearance}experiments = [\"fig05_third_mode\"]\n"),
            "vary[0].experiments",
            "only a joint study",
        ),
    ] {
        let bad = study_file(dir.path(), "bad", &head, &vary);
        let o = shotdamp().arg("study").arg(&bad).arg("--out").arg(dir.path().join("x")).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{key}: {err}");
        assert!(err.contains("bad.toml") && err.contains(key) && err.contains(words), "{key}: {err}");
        assert!(!dir.path().join("x").exists(), "nothing written for bad input");
    }
}

/// A joint study's stored answer: `--store` writes the best samples per model into the
/// reference folder; the report refuses `stored = true` without it, runs each model's best
/// sample again with it, says so when the count differs now, and takes every number from the
/// file or the run.
#[test]
fn a_stored_answer_heads_the_report_and_is_run_again() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let exps =
        common::experiments(root, &["fig04b_no_damper.toml", "fig08_number_of_dampers.toml", "fig10b_impulse.toml"]);
    let reference = root.join("reference");
    common::copy_tree(&repo().join("reference"), &reference);
    let studies = root.join("studies");
    std::fs::create_dir_all(&studies).unwrap();
    let file = study_file(
        &studies,
        "j",
        "experiments = [\"../experiments/fig08_number_of_dampers.toml\", \"../experiments/fig10b_impulse.toml\"]\nstored = true",
        DAMPING,
    );
    let report = |out: &str| {
        shotdamp()
            .arg("--experiments")
            .arg(&exps)
            .arg("--reference")
            .arg(&reference)
            .arg("report")
            .arg("--out")
            .arg(root.join(out))
            .output()
            .unwrap()
    };
    let o = report("r0");
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--store"), "{}", String::from_utf8_lossy(&o.stderr));
    let o = shotdamp()
        .arg("--reference")
        .arg(&reference)
        .arg("study")
        .arg(&file)
        .arg("--out")
        .arg(root.join("o"))
        .arg("--store")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let stored_path = reference.join("studies/j.json");
    let stored: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&stored_path).unwrap()).unwrap();
    let samples = csv_rows(&std::fs::read_to_string(root.join("o/j_samples.csv")).unwrap());
    let holds = samples[0].iter().position(|h| h == "holds").unwrap();
    let most = samples[1..].iter().map(|r| r[holds].parse::<u64>().unwrap()).max().unwrap();
    let best = &stored["models"][0]["best"][0];
    assert_eq!(best["holds"].as_u64(), Some(most), "{stored}");
    assert_eq!(stored["models"][0]["samples"].as_u64(), Some(2));
    let o = report("r1");
    assert!(o.status.code() == Some(0) || o.status.code() == Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    let index = std::fs::read_to_string(root.join("r1/index.html")).unwrap();
    assert!(index.contains("setups searched"), "no stored bottom line");
    assert!(index.contains("gives the stored count"), "the best sample run again gives the stored count");
    assert!(index.contains(&format!("{most} of ")), "the stored count is on the page");
    // A stored count that the run no longer gives is named.
    let tampered = std::fs::read_to_string(&stored_path).unwrap().replacen(
        &format!("\"holds\": {most}"),
        &format!("\"holds\": {}", most + 7),
        1,
    );
    std::fs::write(&stored_path, tampered).unwrap();
    let o = report("r2");
    assert!(o.status.code() == Some(0) || o.status.code() == Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    let index = std::fs::read_to_string(root.join("r2/index.html")).unwrap();
    assert!(index.contains("the stored answer is out of date"), "a changed count is named");
}
