//! The lattice of an adaptive design (docs/studies.md, "Adaptive refinement"), pure index
//! arithmetic: each varied key has a fine grid of `2^levels * k + 1` values; round 0 takes
//! every `2^levels`-th value of each key; round `r` halves the step inside every cell of the
//! previous step whose corners do not all give the same answer, until the step is one grid
//! value. Everything else is inferred from the corners of the smallest cell that holds it and
//! agrees. The points of a round are a pure function of the answers of the rounds before it,
//! in grid order: the same for any number of threads or shards.

use std::collections::BTreeMap;

/// A point of the fine grid: one index per varied key.
pub type Point = Vec<usize>;

/// The fine grid of an adaptive design.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Lattice {
    /// Values per key (each `2^levels * k + 1`, `k >= 1`).
    pub sizes: Vec<usize>,
    /// Halvings of the step after round 0.
    pub levels: u32,
}

impl Lattice {
    /// The lattice of keys with `sizes` values, or why it cannot be one: the index of the
    /// first key whose number of values is not `2^levels * k + 1`.
    pub fn new(sizes: Vec<usize>, levels: u32) -> std::result::Result<Lattice, usize> {
        let step = 1usize.checked_shl(levels).unwrap_or(0);
        match sizes.iter().position(|&n| step == 0 || n < step + 1 || (n - 1) % step != 0) {
            Some(k) => Err(k),
            None => Ok(Lattice { sizes, levels }),
        }
    }

    /// Rounds: the coarse grid and one per halving.
    pub fn rounds(&self) -> u32 {
        self.levels + 1
    }

    /// The step of round `round` in grid values.
    pub fn stride(&self, round: u32) -> usize {
        1 << (self.levels - round.min(self.levels))
    }

    /// Points of the full fine grid.
    pub fn grid_size(&self) -> usize {
        self.sizes.iter().product()
    }

    /// Round 0: every point on the coarse step, in grid order (first key slowest).
    pub fn coarse(&self) -> Vec<Point> {
        let s = self.stride(0);
        let axes: Vec<Vec<usize>> = self.sizes.iter().map(|&n| (0..n).step_by(s).collect()).collect();
        product(&axes)
    }

    /// The points round `round` (1 or more) adds, in grid order: inside every cell of the
    /// previous round's step whose corners are all known and do not all agree, each point on
    /// this round's step not known yet.
    pub fn refine<S: PartialEq>(&self, round: u32, known: &BTreeMap<Point, S>) -> Vec<Point> {
        if round == 0 || round > self.levels {
            return Vec::new();
        }
        let cell = self.stride(round - 1);
        let half = cell / 2;
        let mut out = std::collections::BTreeSet::new();
        for corner in known.keys().filter(|p| self.is_lower_corner(p, cell)) {
            if self.agree(corner, cell, known).is_some() {
                continue;
            }
            let Some(_) = self.corners(corner, cell).iter().map(|c| known.get(c)).collect::<Option<Vec<_>>>() else {
                continue;
            };
            let axes: Vec<Vec<usize>> = corner.iter().map(|&c| vec![c, c + half, c + cell]).collect();
            for p in product(&axes) {
                if !known.contains_key(&p) {
                    out.insert(p);
                }
            }
        }
        out.into_iter().collect()
    }

    /// The answer at every point of the fine grid, in grid order, with whether it was
    /// computed (`true`) or inferred from the corners of the smallest agreeing cell. `None`
    /// where neither holds (a point of a cell that was not refined because a corner was not
    /// known: only when `known` is not the outcome of the rounds).
    pub fn infer<S: Clone + PartialEq>(&self, known: &BTreeMap<Point, S>) -> Vec<(Point, Option<(S, bool)>)> {
        let axes: Vec<Vec<usize>> = self.sizes.iter().map(|&n| (0..n).collect()).collect();
        product(&axes)
            .into_iter()
            .map(|p| {
                let found = self.inferred(&p, known);
                (p, found)
            })
            .collect()
    }

