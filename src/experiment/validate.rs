//! Stage two: raw structs to typed, validated values. Every error names the file, the key,
//! the value and what is allowed.

use std::path::Path;

use crate::error::{Error, Result};
use crate::model::Structure;
use crate::reference::files::Files;
use crate::sim::motion::impulse::ImpulseOptions;
use crate::sim::motion::system::{config_limit, configurations, MAX_DOF};

use super::analysis::analysis;
use super::checks::check;
use super::dampers::dampers;
use super::excitation::{accel_fits, excitation, force_fits};
use super::fields::is_identifier;
use super::file::raw::{RawCase, RawExperiment, RawStructure};
use super::file::raw_design::RawScreen;
use super::outputs::plot;
use super::structure::{structure, structure_kept, Built, Kept};
use super::{Analysis, Case, ClearanceSource, Experiment, Meta, ModelInfo};

/// Validates a raw experiment read from `path`.
pub fn validate(path: &Path, raw: RawExperiment, files: &Files) -> Result<Experiment> {
    validate_keeping(path, raw, files, None).map(|(e, _)| e)
}

/// [`validate`], its structure taken from `kept` where the experiment's `[structure]` is the
/// one kept (its damping aside), and what was built kept for the next (an explorer request,
/// a study sample: [`super::loader::vary`]).
pub(super) fn validate_keeping(
    path: &Path,
    raw: RawExperiment,
    files: &Files,
    kept: Option<&Kept>,
) -> Result<(Experiment, Kept)> {
    let meta = meta(path, raw.experiment)?;
    let model = raw.model.map(|m| ModelInfo { id: m.id, label: m.label, description: m.description });
    let mut raw_structure = raw.structure;
    if let Some(fe) = raw_structure.finite_element.as_mut() {
        // Default: every fixed-interface mode below twice the highest frequency analysed.
        if fe.modes.is_none() && fe.cutoff_hz.is_none() {
            fe.cutoff_hz = super::file::raw::highest_analysed(&raw.analysis, raw.design.as_ref()).map(|f| 2.0 * f);
        }
    }
    let models_as_scenarios = raw.design.as_ref().and_then(|d| d.scenarios.as_ref()).and_then(|s| s.models);
    let screen = screen(
        path,
        raw.design.as_ref().and_then(|d| d.screen.as_ref()),
        &raw_structure,
        models_as_scenarios.unwrap_or(false),
    )?;
    // What runs the structure, and so the most coordinates a finite-element model may be
    // reduced to (refused before its modes are computed).
    let runs = format!("analysis kind \"{}\" runs", raw.analysis.kind);
    let simulated = super::kind::kind_spec(&raw.analysis.kind).is_some_and(|k| k.simulates);
    let limit = simulated.then_some((MAX_DOF, runs.as_str()));
    let kept = structure_kept(path, raw_structure, limit, kept)?;
    let Built { structure, source, damping_assumption, fit, fe: finite_element } = kept.built().clone();
    let fe = finite_element.as_deref();
    let n = structure.dof();
    // A finite-element structure reports its points only (its other coordinates are modal).
    let responses = fe.map_or(n, |f| f.points.len());

    if let Some(f) = fe.filter(|f| raw.excitation.mass.is_some_and(|m| m > f.points.len() as i64)) {
        return Err(Error::invalid(
            path,
            "excitation.mass",
            raw.excitation.mass.unwrap_or_default(),
            format!(
                "the force acts on one of the finite-element points, numbered 1 to {0} (coordinates above {0} are modal)",
                f.points.len()
            ),
        ));
    }
    // A time history and a design against records are driven by their records.
    let on_records = raw.analysis.kind == "time_history"
        || (raw.analysis.kind == "design" && raw.design.as_ref().is_some_and(|d| d.ground_motions.is_some()));
    let excitation = if on_records {
        super::excitation::ground(path, &raw.excitation, &structure)?
    } else {
        excitation(path, &raw.excitation, &structure.masses[..responses])?
    };

    let cases = cases(path, raw.cases, &structure)?;
    if let Some(f) = fe {
        for (ci, case) in cases.iter().enumerate() {
            for (di, d) in case.beds.iter().map(|b| &b.damper).enumerate() {
                super::fe::host_fits(path, f, &format!("cases[{ci}].dampers[{di}].mass"), d.host, d.direction)?;
            }
        }
    }
    let case_ids: Vec<String> = cases.iter().map(|c| c.id.clone()).collect();
    // A full mass matrix's coordinates are not all displacements: its trace is no mass; a
    // finite-element model's is the mass moving along the vertical.
    let total_mass = super::structure_mass(&structure, fe);
    let design = super::design::design(path, raw.design, &raw.analysis.kind, responses, total_mass)?;
    let mut analysis = analysis(path, raw.analysis, n, &case_ids, design)?;
    if let Some(spec) = analysis.design_mut() {
        spec.screen = screen;
    }
    design_fits(path, &analysis, fe, &excitation, &structure)?;
    // The records' stated directions against the structure's supports.
    if let Analysis::TimeHistory { records, .. } = &analysis {
        let stated = records.iter().map(|r| r.direction.as_deref());
        super::ground::directions_fit(path, "analysis.ground_motions", stated, &structure)?;
    }
    if let Some(suite) = analysis.design().and_then(|(spec, _)| spec.suite.as_ref()) {
        let stated = suite.records.iter().map(|r| r.direction.as_deref());
        super::ground::directions_fit(path, "design.ground_motions", stated, &structure)?;
    }
    let drift = analysis.design().and_then(|(spec, _)| spec.suite.as_ref()).map(|s| s.response);
    let heights =
        analysis.design().and_then(|(spec, _)| spec.suite.as_ref()).is_some_and(|s| s.storey_heights_m.is_some());
    if heights && !structure.is_chain() {
        return Err(Error::invalid(
            path,
            "design.storey_height_m",
            "(given)",
            "storey heights give drift ratios of a chain of storeys (structure.masses_kg with chain stiffnesses): this structure has no storeys",
        ));
    }
    if drift == Some(crate::design::seismic::Response::Drift) && !structure.is_chain() {
        return Err(Error::invalid(
            path,
            "design.response",
            "\"drift\" (the default)",
            "storey drifts are those of a chain of storeys (structure.masses_kg with chain stiffnesses): give design.response = \"acceleration\" for this structure",
        ));
    }
    if let Analysis::TimeHistory { storey_heights_m: Some(_), .. } = &analysis {
        if !structure.is_chain() {
            return Err(Error::invalid(
                path,
                "analysis.storey_height_m",
                "(given)",
                "storey heights give drift ratios of a chain of storeys (structure.masses_kg with chain stiffnesses): this structure has no storeys",
            ));
        }
    }
    if excitation.supports {
        super::excitation::supports_fit(path, &analysis)?;
    }
    cases_fit(path, &analysis, &cases, &structure, fe.map(|f| f.points.len()))?;
    if raw.plots.len() > MAX_PLOTS {
        return Err(Error::invalid(
            path,
            "plots",
            format!("{} plots", raw.plots.len()),
            format!("at most {MAX_PLOTS} plots an experiment"),
        ));
    }
    let plots = raw
        .plots
        .into_iter()
        .enumerate()
        .map(|(i, p)| plot(path, i, p, responses, &case_ids, &analysis))
        .collect::<Result<Vec<_>>>()?;
    let checks = raw
        .checks
        .into_iter()
        .enumerate()
        .map(|(i, c)| check(path, i, c, responses, &case_ids, &analysis, files))
        .collect::<Result<Vec<_>>>()?;
    super::texts::validate(path, &meta, &checks)?;

    let exp = Experiment {
        path: path.to_path_buf(),
        meta,
        model,
        models: Vec::new(),
        structure,
        fit,
        structure_source: source,
        finite_element,
        damping_assumption,
        excitation,
        analysis,
        cases,
        plots,
        checks,
    };
    Ok((exp, kept))
}

