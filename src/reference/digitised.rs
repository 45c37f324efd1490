//! Curves digitised from the paper's figures: shotdamp's reference format, and the import of
//! WebPlotDigitizer exports (its JSON project format, version 4, and its CSV export).
//!
//! A WebPlotDigitizer XY axis is calibrated by four points: X1 and X2 on the horizontal axis,
//! Y1 and Y2 on the vertical one, each with its pixel position and its value. The map from
//! pixels to values is the affine map `A p + c` (in the logarithm of a log axis) under which
//! going from X1 to X2 changes only x and going from Y1 to Y2 changes only y, as in
//! WebPlotDigitizer itself. One pixel then spans `|row of A|` in data units (in decades on a
//! log axis, given here as a relative size): that is the digitising uncertainty a check scales.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// What was digitised, by whom, and the size of one pixel in data units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DigitisedMeta {
    /// Always "digitised figure".
    pub provenance: String,
    /// The paper figure, e.g. "Fig. 8".
    pub figure: String,
    /// What the curves were digitised from (document, page, image).
    pub source: String,
    /// Who digitised the curves.
    pub digitised_by: String,
    /// The tool and format.
    pub tool: String,
    /// The file imported.
    pub imported_from: String,
    /// Unit of x.
    pub x_unit: String,
    /// Unit of y.
    pub y_unit: String,
    /// Logarithmic x axis in the figure.
    pub x_log: bool,
    /// Logarithmic y axis in the figure.
    pub y_log: bool,
    /// One pixel in data units on a linear axis, or as a relative size on a log axis.
    pub x_pixel: f64,
    /// One pixel on the y axis, as `x_pixel`.
    pub y_pixel: f64,
}

/// One digitised curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DigitisedCurve {
    /// The dataset's name in the digitiser.
    pub name: String,
    /// The computed case it is compared with, if known.
    #[serde(default)]
    pub case: Option<String>,
    /// The mass (1-based), if known.
    #[serde(default)]
    pub mass: Option<i64>,
    /// Abscissae, in the file's x unit.
    pub x: Vec<f64>,
    /// Ordinates, in the file's y unit.
    pub y: Vec<f64>,
}

/// A file of digitised curves (`reference/digitised/*.toml`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DigitisedFile {
    /// Where the curves come from.
    pub meta: DigitisedMeta,
    /// The curves.
    pub curve: Vec<DigitisedCurve>,
}

impl DigitisedFile {
    /// A curve by name.
    pub fn get(&self, name: &str) -> Option<&DigitisedCurve> {
        self.curve.iter().find(|c| c.name == name)
    }

    /// The file as TOML text.
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string(self).map_err(|e| Error::Render { what: "digitised reference".into(), message: e.to_string() })
    }
}

/// What the user says about an import (the digitiser does not know it).
#[derive(Debug, Clone, Default)]
pub struct ImportInfo {
    /// The paper figure, e.g. "Fig. 8".
    pub figure: String,
    /// What the curves were digitised from.
    pub source: String,
    /// Who digitised them.
    pub digitised_by: String,
    /// The file imported.
    pub imported_from: String,
    /// Unit of x.
    pub x_unit: String,
    /// Unit of y.
    pub y_unit: String,
    /// Dataset name -> (case, 1-based mass).
    pub mapping: Vec<(String, String, i64)>,
    /// For CSV exports, which carry no calibration: axis scales and pixel sizes.
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// One pixel on the x axis (linear: data units; log: relative size).
    pub x_pixel: Option<f64>,
    /// One pixel on the y axis, as `x_pixel`.
    pub y_pixel: Option<f64>,
}

fn bad(file: &str, what: impl Into<String>) -> Error {
    Error::Parse { file: file.to_string(), message: what.into() }
}

/// The calibration of an XY axis: pixels to values (log10 of values on log axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// The linear part of the map from pixels: `[x, y] = a [px, py] + c`.
    pub a: [[f64; 2]; 2],
    /// Its offset.
    pub c: [f64; 2],
    /// Logarithmic x axis (the map gives log10 x).
    pub x_log: bool,
    /// Logarithmic y axis (the map gives log10 y).
    pub y_log: bool,
}

