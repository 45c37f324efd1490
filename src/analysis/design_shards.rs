//! A design's search in shares (docs/design.md, "Sharded searches"): every search of a design
//! (the main one, then one per Pareto budget) is split into items, one per placement, numbered
//! search by search; a shard searches the items it owns, and the merge hands every item's end
//! to the design, which then reports the unsharded answer (each placement's search depends on
//! nothing but the placement). The part files are the runner's.

use crate::design::search::{placements, search_placements, Searched, Space};
use crate::design::{bare, Spec};
use crate::experiment::Experiment;
use crate::sim::SteadyOptions;

/// The searches of a design: the main one, then one per Pareto budget, in that order.
pub fn spaces(exp: &Experiment, spec: &Spec) -> Vec<Space> {
    // Validation refuses Pareto ratios where the structure has no mass to take them of.
    let total_mass = exp.structure_mass().unwrap_or(f64::NAN);
    let main = Space {
        placements: placements(&spec.candidates, spec.max_beds),
        shot_kg: spec.shot_kg,
        clearance_mm: spec.clearance_mm,
        shared_clearance: spec.shared_clearance,
    };
    let mut out = vec![main.clone()];
    out.extend(
        spec.pareto_mass_ratios
            .iter()
            .map(|&r| Space { shot_kg: crate::number::decimal(r * total_mass), ..main.clone() }),
    );
    out
}

/// The number of items of a design's searches (placements times searches).
pub fn items(exp: &Experiment, spec: &Spec) -> usize {
    spaces(exp, spec).iter().map(|s| s.placements.len()).sum()
}

/// One design's share of a sharded search: its fingerprint (a merge refuses parts of another
/// design) and, per search and placement, what the search ended with where this share owns
/// the item.
#[derive(Debug, Clone, PartialEq)]
pub struct Share {
    /// The design's fingerprint ([`crate::design::stored::fingerprint`]).
    pub fingerprint: String,
    /// Per search, per placement.
    pub searches: Vec<Vec<Option<Searched>>>,
}

/// Searches the items of `exp`'s design that `owned` accepts (items numbered placement by
/// placement, search by search), calling `tick` as the design's run does.
pub fn share(
    exp: &Experiment,
    spec: &Spec,
    steady: &SteadyOptions,
    owned: &(dyn Fn(usize) -> bool + Sync),
    tick: &(dyn Fn() + Sync),
) -> Share {
    let p = super::design_problem::problem(exp, spec, steady);
    // The searches run on the screen's model where the design has one (as unsharded).
    let sp = super::design_problem::screen(exp, spec, steady);
    let on = sp.as_ref().unwrap_or(&p);
    let b = bare(on);
    let mut first = 0;
    let searches = spaces(exp, spec)
        .iter()
        .map(|space| {
            let offset = first;
            first += space.placements.len();
            let mine = |placement: usize| owned(offset + placement);
            search_placements(on, &b, space, &spec.search, tick, &spec.halt, &mine).0
        })
        .collect();
    Share { fingerprint: crate::design::stored::fingerprint(&p, spec), searches }
}
