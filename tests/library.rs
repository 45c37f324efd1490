//! The library runs what the command line runs: the same experiments through
//! `shotdamp::runner::run_and_write` and through `shotdamp run` write the same report, byte
//! for byte.

mod common;

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
    let loaded = shotdamp::experiment::load_all(&paths, &reference).unwrap();
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
