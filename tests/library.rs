//! The library runs what the command line runs: the same experiments through
//! `shotdamp::runner::run_and_write` and through `shotdamp run` write the same report, byte
//! for byte; a study through `shotdamp::runner::study` and through `shotdamp study` writes
//! the same long table, summary and heat maps.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use shotdamp::analysis::NoProgress;
use shotdamp::checks::reference::BaselineMode;
use shotdamp::runner::{run_and_write, Settings};

/// Every file below `root`, by its path relative to it.
fn files(root: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(p.strip_prefix(root).unwrap().to_path_buf(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

#[test]
fn a_library_run_writes_the_report_the_command_line_writes() {
    let dir = tempfile::tempdir().unwrap();
    let names = ["fig04b_no_damper.toml", "fig05_clearance_scan.toml", "fig05_third_mode.toml"];
    let exps = common::experiments(dir.path(), &names);
    let paths: Vec<PathBuf> = names.iter().map(|n| exps.join(n)).collect();
    let reference = common::repo().join("reference");

    let cli = dir.path().join("cli");
    let status = common::shotdamp()
        .arg("run")
        .args(&paths)
        .arg("--out")
        .arg(&cli)
        .arg("--jobs")
        .arg("2")
        .output()
        .unwrap()
        .status;
    assert!(status.code().is_some_and(|c| c <= 1), "{status:?}");

    let lib = dir.path().join("lib");
    let loaded = shotdamp::experiment::loader::load_all(&paths, &reference).unwrap();
    let settings = Settings {
        reference,
        out: lib.clone(),
        jobs: Some(1),
        writing: Default::default(),
        baseline_mode: BaselineMode::Optional,
        bless: false,
    };
    let done = run_and_write(&loaded, &[], &settings, &NoProgress, &|_| {}, &|_| {}).unwrap();
    assert_eq!(done.dest, lib);
    assert_eq!(done.results.len(), 9, "three experiments on three models");

    let (a, b) = (files(&cli), files(&lib));
    assert!(a.len() > 50, "{} files", a.len());
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>(), "the same files");
    for (path, bytes) in &a {
        assert!(bytes == &b[path], "{} differs", path.display());
    }
}

#[test]
fn a_library_study_writes_what_the_command_line_writes() {
    use shotdamp::output::manifest::Shard;
    use shotdamp::runner::study::{run_shard, Quiet, ShardEnd};
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("small.toml");
    std::fs::write(
        &file,
        format!(
            "[study]\nid = \"small\"\ntitle = \"t\"\nexperiment = \"{}\"\nmodels = [\"stated\"]\n\n[study.set]\n\"analysis.freq_hz\" = {{ start = 46.0, stop = 50.0, step = 0.5 }}\n\n[[vary]]\nname = \"clearance_mm\"\nkey = \"cases[*].dampers[*].clearance_mm\"\nvalues = [0.2, 0.35]\n",
            common::repo().join("experiments/fig05_third_mode.toml").display()
        ),
    )
    .unwrap();
    let cli = dir.path().join("cli");
    let out =
        common::shotdamp().args(["study", file.to_str().unwrap(), "--out", cli.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));

    let reference = common::repo().join("reference");
    let study = shotdamp::experiment::study::load(&file, &reference).unwrap();
    let lib = dir.path().join("lib");
    let pool = shotdamp::runner::pool(Some(1)).unwrap();
    let (end, merged) = run_shard(&study, &reference, &lib, Shard::WHOLE, &pool, &Quiet).unwrap();
    assert!(matches!(end, ShardEnd::Written(_)));
    let merged = merged.expect("one shard: merged at once");
    assert_eq!(merged.rows, 2 * 3, "two samples, three claims");
    let (a, b) = (files(&cli), files(&lib));
    assert!(a.contains_key(Path::new("small.csv")) && a.contains_key(Path::new("small_summary.csv")));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>(), "the same files");
    for (path, bytes) in &a {
        assert!(bytes == &b[path], "{} differs", path.display());
    }
}

/// Every experiment of the report loaded with one set of reference files parses each value
/// file and digitised file once, and the checks' store takes them from the checks: with those
/// files gone from the reference folder after loading, the store still has them all.
#[test]
fn each_reference_file_is_parsed_once() {
    use shotdamp::reference::files::Files;
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference");
    common::copy_tree(&common::repo().join("reference"), &reference);
    let refs = Files::new(&reference);
    let mut exps = Vec::new();
    for p in shotdamp::experiment::loader::discover(&common::repo().join("experiments")).unwrap() {
        exps.extend(shotdamp::experiment::loader::load_with(&p, &refs).unwrap());
    }
    let parsed: std::collections::BTreeSet<&str> =
        exps.iter().flat_map(|e| &e.checks).filter(|c| c.loaded.is_some()).map(|c| c.reference_file.as_str()).collect();
    assert!(!parsed.is_empty());
    assert!(exps.iter().flat_map(|e| &e.checks).filter(|c| c.loaded.is_some()).count() > 2 * parsed.len());
    assert_eq!(refs.reads(), parsed.len(), "one parse a file: {parsed:?}");
    for file in &parsed {
        std::fs::remove_file(reference.join(file)).unwrap();
    }
    let store = shotdamp::checks::reference::ReferenceStore::load(&reference, &exps).unwrap();
    for file in &parsed {
        assert!(store.values(file).is_some() || store.digitised(file).is_some(), "{file}");
    }
}