/// `[experiment]`: its id (it names the report folder) and its words.
fn meta(path: &Path, m: super::file::raw::RawMeta) -> Result<Meta> {
    if !is_identifier(&m.id) {
        return Err(Error::invalid(
            path,
            "experiment.id",
            format!("\"{}\"", m.id),
            "use letters, digits, '_' and '-' only (it names the report folder)",
        ));
    }
    super::fields::id_length(path, "experiment.id", &m.id)?;
    Ok(Meta {
        id: m.id,
        title: m.title,
        figure: m.figure,
        caption: m.caption,
        claim: m.claim,
        assumptions: m.assumptions,
        notes: m.notes,
        deviation: m.deviation,
    })
}

/// The most plots one experiment draws.
pub const MAX_PLOTS: usize = 64;

/// A design's candidates on a finite-element structure, and its force levels (scenarios, drive
/// levels) within the ranges the excitation allows.
fn design_fits(
    path: &Path,
    analysis: &Analysis,
    fe: Option<&crate::model::fe::FeStructure>,
    excitation: &super::Excitation,
    structure: &Structure,
) -> Result<()> {
    if let (Some((spec, _)), Some(f)) = (analysis.design(), fe) {
        for (i, &c) in spec.candidates.iter().enumerate() {
            super::fe::host_fits(path, f, &format!("design.candidates[{i}]"), c, spec.direction)?;
        }
    }
    if let Some((spec, _)) = analysis.design() {
        let levels = spec.scenario_force_n.iter().map(|f| ("design.scenarios.force_n", f));
        for (i, (key, &f)) in levels.chain(spec.drive_levels_n.iter().map(|f| ("design.drive_levels_n", f))).enumerate()
        {
            let key =
                format!("{key}[{}]", if i < spec.scenario_force_n.len() { i } else { i - spec.scenario_force_n.len() });
            if excitation.supports {
                // The levels are the supports' accelerations, m/s^2.
                accel_fits(path, &key, f, f)?;
            } else {
                force_fits(path, &key, f, structure.masses[excitation.mass])?;
            }
        }
    }
    Ok(())
}

