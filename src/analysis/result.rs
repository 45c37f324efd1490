//! What every analysis kind shares, below them all: an experiment's result
//! ([`ExperimentResult`]) and the progress counters the kinds tick ([`Tick`], [`Progress`]).
//! The kinds (`sweep`, `clearance`, ...) import this room; the dispatcher (`mod.rs`) imports
//! the kinds; nothing here imports a kind but the curve store it carries.

use std::collections::BTreeMap;

use crate::checks::CheckOutcome;
use crate::experiment::Experiment;
use crate::figure::Figure;
use crate::model::modal::ModeSummary;
use crate::table::Table;

use super::curves;

/// Everything an experiment produced, ready to be written and rendered.
#[derive(Debug, Clone)]
pub struct ExperimentResult {
    /// The experiment run (exports resolved).
    pub experiment: Experiment,
    /// Modes of the bare structure.
    pub modes: Vec<ModeSummary>,
    /// Tables for the report's data folder.
    pub tables: Vec<Table>,
    /// Figures for the report.
    pub figures: Vec<Figure>,
    /// Every check's outcome.
    pub checks: Vec<CheckOutcome>,
    /// The compliance curves computed (sweeps, linear responses, scans), by id, for figures
    /// that compare models.
    pub curves: curves::Curves,
    /// Values other experiments may use (`"@ID.KEY"`).
    pub exports: BTreeMap<String, f64>,
    /// A design search's answer, to store (`shotdamp design --store`).
    pub design: Option<crate::design::stored::StoredDesign>,
    /// What a user must know before reading the answer (a design whose beds hardly move at
    /// its drive level, unsettled points): at the top of the page and in the command's
    /// summary.
    pub warnings: Vec<String>,
    /// The answer in one paragraph, where the analysis gives one (a design): the first thing
    /// on the page.
    pub answer: Option<String>,
    /// Why the answer is partial, when it is (a design stopped at its time limit or by an
    /// interrupt: its layouts the best found so far).
    pub partial: Option<String>,
}

/// Counts one finished unit of work (a simulated point). A caller may stop the work at a point
/// by unwinding out of it; `'a` lets it borrow what it reports to.
pub type Tick<'a> = dyn Fn() + Sync + 'a;

/// Receives progress: one counter per experiment.
pub trait Progress: Sync {
    /// A counter for an experiment that will run `total` simulated points.
    fn start(&self, id: &str, total: u64) -> Box<Tick<'static>>;

    /// A counter of a design search's layout evaluations: of unknown total, at most
    /// `ceiling`, with what is expected to be left and what the design is doing in `outlook`
    /// (updated as it goes); by default one of unknown total.
    fn start_search(
        &self,
        id: &str,
        _ceiling: u64,
        _outlook: std::sync::Arc<crate::design::halt::Outlook>,
    ) -> Box<Tick<'static>> {
        self.start(id, 0)
    }
}

/// No progress display.
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _id: &str, _total: u64) -> Box<Tick<'static>> {
        Box::new(|| {})
    }
}

impl ExperimentResult {
    /// True when no check failed.
    pub fn passed(&self) -> bool {
        !self.checks.iter().any(|c| c.status.fails())
    }
}
