//! The paper's figure under ours. A reviewer who has the paper keeps a scan of a figure in
//! `reference/scans/` (not in the repository: no redistributable copy of the paper exists)
//! with a small TOML file that says which plot it is and how its axes are calibrated (a
//! WebPlotDigitizer project, or two pixels and two values per axis). The experiment's page then
//! draws our curves over the scan in the scan's own pixel frame (reviewing.md, "The paper's
//! figure under ours").
//!
//! ```toml
//! title = "Fig. 5 of the paper"          # optional
//! experiment = "fig05_third_mode"
//! plot = "compliance"                    # the id of one of the experiment's plots
//! panel = 1                              # optional: which panel (1-based), default 1
//! models = ["stated"]                    # optional: the pages it goes on, default every model
//! image = "fig05.png"                    # PNG or JPEG, relative to this file
//! wpd = "fig05.json"                     # either the WebPlotDigitizer project (version 4) ...
//! x = { pixels = [112, 868], values = [44, 56] }               # ... or two pixels per axis,
//! y = { pixels = [590, 61], values = [1e-5, 1e-3], log = true } # numbered as in an image editor
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::figure::{Dash, Figure};
use crate::reference::digitised::{wpd_calibration, Calibration};

/// A scan of a paper figure with its calibration.
#[derive(Debug, Clone)]
pub struct Scan {
    /// The TOML file that describes it.
    pub file: PathBuf,
    /// Its stem (names the copy in the report).
    pub name: String,
    /// Title of the paper's figure.
    pub title: String,
    /// The experiment whose figure it goes under.
    pub experiment: String,
    /// The plot id of that figure.
    pub plot: String,
    /// 0-based.
    pub panel: usize,
    /// The models whose pages show it (empty: every model).
    pub models: Vec<String>,
    /// The scanned image.
    pub image: PathBuf,
    /// Its width, pixels.
    pub width: u32,
    /// Its height, pixels.
    pub height: u32,
    /// Pixels to data values.
    pub calibration: Calibration,
    /// Where the calibration comes from, in words.
    pub calibrated_by: String,
    /// From the calibration's pixels to the image's frame, where pixel i spans [i, i + 1):
    /// 0.5 for pixels typed as an image editor numbers them (the pixel's centre), 0 for a
    /// WebPlotDigitizer project (already in that frame).
    pub offset: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAxis {
    pixels: [f64; 2],
    values: [f64; 2],
    #[serde(default)]
    log: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScan {
    title: Option<String>,
    experiment: String,
    plot: String,
    panel: Option<usize>,
    models: Option<Vec<String>>,
    image: String,
    wpd: Option<String>,
    x: Option<RawAxis>,
    y: Option<RawAxis>,
}

/// The pixel size of a PNG or JPEG image.
pub fn image_size(path: &Path) -> Result<(u32, u32)> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let bad = |why: &str| Error::Parse { file: path.display().to_string(), message: why.to_string() };
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() >= 24 {
        let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
        return Ok((be(16), be(20)));
    }
    if bytes.starts_with(&[0xff, 0xd8]) {
        // Walk the JPEG segments to a start-of-frame marker (SOF0-SOF15 but DHT, JPG, DAC).
        let mut i = 2;
        while i + 9 < bytes.len() {
            if bytes[i] != 0xff {
                return Err(bad("a JPEG file whose segments cannot be read"));
            }
            let marker = bytes[i + 1];
            let len = usize::from(u16::from_be_bytes([bytes[i + 2], bytes[i + 3]]));
            if (0xc0..=0xcf).contains(&marker) && ![0xc4, 0xc8, 0xcc].contains(&marker) {
                let h = u16::from_be_bytes([bytes[i + 5], bytes[i + 6]]);
                let w = u16::from_be_bytes([bytes[i + 7], bytes[i + 8]]);
                return Ok((u32::from(w), u32::from(h)));
            }
            i += 2 + len;
        }
        return Err(bad("a JPEG file without a frame header"));
    }
    Err(bad("not a PNG or JPEG image"))
}

/// Reads one scan description.
pub fn load(file: &Path) -> Result<Scan> {
    let text = crate::error::read_to_string(file)?;
    let raw: RawScan =
        toml::from_str(&text).map_err(|e| Error::Parse { file: file.display().to_string(), message: e.to_string() })?;
    let dir = file.parent().unwrap_or(Path::new("."));
    let invalid = |key: &str, value: &dyn std::fmt::Display, why: &str| Error::invalid(file, key, value, why);
    let image = dir.join(&raw.image);
    if !image.is_file() {
        return Err(invalid("image", &format!("\"{}\"", raw.image), "a PNG or JPEG file beside this one"));
    }
    let (width, height) = image_size(&image)?;
    let (calibration, calibrated_by, offset) = match (&raw.wpd, &raw.x, &raw.y) {
        (Some(wpd), None, None) => {
            let path = dir.join(wpd);
            let text = crate::error::read_to_string(&path)?;
            let v: serde_json::Value = serde_json::from_str(&text)
                .map_err(|e| Error::Parse { file: path.display().to_string(), message: format!("not JSON: {e}") })?;
            let (c, _) = wpd_calibration(&path.display().to_string(), &v)?;
            (c, format!("calibrated by the WebPlotDigitizer project {wpd}"), 0.0)
        }
        (None, Some(x), Some(y)) => {
            let p = [(x.pixels[0], 0.0), (x.pixels[1], 0.0), (0.0, y.pixels[0]), (0.0, y.pixels[1])];
            let v = [x.values[0], x.values[1], y.values[0], y.values[1]];
            let c = Calibration::new(p, v, x.log, y.log).ok_or_else(|| {
                invalid(
                    "x, y",
                    &format!("{:?} -> {:?}, {:?} -> {:?}", x.pixels, x.values, y.pixels, y.values),
                    "two different pixels and two different values per axis (values > 0 on a log axis)",
                )
            })?;
            (c, "calibrated by two points per axis".to_string(), 0.5)
        }
        _ => {
            return Err(invalid(
                "wpd, x, y",
                &"(as given)",
                "the calibration: either wpd = \"PROJECT.json\" or both x = { pixels = [..], values = [..] } and y = { ... }",
            ))
        }
    };
    let panel = match raw.panel {
        Some(0) => return Err(invalid("panel", &0, "panels count from 1")),
        Some(k) => k - 1,
        None => 0,
    };
    let name = file.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
    Ok(Scan {
        file: file.to_path_buf(),
        title: raw.title.unwrap_or_else(|| format!("scan {name}")),
        name,
        experiment: raw.experiment,
        plot: raw.plot,
        panel,
        models: raw.models.unwrap_or_default(),
        image,
        width,
        height,
        calibration,
        calibrated_by,
        offset,
    })
}

/// Every scan described in `dir` (`*.toml`, in name order; none when the folder does not
/// exist).
pub fn load_all(dir: &Path) -> Result<Vec<Scan>> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files.iter().map(|f| load(f)).collect()
}

