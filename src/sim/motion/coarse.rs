//! Coarse windows of the event search on large structures (above
//! [`LARGE_ABOVE`](super::system::LARGE_ABOVE) degrees of freedom).
//!
//! The certified search ([`super::roots`]) steps through windows of an eighth of the shortest
//! period of the structure, so that the bound on each event function's fourth derivative
//! stays tight; on a finite-element model whose stiffest mode kept is a hundred times the
//! forcing frequency that is hundreds of windows a period, although the stiff modes carry
//! little of the motion once an impact's ringing has decayed. Here a window of level `k` is
//! `2^k` of those steps long and splits each function's terms at `|lambda| = max_rate / 2^k`:
//! the slow terms and the forced response keep their Taylor polynomial and its fourth
//! derivative's bound, the fast terms are bounded by their moduli from the window's start on
//! (they decay). A function is then at least its slow lower bound less the fast bound over the
//! whole window, and a window in which that stays positive for every watched function holds
//! no event: the search skips it whole. The search tries the coarsest level first, then finer
//! ones, and where none clears, it searches one ordinary window as before (the event is found
//! there, certified, exactly as without coarse windows). No event can be skipped: each skip
//! rests on a bound of the function, as each ordinary window does.

use super::roots::lower_root;
use super::segment::{Point, Segment, Split, Watch};
use super::system::{Dynamics, Levels, MAX_LEVELS};

/// Most ordinary windows the search goes through before it tries a coarse one again after
/// failed tries (where an impact's ringing keeps the stiff modes large, each try costs about
/// one ordinary window's evaluation).
pub const MAX_WAIT: usize = 2;

/// The coarsest level (an index into [`Levels::steps`]) whose window from `pt`, cut at
/// `left` seconds, certainly holds no zero of any of `watches`; `None` when none does.
pub fn clear_level(
    seg: &Segment,
    d: &Dynamics,
    watches: &[Watch],
    pt: &Point,
    levels: &Levels,
    left: f64,
) -> Option<usize> {
    let n = levels.steps.len().min(MAX_LEVELS);
    let mut clear = [true; MAX_LEVELS];
    let mut split = [Split::default(); MAX_LEVELS];
    let mut last = None;
    for w in watches {
        let Some((host, order, bound_order)) = w.reads() else {
            // A grain pair flies under gravity alone: its Taylor data is exact at every level.
            let t = w.compose(d, pt.t, [0.0; 4], 0.0);
            for (k, c) in clear[..n].iter_mut().enumerate() {
                *c = *c && lower_root(&t, levels.steps[k].dt.min(left)).is_none();
            }
            continue;
        };
        // A flying bed's two gaps read the same sums of its host, one after the other.
        if last != Some((host, order, bound_order)) {
            seg.derivs4_levels(d, pt, (host, order, bound_order), &levels.slow[..n], &mut split[..n]);
            last = Some((host, order, bound_order));
        }
        for (k, c) in clear[..n].iter_mut().enumerate() {
            if !*c {
                continue;
            }
            let mut t = w.compose(d, pt.t, split[k].x, split[k].bound4);
            t.h[0] -= split[k].fast;
            *c = lower_root(&t, levels.steps[k].dt.min(left)).is_none();
        }
        if !clear[..n].contains(&true) {
            return None;
        }
    }
    (0..n).rev().find(|&k| clear[k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::system::System;
    use crate::sim::motion::system::STEP_FRACTION;
    use std::f64::consts::PI;

    fn chain(n: usize) -> Dynamics {
        let s = Structure::chain(&vec![0.2; n], &vec![1e5; n], Damping::Rayleigh { alpha: 1.0, beta: 1e-5 });
        let sys = System::plastic(s, vec![Damper::new(n - 1, 0.02, Clearance::from_m(1e-3))], 0, 1.0);
        Dynamics::new(&sys, 2.0 * PI * 20.0).unwrap()
    }

    #[test]
    fn each_level_doubles_its_window_and_splits_the_terms_at_its_rate() {
        let d = chain(12);
        let max_rate = 2.0 * PI / d.min_period;
        for slot in 0..d.configs.len() {
            let (levels, lambda) = (d.levels(slot), &d.configs[slot].modes.lambda);
            assert!(lambda.windows(2).all(|w| w[0].norm() <= w[1].norm()), "terms ordered by rate");
            assert!(levels.steps.len() >= 3, "{} levels", levels.steps.len());
            for (k, (st, &slow)) in levels.steps.iter().zip(&levels.slow).enumerate() {
                let scale = (1u64 << (k + 1)) as f64;
                assert!((st.dt / (d.min_period * STEP_FRACTION * scale) - 1.0).abs() < 1e-12);
                assert!(st.dt <= STEP_FRACTION * 2.0 * PI / d.omega, "within an eighth of the forcing period");
                let rate = max_rate / scale;
                assert!(
                    lambda[..slow].iter().all(|l| l.norm() <= rate) && lambda[slow..].iter().all(|l| l.norm() > rate)
                );
            }
        }
        assert!(chain(8).levels(0).is_empty(), "none up to 8 degrees of freedom");
    }
}
