//! A design's reduction against the drive level (docs/design.md, "Drive level"): where a design
//! file lists several forces as scenarios (`[design.scenarios] force_n`), the objective of the
//! best layout and of the experiment's cases at each force. An impact damper's effect depends
//! on the amplitude: too weak a drive and the beds ride on their hosts (only mass added), too
//! strong and they fly too far to land in step with the structure.

use rayon::prelude::*;

use crate::design::{bare, evaluate, Combine, Evaluation, Layout, Problem, Scenario};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series};
use crate::number::fmt_sig;
use crate::table::Table;

/// A layout reported on: its label, the layout and its evaluation.
type Rated<'a> = super::design_drive::Rated<'a>;

/// Scenarios that differ only in the force: each group's indices into the scenarios, in
/// increasing force, and the group's label (its first scenario's name without the force).
fn groups(problem: &Problem) -> Vec<(String, Vec<usize>)> {
    let cases = problem.cases();
    let mut out: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, sc) in cases.iter().enumerate() {
        match out.iter_mut().find(|(_, g)| cases[g[0]].structure == sc.structure) {
            Some((_, g)) => g.push(i),
            None => {
                let label = sc.name.rsplit_once(", F ").map_or_else(|| "nominal".to_string(), |(a, _)| a.to_string());
                out.push((label, vec![i]));
            }
        }
    }
    for (_, g) in &mut out {
        g.sort_by(|&a, &b| cases[a].force.total_cmp(&cases[b].force));
    }
    out
}

/// The drive levels of a design: the table `design_drive_levels`, its figure, and the first
/// layout's (the best's) objective at each force of the first group, in increasing force.
pub type Levels = (Table, Figure, Vec<(f64, f64)>);

/// The table `design_drive_levels` and its figure, when the scenarios hold two forces or more
/// of one structure; `None` otherwise.
pub fn drive_levels(problem: &Problem, layouts: &[Rated<'_>], figure_name: &str) -> Option<Levels> {
    let cases = problem.cases();
    let groups: Vec<(String, Vec<usize>)> = groups(problem).into_iter().filter(|(_, g)| g.len() > 1).collect();
    if groups.is_empty() {
        return None;
    }
    let mut rows: Vec<(String, String, f64, f64)> = Vec::new();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    let mut panel = Panel::new(
        "the worst band over the bare structure against the force",
        "force amplitude F (N)",
        "worst band over the bare structure",
        (0.0, 1.0),
    )
    .log_x();
    let several = groups.len() > 1;
    for (k, (label, _layout, eval)) in layouts.iter().enumerate() {
        for (gi, (group, idx)) in groups.iter().enumerate() {
            let x: Vec<f64> = idx.iter().map(|&i| cases[i].force).collect();
            let y: Vec<f64> = idx.iter().map(|&i| objective_of(eval, i)).collect();
            for (&i, &v) in idx.iter().zip(&y) {
                rows.push((label.clone(), group.clone(), cases[i].force, v));
            }
            lo = x.iter().copied().fold(lo, f64::min);
            hi = x.iter().copied().fold(hi, f64::max);
            let name = if several { format!("{label} ({group})") } else { label.clone() };
            let mut s = Series::line(name, x, y, k);
            s.marker = Marker::Circle;
            if gi > 0 {
                s = s.dashed(Dash::Dashed);
            }
            panel.series.push(s);
        }
    }
    panel.x_range = (lo / 1.25, hi * 1.25);
    panel.series.push(Series::line("no gain", vec![lo / 1.25, hi * 1.25], vec![1.0, 1.0], 7).dashed(Dash::Dotted));
    panel.legend = Corner::UpperRight;
    let table = Table::new(
        "design_drive_levels",
        "The objective (the worst band's measure over the bare structure's, 1: no gain) of the best layout and the experiment's cases at each force of the scenarios, N: an impact damper's effect depends on the drive level",
    )
    .str("layout", rows.iter().map(|r| r.0.clone()).collect())
    .str("scenario", rows.iter().map(|r| r.1.clone()).collect())
    .f64("force_n", rows.iter().map(|r| r.2).collect())
    .f64("objective", rows.iter().map(|r| r.3).collect());
    let best: Vec<(f64, f64)> = layouts
        .first()
        .map(|(_, _, e)| groups[0].1.iter().map(|&i| (cases[i].force, objective_of(e, i))).collect())
        .unwrap_or_default();
    let span = (!best.is_empty()).then(|| {
        let v = best.iter().map(|b| b.1);
        (v.clone().fold(f64::INFINITY, f64::min), v.fold(0.0, f64::max))
    });
    let caption = match span {
        Some((a, b)) => format!(
            "The worst band's measure over the bare structure's at each force (log axis), for the best layout and the experiment's cases; the best layout's ranges from {} to {} over {}. An impact damper works in a window of drive levels: away from the force it was designed for its beds no longer land in step with the structure (and vertical beds below 1 g at their hosts only add mass).",
            fmt_sig(a, 2),
            fmt_sig(b, 2),
            problem.drive().amount(&format!("{}-{}", fmt_sig(lo, 2), fmt_sig(hi, 2)))
        ),
        None => "The worst band's measure over the bare structure's at each force of the scenarios.".to_string(),
    };
    let figure = Figure {
        id: "design_drive_levels".into(),
        title: format!("{figure_name}: the reduction against the drive level"),
        caption,
        panels: vec![panel],
    };
    Some((table, figure, best))
}

/// The problem at each of `forces` (the nominal structure, one scenario per force) and the
/// evaluations of `layouts` there, in order: what [`drive_levels`] draws for a design file's
/// `drive_levels_n` (evaluated after the search, not part of its objective).
pub fn at_forces(problem: &Problem, forces: &[f64], layouts: &[&Layout]) -> (Problem, Vec<Evaluation>) {
    let mut sorted = forces.to_vec();
    sorted.sort_by(f64::total_cmp);
    let scenarios = sorted
        .iter()
        .map(|&f| Scenario {
            name: if problem.supports {
                format!("A {} m/s^2", crate::number::fmt_num(f))
            } else {
                format!("F {} N", crate::number::fmt_num(f))
            },
            structure: problem.structure.clone(),
            force: f,
        })
        .collect();
    let at = Problem { scenarios, combine: Combine::Worst, ..problem.clone() };
    let b = bare(&at);
    let evaluations = layouts.par_iter().map(|l| evaluate(&at, &b, l)).collect();
    (at, evaluations)
}

/// Scenario `i`'s objective in an evaluation.
fn objective_of(e: &Evaluation, i: usize) -> f64 {
    e.scenarios.get(i).copied().unwrap_or(f64::NAN)
}
