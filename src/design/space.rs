//! What a design search ranges over and what it costs: the space of layouts (placements of
//! containers on the candidate masses, the shot's split and the clearances within their
//! bounds), the search's options, the map from a simplex's free coordinates to a layout, and
//! the counts of evaluations a search makes at most and usually. Below the search
//! ([`super::search`]) and its rounds ([`super::rounds`]), which both read it.

use super::Layout;

/// What may vary, and within which bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct Space {
    /// Placements to try: each a set of distinct 0-based host masses.
    pub placements: Vec<Vec<usize>>,
    /// Total shot mass, kg, split among a placement's containers.
    pub shot_kg: f64,
    /// Bounds of the clearance, mm (`0 < lo < hi`, finite).
    pub clearance_mm: (f64, f64),
    /// One clearance for every container (else one each).
    pub shared_clearance: bool,
}

/// Search settings.
#[derive(Clone, Copy, PartialEq)]
pub struct Options {
    /// Starts per placement: the first at an even split and the best clearance of a coarse
    /// scan, the others seeded.
    pub starts: usize,
    /// Nelder-Mead iterations per start.
    pub max_iters: u64,
    /// Stop a start when the standard deviation of the simplex's objectives falls below this.
    pub tolerance: f64,
    /// Seed of the starts' perturbations (the same seed, the same answer).
    pub seed: u64,
    /// Stop a start when every vertex of its simplex lies within this of the best one in each
    /// free coordinate (0: never; [`super::nelder_mead`]).
    pub step_tolerance: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options { starts: 3, max_iters: 100, tolerance: 1e-6, seed: 1, step_tolerance: 0.0 }
    }
}

/// As derived, without `step_tolerance` when it is 0: the text is part of a stored design's
/// fingerprint, and the answers stored before the key existed stay valid.
impl std::fmt::Debug for Options {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("Options");
        d.field("starts", &self.starts)
            .field("max_iters", &self.max_iters)
            .field("tolerance", &self.tolerance)
            .field("seed", &self.seed);
        if self.step_tolerance != 0.0 {
            d.field("step_tolerance", &self.step_tolerance);
        }
        d.finish()
    }
}

/// Every non-empty subset of `masses` with at most `max` elements, smallest first, each in
/// ascending order.
pub fn placements(masses: &[usize], max: usize) -> Vec<Vec<usize>> {
    let mut sorted = masses.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let n = sorted.len();
    let mut out: Vec<Vec<usize>> = (1u64..(1 << n))
        .filter(|mask| (mask.count_ones() as usize) <= max)
        .map(|mask| (0..n).filter(|i| mask & (1 << i) != 0).map(|i| sorted[i]).collect())
        .collect();
    out.sort_by(|a, b| a.len().cmp(&b.len()).then(a.cmp(b)));
    out
}

/// The number of free coordinates of a placement of `k` containers.
pub fn dimension(k: usize, space: &Space) -> usize {
    (k - 1) + if space.shared_clearance { 1 } else { k }
}

/// The most layout evaluations one search of `space` can make with `opts`: per placement the
/// coarse scan, each start's initial simplex and at most `d + 2` evaluations per Nelder-Mead
/// iteration (a reflection, an expansion or contraction, or a shrink of `d` points), and the
/// final evaluation of its best layout. Searches stop far earlier when the simplex's
/// objectives agree to the tolerance: this bounds, it does not predict.
pub fn most_evaluations(space: &Space, opts: &Options) -> u64 {
    space
        .placements
        .iter()
        .map(|hosts| {
            let d = dimension(hosts.len(), space) as u64;
            let per_start = (d + 1).saturating_add(opts.max_iters.saturating_mul(d + 2));
            (COARSE.len() as u64 + 1).saturating_add((opts.starts.max(1) as u64).saturating_mul(per_start))
        })
        .fold(0u64, u64::saturating_add)
}

