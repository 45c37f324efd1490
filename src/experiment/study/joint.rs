//! Joint studies (docs/studies.md, "Joint studies"): several experiments run at every sample
//! with the same values. What a joint study file must satisfy beyond a study's.

use crate::error::{Error, Result};

use super::Study;

/// Checks the experiments of a joint study (`first` and `others`, named in the file by
/// `files`: key and path): the same samples on every experiment, distinct experiments, every
/// varied and set key reaching at least one of them (a varied key's `experiments` naming
/// some of them).
pub fn check(first: &Study, others: &[Study], files: &[(String, String)]) -> Result<()> {
    let path = &first.path;
    let models =
        |s: &Study| s.base.iter().map(|e| e.model.as_ref().map_or(String::new(), |m| m.id.clone())).collect::<Vec<_>>();
    for (k, other) in others.iter().enumerate() {
        let (key, file) = &files[k + 1];
        if models(other) != models(first) {
            return Err(Error::invalid(
                path,
                key.as_str(),
                format!("\"{file}\""),
                format!(
                    "runs on the models {:?}, the first experiment on {:?}: every experiment of a joint study runs on the same models (give `models`)",
                    models(other),
                    models(first)
                ),
            ));
        }
        let id = &other.base[0].meta.id;
        if let Some(j) = std::iter::once(first).chain(&others[..k]).position(|s| &s.base[0].meta.id == id) {
            return Err(Error::invalid(
                path,
                key.as_str(),
                format!("\"{file}\""),
                format!("experiment \"{id}\" is already {}: each experiment once", files[j].0),
            ));
        }
    }
    let parts: Vec<&Study> = std::iter::once(first).chain(others).collect();
    let reaches = |k: &super::KeyPath| parts.iter().any(|s| s.tables.values().any(|t| !k.get(t).is_empty()));
    let ids: Vec<&str> = parts.iter().map(|s| s.base[0].meta.id.as_str()).collect();
    for (i, v) in first.vary.iter().enumerate() {
        if let Some(bad) = v.experiments.iter().find(|e| !ids.contains(&e.as_str())) {
            return Err(Error::invalid(
                path,
                format!("vary[{i}].experiments"),
                format!("\"{bad}\""),
                format!("the ids of the joint study's experiments: {ids:?}"),
            ));
        }
        if !reaches(&v.key) {
            return Err(Error::invalid(
                path,
                format!("vary[{i}].key"),
                format!("\"{}\"", v.key.as_str()),
                "reaches none of the joint study's experiments (a key is set where an experiment has it)",
            ));
        }
    }
    for (k, _) in &first.set {
        if !reaches(k) {
            return Err(Error::invalid(
                path,
                format!("study.set.\"{}\"", k.as_str()),
                "(given)",
                "reaches none of the joint study's experiments (a key is set where an experiment has it)",
            ));
        }
    }
    Ok(())
}
