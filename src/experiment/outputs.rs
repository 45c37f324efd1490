//! Validation of `[[plots]]` and `[[checks]]`.

use std::path::Path;

use crate::checks::reference::ValueFile;
use crate::error::{Error, Result};

use super::raw::{RawCheck, RawPlot};
use super::validate::{is_identifier, mass_index};
use super::{clearance_key, Analysis, CheckKind, CheckSpec, Linear, PlotKind, PlotSpec, Scale, Start, Tolerance};

/// Plot kinds each analysis kind can draw.
fn plot_kinds(analysis: &Analysis) -> &'static [(&'static str, PlotKind)] {
    match analysis {
        Analysis::Modal => &[],
        Analysis::LinearFrf { .. } | Analysis::Sweep { .. } => {
            &[("compliance", PlotKind::Compliance), ("compliance_panels", PlotKind::CompliancePanels)]
        }
        Analysis::ClearanceStudy { .. } => {
            &[("clearance_scan", PlotKind::ClearanceScan), ("compliance_panels", PlotKind::CompliancePanels)]
        }
        Analysis::Waveform { .. } => &[("waveform", PlotKind::Waveform)],
        Analysis::SdofPeriodic { .. } => {
            &[("orbits", PlotKind::Orbits), ("clearance_choice", PlotKind::ClearanceChoice)]
        }
        Analysis::Impulse { .. } => &[
            ("acceleration", PlotKind::Acceleration),
            ("decay", PlotKind::Decay),
            ("spectrum", PlotKind::Spectrum),
            ("damping", PlotKind::Damping),
        ],
    }
}

fn case_list(path: &Path, key: &str, cs: &[String], case_ids: &[String]) -> Result<()> {
    for (j, c) in cs.iter().enumerate() {
        if !case_ids.contains(c) {
            return Err(Error::invalid(
                path,
                format!("{key}[{j}]"),
                format!("\"{c}\""),
                format!("no such case; the cases are {case_ids:?}"),
            ));
        }
    }
    Ok(())
}

/// The case a check names.
fn case_ref(path: &Path, key: String, v: &Option<String>, case_ids: &[String]) -> Result<String> {
    match v {
        Some(c) if case_ids.contains(c) => Ok(c.clone()),
        Some(c) => {
            Err(Error::invalid(path, key, format!("\"{c}\""), format!("no such case; the cases are {case_ids:?}")))
        }
        None => Err(Error::invalid(path, key, "(missing)", "this check needs the case it compares")),
    }
}

/// Validates one plot.
pub fn plot(path: &Path, i: usize, p: RawPlot, n: usize, case_ids: &[String], analysis: &Analysis) -> Result<PlotSpec> {
    let key = |k: &str| format!("plots[{i}].{k}");
    if !is_identifier(&p.id) {
        return Err(Error::invalid(
            path,
            key("id"),
            format!("\"{}\"", p.id),
            "use letters, digits, '_' and '-' only (it names the image file)",
        ));
    }
    let kinds = plot_kinds(analysis);
    let Some(kind) = kinds.iter().find(|(name, _)| *name == p.kind).map(|(_, k)| *k) else {
        let allowed: Vec<String> = kinds.iter().map(|(name, _)| format!("\"{name}\"")).collect();
        return Err(Error::invalid(
            path,
            key("kind"),
            format!("\"{}\"", p.kind),
            format!(
                "analysis kind \"{}\" draws: {}",
                analysis.kind(),
                if allowed.is_empty() { "no plots".into() } else { allowed.join(", ") }
            ),
        ));
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
            case_list(path, &key("cases"), &cs, case_ids)?;
            cs
        }
        None => case_ids.to_vec(),
    };
    let y_scale = match p.y_scale.as_deref() {
        None | Some("log") => Scale::Log,
        Some("linear") => Scale::Linear,
        Some(other) => {
            return Err(Error::invalid(path, key("y_scale"), format!("\"{other}\""), "allowed: \"log\", \"linear\""))
        }
    };
    let marks: Vec<(String, f64)> = p.marks.unwrap_or_default().into_iter().map(|m| (m.label, m.offset_hz)).collect();
    for (j, (_, off)) in marks.iter().enumerate() {
        if !off.is_finite() {
            return Err(Error::invalid(path, format!("plots[{i}].marks[{j}].offset_hz"), off, "a finite offset in Hz"));
        }
    }
    let marks_relative_to = match p.marks_relative_to {
        Some(c) => {
            case_list(path, &key("marks_relative_to"), std::slice::from_ref(&c), case_ids)?;
            Some(c)
        }
        None if !marks.is_empty() => {
            return Err(Error::invalid(
                path,
                key("marks_relative_to"),
                "(missing)",
                "marks are offsets from the resonance peak of a case: name it",
            ));
        }
        None => None,
    };
    let linear = p
        .linear
        .unwrap_or_default()
        .iter()
        .enumerate()
        .map(|(j, l)| match l.as_str() {
            "bare" => Ok(Linear::Bare),
            "stuck" => Ok(Linear::Stuck),
            other => Err(Error::invalid(
                path,
                format!("plots[{i}].linear[{j}]"),
                format!("\"{other}\""),
                "allowed: \"bare\", \"stuck\"",
            )),
        })
        .collect::<Result<Vec<_>>>()?;
    let x_range = match p.x_range.as_deref() {
        None => None,
        Some(&[a, b]) if a.is_finite() && b.is_finite() && a < b => Some((a, b)),
        Some(v) => {
            return Err(Error::invalid(
                path,
                key("x_range"),
                format!("{v:?}"),
                "give [from, to] with from < to, both finite",
            ))
        }
    };
    Ok(PlotSpec {
        x_range,
        id: p.id,
        kind,
        title: p.title,
        masses,
        cases,
        y_scale,
        mark_natural_frequencies: p.mark_natural_frequencies.unwrap_or(false),
        marks,
        marks_relative_to,
        linear,
    })
}