/// The constant `c` of the evaluations a Nelder-Mead start of `d` free coordinates usually
/// makes, `c (d + 1)^2`: low, middle and high. Measured over whole designs (the evaluations of
/// every placement of the shipped designs' stored answers): 2.3-2.8 on the third-mode,
/// five-storey and plate designs, 5.6-7.2 on the all-modes design (three bands, a rougher
/// objective). An estimate, not a bound ([`most_evaluations`] bounds).
pub const EXPECTED_C: [f64; 3] = [2.0, 4.0, 8.0];

/// The evaluations a start of `d` free coordinates usually makes at `c` ([`EXPECTED_C`]),
/// at most its bound.
pub fn expected_per_start(d: usize, opts: &Options, c: f64) -> u64 {
    let d1 = (d + 1) as f64;
    let most = ((d + 1) as u64).saturating_add(opts.max_iters.saturating_mul(d as u64 + 2));
    ((c * d1 * d1).ceil() as u64).min(most)
}

/// The evaluations one search of `space` usually makes, at each `c` of [`EXPECTED_C`]: per
/// placement the coarse scan and each start's [`expected_per_start`].
pub fn expected_evaluations(space: &Space, opts: &Options) -> [u64; 3] {
    EXPECTED_C.map(|c| {
        space
            .placements
            .iter()
            .map(|hosts| {
                let d = dimension(hosts.len(), space);
                COARSE.len() as u64 + opts.starts.max(1) as u64 * expected_per_start(d, opts, c)
            })
            .sum()
    })
}

/// Evaluations a Nelder-Mead iteration makes on average when a start spends all its
/// iterations, low and high (a reflection and often an expansion or a contraction; a shrink,
/// `d` more, is rare).
pub const SPENT_PER_ITERATION: [f64; 2] = [1.0, 2.5];

/// The evaluations one search of `space` makes when its starts spend their iterations (an
/// objective whose points never settle is noisy, and a simplex without `step_tolerance` may
/// never agree to its tolerance): low and high ([`SPENT_PER_ITERATION`]), at most the bound.
pub fn spent_evaluations(space: &Space, opts: &Options) -> [u64; 2] {
    SPENT_PER_ITERATION.map(|per| {
        space
            .placements
            .iter()
            .map(|hosts| {
                let d = dimension(hosts.len(), space) as u64;
                let most = (d + 1).saturating_add(opts.max_iters.saturating_mul(d + 2));
                let start = ((d + 1) as f64 + opts.max_iters as f64 * per).ceil() as u64;
                COARSE.len() as u64 + opts.starts.max(1) as u64 * start.min(most)
            })
            .sum()
    })
}

fn sigmoid(z: f64) -> f64 {
    1.0 / (1.0 + (-z).exp())
}

/// The layout of free coordinates `x` for `hosts`: shares by a softmax of `(0, x_1..x_{k-1})`,
/// clearances `lo (hi/lo)^sigmoid(z)` (every coordinate maps into the bounds).
pub fn layout(hosts: &[usize], x: &[f64], space: &Space) -> Layout {
    let k = hosts.len();
    let logits: Vec<f64> = std::iter::once(0.0).chain(x[..k - 1].iter().copied()).collect();
    let top = logits.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let w: Vec<f64> = logits.iter().map(|l| (l - top).exp()).collect();
    let sum: f64 = w.iter().sum();
    let (lo, hi) = space.clearance_mm;
    let clearance = |z: f64| lo * (hi / lo).powf(sigmoid(z));
    let clearances_mm = if space.shared_clearance {
        vec![clearance(x[k - 1]); k]
    } else {
        x[k - 1..].iter().map(|&z| clearance(z)).collect()
    };
    Layout { hosts: hosts.to_vec(), masses_kg: w.iter().map(|wi| space.shot_kg * wi / sum).collect(), clearances_mm }
}

/// Clearance coordinates of the coarse scan that places the first start: the objective is
/// flat wherever the beds no longer reach the top (the clearance then acts as none), so a
/// simplex started there may never see the clearances that matter.
pub const COARSE: [f64; 7] = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0];
