//! Frequency sweeps: independent points from rest (in parallel, bit-identical for any
//! number of threads), or continuation upward or downward from point to point.

use std::f64::consts::PI;

use rayon::prelude::*;

use super::orbit_search::{follow, Known, Moved};
use super::rest::steady_from_rest;
use super::steady::{run_to_whole_period, Steady, SteadyOptions};
use super::steady_state;
use crate::sim::motion::engine::{Bed, State};
use crate::sim::motion::system::{Dynamics, SetupError, System};

/// Steady states a followed sweep extrapolates its next first guess from.
const FOLLOWED: usize = 3;

/// Direction of a continuation sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Ascending frequencies.
    Up,
    /// Descending frequencies.
    Down,
}

/// One point of a sweep.
#[derive(Debug, Clone)]
pub struct SweepPoint {
    /// Forcing frequency, Hz.
    pub freq_hz: f64,
    /// The steady state, or why the system could not be set up there.
    pub result: Result<Steady, SetupError>,
}

/// Every frequency from rest, independently. Results are in the order of `freqs_hz`; each
/// point's computation depends on nothing else, so the bytes do not depend on threads.
pub fn from_rest(sys: &System, freqs_hz: &[f64], opts: &SteadyOptions, tick: &(dyn Fn() + Sync)) -> Vec<SweepPoint> {
    // Decomposed once; each frequency adds only its forced response (the same numbers as
    // `Dynamics::new` at that frequency).
    from_rest_on(&Dynamics::unforced(sys), freqs_hz, opts, tick)
}

/// [`from_rest`] on a system already decomposed ([`continued_on`]).
pub fn from_rest_on(
    base: &Result<Dynamics, SetupError>,
    freqs_hz: &[f64],
    opts: &SteadyOptions,
    tick: &(dyn Fn() + Sync),
) -> Vec<SweepPoint> {
    freqs_hz
        .par_iter()
        .map(|&f| {
            let result = base
                .as_ref()
                .map_err(Clone::clone)
                .and_then(|b| b.at_omega(2.0 * PI * f))
                .map(|d| steady_from_rest(&d, opts));
            tick();
            SweepPoint { freq_hz: f, result }
        })
        .collect()
}

/// The state at the end of a steady record, moved to `t = 0` (the forcing phase is zero at
/// both, since records end on a whole period).
pub fn restart(s: &State) -> State {
    let shift = s.t;
    let beds = s
        .beds
        .iter()
        .map(|b| match *b {
            Bed::Free { t0, y0, u0 } => Bed::Free { t0: t0 - shift, y0, u0 },
            other => other,
        })
        .collect();
    State { t: 0.0, x: s.x.clone(), v: s.v.clone(), beds }
}

/// Continuation: the first point from rest, each next one from the previous final state.
/// `freqs_hz` is taken in ascending order for `Up` and descending for `Down`; the result is
/// in the order computed.
pub fn continued(
    sys: &System,
    freqs_hz: &[f64],
    dir: Direction,
    opts: &SteadyOptions,
    tick: &(dyn Fn() + Sync),
) -> Vec<SweepPoint> {
    continued_on(&Dynamics::unforced(sys), freqs_hz, dir, opts, tick)
}

/// [`continued`] on a system already decomposed (`base`: [`Dynamics::unforced`], or why it
/// could not be), so that several sweeps of one system decompose it once. The same points.
pub fn continued_on(
    base: &Result<Dynamics, SetupError>,
    freqs_hz: &[f64],
    dir: Direction,
    opts: &SteadyOptions,
    tick: &(dyn Fn() + Sync),
) -> Vec<SweepPoint> {
    continued_at(&forced_at(base, freqs_hz), dir, opts, tick)
}

/// The dynamics at each of `freqs_hz`, in ascending order (or why there are none): what
/// [`continued_at`] sweeps, shared by the sweeps up and down one band.
pub fn forced_at(base: &Result<Dynamics, SetupError>, freqs_hz: &[f64]) -> Vec<(f64, Result<Dynamics, SetupError>)> {
    let mut order: Vec<f64> = freqs_hz.to_vec();
    order.sort_by(f64::total_cmp);
    order.into_iter().map(|f| (f, base.as_ref().map_err(Clone::clone).and_then(|b| b.at_omega(2.0 * PI * f)))).collect()
}

