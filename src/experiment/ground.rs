//! Ground-motion record files: PEER's `.AT2` (both header styles PEER has used) and a
//! two-column CSV with its acceleration unit named in its header. A bad file is refused with
//! its line and column. Gives [`GroundMotion`] (SI units).

use std::path::Path;

use crate::model::ground::GroundMotion;
use crate::model::GRAVITY;
use crate::{Error, Result};

/// Reads a record file: `.AT2` (any case) as PEER's format, anything else as CSV.
pub fn read(path: &Path) -> Result<GroundMotion> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let at2 = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if at2 {
        parse_at2(&text, path)
    } else {
        parse_csv(&text, path)
    }
}

pub use crate::model::ground::Record;

/// Most records one time history may run.
pub const MAX_RECORDS: usize = 64;

/// Most samples one record may have.
pub const MAX_SAMPLES: usize = 2_000_000;

/// Reads and scales the ground motions at `key` of the experiment file `path`
/// (`analysis.ground_motions`, `design.ground_motions`; their files relative to it).
pub fn records(path: &Path, key: &str, raw: &[super::file::raw_ground::RawGroundMotion]) -> Result<Vec<Record>> {
    if raw.is_empty() || raw.len() > MAX_RECORDS {
        return Err(Error::invalid(
            path,
            key,
            format!("{} records", raw.len()),
            format!("list 1 to {MAX_RECORDS} records: {{ file = \"...\", peak_g = ... }}"),
        ));
    }
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut out: Vec<Record> = Vec::new();
    for (i, r) in raw.iter().enumerate() {
        let at = |k: &str| format!("{key}[{i}].{k}");
        let file = dir.join(&r.file);
        if !file.is_file() {
            return Err(Error::invalid(
                path,
                at("file"),
                format!("\"{}\"", r.file),
                format!("no such file: {} (paths are relative to the experiment file)", file.display()),
            ));
        }
        let motion = read(&file)?;
        if motion.accel_m_s2.len() < 2 || motion.accel_m_s2.len() > MAX_SAMPLES {
            return Err(Error::invalid(
                path,
                at("file"),
                format!("{} samples", motion.accel_m_s2.len()),
                format!("a record of 2 to {MAX_SAMPLES} samples"),
            ));
        }
        let (peak, _) = motion.peak();
        let (motion, scaling) = match (r.scale, r.peak_g) {
            (Some(_), Some(g)) => {
                return Err(Error::invalid(path, at("peak_g"), g, "give one of scale and peak_g, not both"))
            }
            (Some(s), None) => {
                if !(s.is_finite() && s > 0.0 && s <= 1e3) {
                    return Err(Error::invalid(path, at("scale"), s, "a factor above 0 and at most 1000"));
                }
                let words = if s == 1.0 {
                    "as recorded".to_string()
                } else {
                    format!("scaled by {}", crate::number::fmt_num(s))
                };
                (motion.scaled(s), words)
            }
            (None, Some(g)) => {
                if !(g.is_finite() && g > 0.0 && g <= 10.0) {
                    return Err(Error::invalid(path, at("peak_g"), g, "a peak above 0 and at most 10 g"));
                }
                if peak == 0.0 {
                    return Err(Error::invalid(
                        path,
                        at("peak_g"),
                        g,
                        "the record is all zero: it cannot be scaled to a peak",
                    ));
                }
                let factor = g * GRAVITY / peak;
                (
                    motion.scaled_to_peak_g(g),
                    format!(
                        "scaled to a peak of {} g (x {})",
                        crate::number::fmt_num(g),
                        crate::number::fmt_sig(factor, 4)
                    ),
                )
            }
            (None, None) => (motion, "as recorded".to_string()),
        };
        let stem = Path::new(&r.file)
            .file_stem()
            .map_or_else(|| format!("record{}", i + 1), |s| s.to_string_lossy().into_owned());
        let mut key: String =
            stem.to_ascii_lowercase().chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
        if out.iter().any(|o| o.key == key) {
            key = format!("{key}_{}", i + 1);
        }
        let name = r.name.clone().unwrap_or_else(|| motion.name.clone());
        out.push(Record { key, name, file: r.file.clone(), scaling, motion, direction: r.direction.clone() });
    }
    Ok(out)
}

