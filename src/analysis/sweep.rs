//! Sweep analyses: steady-state compliance of every case by simulation (cases without
//! dampers are linear, exactly), linear references beside, marks at chosen frequencies.

use std::collections::BTreeMap;

use crate::checks::fmt_num;
use crate::checks::reference::ReferenceStore;
use crate::experiment::{round_hz, CheckKind, CurveId, Experiment, Linear, PlotSpec, Start};
use crate::figure::VLine;
use crate::model::modal::ModeSummary;
use crate::sim::motion::observe::Observe;
use crate::sim::settle::sweep::{self, Direction};
use crate::sim::SteadyOptions;

use super::branches::{self, OrbitCurve};
use super::curves::{self, union_grid, Curve};
use super::figures::{self, Extras};
use super::kind::{Input, Kind, Output};
use super::result::Tick;

/// Frequencies the curve checks of `curve_id` need, from their reference files.
pub fn check_frequencies(exp: &Experiment, refs: &ReferenceStore, curve_id: &CurveId) -> Vec<f64> {
    exp.checks
        .iter()
        .filter_map(|c| match &c.kind {
            CheckKind::Curve { curve, .. } if curve == curve_id => refs.curve(&c.reference_file),
            _ => None,
        })
        .flat_map(|r| r.column("freq_hz").unwrap_or(&[]).to_vec())
        .collect()
}

/// Number of simulated points a sweep will run (for progress).
pub fn work(exp: &Experiment, freq_hz: &[f64], start: Start, refs: &ReferenceStore) -> u64 {
    exp.cases
        .iter()
        .filter(|c| !c.beds.is_empty())
        .map(|c| {
            let extra = match start {
                Start::Rest => check_frequencies(exp, refs, &CurveId::whole(&c.id)),
                Start::Continuation => Vec::new(),
            };
            let n = union_grid(freq_hz, &extra).len() as u64;
            if start == Start::Continuation {
                2 * n
            } else {
                n
            }
        })
        .sum()
}

/// A sweep analysis (`kind = "sweep"`): its grid, its start and its steady-state settings.
pub(crate) struct Sweep<'a> {
    pub(crate) freq_hz: &'a [f64],
    pub(crate) start: Start,
    pub(crate) steady: &'a SteadyOptions,
}

impl Kind for Sweep<'_> {
    fn work(&self, exp: &Experiment, refs: &ReferenceStore) -> u64 {
        work(exp, self.freq_hz, self.start, refs)
    }

    fn run(&self, i: &Input<'_>) -> Output {
        run(i.exp, i.modes, i.refs, self.freq_hz, self.start, self.steady, i.tick)
    }
}

