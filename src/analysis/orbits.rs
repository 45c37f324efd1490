//! SDOF periodic analyses (Fig. 9): the equivalent SDOF model of a mode with one damper, its
//! periodic orbits continued in frequency with their stability, the exact periodic orbits of
//! the full structure with the same damper, the simulation of the full structure, and the
//! clearance at which only Type II motion appears within the resonance.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use rayon::prelude::*;

use crate::checks::reference::ReferenceStore;
use crate::experiment::{CurveId, Experiment};
use crate::model::modal::ModeSummary;
use crate::model::sdof::EquivalentSdof;
use crate::model::{Clearance, Damper};
use crate::sim::orbits::continuation::{continue_branch, BranchEnd, BranchPoint, ContinuationOptions, Parameter};
use crate::sim::orbits::periodic::{seed, solve, summarize, NewtonOptions};
use crate::sim::settle::sweep::{self, SweepPoint};
use crate::sim::{steady_from_rest, Dynamics, SteadyOptions, System};

use super::curves;
use super::kind::{Input, Kind, Output};
use super::orbit_figures;
use super::result::Tick;

pub use super::evidence::{ClearanceRow, OrbitBranch, OrbitCheckPoint, OrbitPoint, OrbitsResult};

/// An SDOF periodic analysis (`kind = "sdof_periodic"`): the mode, the band and its grid, the
/// candidate clearances when the damper's is scanned, and the steady-state settings.
pub(crate) struct Sdof<'a> {
    pub(crate) mode: usize,
    pub(crate) freq_hz: &'a [f64],
    pub(crate) clearances_mm: Option<&'a [f64]>,
    pub(crate) steady: &'a SteadyOptions,
}

impl Kind for Sdof<'_> {
    fn work(&self, _exp: &Experiment, _refs: &ReferenceStore) -> u64 {
        (self.clearances_mm.map_or(0, |c| c.len()) + 2 + self.freq_hz.len()) as u64
    }

    fn run(&self, i: &Input<'_>) -> Output {
        let (exp, modes) = (i.exp, i.modes);
        let Some(r) = run(exp, modes, self.mode, self.freq_hz, self.clearances_mm, self.steady, i.tick) else {
            return Output::default();
        };
        Output {
            tables: orbit_figures::tables(exp, modes, &r),
            figures: orbit_figures::figures(exp, modes, &r, self.freq_hz),
            exports: exports(&r, modes[self.mode].reference_mass),
            orbits: Some(r),
            ..Output::default()
        }
    }
}

/// "Within the resonance": where the compliance is at least this fraction of its peak (the
/// half-power band).
pub const RESONANCE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Most segments per branch, and most seed frequencies simulated to find them.
const MAX_SEGMENTS: usize = 4;
const MAX_SEEDS: usize = 16;

/// The continuation settings over a band, in Hz.
fn options(freq_hz: &[f64]) -> ContinuationOptions {
    let (lo, hi) = (freq_hz[0], freq_hz[freq_hz.len() - 1]);
    ContinuationOptions {
        p_min: lo,
        p_max: hi,
        p_scale: 1.0,
        ds: 0.02,
        ds_min: 1e-5,
        ds_max: 0.1,
        max_points: 600,
        // 1e-10 of the amplitude: near a grazing impact the map's derivatives grow large and
        // rounding keeps the residual near 1e-10.
        newton: NewtonOptions { tol: 1e-10, ..NewtonOptions::default() },
        parameter: Parameter::FrequencyHz,
    }
}

/// The SDOF system of a mode with a damper set.
pub fn sdof_system(exp: &Experiment, dampers: &[Damper], mode: usize) -> (EquivalentSdof, System) {
    let e = EquivalentSdof::new(&exp.structure, dampers, mode, exp.excitation.mass, exp.excitation.force);
    let sys = System::plastic(e.structure(), vec![e.damper()], 0, e.force);
    (e, sys)
}

