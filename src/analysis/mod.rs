//! Running experiments: solvers in, finished tables, figures and check outcomes out.
//! Nothing here reads or writes files; references arrive pre-loaded.

pub mod branches;
mod checks;
mod claim_checks;
mod clearance;
pub mod curves;
mod decay_checks;
pub mod design;
mod design_conclusion;
mod design_drive;
mod design_levels;
mod design_near;
mod design_problem;
pub mod design_shards;
mod digitised_checks;
mod figures;
pub mod impulse;
mod linear;
pub mod models;
mod orbit_checks;
mod orbit_figures;
pub mod orbits;
mod overlays;
pub mod reduction;
pub mod result;
pub mod study;
pub mod study_adaptive;
pub mod study_samples;
mod sweep;
mod waveform;

use std::collections::BTreeMap;

use crate::checks::baseline;
use crate::checks::fmt_num;
use crate::checks::reference::{BaselineMode, ReferenceStore};
use crate::error::Result;
use crate::experiment::{Analysis, Experiment};
use crate::model::modal::modal_summary;
use crate::model::Damping;

pub use result::{ExperimentResult, NoProgress, Progress, Tick};

/// Simulated points an experiment will run (for progress bars).
pub fn work(exp: &Experiment, refs: &ReferenceStore) -> u64 {
    match &exp.analysis {
        Analysis::Modal | Analysis::LinearFrf { .. } => 0,
        Analysis::Sweep { freq_hz, start, .. } => sweep::work(exp, freq_hz, *start, refs),
        Analysis::ClearanceStudy { freq_hz, clearances_mm, points, objective_mass, objective_case, steady } => {
            clearance::work(
                exp,
                &clearance::Study {
                    freq_hz,
                    clearances_mm: clearances_mm.as_deref(),
                    points: *points,
                    objective_mass: *objective_mass,
                    objective_case,
                    steady,
                },
            )
        }
        Analysis::Waveform { frequencies, .. } => waveform::work(exp, frequencies),
        Analysis::Impulse { .. } => exp.cases.len() as u64,
        Analysis::SdofPeriodic { freq_hz, clearances_mm, .. } => {
            (clearances_mm.as_ref().map_or(0, |c| c.len()) + 2 + freq_hz.len()) as u64
        }
        // A search's evaluations are not known ahead: a counter of unknown total, ticked at
        // every evaluation (a caller may stop there).
        Analysis::Design { .. } => 0,
    }
}