/// The cases against what the analysis runs: scanned clearances, the simulator's size and
/// configurations, kicks, frequencies, and the bed models, directions, columns and counts of
/// dampers the analysis takes.
fn cases_fit(
    path: &Path,
    analysis: &Analysis,
    cases: &[Case],
    structure: &Structure,
    fe_points: Option<usize>,
) -> Result<()> {
    let n = structure.dof();
    let (scanning, may_scan) = (analysis.scans_clearances(), analysis.may_scan_clearances());
    for (ci, case) in cases.iter().enumerate() {
        for (di, bed) in case.beds.iter().enumerate() {
            let scan = bed.clearance == ClearanceSource::Scan;
            if (scan && !(scanning || may_scan)) || (!scan && scanning) {
                return Err(Error::invalid(
                    path,
                    format!("cases[{ci}].dampers[{di}].clearance_mm"),
                    if scanning { "(not \"scan\")" } else { "\"scan\"" },
                    "a clearance study scans every damper's clearance (clearance_mm = \"scan\"), an sdof_periodic analysis with clearances_mm may; other analyses take a number, \"inf\" or \"@EXPERIMENT.KEY\"",
                ));
            }
        }
    }
    if analysis.simulates() {
        let who = format!("analysis kind \"{}\" runs", analysis.kind());
        simulator_fits(path, n, fe_points, &who)?;
        for (ci, case) in cases.iter().enumerate() {
            configurations_fit(path, &format!("cases[{ci}].dampers"), &case.grains(), n, &who)?;
        }
    }
    if let Analysis::Impulse { options, .. } = analysis {
        for case in cases {
            kick_fits(path, options, structure, case)?;
        }
    }
    let simulated = analysis.simulated_frequencies();
    if analysis.design().is_some() || cases.iter().any(|c| !c.beds.is_empty()) {
        for (key, freq_hz) in &simulated {
            super::fields::check_frequencies(&path.display().to_string(), key, freq_hz, structure)?;
        }
    }
    if analysis.plastic_only() {
        for (ci, case) in cases.iter().enumerate() {
            if let Some(di) = case.beds.iter().map(|b| &b.law).position(|l| !l.is_plastic()) {
                return Err(Error::invalid(
                    path,
                    format!("cases[{ci}].dampers[{di}].restitution"),
                    case.beds[di].law.restitution(),
                    "the equivalent SDOF analysis and the design search model the paper's plastic bed only: leave restitution out (0)",
                ));
            }
        }
    }
    if let Analysis::SdofPeriodic { .. } = analysis {
        for (ci, case) in cases.iter().enumerate() {
            if let Some(di) =
                case.beds.iter().map(|b| &b.damper).position(|d| d.direction != crate::model::Direction::Vertical)
            {
                return Err(Error::invalid(
                    path,
                    format!("cases[{ci}].dampers[{di}].direction"),
                    "\"horizontal\"",
                    "the paper's equivalent SDOF analysis (motion types I-III, Fig. 9) models a vertical container: leave direction out",
                ));
            }
        }
    }
    let columns_allowed = analysis.runs_columns();
    if !columns_allowed {
        for (ci, case) in cases.iter().enumerate() {
            if let Some(di) = case.beds.iter().map(|b| &b.grains).position(|&g| g > 1) {
                return Err(Error::invalid(
                    path,
                    format!("cases[{ci}].dampers[{di}].grains"),
                    case.beds[di].grains,
                    format!(
                        "a column of grains runs in a sweep from rest, a clearance study, waveforms or an impulse decay (this analysis is {}{}): use one mass (bed = \"plastic\" or \"restitution\")",
                        analysis.kind(),
                        if matches!(analysis, Analysis::Sweep { .. }) { " with start = \"continuation\"" } else { "" }
                    ),
                ));
            }
        }
    }
    if let Analysis::SdofPeriodic { .. } = analysis {
        for (ci, case) in cases.iter().enumerate() {
            if case.beds.len() != 1 {
                return Err(Error::invalid(
                    path,
                    format!("cases[{ci}].dampers"),
                    format!("{} dampers", case.beds.len()),
                    "periodic orbits are computed for exactly one damper per case",
                ));
            }
        }
    }
    Ok(())
}

