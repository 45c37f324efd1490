//! Reading experiment files: TOML syntax, `extends` merging, and shape (stage one).

use std::path::{Path, PathBuf};

use crate::error::{read_to_string, Error, Result};

use super::raw::RawExperiment;

/// How deep `extends` chains may go before they are taken for a cycle.
const MAX_EXTENDS_DEPTH: usize = 8;

/// Parses TOML text; syntax errors keep their line and column.
pub fn parse_table(path: &Path, text: &str) -> Result<toml::Table> {
    toml::from_str::<toml::Table>(text).map_err(|e| Error::Parse {
        file: path.display().to_string(),
        message: format!("TOML syntax error: {}", e.to_string().trim_end()),
    })
}

/// Deep merge: tables merge key by key, anything else in `child` replaces `base`.
fn merge(base: &mut toml::Table, child: toml::Table) {
    for (key, value) in child {
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(c)) => merge(b, c),
            (_, v) => {
                base.insert(key, v);
            }
        }
    }
}

/// Reads `path` and merges the file it `extends` (relative to it), recursively.
pub fn read_merged(path: &Path) -> Result<toml::Table> {
    read_merged_depth(path, 0)
}

fn read_merged_depth(path: &Path, depth: usize) -> Result<toml::Table> {
    let text = read_to_string(path)?;
    let mut table = parse_table(path, &text)?;
    resolve_model_paths(path, &mut table)?;
    let Some(parent) = table.get("extends") else {
        return Ok(table);
    };
    let Some(parent) = parent.as_str() else {
        return Err(Error::invalid(
            path,
            "extends",
            parent,
            "must be a string: the path of a shared TOML file, relative to this file",
        ));
    };
    if depth >= MAX_EXTENDS_DEPTH {
        return Err(Error::invalid(
            path,
            "extends",
            format!("\"{parent}\""),
            format!("extends chains are limited to {MAX_EXTENDS_DEPTH} files (is there a cycle?)"),
        ));
    }
    let parent_path: PathBuf = path.parent().unwrap_or(Path::new(".")).join(parent);
    if !parent_path.is_file() {
        return Err(Error::invalid(
            path,
            "extends",
            format!("\"{parent}\""),
            if parent_path.exists() {
                format!("not a regular file (a folder, a device or a pipe): {}", parent_path.display())
            } else {
                format!("no such file: {}", parent_path.display())
            },
        ));
    }
    let mut base = read_merged_depth(&parent_path, depth + 1)?;
    base.remove("extends");
    merge(&mut base, table);
    Ok(base)
}

/// Makes the paths of `models = [...]` relative to the file that lists them, so that they
/// survive merging into files elsewhere.
fn resolve_model_paths(path: &Path, table: &mut toml::Table) -> Result<()> {
    let Some(models) = table.get_mut("models") else { return Ok(()) };
    let dir = path.parent().unwrap_or(Path::new("."));
    let bad = |v: &dyn std::fmt::Display| {
        Error::invalid(path, "models", v, "a list of model files (strings), relative to this file")
    };
    let toml::Value::Array(list) = models else { return Err(bad(models)) };
    if list.is_empty() {
        return Err(bad(&"[]"));
    }
    for v in list.iter_mut() {
        let Some(s) = v.as_str() else { return Err(bad(v)) };
        *v = toml::Value::String(dir.join(s).display().to_string());
    }
    Ok(())
}

/// One table per model: the model file's tables with the experiment's merged over them, with
/// the model file's path. Without `models`, the experiment's table alone.
pub fn read_models(path: &Path) -> Result<Vec<(Option<PathBuf>, toml::Table)>> {
    let mut table = read_merged(path)?;
    let Some(models) = table.remove("models") else {
        select_model(path, &mut table, None, &[])?;
        return Ok(vec![(None, table)]);
    };
    let files: Vec<String> =
        models.as_array().map(|a| a.iter().filter_map(|v| v.as_str().map(String::from)).collect()).unwrap_or_default();
    let mut tables = Vec::new();
    let mut ids: Vec<String> = Vec::new();
    for file in &files {
        let model_path = PathBuf::from(file);
        if !model_path.is_file() {
            return Err(Error::invalid(path, "models", format!("\"{file}\""), "no such model file"));
        }
        let mut base = read_merged(&model_path)?;
        base.remove("models");
        let id = base.get("model").and_then(|m| m.get("id")).and_then(|v| v.as_str()).map(String::from).ok_or_else(
            || {
                Error::invalid(
                    &model_path,
                    "model.id",
                    "(missing)",
                    "a model file starts with [model] id, label, description",
                )
            },
        )?;
        if !crate::experiment::fields::is_identifier(&id) {
            return Err(Error::invalid(
                &model_path,
                "model.id",
                format!("\"{id}\""),
                "use letters, digits, '_' and '-' only",
            ));
        }
        crate::experiment::fields::id_length(&model_path, "model.id", &id)?;
        if ids.contains(&id) {
            return Err(Error::invalid(path, "models", format!("\"{id}\""), "each model may be listed once"));
        }
        ids.push(id);
        merge(&mut base, table.clone());
        tables.push(base);
    }
    for (t, id) in tables.iter_mut().zip(&ids) {
        select_model(path, t, Some(id), &ids)?;
    }
    Ok(files.iter().map(PathBuf::from).map(Some).zip(tables).collect())
}

