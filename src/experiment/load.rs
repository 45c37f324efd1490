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
    let table = parse_table(path, &text)?;
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
            format!("no such file: {}", parent_path.display()),
        ));
    }
    let mut base = read_merged_depth(&parent_path, depth + 1)?;
    base.remove("extends");
    merge(&mut base, table);
    Ok(base)
}

/// Stage one: the merged table deserialised into raw structs; unknown keys are errors that
/// name their path.
pub fn read_raw(path: &Path) -> Result<RawExperiment> {
    let table = read_merged(path)?;
    let raw: RawExperiment =
        serde_path_to_error::deserialize(table).map_err(|e: serde_path_to_error::Error<toml::de::Error>| {
            let key = e.path().to_string();
            let inner = e.into_inner();
            Error::Parse {
                file: path.display().to_string(),
                message: if key == "." || key.is_empty() {
                    inner.message().to_string()
                } else {
                    format!("{key}: {}", inner.message())
                },
            }
        })?;
    Ok(raw)
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