impl Calibration {
    /// From the four calibration points (pixels, values) X1, X2, Y1, Y2.
    pub fn new(p: [(f64, f64); 4], v: [f64; 4], x_log: bool, y_log: bool) -> Option<Calibration> {
        let t = |val: f64, log: bool| if log { val.log10() } else { val };
        let (xmin, xmax, ymin, ymax) = (t(v[0], x_log), t(v[1], x_log), t(v[2], y_log), t(v[3], y_log));
        // Columns: X1 - X2 and Y1 - Y2 in pixels.
        let (p00, p10) = (p[0].0 - p[1].0, p[0].1 - p[1].1);
        let (p01, p11) = (p[2].0 - p[3].0, p[2].1 - p[3].1);
        let det = p00 * p11 - p01 * p10;
        if det == 0.0 || !det.is_finite() || !(xmin - xmax).is_finite() || !(ymin - ymax).is_finite() {
            return None;
        }
        let inv = [[p11 / det, -p01 / det], [-p10 / det, p00 / det]];
        // A = diag(xmin - xmax, ymin - ymax) inv.
        let a = [
            [(xmin - xmax) * inv[0][0], (xmin - xmax) * inv[0][1]],
            [(ymin - ymax) * inv[1][0], (ymin - ymax) * inv[1][1]],
        ];
        let c = [xmin - a[0][0] * p[0].0 - a[0][1] * p[0].1, ymin - a[1][0] * p[2].0 - a[1][1] * p[2].1];
        Some(Calibration { a, c, x_log, y_log })
    }

    /// The value at a pixel.
    pub fn value(&self, px: f64, py: f64) -> (f64, f64) {
        let u = self.a[0][0] * px + self.a[0][1] * py + self.c[0];
        let w = self.a[1][0] * px + self.a[1][1] * py + self.c[1];
        (if self.x_log { 10f64.powf(u) } else { u }, if self.y_log { 10f64.powf(w) } else { w })
    }

    /// The pixel of a value (the inverse of [`Calibration::value`]); `None` for a value <= 0
    /// on a log axis.
    pub fn to_pixel(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let t = |v: f64, log: bool| if log { (v > 0.0).then(|| v.log10()) } else { Some(v) };
        let (u, w) = (t(x, self.x_log)? - self.c[0], t(y, self.y_log)? - self.c[1]);
        let det = self.a[0][0] * self.a[1][1] - self.a[0][1] * self.a[1][0];
        Some(((self.a[1][1] * u - self.a[0][1] * w) / det, (self.a[0][0] * w - self.a[1][0] * u) / det))
    }

    /// One pixel in data units (linear axis) or as a relative size (log axis): x, y.
    pub fn pixel(&self) -> (f64, f64) {
        let size = |row: [f64; 2], log: bool| {
            let d = row[0].hypot(row[1]);
            if log {
                10f64.powf(d) - 1.0
            } else {
                d
            }
        };
        (size(self.a[0], self.x_log), size(self.a[1], self.y_log))
    }
}

fn mapped(info: &ImportInfo, name: &str) -> (Option<String>, Option<i64>) {
    info.mapping.iter().find(|(n, _, _)| n == name).map_or((None, None), |(_, c, m)| (Some(c.clone()), Some(*m)))
}

/// The calibration of the first XY axes of a WebPlotDigitizer JSON project (version 4), and
/// the axes' name.
pub fn wpd_calibration(file: &str, v: &serde_json::Value) -> Result<(Calibration, String)> {
    let version = v.get("version").and_then(|x| x.as_array()).and_then(|a| a.first()).and_then(|x| x.as_i64());
    if version != Some(4) {
        return Err(bad(file, format!("WebPlotDigitizer project version {version:?}: version 4 is supported")));
    }
    let axes = v
        .get("axesColl")
        .and_then(|a| a.as_array())
        .and_then(|a| a.iter().find(|x| x.get("type").and_then(|t| t.as_str()) == Some("XYAxes")))
        .ok_or_else(|| bad(file, "no XY axes (axesColl with type \"XYAxes\")"))?;
    let axes_name = axes.get("name").and_then(|x| x.as_str()).unwrap_or("XY").to_string();
    let flag = |k: &str| axes.get(k).and_then(|x| x.as_bool()).unwrap_or(false);
    let (x_log, y_log) = (flag("isLogX"), flag("isLogY"));
    let points = axes
        .get("calibrationPoints")
        .and_then(|x| x.as_array())
        .filter(|a| a.len() == 4)
        .ok_or_else(|| bad(file, "the XY axes need 4 calibration points"))?;
    let num = |x: &serde_json::Value| x.as_f64().or_else(|| x.as_str().and_then(|s| s.trim().parse().ok()));
    let mut px = [(0.0, 0.0); 4];
    let mut val = [0.0; 4];
    for (k, p) in points.iter().enumerate() {
        let field =
            |f: &str| p.get(f).and_then(num).ok_or_else(|| bad(file, format!("calibration point {}: no {f}", k + 1)));
        px[k] = (field("px")?, field("py")?);
        val[k] = if k < 2 { field("dx")? } else { field("dy")? };
    }
    let cal = Calibration::new(px, val, x_log, y_log)
        .ok_or_else(|| bad(file, "the calibration points are degenerate (or a log axis has a value <= 0)"))?;
    Ok((cal, axes_name))
}

