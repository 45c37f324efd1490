//! Validation of `[design]` (analysis kind "design", docs/design.md): every key named in its
//! error, with the value and what is allowed.

use std::path::Path;

use crate::design::search::Options;
use crate::design::seismic::{Over, Response, Suite};
use crate::design::{limits, Band, Combine, Measure, Spec, Sweep};
use crate::error::{Error, Result};
use crate::model::Direction;
use crate::number::fmt_list as fmt_num_list;

use super::analysis::grid;
use super::fields::distinct;
use super::file::raw_design::RawDesign;

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

/// Refuses a design whose one layout evaluation would hold more scenarios or steady-state
/// points than the stated limits (checked again once models are taken as scenarios).
pub(super) fn sized(path: &Path, spec: &Spec) -> Result<()> {
    let scenarios = spec.scenario_count();
    if scenarios > limits::SCENARIOS {
        return Err(Error::invalid(
            path,
            "design.scenarios",
            format!("{scenarios} scenarios"),
            format!("at most {} scenarios (damping x force x models)", limits::SCENARIOS),
        ));
    }
    let points = spec.evaluation_points();
    if points > limits::EVALUATION_POINTS as u64 {
        return Err(Error::invalid(
            path,
            "design.bands",
            format!("{points} steady states per layout"),
            format!(
                "at most {} steady states per layout evaluation (the bands' frequencies x {} sweeps x {scenarios} scenarios)",
                limits::EVALUATION_POINTS,
                spec.sweeps.len()
            ),
        ));
    }
    Ok(())
}

fn whole(path: &Path, key: &str, v: Option<i64>, default: usize, max: usize) -> Result<usize> {
    match v {
        None => Ok(default),
        Some(x) if x >= 1 && x as usize <= max => Ok(x as usize),
        Some(x) => Err(Error::invalid(path, key, x, format!("give a whole number from 1 to {max}"))),
    }
}

/// An input error at `design.KEY` of `path`.
pub(super) fn bad_at(path: &Path) -> impl Fn(&str, &dyn std::fmt::Display, &str) -> Error + '_ {
    move |key, v, msg| Error::invalid(path, format!("design.{key}"), v, msg)
}

/// The total shot mass, kg: `shot_kg`, or `shot_mass_ratio` of the structure's mass.
fn shot(path: &Path, raw: &RawDesign, total_mass: Option<f64>) -> Result<f64> {
    let bad = bad_at(path);
    let kg = match (raw.shot_mass_ratio, raw.shot_kg) {
        (Some(r), None) if total_mass.is_none() => {
            return Err(bad(
                "shot_mass_ratio",
                &r,
                "a structure given by a full mass matrix (structure.mass_matrix_kg) has no total mass to take a ratio of: give design.shot_kg",
            ))
        }
        (Some(r), None) if r.is_finite() && r > 0.0 && r <= 10.0 => crate::number::decimal(r * total_mass.unwrap_or(0.0)),
        (Some(r), None) => return Err(bad("shot_mass_ratio", &r, "a total shot mass ratio in (0, 10]")),
        (None, Some(kg)) if kg.is_finite() && kg > 0.0 => kg,
        (None, Some(kg)) => return Err(bad("shot_kg", &kg, "a shot mass in kg, positive and finite")),
        _ => {
            return Err(bad("shot_mass_ratio", &"(missing or both)", "give exactly one of shot_mass_ratio and shot_kg"))
        }
    };
    Ok(kg)
}

/// The sweeps of each band (`up` and `down` by default).
fn sweeps(path: &Path, raw: &RawDesign) -> Result<Vec<Sweep>> {
    let bad = bad_at(path);
    let sweeps: Vec<Sweep> = match &raw.sweeps {
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
    Ok(sweeps)
}

/// The bands: each a name, a grid of at most `limits::BAND_POINTS` and the masses it measures.
fn bands(path: &Path, raw: &RawDesign, n: usize) -> Result<Vec<Band>> {
    let bad = bad_at(path);
    if raw.bands.is_empty() {
        return Err(bad("bands", &"[]", "give at least one [[design.bands]] (name, freq_hz, masses)"));
    }
    raw
        .bands
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let key = format!("design.bands[{i}].freq_hz");
            let freq_hz = grid(path, &key, &b.freq_hz)?;
            if freq_hz.len() > limits::BAND_POINTS {
                return Err(Error::invalid(
                    path,
                    key,
                    format!("{} frequencies", freq_hz.len()),
                    format!("a design band has at most {} frequencies (each is a steady state in every layout the search evaluates)", limits::BAND_POINTS),
                ));
            }
            Ok(Band { name: b.name.clone(), freq_hz, masses: masses(path, &format!("design.bands[{i}].masses"), &b.masses, n)? })
        })
        .collect::<Result<Vec<_>>>()
}

