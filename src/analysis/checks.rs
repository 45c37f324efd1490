//! Evaluates an experiment's checks against pre-loaded references.

use crate::checks::reference::{Quantity, ReferenceStore, ValueFile};
use crate::checks::{compare_scalar, CheckOutcome, Status, Subject};
use crate::experiment::{CheckKind, CheckSpec, Experiment};
use crate::model::modal::ModeSummary;

/// Every check of `exp`, in file order. A reference that is missing (the loader validates
/// them, so only a programming error gets here) yields a failed check that says so.
pub fn evaluate(
    exp: &Experiment,
    modes: &[ModeSummary],
    refs: &ReferenceStore,
) -> Vec<CheckOutcome> {
    let mut out = Vec::new();
    for spec in &exp.checks {
        let Some(file) = refs.values(&spec.reference_file) else {
            out.push(missing(spec, "reference file not loaded"));
            continue;
        };
        let known = spec.known_deviation.as_deref();
        match &spec.kind {
            CheckKind::NaturalFrequency { mode } => match quantity(file, spec) {
                Some(q) => {
                    let subject = Subject::new(
                        format!("omega_{}", mode + 1),
                        format!("natural frequency {} of the bare structure", mode + 1),
                        q.unit.clone(),
                        file.provenance(q),
                    );
                    let expected = q.value.unwrap_or(f64::NAN);
                    out.push(compare_scalar(
                        subject,
                        modes[*mode].omega,
                        expected,
                        spec.tolerance,
                        known,
                    ));
                }
                None => out.push(missing(spec, "no such quantity")),
            },
            CheckKind::ModeShape { mode } => {
                match quantity(file, spec).and_then(|q| q.values.as_ref().map(|v| (q, v))) {
                    Some((q, values)) => {
                        for (r, (&c, &e)) in modes[*mode].shape.iter().zip(values).enumerate() {
                            let subject = Subject::new(
                                format!("phi_{}[{}]", mode + 1, r + 1),
                                format!(
                                    "mode {} shape at m_{} (largest element = 1)",
                                    mode + 1,
                                    r + 1
                                ),
                                q.unit.clone(),
                                file.provenance(q),
                            );
                            out.push(compare_scalar(subject, c, e, spec.tolerance, known));
                        }
                    }
                    None => out.push(missing(spec, "no such vector quantity")),
                }
            }
            CheckKind::PaperParameters => out.extend(parameters(exp, file, spec)),
        }
    }
    out
}

fn quantity<'a>(file: &'a ValueFile, spec: &CheckSpec) -> Option<&'a Quantity> {
    spec.reference_id.as_deref().and_then(|id| file.get(id))
}

/// The experiment's masses, stiffnesses and force against the paper's.
fn parameters(exp: &Experiment, file: &ValueFile, spec: &CheckSpec) -> Vec<CheckOutcome> {
    let s = &exp.structure;
    let mut pairs: Vec<(String, String, f64)> = Vec::new();
    for (i, &m) in s.masses.iter().enumerate() {
        pairs.push((format!("m_{}", i + 1), format!("mass m_{} (kg)", i + 1), m));
    }
    for (i, k) in chain_springs(&s.stiffness).into_iter().enumerate() {
        pairs.push((
            format!("k_{}", i + 1),
            format!("chain stiffness k_{} (N/m)", i + 1),
            k,
        ));
    }
    pairs.push((
        "F".into(),
        "force amplitude (N)".into(),
        exp.excitation.force,
    ));
    pairs
        .into_iter()
        .filter_map(|(id, what, computed)| {
            let q = file.get(&id)?;
            let subject = Subject::new(
                id.clone(),
                format!("{what}: experiment input against the paper"),
                q.unit.clone(),
                file.provenance(q),
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

fn missing(spec: &CheckSpec, why: &str) -> CheckOutcome {
    CheckOutcome {
        name: format!(
            "{}#{}",
            spec.reference_file,
            spec.reference_id.clone().unwrap_or_default()
        ),
        description: format!("reference missing: {why}"),
        computed: f64::NAN,
        expected: f64::NAN,
        unit: String::new(),
        abs_diff: f64::NAN,
        rel_diff: f64::NAN,
        tolerance: String::new(),
        status: Status::Fail,
        provenance: spec.reference_file.clone(),
        reason: None,
        detail: None,
    }
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