/// Imports a WebPlotDigitizer JSON project (version 4): the first XY axes, every dataset on
/// them, values recomputed from the pixels with the calibration.
pub fn import_wpd_json(file: &str, text: &str, info: &ImportInfo) -> Result<DigitisedFile> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| bad(file, format!("not JSON: {e}")))?;
    let (cal, axes_name) = wpd_calibration(file, &v)?;
    let (x_log, y_log) = (cal.x_log, cal.y_log);
    let num = |x: &serde_json::Value| x.as_f64().or_else(|| x.as_str().and_then(|s| s.trim().parse().ok()));
    let datasets = v.get("datasetColl").and_then(|x| x.as_array()).ok_or_else(|| bad(file, "no datasetColl"))?;
    let mut curve = Vec::new();
    for d in datasets {
        if d.get("axesName").and_then(|x| x.as_str()).is_some_and(|n| n != axes_name) {
            continue;
        }
        let name = d.get("name").and_then(|x| x.as_str()).unwrap_or("dataset").to_string();
        let data = d
            .get("data")
            .and_then(|x| x.as_array())
            .ok_or_else(|| bad(file, format!("dataset \"{name}\": no data")))?;
        let mut pts: Vec<(f64, f64)> = data
            .iter()
            .map(|p| {
                let (x, y) = (p.get("x").and_then(num), p.get("y").and_then(num));
                match (x, y) {
                    (Some(x), Some(y)) => match cal.value(x, y) {
                        (vx, vy) if vx.is_finite() && vy.is_finite() => Ok((vx, vy)),
                        (vx, vy) => Err(bad(
                            file,
                            format!("dataset \"{name}\": the point at pixel ({x}, {y}) is ({vx}, {vy}) in data units, not finite (its axes' calibration?)"),
                        )),
                    },
                    _ => Err(bad(file, format!("dataset \"{name}\": a point without pixel x, y"))),
                }
            })
            .collect::<Result<_>>()?;
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (case, mass) = mapped(info, &name);
        curve.push(DigitisedCurve {
            name,
            case,
            mass,
            x: pts.iter().map(|p| p.0).collect(),
            y: pts.iter().map(|p| p.1).collect(),
        });
    }
    if curve.is_empty() {
        return Err(bad(file, "no dataset on the XY axes"));
    }
    let (xp, yp) = cal.pixel();
    Ok(DigitisedFile { meta: meta(info, "WebPlotDigitizer project (JSON, version 4)", x_log, y_log, xp, yp), curve })
}

fn meta(info: &ImportInfo, tool: &str, x_log: bool, y_log: bool, x_pixel: f64, y_pixel: f64) -> DigitisedMeta {
    DigitisedMeta {
        provenance: "digitised figure".into(),
        figure: info.figure.clone(),
        source: info.source.clone(),
        digitised_by: info.digitised_by.clone(),
        tool: tool.into(),
        imported_from: info.imported_from.clone(),
        x_unit: info.x_unit.clone(),
        y_unit: info.y_unit.clone(),
        x_log,
        y_log,
        x_pixel,
        y_pixel,
    }
}

