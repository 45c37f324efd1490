//! The dampers of a case, one entry per container: the host, the shot's mass, the clearance,
//! the direction the bed moves in and the bed model (docs/experiments.md, "Dampers"). Checked
//! without the structure first (what the Python package's `Damper(...)` checks), then
//! against it.

use std::path::Path;

use crate::error::{Error, Result};
use crate::model::{Clearance, Damper, Direction, Structure};
use crate::sim::motion::bed::ImpactLaw;
use crate::sim::motion::system::{configurations, MAX_BEDS, MAX_CONFIGS};

use super::analysis::export_ref;
use super::fields::mass_index;
use super::file::raw::RawDamper;
use super::{Bed, ClearanceSource};

/// The containers of a case, one row each: damper, clearance spec, impact law and grains. Keys
/// are named `{prefix}dampers[i].KEY` (`prefix` "cases[0]." in an experiment file).
pub(super) fn dampers(path: &Path, prefix: &str, raw: Vec<RawDamper>, s: &Structure) -> Result<Vec<Bed>> {
    let n = s.dof();
    if raw.len() > MAX_BEDS {
        return Err(Error::invalid(
            path,
            format!("{prefix}dampers"),
            format!("{} dampers", raw.len()),
            format!("at most {MAX_BEDS} dampers per case (every one of the 2^N configurations is decomposed)"),
        ));
    }
    let mut beds = Vec::with_capacity(raw.len());
    for (di, d) in raw.into_iter().enumerate() {
        let key = |k: &str| format!("{prefix}dampers[{di}].{k}");
        let host = mass_index(path, &key("mass"), d.mass, n)?;
        let f = damper_alone(path, &key, &d)?;
        let mass = match f.mass {
            DamperMass::Ratio(r) => r * s.masses[host],
            DamperMass::Kg(m) => m,
        };
        let damper = Damper::new(host, mass, f.clearance).along(f.direction);
        beds.push(Bed { damper, clearance: f.spec, law: f.law, grains: f.grains });
    }
    let grains: Vec<usize> = beds.iter().map(|b| b.grains).collect();
    if configurations(grains.iter().copied(), MAX_CONFIGS).is_none() {
        return Err(Error::invalid(
            path,
            format!("{prefix}dampers"),
            beds_value(&grains),
            format!("at most {MAX_CONFIGS} configurations per case: the product over the dampers of (grains + 1) (a single bed counts 2), e.g. three columns of 20 grains"),
        ));
    }
    Ok(beds)
}

/// A case's beds as an error quotes them (`grains` of each, 1 for a single bed): how many,
/// each one's grains unless every one is a single bed, and their configurations (the product
/// of grains + 1).
pub(super) fn beds_value(grains: &[usize]) -> String {
    let configs = configurations(grains.iter().copied(), usize::MAX)
        .map_or_else(|| format!("more than {}", usize::MAX), |c| c.to_string());
    if grains.iter().all(|&g| g <= 1) {
        format!("{} single beds ({configs} configurations)", grains.len())
    } else {
        format!("{} dampers with grains {grains:?} ({configs} configurations)", grains.len())
    }
}

/// A damper's mass as given: a ratio to its host's mass, or kilograms.
pub(super) enum DamperMass {
    /// `mass_ratio`.
    Ratio(f64),
    /// `mass_kg`.
    Kg(f64),
}

/// What a damper entry says, validated without its structure.
pub(super) struct DamperAlone {
    /// Its mass.
    pub mass: DamperMass,
    /// Its clearance and where it comes from.
    pub clearance: Clearance,
    /// How the clearance is given.
    pub spec: ClearanceSource,
    /// Its bed's impact law.
    pub law: ImpactLaw,
    /// Grains of its column (1: one mass).
    pub grains: usize,
    /// The direction its bed moves in.
    pub direction: Direction,
}

