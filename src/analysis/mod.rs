//! Running experiments: solvers in, finished tables, figures and check outcomes out.
//! Nothing here reads or writes files; references arrive pre-loaded.

pub mod branches;
mod checks;
mod clearance;
pub mod curves;
pub mod design;
mod design_best;
mod design_compliance;
mod design_conclusion;
mod design_drive;
mod design_levels;
mod design_near;
pub(crate) mod design_problem;
mod design_search;
mod design_seismic;
pub mod design_shards;
mod design_storeys;
pub mod evidence;
mod figures;
pub mod impulse;
mod kind;
mod linear;
pub mod models;
mod orbit_figures;
pub mod orbits;
mod overlays;
pub mod reduction;
pub mod result;
pub mod study;
pub mod study_adaptive;
pub mod study_samples;
mod sweep;
mod time_history;
mod time_history_figures;
mod time_history_runs;
mod waveform;
pub use waveform::event_words;

use crate::checks::baseline;
use crate::checks::reference::{BaselineMode, ReferenceStore};
use crate::error::Result;
use crate::experiment::{Analysis, Experiment};
use crate::model::modal::modal_summary;

pub use result::{ExperimentResult, NoProgress, Progress, Tick};

use kind::{Input, Kind};

/// The kind of `analysis`, with its settings: the one place that maps a variant of
/// [`Analysis`] to the room that runs it (a new kind adds one arm here).
fn kind(analysis: &Analysis) -> Box<dyn Kind + '_> {
    match analysis {
        Analysis::Modal => Box::new(linear::Modal),
        Analysis::LinearFrf { freq_hz } => Box::new(linear::Frf { freq_hz }),
        Analysis::Sweep { freq_hz, start, steady } => Box::new(sweep::Sweep { freq_hz, start: *start, steady }),
        Analysis::ClearanceStudy { freq_hz, clearances_mm, points, objective_mass, objective_case, steady } => {
            Box::new(clearance::Study {
                freq_hz,
                clearances_mm: clearances_mm.as_deref(),
                points: *points,
                objective_mass: *objective_mass,
                objective_case,
                steady,
            })
        }
        Analysis::Waveform { frequencies, labels, periods, steady } => {
            Box::new(waveform::Waveform { frequencies, labels, periods: *periods, steady })
        }
        Analysis::Impulse { options, spectrum_hz, levels } => {
            Box::new(impulse::Impulse { options, spectrum_hz, levels })
        }
        Analysis::SdofPeriodic { mode, freq_hz, clearances_mm, steady } => {
            Box::new(orbits::Sdof { mode: *mode, freq_hz, clearances_mm: clearances_mm.as_deref(), steady })
        }
        Analysis::Design { spec, steady } => Box::new(design::Design { spec, steady }),
        Analysis::TimeHistory { records, storey_heights_m } => {
            Box::new(time_history::TimeHistory { records, storey_heights_m: storey_heights_m.as_deref() })
        }
    }
}

/// Simulated points an experiment will run (for progress bars; 0 when not known ahead).
pub fn work(exp: &Experiment, refs: &ReferenceStore) -> u64 {
    kind(&exp.analysis).work(exp, refs)
}

/// Runs one experiment (its exported inputs already resolved): its kind, then what every
/// experiment gets (the modal table, the checks, the reduction of a finite-element model,
/// the baseline).
pub fn run(exp: &Experiment, refs: &ReferenceStore, tick: &Tick) -> Result<ExperimentResult> {
    let modes = modal_summary(&exp.structure, &[]);
    let out = kind(&exp.analysis).run(&Input { exp, modes: &modes, refs, tick });
    let mut tables = vec![linear::modal_table(exp, &modes)];
    tables.extend(out.tables);
    let mut figures = out.figures;
    let mut curves = curves::Curves::per(exp.excitation.per_unit());
    curves.extend(out.curves);
    let computed = checks::Computed {
        curves: &curves,
        decays: &out.decays,
        orbits: out.orbits.as_ref(),
        motion_types: &out.motion_types,
    };
    let mut checks = checks::evaluate(exp, &modes, &computed, refs);
    checks.extend(out.checks);
    let mut warnings = out.warnings;
    if let Some(fe) = &exp.finite_element {
        warnings.extend(light_shot(exp, fe.mass_along_up));
        let r = reduction::run(exp, fe);
        warnings.extend(r.warning);
        tables.extend(r.tables);
        checks.extend(r.check);
        figures.extend(r.figure);
    }
    let (id, figure) = (&exp.key(), &exp.meta.figure);
    match (refs.baseline(id), refs.baseline_mode) {
        (_, BaselineMode::Off) => {}
        (Some(blessed), _) => checks.push(baseline::compare(id, figure, &baseline::sample(&tables), blessed)),
        (None, BaselineMode::Required) => checks.push(baseline::missing(id, figure)),
        (None, BaselineMode::Optional) => {}
    }
    Ok(ExperimentResult {
        exports: out.exports,
        experiment: exp.clone(),
        modes,
        tables,
        figures,
        checks,
        curves,
        design: out.design,
        warnings,
        answer: out.answer,
        partial: out.partial,
    })
}

/// A warning when every container of a finite-element structure holds less than 1e-3 of the
/// mass moving along the vertical (`structure`, kg): the files' units are likely not those
/// `structure.finite_element.units` names (SI files read as N-mm-t weigh 1000 times more).
fn light_shot(exp: &Experiment, structure: f64) -> Option<String> {
    let heaviest = exp.cases.iter().flat_map(|c| c.beds.iter()).map(|b| b.damper.mass).fold(0.0, f64::max);
    (heaviest > 0.0 && heaviest < 1e-3 * structure).then(|| {
        format!(
            "{}: the finite-element structure's mass moving along the vertical is {structure:.4} kg and the heaviest container's shot {heaviest:.4} kg, less than 1e-3 of it: check that the files' units are those of structure.finite_element.units (\"N-m-kg\" unless given; \"N-mm-t\" reads tonnes and N/mm)",
            exp.path.display()
        )
    })
}
