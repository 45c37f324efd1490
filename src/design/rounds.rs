//! The Nelder-Mead runs of a search, advanced in rounds: in each round every run that has not
//! ended makes at most [`ROUND_ITERATIONS`] iterations (its first round also evaluates its
//! simplex), and no run starts the next round before every run has finished this one. Each
//! run is sequential and makes exactly the steps it would make uninterrupted, so the answer of
//! a search that is not stopped does not depend on the rounds; a search that a time limit or an
//! interrupt stops leaves every placement refined about as far as every other, instead of
//! some placements converged while others never left their coarse scan.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;

use rayon::prelude::*;

use super::halt::Halt;
use super::nelder_mead::{End, Settings, Simplex};
use super::space::{layout, Options, Space};
use super::{evaluate_below, Evaluation, Problem};

/// Nelder-Mead iterations a run makes in a round (a placement of the shipped designs
/// converges in 5-60).
pub const ROUND_ITERATIONS: u64 = 8;

/// How a placement's search ended: every start converged (its simplex's objectives agreed to
/// the tolerance, or it shrank below its size), some start spent its iterations, or the time
/// limit or an interrupt stopped it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    /// Every start converged.
    Converged,
    /// A start spent its `max_iters` iterations without converging.
    Iterations,
    /// The time limit or an interrupt stopped it.
    Stopped,
}

impl Ended {
    /// The word a table gives it.
    pub fn word(self) -> &'static str {
        match self {
            Ended::Converged => "yes",
            Ended::Iterations => "no: iterations spent",
            Ended::Stopped => "no: stopped",
        }
    }

    /// Parses [`Ended::word`].
    pub fn from_word(w: &str) -> Option<Self> {
        [Ended::Converged, Ended::Iterations, Ended::Stopped].into_iter().find(|e| e.word() == w)
    }

    /// The end of a placement of several starts: stopped before spent before converged.
    pub fn worst(self, other: Ended) -> Ended {
        let rank = |e: Ended| match e {
            Ended::Converged => 0,
            Ended::Iterations => 1,
            Ended::Stopped => 2,
        };
        if rank(other) > rank(self) {
            other
        } else {
            self
        }
    }
}

/// What one run ended with: its best point, objective, evaluations, how it ended, and the
/// evaluation of its best point (kept, so that the placement's best need not be evaluated
/// again on the model the search ran on).
pub struct RunEnd {
    /// The best point's free coordinates.
    pub x: Vec<f64>,
    /// Its objective (infinite when the run evaluated nothing).
    pub objective: f64,
    /// Evaluations the run made.
    pub evaluations: u64,
    /// How it ended.
    pub ended: Ended,
    /// The best point's evaluation, where kept.
    pub evaluation: Option<Evaluation>,
}

/// A run stopped by the deadline or an interrupt.
#[derive(Debug)]
struct TimeLimit;

/// The best point a run evaluated: its coordinates, objective and evaluation.
type Best = Option<(Vec<f64>, f64, Evaluation)>;

/// A run to make: its placement, its start and, where the start was evaluated already (the
/// coarse scan's best), its objective and evaluation.
pub type Start = (usize, Vec<f64>, Option<(f64, Evaluation)>);

/// One run's state between rounds.
struct Run {
    placement: usize,
    x0: Vec<f64>,
    simplex: Option<Simplex>,
    best: Mutex<Best>,
    count: AtomicU64,
    end: Option<Ended>,
}

/// What every run's objective reads.
struct Shared<'a> {
    problem: &'a Problem,
    bare: &'a [Vec<f64>],
    space: &'a Space,
    check: &'a (dyn Fn() + Sync),
    halt: &'a Halt,
    stopped: &'a AtomicBool,
}

