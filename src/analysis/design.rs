//! Analysis kind "design" (docs/design.md): the design search of `[design]` on the
//! experiment's structure, the experiment's cases as reference layouts, how the objective
//! varies with the clearance near the optimum, and the Pareto front of shot mass against the
//! objective. Tables and figures only; the search itself is `crate::design`.

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::checks::reference::ReferenceStore;
use crate::design::search::{self, Found};
use crate::design::{band_compliance, bare, evaluate, Evaluation, Layout, Problem, Spec, PROFILE_POINTS};
use crate::experiment::Experiment;
use crate::figure::{Figure, Marker, Panel, Series};
use crate::number::fmt_num;
use crate::sim::settle::statistic::Motion as Class;
use crate::sim::SteadyOptions;
use crate::table::Table;

pub use super::design_best::ROBUST;
use super::design_best::{clearance_profile, joined, objective_axis, BestIn, Page};
use super::kind::{Input, Kind, Output};

use super::design_compliance::compliance_figure;
pub use super::design_problem::{problem, screen};
use super::design_search::{searched, stored};
pub use super::design_search::{REPLAY_TOL, REPLAY_TOL_UNSETTLED};
use crate::design::search::lowest;

/// A design search (`kind = "design"`, docs/design.md): the problem as the file states it and
/// the steady-state settings of its sweeps.
pub(crate) struct Design<'a> {
    pub(crate) spec: &'a Spec,
    pub(crate) steady: &'a SteadyOptions,
}

impl Kind for Design<'_> {
    // A search's evaluations are not known ahead: a counter of unknown total, ticked at every
    // evaluation (a caller may stop there): the default `work`.
    fn run(&self, i: &Input<'_>) -> Output {
        run(i.exp, self.spec, self.steady, i.refs, i.tick)
    }
}