/// One of our series in the scan's pixels (the calibration's own frame: [`Scan::offset`]
/// from the image's): a polyline per unbroken run of points (line
/// series) or the points themselves (marker series).
#[derive(Debug, Clone)]
pub struct Trace {
    /// Legend label.
    pub label: String,
    /// Stroke colour (CSS).
    pub colour: String,
    /// Dashed stroke.
    pub dashed: bool,
    /// Drawn as a line (else as points).
    pub line: bool,
    /// Runs of (x, y) pixel points, each drawn unbroken.
    pub runs: Vec<Vec<(f64, f64)>>,
}

/// Our series of `scan.panel` of `fig`, in the scan's pixel frame. Points outside the panel's
/// horizontal range, or not positive on a log axis, break a line.
pub fn overlay(scan: &Scan, fig: &Figure) -> Result<Vec<Trace>> {
    let Some(panel) = fig.panels.get(scan.panel) else {
        return Err(Error::invalid(
            &scan.file,
            "panel",
            scan.panel + 1,
            format!("plot {} has {} panel(s)", fig.id, fig.panels.len()),
        ));
    };
    let (x0, x1) = panel.x_range;
    Ok(panel
        .series
        .iter()
        .map(|s| {
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for (&x, &y) in s.x.iter().zip(&s.y) {
                let inside = x.is_finite() && y.is_finite() && x >= x0 && x <= x1;
                match inside.then(|| scan.calibration.to_pixel(x, y)).flatten() {
                    Some(p) => runs.last_mut().map_or((), |r| r.push(p)),
                    None if runs.last().is_some_and(|r| !r.is_empty()) => runs.push(Vec::new()),
                    None => {}
                }
            }
            runs.retain(|r| !r.is_empty());
            Trace {
                label: s.label.clone(),
                colour: super::plot::colour_hex(s.color),
                dashed: s.dash != Dash::Solid,
                line: s.line,
                runs,
            }
        })
        .collect())
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The traces as an SVG element in the scan's frame (its viewBox is the scan's pixels), to lay
/// over the image.
pub fn svg(scan: &Scan, traces: &[Trace]) -> String {
    let mut out = format!(
        "<svg class=\"ours\" viewBox=\"0 0 {} {}\" preserveAspectRatio=\"none\" xmlns=\"http://www.w3.org/2000/svg\">",
        scan.width, scan.height
    );
    let o = scan.offset;
    for t in traces {
        out += &format!("<g stroke=\"{}\" fill=\"none\"><title>{}</title>", t.colour, escape(&t.label));
        for run in &t.runs {
            if t.line {
                let points: Vec<String> = run.iter().map(|(x, y)| format!("{:.2},{:.2}", x + o, y + o)).collect();
                let dash = if t.dashed { " stroke-dasharray=\"6 4\"" } else { "" };
                out += &format!("<polyline stroke-width=\"1.5\"{dash} points=\"{}\"/>", points.join(" "));
            } else {
                for (x, y) in run {
                    out += &format!("<circle cx=\"{:.2}\" cy=\"{:.2}\" r=\"3\" stroke-width=\"1.2\"/>", x + o, y + o);
                }
            }
        }
        out += "</g>";
    }
    out + "</svg>"
}
