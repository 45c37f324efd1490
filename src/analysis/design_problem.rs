//! The design problem of a design experiment: its structure with the scenarios of
//! `[design.scenarios]` (damping ratios, forces, models), what the search and its shards
//! evaluate layouts on.

use crate::design::search::{Found, On};
use crate::design::{evaluate, Problem, Scenario, Screen, Spec};
use crate::experiment::Experiment;
use crate::model::{Damping, Structure};
use crate::number::fmt_num;
use crate::sim::motion::system::LARGE_ABOVE;
use crate::sim::settle::steady::Observe;
use crate::sim::SteadyOptions;

/// The design problem of an experiment, with its scenarios (every combination of the
/// damping ratios and forces of `[design.scenarios]`, the experiment's own value where a list
/// is not given).
pub fn problem(exp: &Experiment, spec: &Spec, steady: &SteadyOptions) -> Problem {
    problem_on(&exp.structure, exp, spec, steady)
}

/// The problem the searches evaluate layouts on: the structure of `[design.screen]` (its
/// scenarios built on it as on the file's), or `None` when the design has none.
pub fn screen(exp: &Experiment, spec: &Spec, steady: &SteadyOptions) -> Option<Problem> {
    spec.screen.as_ref().map(|sc| {
        let mut steady = *steady;
        if let Some(m) = sc.max_periods {
            steady.max_periods = m.max(steady.min_periods);
        }
        problem_on(&sc.structure, exp, spec, &steady)
    })
}

fn problem_on(s: &Structure, exp: &Experiment, spec: &Spec, steady: &SteadyOptions) -> Problem {
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
        steady: SteadyOptions { observe: observed(exp, spec), ..*steady },
        scenarios,
        combine: spec.combine,
        direction: spec.direction,
        suite: spec.suite.clone(),
    }
}

/// What the design of `exp` costs at most ([`Spec::budget`]), over its fastest structure (its
/// models', when they are scenarios).
pub fn budget(exp: &Experiment, spec: &Spec) -> crate::design::Budget {
    let highest = std::iter::once(&exp.structure)
        .chain(spec.model_structures.iter().map(|(_, s, _)| s))
        .map(crate::model::Structure::highest_natural_frequency_hz)
        .fold(0.0, f64::max);
    spec.budget(exp.cases.len(), highest)
}

/// The masses a design reads: its bands' masses and the hosts of its candidates and of the
/// experiment's cases (the drive level's accelerations). On a file's structure of more than
/// [`LARGE_ABOVE`] degrees of freedom only those are measured, on it and on its screen (on a
/// reduced plate 5 of 47 coordinates, 5 of 7 on its screen: following every one took a sixth
/// of a design's time); the paper's structures measure every mass, as their stored answers
/// were searched.
fn observed(exp: &Experiment, spec: &Spec) -> Observe {
    if exp.structure.dof() <= LARGE_ABOVE {
        return Observe::ALL;
    }
    let bands = spec.bands.iter().flat_map(|b| b.masses.iter().copied());
    let cases = exp.cases.iter().flat_map(|c| c.beds.iter().map(|b| b.damper.host));
    Observe::only(bands.chain(spec.candidates.iter().copied()).chain(cases))
}

/// What a screened search says of itself: which model it searched, and where the file's model
/// ranks the placements otherwise than the searched one.
pub fn screen_words(sc: &Screen, found: &[Found]) -> Vec<String> {
    let lowest = |key: &dyn Fn(&Found) -> f64| {
        found.iter().enumerate().fold(None::<(usize, f64)>, |b, (i, f)| match b {
            Some((_, v)) if v <= key(f) => b,
            _ => Some((i, key(f))),
        })
    };
    let words = |f: &Found| f.layout.hosts_words();
    let judged = lowest(&|f| if f.judged { f.evaluation.objective } else { f64::INFINITY });
    let searched = lowest(&|f| f.screened.unwrap_or(f64::INFINITY));
    let largest = found
        .iter()
        .filter_map(|f| {
            f.screened.map(|s| (s - f.evaluation.objective).abs() / f.evaluation.objective.abs().max(1e-300))
        })
        .fold(0.0f64, f64::max);
    let mut out = vec![format!(
        "searched on a coarser reduction ({}); each placement's best layout was then evaluated on the file's model, which ranks them: their objectives differ between the two models by up to {:.1} %; the clearance profile and the near-optimum map are drawn on the searched model",
        sc.kept,
        100.0 * largest
    )];
    if let (Some((j, _)), Some((s, _))) = (judged, searched) {
        if j != s {
            out.push(format!(
                "the searched model's best placement ({}) is not the file's model's ({}): the coarser reduction misranks them; a finer screen (more modes) would search nearer the judged optimum",
                words(&found[s]),
                words(&found[j])
            ));
        }
    }
    out
}

/// A screened design's placements table (`t`, from `found`): the column `screened_objective`
/// and the words on its description; the warnings [`screen_words`] gives. Nothing for a
/// design searched on the file's model.
pub fn with_screened(spec: &Spec, found: &[Found], t: &mut crate::table::Table) -> Vec<String> {
    let Some(sc) = spec.screen.as_ref().filter(|_| found.iter().any(|f| f.screened.is_some())) else {
        return Vec::new();
    };
    t.description += &format!(
        "; searched on a coarser reduction ({}): screened_objective is the layout's objective there, objective on the file's model",
        sc.kept
    );
    t.columns.push((
        "screened_objective".into(),
        crate::table::ColumnData::F64(found.iter().map(|f| f.screened.unwrap_or(f64::NAN)).collect()),
    ));
    // A placement a stopped search did not judge has no objective on the file's model.
    let unjudged: Vec<String> = found.iter().filter(|f| !f.judged).map(|f| f.layout.hosts_words()).collect();
    if let Some((_, crate::table::ColumnData::F64(objective))) = t.columns.iter_mut().find(|c| c.0 == "objective") {
        objective.iter_mut().zip(found).filter(|(_, f)| !f.judged).for_each(|(o, _)| *o = f64::NAN);
    }
    let mut words = screen_words(sc, found);
    if !unjudged.is_empty() {
        words.insert(
            0,
            format!(
                "the search stopped (its time limit or an interrupt) before {} of the {} placements' best layouts were evaluated on the file's model ({}): their objective is blank and they are not ranked (the file's model judged the most promising on the searched model first)",
                unjudged.len(),
                found.len(),
                unjudged.join(", ")
            ),
        );
    }
    words
}

/// The model the maps near the optimum (the clearance profile, each variable's) are drawn on,
/// the best layout evaluated there and the words their captions add: the screen's model where
/// given (`screen`), else `judged` and `best` as they are.
pub fn map_model<'a>(spec: &Spec, screen: Option<On<'a>>, judged: On<'a>, best: &Found) -> (On<'a>, Found, String) {
    match screen {
        Some((sp, sb)) => {
            let kept = spec.screen.as_ref().map_or("", |sc| sc.kept.as_str());
            let note = format!(" (on the model searched, {kept}: a map for the search, not the judged model)");
            ((sp, sb), Found { evaluation: evaluate(sp, sb, &best.layout), ..best.clone() }, note)
        }
        None => (judged, best.clone(), String::new()),
    }
}
