//! `[excitation]`: a force on one mass, or moving supports (docs/model.md section 2.3).

use std::path::Path;

use crate::error::{Error, Result};
use crate::model::base::Drive;
use crate::model::{Structure, GRAVITY};
use crate::number::fmt_num;
use crate::sim::System;

use super::fields::mass_index;
use super::file::raw::RawExcitation;

/// What drives the structure: `F sin(omega t)` on one mass, or its supports accelerating as
/// `A sin(omega t)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Excitation {
    /// 0-based driven mass (0, unused, when the supports move).
    pub mass: usize,
    /// The amplitude the responses are divided by: the force `F`, N, or the supports'
    /// acceleration `A`, m/s^2.
    pub force: f64,
    /// The supports move (`force` is their acceleration) instead of a force on `mass`.
    pub supports: bool,
    /// The supports move with recorded ground motions (a time history's), not harmonically.
    pub ground: bool,
}

impl Excitation {
    /// A force `F sin(omega t)` on mass `mass` (0-based).
    pub fn force(mass: usize, force: f64) -> Excitation {
        Excitation { mass, force, supports: false, ground: false }
    }

    /// Supports accelerating as `A sin(omega t)`, m/s^2.
    pub fn supports(accel: f64) -> Excitation {
        Excitation { mass: 0, force: accel, supports: true, ground: false }
    }

    /// The supports moving with recorded ground motions (amplitude 1 m/s^2: responses are
    /// given as they are, not per unit).
    pub fn records() -> Excitation {
        Excitation { mass: 0, force: 1.0, supports: true, ground: true }
    }

    /// What drives, for words and units ([`Drive`]).
    pub fn drive(&self) -> Drive {
        Drive::of(self.supports)
    }

    /// The unit of the amplitude: "N" or "m/s^2".
    pub fn unit(&self) -> &'static str {
        self.drive().unit()
    }

    /// The unit of a response divided by the amplitude: "m/N" or "m/(m/s^2)".
    pub fn per_unit(&self) -> &'static str {
        self.drive().per_unit()
    }

    /// The response divided by the amplitude, in symbols: "|x / F|" or "|u / A|".
    pub fn ratio(&self) -> &'static str {
        self.drive().ratio()
    }

    /// The excitation in words, e.g. "F = 2.6 N sin(omega t) on m_1".
    pub fn describe(&self) -> String {
        if self.ground {
            "the supports move with the recorded ground accelerations of analysis.ground_motions (linear between samples); displacements relative to the supports".into()
        } else if self.supports {
            format!(
                "supports accelerate as A = {} m/s^2 ({} g) sin(omega t); displacements relative to the supports",
                fmt_num(self.force),
                fmt_num(self.force / GRAVITY)
            )
        } else {
            format!("F = {} N sin(omega t) on m_{}", fmt_num(self.force), self.mass + 1)
        }
    }

    /// The system of `structure` with `dampers` (plastic) driven by this excitation at
    /// amplitude `amplitude` (N or m/s^2).
    pub fn system(&self, structure: &Structure, dampers: Vec<crate::model::Damper>, amplitude: f64) -> System {
        let sys = System::plastic(structure.clone(), dampers, self.mass, amplitude);
        if self.supports {
            sys.on_supports(amplitude)
        } else {
            sys
        }
    }
}

/// The excitation of a time history: its records drive it, so `[excitation]` is left out;
/// the structure must be held by its supports (a stiffness matrix that is not singular).
pub(super) fn ground(path: &Path, e: &RawExcitation, structure: &Structure) -> Result<Excitation> {
    let given = [
        ("excitation.mass", e.mass.is_some()),
        ("excitation.force_n", e.force_n.is_some()),
        ("excitation.base_acceleration_m_s2", e.base_acceleration_m_s2.is_some()),
        ("excitation.base_acceleration_g", e.base_acceleration_g.is_some()),
    ];
    if let Some((key, _)) = given.iter().find(|g| g.1) {
        return Err(Error::invalid(
            path,
            *key,
            "(given)",
            "a time history (analysis.ground_motions) or a design against records (design.ground_motions) is driven by its records: leave [excitation] out",
        ));
    }
    if structure.stiffness.clone().try_inverse().is_none() {
        return Err(Error::invalid(
            path,
            "structure",
            "(a singular stiffness matrix)",
            "a structure under ground motion must be held by its supports",
        ));
    }
    Ok(Excitation::records())
}

