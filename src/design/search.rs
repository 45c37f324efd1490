//! The search over layouts: every placement of containers (subsets of the candidate masses)
//! enumerated; for each, the split of the shot and the clearances by Nelder-Mead from
//! several seeded starts in an unconstrained space that maps onto the bounds; and a brute-force
//! grid for checking it. Every run is sequential and independent, and results are gathered in
//! a fixed order: the same bytes for any number of threads.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::halt::Halt;
pub use super::rounds::Ended;
pub use super::space::{
    dimension, expected_evaluations, expected_per_start, layout, most_evaluations, placements, spent_evaluations,
    Options, Space, COARSE, EXPECTED_C, SPENT_PER_ITERATION,
};
use super::{evaluate, Evaluation, Layout, Problem};

/// The best layout found for one placement, and how it was found.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// The layout.
    pub layout: Layout,
    /// Its evaluation.
    pub evaluation: Evaluation,
    /// Free coordinates of the best point.
    pub x: Vec<f64>,
    /// Starts run and objective evaluations made.
    pub starts: usize,
    /// Objective evaluations made.
    pub evaluations: u64,
    /// The layout's objective on the model the search ran on, where that was a coarser one
    /// (`[design.screen]`; `None`: the search ran on the judged model).
    pub screened: Option<f64>,
    /// Whether `evaluation` is on the file's model. `false` only for a screened search that a
    /// time limit stopped before this placement's best was judged: `evaluation` is then the
    /// searched model's ([`found_until`]).
    pub judged: bool,
    /// How its search ended (`None`: not searched here, a stored answer replayed).
    pub ended: Option<Ended>,
}

/// A design problem with its bare structure's measures: what a layout is evaluated against.
pub type On<'a> = (&'a Problem, &'a [Vec<f64>]);

