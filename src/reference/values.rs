//! Files of values stated in a source (`reference/paper-text.toml`, the independent solver's
//! values): each quantity with its unit, the section that states it and the source's words.

use std::path::Path;

use serde::Deserialize;

use crate::error::{read_to_string, Error, Result};

/// A file of reference values, such as `reference/paper-text.toml`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValueFile {
    /// Where the numbers come from.
    pub meta: ValueFileMeta,
    #[serde(rename = "quantity")]
    /// The quantities.
    pub quantities: Vec<Quantity>,
}

/// Where a value file's numbers come from.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValueFileMeta {
    /// Kind of source: "paper text", "digitised figure", "independent solver".
    pub provenance: String,
    /// The document the numbers come from.
    pub source: String,
}

/// One stated quantity, scalar or vector.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    /// Identifier the checks name it by.
    pub id: String,
    #[serde(default)]
    /// A scalar value.
    pub value: Option<f64>,
    #[serde(default)]
    /// A vector of values.
    pub values: Option<Vec<f64>>,
    /// Unit of the value(s).
    pub unit: String,
    /// Section of the source that states it.
    pub section: String,
    /// The source's words.
    pub quote: String,
    #[serde(default)]
    /// A remark on how to read it.
    pub note: Option<String>,
}

impl ValueFile {
    /// Reads, parses and validates a value file: ids are unique; a quantity has a finite
    /// `value`, a non-empty list of finite `values`, or neither (a claim in words).
    pub fn load(path: &Path) -> Result<ValueFile> {
        let text = read_to_string(path)?;
        let file: ValueFile = toml::from_str(&text).map_err(|e| Error::Parse {
            file: path.display().to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        for (k, q) in file.quantities.iter().enumerate() {
            let key = |what: &str| format!("quantity[{k}] (id \"{}\").{what}", q.id);
            if file.quantities[..k].iter().any(|p| p.id == q.id) {
                return Err(Error::invalid(path, key("id"), &q.id, "ids are unique within a file"));
            }
            match (q.value, &q.values) {
                (Some(v), None) if !v.is_finite() => {
                    return Err(Error::invalid(path, key("value"), v, "a finite number"))
                }
                (None, Some(vs)) if vs.is_empty() => {
                    return Err(Error::invalid(path, key("values"), "[]", "at least one finite number"))
                }
                (None, Some(vs)) => {
                    if let Some((i, v)) = vs.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                        return Err(Error::invalid(path, key(&format!("values[{i}]")), v, "a finite number"));
                    }
                }
                (Some(_), Some(_)) => {
                    return Err(Error::invalid(path, key("value"), "(both value and values)", "give one of them"))
                }
                // A number, or a claim stated in words (its check says how it is judged).
                _ => {}
            }
        }
        Ok(file)
    }

    /// The quantity with this id.
    pub fn get(&self, id: &str) -> Option<&Quantity> {
        self.quantities.iter().find(|q| q.id == id)
    }

    /// A human-readable provenance line for a quantity.
    pub fn provenance(&self, q: &Quantity) -> String {
        format!("{}: {}, section {} (\"{}\")", self.meta.provenance, self.meta.source, q.section, q.quote)
    }
}
