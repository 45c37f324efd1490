//! Runs the experiments of a report on the thread pool as soon as the experiments whose exports
//! they use have finished, the longest chain of dependents first (the Fig. 5 clearance scan
//! before the independent figures, so the experiments that use its clearance start early).
//! Every experiment computes the same numbers whatever the order: only the wall time changes.

use std::collections::BinaryHeap;
use std::sync::{Mutex, MutexGuard};

use crate::analysis::{self, ExperimentResult, Progress};
use crate::checks::reference::ReferenceStore;
use crate::checks::Status;
use crate::experiment::{Experiment, Exports};
use crate::output::ReportWriter;

/// An experiment whose dependencies have finished, ordered so that the heap pops the longest
/// chain of dependents first, then the larger expected work, then the earlier file.
#[derive(PartialEq, Eq, PartialOrd, Ord)]
struct Ready {
    chain: usize,
    work: u64,
    first: std::cmp::Reverse<usize>,
}

/// What the running experiments share.
struct Board {
    ready: BinaryHeap<Ready>,
    /// Per experiment: dependencies not yet finished.
    missing: Vec<usize>,
    exports: Exports,
    slots: Vec<Option<ExperimentResult>>,
    error: Option<crate::Error>,
}

/// What every task reads.
struct Plan<'a> {
    exps: &'a [Experiment],
    dependents: Vec<Vec<usize>>,
    chain: Vec<usize>,
    work: Vec<u64>,
    refs: &'a ReferenceStore,
    writer: &'a ReportWriter,
    progress: &'a dyn Progress,
    log: &'a (dyn Fn(String) + Sync),
    board: Mutex<Board>,
}

impl Plan<'_> {
    fn board(&self) -> MutexGuard<'_, Board> {
        // A panicking experiment propagates through the pool; the board stays readable.
        self.board.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn ready(&self, i: usize) -> Ready {
        Ready { chain: self.chain[i], work: self.work[i], first: std::cmp::Reverse(i) }
    }
}

/// Runs every experiment on `pool`, writing each one's folder as it finishes; the results in
/// the order of `exps`. `graph` is [`crate::experiment::loader::dependency_graph`] of `exps`. The
/// first error stops new experiments from starting and is returned.
pub fn run(
    exps: &[Experiment],
    graph: &[Vec<usize>],
    refs: &ReferenceStore,
    writer: &ReportWriter,
    pool: &rayon::ThreadPool,
    progress: &dyn Progress,
    log: &(dyn Fn(String) + Sync),
) -> crate::Result<Vec<ExperimentResult>> {
    let mut dependents = vec![Vec::new(); exps.len()];
    for (i, deps) in graph.iter().enumerate() {
        for &d in deps {
            dependents[d].push(i);
        }
    }
    let chain = chain_lengths(&dependents);
    let work = exps.iter().map(|e| analysis::work(e, refs)).collect();
    let missing: Vec<usize> = graph.iter().map(Vec::len).collect();
    let plan = Plan {
        exps,
        dependents,
        chain,
        work,
        refs,
        writer,
        progress,
        log,
        board: Mutex::new(Board {
            ready: BinaryHeap::new(),
            missing: missing.clone(),
            exports: Exports::new(),
            slots: vec![None; exps.len()],
            error: None,
        }),
    };
    let first: Vec<usize> = (0..exps.len()).filter(|&i| missing[i] == 0).collect();
    plan.board().ready.extend(first.iter().map(|&i| plan.ready(i)));
    pool.scope(|s| {
        for _ in &first {
            s.spawn(|s| next(s, &plan));
        }
    });
    let board = plan.board.into_inner().unwrap_or_else(|e| e.into_inner());
    if let Some(e) = board.error {
        return Err(e);
    }
    Ok(board.slots.into_iter().flatten().collect())
}

