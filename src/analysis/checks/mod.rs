//! Evaluates an experiment's checks against pre-loaded references.

mod claim;
mod decay;
mod digitised;
mod orbit;

use crate::checks::reference::{Curve as RefCurve, ReferenceStore};
use crate::checks::{compare_scalar, fmt_num, status, CheckOutcome, Source, Subject};
use crate::reference::values::ValueFile;

use std::collections::BTreeMap;

use super::curves::{Curve, Curves};
use super::evidence::{Decay, MotionTypes, OrbitsResult};
use crate::experiment::{CheckKind, CheckSpec, Experiment};
use crate::model::modal::ModeSummary;

/// What an experiment computed that checks compare.
pub struct Computed<'a> {
    pub curves: &'a Curves,
    pub decays: &'a BTreeMap<String, Decay>,
    pub orbits: Option<&'a OrbitsResult>,
    pub motion_types: &'a MotionTypes,
}

/// Every check of `exp`, in file order. A reference that is missing (the loader validates
/// them, so only a programming error gets here) yields a failed check that says so.
pub fn evaluate(
    exp: &Experiment,
    modes: &[ModeSummary],
    computed: &Computed,
    refs: &ReferenceStore,
) -> Vec<CheckOutcome> {
    let mut out = Vec::new();
    for spec in &exp.checks {
        let start = out.len();
        evaluate_one(exp, modes, computed, refs, spec, &mut out);
        // Each outcome carries the check's id: the first as it is, the k-th further `ID[k]`.
        if let Some(id) = &spec.id {
            for (k, o) in out[start..].iter_mut().enumerate() {
                o.id = Some(if k == 0 { id.clone() } else { format!("{id}[{k}]") });
            }
        }
    }
    out
}

/// The outcomes of one check, appended to `out`.
fn evaluate_one(
    exp: &Experiment,
    modes: &[ModeSummary],
    computed: &Computed,
    refs: &ReferenceStore,
    spec: &CheckSpec,
    out: &mut Vec<CheckOutcome>,
) {
    let curves = computed.curves;
    match &spec.kind {
        CheckKind::ImpulseHistory { case, window } => {
            out.push(match (refs.curve(&spec.reference_file), computed.decays.get(case)) {
                (Some(r), Some(d)) => decay::history(spec, r, d, *window),
                _ => CheckOutcome::missing(spec, "reference or impulse run missing"),
            });
            return;
        }
        CheckKind::OrbitVsSimulation => {
            out.push(match computed.orbits {
                Some(r) => orbit::orbit_vs_simulation(spec, r),
                None => CheckOutcome::missing(spec, "no periodic orbits computed"),
            });
            return;
        }
        CheckKind::Tube { case, mass, curve, x_px, y_px } | CheckKind::Peak { case, mass, curve, x_px, y_px, .. } => {
            let file = refs.digitised(&spec.reference_file);
            match (file, file.and_then(|f| f.get(curve)), curves.of_case(case)) {
                (Some(f), Some(d), Some(c)) => match &spec.kind {
                    CheckKind::Peak { window, .. } => {
                        out.extend(digitised::peak_check(spec, f, d, c, *mass, *window, *x_px, *y_px))
                    }
                    _ => out.push(digitised::tube_check(spec, f, d, c, *mass, *x_px, *y_px)),
                },
                _ => out.push(CheckOutcome::missing(spec, "digitised curve or computed curve missing")),
            }
            return;
        }
        CheckKind::DecayTime { case, mass, levels } => {
            match (refs.curve(&spec.reference_file), computed.decays.get(case)) {
                (Some(r), Some(d)) => out.extend(decay::decay_time(spec, r, d, *mass, levels)),
                _ => out.push(CheckOutcome::missing(spec, "reference or impulse run missing")),
            }
            return;
        }
        _ => {}
    }
    if let CheckKind::Curve { curve, columns, fraction, rel_tol_all } = &spec.kind {
        out.push(match (refs.curve(&spec.reference_file), curves.get(curve)) {
            (Some(r), Some(c)) => curve_check(exp, spec, r, c, columns, *fraction, *rel_tol_all),
            (None, _) => CheckOutcome::missing(spec, "reference curve not loaded"),
            (_, None) => CheckOutcome::missing(spec, &format!("no computed curve \"{curve}\"")),
        });
        return;
    }
    let Some(file) = refs.values(&spec.reference_file) else {
        out.push(CheckOutcome::missing(spec, "reference file not loaded"));
        return;
    };
    let known = spec.known_deviation.as_deref();
    match &spec.kind {
        CheckKind::NaturalFrequency { .. } | CheckKind::ModeShape { .. } => {
            out.extend(mode_checks(spec, file, modes, known))
        }
        CheckKind::PaperParameters => out.extend(parameters(exp, file, spec)),
        CheckKind::PeakRatio { case, over_case, mass, bound, window, reading } => {
            out.push(claim::peak_ratio(spec, file, curves, (case, over_case), *mass, bound, *window, *reading));
        }
        CheckKind::MotionTypes { case, present, absent } => match spec.quantity(file) {
            Some(q) => {
                out.push(claim::motion_types(spec, file, q, case, computed.motion_types.get(case), present, absent))
            }
            None => out.push(CheckOutcome::missing(spec, "claim not found")),
        },
        CheckKind::RatioOrder { case, over_case, mass, window, than_window } => {
            out.push(claim::ratio_order(spec, file, curves, (case, over_case), *mass, *window, *than_window));
        }
        CheckKind::DecayRatio { case, over_case, mass, level } => {
            match (spec.quantity(file), computed.decays.get(case), computed.decays.get(over_case)) {
                (Some(q), Some(a), Some(b)) => out.push(decay::ratio(spec, file, q, a, b, *mass, *level)),
                _ => out.push(CheckOutcome::missing(spec, "bound or impulse runs missing")),
            }
        }
        CheckKind::SdofVsSimulation => match (spec.quantity(file), computed.orbits) {
            (Some(q), Some(r)) => out.push(orbit::sdof_vs_simulation(spec, file, q, r, modes)),
            _ => out.push(CheckOutcome::missing(spec, "claim or periodic orbits missing")),
        },
        CheckKind::Curve { .. }
        | CheckKind::Tube { .. }
        | CheckKind::Peak { .. }
        | CheckKind::ImpulseHistory { .. }
        | CheckKind::DecayTime { .. }
        | CheckKind::OrbitVsSimulation
        | CheckKind::DesignConclusion => {}
    }
}