/// Imports a WebPlotDigitizer CSV export: either plain `x,y` rows (one dataset), or its
/// "all datasets" layout (a row of dataset names over `X,Y` column pairs, then the values).
/// The CSV carries no calibration: the pixel sizes and axis scales come from `info`.
pub fn import_wpd_csv(file: &str, text: &str, info: &ImportInfo) -> Result<DigitisedFile> {
    let (Some(x_pixel), Some(y_pixel)) = (info.x_pixel, info.y_pixel) else {
        return Err(bad(file, "a CSV export has no calibration: give the size of one pixel (--x-pixel, --y-pixel)"));
    };
    for (flag, v) in [("--x-pixel", x_pixel), ("--y-pixel", y_pixel)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(
                file,
                format!(
                    "{flag} {v}: the size of one pixel must be a positive number (data units, relative on a log axis)"
                ),
            ));
        }
    }
    let rows: Vec<Vec<String>> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|c| c.trim().trim_matches('"').to_string()).collect())
        .collect();
    let numeric = |r: &Vec<String>| r.iter().filter(|c| !c.is_empty()).all(|c| c.parse::<f64>().is_ok());
    let header = rows.iter().take_while(|r| !numeric(r)).count();
    let names: Vec<String> = match header {
        0 => vec!["Default Dataset".into()],
        _ => rows[0].iter().step_by(2).map(|n| if n.is_empty() { "dataset".into() } else { n.clone() }).collect(),
    };
    let mut curve: Vec<DigitisedCurve> = names
        .iter()
        .map(|n| {
            let (case, mass) = mapped(info, n);
            DigitisedCurve { name: n.clone(), case, mass, x: Vec::new(), y: Vec::new() }
        })
        .collect();
    for (line, r) in rows.iter().enumerate().skip(header) {
        if let Some(extra) = r.iter().skip(2 * curve.len()).position(|c| !c.is_empty()) {
            return Err(bad(
                file,
                format!(
                    "line {}: a value in column {}, beyond the {} column(s) of the {} dataset(s) the header names",
                    line + 1,
                    2 * curve.len() + extra + 1,
                    2 * curve.len(),
                    curve.len()
                ),
            ));
        }
        for (k, c) in curve.iter_mut().enumerate() {
            let (x, y) = (r.get(2 * k).filter(|s| !s.is_empty()), r.get(2 * k + 1).filter(|s| !s.is_empty()));
            if let (Some(x), Some(y)) = (x, y) {
                let p = |s: &str, column: usize, log: bool| {
                    let v = s.parse::<f64>().map_err(|_| {
                        bad(file, format!("line {}, column {column}: \"{s}\" is not a number", line + 1))
                    })?;
                    if !v.is_finite() || (log && v <= 0.0) {
                        let allowed = if log { "a positive finite number (log axis)" } else { "a finite number" };
                        return Err(bad(file, format!("line {}, column {column}: \"{s}\" is not {allowed}", line + 1)));
                    }
                    Ok(v)
                };
                c.x.push(p(x, 2 * k + 1, info.x_log)?);
                c.y.push(p(y, 2 * k + 2, info.y_log)?);
            }
        }
    }
    curve.retain(|c| !c.x.is_empty());
    if curve.is_empty() {
        return Err(bad(file, "no data rows"));
    }
    for c in &mut curve {
        let mut pts: Vec<(f64, f64)> = c.x.iter().copied().zip(c.y.iter().copied()).collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        c.x = pts.iter().map(|p| p.0).collect();
        c.y = pts.iter().map(|p| p.1).collect();
    }
    Ok(DigitisedFile {
        meta: meta(info, "WebPlotDigitizer CSV export", info.x_log, info.y_log, x_pixel, y_pixel),
        curve,
    })
}

/// Reads a digitised reference file.
pub fn load(path: &std::path::Path) -> Result<DigitisedFile> {
    let text = crate::error::read_to_string(path)?;
    let file: DigitisedFile = toml::from_str(&text).map_err(|e| Error::Parse {
        file: path.display().to_string(),
        message: e.to_string().trim_end().to_string(),
    })?;
    validate(path, &file)?;
    Ok(file)
}

/// Pixel sizes are positive and finite; every curve has as many finite x as y values (positive
/// on a log axis), at least one. What an import writes is held to it too.
pub(super) fn validate(path: &std::path::Path, f: &DigitisedFile) -> Result<()> {
    for (key, v) in [("meta.x_pixel", f.meta.x_pixel), ("meta.y_pixel", f.meta.y_pixel)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(path, key, v, "a positive size of one pixel in data units"));
        }
    }
    for (k, c) in f.curve.iter().enumerate() {
        if c.x.is_empty() || c.x.len() != c.y.len() {
            return Err(Error::invalid(
                path,
                format!("curve[{k}] (\"{}\")", c.name),
                format!("{} x and {} y values", c.x.len(), c.y.len()),
                "as many x as y values, at least one",
            ));
        }
        for (axis, values, log) in [("x", &c.x, f.meta.x_log), ("y", &c.y, f.meta.y_log)] {
            if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite() || (log && **v <= 0.0)) {
                let allowed = if log { "a positive finite number (log axis)" } else { "a finite number" };
                return Err(Error::invalid(path, format!("curve[{k}] (\"{}\").{axis}[{i}]", c.name), v, allowed));
            }
        }
    }
    Ok(())
}