/// A table of layouts with their evaluations.
fn layouts_table(
    (name, unit): (&str, &str),
    description: &str,
    spec: &Spec,
    scenarios: &[String],
    rows: &[(String, Layout, Evaluation, u64)],
) -> Table {
    // Against records there are no bands, and no band edge.
    let at_edge = |e: &Evaluation| {
        spec.bands
            .get(e.worst.0)
            .is_some_and(|b| e.worst.1 == b.freq_hz[0] || e.worst.1 == b.freq_hz[b.freq_hz.len() - 1])
    };
    let edges = rows.iter().filter(|r| at_edge(&r.2)).count();
    // The row with the lowest objective, whose interval the others' are compared with.
    let lowest =
        rows.iter().map(|r| &r.2).filter(|e| !e.objective.is_nan()).min_by(|x, y| x.objective.total_cmp(&y.objective));
    let description = if edges > 0 {
        format!(
            "{description}. CAUTION: in {edges} row(s) the largest compliance lies at a band's first or last frequency (worst_at_band_edge = 1): the damped resonance has moved to the edge, and the band, not the dampers, limits that objective; widen the band"
        )
    } else {
        description.to_string()
    };
    let description = format!(
        "{description}. measured_points: steady states with no certified orbit, measured as irregular motion (chaotic_points of them chaotic; unclassified_points of them measured over too short a record to tell chaos from a torus or a transient; screened_points of them over a {}-period screen only: their widened interval lies below their band's highest point's, so they cannot set a peak measure, docs/design.md); objective_half_width: the half-width of the objective's 95 % interval from the measured points it rests on (0: every one a certified orbit; NaN: one was measured too briefly for its batches, so its interval is not known); equal_to_lowest_within_intervals: 1 where the row's interval overlaps the lowest objective's (an interval not known counts as its objective alone)",
        crate::design::race::SCREEN
    );
    let mut t = Table::new(name, description)
        .str("layout", rows.iter().map(|r| r.0.clone()).collect())
        .str("hosts", rows.iter().map(|r| r.1.hosts_words()).collect())
        .f64("shot_kg", rows.iter().map(|r| r.1.shot_kg()).collect())
        .str("bed_kg", rows.iter().map(|r| joined(&r.1.masses_kg)).collect())
        .str("clearance_mm", rows.iter().map(|r| joined(&r.1.clearances_mm)).collect())
        .f64("objective", rows.iter().map(|r| r.2.objective).collect());
    // A column per band (per record against records), and where the worst is.
    let (columns, worst): (Vec<String>, Vec<String>) = match &spec.suite {
        None => (
            spec.bands.iter().map(|b| format!("{} ({unit})", b.name)).collect(),
            rows.iter()
                .map(|r| {
                    format!("{} at {} Hz, m{}", spec.bands[r.2.worst.0].name, fmt_num(r.2.worst.1), r.2.worst.2 + 1)
                })
                .collect(),
        ),
        Some(suite) => {
            let (unit, place) = match suite.response {
                crate::design::seismic::Response::Drift => ("m", "storey"),
                crate::design::seismic::Response::Acceleration => ("m/s^2", "floor"),
            };
            (
                suite.records.iter().map(|r| format!("{} ({unit})", r.name)).collect(),
                rows.iter()
                    .map(|r| {
                        let name = suite.records.get(r.2.worst.0).map_or("", |x| x.name.as_str());
                        format!("{name}, {place} {}", r.2.worst.2 + 1)
                    })
                    .collect(),
            )
        }
    };
    for (k, name) in columns.into_iter().enumerate() {
        t = t.f64(name, rows.iter().map(|r| r.2.bands.get(k).copied().unwrap_or(f64::NAN)).collect());
    }
    t.str("worst", worst)
        .i64("worst_at_band_edge", rows.iter().map(|r| i64::from(at_edge(&r.2))).collect())
        .str("scenario", rows.iter().map(|r| scenarios.get(r.2.worst_scenario).cloned().unwrap_or_default()).collect())
        .i64("unsettled_points", rows.iter().map(|r| r.2.unsettled as i64).collect())
        .i64("measured_points", rows.iter().map(|r| r.2.measured() as i64).collect())
        .i64("chaotic_points", rows.iter().map(|r| r.2.classes[Class::Chaotic.index()] as i64).collect())
        .i64("unclassified_points", rows.iter().map(|r| r.2.classes[Class::Unclassified.index()] as i64).collect())
        .i64("screened_points", rows.iter().map(|r| r.2.screened as i64).collect())
        .f64("objective_half_width", rows.iter().map(|r| r.2.half_width).collect())
        .i64(
            "equal_to_lowest_within_intervals",
            rows.iter().map(|r| i64::from(lowest.is_some_and(|l| l.overlaps(&r.2)))).collect(),
        )
        .i64("evaluations", rows.iter().map(|r| r.3 as i64).collect())
}

/// What a stopped search's answer is, in a sentence or two: why it stopped (`why`), how far
/// each placement's search got (from the placements table's `converged` and `evaluations`),
/// and so what the layout that follows is.
fn stop_words(why: &str, found: &[Found]) -> String {
    let converged = found.iter().filter(|f| f.ended == Some(search::Ended::Converged)).count();
    let others: Vec<u64> =
        found.iter().filter(|f| f.ended != Some(search::Ended::Converged)).map(|f| f.evaluations).collect();
    let unjudged = found.iter().filter(|f| !f.judged).count();
    let unjudged = match unjudged {
        0 => String::new(),
        k => format!(
            " on the searched model; {k} of them were not judged on the file's model before the search stopped (their objective is blank and they are not ranked)"
        ),
    };
    match (others.iter().min(), others.iter().max()) {
        (Some(lo), Some(hi)) => format!(
            "Not a converged answer: {why}; {converged} of the {} placements were searched to convergence, the other {} stopped after {} evaluations (the placements table's converged and evaluations){unjudged}; what follows is the best layout found so far.",
            found.len(),
            others.len(),
            if lo == hi { lo.to_string() } else { format!("{lo}-{hi}") }
        ),
        _ => format!(
            "Not the whole answer: {why} after every one of the {} placements had been searched to convergence{unjudged}, so it stopped only what comes after the main search (the Pareto budgets' searches, the maps near the optimum) and the answer is not stored; what follows is the main search's best layout.",
            found.len()
        ),
    }
}