/// Continues the orbits of `sys` over the band from the first seed frequency whose simulated
/// steady state is period-1 with impacts, both ways; `compliance` maps the orbit's amplitudes
/// to the structure's compliances.
fn branch(
    id: &str,
    label: &str,
    sys: &System,
    freq_hz: &[f64],
    seeds_hz: &[f64],
    steady: &SteadyOptions,
    compliance: &(dyn Fn(&[f64]) -> Vec<f64> + Sync),
) -> OrbitBranch {
    // Decomposed once; each frequency adds only its forced response.
    let base = Dynamics::unforced(sys);
    let family = |f: f64| base.as_ref().map_err(Clone::clone).and_then(|b| b.at_omega(2.0 * PI * f));
    let opts = options(freq_hz);
    let mut out = OrbitBranch { id: id.into(), label: label.into(), ..OrbitBranch::default() };
    let words = |e: &BranchEnd| match e {
        BranchEnd::Range => "reached the end of the band".to_string(),
        BranchEnd::Budget => "point budget used up".to_string(),
        BranchEnd::Failed(why) => format!("ended: {why}"),
    };
    let mut tried = 0;
    for &f in seeds_hz {
        if out.segments.len() >= MAX_SEGMENTS || tried >= MAX_SEEDS {
            break;
        }
        if out.covers(f) {
            continue;
        }
        tried += 1;
        let Ok(d) = family(f) else { continue };
        let st = steady_from_rest(&d, steady);
        if !(st.converged && st.period == 1) || st.bottom_impacts.first().is_none_or(|b| *b == 0.0) {
            continue;
        }
        let length = st.amplitude.iter().copied().fold(0.0, f64::max).max(1e-9);
        let Some((problem, u)) = seed(&d, &st.final_state, 1, length, d.omega, false) else { continue };
        let down = continue_branch(&family, problem, f, &u, false, &opts);
        let up = continue_branch(&family, problem, f, &u, true, &opts);
        let (Ok(down), Ok(up)) = (down, up) else { continue };
        let describe = |p: &BranchPoint| {
            let d = family(p.p).ok()?;
            let s = summarize(&d, &problem, &p.orbit);
            Some(OrbitPoint {
                freq_hz: p.p,
                compliance: compliance(&s.amplitude),
                phi: s.phi,
                tau0: s.tau0,
                tau1: s.tau1,
                tau2: s.tau2,
                kind: s.kind,
                stable: p.orbit.stable,
                smooth: p.orbit.smooth,
                multipliers: p.orbit.multipliers.clone(),
            })
        };
        out.segments.push(down.points.iter().rev().chain(up.points.iter().skip(1)).filter_map(describe).collect());
        out.special.extend(down.special.iter().chain(&up.special).copied());
        out.ends.push(format!(
            "segment from {} Hz: down {}; up {}",
            crate::checks::fmt_num(f),
            words(&down.end),
            words(&up.end)
        ));
    }
    if out.segments.is_empty() {
        out.ends = vec!["no seed: the simulation found no period-1 impacting motion at the seed frequencies".into()];
    }
    out
}

/// Seed frequencies: the mode's natural frequency first, then the band's grid outward from it.
fn seeds(freq_hz: &[f64], natural_hz: f64) -> Vec<f64> {
    let mut s: Vec<f64> = freq_hz.to_vec();
    s.sort_by(|a, b| (a - natural_hz).abs().total_cmp(&(b - natural_hz).abs()));
    s.insert(0, natural_hz);
    s
}

/// The clearance the paper's SDOF technique picks (Fig. 9): of the candidate clearances (mm),
/// those whose stable orbits of the equivalent SDOF model of `mode` (with `dampers`, the
/// location effect of Eq. 12-13 included) are all Type II within the resonance (where the
/// compliance of `reference` is at least 1/sqrt(2) of its peak), the one with the lowest SDOF
/// peak; else the lowest SDOF peak. Every candidate's clearance replaces each damper's.
pub struct SdofChoice {
    /// The clearance chosen, mm.
    pub clearance_mm: f64,
    /// Every candidate's row.
    pub rows: Vec<ClearanceRow>,
    /// How the clearance was chosen, in words.
    pub note: String,
    /// The SDOF branch of each candidate, in the order of the candidates.
    pub branches: Vec<OrbitBranch>,
}

