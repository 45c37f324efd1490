//! `shotdamp reference import`: a WebPlotDigitizer project (`.json`) or export (`.csv`)
//! written as a digitised reference file (`reference/digitised/NAME.toml`), with who digitised
//! it from what, and the size of one pixel.

use std::path::{Path, PathBuf};

use super::digitised::{import_wpd_csv, import_wpd_json, DigitisedFile, ImportInfo};
use crate::error::{read_to_string, Error, Result};

/// One `--map` value, `DATASET=CASE:MASS` (e.g. `"Default Dataset=D:1"`), as the dataset, the
/// case and the 1-based mass.
pub fn parse_mapping(m: &str) -> Result<(String, String, i64)> {
    m.split_once('=')
        .and_then(|(d, rest)| {
            let (case, mass) = rest.split_once(':')?;
            Some((d.to_string(), case.to_string(), mass.trim().parse::<i64>().ok()?))
        })
        .ok_or_else(|| Error::invalid("--map", "map", m, "give DATASET=CASE:MASS, e.g. \"Default Dataset=D:1\""))
}

/// A digitised file written.
#[derive(Debug)]
pub struct Imported {
    /// Where it was written.
    pub dest: PathBuf,
    /// What was written.
    pub file: DigitisedFile,
}

impl Imported {
    /// Points over all curves.
    pub fn points(&self) -> usize {
        self.file.curve.iter().map(|c| c.x.len()).sum()
    }
}

/// Reads `file` (a WebPlotDigitizer `.json` project or `.csv` export), converts it with `info`
/// and writes it to `dest` (default: `reference/digitised/STEM.toml` below `reference`),
/// headed by its provenance.
pub fn import_file(file: &Path, info: &ImportInfo, dest: Option<&Path>, reference: &Path) -> Result<Imported> {
    let name = file.display().to_string();
    let text = read_to_string(file)?;
    let parsed = match file.extension().and_then(|e| e.to_str()) {
        Some("json") => import_wpd_json(&name, &text, info)?,
        Some("csv") => import_wpd_csv(&name, &text, info)?,
        _ => {
            return Err(Error::invalid(
                &name,
                "(file)",
                name.clone(),
                "a WebPlotDigitizer .json project or .csv export",
            ))
        }
    };
    // Never write what the loader refuses (every value was checked above, with its line).
    super::digitised::validate(file, &parsed)?;
    let stem = file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "digitised".into());
    let dest = dest.map(Path::to_path_buf).unwrap_or_else(|| reference.join("digitised").join(format!("{stem}.toml")));
    if let Some(parent) = dest.parent() {
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
    }
    let body = parsed.to_toml()?;
    let header = format!(
        "# Digitised from {} ({}) by {}; imported by shotdamp from {}. One pixel is x_pixel, y_pixel\n# in data units (relative on a log axis). Never edit the numbers to make a check pass.\n",
        parsed.meta.figure, parsed.meta.source, parsed.meta.digitised_by, parsed.meta.imported_from
    );
    std::fs::write(&dest, header + &body).map_err(|e| Error::io(&dest, e))?;
    Ok(Imported { dest, file: parsed })
}