/// The storeys' heights at `key` (one for all, or one a storey of `n`), each above 0 and at
/// most 1000 m.
pub fn heights(
    path: &Path,
    key: &str,
    raw: Option<&super::file::raw_ground::RawHeights>,
    n: usize,
) -> Result<Option<Vec<f64>>> {
    let heights = match raw {
        None => return Ok(None),
        Some(super::file::raw_ground::RawHeights::One(h)) => vec![*h; n],
        Some(super::file::raw_ground::RawHeights::Each(list)) => {
            if list.len() != n {
                return Err(Error::invalid(
                    path,
                    key,
                    format!("{} heights", list.len()),
                    format!("give one height for every storey, or one a storey ({n})"),
                ));
            }
            list.clone()
        }
    };
    if let Some(h) = heights.iter().find(|h| !(h.is_finite() && **h > 0.0 && **h <= 1e3)) {
        return Err(Error::invalid(path, key, h, "storey heights above 0 and at most 1000 m"));
    }
    Ok(Some(heights))
}

/// The direction a structure's supports move in, in a file's words: "along" a chain (any lumped
/// structure), or a finite-element model's `base_direction`.
pub fn supports_direction(structure: &crate::model::Structure) -> &str {
    structure.supports.as_ref().map_or("along", |s| s.direction.as_str())
}

/// Refuses a record (at `key[i].direction`) whose stated direction is not the one the
/// structure's supports move in: one model shakes along one direction (a finite-element
/// model's reduction is made for its `base_direction`).
pub fn directions_fit<'a>(
    path: &Path,
    key: &str,
    stated: impl Iterator<Item = Option<&'a str>>,
    structure: &crate::model::Structure,
) -> Result<()> {
    let along = supports_direction(structure);
    for (i, d) in stated.enumerate() {
        if let Some(d) = d.filter(|d| *d != along) {
            let allowed = if structure.supports.is_some() {
                format!(
                    "\"{along}\": this finite-element model's supports move along {along} (structure.finite_element.base_direction; its reduction is made for it: to shake along another axis, set base_direction and run it as its own experiment)"
                )
            } else {
                "\"along\": the supports of a chain move along it".to_string()
            };
            return Err(Error::invalid(path, format!("{key}[{i}].direction"), format!("\"{d}\""), allowed));
        }
    }
    Ok(())
}

/// An error at `line` (1-based) and `column` (1-based, characters) of `file`.
fn at(file: &Path, line: usize, column: usize, value: &str, what: &str) -> Error {
    Error::invalid(file, format!("line {line}, column {column}"), format!("\"{value}\""), what)
}

/// The numbers of a line, each with its column (1-based), split at blanks and commas.
fn fields(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices() {
        let sep = c.is_whitespace() || c == ',';
        match (sep, start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                out.push((s, &line[s..i]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, &line[s..]));
    }
    out.into_iter().map(|(i, f)| (line[..i].chars().count() + 1, f)).collect()
}

/// A finite number at `(line, column)`, or the error naming them.
fn number(file: &Path, line: usize, (column, text): (usize, &str), what: &str) -> Result<f64> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(at(file, line, column, text, what)),
    }
}