/// SplitMix64: the seeded perturbations of the starts.
fn splitmix(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// The starting points of a placement (deterministic in the seed and the placement).
fn starts(hosts: &[usize], space: &Space, opts: &Options) -> Vec<Vec<f64>> {
    let d = dimension(hosts.len(), space);
    let mut state = opts.seed ^ hosts.iter().fold(0u64, |h, m| h.wrapping_mul(31).wrapping_add(*m as u64 + 1));
    (0..opts.starts.max(1))
        .map(|s| if s == 0 { vec![0.0; d] } else { (0..d).map(|_| 4.0 * splitmix(&mut state) - 2.0).collect() })
        .collect()
}

/// The layout of the coarse scan of `hosts` at clearance coordinate `z` ([`COARSE`]): the shot
/// split evenly, every clearance `lo (hi/lo)^sigmoid(z)`.
pub fn coarse_layout(hosts: &[usize], z: f64, space: &Space) -> Layout {
    let d = dimension(hosts.len(), space);
    let mut x = vec![0.0; d];
    x[hosts.len() - 1..].iter_mut().for_each(|c| *c = z);
    layout(hosts, &x, space)
}

/// What a coarse scan ends with: the first start, the evaluations made, and the start's
/// objective and evaluation (when it was evaluated).
type Coarse = (Vec<f64>, u64, Option<(f64, Evaluation)>);

/// The first start of a placement: an even split and the best shared clearance of a coarse
/// scan ([`COARSE`]), and the layouts it evaluated. After `halt` only the middle clearance is
/// evaluated (each placement keeps one layout, the others are skipped).
fn coarse_start(
    problem: &Problem,
    bare: &[Vec<f64>],
    hosts: &[usize],
    space: &Space,
    check: &(dyn Fn() + Sync),
    halt: &Halt,
) -> Coarse {
    let d = dimension(hosts.len(), space);
    let k = hosts.len();
    let at = |z: f64| {
        let mut x = vec![0.0; d];
        x[k - 1..].iter_mut().for_each(|c| *c = z);
        x
    };
    let scored: Vec<Option<(f64, f64, Evaluation)>> = COARSE
        .par_iter()
        .map(|&z| {
            if z != 0.0 && halt.reached() {
                return None;
            }
            check();
            let e = halt.timed(|| evaluate(problem, bare, &layout(hosts, &at(z), space)));
            Some((z, if e.objective.is_finite() { e.objective } else { f64::INFINITY }, e))
        })
        .collect();
    // The lowest; of equal ones the first (the smallest clearance).
    let best = scored.iter().flatten().fold((0.0, f64::INFINITY), |b, (z, o, _)| if *o < b.1 { (*z, *o) } else { b });
    let count = scored.iter().flatten().count() as u64;
    // Its evaluation, with the objective as Nelder-Mead takes it (a point that cannot be
    // computed is +1e300): the first start's best until it evaluates a better one.
    let kept = scored.into_iter().flatten().find(|(z, _, _)| *z == best.0).map(|(_, o, e)| (o.min(1e300), e));
    (at(best.0), count, kept)
}

/// The best layout for each placement of `space`, in the order of `space.placements` (every
/// placement's starts run in parallel; each run is sequential). The first start of each
/// placement comes from a coarse scan of the clearance (`COARSE`), the others are seeded.
pub fn optimise(problem: &Problem, bare: &[Vec<f64>], space: &Space, opts: &Options) -> Vec<Found> {
    optimise_checked(problem, bare, space, opts, &|| {})
}

/// [`optimise`], calling `check` before every evaluation of a layout: a caller may stop the
/// search there by unwinding (the Python package's Ctrl-C). The answer does not depend on it.
pub fn optimise_checked(
    problem: &Problem,
    bare: &[Vec<f64>],
    space: &Space,
    opts: &Options,
    check: &(dyn Fn() + Sync),
) -> Vec<Found> {
    optimise_until((problem, bare), None, space, opts, check, &Halt::default()).0
}

/// [`optimise_checked`] that stops at its first evaluation after `halt` is reached: a coarse
/// scan not yet done evaluates only its middle clearance (each placement keeps one layout),
/// every Nelder-Mead run keeps the best point it evaluated. The searches run on `screen`
/// where given (a coarser model of the structure), each placement's best is then evaluated on
/// `judged`. Returns the layouts and whether the halt stopped the search or left a placement
/// unjudged (then they are the best found so far, not converged optima).
pub fn optimise_until(
    judged: On,
    screen: Option<On>,
    space: &Space,
    opts: &Options,
    check: &(dyn Fn() + Sync),
    halt: &Halt,
) -> (Vec<Found>, bool) {
    let (problem, bare) = screen.unwrap_or(judged);
    let (searched, stopped) = search_placements(problem, bare, space, opts, check, halt, &|_| true);
    let searched: Vec<Searched> = searched.into_iter().flatten().collect();
    let found = found_until(judged, screen, space, &searched, halt);
    // A placement the deadline left unjudged makes the answer partial too.
    let unjudged = found.iter().any(|f| !f.judged);
    (found, stopped || unjudged)
}

/// What the search of one placement ended with: its best point, the starts run and the
/// evaluations made. [`found`] makes it a [`Found`] (its layout evaluated again), so a shard of
/// a design hands these to the merge and the merged answer is the unsharded one.
#[derive(Debug, Clone, PartialEq)]
pub struct Searched {
    /// Free coordinates of the best point.
    pub x: Vec<f64>,
    /// Starts run.
    pub starts: usize,
    /// Objective evaluations made (the coarse scan's included).
    pub evaluations: u64,
    /// How it ended (`None`: not known, a part of a sharded search written before this was
    /// recorded).
    pub ended: Option<Ended>,
    /// The evaluation of `x` on the model searched, where the search kept it (not in a
    /// sharded search's parts): [`found`] then does not evaluate it again there.
    pub evaluation: Option<Evaluation>,
}

/// The search of the placements of `space` that `owned` accepts (by index), as
/// [`optimise_until`] searches them: `None` for the others. Each placement's search depends on
/// nothing but the placement, so any split of them gives the same numbers.
pub fn search_placements(
    problem: &Problem,
    bare: &[Vec<f64>],
    space: &Space,
    opts: &Options,
    check: &(dyn Fn() + Sync),
    halt: &Halt,
    owned: &(dyn Fn(usize) -> bool + Sync),
) -> (Vec<Option<Searched>>, bool) {
    let stopped = AtomicBool::new(false);
    let mine: Vec<usize> = (0..space.placements.len()).filter(|&p| owned(p)).collect();
    let per_start = |p: usize| expected_per_start(dimension(space.placements[p].len(), space), opts, EXPECTED_C[1]);
    halt.expect(mine.iter().map(|&p| COARSE.len() as u64 + opts.starts.max(1) as u64 * per_start(p)).sum());
    let firsts: Vec<Coarse> =
        mine.par_iter().map(|&p| coarse_start(problem, bare, &space.placements[p], space, check, halt)).collect();
    let runs: Vec<super::rounds::Start> = mine
        .iter()
        .zip(&firsts)
        .flat_map(|(&p, first)| {
            let hosts = &space.placements[p];
            let mut xs = starts(hosts, space, opts);
            xs[0] = first.0.clone();
            xs.into_iter().enumerate().map(move |(k, x)| (p, x, if k == 0 { first.2.clone() } else { None }))
        })
        .collect();
    let results = super::rounds::run_all((problem, bare), space, opts, check, halt, runs, &stopped);
    let stopped = stopped.load(Ordering::Relaxed) || firsts.iter().any(|f| (f.1 as usize) < COARSE.len());
    let mine_index = |p: usize| mine.iter().position(|&q| q == p);
    let mut results: Vec<Option<(usize, super::rounds::RunEnd)>> = results.into_iter().map(Some).collect();
    let searched = space
        .placements
        .iter()
        .enumerate()
        .map(|(p, hosts)| {
            if !owned(p) {
                return None;
            }
            let mine: Vec<super::rounds::RunEnd> = results
                .iter_mut()
                .filter(|r| r.as_ref().is_some_and(|r| r.0 == p))
                .filter_map(|r| r.take())
                .map(|r| r.1)
                .collect();
            let scanned = mine_index(p).map_or(0, |i| firsts[i].1);
            let evaluations = mine.iter().map(|r| r.evaluations).sum::<u64>() + scanned;
            let ended = mine.iter().map(|r| r.ended).reduce(Ended::worst).unwrap_or(Ended::Stopped);
            let starts = mine.len();
            // The lowest objective; of equal ones the first start's.
            let best = mine.into_iter().reduce(|b, r| if b.objective <= r.objective { b } else { r });
            let (x, evaluation) = match best {
                Some(b) => (b.x, b.evaluation),
                None => (vec![0.0; dimension(hosts.len(), space)], None),
            };
            Some(Searched { x, starts, evaluations, ended: Some(ended), evaluation })
        })
        .collect();
    (searched, stopped)
}

/// The placement with the lowest objective; of equal ones the first.
pub fn lowest(found: Vec<Found>) -> Option<Found> {
    // A layout judged on the file's model before one that was not (a stopped screened search).
    let any_judged = found.iter().any(|f| f.judged);
    found.into_iter().filter(|f| f.judged || !any_judged).reduce(|a, x| {
        if a.evaluation.objective <= x.evaluation.objective {
            a
        } else {
            x
        }
    })
}

/// The best layout of each placement of `space` from what its search ended with (`searched`,
/// one per placement in order): the layout at its best point, evaluated again on `judged`
/// (and on `screen`, the model searched, where that was a coarser one). In parallel, gathered
/// in order.
pub fn found(judged: On, screen: Option<On>, space: &Space, searched: &[Searched]) -> Vec<Found> {
    let (problem, bare) = judged;
    space
        .placements
        .par_iter()
        .zip(searched)
        .map(|(hosts, s)| {
            let layout = layout(hosts, &s.x, space);
            // The search's own evaluation of its best point, on the model it searched.
            let kept = s.evaluation.clone();
            let (evaluation, screened) = match screen {
                None => (kept.unwrap_or_else(|| evaluate(problem, bare, &layout)), None),
                Some((p, b)) => (
                    evaluate(problem, bare, &layout),
                    Some(kept.map_or_else(|| evaluate(p, b, &layout).objective, |e| e.objective)),
                ),
            };
            Found {
                layout,
                evaluation,
                x: s.x.clone(),
                starts: s.starts,
                evaluations: s.evaluations,
                screened,
                judged: true,
                ended: s.ended,
            }
        })
        .collect()
}

/// [`found`] under a halt, for a screened search: every placement's best evaluated on the
/// screen, then judged on the file's model in the order of its screened objective (the most
/// promising first), a round of one evaluation a thread at a time, until the halt's deadline
/// (no round begun that the longest so far says would end past it) or interrupt. The first
/// round always runs: one evaluation a thread at a deadline, the most promising placement
/// alone after an interrupt (a batch system kills 30 s after its SIGTERM). A placement not
/// judged keeps its screen evaluation, marked ([`Found::judged`]). Without a screen or a
/// halt: [`found`].
pub fn found_until(judged: On, screen: Option<On>, space: &Space, searched: &[Searched], halt: &Halt) -> Vec<Found> {
    let Some((sp, sb)) = screen.filter(|_| halt.deadline.is_some() || halt.interrupt.is_some()) else {
        return found(judged, screen, space, searched);
    };
    let layouts: Vec<Layout> = space.placements.iter().zip(searched).map(|(h, s)| layout(h, &s.x, space)).collect();
    let on_screen: Vec<Evaluation> = layouts
        .par_iter()
        .zip(searched)
        .map(|(l, s)| s.evaluation.clone().unwrap_or_else(|| evaluate(sp, sb, l)))
        .collect();
    let mut order: Vec<usize> = (0..layouts.len()).collect();
    order.sort_by(|&a, &b| on_screen[a].objective.total_cmp(&on_screen[b].objective).then(a.cmp(&b)));
    let threads = rayon::current_num_threads().max(1);
    let mut on_file: Vec<Option<Evaluation>> = vec![None; layouts.len()];
    let per_round = if halt.interrupted() { 1 } else { threads };
    // The longest round so far: a round expected to end past the deadline, with the rounds
    // of what follows on the file's model (the drive levels) after it, is not begun.
    let mut longest = std::time::Duration::ZERO;
    let rounds_after = halt.after_judging().div_ceil(threads as u64) as u32;
    for (round, chunk) in order.chunks(per_round).enumerate() {
        let late = halt.deadline.is_some_and(|d| std::time::Instant::now() + longest * (1 + rounds_after) > d);
        if round > 0 && (halt.passed() || late) {
            break;
        }
        let started = std::time::Instant::now();
        let done: Vec<Evaluation> = chunk.par_iter().map(|&i| evaluate(judged.0, judged.1, &layouts[i])).collect();
        longest = longest.max(started.elapsed());
        for (&i, e) in chunk.iter().zip(done) {
            on_file[i] = Some(e);
        }
    }
    layouts
        .into_iter()
        .zip(searched)
        .zip(on_screen.into_iter().zip(on_file))
        .map(|((layout, s), (screen_eval, file_eval))| {
            let screened = Some(screen_eval.objective);
            let judged = file_eval.is_some();
            Found {
                layout,
                evaluation: file_eval.unwrap_or(screen_eval),
                x: s.x.clone(),
                starts: s.starts,
                evaluations: s.evaluations,
                screened,
                judged,
                ended: s.ended,
            }
        })
        .collect()
}

/// Every layout of a grid: for each placement, each clearance of `clearances_mm` (shared) and
/// each split of `shares` (fractions of the shot for the first `k - 1` containers, the rest to
/// the last; splits that do not leave the last a share of at least 0 are skipped). In order,
/// computed in parallel.
pub fn grid(
    problem: &Problem,
    bare: &[Vec<f64>],
    space: &Space,
    clearances_mm: &[f64],
    shares: &[f64],
) -> Vec<(Layout, Evaluation)> {
    let mut layouts = Vec::new();
    for hosts in &space.placements {
        let k = hosts.len();
        let mut splits: Vec<Vec<f64>> = vec![Vec::new()];
        for _ in 1..k {
            splits =
                splits.into_iter().flat_map(|s| shares.iter().map(move |&f| [s.clone(), vec![f]].concat())).collect();
        }
        for split in splits {
            let used: f64 = split.iter().sum();
            if used > 1.0 + 1e-12 {
                continue;
            }
            let fractions: Vec<f64> = split.iter().copied().chain(std::iter::once((1.0 - used).max(0.0))).collect();
            for &d in clearances_mm {
                layouts.push(Layout {
                    hosts: hosts.clone(),
                    masses_kg: fractions.iter().map(|f| f * space.shot_kg).collect(),
                    clearances_mm: vec![d; k],
                });
            }
        }
    }
    layouts
        .into_par_iter()
        .map(|l| {
            let e = evaluate(problem, bare, &l);
            (l, e)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placements_are_every_subset_up_to_the_limit_in_a_fixed_order() {
        assert_eq!(
            placements(&[2, 0, 1], 3),
            vec![vec![0], vec![1], vec![2], vec![0, 1], vec![0, 2], vec![1, 2], vec![0, 1, 2]]
        );
        assert_eq!(placements(&[0, 1, 2], 1), vec![vec![0], vec![1], vec![2]]);
    }

    #[test]
    fn free_coordinates_map_into_the_bounds_and_keep_the_shot() {
        let space = Space { placements: vec![], shot_kg: 0.2, clearance_mm: (0.05, 2.0), shared_clearance: false };
        for x in
            [vec![0.0, 0.0, 0.0, 0.0, 0.0], vec![30.0, -30.0, 50.0, -50.0, 0.3], vec![-1.0, 2.0, -700.0, 700.0, 1.0]]
        {
            let l = layout(&[0, 1, 2], &x, &space);
            assert!((l.shot_kg() - 0.2).abs() < 1e-15);
            assert!(l.masses_kg.iter().all(|m| *m >= 0.0));
            assert!(l.clearances_mm.iter().all(|d| (0.05..=2.0).contains(d)), "{:?}", l.clearances_mm);
        }
        // The origin: an even split and the geometric middle of the bounds.
        let l = layout(&[0, 2], &[0.0, 0.0], &Space { shared_clearance: true, ..space });
        assert_eq!(l.masses_kg, vec![0.1, 0.1]);
        assert!((l.clearances_mm[0] - (0.05f64 * 2.0).sqrt()).abs() < 1e-15);
    }
}