    fn inferred<S: Clone + PartialEq>(&self, p: &Point, known: &BTreeMap<Point, S>) -> Option<(S, bool)> {
        if let Some(s) = known.get(p) {
            return Some((s.clone(), true));
        }
        for round in 0..self.levels {
            let s = self.stride(round);
            let corner: Point = p.iter().zip(&self.sizes).map(|(&x, &n)| (x / s * s).min(n - 1 - s)).collect();
            if let Some(v) = self.agree(&corner, s, known) {
                return Some((v.clone(), false));
            }
        }
        None
    }

    /// The common answer of a cell's corners, when all are known and agree.
    fn agree<'a, S: PartialEq>(&self, corner: &Point, cell: usize, known: &'a BTreeMap<Point, S>) -> Option<&'a S> {
        let mut first: Option<&S> = None;
        for c in self.corners(corner, cell) {
            let v = known.get(&c)?;
            match first {
                None => first = Some(v),
                Some(f) if f != v => return None,
                Some(_) => {}
            }
        }
        first
    }

    fn is_lower_corner(&self, p: &Point, cell: usize) -> bool {
        p.iter().zip(&self.sizes).all(|(&x, &n)| x % cell == 0 && x + cell < n)
    }

    fn corners(&self, corner: &Point, cell: usize) -> Vec<Point> {
        let axes: Vec<Vec<usize>> = corner.iter().map(|&c| vec![c, c + cell]).collect();
        product(&axes)
    }
}

/// Every combination of the axes' values, the first axis slowest.
fn product(axes: &[Vec<usize>]) -> Vec<Point> {
    let mut out: Vec<Point> = vec![Vec::new()];
    for a in axes {
        out = out.iter().flat_map(|p| a.iter().map(move |&v| [p.as_slice(), &[v]].concat())).collect();
    }
    out
}

/// The rounds of an adaptive design over `models` models (each refined on its own), driven
/// by `evaluate`, which is given a round's samples (model, point) in order and returns their
/// answers in the same order. Returns the points computed, per model, with their answers and
/// rounds.
pub fn run<S, E, F>(
    lattice: &Lattice,
    models: usize,
    mut evaluate: F,
) -> std::result::Result<Vec<BTreeMap<Point, S>>, E>
where
    S: PartialEq,
    F: FnMut(u32, &[(usize, Point)]) -> std::result::Result<Vec<S>, E>,
{
    let mut known: Vec<BTreeMap<Point, S>> = (0..models).map(|_| BTreeMap::new()).collect();
    for round in 0..lattice.rounds() {
        let todo = round_points(lattice, round, &known);
        if todo.is_empty() {
            break;
        }
        let answers = evaluate(round, &todo)?;
        for ((m, p), s) in todo.into_iter().zip(answers) {
            known[m].insert(p, s);
        }
    }
    Ok(known)
}