/// PEER's `.AT2`: three title lines (the database, the event and station, "ACCELERATION TIME
/// SERIES IN UNITS OF G"), then the count and step, either as `NPTS= N, DT= dt SEC` (the NGA
/// files) or as two bare numbers first on the line (the older files: `N dt NPTS, DT`), then
/// the accelerations in g, several a line. The count must be what follows.
pub fn parse_at2(text: &str, file: &Path) -> Result<GroundMotion> {
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < 4 {
        return Err(at(
            file,
            lines.len() + 1,
            1,
            "(end of file)",
            "a PEER .AT2 record: three title lines, a line with NPTS and DT, then the accelerations",
        ));
    }
    let unit = lines[2];
    if !unit.to_ascii_uppercase().contains("UNITS OF G") {
        return Err(at(file, 3, 1, unit.trim(), "the title line \"ACCELERATION TIME SERIES IN UNITS OF G\""));
    }
    let header = lines[3];
    let upper = header.to_ascii_uppercase();
    let (count, dt) = if upper.contains("NPTS=") {
        let after = |key: &str| -> Result<(usize, &str)> {
            let i = upper.find(key).map(|i| i + key.len()).unwrap_or(header.len());
            let rest = &header[i..];
            let f = fields(rest).into_iter().next().ok_or_else(|| at(file, 4, i + 1, rest.trim(), "a number"))?;
            Ok((header[..i].chars().count() + f.0, f.1))
        };
        let n = after("NPTS=")?;
        let d = after("DT=")?;
        (n, d)
    } else {
        let f = fields(header);
        if f.len() < 2 {
            return Err(at(
                file,
                4,
                1,
                header.trim(),
                "NPTS= N, DT= STEP SEC, or the count and the step first on the line",
            ));
        }
        (f[0], f[1])
    };
    let n = number(file, 4, count, "the number of points, a whole number")?;
    if !(n >= 1.0 && n.fract() == 0.0) {
        return Err(at(file, 4, count.0, count.1, "the number of points, a whole number of at least 1"));
    }
    let dt_s = number(file, 4, dt, "the time step in seconds, a number above 0")?;
    if dt_s <= 0.0 {
        return Err(at(file, 4, dt.0, dt.1, "the time step in seconds, a number above 0"));
    }
    let mut accel_m_s2 = Vec::with_capacity(n as usize);
    for (i, line) in lines.iter().enumerate().skip(4) {
        for f in fields(line) {
            accel_m_s2.push(number(file, i + 1, f, "an acceleration in g")? * GRAVITY);
        }
    }
    if accel_m_s2.len() != n as usize {
        return Err(at(
            file,
            4,
            count.0,
            count.1,
            &format!("the number of points that follow ({} values are given)", accel_m_s2.len()),
        ));
    }
    let name = format!("{} ({})", lines[1].trim(), lines[0].trim());
    Ok(GroundMotion { name, dt_s, accel_m_s2 })
}

/// The units a CSV's acceleration column may name in its header, and their size in m/s^2.
pub const CSV_UNITS: [(&str, f64); 4] = [("(g)", GRAVITY), ("(m/s^2)", 1.0), ("(m/s2)", 1.0), ("(cm/s^2)", 0.01)];