/// Validates one check; reference files and ids must exist.
pub fn check(
    path: &Path,
    i: usize,
    c: RawCheck,
    n: usize,
    case_ids: &[String],
    analysis: &Analysis,
    reference_dir: &Path,
) -> Result<CheckSpec> {
    let key = |k: &str| format!("checks[{i}].{k}");
    let mode = |m: Option<i64>| -> Result<usize> {
        let Some(m) = m else {
            return Err(Error::invalid(path, key("mode"), "(missing)", format!("this check needs mode = 1..{n}")));
        };
        if m < 1 || m as usize > n {
            return Err(Error::invalid(path, key("mode"), m, format!("modes are numbered 1 to {n}")));
        }
        Ok(m as usize - 1)
    };
    let case = |field: &str, v: &Option<String>| case_ref(path, key(field), v, case_ids);
    for (k, v) in [("rel_tol", c.rel_tol), ("abs_tol", c.abs_tol), ("rel_tol_all", c.rel_tol_all)] {
        if let Some(v) = v {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(path, key(k), v, "a tolerance must be >= 0 and finite"));
            }
        }
    }
    let kind =
        match c.kind.as_str() {
            "natural_frequency" => CheckKind::NaturalFrequency { mode: mode(c.mode)? },
            "mode_shape" => CheckKind::ModeShape {
                mode: mode(c.mode)?,
                elements: match &c.elements {
                    Some(list) => list
                        .iter()
                        .enumerate()
                        .map(|(j, &m)| mass_index(path, &format!("checks[{i}].elements[{j}]"), m, n))
                        .collect::<Result<Vec<_>>>()?,
                    None => (0..n).collect(),
                },
            },
            "paper_parameters" => CheckKind::PaperParameters,
            "curve" => {
                let fraction = c.fraction.unwrap_or(1.0);
                if !(fraction > 0.0 && fraction <= 1.0) {
                    return Err(Error::invalid(path, key("fraction"), fraction, "a fraction of the points in (0, 1]"));
                }
                let rel = c.rel_tol.unwrap_or(0.0);
                let id = case("case", &c.case)?;
                let curve = match (analysis, c.direction.as_deref(), c.clearance_mm) {
                    (Analysis::Sweep { start: Start::Continuation, .. }, Some(dir @ ("up" | "down")), None) => {
                        format!("{id}:{dir}")
                    }
                    (Analysis::Sweep { start: Start::Continuation, .. }, _, _) => {
                        return Err(Error::invalid(
                            path,
                            key("direction"),
                            format!("{:?}", c.direction),
                            "a continuation sweep has an \"up\" and a \"down\" curve: give direction",
                        ));
                    }
                    (Analysis::ClearanceStudy { clearances_mm: Some(list), .. }, None, Some(mm))
                        if list.iter().any(|x| (x - mm).abs() < 1e-12) =>
                    {
                        clearance_key(&id, mm)
                    }
                    (Analysis::ClearanceStudy { .. }, _, _) => {
                        return Err(Error::invalid(
                            path,
                            key("clearance_mm"),
                            format!("{:?}", c.clearance_mm),
                            "name one of the clearances the study scans (analysis.clearances_mm)",
                        ));
                    }
                    (_, None, None) => id,
                    _ => {
                        return Err(Error::invalid(
                            path,
                            key("direction"),
                            "(given)",
                            "direction and clearance_mm only apply to continuation sweeps and clearance studies",
                        ))
                    }
                };
                CheckKind::Curve {
                    curve,
                    columns: c.columns.clone().unwrap_or_default(),
                    fraction,
                    rel_tol_all: c.rel_tol_all.unwrap_or(rel),
                }
            }
            "peak_ratio" => {
                let mass = match c.mass {
                    Some(m) => mass_index(path, &key("mass"), m, n)?,
                    None => {
                        return Err(Error::invalid(path, key("mass"), "(missing)", format!("name the mass (1 to {n})")))
                    }
                };
                let Some(upper_id) = c.range_to.clone() else {
                    return Err(Error::invalid(
                        path,
                        key("range_to"),
                        "(missing)",
                        "name the id of the range's upper bound in the reference file",
                    ));
                };
                CheckKind::PeakRatio {
                    case: case("case", &c.case)?,
                    over_case: case("over_case", &c.over_case)?,
                    mass,
                    upper_id,
                }
            }
            "orbit_vs_simulation" | "sdof_vs_simulation" => {
                if !matches!(analysis, Analysis::SdofPeriodic { .. }) {
                    return Err(Error::invalid(
                        path,
                        key("kind"),
                        format!("\"{}\"", c.kind),
                        format!("only an sdof_periodic analysis has periodic orbits (this one is \"{}\")", analysis.kind()),
                    ));
                }
                if c.kind == "orbit_vs_simulation" {
                    CheckKind::OrbitVsSimulation
                } else {
                    CheckKind::SdofVsSimulation
                }
            }
            "impulse_history" | "decay_time" | "decay_ratio" => {
                let Analysis::Impulse { levels, .. } = analysis else {
                    return Err(Error::invalid(
                        path,
                        key("kind"),
                        format!("\"{}\"", c.kind),
                        format!("only an impulse analysis has decay histories (this one is \"{}\")", analysis.kind()),
                    ));
                };
                impulse_check(path, i, &c, n, case_ids, levels)?
            }
            other => return Err(Error::invalid(
                path,
                key("kind"),
                format!("\"{other}\""),
                "allowed kinds: \"natural_frequency\", \"mode_shape\", \"paper_parameters\", \"curve\", \"peak_ratio\", \"impulse_history\", \"decay_time\", \"decay_ratio\", \"orbit_vs_simulation\", \"sdof_vs_simulation\"",
            )),
        };
    if c.rel_tol.is_none() && c.abs_tol.is_none() {
        return Err(Error::invalid(
            path,
            key("rel_tol"),
            "(missing)",
            "a check needs a tolerance: rel_tol and/or abs_tol",
        ));
    }
    let tolerance = Tolerance { rel: c.rel_tol.unwrap_or(0.0), abs: c.abs_tol.unwrap_or(0.0) };
    let reference = match (&kind, &c.reference) {
        (CheckKind::OrbitVsSimulation, None) => {
            return Ok(CheckSpec {
                kind,
                reference_file: String::new(),
                reference_id: None,
                tolerance,
                known_deviation: c.known_deviation,
            })
        }
        (CheckKind::OrbitVsSimulation, Some(r)) => {
            return Err(Error::invalid(
                path,
                key("reference"),
                format!("\"{r}\""),
                "this check compares two computations of the same run: it takes no reference",
            ))
        }
        (_, None) => {
            return Err(Error::invalid(
                path,
                key("reference"),
                "(missing)",
                "name the reference: FILE or FILE#ID under reference/",
            ))
        }
        (_, Some(r)) => r.clone(),
    };
    let (file, id) = match reference.split_once('#') {
        Some((f, id)) => (f.to_string(), Some(id.to_string())),
        None => (reference.clone(), None),
    };
    let ref_path = reference_dir.join(&file);
    if !ref_path.is_file() {
        return Err(Error::invalid(
            path,
            key("reference"),
            format!("\"{reference}\""),
            format!("no such reference file: {}", ref_path.display()),
        ));
    }
    let mut ids: Vec<&str> = Vec::new();
    match &kind {
        CheckKind::NaturalFrequency { .. } | CheckKind::ModeShape { .. } => match &id {
            Some(id) => ids.push(id),
            None => {
                return Err(Error::invalid(
                    path,
                    key("reference"),
                    format!("\"{reference}\""),
                    "name the value: FILE#ID",
                ))
            }
        },
        CheckKind::PeakRatio { upper_id, .. } => match &id {
            Some(id) => {
                ids.push(id);
                ids.push(upper_id);
            }
            None => {
                return Err(Error::invalid(
                    path,
                    key("reference"),
                    format!("\"{reference}\""),
                    "name the lower bound: FILE#ID",
                ))
            }
        },
        CheckKind::DecayRatio { .. } | CheckKind::SdofVsSimulation => match &id {
            Some(id) => ids.push(id),
            None => {
                return Err(Error::invalid(
                    path,
                    key("reference"),
                    format!("\"{reference}\""),
                    "name the upper bound of the ratio: FILE#ID",
                ))
            }
        },
        CheckKind::Curve { .. } | CheckKind::ImpulseHistory { .. } | CheckKind::DecayTime { .. }
            if !file.ends_with(".csv") =>
        {
            return Err(Error::invalid(
                path,
                key("reference"),
                format!("\"{reference}\""),
                "a curve reference is a CSV file",
            ));
        }
        _ => {}
    }
    if !ids.is_empty() {
        let values = ValueFile::load(&ref_path)?;
        for id in ids {
            if values.get(id).is_none() {
                return Err(Error::invalid(
                    path,
                    key("reference"),
                    format!("\"{reference}\""),
                    format!("{} has no quantity with id \"{id}\"", ref_path.display()),
                ));
            }
        }
    }
    Ok(CheckSpec { kind, reference_file: file, reference_id: id, tolerance, known_deviation: c.known_deviation })
}