/// See [`SdofChoice`]. `list` must not be empty.
#[allow(clippy::too_many_arguments)]
pub fn sdof_choice(
    exp: &Experiment,
    dampers: &[Damper],
    mode: usize,
    reference: usize,
    freq_hz: &[f64],
    list: &[f64],
    steady: &SteadyOptions,
    tick: &(dyn Fn() + Sync),
) -> SdofChoice {
    let force = exp.excitation.force;
    let natural = crate::model::modal::modal_summary(&exp.structure, &[])[mode].freq_hz;
    let seeds_hz = seeds(freq_hz, natural);
    let sdof_compliance = |e: &EquivalentSdof| {
        let shape = e.mode.shape.clone();
        move |a: &[f64]| shape.iter().map(|s| s.abs() * a[0] / force).collect::<Vec<f64>>()
    };
    let (rows, branches): (Vec<ClearanceRow>, Vec<OrbitBranch>) = list
        .par_iter()
        .map(|&mm| {
            let dampers: Vec<Damper> =
                dampers.iter().map(|d| Damper { clearance: Clearance::from_mm(mm), ..*d }).collect();
            let (e, sys) = sdof_system(exp, &dampers, mode);
            let b = branch("sdof", "", &sys, freq_hz, &seeds_hz, steady, &sdof_compliance(&e));
            tick();
            let peak = b.peak(reference);
            let mut kinds: Vec<String> = b
                .points()
                .filter(|p| p.stable && peak.is_some_and(|pk| p.compliance[reference] >= RESONANCE * pk.1))
                .map(|p| p.kind.clone())
                .collect();
            kinds.sort();
            kinds.dedup();
            let only_type_ii = !kinds.is_empty() && kinds.iter().all(|k| k == "II");
            (ClearanceRow { clearance_mm: mm, peak, kinds, only_type_ii }, b)
        })
        .unzip();
    let best = |ok: bool| {
        rows.iter()
            .filter(|r| r.peak.is_some() && (!ok || r.only_type_ii))
            .min_by(|a, b| a.peak.map_or(f64::INFINITY, |p| p.1).total_cmp(&b.peak.map_or(f64::INFINITY, |p| p.1)))
    };
    let (pick, note) = match best(true) {
        Some(r) => (
            r.clearance_mm,
            format!(
                "Of the {} candidate clearances, those whose stable SDOF orbits are all Type II within the resonance (where the compliance of m{} is at least 1/sqrt(2) of its peak); among them, the one with the lowest peak: {} mm.",
                rows.len(),
                reference + 1,
                crate::checks::fmt_num(r.clearance_mm)
            ),
        ),
        None => match best(false) {
            Some(r) => (
                r.clearance_mm,
                format!(
                    "No candidate clearance gives Type II alone within the resonance (where the compliance is at least 1/sqrt(2) of its peak: see the table of types); the one with the lowest peak is used: {} mm.",
                    crate::checks::fmt_num(r.clearance_mm)
                ),
            ),
            None => (list[0], "No candidate clearance has an impacting SDOF orbit; the first is used.".into()),
        },
    };
    SdofChoice { clearance_mm: pick, rows, note, branches }
}

