//! Parts of an experiment built outside a file: a structure, a case's dampers, an excitation
//! and steady-state settings from TOML-shaped tables (what the Python package passes), through
//! the same reading and validation as an experiment file, so that a bad value gets the same
//! message. `origin` stands where a file's path would (e.g. "shotdamp.Structure").

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};
use crate::model::Structure;
use crate::sim::motion::impulse::ImpulseOptions;
use crate::sim::{SteadyOptions, System};

use super::file::raw::{RawAnalysis, RawDamper, RawExcitation, RawSteady, RawStructure};
use super::{Analysis, Case, ClearanceSource, Excitation};

pub use super::fields::{check_frequencies, MIN_FREQUENCY_RATIO};

/// Reads `value` as a `T`, naming a wrong key `{prefix}KEY` as an experiment file would.
fn read<T: DeserializeOwned>(origin: &str, prefix: &str, mut value: toml::Value) -> Result<T> {
    super::file::read::whole_floats(&mut value);
    serde_path_to_error::deserialize(value).map_err(|e: serde_path_to_error::Error<toml::de::Error>| {
        let key = e.path().to_string();
        let inner = e.into_inner();
        let key = if key == "." || key.is_empty() {
            prefix.trim_end_matches('.').to_string()
        } else {
            format!("{prefix}{key}")
        };
        Error::Parse {
            file: origin.to_string(),
            message: if key.is_empty() {
                super::file::read::serde_words(inner.message())
            } else {
                format!("{key}: {}", super::file::read::serde_words(inner.message()))
            },
        }
    })
}

/// A structure from the keys of an experiment file's `[structure]` table (`masses_kg`, one of
/// `chain_stiffness_n_per_m`, `stiffness_matrix_n_per_m` and `fit`, `ground_stiffness_n_per_m`,
/// `damping`).
pub fn structure(origin: &str, table: toml::Table) -> Result<Structure> {
    Ok(structure_and_model(origin, table)?.0)
}

/// [`structure`], and the finite-element model it was reduced from when the table has
/// `finite_element` (its full matrices, points and reduction: what
/// [`crate::analysis::reduction::compare`] compares).
pub fn structure_and_model(
    origin: &str,
    table: toml::Table,
) -> Result<(Structure, Option<std::sync::Arc<crate::model::fe::FeStructure>>)> {
    let raw: RawStructure = read(origin, "structure.", toml::Value::Table(table))?;
    let built = super::structure::structure(origin.as_ref(), raw, None)?;
    Ok((built.structure, built.fe))
}

/// The dampers of one case from tables with the keys of an experiment file's
/// `[[cases]].dampers` entries (`mass`, `mass_ratio` or `mass_kg`, `clearance_mm` as a number
/// or "inf", `bed`, `grains`, `restitution`, `stick_speed_m_s`); keys are named
/// `dampers[i].KEY`. The case is named `id`.
pub fn case(origin: &str, id: &str, dampers: Vec<toml::Table>, structure: &Structure) -> Result<Case> {
    let mut raw = Vec::with_capacity(dampers.len());
    for (i, d) in dampers.into_iter().enumerate() {
        raw.push(read::<RawDamper>(origin, &format!("dampers[{i}]."), toml::Value::Table(d))?);
    }
    let beds = super::dampers::dampers(origin.as_ref(), "", raw, structure)?;
    if let Some(i) = beds.iter().position(|b| b.clearance != ClearanceSource::Fixed) {
        return Err(fixed_only(origin, &format!("dampers[{i}].")));
    }
    Ok(Case { id: id.into(), label: id.into(), beds })
}

/// Validates one damper entry (the keys of [`case`]'s tables) on its own, before any
/// structure is known: everything but whether its host mass exists, with the messages an
/// experiment file gets. Keys are named `damper.KEY`.
pub fn damper(origin: &str, table: toml::Table) -> Result<()> {
    let raw: RawDamper = read(origin, "damper.", toml::Value::Table(table))?;
    let f = super::dampers::damper_alone(origin.as_ref(), &|k: &str| format!("damper.{k}"), &raw)?;
    if f.spec != ClearanceSource::Fixed {
        return Err(fixed_only(origin, "damper."));
    }
    Ok(())
}

