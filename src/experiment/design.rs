//! Validation of `[design]` (analysis kind "design", docs/design.md): every key named in its
//! error, with the value and what is allowed.

use std::path::Path;

use crate::design::search::Options;
use crate::design::{Band, Combine, Measure, Spec, Sweep};
use crate::error::{Error, Result};

use super::analysis::grid;
use super::raw::RawDesign;

/// A 1-based mass list as 0-based indices, each in range and distinct.
fn masses(path: &Path, key: &str, list: &[i64], n: usize) -> Result<Vec<usize>> {
    if list.is_empty() {
        return Err(Error::invalid(path, key, "[]", format!("name at least one mass (1 to {n})")));
    }
    let mut out = Vec::with_capacity(list.len());
    for (i, &m) in list.iter().enumerate() {
        if m < 1 || m as usize > n {
            return Err(Error::invalid(
                path,
                format!("{key}[{i}]"),
                m,
                format!("masses are numbered 1 to {n} (the structure has {n} masses)"),
            ));
        }
        if out.contains(&(m as usize - 1)) {
            return Err(Error::invalid(path, format!("{key}[{i}]"), m, "each mass once"));
        }
        out.push(m as usize - 1);
    }
    Ok(out)
}

fn whole(path: &Path, key: &str, v: Option<i64>, default: usize, max: usize) -> Result<usize> {
    match v {
        None => Ok(default),
        Some(x) if x >= 1 && x as usize <= max => Ok(x as usize),
        Some(x) => Err(Error::invalid(path, key, x, format!("give a whole number from 1 to {max}"))),
    }
}