/// The placements table's column `converged`: whether each placement's search converged (every
/// start's simplex agreed to its tolerance), spent its iterations, or was stopped; blank
/// where the placement was not searched here (a stored answer replayed).
fn with_converged(found: &[Found], t: &mut Table) {
    t.description += "; converged: whether the placement's search converged (\"yes\": every start's simplex agreed to its tolerance), spent its iterations or was stopped (time limit or interrupt), blank for a stored answer replayed; evaluations: the layouts its search evaluated";
    t.columns.push((
        "converged".into(),
        crate::table::ColumnData::Str(found.iter().map(|f| f.ended.map_or("", |e| e.word()).to_string()).collect()),
    ));
}

/// The layout of a case of the experiment (its dampers as they are).
fn case_layout(case: &crate::experiment::Case) -> Layout {
    Layout {
        hosts: case.beds.iter().map(|b| &b.damper).map(|d| d.host).collect(),
        masses_kg: case.beds.iter().map(|b| &b.damper).map(|d| d.mass).collect(),
        clearances_mm: case.beds.iter().map(|b| &b.damper).map(|d| d.clearance.mm()).collect(),
    }
}

/// Runs the design of `exp`: its tables, figures and exports, the replay's checks, the
/// warnings, the answer in a paragraph, and the answer to store (none when the time limit
/// stopped the search: the layouts are then the best found so far).
fn run(
    exp: &Experiment,
    spec: &Spec,
    steady: &SteadyOptions,
    refs: &ReferenceStore,
    tick: &(dyn Fn() + Sync),
) -> Output {
    let p = problem(exp, spec, steady);
    let b = bare(&p);
    // The searches' model, where the design screens on a coarser one (its bare measures too:
    // each model's objective is against its own bare structure); a replay draws its maps near
    // the optimum on it, as the search did.
    let sp = super::design_problem::screen(exp, spec, steady);
    let sb = sp.as_ref().map(bare);
    let screen = sp.as_ref().zip(sb.as_deref());
    // A finite-element model's: the stated mass, else the mass moving along the vertical (its
    // modal coordinates' is no mass).
    let total_mass = match &exp.finite_element {
        Some(fe) => Some(fe.mass()),
        None => exp.structure_mass().map(|m| (m, "mass".to_string())),
    };
    let names: Vec<String> = p.cases().iter().map(|c| c.name.clone()).collect();
    let outlook = &spec.halt.outlook;
    outlook.set_phase("evaluating the experiment's cases", 0);
    let case_rows = cases_evaluated(exp, spec, &p, &b);
    outlook.set_phase("searching", 0);
    let (found, front, checks, stopped) = searched(exp, spec, (&p, &b), screen, refs, tick);
    after_search_phase(exp, spec, stopped);
    tick();
    let stored = stored(exp, &p, spec, &found, &front);
    let best = lowest(found.clone());
    let mut page = Page::default();
    let rows: Vec<(String, Layout, Evaluation, u64)> =
        found.iter().map(|f| (f.layout.hosts_words(), f.layout.clone(), f.evaluation.clone(), f.evaluations)).collect();
    page.tables.push(layouts_table(
        ("design_placements", exp.excitation.per_unit()),
        &format!(
            "The best layout found for each placement of containers: {} kg of shot{} split among them, clearances in {}-{} mm; objective: {} (1 = no gain)",
            fmt_num(spec.shot_kg),
            total_mass.as_ref().map_or(String::new(), |(m, what)| format!(" ({} of the structure's {what})", fmt_num(spec.shot_kg / m))),
            fmt_num(spec.clearance_mm.0),
            fmt_num(spec.clearance_mm.1),
            objective_axis(spec)
        ),
        spec,
        &names,
        &rows,
    ));
    if let Some(t) = page.tables.last_mut() {
        page.warnings.extend(super::design_problem::with_screened(spec, &found, t));
        with_converged(&found, t);
    }
    for (id, _, e, _) in &case_rows {
        page.exports.insert(format!("objective_{id}"), e.objective);
    }
    page.tables.push(layouts_table(
        ("design_cases", exp.excitation.per_unit()),
        "The experiment's cases as reference layouts, with the same objective",
        spec,
        &names,
        &case_rows,
    ));
    // A search the time limit or an interrupt stopped ends here too: what would search more
    // layouts after it (the clearance profile, the near-optimum map, the SDOF method) is
    // skipped, and the page says so; the drive levels are still evaluated (the best layout's).
    let more = !stopped;
    let why = stopped.then(|| {
        if spec.halt.interrupted() {
            "the search was interrupted (Ctrl-C or SIGTERM)"
        } else {
            "the search stopped at its time limit (--time-limit)"
        }
    });
    // How far the stopped search got, placement by placement (the placements table's
    // `evaluations` and `converged`).
    let stop_words = why.map(|w| stop_words(w, &found));
    let answer = best.as_ref().map(|best| {
        let best_in = BestIn {
            p: &p,
            judged: (&p, &b),
            screen,
            best,
            case_rows: &case_rows,
            total_mass: total_mass.clone(),
            more,
            stopped: stop_words.as_deref(),
        };
        match &spec.suite {
            Some(suite) => super::design_seismic::about_the_best(exp, spec, suite, &best_in, &mut page, tick),
            None => about_the_best(exp, spec, &best_in, &mut page),
        }
    });
    if let Some((mode, candidates)) = spec.sdof.as_ref().filter(|_| more) {
        let (table, sdof_exports) = sdof_method(exp, steady, &p, &b, &found, *mode, candidates, &names, spec.replay);
        page.tables.push(table);
        page.exports.extend(sdof_exports);
    }
    tick();
    if !front.is_empty() {
        let (table, figure) = pareto(exp, spec, &names, &front);
        page.tables.push(table);
        page.figures.push(figure);
    }
    if let Some(why) = why {
        let levels = if spec.drive_level_count() == 0 { "" } else { " (the drive levels are: the best layout's only)" };
        // A design against records has a clearance profile only.
        let more_layouts = if spec.suite.is_some() {
            "the clearance profile"
        } else {
            "the clearance profile, the near-optimum map, the SDOF method"
        };
        page.warnings.insert(
            0,
            format!("{why}: every layout here is the best found so far, not a converged optimum, and it is not stored as the design's answer; what would search more layouts ({more_layouts}) is not computed{levels}"),
        );
    }
    Output {
        tables: page.tables,
        figures: page.figures,
        exports: page.exports,
        checks,
        warnings: page.warnings,
        design: (!stopped).then_some(stored),
        answer,
        partial: why.map(|w| format!("{w}: the layouts are the best found so far")),
        ..Output::default()
    }
}

