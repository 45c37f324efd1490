//! A design search's answer, stored: the best layout of every placement and of every point of
//! the Pareto front, with the objective the search found for it (docs/design.md, "In the
//! report"). `shotdamp design --store` writes it; `shotdamp report` evaluates the stored
//! layouts again with the simulator instead of searching, and fails a check when a stored
//! objective is not what the layout gives now or when the design problem has changed since
//! the search (the fingerprint). Serialisation only; no I/O.

use serde::{Deserialize, Serialize};

use super::{Layout, Problem, Spec};

/// One stored layout and what the search found for it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredLayout {
    /// What it is the best of: the placement (e.g. "m1 m2") or the Pareto point.
    pub label: String,
    /// 0-based host masses.
    pub hosts: Vec<usize>,
    /// Shot mass of each container, kg.
    pub masses_kg: Vec<f64>,
    /// Clearance of each container, mm.
    pub clearances_mm: Vec<f64>,
    /// The objective the search computed.
    pub objective: f64,
    /// Objective evaluations the search made for it.
    pub evaluations: u64,
}

impl StoredLayout {
    /// The layout.
    pub fn layout(&self) -> Layout {
        Layout {
            hosts: self.hosts.clone(),
            masses_kg: self.masses_kg.clone(),
            clearances_mm: self.clearances_mm.clone(),
        }
    }

    /// Stores a layout found by the search.
    pub fn of(label: String, layout: &Layout, objective: f64, evaluations: u64) -> StoredLayout {
        StoredLayout {
            label,
            hosts: layout.hosts.clone(),
            masses_kg: layout.masses_kg.clone(),
            clearances_mm: layout.clearances_mm.clone(),
            objective,
            evaluations,
        }
    }
}

/// A Pareto point: the total shot mass ratio and its best layout.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredPareto {
    /// Total shot mass over the structure's total mass.
    pub mass_ratio: f64,
    /// The best layout with that much shot.
    pub best: StoredLayout,
}

/// The stored answer of one design experiment on one model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredDesign {
    /// The experiment's key (`ID/MODEL`).
    pub experiment: String,
    /// [`fingerprint`] of the design problem searched.
    pub fingerprint: String,
    /// How it was computed: the command, shotdamp's version, the date, the time taken.
    pub provenance: String,
    /// The best layout of each placement.
    pub placements: Vec<StoredLayout>,
    /// The Pareto front: the best layout per total mass ratio.
    pub pareto: Vec<StoredPareto>,
}

impl StoredDesign {
    /// As its stored file holds it: pretty JSON ending in a newline.
    pub fn to_json(&self) -> crate::Result<String> {
        serde_json::to_string_pretty(self).map(|text| text + "\n").map_err(|e| crate::Error::Render {
            what: format!("the design answer of {}", self.experiment),
            message: e.to_string(),
        })
    }
}

/// A fingerprint of everything a search's answer depends on: the structure and force (with
/// the scenarios), the bands, measure, sweeps and steady-state settings (or the records and what
/// is measured under them), and the search space and settings (64-bit FNV-1a of their exact
/// values, in hex).
pub fn fingerprint(problem: &Problem, spec: &Spec) -> String {
    // A horizontal design adds its direction; a vertical one's text is as it always was (the
    // answers stored before containers had a direction stay valid).
    let direction = match problem.direction {
        crate::model::Direction::Vertical => String::new(),
        other => format!("|{}", other.name()),
    } + if problem.supports { "|supports" } else { "" }
        // A design searched on a coarser model adds it (the others' texts are unchanged).
        + &spec.screen.as_ref().map_or(String::new(), |sc| format!("|screen {:?}", sc.structure))
        + &spec.screen.as_ref().and_then(|sc| sc.max_periods).map_or(String::new(), |m| format!("|screen max_periods {m}"))
        // A design against records adds them, every sample, and what it measures.
        + &problem.suite.as_ref().map_or(String::new(), |s| format!("|suite {s:?}"));
    let text = format!(
        "{:?}|{}|{}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        problem.structure,
        problem.driven,
        problem.force,
        problem.bands,
        problem.measure,
        problem.sweeps,
        problem.steady,
        problem.scenarios.iter().map(|s| (&s.name, &s.structure, s.force)).collect::<Vec<_>>(),
        problem.combine,
        spec.candidates,
        spec.max_beds,
        spec.shot_kg,
        spec.clearance_mm,
        spec.shared_clearance,
        spec.search,
        spec.pareto_mass_ratios,
    ) + &direction;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}