/// The design of an experiment: required by kind "design", refused by every other kind.
/// `total_mass`: the structure's total mass, kg (for a shot mass ratio).
pub fn design(path: &Path, raw: Option<RawDesign>, kind: &str, n: usize, total_mass: f64) -> Result<Option<Spec>> {
    let raw = match (raw, kind) {
        (None, "design") => {
            return Err(Error::invalid(path, "design", "(missing)", "analysis kind \"design\" needs a [design] table"))
        }
        (None, _) => return Ok(None),
        (Some(_), k) if k != "design" => {
            return Err(Error::invalid(
                path,
                "design",
                "(given)",
                format!("only analysis kind \"design\" reads [design] (this file's kind is \"{k}\")"),
            ))
        }
        (Some(r), _) => r,
    };
    let bad = |key: &str, v: &dyn std::fmt::Display, msg: &str| Error::invalid(path, format!("design.{key}"), v, msg);
    let candidates = masses(path, "design.candidates", &raw.candidates, n)?;
    let max_beds = whole(path, "design.max_beds", raw.max_beds, candidates.len(), candidates.len())?;
    let shot_kg = match (raw.shot_mass_ratio, raw.shot_kg) {
        (Some(r), None) if r.is_finite() && r > 0.0 && r <= 10.0 => r * total_mass,
        (Some(r), None) => return Err(bad("shot_mass_ratio", &r, "a total shot mass ratio in (0, 10]")),
        (None, Some(kg)) if kg.is_finite() && kg > 0.0 => kg,
        (None, Some(kg)) => return Err(bad("shot_kg", &kg, "a shot mass in kg, positive and finite")),
        _ => {
            return Err(bad("shot_mass_ratio", &"(missing or both)", "give exactly one of shot_mass_ratio and shot_kg"))
        }
    };
    let clearance_mm = match raw.clearance_mm.as_slice() {
        &[lo, hi] if lo.is_finite() && hi.is_finite() && 0.0 < lo && lo < hi => (lo, hi),
        other => {
            return Err(bad("clearance_mm", &format!("{other:?}"), "[min, max] in mm with 0 < min < max, both finite"))
        }
    };
    let measure = match raw.measure.as_deref() {
        None | Some("peak") => Measure::Peak,
        Some("rms") => Measure::Rms,
        Some(other) => return Err(bad("measure", &format!("\"{other}\""), "\"peak\" or \"rms\"")),
    };
    let sweeps = match &raw.sweeps {
        None => vec![Sweep::Up, Sweep::Down],
        Some(list) if !list.is_empty() => list
            .iter()
            .enumerate()
            .map(|(i, s)| match s.as_str() {
                "rest" => Ok(Sweep::Rest),
                "up" => Ok(Sweep::Up),
                "down" => Ok(Sweep::Down),
                other => Err(bad(&format!("sweeps[{i}]"), &format!("\"{other}\""), "\"rest\", \"up\" or \"down\"")),
            })
            .collect::<Result<_>>()?,
        Some(_) => return Err(bad("sweeps", &"[]", "at least one of \"rest\", \"up\", \"down\"")),
    };
    if raw.bands.is_empty() {
        return Err(bad("bands", &"[]", "give at least one [[design.bands]] (name, freq_hz, masses)"));
    }
    let bands = raw
        .bands
        .iter()
        .enumerate()
        .map(|(i, b)| {
            Ok(Band {
                name: b.name.clone(),
                freq_hz: grid(path, &format!("design.bands[{i}].freq_hz"), &b.freq_hz)?,
                masses: masses(path, &format!("design.bands[{i}].masses"), &b.masses, n)?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let pareto_mass_ratios = raw.pareto_mass_ratios.clone().unwrap_or_default();
    if let Some((i, r)) =
        pareto_mass_ratios.iter().enumerate().find(|(_, r)| !(r.is_finite() && **r > 0.0 && **r <= 10.0))
    {
        return Err(bad(&format!("pareto_mass_ratios[{i}]"), r, "total shot mass ratios in (0, 10]"));
    }
    let scenario_models = raw.scenarios.as_ref().and_then(|sc| sc.models).unwrap_or(false);
    let (scenario_damping, scenario_force_n, combine) = match &raw.scenarios {
        None => (Vec::new(), Vec::new(), Combine::Worst),
        Some(sc) => {
            let damping = sc.damping.clone().unwrap_or_default();
            if let Some((i, z)) = damping.iter().enumerate().find(|(_, z)| !(z.is_finite() && **z >= 0.0 && **z < 1.0))
            {
                return Err(bad(&format!("scenarios.damping[{i}]"), z, "a modal damping ratio in [0, 1)"));
            }
            let force = sc.force_n.clone().unwrap_or_default();
            if let Some((i, f)) = force.iter().enumerate().find(|(_, f)| !(f.is_finite() && **f > 0.0)) {
                return Err(bad(&format!("scenarios.force_n[{i}]"), f, "a force amplitude in N, positive and finite"));
            }
            if damping.is_empty() && force.is_empty() && !scenario_models {
                return Err(bad("scenarios", &"(empty)", "give damping = [...], force_n = [...] and/or models = true"));
            }
            let combine = match sc.combine.as_deref() {
                None | Some("worst") => Combine::Worst,
                Some("mean") => Combine::Mean,
                Some(other) => return Err(bad("scenarios.combine", &format!("\"{other}\""), "\"worst\" or \"mean\"")),
            };
            (damping, force, combine)
        }
    };
    let sdof = match &raw.sdof {
        None => None,
        Some(sd) => {
            if sd.mode < 1 || sd.mode as usize > n {
                return Err(bad("sdof.mode", &sd.mode, &format!("modes are numbered 1 to {n}")));
            }
            if sd.clearances_mm.is_empty() {
                return Err(bad("sdof.clearances_mm", &"[]", "the candidate clearances of the SDOF rule, mm"));
            }
            if let Some((i, d)) = sd.clearances_mm.iter().enumerate().find(|(_, d)| !(d.is_finite() && **d > 0.0)) {
                return Err(bad(&format!("sdof.clearances_mm[{i}]"), d, "a clearance in mm, positive and finite"));
            }
            Some((sd.mode as usize - 1, sd.clearances_mm.clone()))
        }
    };
    let defaults = Options::default();
    let search = Options {
        starts: whole(path, "design.starts", raw.starts, defaults.starts, 100)?,
        max_iters: whole(path, "design.max_iters", raw.max_iters, defaults.max_iters as usize, 100_000)? as u64,
        tolerance: defaults.tolerance,
        seed: match raw.seed {
            None => defaults.seed,
            Some(s) if s >= 0 => s as u64,
            Some(s) => return Err(bad("seed", &s, "a whole number >= 0")),
        },
    };
    Ok(Some(Spec {
        candidates,
        max_beds,
        shot_kg,
        clearance_mm,
        shared_clearance: raw.shared_clearance.unwrap_or(true),
        bands,
        measure,
        sweeps,
        search,
        pareto_mass_ratios,
        scenario_damping,
        scenario_force_n,
        combine,
        sdof,
        replay: false,
        report: raw.report.unwrap_or(false),
        scenario_models,
        model_structures: Vec::new(),
    }))
}