/// A natural frequency's check, or a mode shape's (one per element compared), against the
/// bare structure's modes.
fn mode_checks(spec: &CheckSpec, file: &ValueFile, modes: &[ModeSummary], known: Option<&str>) -> Vec<CheckOutcome> {
    let mut out = Vec::new();
    match &spec.kind {
        CheckKind::NaturalFrequency { mode } => match spec.quantity(file) {
            Some(q) => {
                let subject = Subject::new(
                    format!("omega_{}", mode + 1),
                    format!("natural frequency {} of the bare structure", mode + 1),
                    q.unit.clone(),
                    file.provenance(q),
                    Source::from_provenance(&file.meta.provenance),
                );
                let expected = q.value.unwrap_or(f64::NAN);
                out.push(compare_scalar(subject, modes[*mode].omega, expected, spec.tolerance, known));
            }
            None => out.push(CheckOutcome::missing(spec, "no such quantity")),
        },
        CheckKind::ModeShape { mode, elements } => {
            match spec.quantity(file).and_then(|q| q.values.as_ref().map(|v| (q, v))) {
                Some((q, values)) => {
                    for (r, (&c, &e)) in
                        modes[*mode].shape.iter().zip(values).enumerate().filter(|(r, _)| elements.contains(r))
                    {
                        let subject = Subject::new(
                            format!("phi_{}[{}]", mode + 1, r + 1),
                            format!("mode {} shape at m_{} (largest element = 1)", mode + 1, r + 1),
                            q.unit.clone(),
                            file.provenance(q),
                            Source::from_provenance(&file.meta.provenance),
                        );
                        out.push(compare_scalar(subject, c, e, spec.tolerance, known));
                    }
                }
                None => out.push(CheckOutcome::missing(spec, "no such vector quantity")),
            }
        }
        _ => {}
    }
    out
}

/// The experiment's masses, stiffnesses and force against the paper's.
fn parameters(exp: &Experiment, file: &ValueFile, spec: &CheckSpec) -> Vec<CheckOutcome> {
    let s = &exp.structure;
    let mut pairs: Vec<(String, String, f64)> = Vec::new();
    for (i, &m) in s.masses.iter().enumerate() {
        pairs.push((format!("m_{}", i + 1), format!("mass m_{} (kg)", i + 1), m));
    }
    for (i, k) in chain_springs(&s.stiffness).into_iter().enumerate() {
        pairs.push((format!("k_{}", i + 1), format!("chain stiffness k_{} (N/m)", i + 1), k));
    }
    if exp.excitation.supports {
        pairs.push(("A".into(), "support acceleration amplitude (m/s^2)".into(), exp.excitation.force));
    } else {
        pairs.push(("F".into(), "force amplitude (N)".into(), exp.excitation.force));
    }
    pairs
        .into_iter()
        .filter_map(|(id, what, computed)| {
            let q = file.get(&id)?;
            let subject = Subject::new(
                id.clone(),
                format!("{what}: experiment input against the paper"),
                q.unit.clone(),
                file.provenance(q),
                Source::from_provenance(&file.meta.provenance),
            );
            Some(compare_scalar(
                subject,
                computed,
                q.value.unwrap_or(f64::NAN),
                spec.tolerance,
                spec.known_deviation.as_deref(),
            ))
        })
        .collect()
}