/// Runs one experiment (its exported inputs already resolved).
pub fn run(exp: &Experiment, refs: &ReferenceStore, tick: &Tick) -> Result<ExperimentResult> {
    let modes = modal_summary(&exp.structure, &[]);
    let mut tables = vec![linear::modal_table(exp, &modes)];
    let mut figures = Vec::new();
    let mut curves = curves::Curves::per(exp.excitation.per_unit());
    let mut decays = std::collections::BTreeMap::new();
    let mut orbits_result = None;
    let mut motion_types = waveform::MotionTypes::new();
    let mut exports = BTreeMap::new();
    let mut design_checks = Vec::new();
    let mut design_answer = None;
    let mut warnings = Vec::new();
    let mut answer = None;
    match &exp.analysis {
        Analysis::Modal => {}
        Analysis::LinearFrf { freq_hz } => {
            let (table, figs, cs) = linear::frf(exp, &modes, freq_hz, refs);
            tables.push(table);
            figures.extend(figs);
            curves.extend(cs);
        }
        Analysis::Sweep { freq_hz, start, steady } => {
            let out = sweep::run(exp, &modes, refs, freq_hz, *start, steady, tick);
            tables.extend(out.tables);
            figures.extend(out.figures);
            curves.extend(out.curves);
            exports = out.exports;
        }
        Analysis::ClearanceStudy { freq_hz, clearances_mm, points, objective_mass, objective_case, steady } => {
            let study = clearance::Study {
                freq_hz,
                clearances_mm: clearances_mm.as_deref(),
                points: *points,
                objective_mass: *objective_mass,
                objective_case,
                steady,
            };
            let out = clearance::run(exp, refs, &study, tick);
            tables.extend(out.tables);
            figures.extend(out.figures);
            curves.extend(out.curves);
            exports = out.exports;
        }
        Analysis::Waveform { frequencies, labels, periods, steady } => {
            let (t, f, m, skipped) = waveform::run(exp, frequencies, labels, *periods, steady, tick);
            tables.extend(t);
            figures.extend(f);
            motion_types = m;
            warnings.extend(skipped);
        }
        Analysis::Impulse { options, spectrum_hz, levels } => {
            let out = impulse::run(exp, &modes, options, spectrum_hz, levels, tick);
            tables.extend(out.tables);
            figures.extend(out.figures);
            decays = out.decays;
            warnings.extend(out.skipped);
        }
        Analysis::Design { spec, steady } => {
            let out = design::run(exp, spec, steady, refs, tick);
            tables.extend(out.tables);
            figures.extend(out.figures);
            exports = out.exports;
            design_checks = out.checks;
            // A search its time limit stopped has no answer to store.
            design_answer = (!out.stopped).then_some(out.stored);
            warnings = out.warnings;
            answer = out.answer;
        }
        Analysis::SdofPeriodic { mode, freq_hz, clearances_mm, steady } => {
            if let Some(r) = orbits::run(exp, &modes, *mode, freq_hz, clearances_mm.as_deref(), steady, tick) {
                tables.extend(orbit_figures::tables(exp, &modes, &r));
                figures.extend(orbit_figures::figures(exp, &modes, &r, freq_hz));
                exports = orbits::exports(&r, modes[*mode].reference_mass);
                orbits_result = Some(r);
            }
        }
    }
    let mut checks = checks::evaluate(
        exp,
        &modes,
        &checks::Computed {
            curves: &curves,
            decays: &decays,
            orbits: orbits_result.as_ref(),
            motion_types: &motion_types,
        },
        refs,
    );
    checks.extend(design_checks);
    // A case that cannot be simulated is missing from a figure: a failed check says so.
    if matches!(exp.analysis, Analysis::Waveform { .. } | Analysis::Impulse { .. }) {
        checks.extend(warnings.iter().map(|w| {
            crate::checks::CheckOutcome::unavailable(
                "simulation".into(),
                format!("{} ({}): {w}", exp.meta.figure, exp.key()),
                "the experiment file".into(),
                crate::checks::Source::Internal,
                Some("the case is missing from this page's tables and figures".into()),
            )
        }));
    }
    if let Some(fe) = &exp.finite_element {
        let out = reduction::run(exp, fe);
        tables.extend(out.tables);
        checks.extend(out.check);
        figures.extend(out.figure);
    }
    let (id, figure) = (&exp.key(), &exp.meta.figure);
    match (refs.baseline(id), refs.baseline_mode) {
        (_, BaselineMode::Off) => {}
        (Some(blessed), _) => checks.push(baseline::compare(id, figure, &baseline::sample(&tables), blessed)),
        (None, BaselineMode::Required) => checks.push(baseline::missing(id, figure)),
        (None, BaselineMode::Optional) => {}
    }
    Ok(ExperimentResult {
        exports,
        parameters: parameters(exp),
        assumptions: assumptions(exp),
        experiment: exp.clone(),
        modes,
        tables,
        figures,
        checks,
        curves,
        design: design_answer,
        warnings,
        answer,
    })
}

fn list(v: &[f64]) -> String {
    v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(", ")
}