/// Runs the analysis for the (single) case with a damper.
pub fn run(
    exp: &Experiment,
    modes: &[ModeSummary],
    mode: usize,
    freq_hz: &[f64],
    clearances_mm: Option<&[f64]>,
    steady: &SteadyOptions,
    tick: &Tick,
) -> Option<OrbitsResult> {
    let case = exp.cases.iter().find(|c| c.beds.len() == 1)?.clone();
    let force = exp.excitation.force;
    let natural = modes[mode].freq_hz;
    let seeds_hz = seeds(freq_hz, natural);
    let sdof_compliance = |e: &EquivalentSdof| {
        let shape = e.mode.shape.clone();
        move |a: &[f64]| shape.iter().map(|s| s.abs() * a[0] / force).collect::<Vec<f64>>()
    };
    let reference = modes[mode].reference_mass;
    // Candidate clearances: the SDOF branch of each, and the types within its resonance.
    let scan = matches!(case.beds.first().map(|b| &b.clearance), Some(crate::experiment::ClearanceSource::Scan));
    let (chosen_mm, clearance_rows, clearance_note, mut branches) = match (scan, clearances_mm) {
        (true, Some(list)) => {
            let choice = sdof_choice(exp, &case.dampers(), mode, reference, freq_hz, list, steady, tick);
            (choice.clearance_mm, choice.rows, choice.note, choice.branches)
        }
        _ => {
            let mm = case.beds[0].damper.clearance.mm();
            (mm, Vec::new(), format!("The clearance is given: {} mm.", crate::checks::fmt_num(mm)), Vec::new())
        }
    };
    let mut case = case;
    case.beds[0].damper.clearance = Clearance::from_mm(chosen_mm);
    case.beds[0].clearance = crate::experiment::ClearanceSource::Fixed;
    let (sdof_model, sdof_sys) = sdof_system(exp, &case.dampers(), mode);
    // The chosen candidate's branch is already there (the same system, computed the same way).
    let sdof = match clearance_rows.iter().position(|r| r.clearance_mm == chosen_mm) {
        Some(i) => OrbitBranch { label: "equivalent SDOF".into(), ..branches.swap_remove(i) },
        None => branch("sdof", "equivalent SDOF", &sdof_sys, freq_hz, &seeds_hz, steady, &sdof_compliance(&sdof_model)),
    };
    tick();
    let full = curves::system(exp, &case);
    let exact =
        branch("exact", "exact orbit of the 3-mass structure", &full, freq_hz, &seeds_hz, steady, &|a: &[f64]| {
            a.iter().map(|x| x / force).collect()
        });
    tick();
    let n = exp.structure.dof();
    let points: Vec<SweepPoint> = sweep::from_rest(&full, freq_hz, steady, tick);
    let checked = check_points(&full, &points, force);
    let simulation =
        curves::from_sweep(CurveId::whole("simulation"), "simulation of the 3-mass structure", points, force, &[1], n);
    Some(OrbitsResult {
        mode,
        force,
        case,
        sdof_model,
        clearance_rows,
        clearance_note,
        sdof,
        exact,
        simulation,
        checked,
    })
}

/// At every simulated point that settled on a period-1 motion: the exact orbit through its
/// final state by Newton's method, and the largest relative difference of the compliances.
fn check_points(sys: &System, points: &[SweepPoint], force: f64) -> Vec<OrbitCheckPoint> {
    let base = Dynamics::unforced(sys);
    points
        .par_iter()
        .filter_map(|p| {
            // A point that could not be set up has no motion to check (its sweep says why).
            let st = p.result.as_ref().ok()?;
            if !(st.converged && st.period == 1) || st.bottom_impacts[0] == 0.0 {
                return None;
            }
            let d = match base.as_ref().map_err(Clone::clone).and_then(|b| b.at_omega(2.0 * PI * p.freq_hz)) {
                Ok(d) => d,
                Err(e) => {
                    let note = format!("cannot be set up: {e}");
                    return Some(OrbitCheckPoint { freq_hz: p.freq_hz, rel_diff: f64::NAN, stable: false, note });
                }
            };
            let length = st.amplitude.iter().copied().fold(0.0, f64::max);
            let Some((problem, u)) = seed(&d, &st.final_state, 1, length, d.omega, false) else {
                return Some(OrbitCheckPoint {
                    freq_hz: p.freq_hz,
                    rel_diff: f64::NAN,
                    stable: false,
                    note: "no seed".into(),
                });
            };
            Some(match solve(&problem, &d, &u, &NewtonOptions::default()) {
                Ok(o) => {
                    let s = summarize(&d, &problem, &o);
                    let rel = s
                        .amplitude
                        .iter()
                        .zip(&st.amplitude)
                        .map(|(a, b)| (a / force - b / force).abs() / (b / force))
                        .fold(0.0, f64::max);
                    OrbitCheckPoint { freq_hz: p.freq_hz, rel_diff: rel, stable: o.stable, note: s.kind }
                }
                Err(e) => {
                    OrbitCheckPoint { freq_hz: p.freq_hz, rel_diff: f64::NAN, stable: false, note: e.to_string() }
                }
            })
        })
        .collect()
}