/// The scenarios: damping ratios, forces and how their objectives combine.
fn scenarios(path: &Path, raw: &RawDesign, scenario_models: bool) -> Result<(Vec<f64>, Vec<f64>, Combine)> {
    let bad = bad_at(path);
    Ok(match &raw.scenarios {
        None => (Vec::new(), Vec::new(), Combine::Worst),
        Some(sc) => {
            let damping = sc.damping.clone().unwrap_or_default();
            if let Some((i, z)) = damping.iter().enumerate().find(|(_, z)| !(z.is_finite() && **z >= 0.0 && **z < 1.0))
            {
                return Err(bad(&format!("scenarios.damping[{i}]"), z, "a modal damping ratio in [0, 1)"));
            }
            distinct(path, "design.scenarios.damping", &damping, limits::SCENARIO_VALUES, "damping scenarios")?;
            let force = sc.force_n.clone().unwrap_or_default();
            if let Some((i, f)) = force.iter().enumerate().find(|(_, f)| !(f.is_finite() && **f > 0.0)) {
                return Err(bad(&format!("scenarios.force_n[{i}]"), f, "a force amplitude in N, positive and finite"));
            }
            distinct(path, "design.scenarios.force_n", &force, limits::SCENARIO_VALUES, "force scenarios")?;
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
    })
}

/// What the search minimises: at the file's force (`"nominal"`, the default), or the worst
/// over the drive levels (`"worst_over_drive_levels"`: the levels become the scenarios'
/// forces, combined by the worst, and their figure is drawn from the search's own
/// evaluations). Takes and returns the scenarios' forces, how they combine and the drive
/// levels evaluated after the search.
fn objective(
    path: &Path,
    raw: &RawDesign,
    (forces, combine, levels): (Vec<f64>, Combine, Vec<f64>),
) -> Result<(Vec<f64>, Combine, Vec<f64>)> {
    let bad = bad_at(path);
    match raw.objective.as_deref() {
        None | Some("nominal") => Ok((forces, combine, levels)),
        Some(name @ "worst_over_drive_levels") => {
            let value = format!("\"{name}\"");
            if levels.len() < 2 {
                return Err(bad("objective", &value, "give design.drive_levels_n with two forces or more: the search's objective is the worst over them"));
            }
            if !forces.is_empty() {
                return Err(bad("objective", &value, "leave design.scenarios.force_n out: the drive levels are the forces"));
            }
            if combine != Combine::Worst {
                return Err(bad("objective", &value, "leave design.scenarios.combine out or \"worst\": the objective is the worst over the levels"));
            }
            Ok((levels, Combine::Worst, Vec::new()))
        }
        Some(other) => Err(bad(
            "objective",
            &format!("\"{other}\""),
            "\"nominal\" (default: at the file's force) or \"worst_over_drive_levels\" (the worst over design.drive_levels_n)",
        )),
    }
}

/// The paper's SDOF technique beside the search: its mode (0-based) and candidate clearances.
fn sdof(path: &Path, raw: &RawDesign, n: usize) -> Result<Option<(usize, Vec<f64>)>> {
    let bad = bad_at(path);
    Ok(match &raw.sdof {
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
            distinct(
                path,
                "design.sdof.clearances_mm",
                &sd.clearances_mm,
                limits::SDOF_CLEARANCES,
                "candidate clearances",
            )?;
            Some((sd.mode as usize - 1, sd.clearances_mm.clone()))
        }
    })
}