/// Tells the outlook what follows the searches: the best layout's clearance profile (not after
/// a stop), its drive levels, the maps near it, the SDOF method's layouts.
fn after_search_phase(exp: &Experiment, spec: &Spec, stopped: bool) {
    let budget = super::design_problem::budget(exp, spec);
    let placements = budget.placements as u64;
    // The drive levels are evaluated on the file's model: on a screened design each costs
    // what several of the searches' evaluations did (the outlook counts at their pace).
    let dearer = budget.judged_over_searched(exp.structure.dof()).ceil() as u64;
    let levels = (spec.drive_level_count() * if stopped { 1 } else { 1 + exp.cases.len() }) as u64 * dearer;
    let profile = if stopped { 0 } else { PROFILE_POINTS as u64 + placements * u64::from(spec.sdof.is_some()) };
    spec.halt
        .outlook
        .set_phase("evaluating the best layout again (clearance profile, drive levels, maps)", levels + profile);
}

/// The experiment's cases as reference layouts (the paper's, one container on the loop
/// point, ...), evaluated with the same objective, before the searches: under a time limit
/// they measure what an evaluation on the file's model costs ([`plan_after`]).
fn cases_evaluated(
    exp: &Experiment,
    spec: &Spec,
    p: &Problem,
    b: &[Vec<f64>],
) -> Vec<(String, Layout, Evaluation, u64)> {
    let judged = std::sync::atomic::AtomicU64::new(0);
    let case_rows: Vec<(String, Layout, Evaluation, u64)> = exp
        .cases
        .par_iter()
        .map(|c| {
            let l = case_layout(c);
            let started = std::time::Instant::now();
            let e = evaluate(p, b, &l);
            judged.fetch_add(started.elapsed().as_nanos() as u64, std::sync::atomic::Ordering::Relaxed);
            (c.id.clone(), l, e, 1)
        })
        .collect();
    let with_beds = exp.cases.iter().filter(|c| c.beds.iter().any(|b| b.damper.mass > 0.0)).count();
    let per_judged =
        (with_beds > 0).then(|| std::time::Duration::from_nanos(judged.into_inner() / exp.cases.len() as u64));
    plan_after(exp, spec, per_judged);
    case_rows
}

