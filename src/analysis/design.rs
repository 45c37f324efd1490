//! Analysis kind "design" (docs/design.md): the design search of `[design]` on the
//! experiment's structure, the experiment's cases as reference layouts, how the objective
//! varies with the clearance near the optimum, and the Pareto front of shot mass against the
//! objective. Tables and figures only; the search itself is `crate::design`.

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::design::search::{optimise, placements, Found, Space};
use crate::design::{band_compliance, bare, evaluate, Evaluation, Layout, Problem, Scenario, Spec};
use crate::experiment::Experiment;
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series, VLine};
use crate::model::{Damping, Structure};
use crate::number::fmt_num;
use crate::sim::{SteadyOptions, System};
use crate::table::Table;

/// Clearances of the profile around the best layout.
const PROFILE_POINTS: usize = 25;

/// A clearance is in the robust band when its objective is within this factor of the best.
pub const ROBUST: f64 = 1.05;

/// What a design run hands over.
pub struct DesignOutput {
    pub tables: Vec<Table>,
    pub figures: Vec<Figure>,
    pub exports: BTreeMap<String, f64>,
}

/// The design problem of an experiment, with its scenarios (every combination of the
/// damping ratios and forces of `[design.scenarios]`, the experiment's own value where a list
/// is not given).
pub fn problem(exp: &Experiment, spec: &Spec, steady: &SteadyOptions) -> Problem {
    let s = &exp.structure;
    let mut scenarios = Vec::new();
    if !(spec.scenario_damping.is_empty() && spec.scenario_force_n.is_empty()) {
        let dampings: Vec<Option<f64>> = if spec.scenario_damping.is_empty() {
            vec![None]
        } else {
            spec.scenario_damping.iter().map(|z| Some(*z)).collect()
        };
        let forces: Vec<f64> =
            if spec.scenario_force_n.is_empty() { vec![exp.excitation.force] } else { spec.scenario_force_n.clone() };
        for z in &dampings {
            for &f in &forces {
                let (structure, zname) = match z {
                    Some(z) => (
                        Structure::from_matrices(
                            &s.masses,
                            s.stiffness.clone(),
                            Damping::ModalRatios(vec![*z; s.dof()]),
                        ),
                        format!("damping {}", fmt_num(*z)),
                    ),
                    None => (s.clone(), "damping as the model".to_string()),
                };
                scenarios.push(Scenario { name: format!("{zname}, F {} N", fmt_num(f)), structure, force: f });
            }
        }
    }
    Problem {
        structure: s.clone(),
        driven: exp.excitation.mass,
        force: exp.excitation.force,
        bands: spec.bands.clone(),
        measure: spec.measure,
        sweeps: spec.sweeps.clone(),
        steady: *steady,
        scenarios,
        combine: spec.combine,
    }
}

fn hosts_words(l: &Layout) -> String {
    l.hosts.iter().map(|h| format!("m{}", h + 1)).collect::<Vec<_>>().join(" ")
}

fn joined(v: &[f64]) -> String {
    v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(" / ")
}

/// A table of layouts with their evaluations.
fn layouts_table(
    name: &str,
    description: &str,
    spec: &Spec,
    scenarios: &[String],
    rows: &[(String, Layout, Evaluation, u64)],
) -> Table {
    let at_edge = |e: &Evaluation| {
        let f = &spec.bands[e.worst.0].freq_hz;
        e.worst.1 == f[0] || e.worst.1 == f[f.len() - 1]
    };
    let edges = rows.iter().filter(|r| at_edge(&r.2)).count();
    let description = if edges > 0 {
        format!(
            "{description}. CAUTION: in {edges} row(s) the largest compliance lies at a band's first or last frequency (worst_at_band_edge = 1): the damped resonance has moved to the edge, and the band, not the dampers, limits that objective; widen the band"
        )
    } else {
        description.to_string()
    };
    let mut t = Table::new(name, description)
        .str("layout", rows.iter().map(|r| r.0.clone()).collect())
        .str("hosts", rows.iter().map(|r| hosts_words(&r.1)).collect())
        .f64("shot_kg", rows.iter().map(|r| r.1.shot_kg()).collect())
        .str("bed_kg", rows.iter().map(|r| joined(&r.1.masses_kg)).collect())
        .str("clearance_mm", rows.iter().map(|r| joined(&r.1.clearances_mm)).collect())
        .f64("objective", rows.iter().map(|r| r.2.objective).collect());
    for (k, b) in spec.bands.iter().enumerate() {
        t = t.f64(format!("{} (m/N)", b.name), rows.iter().map(|r| r.2.bands[k]).collect());
    }
    t.str(
        "worst",
        rows.iter()
            .map(|r| format!("{} at {} Hz, m{}", spec.bands[r.2.worst.0].name, fmt_num(r.2.worst.1), r.2.worst.2 + 1))
            .collect(),
    )
    .i64("worst_at_band_edge", rows.iter().map(|r| i64::from(at_edge(&r.2))).collect())
    .str("scenario", rows.iter().map(|r| scenarios.get(r.2.worst_scenario).cloned().unwrap_or_default()).collect())
    .i64("unsettled_points", rows.iter().map(|r| r.2.unsettled as i64).collect())
    .i64("evaluations", rows.iter().map(|r| r.3 as i64).collect())
}