/// [`continued_on`] over dynamics already forced at each frequency ([`forced_at`]). The same
/// points.
pub fn continued_at(
    forced: &[(f64, Result<Dynamics, SetupError>)],
    dir: Direction,
    opts: &SteadyOptions,
    tick: &(dyn Fn() + Sync),
) -> Vec<SweepPoint> {
    continued_until(forced, dir, opts, tick, &|_| false)
}

/// [`continued_at`] that ends after the first point `enough` accepts: its points are the
/// first ones of [`continued_at`]'s, the same numbers (a design's evaluation ends there once
/// a point shows its objective above the comparison it feeds).
pub fn continued_until(
    forced: &[(f64, Result<Dynamics, SetupError>)],
    dir: Direction,
    opts: &SteadyOptions,
    tick: &(dyn Fn() + Sync),
    enough: &(dyn Fn(&SweepPoint) -> bool + Sync),
) -> Vec<SweepPoint> {
    let order: Vec<&(f64, Result<Dynamics, SetupError>)> = match dir {
        Direction::Up => forced.iter().collect(),
        Direction::Down => forced.iter().rev().collect(),
    };
    let mut out: Vec<SweepPoint> = Vec::with_capacity(order.len());
    // Index in `out` of the last point with a steady state; following, the last `FOLLOWED` such.
    let mut last: Option<usize> = None;
    let mut known: Vec<usize> = Vec::new();
    // The dynamics of the last point with a steady state when it was followed: its record
    // ends where its orbit closes, not on a whole period, so a fallback runs it on first.
    let mut followed_at: Option<&Dynamics> = None;
    // Earlier points' states on the section the branch moved to, the last time it moved.
    let mut moved: Vec<Moved> = Vec::new();
    for (f, forced) in order {
        let f = *f;
        let result = forced.as_ref().map_err(Clone::clone).map(|d| {
            let previous = last.and_then(|i| out[i].result.as_ref().ok());
            let followed = match known.last() {
                Some(&p) if opts.follow && d.system.columns.is_empty() => {
                    let before: Vec<Known> =
                        known[..known.len() - 1].iter().filter_map(|&i| known_point(&out, i)).collect();
                    let found = known_point(&out, p).and_then(|p| follow(&p, &before, &moved, d, f, opts));
                    found.map(|(st, now)| {
                        if !now.is_empty() {
                            moved = now;
                        }
                        st
                    })
                }
                _ => None,
            };
            let was_followed = followed.is_some();
            let start = |s: &Steady| restart(&on_whole_period(followed_at, &s.final_state));
            let st = followed.unwrap_or_else(|| match previous {
                // A followed sweep's fallback starts next to a settled motion: it is judged as
                // soon as its events have repeated (`consecutive` periods).
                Some(s) if opts.follow => {
                    let near = SteadyOptions { min_periods: opts.min_periods.min(opts.consecutive), ..*opts };
                    steady_state(d, start(s), &near)
                }
                Some(s) => steady_state(d, start(s), opts),
                None => steady_from_rest(d, opts),
            });
            (st, was_followed.then_some(d))
        });
        let result = result.map(|(st, d)| {
            followed_at = d;
            st
        });
        let result = match result {
            Ok(st) => {
                last = Some(out.len());
                if opts.follow {
                    if known.len() == FOLLOWED {
                        known.remove(0);
                    }
                    known.push(out.len());
                }
                Ok(st)
            }
            Err(e) => Err(e),
        };
        tick();
        out.push(SweepPoint { freq_hz: f, result });
        if out.last().is_some_and(enough) {
            break;
        }
    }
    out
}

/// A followed point's final state (the end of its record) run on to the next whole forcing
/// period under its own dynamics `d` (the state every other point's record ends in); any
/// other point's as it is (`d` is `None`).
fn on_whole_period(d: Option<&Dynamics>, s: &State) -> State {
    let mut s = s.clone();
    if let Some(d) = d {
        // A chatter stop cannot happen on the orbit just recorded; if it did, the state
        // reached is where the sweep goes on from.
        let _ = run_to_whole_period(d, &mut s);
    }
    s
}

/// A computed point of `out`.
fn known_point(out: &[SweepPoint], i: usize) -> Option<Known<'_>> {
    let p = out.get(i)?;
    Some(Known { steady: p.result.as_ref().ok()?, freq_hz: p.freq_hz })
}