/// The excitation of an experiment file: either `mass` and `force_n`, or one of
/// `base_acceleration_m_s2` and `base_acceleration_g`; `masses` are the structure's (or the
/// finite-element points').
pub(super) fn excitation(path: &Path, e: &RawExcitation, masses: &[f64]) -> Result<Excitation> {
    let base = match (e.base_acceleration_m_s2, e.base_acceleration_g) {
        (Some(a), None) => Some(("excitation.base_acceleration_m_s2", a, a)),
        (None, Some(g)) => Some(("excitation.base_acceleration_g", g, g * GRAVITY)),
        (Some(_), Some(g)) => {
            return Err(Error::invalid(
                path,
                "excitation.base_acceleration_g",
                g,
                "give the supports' acceleration once: in m/s^2 or in g, not both",
            ))
        }
        (None, None) => None,
    };
    let Some((key, given, accel)) = base else {
        let Some(force_n) = e.force_n else {
            return Err(Error::invalid(
                path,
                "excitation.force_n",
                "(missing)",
                "give a force (mass = M, force_n = F) or moving supports (base_acceleration_m_s2 = A or base_acceleration_g = A)",
            ));
        };
        let Some(m) = e.mass else {
            return Err(Error::invalid(path, "excitation.mass", "(missing)", "name the driven mass (1-based)"));
        };
        let mass = mass_index(path, "excitation.mass", m, masses.len())?;
        if !(force_n.is_finite() && force_n > 0.0) {
            return Err(Error::invalid(
                path,
                "excitation.force_n",
                force_n,
                "the force amplitude must be positive and finite (N)",
            ));
        }
        force_fits(path, "excitation.force_n", force_n, masses[mass])?;
        return Ok(Excitation::force(mass, force_n));
    };
    for (other, given) in [("excitation.force_n", e.force_n.is_some()), ("excitation.mass", e.mass.is_some())] {
        if given {
            return Err(Error::invalid(
                path,
                other,
                "(given)",
                format!("{key} moves the supports, which drive every mass: give no force and no driven mass beside it"),
            ));
        }
    }
    accel_fits(path, key, given, accel)?;
    Ok(Excitation::supports(accel))
}

/// Refuses a support acceleration (given as `given` in the key's unit, `accel` m/s^2) that is
/// not positive and finite or exceeds [`MAX_FORCE_G`].
pub(super) fn accel_fits(path: &Path, key: &str, given: f64, accel: f64) -> Result<()> {
    if !(given.is_finite() && given > 0.0) {
        return Err(Error::invalid(
            path,
            key,
            given,
            "the supports' acceleration amplitude must be positive and finite",
        ));
    }
    if accel > MAX_FORCE_G * GRAVITY {
        return Err(Error::invalid(
            path,
            key,
            given,
            format!(
                "the supports may accelerate by at most {MAX_FORCE_G} g ({} m/s^2): beyond it no bench structure holds together and the beds' flights leave every axis",
                fmt_num(MAX_FORCE_G * GRAVITY)
            ),
        ));
    }
    Ok(())
}

/// Refuses a force amplitude (N) that accelerates the driven mass (kg) by more than
/// [`MAX_FORCE_G`].
pub(super) fn force_fits(path: &Path, key: &str, force: f64, driven: f64) -> Result<()> {
    let most = MAX_FORCE_G * GRAVITY * driven;
    if force <= most {
        return Ok(());
    }
    Err(Error::invalid(
        path,
        key,
        force,
        format!(
            "the force amplitude may accelerate the driven mass ({} kg) by at most {MAX_FORCE_G} g, {} N: beyond it no bench structure holds together and the beds' flights leave every axis",
            fmt_num(driven),
            fmt_num(most)
        ),
    ))
}

/// The largest force amplitude over the driven mass (or support acceleration), in g.
pub const MAX_FORCE_G: f64 = 1e4;

/// Refuses what moving supports cannot drive: the equivalent SDOF models (paper Eq. 12-13
/// take a force on one mass).
pub(super) fn supports_fit(path: &Path, analysis: &super::Analysis) -> Result<()> {
    let key = "excitation.base_acceleration_m_s2";
    let refuse = |what: &str| {
        Err(Error::invalid(
            path,
            key,
            "(moving supports)",
            format!("{what}: drive it with a force (mass = M, force_n = F) instead"),
        ))
    };
    if matches!(analysis, super::Analysis::SdofPeriodic { .. }) {
        return refuse(
            "the equivalent SDOF model (paper Eq. 12-13) of kind \"sdof_periodic\" takes a force on one mass",
        );
    }
    if analysis.design().is_some_and(|(spec, _)| spec.sdof.is_some()) {
        return refuse("[design.sdof]'s equivalent SDOF rule (paper Eq. 12-13) takes a force on one mass");
    }
    Ok(())
}

impl Excitation {
    /// The amplitude's symbol: "F" or "A".
    pub fn symbol(&self) -> &'static str {
        self.drive().symbol()
    }

    /// Where the excitation acts, for captions: "F = 2.6 N on m1" or "A = 3 m/s^2 at the
    /// supports".
    pub fn at(&self) -> String {
        if self.supports {
            format!("A = {} m/s^2 at the supports", self.force)
        } else {
            format!("F = {} N on m{}", self.force, self.mass + 1)
        }
    }
}