/// The layout of a case of the experiment (its dampers as they are).
fn case_layout(case: &crate::experiment::Case) -> Layout {
    Layout {
        hosts: case.dampers.iter().map(|d| d.host).collect(),
        masses_kg: case.dampers.iter().map(|d| d.mass).collect(),
        clearances_mm: case.dampers.iter().map(|d| d.clearance * 1e3).collect(),
    }
}

/// The placement with the lowest objective; of equal ones the first.
fn lowest(found: Vec<Found>) -> Option<Found> {
    found.into_iter().reduce(|a, x| if a.evaluation.objective <= x.evaluation.objective { a } else { x })
}

/// Runs the design of `exp`.
pub fn run(exp: &Experiment, spec: &Spec, steady: &SteadyOptions, tick: &(dyn Fn() + Sync)) -> DesignOutput {
    let p = problem(exp, spec, steady);
    let b = bare(&p);
    let names: Vec<String> = p.cases().iter().map(|c| c.name.clone()).collect();
    let space = Space {
        placements: placements(&spec.candidates, spec.max_beds),
        shot_kg: spec.shot_kg,
        clearance_mm: spec.clearance_mm,
        shared_clearance: spec.shared_clearance,
    };
    let found = optimise(&p, &b, &space, &spec.search);
    tick();
    let best = lowest(found.clone());
    let mut exports = BTreeMap::new();
    let total_mass = exp.structure.mass_matrix().trace();
    let mut tables = Vec::new();
    let rows: Vec<(String, Layout, Evaluation, u64)> =
        found.iter().map(|f| (hosts_words(&f.layout), f.layout.clone(), f.evaluation.clone(), f.evaluations)).collect();
    tables.push(layouts_table(
        "design_placements",
        &format!(
            "The best layout found for each placement of containers: {} kg of shot ({} of the structure's mass) split among them, clearances in {}-{} mm; objective: the worst band's measure over the bare structure's (1 = no gain)",
            fmt_num(spec.shot_kg),
            fmt_num(spec.shot_kg / total_mass),
            fmt_num(spec.clearance_mm.0),
            fmt_num(spec.clearance_mm.1)
        ),
        spec,
        &names,
        &rows,
    ));
    // The experiment's cases as reference layouts (the paper's, one container on the loop
    // point, ...), evaluated with the same objective.
    let case_rows: Vec<(String, Layout, Evaluation, u64)> = exp
        .cases
        .par_iter()
        .map(|c| {
            let l = case_layout(c);
            let e = evaluate(&p, &b, &l);
            (c.id.clone(), l, e, 1)
        })
        .collect();
    for (id, _, e, _) in &case_rows {
        exports.insert(format!("objective_{id}"), e.objective);
    }
    tables.push(layouts_table(
        "design_cases",
        "The experiment's cases as reference layouts, with the same objective",
        spec,
        &names,
        &case_rows,
    ));
    let mut figures = Vec::new();
    if let Some(best) = &best {
        exports.insert("best_objective".into(), best.evaluation.objective);
        if spec.shared_clearance {
            exports.insert("best_clearance_mm".into(), best.layout.clearances_mm[0]);
        }
        // How the objective varies with the clearance, the best hosts and split held.
        let (lo, hi) = spec.clearance_mm;
        let ds: Vec<f64> =
            (0..PROFILE_POINTS).map(|i| lo * (hi / lo).powf(i as f64 / (PROFILE_POINTS - 1) as f64)).collect();
        let profile: Vec<f64> = ds
            .par_iter()
            .map(|&d| {
                let l = Layout { clearances_mm: vec![d; best.layout.hosts.len()], ..best.layout.clone() };
                evaluate(&p, &b, &l).objective
            })
            .collect();
        let target = ROBUST * best.evaluation.objective;
        let inside: Vec<f64> = ds.iter().zip(&profile).filter(|(_, o)| **o <= target).map(|(d, _)| *d).collect();
        let (rlo, rhi) = (
            inside.iter().copied().fold(f64::INFINITY, f64::min),
            inside.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
        if rlo.is_finite() {
            exports.insert("robust_clearance_min_mm".into(), rlo);
            exports.insert("robust_clearance_max_mm".into(), rhi);
        }
        tables.push(
            Table::new(
                "design_clearance",
                format!(
                    "The objective of the best layout ({}, bed kg {}) with one clearance for every container, from {} to {} mm: the robust band is where it is within {} % of the best",
                    hosts_words(&best.layout),
                    joined(&best.layout.masses_kg),
                    fmt_num(lo),
                    fmt_num(hi),
                    fmt_num(100.0 * (ROBUST - 1.0))
                ),
            )
            .f64("clearance_mm", ds.clone())
            .f64("objective", profile.clone())
            .i64("robust", profile.iter().map(|o| i64::from(*o <= target)).collect()),
        );
        let mut panel = Panel::new(
            "objective against the clearance, best hosts and split held",
            "clearance d (mm)",
            "worst band over the bare structure",
            (lo, hi),
        )
        .log_x();
        let mut s = Series::line(hosts_words(&best.layout), ds.clone(), profile.clone(), 0);
        s.marker = Marker::Circle;
        panel.series.push(s);
        panel
            .series
            .push(Series::line(format!("best x {ROBUST}"), vec![lo, hi], vec![target, target], 1).dashed(Dash::Dashed));
        if rlo.is_finite() {
            panel.vlines.push(VLine { x: rlo, label: format!(" robust band {}-{} mm", fmt_num(rlo), fmt_num(rhi)) });
            panel.vlines.push(VLine { x: rhi, label: String::new() });
        }
        panel.legend = Corner::UpperRight;
        figures.push(Figure {
            id: "design_clearance".into(),
            title: format!("{}: the objective near the optimum", exp.meta.figure),
            caption: "The worst band's measure over the bare structure's against one clearance for every container, with the best layout's hosts and shot split; dashed: 5 % above the best (the robust band).".into(),
            panels: vec![panel],
        });
        figures.push(compliance_figure(exp, spec, &p, best, &case_rows));
    }
    if let Some((mode, candidates)) = &spec.sdof {
        let (table, sdof_exports) = sdof_method(exp, steady, &p, &b, &found, *mode, candidates, &names);
        tables.push(table);
        exports.extend(sdof_exports);
    }
    tick();
    if !spec.pareto_mass_ratios.is_empty() {
        let front: Vec<(f64, Found)> = spec
            .pareto_mass_ratios
            .iter()
            .filter_map(|&r| {
                let s = Space { shot_kg: r * total_mass, ..space.clone() };
                lowest(optimise(&p, &b, &s, &spec.search)).map(|f| (r, f))
            })
            .collect();
        let rows: Vec<(String, Layout, Evaluation, u64)> = front
            .iter()
            .map(|(r, f)| {
                (format!("mass ratio {}", fmt_num(*r)), f.layout.clone(), f.evaluation.clone(), f.evaluations)
            })
            .collect();
        tables.push(layouts_table(
            "design_pareto",
            "The best layout for each total shot mass ratio (the Pareto front of shot mass against the objective)",
            spec,
            &names,
            &rows,
        ));
        let x: Vec<f64> = front.iter().map(|(r, _)| *r).collect();
        let y: Vec<f64> = front.iter().map(|(_, f)| f.evaluation.objective).collect();
        let mut panel = Panel::new(
            "best objective against the shot budget",
            "total shot mass / structure mass",
            "worst band over the bare structure",
            (x[0], x[x.len() - 1]),
        );
        let mut s = Series::line("best layout", x, y, 0);
        s.marker = Marker::Circle;
        panel.series.push(s);
        figures.push(Figure {
            id: "design_pareto".into(),
            title: format!("{}: shot mass against the objective", exp.meta.figure),
            caption: "The best objective found for each total shot mass ratio (every placement, split and clearance searched again for each). Where the table's worst_at_band_edge is 1 the damped resonance has moved to the band's edge (more shot lowers it): that point is limited by the band, not the dampers.".into(),
            panels: vec![panel],
        });
    }
    DesignOutput { tables, figures, exports }
}

/// The compliance over each band of the bare structure, the best layout and the cases (the
/// worst of the sweeps at each frequency), one panel per band.
fn compliance_figure(
    exp: &Experiment,
    spec: &Spec,
    p: &Problem,
    best: &Found,
    cases: &[(String, Layout, Evaluation, u64)],
) -> Figure {
    let mut layouts: Vec<(String, Layout)> =
        vec![("bare".into(), Layout { hosts: vec![], masses_kg: vec![], clearances_mm: vec![] })];
    layouts.push((format!("best: {}", hosts_words(&best.layout)), best.layout.clone()));
    layouts.extend(cases.iter().filter(|c| !c.1.hosts.is_empty()).map(|c| (format!("case {}", c.0), c.1.clone())));
    let panels = spec
        .bands
        .iter()
        .map(|band| {
            let mut panel = Panel::new(
                format!(
                    "{}: compliance of m{}",
                    band.name,
                    band.masses.iter().map(|m| (m + 1).to_string()).collect::<Vec<_>>().join(", m")
                ),
                "frequency (Hz)",
                "compliance (m/N)",
                (band.freq_hz[0], band.freq_hz[band.freq_hz.len() - 1]),
            )
            .log_y();
            for (k, (label, l)) in layouts.iter().enumerate() {
                let sys = System::plastic(p.structure.clone(), l.dampers(), p.driven, p.force);
                let (c, _) = band_compliance(&sys, band, &p.sweeps, &p.steady);
                for &m in &band.masses {
                    let y: Vec<f64> = c.iter().map(|r| r[m]).collect();
                    let name = if band.masses.len() > 1 { format!("{label}, m{}", m + 1) } else { label.clone() };
                    let s = Series::line(name, band.freq_hz.clone(), y, k);
                    panel.series.push(if k == 0 { s.dashed(Dash::Dashed) } else { s });
                }
            }
            panel
        })
        .collect();
    Figure {
        id: "design_compliance".into(),
        title: format!("{}: the best layout against the bare structure and the cases", exp.meta.figure),
        caption: "Compliance over each band: the largest over the sweeps at each frequency (where motions coexist the structure may sit on either).".into(),
        panels,
    }
}

/// The paper's technique as a design method: for each placement's best shot split, the
/// clearance the equivalent SDOF model of `mode` picks by the rule of Fig. 9 (the location
/// effect of Eq. 12-13 included), evaluated on the full structure beside the optimiser's.
#[allow(clippy::too_many_arguments)]
fn sdof_method(
    exp: &Experiment,
    steady: &SteadyOptions,
    p: &Problem,
    b: &[Vec<f64>],
    found: &[Found],
    mode: usize,
    candidates: &[f64],
    names: &[String],
) -> (Table, BTreeMap<String, f64>) {
    let modes = crate::model::modal::modal_summary(&exp.structure, &[]);
    let reference = modes[mode].reference_mass;
    let band = &p.bands[0].freq_hz;
    let rows: Vec<(String, f64, Evaluation, f64)> = found
        .iter()
        .map(|f| {
            let choice =
                super::orbits::sdof_choice(exp, &f.layout.dampers(), mode, reference, band, candidates, steady, &|| {});
            let l = Layout { clearances_mm: vec![choice.clearance_mm; f.layout.hosts.len()], ..f.layout.clone() };
            let e = evaluate(p, b, &l);
            (hosts_words(&f.layout), choice.clearance_mm, e, f.evaluation.objective)
        })
        .collect();
    let mut exports = BTreeMap::new();
    if let Some(best) = rows.iter().min_by(|x, y| x.3.total_cmp(&y.3)) {
        exports.insert("sdof_clearance_mm".into(), best.1);
        exports.insert("sdof_objective".into(), best.2.objective);
    }
    let table = Table::new(
        "design_sdof",
        format!(
            "The paper's SDOF technique as a design method: for each placement and its best shot split, the clearance the equivalent SDOF model of mode {} picks by the rule of Fig. 9 (Type II alone within the resonance, the lowest SDOF peak; candidates {} mm; the SDOF model over the first band), evaluated on the full structure beside the optimiser's",
            mode + 1,
            joined(candidates)
        ),
    )
    .str("layout", rows.iter().map(|r| r.0.clone()).collect())
    .f64("sdof_clearance_mm", rows.iter().map(|r| r.1).collect())
    .f64("objective_sdof", rows.iter().map(|r| r.2.objective).collect())
    .f64("objective_optimiser", rows.iter().map(|r| r.3).collect())
    .f64("left_on_the_table", rows.iter().map(|r| r.2.objective / r.3 - 1.0).collect())
    .str("scenario", rows.iter().map(|r| names.get(r.2.worst_scenario).cloned().unwrap_or_default()).collect())
    .i64("unsettled_points", rows.iter().map(|r| r.2.unsettled as i64).collect());
    (table, exports)
}
