//! Helpers shared by the end-to-end tests of the binary.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use assert_cmd::Command;

/// The repository.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The binary, run from the repository.
pub fn shotdamp() -> Command {
    let mut c = Command::cargo_bin("shotdamp").expect("binary");
    c.current_dir(repo());
    c
}

/// An experiments folder in `dir` holding the shared structure file and copies of `files`
/// (names in `experiments/`).
pub fn experiments(dir: &Path, files: &[&str]) -> PathBuf {
    let exps = dir.join("experiments");
    std::fs::create_dir_all(exps.join("shared")).unwrap();
    std::fs::copy(repo().join("experiments/shared/paper_structure.toml"), exps.join("shared/paper_structure.toml"))
        .unwrap();
    for f in files {
        std::fs::copy(repo().join("experiments").join(f), exps.join(f)).unwrap();
    }
    exps
}