/// A two-column CSV: a header `time, acc (UNIT)` naming the unit (g, m/s^2, cm/s^2), then
/// time in s and acceleration rows at a constant step from 0.
pub fn parse_csv(text: &str, file: &Path) -> Result<GroundMotion> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let units = CSV_UNITS.iter().map(|u| u.0).collect::<Vec<_>>().join(", ");
    let Some((_, header)) = lines.next() else {
        return Err(at(file, 1, 1, "(empty)", "a header \"time, acc (UNIT)\" and rows of time and acceleration"));
    };
    let lower = header.to_ascii_lowercase().replace(' ', "");
    let Some(scale) = CSV_UNITS.iter().find(|u| lower.contains(u.0)).map(|u| u.1) else {
        return Err(at(file, 1, 1, header.trim(), &format!("a header naming the acceleration's unit: one of {units}")));
    };
    let (mut times, mut accel_m_s2) = (Vec::new(), Vec::new());
    for (i, line) in lines {
        let f = fields(line);
        if f.len() != 2 {
            return Err(at(file, i + 1, 1, line.trim(), "two columns: time (s), acceleration"));
        }
        times.push((i + 1, f[0], number(file, i + 1, f[0], "a time in s")?));
        accel_m_s2.push(number(file, i + 1, f[1], "an acceleration")? * scale);
    }
    if times.len() < 2 {
        return Err(at(file, 2, 1, "(too few rows)", "at least two rows of time and acceleration"));
    }
    let dt_s = times[1].2 - times[0].2;
    if times[0].2 != 0.0 {
        let (l, f, _) = times[0];
        return Err(at(file, l, f.0, f.1, "a record starting at time 0"));
    }
    for (k, &(l, f, t)) in times.iter().enumerate() {
        // A constant step, to the rounding of the times written.
        if dt_s <= 0.0 || dt_s.is_nan() || (t - k as f64 * dt_s).abs() > 1e-6 * dt_s.max(t.abs()) {
            return Err(at(
                file,
                l,
                f.0,
                f.1,
                &format!("time {} s: a constant step ({dt_s} s from the first two rows)", k as f64 * dt_s),
            ));
        }
    }
    let name = file.file_name().map_or_else(|| file.display().to_string(), |n| n.to_string_lossy().into_owned());
    Ok(GroundMotion { name, dt_s, accel_m_s2 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("r.AT2")
    }

    #[test]
    fn both_peer_header_styles_give_the_same_record() {
        let body = "  .1E-01  -.2E-01   .3E-01\n  .4E-01\n";
        let nga = format!("PEER NGA STRONG MOTION DATABASE RECORD\nE, S, 180\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=      4, DT=   .0100 SEC,\n{body}");
        let old = format!("PEER STRONG MOTION DATABASE RECORD\nE, S, 180\nACCELERATION TIME SERIES IN UNITS OF G\n    4    .01000    NPTS, DT\n{body}");
        let a = parse_at2(&nga, p()).unwrap();
        let b = parse_at2(&old, p()).unwrap();
        assert_eq!(a.accel_m_s2, b.accel_m_s2);
        assert_eq!((a.dt_s, a.accel_m_s2.len()), (0.01, 4));
        assert_eq!(a.accel_m_s2[1], -0.02 * GRAVITY);
    }

    #[test]
    fn a_bad_record_names_its_line_and_column() {
        let head = "PEER\nE\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=      3, DT=   .0100 SEC\n";
        let err = parse_at2(&format!("{head}  .1  x.2  .3\n"), p()).unwrap_err().to_string();
        assert!(err.contains("line 5, column 7") && err.contains("\"x.2\""), "{err}");
        let err = parse_at2(&format!("{head}  .1  .2\n"), p()).unwrap_err().to_string();
        assert!(err.contains("line 4, column 12") && err.contains("(2 values are given)"), "{err}");
        let err = parse_at2(&head.replace("UNITS OF G", "UNITS OF CM/S/S"), p()).unwrap_err().to_string();
        assert!(err.contains("line 3, column 1"), "{err}");
        let err = parse_at2(&head.replace(".0100", "-.01"), p()).unwrap_err().to_string();
        assert!(err.contains("line 4") && err.contains("above 0"), "{err}");
    }

    #[test]
    fn a_csv_names_its_unit_and_keeps_a_constant_step() {
        let csv = Path::new("r.csv");
        let r = parse_csv("time,acc (g)\n0,0\n0.02,0.5\n0.04,-0.25\n", csv).unwrap();
        assert_eq!((r.dt_s, r.accel_m_s2.clone()), (0.02, vec![0.0, 0.5 * GRAVITY, -0.25 * GRAVITY]));
        let cm = parse_csv("t, a (cm/s^2)\n0, 100\n0.5, 200\n", csv).unwrap();
        assert_eq!(cm.accel_m_s2, vec![1.0, 2.0]);
        let err = parse_csv("time,acc\n0,0\n0.02,1\n", csv).unwrap_err().to_string();
        assert!(err.contains("line 1") && err.contains("(g)"), "{err}");
        let err = parse_csv("time,acc (g)\n0,0\n0.02,1\n0.05,1\n", csv).unwrap_err().to_string();
        assert!(err.contains("line 4, column 1") && err.contains("constant step"), "{err}");
        let err = parse_csv("time,acc (g)\n0,0\n0.02,1,3\n", csv).unwrap_err().to_string();
        assert!(err.contains("line 3") && err.contains("two columns"), "{err}");
    }
}