/// The chain springs k_1..k_n behind a chain stiffness matrix (k_1 ties m_1 to ground).
fn chain_springs(k: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    let n = k.nrows();
    let mut springs = vec![0.0; n];
    for i in 1..n {
        springs[i] = -k[(i - 1, i)];
    }
    springs[0] = k[(0, 0)] - if n > 1 { springs[1] } else { 0.0 };
    springs
}

/// A computed curve against a reference curve at the reference's own frequencies. Points are
/// compared where both mark the motion settled and period-1 (a reference without those
/// columns is linear: every point counts).
fn curve_check(
    exp: &Experiment,
    spec: &CheckSpec,
    r: &RefCurve,
    c: &Curve,
    prefix: &str,
    fraction: f64,
    rel_all: f64,
) -> CheckOutcome {
    let n = exp.structure.dof();
    let freq = r.column("freq_hz").unwrap_or(&[]);
    let conv = r.column("converged");
    let per = r.column("period");
    let mut diffs: Vec<(f64, f64, usize, f64, f64)> = Vec::new(); // (rel, f, mass, ours, theirs)
    let (mut missing_points, mut disagree, mut neither, mut compared) = (0, 0, 0, 0);
    for (k, &f) in freq.iter().enumerate() {
        let ref_regular = conv.is_none_or(|v| v[k] == 1.0) && per.is_none_or(|v| v[k] == 1.0);
        let Some(i) = c.index_of(f) else {
            missing_points += 1;
            continue;
        };
        if !(ref_regular && c.regular(i)) {
            if ref_regular != c.regular(i) {
                disagree += 1;
            } else {
                neither += 1;
            }
            continue;
        }
        compared += 1;
        for m in 0..n {
            // The loader made sure the columns are there (ReferenceStore::load).
            if let Some(col) = r.column(&format!("{prefix}c{}", m + 1)) {
                let (ours, theirs) = (c.compliance[i][m], col[k]);
                diffs.push(((ours - theirs).abs() / theirs.abs(), f, m, ours, theirs));
            }
        }
    }
    // Points not compared count against the fraction: a reference that quietly stops being
    // compared must not pass.
    let enough = compared as f64 >= fraction * freq.len() as f64;
    let total = diffs.len();
    let within = diffs.iter().filter(|d| d.0 <= spec.tolerance.rel).count();
    let worst = diffs.iter().copied().max_by(|a, b| a.0.total_cmp(&b.0));
    let achieved = if total > 0 { within as f64 / total as f64 } else { 0.0 };
    let ok = total > 0 && enough && missing_points == 0 && achieved >= fraction && worst.is_none_or(|w| w.0 <= rel_all);
    let mut detail = format!(
        "{compared} of the reference's {} points compared{}; {within} of {total} values (mass x frequency) within {} ({:.1} %, {:.0} % required)",
        freq.len(),
        if enough { String::new() } else { format!(", fewer than the {:.0} % required", 100.0 * fraction) },
        fmt_num(spec.tolerance.rel),
        100.0 * achieved,
        100.0 * fraction
    );
    if let Some((d, f, m, ours, theirs)) = worst {
        detail += &format!(
            "; worst at {} Hz, m{}: {} vs {} {} ({:.2e} relative)",
            fmt_num(f),
            m + 1,
            fmt_num(ours),
            fmt_num(theirs),
            exp.excitation.per_unit(),
            d
        );
    }
    if disagree > 0 {
        detail += &format!("; {disagree} points settled and period-1 on one side only (not compared)");
    }
    if neither > 0 {
        detail += &format!("; {neither} points settled and period-1 on neither side (not compared)");
    }
    if missing_points > 0 {
        detail += &format!("; {missing_points} reference frequencies not computed");
    }
    CheckOutcome {
        settled: Some(true),
        id: None,
        values: Vec::new(),
        name: format!("{} vs {}", c.id, spec.reference_file),
        description: format!("compliance of curve {} ({}) at the reference's frequencies", c.id, c.label),
        computed: worst.map(|w| w.0).unwrap_or(f64::NAN),
        expected: 0.0,
        unit: "(largest relative difference)".into(),
        abs_diff: worst.map(|w| (w.3 - w.4).abs()).unwrap_or(f64::NAN),
        rel_diff: worst.map(|w| w.0).unwrap_or(f64::NAN),
        tolerance: format!(
            "{} at {:.0} % of values, {} at all",
            fmt_num(spec.tolerance.rel),
            100.0 * fraction,
            fmt_num(rel_all)
        ),
        status: status(ok, spec.known_deviation.is_some()),
        provenance: format!("independent solver: {} (reference/independent-solver/PROVENANCE.md)", spec.reference_file),
        source: Source::IndependentSolver,
        reason: spec.known_deviation.clone(),
        detail: Some(detail),
    }
}