fn cases(path: &Path, raw: Vec<RawCase>, s: &Structure) -> Result<Vec<Case>> {
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
        super::fields::id_length(path, &format!("cases[{ci}].id"), &c.id)?;
        if out.iter().any(|o| o.id == c.id) {
            return Err(Error::invalid(
                path,
                format!("cases[{ci}].id"),
                format!("\"{}\"", c.id),
                "case ids must be unique",
            ));
        }
        let beds = dampers(path, &format!("cases[{ci}]."), c.dampers, s)?;
        out.push(Case { id: c.id, label: c.label, beds });
    }
    Ok(out)
}

/// Refuses an impulse whose kick gives the struck mass an initial speed outside
/// `KICK_SPEED_M_S` in `case` (an impulse is shared with the beds resting
/// on the struck mass, as the simulation shares it).
pub(super) fn kick_fits(path: &Path, options: &ImpulseOptions, structure: &Structure, case: &Case) -> Result<()> {
    let k = options.mass;
    let resting: f64 = case.beds.iter().map(|b| &b.damper).filter(|d| d.host == k).map(|d| d.mass).sum();
    super::analysis::kick_speed_fits(path, options.kick, structure.masses[k] + resting)
}

/// Refuses a structure of `n` degrees of freedom larger than the exact simulator takes; `who`
/// says what runs it (e.g. `analysis kind "sweep" runs`); `fe_points`, the points of a
/// finite-element model (its other coordinates are modal).
pub(super) fn simulator_fits(path: &Path, n: usize, fe_points: Option<usize>, who: &str) -> Result<()> {
    if n <= MAX_DOF {
        return Ok(());
    }
    let (key, value, keep) = match fe_points {
        Some(p) => (
            "structure.finite_element",
            format!("{n} coordinates ({p} points and {} fixed-interface modes)", n - p),
            format!(", keeping at most {} modes (modes or cutoff_hz)", MAX_DOF.saturating_sub(p)),
        ),
        None => ("structure.masses_kg", format!("{n} masses"), String::new()),
    };
    Err(Error::invalid(
        path,
        key,
        value,
        format!(
            "{who} the exact simulator, which takes at most {MAX_DOF} degrees of freedom{keep} (analysis kinds \"modal\" and \"linear_frf\" take any number)"
        ),
    ))
}