/// The samples (model, point) of round `round`, models outermost, given what the rounds before
/// it found.
pub fn round_points<S: PartialEq>(lattice: &Lattice, round: u32, known: &[BTreeMap<Point, S>]) -> Vec<(usize, Point)> {
    if round == 0 {
        let coarse = lattice.coarse();
        return (0..known.len()).flat_map(|m| coarse.iter().map(move |p| (m, p.clone()))).collect();
    }
    known.iter().enumerate().flat_map(|(m, k)| lattice.refine(round, k).into_iter().map(move |p| (m, p))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_must_fit_the_levels() {
        assert!(Lattice::new(vec![17, 33], 3).is_ok());
        assert_eq!(Lattice::new(vec![17, 32], 3), Err(1));
        assert_eq!(Lattice::new(vec![5, 9], 3), Err(0));
        assert_eq!(Lattice::new(vec![9], 64), Err(0));
        let l = Lattice::new(vec![9, 17], 3).unwrap();
        assert_eq!(l.coarse(), vec![vec![0, 0], vec![0, 8], vec![0, 16], vec![8, 0], vec![8, 8], vec![8, 16]]);
        assert_eq!(l.stride(0), 8);
        assert_eq!(l.stride(3), 1);
    }

    /// A claim that holds on one side of a straight line in two keys: the rounds find every
    /// point of the fine grid on its side, with a fraction of the grid's samples.
    #[test]
    fn a_straight_boundary_is_located_to_one_grid_step_with_few_samples() {
        let lattice = Lattice::new(vec![65, 65], 4).unwrap();
        let truth = |p: &Point| 3.0 * p[0] as f64 + 7.0 * p[1] as f64 > 250.0;
        let mut rounds = Vec::new();
        let known = run::<_, (), _>(&lattice, 1, |round, todo| {
            rounds.push((round, todo.len()));
            Ok(todo.iter().map(|(_, p)| truth(p)).collect())
        })
        .unwrap();
        let computed = known[0].len();
        let inferred = lattice.infer(&known[0]);
        assert_eq!(inferred.len(), 65 * 65);
        let wrong = inferred.iter().filter(|(p, v)| v.as_ref().map(|v| v.0) != Some(truth(p))).count();
        assert_eq!(wrong, 0, "every point of the fine grid on its side");
        // The boundary is resolved to one step: on every row, the last point that fails and
        // the first that holds are both computed.
        for x in 0..65 {
            let row: Vec<&(Point, Option<(bool, bool)>)> = inferred.iter().filter(|(p, _)| p[0] == x).collect();
            if let Some(k) = row.iter().position(|(_, v)| v.is_some_and(|v| v.0)).filter(|&k| k > 0) {
                assert!(row[k].1.is_some_and(|v| v.1) && row[k - 1].1.is_some_and(|v| v.1), "row {x}");
            }
        }
        assert_eq!(rounds.len(), 5);
        assert_eq!(rounds[0], (0, 25));
        assert!(computed * 4 <= 65 * 65, "{computed} samples of a {} grid", 65 * 65);
    }

    #[test]
    fn agreeing_corners_stop_the_refinement_and_models_refine_apart() {
        let lattice = Lattice::new(vec![9, 9], 2).unwrap();
        let known = run::<_, (), _>(&lattice, 2, |_, todo| {
            Ok(todo.iter().map(|(m, p)| *m == 1 && p[0] >= 5 && p[1] >= 5).collect())
        })
        .unwrap();
        assert_eq!(known[0].len(), 9, "one answer everywhere: the coarse grid only");
        assert!(known[1].len() > 9);
        let inferred = lattice.infer(&known[1]);
        assert!(inferred.iter().all(|(p, v)| v.as_ref().map(|v| v.0) == Some(p[0] >= 5 && p[1] >= 5)));
    }

    #[test]
    fn each_round_adds_new_points_in_grid_order_inside_disagreeing_cells_only() {
        let lattice = Lattice::new(vec![17, 9, 5], 2).unwrap();
        let f = |p: &Point| (p[0] * p[0] + 2 * p[1] * p[1] + 3 * p[2]) / 40;
        let mut seen: Vec<Point> = Vec::new();
        let known = run::<_, (), _>(&lattice, 1, |round, todo| {
            let points: Vec<Point> = todo.iter().map(|(_, p)| p.clone()).collect();
            // Sorted, no point twice, none computed in an earlier round.
            assert!(points.windows(2).all(|w| w[0] < w[1]), "round {round} not in grid order");
            assert!(points.iter().all(|p| !seen.contains(p)), "round {round} repeats a point");
            // Every point of round r >= 1 lies on its step, inside a cell of the step before.
            let step = lattice.stride(round);
            assert!(points.iter().all(|p| p.iter().all(|x| x % step == 0)), "round {round} off its step");
            if round > 0 {
                let cell = 2 * step;
                for p in &points {
                    let corner: Point =
                        p.iter().zip(&lattice.sizes).map(|(&x, &n)| (x / cell * cell).min(n - 1 - cell)).collect();
                    let answers: Vec<usize> = lattice.corners(&corner, cell).iter().map(f).collect();
                    let disagree = answers.iter().any(|a| *a != answers[0]);
                    // On a face two cells share a point: either may be the one that disagrees.
                    let on_face = p.iter().any(|x| x % cell == 0);
                    assert!(disagree || on_face, "round {round}: {p:?} in a cell whose corners agree");
                }
            }
            seen.extend(points);
            Ok(todo.iter().map(|(_, p)| f(p)).collect())
        })
        .unwrap();
        assert_eq!(known[0].len(), seen.len());
        // Wherever the rounds stopped, the corners agreed: the inferred answer is theirs.
        for (p, v) in lattice.infer(&known[0]) {
            let (answer, computed) = v.expect("every point known or inferred");
            if computed {
                assert_eq!(answer, f(&p));
            }
        }
    }
}