/// The parameter table of the report.
pub fn parameters(exp: &Experiment) -> Vec<(String, String)> {
    let s = &exp.structure;
    let rows = |m: &nalgebra::DMatrix<f64>| {
        (0..s.dof())
            .map(|i| format!("[{}]", list(&m.row(i).iter().copied().collect::<Vec<_>>())))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let masses = match &s.coupled_mass {
        None => ("masses m_1..m_n (kg)".to_string(), list(&s.masses)),
        Some(m) => ("mass matrix M0 (kg), rows (not diagonal: coordinates, not masses)".to_string(), rows(m)),
    };
    let mut p = vec![
        masses,
        (
            "stiffness K (N/m), rows".to_string(),
            (0..s.dof())
                .map(|i| format!("[{}]", list(&s.stiffness.row(i).iter().copied().collect::<Vec<_>>())))
                .collect::<Vec<_>>()
                .join(" "),
        ),
        (
            "damping".to_string(),
            match &s.damping_spec {
                Damping::ModalRatios(z) => format!("modal ratios zeta = [{}]", list(z)),
                Damping::Rayleigh { alpha, beta } => {
                    format!("Rayleigh alpha = {} 1/s, beta = {} s", fmt_num(*alpha), fmt_num(*beta))
                }
            },
        ),
        ("excitation".to_string(), exp.excitation.describe()),
        ("analysis".to_string(), exp.analysis.kind().to_string()),
    ];
    if let Some(m) = &exp.model {
        p.insert(0, ("model".to_string(), format!("{} ({}): {}", m.label, m.id, m.description)));
    }
    if let Some(f) = &exp.fit {
        let worst = f.shape_residuals.iter().flatten().fold(0.0_f64, |a, r| a.max(r.abs()));
        let freq = f
            .frequency_residuals
            .iter()
            .zip(&f.omegas)
            .map(|(r, w)| format!("{:.1e}", r / (w - r)))
            .collect::<Vec<_>>()
            .join(", ");
        p.push((
            "stiffness fit".to_string(),
            format!(
                "Levenberg-Marquardt from {} starts, {} at the best fit ({}); condition of K {:.2}; relative frequency residuals [{freq}]; largest mode-shape residual {:.4}; measured shapes mass-orthogonal to {:.3}",
                f.starts,
                f.starts_at_best,
                if f.unique() { "unique" } else { "NOT unique" },
                f.condition,
                worst,
                f.orthogonality
            ),
        ));
    }
    if let Analysis::LinearFrf { freq_hz } = &exp.analysis {
        if let (Some(a), Some(b)) = (freq_hz.first(), freq_hz.last()) {
            p.push((
                "frequency grid (Hz)".into(),
                format!("{} to {}, {} points", fmt_num(*a), fmt_num(*b), freq_hz.len()),
            ));
        }
    }
    for c in &exp.cases {
        let d = if c.beds.is_empty() {
            "no damper".to_string()
        } else {
            c.beds
                .iter()
                .map(|b| {
                    let (d, law, grains) = (&b.damper, b.law, b.grains);
                    let clr = d.clearance.to_string();
                    let sticks =
                        law.stick_speed().map_or(String::new(), |v| format!(" (sticks below {} m/s)", fmt_num(v)));
                    let bed = if grains > 1 {
                        format!(
                            ", a column of {grains} grains, restitution e = {}{}",
                            fmt_num(law.restitution()),
                            sticks
                        )
                    } else if !law.is_plastic() {
                        format!(", restitution e = {}{sticks}", fmt_num(law.restitution()))
                    } else {
                        String::new()
                    };
                    let along = match d.direction {
                        crate::model::Direction::Vertical => "",
                        crate::model::Direction::Horizontal => ", horizontal",
                    };
                    format!(
                        "m_{}: m_d = {} kg (mu = {}), d = {clr}{bed}{along}",
                        d.host + 1,
                        fmt_num(d.mass),
                        fmt_num(d.mass / s.masses[d.host])
                    )
                })
                .collect::<Vec<_>>()
                .join("; ")
        };
        p.push((format!("case {} ({})", c.id, c.label), d));
    }
    p
}

/// The assumptions a run rests on: derived from the model settings, then the file's own.
pub fn assumptions(exp: &Experiment) -> Vec<String> {
    let mut a = Vec::new();
    let damping = match &exp.structure.damping_spec {
        Damping::ModalRatios(z) => format!("Damping of the bare structure: modal damping ratios [{}]", list(z)),
        Damping::Rayleigh { alpha, beta } => {
            format!("Damping of the bare structure: Rayleigh alpha = {}, beta = {}", fmt_num(*alpha), fmt_num(*beta))
        }
    };
    a.push(match &exp.damping_assumption {
        Some(why) => format!("{damping} ({why})."),
        None => format!("{damping}."),
    });
    if let Some(src) = &exp.structure_source {
        a.push(format!("Structure: {src}."));
    }
    for c in &exp.cases {
        for (d, law, n) in c.beds.iter().filter(|b| b.grains > 1).map(|b| (&b.damper, b.law, b.grains)) {
            a.push(format!(
                "Case {}: the bed on m_{} is a column of {n} equal grains (total mass unchanged) with restitution e = {} between grains and against the ends{}; grains resting on an end move with it, grains in free flight meet in binary collisions resolved in sequence (docs/model.md, \"Bed models\"); the paper's bed is one plastic mass.",
                c.id,
                d.host + 1,
                fmt_num(law.restitution()),
                law.stick_speed().map_or(String::new(), |v| format!(", sticking below {} m/s", fmt_num(v)))
            ));
        }
        for (d, law) in c.beds.iter().filter(|b| !b.law.is_plastic() && b.grains <= 1).map(|b| (&b.damper, b.law)) {
            a.push(format!(
                "Case {}: the bed on m_{} bounces off its container's ends with restitution e = {} and sticks below {} m/s (the paper's bed is plastic, e = 0).",
                c.id,
                d.host + 1,
                fmt_num(law.restitution()),
                fmt_num(law.stick_speed().unwrap_or(0.0))
            ));
        }
    }
    for c in &exp.cases {
        for d in c.beds.iter().map(|b| &b.damper).filter(|d| d.direction == crate::model::Direction::Horizontal) {
            a.push(format!(
                "Case {}: the container on m_{} is horizontal: no gravity along its bed's motion, which flies at constant velocity between two walls {} apart and hits either; friction with the container's floor is neglected (docs/model.md section 5; the paper's containers are vertical).",
                c.id,
                d.host + 1,
                d.clearance
            ));
        }
    }
    a.extend(exp.meta.assumptions.iter().cloned());
    a
}
