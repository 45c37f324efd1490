//! Which irregular points of a band are measured to the design's interval (docs/design.md,
//! "Points that cannot set the peak"). A band's peak measure rests on its highest point only:
//! every point without an orbit is first measured over a short screen ([`SCREEN`] periods),
//! and only those that may be the band's highest are then measured on to the design's
//! interval; the others keep their screen's statistic and wider interval. No I/O.

use rayon::prelude::*;

use super::{Band, INTERVAL_TOL};
use crate::sim::motion::system::{Dynamics, SetupError};
use crate::sim::settle::irregular;
use crate::sim::settle::statistic::Measure;
use crate::sim::settle::sweep::SweepPoint;
use crate::sim::SteadyOptions;

/// Periods of a screen record: about 113 kept after the alignment a record that short cuts (a
/// quarter of it, [`crate::sim::settle::statistic::ALIGN`] at most), eleven batches of ten
/// periods ([`crate::sim::settle::statistic::batches_for`]).
pub const SCREEN: usize = 150;

/// A screen's half-width is widened by this factor before a point is set aside: its eleven
/// batches of ten periods are short against the correlation of a lightly damped structure's
/// peaks, so its interval is narrower than it says. Measured (`cargo run --release --example
/// interval_coverage -- 400000`, 3,539 screens of each of two chaotic points): a screen's own
/// interval holds the long run's value in 80-89 % of records, widened 2.5 times in 99.0-99.4
/// %; the value lies above the widened upper end in 0.6-0.9 % (twice: 1.5-2.6 %; three times:
/// 0.2-0.4 %).
pub const SCREEN_WIDEN: f64 = 2.5;

/// The screen of a design's points ([`Measure::hand_over`] with at most [`SCREEN`] periods a
/// measurement), where the budget leaves room for it (`max_periods` at least `hand_over +
/// SCREEN`); `None` otherwise.
pub fn screen(hand_over: usize, tol: f64, max_periods: usize) -> Option<Measure> {
    (max_periods >= hand_over + SCREEN)
        .then_some(Measure { max_periods: Some(SCREEN), ..Measure::handed_over(hand_over, tol) })
}

/// A point's bounds on its band's masses' amplitudes: the lowest its value may be and the
/// highest, m.
fn bounds(p: &SweepPoint, band: &Band, measured_on: bool) -> Option<(f64, f64)> {
    let st = p.result.as_ref().ok()?;
    let widen = if measured_on { 1.0 } else { SCREEN_WIDEN };
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for &m in &band.masses {
        let a = *st.amplitude.get(m)?;
        let h = st.measured.as_ref().map_or(0.0, |x| x.half_width.get(m).copied().unwrap_or(f64::NAN));
        if a.is_nan() {
            hi = f64::INFINITY;
            continue;
        }
        // An unknown interval may be anything: it sets no floor and is never set aside.
        let (l, u) = if h.is_finite() { (a - widen * h, a + widen * h) } else { (f64::NEG_INFINITY, f64::INFINITY) };
        lo = lo.max(l);
        hi = hi.max(u);
    }
    Some((lo, hi))
}

/// Measures on, to the design's interval, every screened point of `swept` (the band's sweeps)
/// that may be the band's highest: whose amplitude's upper bound (the screen's interval
/// widened by [`SCREEN_WIDEN`]) reaches the highest lower bound of any point (a certified
/// orbit's value, a point measured on less its half-width, a screened one less its widened
/// half-width), until none is left. Each is measured from where its screen ended, within a
/// budget of `steady.max_periods` of its own. `forced`: the dynamics at the band's
/// frequencies ([`crate::sim::settle::sweep::forced_at`]). The points left with their screen
/// state its interval widened by [`SCREEN_WIDEN`] (every half-width of their measurement),
/// the one they were set aside by. Returns, per sweep and point, whether it was left so. The
/// same points for any thread count.
pub(super) fn measure_on(
    forced: &[(f64, Result<Dynamics, SetupError>)],
    swept: &mut [Vec<SweepPoint>],
    band: &Band,
    steady: &SteadyOptions,
) -> Vec<Vec<bool>> {
    let mut on: Vec<Vec<bool>> = swept.iter().map(|s| vec![false; s.len()]).collect();
    let screened = |p: &SweepPoint| p.result.as_ref().is_ok_and(|st| st.measured.is_some());
    let opts = SteadyOptions { measure: Measure::periods(steady.max_periods, INTERVAL_TOL), ..*steady };
    loop {
        let floor = swept
            .iter()
            .zip(&on)
            .flat_map(|(s, o)| s.iter().zip(o).filter_map(|(p, &m)| bounds(p, band, m)))
            .fold(f64::NEG_INFINITY, |a, (lo, _)| a.max(lo));
        let next: Vec<(usize, usize)> = swept
            .iter()
            .enumerate()
            .flat_map(|(k, s)| s.iter().enumerate().map(move |(j, p)| (k, j, p)))
            .filter(|&(k, j, p)| !on[k][j] && screened(p) && bounds(p, band, false).is_some_and(|(_, hi)| hi >= floor))
            .map(|(k, j, _)| (k, j))
            .collect();
        if next.is_empty() {
            break;
        }
        let done: Vec<_> = next
            .par_iter()
            .map(|&(k, j)| {
                let p = &swept[k][j];
                let d = forced.iter().find(|(f, _)| *f == p.freq_hz).and_then(|(_, d)| d.as_ref().ok());
                match (d, &p.result) {
                    (Some(d), Ok(st)) => Ok(irregular::measure(d, st.clone(), &opts)),
                    (_, r) => r.clone(),
                }
            })
            .collect();
        for ((k, j), r) in next.into_iter().zip(done) {
            swept[k][j].result = r;
            on[k][j] = true;
        }
    }
    let mut aside: Vec<Vec<bool>> = swept.iter().map(|s| vec![false; s.len()]).collect();
    for ((s, o), a) in swept.iter_mut().zip(&on).zip(&mut aside) {
        for ((p, _), a) in s.iter_mut().zip(o).zip(a).filter(|((_, &o), _)| !o) {
            if let Some(m) = p.result.as_mut().ok().and_then(|st| st.measured.as_mut()) {
                m.half_width.iter_mut().for_each(|h| *h *= SCREEN_WIDEN);
                m.met = false;
                *a = true;
            }
        }
    }
    aside
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The screen is asked only where the budget holds the search's periods and a screen.
    #[test]
    fn a_screen_needs_room_in_the_budget() {
        assert_eq!(screen(100, 0.05, 249), None);
        let m = screen(100, 0.05, 250).unwrap();
        assert_eq!((m.max_periods, m.hand_over, m.tol), (Some(SCREEN), Some(100), 0.05));
    }
}