/// The checks of an impulse analysis: `impulse_history`, `decay_time`, `decay_ratio`.
fn impulse_check(
    path: &Path,
    i: usize,
    c: &RawCheck,
    n: usize,
    case_ids: &[String],
    levels: &[f64],
) -> Result<CheckKind> {
    let key = |k: &str| format!("checks[{i}].{k}");
    let case = |field: &str, v: &Option<String>| case_ref(path, key(field), v, case_ids);
    let mass = || match c.mass {
        Some(m) => mass_index(path, &key("mass"), m, n),
        None => Err(Error::invalid(path, key("mass"), "(missing)", format!("name the mass (1 to {n})"))),
    };
    let level = |l: f64| -> Result<f64> {
        if l > 0.0 && l < 1.0 {
            Ok(l)
        } else {
            Err(Error::invalid(path, key("level"), l, "a fraction of the first envelope peak in (0, 1)"))
        }
    };
    Ok(match c.kind.as_str() {
        "impulse_history" => {
            let window = c.window_s.unwrap_or(0.02);
            if !(window.is_finite() && window > 0.0) {
                return Err(Error::invalid(path, key("window_s"), window, "a positive window (s)"));
            }
            CheckKind::ImpulseHistory { case: case("case", &c.case)?, window }
        }
        "decay_time" => CheckKind::DecayTime {
            case: case("case", &c.case)?,
            mass: mass()?,
            levels: match c.level {
                Some(l) => vec![level(l)?],
                None => levels.to_vec(),
            },
        },
        _ => CheckKind::DecayRatio {
            case: case("case", &c.case)?,
            over_case: case("over_case", &c.over_case)?,
            mass: mass()?,
            level: level(c.level.unwrap_or(0.1))?,
        },
    })
}