/// Keeps what applies to `model`: checks whose `models` list it (or that list none), and of
/// `experiment.deviation` and each check's `known_deviation`, the text for this model when
/// given as a table keyed by model id.
fn select_model(path: &Path, table: &mut toml::Table, model: Option<&str>, ids: &[String]) -> Result<()> {
    let per_model = |key: String, value: &mut toml::Value| -> Result<bool> {
        let toml::Value::Table(t) = value else { return Ok(true) };
        for k in t.keys() {
            if !ids.contains(k) {
                return Err(Error::invalid(
                    path,
                    key,
                    k,
                    format!("a table of texts keyed by model id; the models are {ids:?}"),
                ));
            }
        }
        match model.and_then(|m| t.get(m)).cloned() {
            Some(text) => {
                *value = text;
                Ok(true)
            }
            None => Ok(false),
        }
    };
    if let Some(toml::Value::Table(meta)) = table.get_mut("experiment") {
        if let Some(v) = meta.get_mut("deviation") {
            if !per_model("experiment.deviation".into(), v)? {
                meta.remove("deviation");
            }
        }
    }
    if let Some(toml::Value::Array(checks)) = table.get_mut("checks") {
        let mut kept = Vec::new();
        for (i, mut c) in std::mem::take(checks).into_iter().enumerate() {
            let Some(ct) = c.as_table_mut() else {
                kept.push(c);
                continue;
            };
            if let Some(list) = ct.remove("models") {
                let names: Option<Vec<String>> =
                    list.as_array().and_then(|a| a.iter().map(|v| v.as_str().map(String::from)).collect());
                let Some(names) = names.filter(|n| !n.is_empty() && n.iter().all(|x| ids.contains(x))) else {
                    return Err(Error::invalid(
                        path,
                        format!("checks[{i}].models"),
                        &list,
                        format!("a non-empty list of the experiment's model ids {ids:?}"),
                    ));
                };
                if !model.is_some_and(|m| names.iter().any(|x| x == m)) {
                    continue;
                }
            }
            if let Some(v) = ct.get_mut("known_deviation") {
                if !per_model(format!("checks[{i}].known_deviation"), v)? {
                    ct.remove("known_deviation");
                }
            }
            kept.push(c);
        }
        *checks = kept;
    }
    Ok(())
}

/// Stage one: a merged table deserialised into raw structs; unknown keys are errors that
/// name their path.
pub fn read_raw(path: &Path, mut table: toml::Table) -> Result<RawExperiment> {
    table.iter_mut().for_each(|(_, v)| whole_floats(v));
    let raw: RawExperiment =
        serde_path_to_error::deserialize(table).map_err(|e: serde_path_to_error::Error<toml::de::Error>| {
            let key = e.path().to_string();
            let inner = e.into_inner();
            Error::Parse {
                file: path.display().to_string(),
                message: if key == "." || key.is_empty() {
                    serde_words(inner.message())
                } else {
                    format!("{key}: {}", serde_words(inner.message()))
                },
            }
        })?;
    Ok(raw)
}

/// Whole-valued floats (`1e3`, `4.0`) made integers, so that a key taking a whole number
/// reads them and its validation states the allowed range (`max_iters = 1e9`: "give a whole
/// number from 1 to 10000"); a key taking a float reads an integer as the same float.
/// Beyond 2^53 a float stays a float.
pub(in crate::experiment) fn whole_floats(v: &mut toml::Value) {
    match v {
        toml::Value::Float(f) if f.fract() == 0.0 && f.abs() <= 9_007_199_254_740_992.0 => {
            *v = toml::Value::Integer(*f as i64);
        }
        toml::Value::Array(a) => a.iter_mut().for_each(whole_floats),
        toml::Value::Table(t) => t.iter_mut().for_each(|(_, v)| whole_floats(v)),
        _ => {}
    }
}

/// A deserialiser's message in the words of the files: Rust's type names become what a
/// file gives ("expected i64" is "expected a whole number").
pub(in crate::experiment) fn serde_words(message: &str) -> String {
    [
        ("expected i64", "expected a whole number"),
        ("expected u64", "expected a whole number >= 0"),
        ("expected f64", "expected a number"),
    ]
    .iter()
    .fold(message.to_string(), |m, (from, to)| m.replace(from, to))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_is_deep_and_child_wins() {
        let mut base: toml::Table = toml::from_str("[a]\nx = 1\ny = 2\n[b]\nz = [1, 2]").unwrap();
        let child: toml::Table = toml::from_str("[a]\ny = 3\n[b]\nz = [5]").unwrap();
        merge(&mut base, child);
        assert_eq!(base["a"]["x"].as_integer(), Some(1));
        assert_eq!(base["a"]["y"].as_integer(), Some(3));
        assert_eq!(base["b"]["z"].as_array().map(|a| a.len()), Some(1));
    }
}