/// Refuses beds (`grains` of each, 1 for a single bed) whose configurations the exact
/// simulator cannot decompose on a structure of `n` degrees of freedom
/// ([`crate::sim::motion::system::config_limit`]); `key` names them, `who` says what runs them.
pub(super) fn configurations_fit(path: &Path, key: &str, grains: &[usize], n: usize, who: &str) -> Result<()> {
    let limit = config_limit(n);
    if configurations(grains.iter().copied(), limit).is_some() {
        return Ok(());
    }
    Err(Error::invalid(
        path,
        key,
        super::dampers::beds_value(grains),
        format!(
            "{who} the exact simulator, which decomposes every configuration up front: at most {limit} configurations on {n} degrees of freedom (the product over the dampers of grains + 1; a single bed counts 2; docs/simulator.md, \"Cost per degree of freedom\")"
        ),
    ))
}

/// `[design.screen]`: the finite-element structure `given` reduced again with the
/// screen's modes, for the searches (docs/design.md, "Searching on a coarser reduction").
fn screen(
    path: &Path,
    raw: Option<&RawScreen>,
    given: &RawStructure,
    models_as_scenarios: bool,
) -> Result<Option<crate::design::Screen>> {
    let Some(raw) = raw else { return Ok(None) };
    let bad = super::design::bad_at(path);
    let Some(fe) = given.finite_element.as_ref() else {
        return Err(bad(
            "screen",
            &"(given)",
            "a search on a coarser reduction needs a finite-element structure ([structure.finite_element]): leave [design.screen] out",
        ));
    };
    if models_as_scenarios {
        return Err(bad(
            "screen",
            &"(given)",
            "the models of [design.scenarios] models = true are not reduced again: leave [design.screen] or models out",
        ));
    }
    let kept = match (raw.modes, raw.cutoff_hz) {
        (Some(m), None) if (0..=10_000).contains(&m) => format!("the lowest {m} fixed-interface modes"),
        (Some(m), None) => {
            return Err(bad("screen.modes", &m, "the fixed-interface modes kept: a whole number from 0 to 10000"))
        }
        (None, Some(f)) if f.is_finite() && f > 0.0 => {
            format!("fixed-interface modes below {} Hz", crate::number::fmt_num(f))
        }
        (None, Some(f)) => return Err(bad("screen.cutoff_hz", &f, "a positive frequency, Hz")),
        _ => {
            return Err(bad(
                "screen",
                &"modes / cutoff_hz (both or neither)",
                "give one: modes = N (the lowest N fixed-interface modes) or cutoff_hz = F (every one below F)",
            ))
        }
    };
    let max_periods = match raw.max_periods {
        None => None,
        Some(m) if (1..=1_000_000).contains(&m) => Some(m as usize),
        Some(m) => {
            return Err(bad(
                "screen.max_periods",
                &m,
                "the forcing periods a steady state of the search may run: a whole number from 1 to 1000000 (default: steady.max_periods)",
            ))
        }
    };
    let mut coarse = given.clone();
    coarse.finite_element =
        Some(super::file::raw::RawFiniteElement { modes: raw.modes, cutoff_hz: raw.cutoff_hz, ..fe.clone() });
    // The screen's modes are this table's keys: an error about them names them here.
    let who = "the design's search on the reduction of [design.screen] runs";
    let built = structure(path, coarse, Some((MAX_DOF, who))).map_err(|e| match e.key() {
        Some("structure.finite_element.modes" | "structure.finite_element.cutoff_hz") => {
            e.with_key(|key| key.replace("structure.finite_element.", "design.screen."))
        }
        _ => e,
    })?;
    let n = built.structure.dof();
    Ok(Some(crate::design::Screen {
        structure: built.structure,
        kept: format!(
            "{kept}: {n} coordinates{}",
            max_periods.map_or(String::new(), |m| format!(", steady states of at most {m} forcing periods"))
        ),
        max_periods,
    }))
}
