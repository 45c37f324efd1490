//! Stage two: raw structs to typed, validated values. Every error names the file, the key,
//! the value and what is allowed.

use std::path::Path;

use nalgebra::DMatrix;

use crate::checks::reference::ValueFile;
use crate::error::{Error, Result};
use crate::model::{Damper, Damping, Structure};

use super::raw::{RawAnalysis, RawCase, RawCheck, RawExperiment, RawGrid, RawPlot, RawStructure};
use super::{
    Analysis, Case, CheckKind, CheckSpec, Excitation, Experiment, Meta, PlotKind, PlotSpec, Scale,
    Tolerance,
};

/// Most grid points a frequency axis may have.
const MAX_GRID_POINTS: usize = 100_000;

/// Validates a raw experiment read from `path`.
pub fn validate(path: &Path, raw: RawExperiment, reference_dir: &Path) -> Result<Experiment> {
    let bad =
        |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);

    let m = raw.experiment;
    if !is_identifier(&m.id) {
        return Err(bad(
            "experiment.id",
            &format!("\"{}\"", m.id),
            "use letters, digits, '_' and '-' only (it names the report folder)",
        ));
    }
    let meta = Meta {
        id: m.id,
        title: m.title,
        figure: m.figure,
        caption: m.caption,
        claim: m.claim,
        assumptions: m.assumptions,
        notes: m.notes,
    };

    let (structure, source, damping_assumption) = structure(path, raw.structure)?;
    let n = structure.dof();

    let e = raw.excitation;
    let driven = mass_index(path, "excitation.mass", e.mass, n)?;
    if !(e.force_n.is_finite() && e.force_n > 0.0) {
        return Err(bad(
            "excitation.force_n",
            &e.force_n,
            "the force amplitude must be positive and finite (N)",
        ));
    }
    let excitation = Excitation {
        mass: driven,
        force: e.force_n,
    };

    let analysis = analysis(path, raw.analysis)?;
    let cases = cases(path, raw.cases, &structure)?;
    let case_ids: Vec<String> = cases.iter().map(|c| c.id.clone()).collect();
    let plots = raw
        .plots
        .into_iter()
        .enumerate()
        .map(|(i, p)| plot(path, i, p, n, &case_ids))
        .collect::<Result<Vec<_>>>()?;
    let checks = raw
        .checks
        .into_iter()
        .enumerate()
        .map(|(i, c)| check(path, i, c, n, reference_dir))
        .collect::<Result<Vec<_>>>()?;

    Ok(Experiment {
        path: path.to_path_buf(),
        meta,
        structure,
        structure_source: source,
        damping_assumption,
        excitation,
        analysis,
        cases,
        plots,
        checks,
    })
}

fn is_identifier(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

fn mass_index(path: &Path, key: &str, value: i64, n: usize) -> Result<usize> {
    if value < 1 || value as usize > n {
        return Err(Error::invalid(
            path,
            key,
            value,
            format!("masses are numbered 1 to {n} (the structure has {n} masses)"),
        ));
    }
    Ok(value as usize - 1)
}

fn positive_list(path: &Path, key: &str, values: &[f64], what: &str) -> Result<()> {
    if values.is_empty() {
        return Err(Error::invalid(
            path,
            key,
            "[]",
            format!("give at least one {what}"),
        ));
    }
    for (i, v) in values.iter().enumerate() {
        if !(v.is_finite() && *v > 0.0) {
            return Err(Error::invalid(
                path,
                format!("{key}[{i}]"),
                v,
                format!("a {what} must be positive and finite"),
            ));
        }
    }
    Ok(())
}

fn structure(path: &Path, s: RawStructure) -> Result<(Structure, Option<String>, Option<String>)> {
    positive_list(path, "structure.masses_kg", &s.masses_kg, "mass")?;
    let n = s.masses_kg.len();
    let k = match (&s.chain_stiffness_n_per_m, &s.stiffness_matrix_n_per_m) {
        (Some(k), None) => {
            positive_list(path, "structure.chain_stiffness_n_per_m", k, "stiffness")?;
            if k.len() != n {
                return Err(Error::invalid(
                    path,
                    "structure.chain_stiffness_n_per_m",
                    format!("{} values", k.len()),
                    format!("expected {n} stiffnesses, one per mass (masses_kg has {n})"),
                ));
            }
            crate::model::structure::chain_stiffness(k)
        }
        (None, Some(rows)) => stiffness_matrix(path, rows, n)?,
        _ => {
            return Err(Error::invalid(
                path,
                "structure",
                "chain_stiffness_n_per_m / stiffness_matrix_n_per_m",
                "give exactly one of chain_stiffness_n_per_m and stiffness_matrix_n_per_m",
            ))
        }
    };
    let d = s.damping;
    let damping = match (d.modal_ratios, d.rayleigh_alpha, d.rayleigh_beta) {
        (Some(z), None, None) => {
            if z.len() != n {
                return Err(Error::invalid(
                    path,
                    "structure.damping.modal_ratios",
                    format!("{} values", z.len()),
                    format!("expected {n} damping ratios, one per mode"),
                ));
            }
            for (i, v) in z.iter().enumerate() {
                if !(v.is_finite() && *v >= 0.0 && *v < 1.0) {
                    return Err(Error::invalid(
                        path,
                        format!("structure.damping.modal_ratios[{i}]"),
                        v,
                        "a modal damping ratio must lie in [0, 1)",
                    ));
                }
            }
            Damping::ModalRatios(z)
        }
        (None, Some(alpha), Some(beta)) => {
            for (key, v) in [("rayleigh_alpha", alpha), ("rayleigh_beta", beta)] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(Error::invalid(
                        path,
                        format!("structure.damping.{key}"),
                        v,
                        "Rayleigh coefficients must be non-negative and finite",
                    ));
                }
            }
            Damping::Rayleigh { alpha, beta }
        }
        _ => {
            return Err(Error::invalid(
                path,
                "structure.damping",
                "(incomplete)",
                "give either modal_ratios = [...] or both rayleigh_alpha and rayleigh_beta",
            ))
        }
    };
    Ok((
        Structure::from_matrices(&s.masses_kg, k, damping),
        s.source,
        d.assumption,
    ))
}

