//! The experiments whose exports a set of experiments uses and does not hold, found in the
//! folders of the files that name them: what `shotdamp run FILE` and `shotdamp explore FILE`
//! run first.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::reference::files::Files;

use super::loader::{discover, load_with};
use super::Experiment;

/// One folder's experiment files, loaded once: the experiments, and the first file that did
/// not load (reported only if an id is then missing from the folder).
struct Folder {
    dir: PathBuf,
    experiments: Vec<Experiment>,
    failed: Option<Error>,
}

/// The experiments that `exps` take exports from (`@id` references) and do not hold, with
/// those these take exports from in turn, each looked for among the experiment files
/// (`*.toml`) of the folder of the file that names it. An id no file there holds is an input
/// error naming the file and the reference (or, when a file of that folder did not load,
/// that file's error: the id may be in it).
pub fn missing_dependencies(exps: &[Experiment], files: &Files) -> Result<Vec<Experiment>> {
    let uses = |e: &Experiment| e.dependencies().into_iter().map(|d| (d, e.path.clone())).collect::<Vec<_>>();
    let mut held: Vec<String> = exps.iter().map(|e| e.meta.id.clone()).collect();
    let mut wanted: Vec<(String, PathBuf)> = exps.iter().rev().flat_map(uses).collect();
    let mut folders: Vec<Folder> = Vec::new();
    let mut added: Vec<Experiment> = Vec::new();
    while let Some((id, user)) = wanted.pop() {
        if held.contains(&id) {
            continue;
        }
        let dir = user.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new(".")).to_path_buf();
        let at = match folders.iter().position(|f| f.dir == dir) {
            Some(at) => at,
            None => {
                let mut folder = Folder { dir: dir.clone(), experiments: Vec::new(), failed: None };
                for file in discover(&dir)? {
                    if exps.iter().any(|e| e.path == file) {
                        continue;
                    }
                    match load_with(&file, files) {
                        Ok(v) => folder.experiments.extend(v),
                        Err(e) => {
                            folder.failed.get_or_insert(e);
                        }
                    }
                }
                folders.push(folder);
                folders.len() - 1
            }
        };
        let found: Vec<Experiment> = folders[at].experiments.iter().filter(|e| e.meta.id == id).cloned().collect();
        if found.is_empty() {
            return Err(folders[at].failed.take().unwrap_or_else(|| {
                Error::invalid(
                    &user,
                    "(export reference)",
                    format!("@{id}"),
                    format!("no experiment with id \"{id}\" among the experiment files of {}", dir.display()),
                )
            }));
        }
        held.push(id);
        wanted.extend(found.iter().rev().flat_map(uses));
        added.extend(found);
    }
    Ok(added)
}
