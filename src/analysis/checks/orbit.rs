//! Checks of SDOF periodic analyses: the exact orbits against the simulation of the same
//! structure (a second method), and the paper's "close agreement" of the SDOF solution with
//! the simulation, as a number.

use crate::checks::{fmt_num, status, CheckOutcome, Source};
use crate::experiment::CheckSpec;
use crate::model::modal::ModeSummary;
use crate::reference::values::{Quantity, ValueFile};

use super::super::evidence::OrbitsResult;

/// The exact orbits found through the simulated steady states: the largest relative
/// difference of the compliances over the points whose orbit is stable.
pub fn orbit_vs_simulation(spec: &CheckSpec, r: &OrbitsResult) -> CheckOutcome {
    let stable: Vec<_> = r.checked.iter().filter(|c| c.stable).collect();
    let failed = r.checked.iter().filter(|c| !c.rel_diff.is_finite()).count();
    let worst = stable.iter().max_by(|a, b| a.rel_diff.total_cmp(&b.rel_diff));
    let value = worst.map_or(f64::NAN, |w| w.rel_diff);
    let ok = !stable.is_empty() && failed == 0 && value <= spec.tolerance.rel;
    let mut detail = format!(
        "{} simulated points settled on a period-1 impacting motion; {} of their orbits are stable",
        r.checked.len(),
        stable.len()
    );
    if let Some(w) = worst {
        detail += &format!("; worst at {} Hz ({:.2e})", fmt_num(w.freq_hz), w.rel_diff);
    }
    if failed > 0 {
        detail += &format!("; no orbit found at {failed} points");
    }
    let unstable = r.checked.len() - stable.len() - failed;
    if unstable > 0 {
        detail += &format!("; {unstable} orbits unstable (a settled simulation cannot sit on them: see the table)");
    }
    CheckOutcome {
        settled: None,
        id: None,
        values: Vec::new(),
        name: "exact orbits vs simulation".into(),
        description: "compliance of every mass: the periodic orbit solved on the impact section through each simulated steady state (itself an orbit of the stroboscopic section), against that steady state".into(),
        computed: value,
        expected: 0.0,
        unit: "(largest relative difference)".into(),
        abs_diff: value,
        rel_diff: value,
        tolerance: format!("{} relative (two sections, each solved to a residual of ~1e-13)", fmt_num(spec.tolerance.rel)),
        status: status(ok, spec.known_deviation.is_some()),
        provenance: "the steady states of the same structure in this run (another section and another return map)".into(),
        source: Source::Internal,
        reason: spec.known_deviation.clone(),
        detail: Some(detail),
    }
}

/// The peak compliance of the stable SDOF orbits against the peak of the simulation of the
/// full structure, at the mode's reference mass.
pub fn sdof_vs_simulation(
    spec: &CheckSpec,
    file: &ValueFile,
    claim: &Quantity,
    r: &OrbitsResult,
    modes: &[ModeSummary],
) -> CheckOutcome {
    let m = modes[r.mode].reference_mass;
    let (sdof, sim) = (r.sdof.peak(m), r.simulation.refined_peak(m));
    let (c, e) = (sdof.map_or(f64::NAN, |p| p.1), sim.map_or(f64::NAN, |p| p.1));
    let exact = r.exact.peak(m);
    let (fs, fe) = (sdof.map_or(f64::NAN, |p| p.0), sim.map_or(f64::NAN, |p| p.0));
    let values = vec![
        ("f".to_string(), fs),
        ("f_simulation".to_string(), fe),
        ("df_hz".to_string(), fs - fe),
        ("exact".to_string(), exact.map_or(f64::NAN, |p| p.1)),
        ("over_exact".to_string(), exact.map_or(f64::NAN, |p| c / p.1)),
    ];
    let abs = (c - e).abs();
    let within = abs <= spec.tolerance.abs + spec.tolerance.rel * e.abs();
    CheckOutcome {
        settled: None,
        id: None,
        values,
        name: format!("SDOF peak vs simulation, m{}", m + 1),
        description: format!(
            "peak compliance of m{} of the stable equivalent-SDOF orbits against the simulated 3-mass structure (each peak refined: the top of the parabola through the highest point and its two neighbours)",
            m + 1
        ),
        computed: c,
        expected: e,
        unit: "m/N".into(),
        abs_diff: abs,
        rel_diff: abs / e.abs(),
        tolerance: crate::checks::describe_tolerance(spec.tolerance),
        status: status(within, spec.known_deviation.is_some()),
        provenance: format!("{} (the simulated value is this run's)", file.provenance(claim)),
        source: Source::from_provenance(&file.meta.provenance),
        reason: spec.known_deviation.clone(),
        detail: Some(format!(
            "SDOF peak at {} Hz, simulation peak at {} Hz",
            sdof.map_or("-".into(), |p| fmt_num(p.0)),
            sim.map_or("-".into(), |p| fmt_num(p.0))
        )),
    }
}