impl Shared<'_> {
    /// The objective of `x` for the run's placement (a point that cannot be computed is
    /// +1e300), or the halt; infinity where the evaluation ended once it showed the objective
    /// above `cap` ([`evaluate_below`]: the comparison Nelder-Mead makes with it, which then
    /// needs no value; such a point is never the run's best).
    fn cost(&self, run: (&[usize], &AtomicU64, &Mutex<Best>), x: &[f64], cap: f64) -> Result<f64, TimeLimit> {
        let (hosts, count, best) = run;
        if self.halt.reached() {
            self.stopped.store(true, Ordering::Relaxed);
            return Err(TimeLimit);
        }
        count.fetch_add(1, Ordering::Relaxed);
        (self.check)();
        let layout = layout(hosts, x, self.space);
        let Some(e) = self.halt.timed_whole(|| evaluate_below(self.problem, self.bare, &layout, cap)) else {
            return Ok(f64::INFINITY);
        };
        let objective = if e.objective.is_finite() { e.objective } else { 1e300 };
        if let Ok(mut best) = best.lock() {
            if best.as_ref().is_none_or(|b| objective < b.1) {
                *best = Some((x.to_vec(), objective, e));
            }
        }
        Ok(objective)
    }

    /// One round of `run`: its simplex evaluated if it has none yet, then at most
    /// [`ROUND_ITERATIONS`] iterations.
    fn round(&self, run: &mut Run, opts: &Options) {
        let Run { placement, x0, simplex, best, count, end } = run;
        let hosts = &self.space.placements[*placement];
        let cost = |x: &[f64], cap: f64| self.cost((hosts, count, best), x, cap);
        let settings =
            Settings { max_iters: opts.max_iters, sd_tolerance: opts.tolerance, step_tolerance: opts.step_tolerance };
        if simplex.is_none() {
            let d = x0.len();
            let mut vertices = vec![x0.clone()];
            for i in 0..d {
                let mut v = x0.clone();
                v[i] += 1.0;
                vertices.push(v);
            }
            match Simplex::new(cost, vertices) {
                Ok(s) => *simplex = Some(s),
                Err(TimeLimit) => {
                    *end = Some(Ended::Stopped);
                    return;
                }
            }
        }
        let Some(s) = simplex.as_mut() else { return };
        *end = match s.advance(cost, &settings, ROUND_ITERATIONS) {
            Ok(Some(End::Converged)) => Some(Ended::Converged),
            Ok(Some(End::Iterations)) => Some(Ended::Iterations),
            Ok(None) => None,
            Err(TimeLimit) => Some(Ended::Stopped),
        };
    }
}

/// Tells the halt's outlook what the runs going on are expected to need still: what a start
/// of their size usually needs less what each has done; a run already past that is expected
/// to spend its iterations (a noisy objective) at its own evaluations per iteration.
fn outlook(runs: &[Run], opts: &Options, halt: &Halt) {
    let left = runs
        .iter()
        .filter(|r| r.end.is_none())
        .map(|r| {
            let done = r.count.load(Ordering::Relaxed);
            let usual = super::space::expected_per_start(r.x0.len(), opts, super::space::EXPECTED_C[1]);
            let iterations = r.simplex.as_ref().map_or(0, Simplex::iterations);
            if done < usual || iterations == 0 {
                return usual.saturating_sub(done).max(1);
            }
            let per = done as f64 / iterations as f64;
            (opts.max_iters.saturating_sub(iterations) as f64 * per).ceil() as u64
        })
        .sum();
    halt.expect(left);
}

/// Runs Nelder-Mead from each `(placement, start)` of `starts` on `problem` (initial simplex:
/// steps of 1 along each coordinate), in rounds, until every run has ended or `halt` stops
/// them; calls `check` before every evaluation. A stopped run keeps the best point it
/// evaluated (its start when it evaluated none: of the objective given with it, else unknown). In the order of
/// `starts`; the same numbers for any number of threads.
pub fn run_all(
    (problem, bare): (&Problem, &[Vec<f64>]),
    space: &Space,
    opts: &Options,
    check: &(dyn Fn() + Sync),
    halt: &Halt,
    starts: Vec<Start>,
    stopped: &AtomicBool,
) -> Vec<(usize, RunEnd)> {
    let shared = Shared { problem, bare, space, check, halt, stopped };
    let mut runs: Vec<Run> = starts
        .into_iter()
        .map(|(placement, x0, known)| Run {
            placement,
            best: Mutex::new(known.map(|(o, e)| (x0.clone(), o, e))),
            x0,
            simplex: None,
            count: AtomicU64::new(0),
            end: None,
        })
        .collect();
    outlook(&runs, opts, halt);
    while runs.iter().any(|r| r.end.is_none()) {
        runs.par_iter_mut().filter(|r| r.end.is_none()).for_each(|r| shared.round(r, opts));
        outlook(&runs, opts, halt);
    }
    runs.into_iter()
        .map(|r| {
            let evaluations = r.count.load(Ordering::Relaxed);
            let ended = r.end.unwrap_or(Ended::Stopped);
            let kept = r.best.into_inner().ok().flatten();
            let end = match (r.simplex, ended) {
                (Some(s), Ended::Converged | Ended::Iterations) => {
                    let (x, objective) = s.best().clone();
                    // The run's best vertex is the best point it evaluated, whose evaluation
                    // was kept (the same point, bit for bit, or it is evaluated again later).
                    let evaluation = kept.filter(|k| k.0 == x).map(|k| k.2);
                    RunEnd { x, objective, evaluations, ended, evaluation }
                }
                _ => match kept {
                    Some((x, objective, e)) => RunEnd { x, objective, evaluations, ended, evaluation: Some(e) },
                    None => RunEnd { x: r.x0, objective: f64::INFINITY, evaluations, ended, evaluation: None },
                },
            };
            (r.placement, end)
        })
        .collect()
}
