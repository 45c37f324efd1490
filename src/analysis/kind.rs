//! The seam every analysis kind plugs into: one trait ([`Kind`]) that says how much work a
//! kind will do and runs it, what it is given ([`Input`]) and the one value it returns
//! ([`Output`]). The kinds (`sweep.rs`, `impulse.rs`, ...) implement it; the dispatcher
//! (`mod.rs`) picks the kind of an experiment in one match and does the rest (checks, the
//! finite-element reduction, baselines) the same way for all. Nothing here imports a kind.

use std::collections::BTreeMap;

use crate::checks::reference::ReferenceStore;
use crate::checks::{CheckOutcome, Source};
use crate::design::stored::StoredDesign;
use crate::experiment::Experiment;
use crate::figure::Figure;
use crate::model::modal::ModeSummary;
use crate::table::Table;

use super::curves::Curve;
use super::evidence::{Decay, MotionTypes, OrbitsResult};
use super::result::Tick;

/// What a kind is given to run.
pub struct Input<'a> {
    /// The experiment (its exported inputs resolved).
    pub exp: &'a Experiment,
    /// The modes of the bare structure.
    pub modes: &'a [ModeSummary],
    /// The references, pre-loaded.
    pub refs: &'a ReferenceStore,
    /// Ticked at every simulated point (or design evaluation).
    pub tick: &'a Tick<'a>,
}

/// Everything a kind produced. Each kind fills in what it computes and leaves the rest at
/// its default (empty).
#[derive(Default)]
pub struct Output {
    /// Tables for the data folder (after the modal table, which every experiment has).
    pub tables: Vec<Table>,
    /// Figures for the page.
    pub figures: Vec<Figure>,
    /// Compliance curves, for the curve checks and figures that compare models.
    pub curves: Vec<Curve>,
    /// Values other experiments may use (`"@ID.KEY"`).
    pub exports: BTreeMap<String, f64>,
    /// Checks the kind evaluates itself (a design's replay, a case that could not be drawn),
    /// after the experiment's own checks.
    pub checks: Vec<CheckOutcome>,
    /// What a user must know before reading the results.
    pub warnings: Vec<String>,
    /// Each case's free decay (impulse), by case id: for the decay checks.
    pub decays: BTreeMap<String, Decay>,
    /// The orbits of an SDOF analysis: for the orbit checks.
    pub orbits: Option<OrbitsResult>,
    /// The motion types of a waveform analysis: for the motion-type checks.
    pub motion_types: MotionTypes,
    /// A design search's answer, to store.
    pub design: Option<StoredDesign>,
    /// The answer in one paragraph, where the kind gives one.
    pub answer: Option<String>,
    /// Why the answer is partial (a search stopped at its time limit or by an interrupt, its
    /// layouts the best found so far), when it is: the front page opens with it and the
    /// command exits with 3 (README, "Exit codes").
    pub partial: Option<String>,
}

impl Output {
    /// Cases that could not be simulated, and why: each is a warning and a failed check (the
    /// case is missing from the page's tables and figures, which must not pass silently).
    pub fn missing_cases(&mut self, exp: &Experiment, skipped: Vec<String>) {
        self.checks.extend(skipped.iter().map(|w| {
            CheckOutcome::unavailable(
                "simulation".into(),
                format!("{} ({}): {w}", exp.meta.figure, exp.key()),
                "the experiment file".into(),
                Source::Internal,
                Some("the case is missing from this page's tables and figures".into()),
            )
        }));
        self.warnings.extend(skipped);
    }
}

/// One analysis kind: its settings (borrowed from `experiment::Analysis`) and how it runs.
pub trait Kind {
    /// Simulated points it will run, for progress bars (0: not known ahead, or none).
    fn work(&self, _exp: &Experiment, _refs: &ReferenceStore) -> u64 {
        0
    }

    /// Runs it.
    fn run(&self, input: &Input<'_>) -> Output;
}