fn stiffness_matrix(path: &Path, rows: &[Vec<f64>], n: usize) -> Result<DMatrix<f64>> {
    let key = "structure.stiffness_matrix_n_per_m";
    if rows.len() != n || rows.iter().any(|r| r.len() != n) {
        return Err(Error::invalid(
            path,
            key,
            format!("{} rows", rows.len()),
            format!("expected {n} rows of {n} values"),
        ));
    }
    let k = DMatrix::from_fn(n, n, |i, j| rows[i][j]);
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (k[(i, j)], k[(j, i)]);
            if !a.is_finite() || (a - b).abs() > 1e-12 * a.abs().max(b.abs()) {
                return Err(Error::invalid(
                    path,
                    format!("{key}[{i}][{j}]"),
                    a,
                    "the stiffness matrix must be symmetric and finite",
                ));
            }
        }
    }
    if k.clone().cholesky().is_none() {
        return Err(Error::invalid(
            path,
            key,
            "(matrix)",
            "the stiffness matrix must be positive definite",
        ));
    }
    Ok(k)
}

/// A frequency grid in Hz, validated.
pub fn grid(path: &Path, key: &str, g: &RawGrid) -> Result<Vec<f64>> {
    let bad = |k: &str, v: &dyn std::fmt::Display, msg: &str| {
        Error::invalid(path, format!("{key}.{k}"), v, msg)
    };
    if !(g.start.is_finite() && g.start > 0.0) {
        return Err(bad(
            "start",
            &g.start,
            "frequencies must be positive and finite (Hz)",
        ));
    }
    if !(g.stop.is_finite() && g.stop > g.start) {
        return Err(bad(
            "stop",
            &g.stop,
            &format!("stop must be greater than start = {}", g.start),
        ));
    }
    let points = match (g.points, g.step) {
        (Some(p), None) => {
            if p < 2 || p as usize > MAX_GRID_POINTS {
                return Err(bad(
                    "points",
                    &p,
                    &format!("give 2 to {MAX_GRID_POINTS} points"),
                ));
            }
            p as usize
        }
        (None, Some(s)) => {
            let span = g.stop - g.start;
            if !(s.is_finite() && s > 0.0 && span / s < MAX_GRID_POINTS as f64) {
                return Err(bad(
                    "step",
                    &s,
                    &format!("the step must be positive and give at most {MAX_GRID_POINTS} points"),
                ));
            }
            // Round so that 8..60 step 0.1 includes 60 despite floating point.
            (span / s + 1e-9).floor() as usize + 1
        }
        _ => {
            return Err(Error::invalid(
                path,
                key,
                "(grid)",
                "give exactly one of points and step",
            ));
        }
    };
    Ok(match g.step {
        Some(s) => (0..points)
            .map(|i| round_hz(g.start + s * i as f64))
            .collect(),
        None => (0..points)
            .map(|i| g.start + (g.stop - g.start) * i as f64 / (points - 1) as f64)
            .collect(),
    })
}