/// A clearance other than a number or "inf" outside an experiment file.
fn fixed_only(origin: &str, prefix: &str) -> Error {
    Error::invalid(
        origin,
        format!("{prefix}clearance_mm"),
        "(scan or @EXPERIMENT.KEY)",
        "a clearance outside an experiment file is a number of millimetres >= 0 or \"inf\"",
    )
}

/// The excitation: `mass` (1-based) driven by `force_n` sin(omega t), as an experiment file's
/// `[excitation]`.
pub fn excitation(origin: &str, mass: i64, force_n: f64, structure: &Structure) -> Result<Excitation> {
    let raw = RawExcitation {
        mass: Some(mass),
        force_n: Some(force_n),
        base_acceleration_m_s2: None,
        base_acceleration_g: None,
    };
    super::excitation::excitation(origin.as_ref(), &raw, &structure.masses)
}

/// The excitation from the keys of an experiment file's `[excitation]` (a force: `mass` and
/// `force_n`; or moving supports: `base_acceleration_m_s2`), validated as there.
pub fn drive(
    origin: &str,
    mass: Option<i64>,
    force_n: Option<f64>,
    base_acceleration_m_s2: Option<f64>,
    structure: &Structure,
) -> Result<Excitation> {
    let raw = RawExcitation { mass, force_n, base_acceleration_m_s2, base_acceleration_g: None };
    super::excitation::excitation(origin.as_ref(), &raw, &structure.masses)
}

/// Steady-state settings from the keys of an experiment file's `[analysis.steady]` (the
/// defaults for an empty table); keys are named `steady.KEY`.
pub fn steady(origin: &str, table: toml::Table) -> Result<SteadyOptions> {
    let raw: RawSteady = read(origin, "steady.", toml::Value::Table(table))?;
    super::analysis::steady_at(origin.as_ref(), "steady.", Some(&raw))
}

/// An impulse's settings from the keys of an impulse experiment's `[analysis]` table
/// (`struck_mass`, `initial_velocity_m_s` or `impulse_n_s`, `duration_s`, `sample_rate_hz`)
/// on `structure`; keys are named `analysis.KEY`.
pub fn impulse(origin: &str, mut table: toml::Table, structure: &Structure) -> Result<ImpulseOptions> {
    table.insert("kind".into(), toml::Value::String("impulse".into()));
    let raw: RawAnalysis = read(origin, "analysis.", toml::Value::Table(table))?;
    match super::analysis::impulse(origin.as_ref(), &raw, structure.dof())? {
        Analysis::Impulse { options, .. } => Ok(options),
        other => Err(Error::invalid(origin, "analysis.kind", other.kind(), "an impulse analysis")),
    }
}

/// Refuses a structure the exact simulator cannot take (more masses than it holds), before
/// anything runs: `origin` names the caller (e.g. "shotdamp.System"); `fe`, the
/// finite-element model the structure was reduced from, if any.
pub fn simulated_structure(
    origin: &str,
    structure: &Structure,
    fe: Option<&crate::model::fe::FeStructure>,
) -> Result<()> {
    let points = fe.map(|f| f.points.len());
    super::validate::simulator_fits(origin.as_ref(), structure.dof(), points, &format!("{origin} runs"))
}

/// Refuses the beds of `case` when the exact simulator cannot decompose their configurations on
/// `structure` (`crate::sim::motion::system::config_limit`), before anything runs.
pub fn simulated_case(origin: &str, case: &Case, structure: &Structure) -> Result<()> {
    super::validate::configurations_fit(
        origin.as_ref(),
        "dampers",
        &case.grains(),
        structure.dof(),
        &format!("{origin} runs"),
    )
}

/// Refuses a kick that gives the struck mass an initial speed outside the physical range
/// (`experiment::analysis::KICK_SPEED_M_S`) in `case`.
pub fn kick(origin: &str, options: &ImpulseOptions, structure: &Structure, case: &Case) -> Result<()> {
    super::validate::kick_fits(origin.as_ref(), options, structure, case)
}

/// The simulated system of a case: the structure, the case's dampers with their impact laws
/// (a column's grains as beds of their own), driven by the excitation.
pub fn system(structure: &Structure, excitation: &Excitation, case: &Case) -> System {
    let sys = System { laws: case.laws(), ..excitation.system(structure, case.dampers(), excitation.force) };
    if case.beds.iter().map(|b| &b.grains).any(|&g| g > 1) {
        sys.with_grains(&case.grains())
    } else {
        sys
    }
}