/// Validates every key of a damper entry that does not depend on the structure (all but the
/// host's upper bound): the host is a mass number >= 1, exactly one of `mass_ratio` and
/// `mass_kg`, positive and finite, the clearance, the bed model. What the Python package's
/// `Damper(...)` checks when it is built; an experiment file's dampers pass here first.
pub(super) fn damper_alone(path: &Path, key: &dyn Fn(&str) -> String, d: &RawDamper) -> Result<DamperAlone> {
    if d.mass < 1 {
        return Err(Error::invalid(path, key("mass"), d.mass, "masses are numbered from 1"));
    }
    let mass = match (d.mass_ratio, d.mass_kg) {
        (Some(r), None) => {
            if !(r.is_finite() && r > 0.0) {
                return Err(Error::invalid(path, key("mass_ratio"), r, "a mass ratio must be positive"));
            }
            DamperMass::Ratio(r)
        }
        (None, Some(m)) => {
            if !(m.is_finite() && m > 0.0) {
                return Err(Error::invalid(path, key("mass_kg"), m, "a damper mass must be positive"));
            }
            DamperMass::Kg(m)
        }
        (None, None) => {
            return Err(Error::invalid(
                path,
                key("mass_ratio"),
                "(missing)",
                "give exactly one of mass_ratio and mass_kg",
            ))
        }
        (Some(_), Some(_)) => {
            return Err(Error::invalid(
                path,
                key("mass_ratio"),
                "(both mass_ratio and mass_kg)",
                "give exactly one of mass_ratio and mass_kg",
            ))
        }
    };
    let (clearance, spec) = clearance(path, &key("clearance_mm"), &d.clearance_mm)?;
    let (law, grains) = bed_model(path, key, d)?;
    let direction = direction(path, key, d, clearance, &spec, grains)?;
    Ok(DamperAlone { mass, clearance, spec, law, grains, direction })
}

/// A damper's `direction` (default "vertical", the paper's). A horizontal container needs
/// two walls (a finite clearance: its bed has no gravity to bring it back) and holds one bed
/// (a column of grains stacks under gravity).
fn direction(
    path: &Path,
    key: &dyn Fn(&str) -> String,
    d: &RawDamper,
    clearance: Clearance,
    spec: &ClearanceSource,
    grains: usize,
) -> Result<Direction> {
    let Some(name) = d.direction.as_deref() else {
        return Ok(Direction::Vertical);
    };
    let Some(direction) = Direction::from_name(name) else {
        return Err(Error::invalid(path, key("direction"), format!("\"{name}\""), Direction::NAMES));
    };
    if direction == Direction::Horizontal {
        if matches!(spec, ClearanceSource::Scan) || (matches!(spec, ClearanceSource::Fixed) && !clearance.is_bounded())
        {
            let given = if matches!(spec, ClearanceSource::Scan) { "\"scan\"" } else { "\"inf\"" };
            return Err(Error::invalid(
                path,
                key("clearance_mm"),
                given,
                "a horizontal container needs a finite clearance in mm: its bed flies between two walls, with no gravity to bring it back",
            ));
        }
        if grains > 1 || d.bed.as_deref() == Some("column") {
            return Err(Error::invalid(
                path,
                key("bed"),
                "\"column\"",
                "a horizontal container holds a \"plastic\" or \"restitution\" bed: a column of grains stacks under gravity, which does not act along a horizontal container",
            ));
        }
    }
    Ok(direction)
}

/// Default sticking speed of a bed with restitution, m/s: slower impacts are plastic (what
/// ends a sequence of ever smaller bounces; docs/model.md section 2).
pub const DEFAULT_STICK_SPEED: f64 = 1e-3;