/// Longest chain of dependents below each experiment (0: nothing uses its exports). The graph
/// is acyclic ([`crate::experiment::loader::dependency_graph`] checked it).
fn chain_lengths(dependents: &[Vec<usize>]) -> Vec<usize> {
    fn length(i: usize, dependents: &[Vec<usize>], memo: &mut [Option<usize>]) -> usize {
        if let Some(l) = memo[i] {
            return l;
        }
        let l = dependents[i].iter().map(|&j| 1 + length(j, dependents, memo)).max().unwrap_or(0);
        memo[i] = Some(l);
        l
    }
    let mut memo = vec![None; dependents.len()];
    (0..dependents.len()).map(|i| length(i, dependents, &mut memo)).collect()
}

/// One task: runs the best ready experiment, then spawns one task per experiment it made ready
/// (every task pops exactly one, so the heap is never empty when a task starts).
fn next<'s>(s: &rayon::Scope<'s>, plan: &'s Plan<'s>) {
    let (i, exp) = {
        let mut board = plan.board();
        if board.error.is_some() {
            return;
        }
        let Some(Ready { first: std::cmp::Reverse(i), .. }) = board.ready.pop() else { return };
        match plan.exps[i].resolve(&board.exports) {
            Ok(exp) => (i, exp),
            Err(e) => {
                board.error = Some(e);
                return;
            }
        }
    };
    let outcome = run_one(plan, &exp, plan.work[i]);
    let mut board = plan.board();
    let r = match outcome {
        Ok(r) => r,
        Err(e) => {
            board.error.get_or_insert(e);
            return;
        }
    };
    board.exports.insert(r.experiment.key(), r.exports.clone());
    board.slots[i] = Some(r);
    let mut spawn = 0;
    for &j in &plan.dependents[i] {
        board.missing[j] -= 1;
        if board.missing[j] == 0 {
            let ready = plan.ready(j);
            board.ready.push(ready);
            spawn += 1;
        }
    }
    drop(board);
    for _ in 0..spawn {
        s.spawn(|s| next(s, plan));
    }
}

/// Runs one experiment (`work` points for its progress bar) and writes its folder.
fn run_one(plan: &Plan<'_>, exp: &Experiment, work: u64) -> crate::Result<ExperimentResult> {
    let started = std::time::Instant::now();
    let tick = match exp.analysis.design() {
        // A search stops when it converges: its bound is all that is known ahead.
        Some((spec, _)) if !spec.replay => {
            let highest = exp.structure.highest_natural_frequency_hz();
            let most = spec.budget(exp.cases.len(), highest).evaluations;
            plan.progress.start_search(&exp.key(), most, spec.halt.outlook.clone())
        }
        _ => plan.progress.start(&exp.key(), work),
    };
    let r = analysis::run(exp, plan.refs, &*tick)?;
    plan.writer.write_experiment(&r)?;
    let n_fail = r.checks.iter().filter(|c| c.status == Status::Fail).count();
    let mark = if n_fail > 0 { "FAIL" } else { "ok" };
    (plan.log)(format!(
        "{mark:>4} {:<36} {} checks, {n_fail} failed ({:.2} s)",
        exp.key(),
        r.checks.len(),
        started.elapsed().as_secs_f64()
    ));
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_count_the_longest_path_of_dependents() {
        // 0 -> 1 -> 3, 0 -> 2, 4 alone: the scan, what uses it, what uses that.
        let dependents = vec![vec![1, 2], vec![3], vec![], vec![], vec![]];
        assert_eq!(chain_lengths(&dependents), vec![2, 1, 0, 0, 0]);
    }

    #[test]
    fn the_heap_pops_longer_chains_then_more_work_then_earlier_files() {
        let r = |chain, work, i| Ready { chain, work, first: std::cmp::Reverse(i) };
        let mut heap: BinaryHeap<Ready> = [r(0, 900, 0), r(2, 10, 5), r(0, 900, 3), r(1, 0, 1), r(0, 50, 2)].into();
        let order: Vec<usize> = std::iter::from_fn(|| heap.pop().map(|x| x.first.0)).collect();
        assert_eq!(order, vec![5, 1, 0, 3, 2]);
    }
}