/// Grid values from a step are rounded to 1e-9 Hz so that they print as written.
fn round_hz(f: f64) -> f64 {
    (f * 1e9).round() / 1e9
}

fn analysis(path: &Path, a: RawAnalysis) -> Result<Analysis> {
    match a.kind.as_str() {
        "modal" => Ok(Analysis::Modal),
        "linear_frf" => {
            let Some(g) = &a.freq_hz else {
                return Err(Error::invalid(
                    path,
                    "analysis.freq_hz",
                    "(missing)",
                    "linear_frf needs a grid: freq_hz = { start, stop, points | step }",
                ));
            };
            Ok(Analysis::LinearFrf {
                freq_hz: grid(path, "analysis.freq_hz", g)?,
            })
        }
        other => Err(Error::invalid(
            path,
            "analysis.kind",
            format!("\"{other}\""),
            "allowed kinds: \"modal\", \"linear_frf\"",
        )),
    }
}

fn cases(path: &Path, raw: Vec<RawCase>, s: &Structure) -> Result<Vec<Case>> {
    let n = s.dof();
    let mut out: Vec<Case> = Vec::with_capacity(raw.len());
    for (ci, c) in raw.into_iter().enumerate() {
        if !is_identifier(&c.id) {
            return Err(Error::invalid(
                path,
                format!("cases[{ci}].id"),
                format!("\"{}\"", c.id),
                "use letters, digits, '_' and '-' only",
            ));
        }
        if out.iter().any(|o| o.id == c.id) {
            return Err(Error::invalid(
                path,
                format!("cases[{ci}].id"),
                format!("\"{}\"", c.id),
                "case ids must be unique",
            ));
        }
        let mut dampers = Vec::with_capacity(c.dampers.len());
        for (di, d) in c.dampers.into_iter().enumerate() {
            let key = |k: &str| format!("cases[{ci}].dampers[{di}].{k}");
            let host = mass_index(path, &key("mass"), d.mass, n)?;
            let mass = match (d.mass_ratio, d.mass_kg) {
                (Some(r), None) => {
                    if !(r.is_finite() && r > 0.0) {
                        return Err(Error::invalid(
                            path,
                            key("mass_ratio"),
                            r,
                            "a mass ratio must be positive",
                        ));
                    }
                    r * s.masses[host]
                }
                (None, Some(m)) => {
                    if !(m.is_finite() && m > 0.0) {
                        return Err(Error::invalid(
                            path,
                            key("mass_kg"),
                            m,
                            "a damper mass must be positive",
                        ));
                    }
                    m
                }
                _ => {
                    return Err(Error::invalid(
                        path,
                        key("mass_ratio"),
                        "(missing)",
                        "give exactly one of mass_ratio and mass_kg",
                    ))
                }
            };
            let clearance = clearance(path, &key("clearance_mm"), &d.clearance_mm)?;
            dampers.push(Damper {
                host,
                mass,
                clearance,
            });
        }
        out.push(Case {
            id: c.id,
            label: c.label,
            dampers,
        });
    }
    Ok(out)
}

/// A clearance in mm (number or "inf") to metres.
fn clearance(path: &Path, key: &str, v: &toml::Value) -> Result<f64> {
    let mm = match v {
        toml::Value::Float(f) => *f,
        toml::Value::Integer(i) => *i as f64,
        toml::Value::String(s) if s == "inf" => f64::INFINITY,
        other => {
            return Err(Error::invalid(
                path,
                key,
                other,
                "a clearance is a number of millimetres >= 0, or \"inf\" for no top",
            ))
        }
    };
    if mm.is_nan() || mm < 0.0 {
        return Err(Error::invalid(
            path,
            key,
            mm,
            "a clearance must be >= 0 mm (or \"inf\")",
        ));
    }
    Ok(mm * 1e-3)
}