/// The records of `design.ground_motions` and what is measured under them; refuses the keys
/// of a design over frequency bands beside them.
fn suite(path: &Path, raw: &RawDesign, n: usize) -> Result<Option<Suite>> {
    let bad = bad_at(path);
    let Some(list) = &raw.ground_motions else {
        let given = [
            ("response", raw.response.is_some()),
            ("over_records", raw.over_records.is_some()),
            ("storey_height_m", raw.storey_height_m.is_some()),
        ];
        if let Some((key, _)) = given.iter().find(|g| g.1) {
            return Err(bad(key, &"(given)", "only a design against records (design.ground_motions) reads it"));
        }
        return Ok(None);
    };
    // What a design over frequency bands reads and a design against records does not.
    let banded = [
        ("bands", !raw.bands.is_empty()),
        ("sweeps", raw.sweeps.is_some()),
        ("measure", raw.measure.is_some()),
        ("drive_levels_n", raw.drive_levels_n.is_some()),
        ("objective", raw.objective.is_some()),
        ("sdof", raw.sdof.is_some()),
        ("screen", raw.screen.is_some()),
        ("scenarios.force_n", raw.scenarios.as_ref().is_some_and(|sc| sc.force_n.is_some())),
    ];
    if let Some((key, _)) = banded.iter().find(|g| g.1) {
        return Err(bad(
            key,
            &"(given)",
            "a design against recorded ground motions (design.ground_motions) judges each layout under the records: leave out bands, sweeps, measure, drive_levels_n, objective, sdof, screen and scenarios.force_n (design.response and design.over_records say what counts)",
        ));
    }
    let records = super::ground::records(path, "design.ground_motions", list)?;
    let response = match raw.response.as_deref() {
        None => Response::Drift,
        Some(name) => {
            Response::from_name(name).ok_or_else(|| bad("response", &format!("\"{name}\""), Response::NAMES))?
        }
    };
    let over = match raw.over_records.as_deref() {
        None => Over::Largest,
        Some(name) => Over::from_name(name).ok_or_else(|| bad("over_records", &format!("\"{name}\""), Over::NAMES))?,
    };
    let storey_heights_m = super::ground::heights(path, "design.storey_height_m", raw.storey_height_m.as_ref(), n)?;
    Ok(Some(Suite { records, response, over, storey_heights_m }))
}

/// The Nelder-Mead search's options of `raw` (`starts`, `max_iters`, `tolerance`, `seed`,
/// `step_tolerance`), each within its stated limit.
fn search_options(path: &Path, raw: &RawDesign) -> Result<Options> {
    let bad = bad_at(path);
    let defaults = Options::default();
    Ok(Options {
        starts: whole(path, "design.starts", raw.starts, defaults.starts, limits::STARTS)?,
        max_iters: whole(path, "design.max_iters", raw.max_iters, defaults.max_iters as usize, limits::MAX_ITERS)?
            as u64,
        tolerance: match raw.tolerance {
            None => defaults.tolerance,
            Some(t) if t.is_finite() && t > 0.0 && t < 1.0 => t,
            Some(t) => {
                return Err(bad(
                    "tolerance",
                    &t,
                    "the spread of a simplex's objectives at which a start ends: between 0 and 1 (default 1e-6)",
                ))
            }
        },
        seed: match raw.seed {
            None => defaults.seed,
            Some(s) if s >= 0 => s as u64,
            Some(s) => return Err(bad("seed", &s, "a whole number >= 0")),
        },
        step_tolerance: match raw.step_tolerance {
            None => defaults.step_tolerance,
            Some(t) if t.is_finite() && (0.0..1.0).contains(&t) => t,
            Some(t) => {
                return Err(bad(
                    "step_tolerance",
                    &t,
                    "the size of a simplex (in the search's free coordinates, its first steps 1 long) at which a start ends: from 0 (never, the default) to below 1",
                ))
            }
        },
    })
}