/// Runs a sweep analysis.
pub fn run(
    exp: &Experiment,
    modes: &[ModeSummary],
    refs: &ReferenceStore,
    freq_hz: &[f64],
    start: Start,
    steady: &SteadyOptions,
    tick: &Tick,
) -> Output {
    let n = exp.structure.dof();
    let beds = exp.cases.iter().map(|c| c.beds.len()).max().unwrap_or(0);
    // A reduced model's modal coordinates are no displacement of any point (docs/fe-models.md):
    // its sweeps measure and tabulate its points alone, which spares the record the work of
    // following every coordinate (most of a followed point's time on the plate).
    let shown = exp.structure.physical();
    let observe = if shown < n { Observe::only(0..shown) } else { steady.observe };
    // On moving supports the records also find the storeys' drifts and the floors' absolute
    // accelerations (what an engineer checks on a building).
    let steady = &SteadyOptions { peaks: exp.excitation.supports, observe, ..*steady };
    let mut curves: Vec<Curve> = Vec::new();
    let mut orbit_branches: Vec<OrbitCurve> = Vec::new();
    let band = (freq_hz[0], freq_hz[freq_hz.len() - 1]);
    for case in &exp.cases {
        if case.beds.is_empty() {
            let grid = union_grid(freq_hz, &check_frequencies(exp, refs, &CurveId::whole(&case.id)));
            curves.push(curves::linear(exp, case, CurveId::whole(&case.id), &case.label, &grid, false));
            continue;
        }
        let sys = curves::system(exp, case);
        match start {
            Start::Rest => {
                let grid = union_grid(freq_hz, &check_frequencies(exp, refs, &CurveId::whole(&case.id)));
                let pts = sweep::from_rest(&sys, &grid, steady, tick);
                curves.push(curves::from_sweep(
                    CurveId::whole(&case.id),
                    &case.label,
                    pts,
                    exp.excitation.force,
                    &case.grains(),
                    n,
                ));
            }
            Start::Continuation => {
                for (dir, word) in [(Direction::Up, "up"), (Direction::Down, "down")] {
                    let pts = sweep::continued(&sys, freq_hz, dir, steady, tick);
                    // The orbit of the sweep's first point, continued through the band.
                    if let Some((f, Ok(st))) = pts.first().map(|p| (p.freq_hz, &p.result)) {
                        orbit_branches.push(branches::continue_orbit(
                            CurveId::orbits(&case.id, dir),
                            &format!("orbits continued {word}ward from {} Hz", fmt_num(f)),
                            &sys,
                            f,
                            st,
                            dir == Direction::Up,
                            band,
                        ));
                    }
                    let id = CurveId::continued(&case.id, dir);
                    let label = format!("{} (continued {word}ward)", case.label);
                    curves.push(curves::from_sweep(id, &label, pts, exp.excitation.force, &case.grains(), n));
                }
            }
        }
    }
    let (marks, exports) = marks(exp, &curves);
    let linear = linear_refs(exp, freq_hz);
    let plots: Vec<&PlotSpec> = exp.plots.iter().collect();
    let refs_c: Vec<&Curve> = curves.iter().collect();
    let figures = figures::compliance(
        exp,
        &plots,
        &refs_c,
        &Extras {
            overlays: super::overlays::overlays(exp, refs, &curves),
            linear: linear.iter().collect(),
            marks,
            branches: orbit_branches.iter().collect(),
            range: band,
        },
        modes,
    );
    let mut figures = figures;
    figures.extend(drift_figure(exp, &refs_c, &linear, band));
    let peaks_words = if exp.excitation.supports {
        format!(
            ", each storey's drift amplitude (drift1..: the floor's displacement less the one below, the first storey's less the ground's) over {} (s^2) and each floor's absolute acceleration amplitude (acc1..) over {} (1: the ground's own; both at a point with no certified orbit the largest over its measured record)",
            exp.excitation.symbol(),
            exp.excitation.symbol()
        )
    } else {
        String::new()
    };
    let mut tables = vec![curves::table(
        "compliance",
        &format!("Steady-state compliance (max - min)/2 / {} ({}{}) of each mass (c1..cn) per curve and frequency{peaks_words}, whether it settled, its period, impacts per forcing period on the bottom and top of each bed, the highest flight of each bed (mm), the transient periods simulated; a point with no certified orbit gives its measured statistic", exp.excitation.symbol(), exp.excitation.per_unit(), if exp.excitation.supports { ": displacements relative to the supports" } else { "" }),
        &refs_c,
        shown,
        beds,
    )];
    if !orbit_branches.is_empty() {
        tables.extend(branches::tables(&orbit_branches, shown));
    }
    if !linear.is_empty() {
        let l: Vec<&Curve> = linear.iter().collect();
        tables.push(curves::table(
            "linear",
            &format!(
                "Exact linear compliance ({}) of the references drawn beside: bare structure, damper masses stuck",
                exp.excitation.per_unit()
            ),
            &l,
            shown,
            0,
        ));
    }
    // A simulated curve without one computed point (every point's setup failed) is a failed
    // check and a warning, never a page that passes with nothing on it.
    let skipped: Vec<String> = curves
        .iter()
        .filter(|c| !c.stop.is_empty() && c.stop.iter().all(|s| !s.is_empty()))
        .filter(|c| c.compliance.iter().all(|row| row.iter().all(|x| !x.is_finite())))
        .map(|c| format!("curve {}: no point of the sweep could be computed: {}", c.id, c.stop[0]))
        .collect();
    let mut out = Output { tables, figures, curves, exports, ..Output::default() };
    out.missing_cases(exp, skipped);
    out
}

/// The linear curves the plots ask for, on a fine grid over the sweep's range.
fn linear_refs(exp: &Experiment, freq_hz: &[f64]) -> Vec<Curve> {
    let (lo, hi) = (freq_hz[0], freq_hz[freq_hz.len() - 1]);
    let fine: Vec<f64> = (0..=2000).map(|i| lo + (hi - lo) * i as f64 / 2000.0).collect();
    let wanted: Vec<Linear> = exp.plots.iter().flat_map(|p| p.linear.iter().copied()).collect();
    let mut out = Vec::new();
    if wanted.contains(&Linear::Bare) {
        let bare = exp.cases.iter().find(|c| c.beds.is_empty()).cloned().unwrap_or_else(crate::experiment::Case::bare);
        out.push(curves::linear(
            exp,
            &bare,
            CurveId::linear(&bare.id, Linear::Bare),
            "no damper (linear)",
            &fine,
            false,
        ));
    }
    if wanted.contains(&Linear::Stuck) {
        for case in exp.cases.iter().filter(|c| !c.beds.is_empty()) {
            out.push(curves::linear(
                exp,
                case,
                CurveId::linear(&case.id, Linear::Stuck),
                &format!("{}, masses stuck (linear)", case.label),
                &fine,
                true,
            ));
        }
    }
    out
}

