//! Adaptive studies (docs/studies.md, "Adaptive refinement"): every sample computed is the
//! grid's sample at the same values, bit for bit; rounds refine only where the answer changes;
//! shards started together, one shard alone, and the whole study in one process give the same
//! folder, byte for byte; bad adaptive files are named.

use crate::common;

use std::path::{Path, PathBuf};

use common::{csv_rows, repo, shotdamp};

/// Fig. 5 over damping x clearance on the stated chain, 25 frequencies: `head` says the
/// design.
fn fig5(dir: &Path, name: &str, head: &str, counts: (usize, usize)) -> PathBuf {
    let file = dir.join(format!("{name}.toml"));
    let text = format!(
        "[study]\nid = \"{name}\"\ntitle = \"t\"\nexperiment = \"{}\"\nmodels = [\"stated\"]\n{head}\n\n[study.set]\n\"analysis.freq_hz\" = {{ start = 44.0, stop = 56.0, step = 0.5 }}\n\n[[vary]]\nname = \"damping\"\nkey = \"structure.damping.modal_ratios\"\nrange = {{ start = 0.002, stop = 0.016, count = {}, scale = \"log\" }}\n\n[[vary]]\nname = \"clearance_mm\"\nkey = \"cases[*].dampers[*].clearance_mm\"\nrange = {{ start = 0.1, stop = 0.74, count = {} }}\n",
        repo().join("experiments/fig05_third_mode.toml").display(),
        counts.0,
        counts.1
    );
    std::fs::write(&file, text).unwrap();
    file
}

fn run(file: &Path, out: &Path, more: &[&str]) -> (Option<i32>, String) {
    let o = shotdamp().arg("study").arg(file).arg("--out").arg(out).args(more).output().unwrap();
    (o.status.code(), format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr)))
}

fn ok(file: &Path, out: &Path, more: &[&str]) -> String {
    let (code, text) = run(file, out, more);
    assert_eq!(code, Some(0), "{text}");
    text
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{}: {e}", dir.join(name).display()))
}

#[test]
fn every_computed_sample_is_the_grid_s_and_the_map_agrees_with_the_grid() {
    let dir = tempfile::tempdir().unwrap();
    let adaptive = fig5(dir.path(), "ad", "design = \"adaptive\"\nlevels = 2\nrefine = \"count\"", (9, 17));
    let grid = fig5(dir.path(), "gr", "", (9, 17));
    let said = ok(&adaptive, &dir.path().join("a"), &[]);
    assert!(said.contains("round 0: 15 samples"), "{said}");
    ok(&grid, &dir.path().join("g"), &[]);
    let a = csv_rows(&String::from_utf8(read(&dir.path().join("a"), "ad.csv")).unwrap());
    let g = csv_rows(&String::from_utf8(read(&dir.path().join("g"), "gr.csv")).unwrap());
    // Rows keyed by their values and check; everything after the sample number must match.
    let key = |r: &Vec<String>| (r[2].clone(), r[3].clone(), r[4].clone());
    let grid_rows: std::collections::BTreeMap<_, _> = g[1..].iter().map(|r| (key(r), r[1..].to_vec())).collect();
    let computed = a[1..].len() / 3;
    assert!(computed > 15 && computed < 9 * 17, "{computed} samples");
    for r in &a[1..] {
        assert_eq!(grid_rows.get(&key(r)), Some(&r[1..].to_vec()), "{r:?}");
    }
    // The map: every point of the fine grid once, computed where the table has it; where
    // inferred, the grid's number of claims that hold is the corners' (the refinement stops
    // only where all corners agree: a change inside such a cell is what the coarse step can
    // miss, and is counted here, not hidden).
    let map = csv_rows(&String::from_utf8(read(&dir.path().join("a"), "ad_map.csv")).unwrap());
    assert_eq!(map.len() - 1, 9 * 17);
    let how = map[0].iter().position(|h| h == "how").unwrap();
    let answer = map[0].iter().position(|h| h == "answer").unwrap();
    assert_eq!(map[1..].iter().filter(|r| r[how] == "computed").count(), computed);
    let holds = |values: &(String, String)| {
        g[1..].iter().filter(|r| (&r[2], &r[3]) == (&values.0, &values.1) && r[10] == "holds" && r[8] == "1").count()
    };
    let outcome = g[0].iter().position(|h| h == "outcome").unwrap();
    let settled = g[0].iter().position(|h| h == "settled").unwrap();
    assert_eq!((outcome, settled), (10, 8), "{:?}", g[0]);
    let wrong = map[1..].iter().filter(|r| r[answer] != holds(&(r[1].clone(), r[2].clone())).to_string()).count();
    assert!(wrong * 10 <= 9 * 17, "{wrong} of the fine grid's points inferred otherwise than the grid computes them");
}