fn plot(path: &Path, i: usize, p: RawPlot, n: usize, case_ids: &[String]) -> Result<PlotSpec> {
    let key = |k: &str| format!("plots[{i}].{k}");
    if !is_identifier(&p.id) {
        return Err(Error::invalid(
            path,
            key("id"),
            format!("\"{}\"", p.id),
            "use letters, digits, '_' and '-' only (it names the image file)",
        ));
    }
    let kind = match p.kind.as_str() {
        "compliance" => PlotKind::Compliance,
        other => {
            return Err(Error::invalid(
                path,
                key("kind"),
                format!("\"{other}\""),
                "allowed kinds: \"compliance\"",
            ))
        }
    };
    let masses = match p.masses {
        Some(ms) => ms
            .iter()
            .enumerate()
            .map(|(j, &m)| mass_index(path, &format!("plots[{i}].masses[{j}]"), m, n))
            .collect::<Result<Vec<_>>>()?,
        None => (0..n).collect(),
    };
    let cases = match p.cases {
        Some(cs) => {
            for (j, c) in cs.iter().enumerate() {
                if !case_ids.contains(c) {
                    return Err(Error::invalid(
                        path,
                        format!("plots[{i}].cases[{j}]"),
                        format!("\"{c}\""),
                        format!("no such case; the cases are {case_ids:?}"),
                    ));
                }
            }
            cs
        }
        None => case_ids.to_vec(),
    };
    let y_scale = match p.y_scale.as_deref() {
        None | Some("log") => Scale::Log,
        Some("linear") => Scale::Linear,
        Some(other) => {
            return Err(Error::invalid(
                path,
                key("y_scale"),
                format!("\"{other}\""),
                "allowed: \"log\", \"linear\"",
            ))
        }
    };
    Ok(PlotSpec {
        id: p.id,
        kind,
        title: p.title,
        masses,
        cases,
        y_scale,
        mark_natural_frequencies: p.mark_natural_frequencies.unwrap_or(false),
    })
}

fn check(path: &Path, i: usize, c: RawCheck, n: usize, reference_dir: &Path) -> Result<CheckSpec> {
    let key = |k: &str| format!("checks[{i}].{k}");
    let mode = |m: Option<i64>| -> Result<usize> {
        let Some(m) = m else {
            return Err(Error::invalid(
                path,
                key("mode"),
                "(missing)",
                format!("this check needs mode = 1..{n}"),
            ));
        };
        if m < 1 || m as usize > n {
            return Err(Error::invalid(
                path,
                key("mode"),
                m,
                format!("modes are numbered 1 to {n}"),
            ));
        }
        Ok(m as usize - 1)
    };
    let kind = match c.kind.as_str() {
        "natural_frequency" => CheckKind::NaturalFrequency {
            mode: mode(c.mode)?,
        },
        "mode_shape" => CheckKind::ModeShape {
            mode: mode(c.mode)?,
        },
        "paper_parameters" => CheckKind::PaperParameters,
        other => {
            return Err(Error::invalid(
                path,
                key("kind"),
                format!("\"{other}\""),
                "allowed kinds: \"natural_frequency\", \"mode_shape\", \"paper_parameters\"",
            ))
        }
    };
    for (k, v) in [("rel_tol", c.rel_tol), ("abs_tol", c.abs_tol)] {
        if let Some(v) = v {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(
                    path,
                    key(k),
                    v,
                    "a tolerance must be >= 0 and finite",
                ));
            }
        }
    }
    if c.rel_tol.is_none() && c.abs_tol.is_none() {
        return Err(Error::invalid(
            path,
            key("rel_tol"),
            "(missing)",
            "a check needs a tolerance: rel_tol and/or abs_tol",
        ));
    }
    let tolerance = Tolerance {
        rel: c.rel_tol.unwrap_or(0.0),
        abs: c.abs_tol.unwrap_or(0.0),
    };
    let (file, id) = match c.reference.split_once('#') {
        Some((f, id)) => (f.to_string(), Some(id.to_string())),
        None => (c.reference.clone(), None),
    };
    let ref_path = reference_dir.join(&file);
    if !ref_path.is_file() {
        return Err(Error::invalid(
            path,
            key("reference"),
            format!("\"{}\"", c.reference),
            format!("no such reference file: {}", ref_path.display()),
        ));
    }
    let needs_id = !matches!(kind, CheckKind::PaperParameters);
    if needs_id {
        let Some(id) = &id else {
            return Err(Error::invalid(
                path,
                key("reference"),
                format!("\"{}\"", c.reference),
                "name the value: FILE#ID",
            ));
        };
        let values = ValueFile::load(&ref_path)?;
        if values.get(id).is_none() {
            return Err(Error::invalid(
                path,
                key("reference"),
                format!("\"{}\"", c.reference),
                format!("{} has no quantity with id \"{id}\"", ref_path.display()),
            ));
        }
    }
    Ok(CheckSpec {
        kind,
        reference_file: file,
        reference_id: id,
        tolerance,
        known_deviation: c.known_deviation,
    })
}
