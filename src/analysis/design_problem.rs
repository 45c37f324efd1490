//! The design problem of a design experiment: its structure with the scenarios of
//! `[design.scenarios]` (damping ratios, forces, models), what the search and its shards
//! evaluate layouts on.

use crate::design::{Problem, Scenario, Spec};
use crate::experiment::Experiment;
use crate::model::{Damping, Structure};
use crate::number::fmt_num;
use crate::sim::SteadyOptions;

/// The design problem of an experiment, with its scenarios (every combination of the
/// damping ratios and forces of `[design.scenarios]`, the experiment's own value where a list
/// is not given).
pub fn problem(exp: &Experiment, spec: &Spec, steady: &SteadyOptions) -> Problem {
    let s = &exp.structure;
    let mut scenarios = Vec::new();
    let any = !(spec.scenario_damping.is_empty() && spec.scenario_force_n.is_empty());
    if any || !spec.model_structures.is_empty() {
        // The structures the scenarios start from: every model's (models as scenarios), or
        // the experiment's.
        let bases: Vec<(String, Structure, f64)> = if spec.model_structures.is_empty() {
            vec![(String::new(), s.clone(), exp.excitation.force)]
        } else {
            spec.model_structures.clone()
        };
        let dampings: Vec<Option<f64>> = if spec.scenario_damping.is_empty() {
            vec![None]
        } else {
            spec.scenario_damping.iter().map(|z| Some(*z)).collect()
        };
        for (model, base, nominal_force) in &bases {
            let forces: Vec<f64> =
                if spec.scenario_force_n.is_empty() { vec![*nominal_force] } else { spec.scenario_force_n.clone() };
            for z in &dampings {
                for &f in &forces {
                    let (structure, zname) = match z {
                        Some(z) => (
                            base.with_damping(Damping::ModalRatios(vec![*z; base.dof()])),
                            format!("damping {}", fmt_num(*z)),
                        ),
                        None => (base.clone(), "damping as the model".to_string()),
                    };
                    let prefix = if model.is_empty() { String::new() } else { format!("{model}, ") };
                    scenarios.push(Scenario {
                        name: if exp.excitation.supports {
                            format!("{prefix}{zname}, A {} m/s^2", fmt_num(f))
                        } else {
                            format!("{prefix}{zname}, F {} N", fmt_num(f))
                        },
                        structure,
                        force: f,
                    });
                }
            }
        }
    }
    Problem {
        structure: s.clone(),
        driven: exp.excitation.mass,
        force: exp.excitation.force,
        supports: exp.excitation.supports,
        bands: spec.bands.clone(),
        measure: spec.measure,
        sweeps: spec.sweeps.clone(),
        steady: *steady,
        scenarios,
        combine: spec.combine,
        direction: spec.direction,
    }
}