/// The design of an experiment: required by kind "design", refused by every other kind.
/// `total_mass`: the structure's mass a shot mass is stated against, kg ([`super::structure_mass`],
/// for a shot mass ratio and Pareto ratios; `None` for a full mass matrix, whose total mass the
/// file does not give).
pub fn design(
    path: &Path,
    raw: Option<RawDesign>,
    kind: &str,
    n: usize,
    total_mass: Option<f64>,
) -> Result<Option<Spec>> {
    // The kind that answers a design question is the one that reads `[design]`.
    let designs = super::kind::kind_spec(kind).is_some_and(|k| k.answers);
    let raw = match (raw, designs) {
        (None, true) => {
            return Err(Error::invalid(path, "design", "(missing)", "analysis kind \"design\" needs a [design] table"))
        }
        (None, false) => return Ok(None),
        (Some(_), false) => {
            return Err(Error::invalid(
                path,
                "design",
                "(given)",
                format!("only analysis kind \"design\" reads [design] (this file's kind is \"{kind}\")"),
            ))
        }
        (Some(r), true) => r,
    };
    let bad = bad_at(path);
    let candidates = masses(path, "design.candidates", &raw.candidates, n)?;
    let max_beds = whole(path, "design.max_beds", raw.max_beds, candidates.len(), candidates.len())?;
    let most = crate::sim::motion::system::config_limit(n).ilog2() as usize;
    if max_beds > most {
        return Err(bad(
            "max_beds",
            &max_beds,
            &format!(
                "at most {most} containers at once on {n} degrees of freedom (the exact simulator decomposes all 2^N configurations up front; give design.max_beds, which defaults to the number of candidates)"
            ),
        ));
    }
    let shot_kg = shot(path, &raw, total_mass)?;
    let clearance_mm = match raw.clearance_mm.as_slice() {
        &[lo, hi] if lo.is_finite() && hi.is_finite() && 0.0 < lo && lo < hi => (lo, hi),
        other => {
            return Err(bad("clearance_mm", &fmt_num_list(other), "[min, max] in mm with 0 < min < max, both finite"))
        }
    };
    let measure = match raw.measure.as_deref() {
        None | Some("peak") => Measure::Peak,
        Some("rms") => Measure::Rms,
        Some(other) => return Err(bad("measure", &format!("\"{other}\""), "\"peak\" or \"rms\"")),
    };
    let suite = suite(path, &raw, n)?;
    let (sweeps, bands) =
        if suite.is_some() { (Vec::new(), Vec::new()) } else { (sweeps(path, &raw)?, bands(path, &raw, n)?) };
    let pareto_mass_ratios = raw.pareto_mass_ratios.clone().unwrap_or_default();
    if let Some((i, r)) =
        pareto_mass_ratios.iter().enumerate().find(|(_, r)| !(r.is_finite() && **r > 0.0 && **r <= 10.0))
    {
        return Err(bad(&format!("pareto_mass_ratios[{i}]"), r, "total shot mass ratios in (0, 10]"));
    }
    if let (Some(r), None) = (pareto_mass_ratios.first(), total_mass) {
        return Err(bad(
            "pareto_mass_ratios[0]",
            r,
            "a structure given by a full mass matrix (structure.mass_matrix_kg) has no total mass to take a ratio of: leave pareto_mass_ratios out",
        ));
    }
    distinct(
        path,
        "design.pareto_mass_ratios",
        &pareto_mass_ratios,
        limits::PARETO_RATIOS,
        "Pareto ratios (each is a search of its own)",
    )?;
    let scenario_models = raw.scenarios.as_ref().and_then(|sc| sc.models).unwrap_or(false);
    let (scenario_damping, scenario_force_n, combine) = scenarios(path, &raw, scenario_models)?;
    let sdof = sdof(path, &raw, n)?;
    let search = search_options(path, &raw)?;
    let direction = match raw.direction.as_deref() {
        None => Direction::Vertical,
        Some(name) => match Direction::from_name(name) {
            Some(d) => d,
            None => return Err(bad("direction", &format!("\"{name}\""), Direction::NAMES)),
        },
    };
    if direction == Direction::Horizontal && sdof.is_some() {
        return Err(bad(
            "sdof",
            &"(given)",
            "the paper's SDOF technique (Fig. 9, motion types I-III) models a vertical container: leave [design.sdof] out of a horizontal design",
        ));
    }
    let drive_levels_n = raw.drive_levels_n.clone().unwrap_or_default();
    if let Some((i, f)) = drive_levels_n.iter().enumerate().find(|(_, f)| !(f.is_finite() && **f > 0.0)) {
        return Err(bad(&format!("drive_levels_n[{i}]"), f, "a force amplitude in N, positive and finite"));
    }
    distinct(path, "design.drive_levels_n", &drive_levels_n, limits::SCENARIO_VALUES, "drive levels")?;
    let (scenario_force_n, combine, drive_levels_n) =
        objective(path, &raw, (scenario_force_n, combine, drive_levels_n))?;
    let spec = Spec {
        candidates,
        max_beds,
        shot_kg,
        clearance_mm,
        shared_clearance: raw.shared_clearance.unwrap_or(true),
        direction,
        drive_levels_n,
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
        halt: Default::default(),
        merged: None,
        report: raw.report.unwrap_or(false),
        scenario_models,
        model_structures: Vec::new(),
        screen: None,
        suite,
    };
    sized(path, &spec)?;
    Ok(Some(spec))
}