/// Marked frequencies (offsets from a case's resonance peak) and the values exported:
/// `peak_hz_CASE`, `peak_CASE_mR` (m/N) and `mark_LABEL_hz`.
fn marks(exp: &Experiment, curves: &[Curve]) -> (Vec<VLine>, BTreeMap<String, f64>) {
    let mut exports = BTreeMap::new();
    for c in curves {
        for m in 0..exp.structure.dof() {
            if let Some((f, v)) = c.peak(m) {
                exports.insert(format!("peak_{}_m{}", c.id, m + 1), v);
                exports.insert(format!("peak_hz_{}_m{}", c.id, m + 1), f);
            }
        }
    }
    let mut lines = Vec::new();
    for p in &exp.plots {
        let Some(rel) = &p.marks_relative_to else { continue };
        let Some(curve) = curves.iter().find(|c| c.id == CurveId::whole(rel)) else { continue };
        let mass = p.masses.first().copied().unwrap_or(0);
        let Some((peak, _)) = curve.peak(mass) else { continue };
        for (label, off) in &p.marks {
            let f = round_hz(peak + off);
            exports.insert(format!("mark_{label}_hz"), f);
            lines.push(VLine { x: f, label: format!(" {label}: {} Hz", fmt_num(f)) });
        }
    }
    (lines, exports)
}

/// On moving supports: the first storey's drift and the top floor's absolute acceleration
/// against frequency, per curve (and the exact linear references): what an engineer checks
/// on a building shaken at its base. `None` under a force or when nothing was computed.
fn drift_figure(
    exp: &Experiment,
    curves: &[&Curve],
    linear: &[Curve],
    band: (f64, f64),
) -> Option<crate::figure::Figure> {
    use crate::figure::{Dash, Figure, Panel, Series};
    if !exp.excitation.supports {
        return None;
    }
    let storeys = curves.iter().flat_map(|c| c.drift.iter().map(Vec::len)).max().unwrap_or(0);
    let floors = curves.iter().flat_map(|c| c.acceleration.iter().map(Vec::len)).max().unwrap_or(0);
    if floors == 0 {
        return None;
    }
    let a = exp.excitation.symbol();
    let at = |v: &Vec<Vec<f64>>, r: usize| v.iter().map(|p| p.get(r).copied().unwrap_or(f64::NAN)).collect::<Vec<_>>();
    let mut panels = Vec::new();
    let mut wanted: Vec<(String, String, bool, usize)> = Vec::new();
    if storeys > 0 {
        wanted.push(("the first storey's drift".into(), format!("drift amplitude / {a} (s^2)"), true, 0));
    }
    wanted.push((
        format!("the top floor's (coordinate {floors}) absolute acceleration"),
        format!("absolute acceleration amplitude / {a}"),
        false,
        floors - 1,
    ));
    for (title, y_label, drift, r) in wanted {
        let mut panel = Panel::new(title, "forcing frequency (Hz)", y_label, band);
        let pick = |c: &Curve| if drift { at(&c.drift, r) } else { at(&c.acceleration, r) };
        for (k, c) in curves.iter().enumerate() {
            let mut s = Series::line(c.label.clone(), c.freq_hz.clone(), pick(c), k);
            if c.converged.iter().any(|&v| !v) {
                s.marker = crate::figure::Marker::Circle;
            }
            panel.series.push(s);
        }
        for (k, c) in linear.iter().enumerate() {
            panel
                .series
                .push(Series::line(c.label.clone(), c.freq_hz.clone(), pick(c), curves.len() + k).dashed(Dash::Dashed));
        }
        panels.push(panel);
    }
    Some(Figure {
        id: "drift_acceleration".into(),
        title: format!("{}: storey drift and floor acceleration", exp.meta.figure),
        caption: format!(
            "On moving supports an engineer checks the storeys' drift and the floors' absolute acceleration besides the displacements: the first storey's drift amplitude and the top floor's absolute acceleration amplitude per unit ground acceleration {a}, each curve of the sweep (found exactly between events, as the displacements are; a curve with points that did not settle has circles: there the largest over the measured record) and the exact linear references dashed. The accelerations are those between impacts: an impact is instantaneous in the model (a velocity jump, an impulse no finite acceleration stands for): each impact's velocity jump sets the floors' higher modes going, which shows in the acceleration more than in the drift. Every storey and floor is in the compliance table (drift1.., acc1..)."
        ),
        panels,
    })
}