/// A damper's bed model (its `bed`, `grains`, `restitution`, `stick_speed_m_s`): its impact
/// law and its number of grains (1: one mass).
fn bed_model(path: &Path, key: &dyn Fn(&str) -> String, d: &RawDamper) -> Result<(ImpactLaw, usize)> {
    let bounces = d.restitution.is_some_and(|e| e != 0.0);
    let model = match d.bed.as_deref() {
        Some(m) => m,
        None if d.grains.is_some() => "column",
        None if bounces => "restitution",
        None => "plastic",
    };
    let law = impact_law(path, key, d.restitution, d.stick_speed_m_s)?;
    let no_grains = |model: &str| match d.grains {
        Some(g) => Err(Error::invalid(
            path,
            key("grains"),
            g,
            format!("only a column bed has grains (this bed is \"{model}\"): leave grains out or set bed = \"column\""),
        )),
        None => Ok(()),
    };
    match model {
        "plastic" => {
            if bounces {
                return Err(Error::invalid(
                    path,
                    key("restitution"),
                    law.restitution(),
                    "a plastic bed has e = 0: leave restitution out, or set bed = \"restitution\" or \"column\"",
                ));
            }
            no_grains(model)?;
            Ok((law, 1))
        }
        "restitution" => {
            if d.restitution.is_none() {
                return Err(Error::invalid(
                    path,
                    key("restitution"),
                    "(missing)",
                    "a bed = \"restitution\" needs its coefficient of restitution in [0, 1)",
                ));
            }
            no_grains(model)?;
            Ok((law, 1))
        }
        "column" => match d.grains {
            Some(g) if g.fract() == 0.0 && (1.0..=MAX_COLUMN_GRAINS as f64).contains(&g) => Ok((law, g as usize)),
            Some(g) => Err(Error::invalid(
                path,
                key("grains"),
                g,
                format!("a whole number of grains from 1 to {MAX_COLUMN_GRAINS}"),
            )),
            None => Err(Error::invalid(
                path,
                key("grains"),
                "(missing)",
                "a column bed needs its number of grains (1 to 60)",
            )),
        },
        other => Err(Error::invalid(
            path,
            key("bed"),
            format!("\"{other}\""),
            "one of \"plastic\", \"restitution\", \"column\"",
        )),
    }
}

/// Most grains in one column (every grain is a bit of a configuration mask).
pub const MAX_COLUMN_GRAINS: usize = 60;

/// A damper's impact law from its `restitution` and `stick_speed_m_s`.
fn impact_law(
    path: &Path,
    key: &dyn Fn(&str) -> String,
    restitution: Option<f64>,
    stick: Option<f64>,
) -> Result<ImpactLaw> {
    let e = restitution.unwrap_or(0.0);
    if !(e.is_finite() && (0.0..1.0).contains(&e)) {
        return Err(Error::invalid(path, key("restitution"), e, "a coefficient of restitution in [0, 1) (0: plastic)"));
    }
    let stick_speed = stick.unwrap_or(DEFAULT_STICK_SPEED);
    if !(stick_speed.is_finite() && stick_speed > 0.0) {
        return Err(Error::invalid(
            path,
            key("stick_speed_m_s"),
            stick_speed,
            "a positive relative speed in m/s below which the bed sticks (it ends chatter)",
        ));
    }
    if e == 0.0 && stick.is_some() {
        return Err(Error::invalid(
            path,
            key("stick_speed_m_s"),
            stick_speed,
            "only with a restitution > 0 (a plastic bed always sticks)",
        ));
    }
    Ok(ImpactLaw::with_restitution(e, stick_speed))
}

/// A clearance in mm (a number, "inf", "scan" or "@EXPERIMENT.KEY"); scanned and exported
/// clearances have no top until resolved.
fn clearance(path: &Path, key: &str, v: &toml::Value) -> Result<(Clearance, ClearanceSource)> {
    let allowed = "a clearance is a number of millimetres >= 0, \"inf\" for no top, \"scan\" in a clearance study, or \"@EXPERIMENT.KEY\"";
    let mm = match v {
        toml::Value::Float(f) => *f,
        toml::Value::Integer(i) => *i as f64,
        toml::Value::String(s) if s == "inf" => f64::INFINITY,
        toml::Value::String(s) if s == "scan" => return Ok((Clearance::NO_TOP, ClearanceSource::Scan)),
        toml::Value::String(s) => match export_ref(s) {
            Some(r) => return Ok((Clearance::NO_TOP, ClearanceSource::Export(r))),
            None => return Err(Error::invalid(path, key, v, allowed)),
        },
        other => return Err(Error::invalid(path, key, other, allowed)),
    };
    if mm.is_nan() || mm < 0.0 {
        return Err(Error::invalid(path, key, mm, "a clearance must be >= 0 mm (or \"inf\")"));
    }
    Ok((Clearance::from_mm(mm), ClearanceSource::Fixed))
}
