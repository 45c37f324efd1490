//! The adaptive design of a study file (docs/studies.md, "Adaptive refinement"): its keys
//! (`levels`, `refine`) checked against the varied keys' grids, and a study's samples at
//! lattice points ([`super::lattice`]).

use std::path::Path;

use crate::error::{Error, Result};

use super::design::{values_at, Design, Refine};
use super::lattice::{Lattice, Point};
use super::{Sample, Study, Vary};

/// Halvings of the step when a study gives none.
pub const DEFAULT_LEVELS: u32 = 3;

/// The adaptive design of a study file: `levels` (default [`DEFAULT_LEVELS`]) and `refine`
/// (`"all"`, the default; `"count"`; `"outcomes"`; or a claim's number), checked against the
/// varied keys' grids.
pub(super) fn design_of(
    path: &Path,
    levels: Option<i64>,
    refine: Option<&toml::Value>,
    sampled: bool,
    vary: &[Vary],
) -> Result<Design> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: &str| Error::invalid(path, key, value, msg);
    if sampled {
        return Err(bad(
            "study.samples",
            &"(given)",
            "an adaptive design chooses its samples: give `levels` and each key's grid, no `samples` or `seed`",
        ));
    }
    let levels = match levels {
        None => DEFAULT_LEVELS,
        Some(n) if (1..=8).contains(&n) => n as u32,
        Some(n) => return Err(bad("study.levels", &n, "a whole number from 1 to 8 (halvings of the coarse step)")),
    };
    let refine = match refine {
        None => Refine::All,
        Some(toml::Value::String(s)) if s == "all" => Refine::All,
        Some(toml::Value::String(s)) if s == "count" => Refine::Count,
        Some(toml::Value::String(s)) if s == "outcomes" => Refine::Outcomes,
        Some(toml::Value::Integer(k)) if *k >= 0 => Refine::Check(*k as usize),
        Some(other) => {
            return Err(bad(
                "study.refine",
                other,
                "\"all\" (whether every claim holds), \"count\" (the number of claims that hold), \"outcomes\" (every claim's outcome) or a claim's number (0-based, the `check` column)",
            ))
        }
    };
    let step = 1usize << levels;
    if vary.is_empty() {
        return Err(bad("vary", &"(none)", "an adaptive design refines over varied keys: give at least one"));
    }
    for (i, v) in vary.iter().enumerate() {
        let n = v.domain.grid().map(|g| g.len());
        match n {
            Some(n) if n > step && (n - 1) % step == 0 => {}
            _ => {
                let key = if matches!(v.domain, super::Domain::Values(_)) { "values" } else { "range.count" };
                return Err(bad(
                    &format!("vary[{i}].{key}"),
                    &n.map_or("(missing)".to_string(), |n| format!("{n} values")),
                    &format!(
                        "an adaptive design of {levels} levels needs {step} k + 1 values of each key ({}, {}, {}, ...): the fine grid it refines to, every {step}th value computed first",
                        step + 1,
                        2 * step + 1,
                        4 * step + 1
                    ),
                ));
            }
        }
    }
    Ok(Design::Adaptive { levels, refine })
}

impl Study {
    /// The fine lattice of an adaptive study (`None` for other designs).
    pub fn lattice(&self) -> Option<Lattice> {
        let domains: Vec<super::Domain> = self.vary.iter().map(|v| v.domain.clone()).collect();
        self.design.lattice(&domains)
    }

    /// The samples of lattice points `(model index, point)`, numbered from `first`.
    pub fn samples_at(&self, points: &[(usize, Point)], first: usize) -> Vec<Sample> {
        let domains: Vec<super::Domain> = self.vary.iter().map(|v| v.domain.clone()).collect();
        let models = self.models();
        points
            .iter()
            .enumerate()
            .map(|(i, (m, p))| Sample {
                index: first + i,
                model: models.get(*m).cloned().unwrap_or_default(),
                values: values_at(&domains, p),
            })
            .collect()
    }

    /// The study with other samples (a round of an adaptive design), on every experiment of
    /// a joint study.
    pub fn with_samples(&self, samples: Vec<Sample>) -> Study {
        let mut s = self.clone();
        for part in &mut s.joint {
            part.samples = samples.clone();
        }
        s.samples = samples;
        s
    }
}
