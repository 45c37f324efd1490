//! Tables and figures of SDOF periodic analyses (Fig. 9): the branches with stable parts solid
//! and unstable parts dashed, the simulation as points, the linear curves beside, and the
//! phases of the SDOF solution in a panel below (the paper's right-hand axis).

use crate::checks::fmt_num;
use crate::experiment::{CurveId, Experiment, PlotKind};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series, VLine};
use crate::model::modal::ModeSummary;
use crate::sim::orbits::continuation::Special;
use crate::table::Table;

use super::curves::{self, Curve};
use super::evidence::{OrbitBranch, OrbitPoint, OrbitsResult};

/// A quantity read off an orbit point.
type Value<'a> = dyn Fn(&OrbitPoint) -> f64 + 'a;

fn opt(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

/// One table per branch.
fn branch_table(b: &OrbitBranch, n: usize) -> Table {
    let seg: Vec<i64> =
        b.segments.iter().enumerate().flat_map(|(k, s)| std::iter::repeat_n(k as i64 + 1, s.len())).collect();
    let p: Vec<&OrbitPoint> = b.points().collect();
    let mut t = Table::new(
        format!("{}_branch", b.id),
        format!(
            "Periodic orbits of the {} in branch order, per continued segment: frequency (Hz), compliance of each mass (m/N), impact phase phi and tau0 (lift-off), tau1 (top impact), tau2 (top release) in rad of forcing phase from the bottom impact, motion type, stability, whether the event sequence held across the difference steps (smooth), the largest multiplier modulus and all multipliers",
            b.label
        ),
    )
    .i64("segment", seg)
    .f64("freq_hz", p.iter().map(|x| x.freq_hz).collect());
    for r in 0..n {
        t = t.f64(format!("c{}", r + 1), p.iter().map(|x| x.compliance[r]).collect());
    }
    t.f64("phi", p.iter().map(|x| x.phi).collect())
        .f64("tau0", p.iter().map(|x| opt(x.tau0)).collect())
        .f64("tau1", p.iter().map(|x| opt(x.tau1)).collect())
        .f64("tau2", p.iter().map(|x| opt(x.tau2)).collect())
        .str("type", p.iter().map(|x| x.kind.clone()).collect())
        .i64("stable", p.iter().map(|x| x.stable as i64).collect())
        .i64("smooth", p.iter().map(|x| x.smooth as i64).collect())
        .f64("max_multiplier", p.iter().map(|x| x.multipliers.iter().map(|z| z.norm()).fold(0.0, f64::max)).collect())
        .str(
            "multipliers",
            p.iter()
                .map(|x| {
                    x.multipliers.iter().map(|z| format!("{:.6}{:+.6}i", z.re, z.im)).collect::<Vec<_>>().join(" ")
                })
                .collect(),
        )
}

/// The tables of an SDOF periodic analysis.
pub fn tables(exp: &Experiment, modes: &[ModeSummary], r: &OrbitsResult) -> Vec<Table> {
    let n = exp.structure.dof();
    let reference = modes[r.mode].reference_mass;
    let mut out = Vec::new();
    if !r.clearance_rows.is_empty() {
        let rows = &r.clearance_rows;
        out.push(
            Table::new(
                "clearance_choice",
                format!(
                    "SDOF model of mode {} per candidate clearance (mm): peak compliance of m{} on the stable branch (m/N), its frequency (Hz), the motion types of the stable orbits within the resonance (compliance at least 1/sqrt(2) of the peak), and whether that is Type II alone",
                    r.mode + 1,
                    reference + 1
                ),
            )
            .f64("clearance_mm", rows.iter().map(|x| x.clearance_mm).collect())
            .f64("peak", rows.iter().map(|x| x.peak.map_or(f64::NAN, |p| p.1)).collect())
            .f64("peak_hz", rows.iter().map(|x| x.peak.map_or(f64::NAN, |p| p.0)).collect())
            .str("types_in_resonance", rows.iter().map(|x| x.kinds.join("; ")).collect())
            .i64("only_type_ii", rows.iter().map(|x| x.only_type_ii as i64).collect())
            .i64(
                "chosen",
                rows.iter().map(|x| (x.clearance_mm == r.case.beds[0].damper.clearance.mm()) as i64).collect(),
            ),
        );
    }
    out.push(branch_table(&r.sdof, n));
    out.push(branch_table(&r.exact, n));
    out.push(curves::table(
        "simulation",
        "Steady-state compliance (m/N) of the 3-mass structure with the damper, simulated from rest at each frequency, as in sweeps",
        &[&r.simulation],
        n,
        1,
    ));
    let specials: Vec<(&str, &Special)> =
        r.sdof.special.iter().map(|s| ("sdof", s)).chain(r.exact.special.iter().map(|s| ("exact", s))).collect();
    out.push(
        Table::new(
            "special_points",
            "Folds (saddle-nodes), turns at a graze (non-smooth, between two branch points: the outer one) and period doublings located on each branch, frequency in Hz",
        )
        .str("branch", specials.iter().map(|(b, _)| b.to_string()).collect())
        .str("kind", specials.iter().map(|(_, s)| s.name().to_string()).collect())
        .f64("freq_hz", specials.iter().map(|(_, s)| s.p()).collect()),
    );
    // The SDOF approximation against the exact orbits and the simulation.
    let rows: Vec<(&str, Option<(f64, f64)>)> = vec![
        ("equivalent SDOF (stable orbits)", r.sdof.peak(reference)),
        ("exact orbits of the 3-mass structure (stable)", r.exact.peak(reference)),
        ("simulation of the 3-mass structure (settled points)", r.simulation.refined_peak(reference)),
    ];
    let exact = r.exact.peak(reference);
    out.push(
        Table::new(
            "comparison",
            format!(
                "Peak compliance of m{} (m/N) and its frequency (Hz) by each method, and the differences from the exact orbits (relative for the peak, in Hz for the frequency)",
                reference + 1
            ),
        )
        .str("method", rows.iter().map(|x| x.0.to_string()).collect())
        .f64("peak", rows.iter().map(|x| x.1.map_or(f64::NAN, |p| p.1)).collect())
        .f64("peak_hz", rows.iter().map(|x| x.1.map_or(f64::NAN, |p| p.0)).collect())
        .f64(
            "peak_rel_diff_vs_exact",
            rows.iter().map(|x| match (x.1, exact) {
                (Some(a), Some(e)) => (a.1 - e.1) / e.1,
                _ => f64::NAN,
            })
            .collect(),
        )
        .f64(
            "freq_diff_vs_exact_hz",
            rows.iter().map(|x| match (x.1, exact) {
                (Some(a), Some(e)) => a.0 - e.0,
                _ => f64::NAN,
            })
            .collect(),
        ),
    );
    out.push(
        Table::new(
            "orbit_vs_simulation",
            "At each simulated point that settled on a period-1 impacting motion: the exact orbit through its final state, the largest relative difference of the compliances, its stability and type",
        )
        .f64("freq_hz", r.checked.iter().map(|c| c.freq_hz).collect())
        .f64("rel_diff", r.checked.iter().map(|c| c.rel_diff).collect())
        .i64("stable", r.checked.iter().map(|c| c.stable as i64).collect())
        .str("note", r.checked.iter().map(|c| c.note.clone()).collect()),
    );
    out
}

/// Runs of consecutive points with the same stability: (stable, points).
fn runs(points: &[OrbitPoint]) -> Vec<(bool, Vec<&OrbitPoint>)> {
    let mut out: Vec<(bool, Vec<&OrbitPoint>)> = Vec::new();
    for p in points {
        match out.last_mut() {
            Some((s, run)) if *s == p.stable => run.push(p),
            _ => {
                // Overlap by one point so the drawn line is continuous.
                let mut run = out.last().and_then(|(_, r)| r.last().copied()).into_iter().collect::<Vec<_>>();
                run.push(p);
                out.push((p.stable, run));
            }
        }
    }
    out
}

/// A branch's value as stable (solid) and unstable (dashed) series; an angle (`wrap`) is
/// broken where it wraps around 2 pi.
fn branch_series(b: &OrbitBranch, label: &str, color: usize, wrap: bool, value: &Value<'_>) -> Vec<Series> {
    let mut out = Vec::new();
    let (mut s_done, mut u_done) = (false, false);
    for (stable, run) in b.segments.iter().flat_map(|seg| runs(seg)) {
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for p in &run {
            let y = value(p);
            if wrap && ys.last().is_some_and(|last: &f64| (y - last).abs() > std::f64::consts::PI) {
                xs.push(p.freq_hz);
                ys.push(f64::NAN);
            }
            xs.push(p.freq_hz);
            ys.push(y);
        }
        // A run along which the value is not defined (tau1 where the bed never reaches the
        // top) draws nothing: it takes no legend entry from a run that is drawn.
        if !ys.iter().any(|y| y.is_finite()) {
            continue;
        }
        let name = match (stable, s_done, u_done) {
            (true, false, _) => {
                s_done = true;
                format!("{label}, stable")
            }
            (false, _, false) => {
                u_done = true;
                format!("{label}, unstable")
            }
            _ => String::new(),
        };
        let s = Series::line(name, xs, ys, color);
        out.push(if stable { s } else { s.dashed(Dash::Dashed) });
    }
    out
}

/// The special points of a branch as markers on a value: folds as squares, period doublings
/// as triangles, at the branch point nearest in frequency.
fn special_markers(b: &OrbitBranch, tag: &str, color: usize, value: &Value<'_>) -> Vec<Series> {
    let at = |p: f64| {
        b.points().min_by(|a, c| (a.freq_hz - p).abs().total_cmp(&(c.freq_hz - p).abs())).map(|x| (p, value(x)))
    };
    let mut folds = (Vec::new(), Vec::new());
    let mut pds = (Vec::new(), Vec::new());
    for s in &b.special {
        let (list, p) = match s {
            Special::Fold { p } | Special::Grazing { p } => (&mut folds, *p),
            Special::PeriodDoubling { p } => (&mut pds, *p),
        };
        if let Some((x, y)) = at(p) {
            list.0.push(x);
            list.1.push(y);
        }
    }
    let mut out = Vec::new();
    if !folds.0.is_empty() {
        out.push(
            Series::points(format!("{tag}: folds and turns at a graze"), folds.0, folds.1, color, Marker::Square)
                .filled(),
        );
    }
    if !pds.0.is_empty() {
        out.push(Series::points(format!("{tag}: period doublings"), pds.0, pds.1, color, Marker::Triangle).filled());
    }
    out
}

/// The figures of an SDOF periodic analysis.
pub fn figures(exp: &Experiment, modes: &[ModeSummary], r: &OrbitsResult, freq_hz: &[f64]) -> Vec<Figure> {
    let reference = modes[r.mode].reference_mass;
    let band = (freq_hz[0], freq_hz[freq_hz.len() - 1]);
    let mut out = Vec::new();
    for p in &exp.plots {
        let title = p.title.clone().unwrap_or_else(|| format!("{}: {}", exp.meta.figure, exp.meta.title));
        let range = p.x_range.unwrap_or(band);
        match p.kind {
            PlotKind::Orbits => {
                let masses: Vec<usize> =
                    if p.masses.len() == exp.structure.dof() { vec![reference] } else { p.masses.clone() };
                let fine: Vec<f64> = (0..=1200).map(|i| range.0 + (range.1 - range.0) * i as f64 / 1200.0).collect();
                let bare_case = crate::experiment::Case::bare();
                let bare: Curve =
                    curves::linear(exp, &bare_case, CurveId::whole("bare"), "no damper (linear)", &fine, false);
                let stuck: Curve =
                    curves::linear(exp, &r.case, CurveId::whole("stuck"), "damper mass stuck (linear)", &fine, true);
                let mut panels = Vec::new();
                for &m in &masses {
                    panels.push(compliance_panel(&title, r, m, range, &fine, &bare, &stuck));
                }
                let mut phases = Panel::new(
                    "equivalent SDOF: impact phase and event times (the paper's right-hand axis)",
                    "frequency (Hz)",
                    "forcing phase from the bottom impact (rad)",
                    range,
                );
                phases.y_range = Some((0.0, 2.0 * std::f64::consts::PI));
                phases.legend = Corner::LowerRight;
                let quantities: [(&str, &Value<'_>); 4] = [
                    ("phi (force behind impact)", &|x| x.phi),
                    ("tau0 (lift-off from bottom)", &|x| opt(x.tau0)),
                    ("tau1 (impact on top)", &|x| opt(x.tau1)),
                    ("tau2 (release from top)", &|x| opt(x.tau2)),
                ];
                for (k, (name, f)) in quantities.iter().enumerate() {
                    if r.sdof.points().any(|x| f(x).is_finite()) {
                        phases.series.extend(branch_series(&r.sdof, name, 3 + k, true, *f));
                    }
                }
                panels.push(phases);
                let kinds: Vec<String> = {
                    let mut k: Vec<String> = r.sdof.points().filter(|x| x.stable).map(|x| x.kind.clone()).collect();
                    k.sort();
                    k.dedup();
                    k
                };
                out.push(Figure {
                    id: p.id.clone(),
                    title: title.clone(),
                    caption: format!(
                        "Mode {} with one damper on m{} (mu_{} = {:.4}, d = {} mm): periodic orbits of the equivalent SDOF model and of the exact 3-mass structure, stable solid and unstable dashed; circles: simulation of the 3-mass structure from rest; dotted: no damper; dash-dot: damper mass stuck; squares: folds, triangles: period doublings. Where no impacting orbit exists the bed rests and the SDOF solution is its linear response with the bed's mass added (thin blue, drawn where its acceleration stays below g). Below: phi, tau0, tau1, tau2 of the SDOF orbits in rad of forcing phase from the bottom impact. Stable SDOF motion types: {}.",
                        r.mode + 1,
                        r.case.beds[0].damper.host + 1,
                        r.mode + 1,
                        r.sdof_model.mode.mass_ratio,
                        fmt_num(r.case.beds[0].damper.clearance.mm()),
                        kinds.join(", ")
                    ),
                    panels,
                });
            }
            PlotKind::ClearanceChoice if !r.clearance_rows.is_empty() => {
                let rows = &r.clearance_rows;
                let xs: Vec<f64> = rows.iter().map(|x| x.clearance_mm).collect();
                let hi = xs.iter().copied().fold(0.0, f64::max) * 1.08;
                let mut panel = Panel::new(
                    title.clone(),
                    "clearance d (mm)",
                    format!("peak compliance of m{}, equivalent SDOF (m/N)", reference + 1),
                    (0.0, hi),
                );
                let pick = |ok: bool| -> (Vec<f64>, Vec<f64>) {
                    rows.iter()
                        .filter(|x| x.only_type_ii == ok)
                        .filter_map(|x| x.peak.map(|p| (x.clearance_mm, p.1)))
                        .unzip()
                };
                let all: (Vec<f64>, Vec<f64>) =
                    rows.iter().filter_map(|x| x.peak.map(|p| (x.clearance_mm, p.1))).unzip();
                panel.series.push(Series::line("", all.0, all.1, 7));
                let (x, y) = pick(true);
                panel
                    .series
                    .push(Series::points("only Type II within the resonance", x, y, 2, Marker::Circle).filled());
                let (x, y) = pick(false);
                panel.series.push(Series::points("other types within the resonance", x, y, 1, Marker::Cross));
                panel.vlines.push(VLine {
                    x: r.case.beds[0].damper.clearance.mm(),
                    label: format!(" chosen: {}", r.case.beds[0].damper.clearance),
                });
                out.push(Figure {
                    id: p.id.clone(),
                    title: title.clone(),
                    caption: r.clearance_note.clone(),
                    panels: vec![panel],
                });
            }
            _ => {}
        }
    }
    out
}

/// The compliance of mass `m` in `range`: the SDOF's and the exact orbits (stable solid,
/// unstable dashed), the simulation from rest, the bare and stuck linear curves, the folds and
/// doublings.
fn compliance_panel(
    title: &str,
    r: &OrbitsResult,
    m: usize,
    range: (f64, f64),
    fine: &[f64],
    bare: &Curve,
    stuck: &Curve,
) -> Panel {
    let mut panel = Panel::new(
        format!("{title}: compliance of m{}", m + 1),
        "frequency (Hz)",
        format!("compliance of m{} (m/N)", m + 1),
        range,
    );
    // Where the beds rest all the time, the SDOF solution is its linear response
    // with the bed's mass added (valid while the acceleration stays below g).
    let (xs, ys) = resting_sdof(r, fine, m);
    panel.series.push(Series::line("equivalent SDOF, bed resting (linear)", xs, ys, 0));
    panel.series.extend(branch_series(&r.sdof, "equivalent SDOF", 0, false, &|x| x.compliance[m]));
    panel.series.extend(branch_series(&r.exact, "exact 3-mass orbit", 1, false, &|x| x.compliance[m]));
    let sim = &r.simulation;
    let (reg, irr): (Vec<usize>, Vec<usize>) = (0..sim.freq_hz.len()).partition(|&i| sim.regular(i));
    panel.series.push(Series::points(
        "3-mass simulation",
        reg.iter().map(|&i| sim.freq_hz[i]).collect(),
        reg.iter().map(|&i| sim.compliance[i][m]).collect(),
        2,
        Marker::Circle,
    ));
    if !irr.is_empty() {
        panel.series.push(Series::points(
            "simulation, not settled or not period-1",
            irr.iter().map(|&i| sim.freq_hz[i]).collect(),
            irr.iter().map(|&i| sim.compliance[i][m]).collect(),
            2,
            Marker::Cross,
        ));
    }
    panel.series.push(
        Series::line(bare.label.clone(), fine.to_vec(), bare.compliance.iter().map(|c| c[m]).collect(), 7)
            .dashed(Dash::Dotted),
    );
    panel.series.push(
        Series::line(stuck.label.clone(), fine.to_vec(), stuck.compliance.iter().map(|c| c[m]).collect(), 7)
            .dashed(Dash::DashDot),
    );
    panel.series.extend(special_markers(&r.sdof, "SDOF", 0, &|x| x.compliance[m]));
    panel.series.extend(special_markers(&r.exact, "exact", 1, &|x| x.compliance[m]));
    panel
}

/// The SDOF model's linear response with its bed resting, where the bed never lifts off
/// (acceleration amplitude below g); NaN elsewhere, so the line breaks there.
fn resting_sdof(r: &OrbitsResult, freq_hz: &[f64], mass: usize) -> (Vec<f64>, Vec<f64>) {
    let e = &r.sdof_model;
    let m = &e.mode;
    let ys = freq_hz
        .iter()
        .map(|f| {
            let w = 2.0 * std::f64::consts::PI * f;
            let dyn_k = num_complex::Complex64::new(
                m.modal_stiffness - w * w * (m.modal_mass + e.damper_mass),
                w * m.modal_damping,
            );
            let q = e.force.abs() / dyn_k.norm();
            if w * w * q < crate::model::GRAVITY {
                e.shape(mass).abs() * q / r.force
            } else {
                f64::NAN
            }
        })
        .collect();
    (freq_hz.to_vec(), ys)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(freq_hz: f64, stable: bool, tau1: Option<f64>) -> OrbitPoint {
        OrbitPoint {
            freq_hz,
            compliance: vec![1e-4],
            phi: 1.0,
            tau0: Some(0.5),
            tau1,
            tau2: tau1,
            kind: "II".into(),
            stable,
            smooth: true,
            multipliers: Vec::new(),
        }
    }

    /// A stable run along which tau1 is not defined (no top impact) is not drawn and leaves
    /// the legend's "stable" entry to the stable run that is.
    #[test]
    fn an_undrawn_run_takes_no_legend_entry() {
        let seg = vec![
            point(44.0, true, None),
            point(44.5, true, None),
            point(45.0, false, Some(4.6)),
            point(45.5, false, Some(4.6)),
            point(46.0, true, Some(4.5)),
            point(46.5, true, Some(4.5)),
        ];
        let b = OrbitBranch { segments: vec![seg], ..OrbitBranch::default() };
        let tau1 = |p: &OrbitPoint| p.tau1.unwrap_or(f64::NAN);
        let series = branch_series(&b, "tau1", 5, true, &tau1);
        let drawn: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(series.len(), 2, "{drawn:?}");
        assert!(drawn.contains(&"tau1, stable") && drawn.contains(&"tau1, unstable"), "{drawn:?}");
        assert!(series.iter().all(|s| s.y.iter().any(|y| y.is_finite())));
    }
}