/// Values other experiments may use.
pub fn exports(r: &OrbitsResult, reference: usize) -> BTreeMap<String, f64> {
    let mut e = BTreeMap::new();
    e.insert("clearance_mm".into(), r.case.beds[0].damper.clearance.mm());
    for (name, b) in [("sdof", &r.sdof), ("exact", &r.exact)] {
        if let Some((f, c)) = b.peak(reference) {
            e.insert(format!("peak_{name}"), c);
            e.insert(format!("peak_hz_{name}"), f);
        }
    }
    if let Some((f, c)) = r.simulation.refined_peak(reference) {
        e.insert("peak_simulation".into(), c);
        e.insert("peak_hz_simulation".into(), f);
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::curves::parabola_top;

    /// A damped resonance near 49 Hz (damping 0.01): the compliance at `f`.
    fn resonance(f: f64) -> f64 {
        let r = f / 49.0;
        1e-4 / ((1.0 - r * r).powi(2) + (0.02 * r).powi(2)).sqrt()
    }

    /// A branch through the resonance with the continuation's steps given.
    fn branch(steps: impl Iterator<Item = f64>) -> OrbitBranch {
        let mut f = 46.0;
        let mut seg = Vec::new();
        for h in steps {
            seg.push(OrbitPoint {
                freq_hz: f,
                compliance: vec![resonance(f)],
                phi: 0.0,
                tau0: None,
                tau1: None,
                tau2: None,
                kind: "II".into(),
                stable: true,
                smooth: true,
                multipliers: Vec::new(),
            });
            f += h;
            if f > 52.0 {
                break;
            }
        }
        OrbitBranch { segments: vec![seg], ..OrbitBranch::default() }
    }

    #[test]
    fn a_branchs_peak_does_not_depend_on_the_continuations_steps() {
        let (f_true, c_true) = (49.0 * (1.0f64 - 2.0 * 0.01 * 0.01).sqrt(), resonance(49.0 * (1.0f64 - 2e-4).sqrt()));
        // Steps of 0.02-0.1 Hz in three patterns, as an adaptive continuation takes them.
        let patterns: [Box<dyn Fn(usize) -> f64>; 3] = [
            Box::new(|_| 0.05),
            Box::new(|i| 0.02 + 0.08 * ((i * 7919) % 13) as f64 / 12.0),
            Box::new(|i| if i % 2 == 0 { 0.03 } else { 0.07 }),
        ];
        let (mut raw, mut refined, mut at) = (0.0f64, 0.0f64, 0.0f64);
        for p in &patterns {
            let b = branch((0..).map(p));
            let (f, c) = b.peak(0).unwrap();
            let (_, highest) = b.highest(0).unwrap();
            assert!(c >= highest);
            raw = raw.max((highest / c_true - 1.0).abs());
            refined = refined.max((c / c_true - 1.0).abs());
            at = at.max((f - f_true).abs());
        }
        // The highest computed point alone is off by where the steps fell; the refined peak is
        // ten times closer, at the right frequency.
        assert!(raw > 1e-3, "{raw}");
        assert!(refined < raw / 10.0, "refined {refined}, highest point {raw}");
        assert!(at < 2e-3, "{at} Hz");
    }

    #[test]
    fn the_parabola_needs_a_cap() {
        assert_eq!(parabola_top([(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)]), None);
        assert_eq!(parabola_top([(0.0, 0.0), (2.0, 1.0), (1.0, 0.0)]), None);
        let (x, y) = parabola_top([(-1.0, 0.0), (0.5, 0.75), (1.0, 0.0)]).unwrap();
        assert!((x - 0.0).abs() < 1e-12 && (y - 1.0).abs() < 1e-12, "{x} {y}");
    }
}