/// Reserves, under a time limit, what runs after the searches ([`crate::design::halt::Halt::plan_after`]):
/// on the file's model, a screened search's first round of judging (the rest is judged until
/// the deadline; an unscreened search keeps its placements' evaluations), the
/// drive levels and the bare curves, at `per_judged` an evaluation (the cases' mean, measured
/// before the searches; without cases with beds, the searches' pace times the nominal ratio of
/// the two models); on the searched model, the middle clearance of a placement whose scan had
/// not started, and each placement's best on the screen when there is one.
fn plan_after(exp: &Experiment, spec: &Spec, per_judged: Option<std::time::Duration>) {
    let budget = super::design_problem::budget(exp, spec);
    let placements = budget.placements as u64;
    let screened = u64::from(budget.screened.0 > 0);
    // A screened search's pages are judged until the deadline (`search::found_until`): its
    // first round, one evaluation a thread, is reserved.
    // An unscreened search keeps its placements' evaluations: none is evaluated again.
    let pages = if screened > 0 { rayon::current_num_threads() as u64 } else { 0 };
    // The drive levels: the best layout's and the cases' (only the best's after a stop); on
    // moving supports one more evaluation of the best (its storeys' drifts).
    let judged =
        pages + (spec.drive_level_count() * (1 + exp.cases.len())) as u64 + 1 + u64::from(exp.excitation.supports);
    let searched = placements + placements * budget.searches as u64 * screened;
    // A stopped search's drive levels (the best layout's) follow its judging on the file's model.
    spec.halt.plan_after_judging(spec.drive_level_count() as u64);
    match per_judged {
        Some(per) if screened > 0 => {
            spec.halt.plan_after_dearer(searched, judged, Some(per), budget.judged_over_searched(exp.structure.dof()))
        }
        Some(per) => spec.halt.plan_after(searched, judged, Some(per)),
        None => {
            let dearer = budget.judged_over_searched(exp.structure.dof()).ceil() as u64;
            spec.halt.plan_after(searched + judged * dearer, 0, None)
        }
    }
}