#[test]
fn shards_together_one_shard_alone_and_one_process_give_the_same_folder() {
    let dir = tempfile::tempdir().unwrap();
    let file = fig5(dir.path(), "ad", "design = \"adaptive\"\nlevels = 2", (9, 9));
    ok(&file, &dir.path().join("whole"), &["--jobs", "1"]);
    // Three shards started at once: each computes its share of a round, then the shares no
    // one holds, and the round after.
    let out = dir.path().join("three");
    let children: Vec<_> = (0..3)
        .map(|i| {
            std::process::Command::new(assert_cmd::cargo::cargo_bin("shotdamp"))
                .current_dir(repo())
                .arg("study")
                .arg(&file)
                .arg("--out")
                .arg(&out)
                .arg("--shard")
                .arg(format!("{i}/3"))
                .arg("--jobs")
                .arg("1")
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for c in children {
        let o = c.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }
    // One shard of five alone does the whole study.
    ok(&file, &dir.path().join("alone"), &["--shard", "3/5"]);
    for name in ["ad.csv", "ad.parquet", "ad_map.csv", "ad_samples.csv", "ad_summary.csv"] {
        let whole = read(&dir.path().join("whole"), name);
        assert_eq!(whole, read(&out, name), "{name}: three shards");
        assert_eq!(whole, read(&dir.path().join("alone"), name), "{name}: one shard of five");
    }
    // Run again: nothing to compute, the same folder.
    let again = ok(&file, &dir.path().join("whole"), &[]);
    assert!(again.contains("already complete"), "{again}");
    assert_eq!(read(&dir.path().join("whole"), "ad.csv"), read(&out, "ad.csv"));
    // `study merge` of a finished folder (as a cluster's chained merge runs it) writes it again,
    // the same.
    let o = shotdamp().arg("study").arg("merge").arg(&out).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    for name in ["ad.csv", "ad_samples.csv", "ad_summary.csv"] {
        assert_eq!(read(&dir.path().join("whole"), name), read(&out, name), "{name}: merged again");
    }
    // A folder whose rounds have not ended says how to finish it.
    let part = dir.path().join("part");
    let manifest = std::fs::read_to_string(out.join("study.json")).unwrap();
    std::fs::create_dir_all(part.join("parts")).unwrap();
    std::fs::write(part.join("study.json"), manifest.replace("\"rounds\"", "\"rounds_not\"")).unwrap();
    copy_dir(&out.join("parts/round-0"), &part.join("parts/round-0"));
    let o = shotdamp().arg("study").arg("merge").arg(&part).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("rounds have not all ended"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.path().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn bad_adaptive_studies_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, (usize, usize), &str); 5] = [
        ("design = \"adaptive\"\nlevels = 2", (9, 10), "vary[1].range.count"),
        ("design = \"adaptive\"\nlevels = 9", (9, 9), "study.levels"),
        ("design = \"adaptive\"\nrefine = \"most\"", (9, 9), "study.refine"),
        ("design = \"adaptive\"\nrefine = 3", (9, 9), "study.refine"),
        ("levels = 2", (9, 9), "study.levels"),
    ];
    for (i, (head, counts, key)) in cases.iter().enumerate() {
        let file = fig5(dir.path(), &format!("bad{i}"), head, *counts);
        let (code, text) = run(&file, &dir.path().join(format!("o{i}")), &["--dry-run"]);
        assert_eq!(code, Some(2), "{head}: {text}");
        assert!(text.contains(key), "{head}: {text}");
    }
}

/// The report runs an adaptive study in its process (no folder): the same rows as the folder.
#[test]
fn the_report_s_run_in_one_process_gives_the_folder_s_rows() {
    let dir = tempfile::tempdir().unwrap();
    let file = fig5(dir.path(), "ad", "design = \"adaptive\"\nlevels = 2\nrefine = \"outcomes\"", (9, 9));
    ok(&file, &dir.path().join("f"), &[]);
    let reference = repo().join("reference");
    let study = shotdamp::experiment::study::load(&file, &reference).unwrap();
    let refs = shotdamp::runner::study_references(&study, &reference).unwrap();
    let rows = shotdamp::analysis::study_adaptive::run_all(&study, &refs, &|| {}).unwrap();
    let table = shotdamp::analysis::study::table(&study, &rows);
    let csv = shotdamp::table::to_csv(&table).unwrap();
    let folder = csv_rows(&String::from_utf8(read(&dir.path().join("f"), "ad.csv")).unwrap());
    let mine = csv_rows(&String::from_utf8(csv).unwrap());
    assert!(rows.len() > 3 * 9, "{} rows: the rounds after the coarse grid ran", rows.len());
    assert_eq!(mine.len(), folder.len());
    for (a, b) in mine.iter().zip(&folder) {
        // Numbers as the folder's CSV (polars) and the report's table write them.
        let num = |s: &str| s.parse::<f64>().map(|x| format!("{x:e}")).unwrap_or_else(|_| s.to_string());
        assert_eq!(a.iter().map(|s| num(s)).collect::<Vec<_>>(), b.iter().map(|s| num(s)).collect::<Vec<_>>());
    }
}
