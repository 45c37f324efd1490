//! How a design's objective varies with each of its variables near the best layout found:
//! each host's share of the shot (the others scaled so the total is kept) and each clearance
//! (or the shared one), changed by -40 % to +40 % one at a time (docs/design.md); the shared clearance has its own
//! profile.

use rayon::prelude::*;

use crate::design::{evaluate, Evaluation, Layout, Problem, Spec};
use crate::figure::{Corner, Figure, Marker, Panel, Series};
use crate::table::Table;

/// Relative changes of a variable, %.
const CHANGES: [f64; 5] = [-40.0, -10.0, 0.0, 10.0, 40.0];

/// The layout with one variable changed by `pct` %, or `None` when that leaves the bounds or
/// leaves no shot for the other hosts.
fn changed(best: &Layout, var: &Variable, pct: f64, bounds: (f64, f64)) -> Option<Layout> {
    let f = 1.0 + pct / 100.0;
    let mut l = best.clone();
    match *var {
        Variable::Share(i) => {
            let total: f64 = best.masses_kg.iter().sum();
            let rest = total - best.masses_kg[i];
            let mine = best.masses_kg[i] * f;
            if rest <= 0.0 || mine > total {
                return None;
            }
            let scale = (total - mine) / rest;
            for (k, m) in l.masses_kg.iter_mut().enumerate() {
                *m = if k == i { mine } else { *m * scale };
            }
        }
        Variable::Clearance(i) => {
            let d = best.clearances_mm[i] * f;
            if !(bounds.0..=bounds.1).contains(&d) {
                return None;
            }
            l.clearances_mm[i] = d;
        }
    }
    Some(l)
}

enum Variable {
    Share(usize),
    Clearance(usize),
}

/// A changed layout's objective and its unsettled points.
type Outcome = (f64, usize);

/// The table `design_near_optimum` and its figure.
pub fn near_optimum(
    spec: &Spec,
    p: &Problem,
    b: &[Vec<f64>],
    best: &Layout,
    best_evaluation: &Evaluation,
    title: &str,
) -> Option<(Table, Figure)> {
    let mut vars: Vec<(String, Variable)> = Vec::new();
    if best.hosts.len() > 1 {
        for (i, h) in best.hosts.iter().enumerate() {
            vars.push((format!("shot on m{}", h + 1), Variable::Share(i)));
        }
    }
    // The shared clearance has its own profile (design_clearance).
    if !spec.shared_clearance {
        for (i, h) in best.hosts.iter().enumerate() {
            vars.push((format!("clearance on m{}", h + 1), Variable::Clearance(i)));
        }
    }
    if vars.is_empty() {
        return None;
    }
    let jobs: Vec<(usize, f64)> = (0..vars.len()).flat_map(|v| CHANGES.iter().map(move |c| (v, *c))).collect();
    // Per change: the variable, the change and its outcome.
    let rows: Vec<(usize, f64, Option<Outcome>)> = jobs
        .par_iter()
        .map(|&(v, c)| {
            let o = if c == 0.0 {
                Some((best_evaluation.objective, best_evaluation.unsettled))
            } else {
                changed(best, &vars[v].1, c, spec.clearance_mm).map(|l| {
                    let e = evaluate(p, b, &l);
                    (e.objective, e.unsettled)
                })
            };
            (v, c, o)
        })
        .collect();
    let kept: Vec<&(usize, f64, Option<Outcome>)> = rows.iter().filter(|r| r.2.is_some()).collect();
    let table = Table::new(
        "design_near_optimum",
        "The objective near the best layout: each variable changed by -40 % to +40 % with the others held (a shared clearance: see design_clearance) (a host's share of the shot changed, the other hosts' shares scaled to keep the total); changes that leave the clearance bounds or the shot budget are left out",
    )
    .str("variable", kept.iter().map(|r| vars[r.0].0.clone()).collect())
    .f64("change_percent", kept.iter().map(|r| r.1).collect())
    .f64("objective", kept.iter().map(|r| r.2.map_or(f64::NAN, |o| o.0)).collect())
    .i64("unsettled_points", kept.iter().map(|r| r.2.map_or(0, |o| o.1 as i64)).collect());
    let mut panel = Panel::new(
        "objective near the optimum, one variable at a time",
        "change of the variable (%)",
        "worst band over the bare structure",
        (CHANGES[0], CHANGES[CHANGES.len() - 1]),
    );
    for (k, (name, _)) in vars.iter().enumerate() {
        let pts: Vec<&&(usize, f64, Option<Outcome>)> = kept.iter().filter(|r| r.0 == k).collect();
        let mut s = Series::line(
            name.clone(),
            pts.iter().map(|r| r.1).collect(),
            pts.iter().map(|r| r.2.map_or(f64::NAN, |o| o.0)).collect(),
            k,
        );
        s.marker = Marker::Circle;
        panel.series.push(s);
    }
    panel.legend = Corner::UpperRight;
    let figure = Figure {
        id: "design_near_optimum".into(),
        title: format!("{title}: each variable near the optimum"),
        caption: "The objective of the best layout with one variable changed at a time: a host's share of the shot (the others scaled to keep the total) or a clearance. A flat line is a variable the optimum does not hinge on; a steep one must be set with care.".into(),
        panels: vec![panel],
    };
    Some((table, figure))
}