/// The best layout's pages: its clearance profile, its compliance against the bare structure's
/// and the cases', its drive levels, the map near the optimum; and the design's answer in words.
fn about_the_best(exp: &Experiment, spec: &Spec, i: &BestIn<'_>, page: &mut Page) -> String {
    let (p, best, more) = (i.p, i.best, i.more);
    // The maps near the optimum are drawn on the searched model.
    let (map_on, map_best, map_note) =
        super::design_problem::map_model(spec, i.screen.filter(|_| more), i.judged, best);
    let map_best = &map_best;
    let map_note = map_note.as_str();
    page.exports.insert("best_objective".into(), best.evaluation.objective);
    if spec.shared_clearance {
        page.exports.insert("best_clearance_mm".into(), best.layout.clearances_mm[0]);
    }
    if more {
        let (mut table, mut figure, robust) = clearance_profile(exp, spec, map_on.0, map_on.1, map_best);
        table.description += map_note;
        figure.caption += map_note;
        if let Some((rlo, rhi)) = robust {
            page.exports.insert("robust_clearance_min_mm".into(), rlo);
            page.exports.insert("robust_clearance_max_mm".into(), rhi);
        }
        page.tables.push(table);
        page.figures.push(figure);
    }
    // The bare structure's curves (the first scenario's, as the evaluations' curves).
    let bare_sys = p.system(&p.cases()[0], Vec::new());
    let bare_curves: Vec<Vec<Vec<f64>>> =
        spec.bands.iter().map(|band| band_compliance(&bare_sys, band, &p.sweeps, &p.steady).0).collect();
    let (table, figure) = compliance_figure(exp, spec, p, best, i.case_rows, &bare_curves);
    page.tables.push(table);
    page.figures.push(figure);
    let mut rated: Vec<super::design_drive::Rated<'_>> =
        vec![(format!("best: {}", best.layout.hosts_words()), &best.layout, &best.evaluation)];
    rated.extend(i.case_rows.iter().filter(|c| !c.1.hosts.is_empty()).map(|c| (format!("case {}", c.0), &c.1, &c.2)));
    let profile = match (more, page.exports.get("robust_clearance_min_mm"), page.exports.get("robust_clearance_max_mm"))
    {
        (false, _, _) => super::design_drive::Profile::NotComputed,
        (true, Some(lo), Some(hi)) => super::design_drive::Profile::Within(*lo, *hi),
        (true, _, _) => super::design_drive::Profile::Narrow,
    };
    let (table, w) = super::design_drive::drive(p, &bare_curves, &rated);
    page.tables.push(table);
    page.warnings.extend(w);
    // The reduction against the drive level: at the file's drive levels when it gives them,
    // over the forces of its scenarios when they vary the force (read from the evaluations
    // made), else from a quarter to four times the design's force. After a stopped search the
    // levels are still evaluated, for the best layout only (one evaluation a level): the answer
    // must not hide a level at which the shot makes things worse.
    let forces = spec.drive_levels(p.cases()[0].force);
    let levels = if forces.is_empty() {
        super::design_levels::drive_levels(p, &rated, &exp.meta.figure)
    } else {
        if !more {
            rated.truncate(1);
        }
        let layouts: Vec<&Layout> = rated.iter().map(|r| r.1).collect();
        let (at, evals) = super::design_levels::at_forces(p, &forces, &layouts);
        let rated_at: Vec<super::design_drive::Rated<'_>> =
            rated.iter().zip(&evals).map(|(r, e)| (r.0.clone(), r.1, e)).collect();
        super::design_levels::drive_levels(&at, &rated_at, &exp.meta.figure)
    };
    // On moving supports: the storeys' drifts and floors' accelerations of the best layout.
    let mut storeys_said = String::new();
    if let Some((table, figure, said)) = super::design_storeys::storeys(
        p,
        spec,
        &format!("best: {}", best.layout.hosts_words()),
        best.layout.dampers(p.direction),
        &exp.meta.figure,
    ) {
        page.tables.push(table);
        page.figures.push(figure);
        storeys_said = said;
    }
    let mut at_levels = Vec::new();
    if let Some((mut table, mut figure, best_at)) = levels {
        if spec.drive_levels_n.is_empty() && !forces.is_empty() {
            let chosen = " The file gives no drive_levels_n: the levels are a quarter to four times the force the design is made for.";
            table.description += chosen;
            figure.caption += chosen;
        }
        page.tables.push(table);
        page.figures.push(figure);
        at_levels = best_at;
    }
    let answer_in = super::design_drive::AnswerIn {
        total_mass: i.total_mass.clone(),
        profile,
        sampled: spec.clearance_mm,
        levels: &at_levels,
        stopped: i.stopped,
        storeys: &storeys_said,
    };
    let answer = super::design_drive::answer(p, &rated[0], &answer_in, &bare_curves);
    if let Some((mut table, mut figure)) = more
        .then(|| {
            let (layout, evaluation) = (&map_best.layout, &map_best.evaluation);
            super::design_near::near_optimum(spec, map_on.0, map_on.1, layout, evaluation, &exp.meta.figure)
        })
        .flatten()
    {
        table.description += map_note;
        figure.caption += map_note;
        page.tables.push(table);
        page.figures.push(figure);
    }
    answer
}

/// The Pareto front of shot mass against the objective: its table and figure.
fn pareto(exp: &Experiment, spec: &Spec, names: &[String], front: &[(f64, Found)]) -> (Table, Figure) {
    let rows: Vec<(String, Layout, Evaluation, u64)> = front
        .iter()
        .map(|(r, f)| (format!("mass ratio {}", fmt_num(*r)), f.layout.clone(), f.evaluation.clone(), f.evaluations))
        .collect();
    let table = layouts_table(
        ("design_pareto", exp.excitation.per_unit()),
        "The best layout for each total shot mass ratio (the Pareto front of shot mass against the objective)",
        spec,
        names,
        &rows,
    );
    let x: Vec<f64> = front.iter().map(|(r, _)| *r).collect();
    let y: Vec<f64> = front.iter().map(|(_, f)| f.evaluation.objective).collect();
    let mut panel = Panel::new(
        "best objective against the shot budget",
        "total shot mass / structure mass",
        objective_axis(spec),
        (x[0], x[x.len() - 1]),
    );
    let mut s = Series::line("best layout", x, y, 0);
    s.marker = Marker::Circle;
    panel.series.push(s);
    let figure = Figure {
        id: "design_pareto".into(),
        title: format!("{}: shot mass against the objective", exp.meta.figure),
        caption: "The best objective found for each total shot mass ratio (every placement, split and clearance searched again for each). Where the table's worst_at_band_edge is 1 the damped resonance has moved to the band's edge (more shot lowers it): that point is limited by the band, not the dampers.".into(),
        panels: vec![panel],
    };
    (table, figure)
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
    replay: bool,
) -> (Table, BTreeMap<String, f64>) {
    let modes = crate::model::modal::modal_summary(&exp.structure, &[]);
    let reference = modes[mode].reference_mass;
    let band = &p.bands[0].freq_hz;
    // In the report (replay) the best placement and the best one-container placement (Fig.
    // 9's setting); a search run takes every placement.
    let lowest_of = |one: bool| {
        found
            .iter()
            .filter(|f| !one || f.layout.hosts.len() == 1)
            .map(|f| f.evaluation.objective)
            .fold(f64::INFINITY, f64::min)
    };
    let (best, best_single) = (lowest_of(false), lowest_of(true));
    let rows: Vec<(String, f64, Evaluation, f64)> = found
        .iter()
        .filter(|f| {
            !replay
                || f.evaluation.objective == best
                || (f.layout.hosts.len() == 1 && f.evaluation.objective == best_single)
        })
        .map(|f| {
            let choice = super::orbits::sdof_choice(
                exp,
                &f.layout.dampers(p.direction),
                mode,
                reference,
                band,
                candidates,
                steady,
                &|| {},
            );
            let l = Layout { clearances_mm: vec![choice.clearance_mm; f.layout.hosts.len()], ..f.layout.clone() };
            let e = evaluate(p, b, &l);
            (f.layout.hosts_words(), choice.clearance_mm, e, f.evaluation.objective)
        })
        .collect();
    // A pick at either end of the candidates may be the list's limit, not the technique's.
    let (lo, hi) = candidates.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &c| (a.min(c), b.max(c)));
    let edge = |d: f64| {
        if candidates.len() < 2 {
            ""
        } else if d == lo {
            "smallest candidate: the list may stop the pick"
        } else if d == hi {
            "largest candidate: the list may stop the pick"
        } else {
            ""
        }
    };
    let mut exports = BTreeMap::new();
    if let Some(best) = rows.iter().min_by(|x, y| x.3.total_cmp(&y.3)) {
        exports.insert("sdof_clearance_mm".into(), best.1);
        exports.insert("sdof_objective".into(), best.2.objective);
        exports.insert("sdof_at_edge".into(), if edge(best.1).is_empty() { 0.0 } else { 1.0 });
    }
    let table = Table::new(
        "design_sdof",
        format!(
            "The paper's SDOF technique as a design method: for each placement (in the report: the best placement and the best one-container placement) and its best shot split, the clearance the equivalent SDOF model of mode {} picks by the rule of Fig. 9 (Type II alone within the resonance, the lowest SDOF peak; candidates {} mm; the SDOF model over the first band), evaluated on the full structure beside the optimiser's",
            mode + 1,
            joined(candidates)
        ),
    )
    .str("layout", rows.iter().map(|r| r.0.clone()).collect())
    .f64("sdof_clearance_mm", rows.iter().map(|r| r.1).collect())
    .str("sdof_pick", rows.iter().map(|r| edge(r.1).to_string()).collect())
    .f64("objective_sdof", rows.iter().map(|r| r.2.objective).collect())
    .f64("objective_optimiser", rows.iter().map(|r| r.3).collect())
    .f64("left_on_the_table", rows.iter().map(|r| r.2.objective / r.3 - 1.0).collect())
    .str("scenario", rows.iter().map(|r| names.get(r.2.worst_scenario).cloned().unwrap_or_default()).collect())
    .i64("unsettled_points", rows.iter().map(|r| r.2.unsettled as i64).collect());
    (table, exports)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn found(ended: search::Ended, evaluations: u64) -> Found {
        Found {
            layout: Layout { hosts: vec![0], masses_kg: vec![0.1], clearances_mm: vec![1.0] },
            evaluation: Evaluation::with_objective(0.5, 0, 10),
            x: Vec::new(),
            starts: 1,
            evaluations,
            screened: None,
            judged: true,
            ended: Some(ended),
        }
    }

    #[test]
    fn a_stopped_search_says_what_its_layout_is() {
        use search::Ended::{Converged, Stopped};
        let why = "the search stopped at its time limit (--time-limit)";
        // Stopped inside the main search: not converged, the best so far.
        let w = stop_words(why, &[found(Converged, 40), found(Stopped, 3), found(Stopped, 5)]);
        assert!(w.starts_with("Not a converged answer: the search stopped"), "{w}");
        assert!(w.contains("1 of the 3 placements were searched to convergence, the other 2 stopped after 3-5"), "{w}");
        assert!(w.ends_with("the best layout found so far."), "{w}");
        // Stopped after every placement converged: converged, but not the whole answer.
        let w = stop_words(why, &[found(Converged, 40), found(Converged, 30)]);
        assert!(w.starts_with("Not the whole answer: the search stopped"), "{w}");
        assert!(w.contains("every one of the 2 placements had been searched to convergence"), "{w}");
        assert!(!w.contains("Not a converged") && !w.contains("found so far"), "{w}");
    }
}
