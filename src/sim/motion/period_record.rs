//! The extremes of one forcing period, taken when the period is over: what an irregular
//! point's measurement records of every period (docs/simulator.md, "Irregular motion").
//!
//! [`Extrema`] takes each segment as it comes: the first half of a period keeps reaching new
//! extremes, so its velocity is sampled every sixteenth of the shortest natural period over
//! the whole period, and every first sign change is refined. [`PeriodExtrema`] holds the
//! period's segments instead and, at its end, first takes each followed mass's displacement
//! (and each flying bed's gap) at the start of every window of 16 fine steps: values
//! the motion reaches, so lower bounds of the highest and upper bounds of the lowest. A window
//! is then sampled finely ([`Extrema`]'s own record of it) only where, from its start, the
//! bound on the acceleration (on the jerk, for a flight) lets it pass them by more than the
//! fine record's margin: the extremes are those of the fine record over the whole period to
//! rounding (the same numbers where a window is a whole segment). No I/O.

use super::engine::{Bed, Event, Observer, State};
use super::observe::{piece_samples, shown, supports_amplitude, Extrema, Observe, COARSE_STEPS};
use super::segment::{Point, Segment};
use super::system::Dynamics;

/// Shortest natural periods a forcing period holds from which it is taken at its end: below,
/// a window of 16 fine steps is a sizeable part of the period and most windows
/// open (measured in docs/simulator.md, "Irregular motion").
pub const WINDOWED_FROM: f64 = 8.0;

/// One segment of the period, held until its end.
struct Held {
    seg: Segment,
    beds: Vec<Bed>,
    t_a: f64,
    t_b: f64,
}

/// What a window's start lets the window reach: each followed mass's highest and lowest
/// displacement bounds and its scale (for the margin), then each bed's highest gap (or
/// `-inf` for a bed that does not fly).
struct Reach {
    masses: Vec<(f64, f64, f64)>,
    flights: Vec<f64>,
}

/// An [`Observer`] of one forcing period at a time: [`PeriodExtrema::finish`] gives the
/// period's [`Extrema`] and starts the next period.
pub struct PeriodExtrema {
    ext: Extrema,
    /// Whether the period is taken at its end; otherwise each segment as it comes.
    windowed: bool,
    held: Vec<Held>,
    /// Window edges `(segment, t_a, t_b)` and what each may reach (buffers kept from period
    /// to period).
    edges: Vec<(usize, f64, f64)>,
    reach: Reach,
    /// Windows seen and windows sampled finely, over the record's life.
    pub windows: (usize, usize),
}

impl PeriodExtrema {
    /// An empty record of the periods of `d`'s forcing, following the masses of `observe`:
    /// taken at each period's end where the period holds at least [`WINDOWED_FROM`] of the
    /// shortest natural periods, as [`Extrema`] takes it otherwise.
    pub fn observing(d: &Dynamics, observe: Observe) -> PeriodExtrema {
        let windowed = 2.0 * std::f64::consts::PI / d.omega >= WINDOWED_FROM * d.min_period;
        PeriodExtrema::windowed(d, observe, windowed)
    }

    /// An empty record of `d`'s masses and beds, taken at each period's end or not.
    pub fn windowed(d: &Dynamics, observe: Observe, windowed: bool) -> PeriodExtrema {
        PeriodExtrema {
            windowed,
            ext: Extrema::observing(d.system.dof(), d.system.dampers.len(), observe),
            held: Vec::new(),
            edges: Vec::new(),
            reach: Reach { masses: Vec::new(), flights: Vec::new() },
            windows: (0, 0),
        }
    }

    /// The extremes, counts and flights of the segments and events seen since the last call
    /// (or since the record was made); the record is then empty for the next period.
    pub fn finish(&mut self, d: &Dynamics) -> Extrema {
        let (n, nb) = (self.ext.min.len(), self.ext.max_flight.len());
        let observe = self.ext.observe;
        if !self.windowed {
            return std::mem::replace(&mut self.ext, Extrema::observing(n, nb, observe));
        }
        let followed: Vec<usize> = (0..n).filter(|&i| self.ext.observe.contains(i)).collect();
        self.starts(d, &followed);
        // The windows that may hold a new extreme, sampled finely (adjacent ones of a segment
        // together, up to a piece of the fine record's memory bound).
        let (f, b) = (followed.len(), nb);
        let mut open: Option<(usize, f64, f64, usize)> = None;
        for w in 0..self.edges.len() {
            let (h, t_a, t_b) = self.edges[w];
            let ext = &self.ext;
            let masses = followed.iter().enumerate().any(|(r, &i)| {
                let (hi, lo, scale) = self.reach.masses[w * f + r];
                let margin = 1e-9 * (ext.min[i].abs() + ext.max[i].abs()) + 1e-12 * scale;
                hi + margin >= ext.max[i] || lo - margin <= ext.min[i]
            });
            // With the fine record's margin, far above rounding and far below any flight.
            let flights = (0..b).any(|j| {
                let c = self.reach.flights[w * b + j];
                c.is_finite() && c * (1.0 + 1e-6) + 1e-15 >= ext.max_flight[j]
            });
            self.windows.0 += 1;
            if !(masses || flights) {
                continue;
            }
            self.windows.1 += 1;
            let most = piece_samples(d, &self.held[h].seg) / COARSE_STEPS;
            open = match open {
                Some((g, a, e, k)) if g == h && e == t_a && k < most => Some((g, a, t_b, k + 1)),
                Some((g, a, e, _)) => {
                    self.fine(d, g, a, e);
                    Some((h, t_a, t_b, 1))
                }
                None => Some((h, t_a, t_b, 1)),
            };
        }
        if let Some((g, a, e, _)) = open {
            self.fine(d, g, a, e);
        }
        self.held.clear();
        std::mem::replace(&mut self.ext, Extrema::observing(n, nb, observe))
    }

    /// [`Extrema`]'s fine record of `[t_a, t_b]` of held segment `h`.
    fn fine(&mut self, d: &Dynamics, h: usize, t_a: f64, t_b: f64) {
        let held = &self.held[h];
        self.ext.fine(d, &held.seg, &held.beds, t_a, t_b);
    }

    /// Every window's start taken (and the period's end), and what each window may reach.
    fn starts(&mut self, d: &Dynamics, followed: &[usize]) {
        let nb = self.ext.max_flight.len();
        self.edges.clear();
        self.reach.masses.clear();
        self.reach.flights.clear();
        for (h, held) in self.held.iter().enumerate() {
            let (seg, t_a, t_b) = (&held.seg, held.t_a, held.t_b);
            let m = (((t_b - t_a) / (d.min_period / 16.0)).ceil() as usize).max(2);
            let count = m.div_ceil(COARSE_STEPS);
            let step = (count > 1).then(|| seg.step(d, (t_b - t_a) / count as f64));
            let edge = |k: usize| if k == count { t_b } else { t_a + (t_b - t_a) * k as f64 / count as f64 };
            let mut pt = seg.point(d, t_a);
            for k in 0..count {
                if let (true, Some(step)) = (k > 0, &step) {
                    pt.advance(step, edge(k));
                }
                let dt = edge(k + 1) - edge(k);
                for &i in followed {
                    // From the window's start the displacement stays within `x + v dt + a dt^2
                    // / 2 +- J dt^3 / 6` at `dt` on, `J` the bound on the jerk from there on;
                    // the largest and least over the window taken term by term.
                    let ([x, v, a, _], jerk) = start_of(d, seg, &pt, i);
                    self.ext.take(i, x);
                    let cubic = jerk * dt * dt * dt / 6.0;
                    let (up, down) =
                        (v.max(0.0) * dt + a.max(0.0) * dt * dt / 2.0, v.min(0.0) * dt + a.min(0.0) * dt * dt / 2.0);
                    self.reach.masses.push((x + up + cubic, x + down - cubic, seg.bound(d, &pt, i, 0)));
                }
                for (j, bed) in held.beds.iter().enumerate() {
                    let Bed::Free { t0, y0, u0 } = *bed else {
                        self.reach.flights.push(f64::NEG_INFINITY);
                        continue;
                    };
                    // From the window's start `t_k` the gap is at most `gap_k + max(rel_v, 0)
                    // dt + max(rel_a, 0) dt^2 / 2 + J dt^3 / 6`, `J` the bound on the host's
                    // jerk from `t_k` on (the bed's is zero).
                    let (p, g) = (d.system.dampers[j].host, d.system.dampers[j].gravity());
                    let (y, u) = Bed::flight(g, t0, y0, u0, pt.t);
                    let ([x, v, a, _], jerk) = seg.derivs4_bound(d, &pt, p, 0, 3);
                    let (gap, rel, acc) = (y - x, u - v, -g - a);
                    self.ext.max_flight[j] = self.ext.max_flight[j].max(gap);
                    self.reach.flights.push(gap + dt * (rel.max(0.0) + dt * (acc.max(0.0) / 2.0 + dt * jerk / 6.0)));
                }
                debug_assert_eq!(self.reach.flights.len(), (self.edges.len() + 1) * nb);
                self.edges.push((h, edge(k), edge(k + 1)));
            }
        }
        // The period's end (every other segment's end is the next one's start).
        if let Some(last) = self.held.last() {
            let pt = last.seg.point(d, last.t_b);
            for &i in followed {
                self.ext.take(i, shown(d, &last.seg, &pt, i, 0));
            }
            for (j, bed) in last.beds.iter().enumerate() {
                if let Bed::Free { t0, y0, u0 } = *bed {
                    let (p, g) = (d.system.dampers[j].host, d.system.dampers[j].gravity());
                    let gap = Bed::flight(g, t0, y0, u0, last.t_b).0 - last.seg.deriv(d, &pt, p, 0);
                    self.ext.max_flight[j] = self.ext.max_flight[j].max(gap);
                }
            }
        }
    }
}

/// The displacement of mass `i` relative to the supports at `pt` and its first three
/// derivatives ([`shown`]), and a bound on the third from `pt` on, in one pass over the terms.
fn start_of(d: &Dynamics, seg: &Segment, pt: &Point, i: usize) -> ([f64; 4], f64) {
    let (mut x, jerk) = seg.derivs4_bound(d, pt, i, 0, 3);
    if d.system.base.is_none() {
        return (x, jerk);
    }
    for (order, x) in x.iter_mut().enumerate() {
        *x -= d.support_motion(i, order, pt.sin, pt.cos);
    }
    (x, jerk + supports_amplitude(d, i, 3))
}

impl Observer for PeriodExtrema {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        if !self.windowed {
            self.ext.segment(d, seg, beds, t_a, t_b);
        } else if t_b > t_a {
            self.held.push(Held { seg: seg.clone(), beds: beds.to_vec(), t_a, t_b });
        }
    }

    fn event(&mut self, ev: &Event, after: &State) {
        self.ext.event(ev, after);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    use crate::model::{Clearance, Damper, Damping, Direction, Structure};
    use crate::sim::motion::engine::Engine;
    use crate::sim::motion::observe::Both;
    use crate::sim::motion::system::System;

    /// Every period of `periods` after `skip` from `start`: the period's record against
    /// [`Extrema`]'s own (every segment as it comes), to rounding; the share of its windows
    /// sampled finely and whether beds flew and struck.
    fn agrees(sys: &System, freq: f64, skip: usize, periods: usize, start: fn(&Dynamics) -> State) -> (f64, bool) {
        let d = Dynamics::new(sys, 2.0 * PI * freq).unwrap();
        let (n, nb) = (sys.dof(), sys.dampers.len());
        let mut s = start(&d);
        let engine = Engine::new(&d);
        let period = 1.0 / freq;
        let mut record = PeriodExtrema::windowed(&d, Observe::ALL, true);
        let (mut flew, mut hit) = (0.0f64, 0);
        for k in 1..=skip + periods {
            let mut direct = Extrema::new(n, nb);
            engine.advance(&mut s, k as f64 * period, &mut Both(&mut direct, &mut record)).unwrap();
            let held = record.finish(&d);
            if k <= skip {
                continue;
            }
            let scale = direct.max.iter().chain(&direct.min).fold(0.0f64, |a, x| a.max(x.abs()));
            for i in 0..n {
                assert!((held.max[i] - direct.max[i]).abs() <= 1e-12 * scale, "{freq} Hz, period {k}: m{} max", i + 1);
                assert!((held.min[i] - direct.min[i]).abs() <= 1e-12 * scale, "{freq} Hz, period {k}: m{} min", i + 1);
            }
            for j in 0..nb {
                let (a, b) = (held.max_flight[j], direct.max_flight[j]);
                assert!(
                    (a - b).abs() <= 1e-12 * b.abs() + 1e-18,
                    "{freq} Hz, period {k}: bed {j} flight {a:e} vs {b:e}"
                );
                flew = flew.max(b);
            }
            assert_eq!(
                (&held.bottom_impacts, &held.top_impacts, &held.liftoffs),
                (&direct.bottom_impacts, &direct.top_impacts, &direct.liftoffs)
            );
            hit += direct.bottom_impacts.iter().chain(&direct.top_impacts).sum::<usize>();
        }
        let (seen, opened) = record.windows;
        eprintln!("{freq} Hz: {opened} of {seen} windows sampled finely, highest flight {flew:e} m, {hit} impacts");
        (opened as f64 / seen as f64, flew > 0.0 && hit > 0)
    }

    #[test]
    fn a_period_taken_at_its_end_has_the_extremes_of_every_segment_taken_as_it_comes() {
        // A swaying frame whose roof container's shot flies between its walls (chaos at 5.3 Hz).
        let frame = Structure::chain(
            &[2.0, 2.0, 2.0, 2.0, 2.0, 1.5],
            &[40e3, 38e3, 36e3, 34e3, 32e3, 30e3],
            Damping::ModalRatios(vec![0.02; 6]),
        );
        let bed = Damper::new(5, 1.15, Clearance::from_mm(20.0)).along(Direction::Horizontal);
        assert!(agrees(&System::plastic(frame, vec![bed], 5, 5.0), 5.3, 40, 30, State::at_rest).1);
        // 16 masses, three beds lifting off their floors and striking them.
        let n = 16;
        let chain = |k: f64| Structure::chain(&vec![0.13; n], &vec![k; n], Damping::ModalRatios(vec![0.01; n]));
        let beds = |mm: f64| (n - 3..n).map(|j| Damper::new(j, 0.013, Clearance::from_mm(mm))).collect::<Vec<_>>();
        assert!(agrees(&System::plastic(chain(3e6), beds(1.0), n - 1, 30.0), 45.0, 20, 20, State::at_rest).1);
        // Stiff modes (230 Hz to 4.8 kHz) quiet on a forced response, the beds riding: most
        // windows stay closed, so every extreme found rests on the windows' bounds (at five
        // frequencies, five places of the extremes among the windows).
        let riding = System::plastic(chain(3e7), beds(f64::INFINITY), 0, 0.05);
        let on_response = |d: &Dynamics| {
            let (x, v) = d.particular(7, 0.0);
            State { t: 0.0, x, v, beds: vec![Bed::Bottom; 3] }
        };
        for f in [17.0, 20.0, 23.0, 26.0, 29.0] {
            let (opened, _) = agrees(&riding, f, 0, 10, on_response);
            assert!(opened < 0.25, "{f} Hz: {opened} of the windows sampled finely");
        }
        // Shaken supports: displacements relative to them, a bed flying in a vertical container.
        let three = Structure::chain(&[1.0; 3], &[1e4; 3], Damping::ModalRatios(vec![0.02; 3]));
        let bed = Damper::new(2, 0.1, Clearance::from_mm(5.0));
        assert!(agrees(&System::plastic(three, vec![bed], 0, 0.0).on_supports(15.0), 7.0, 20, 20, State::at_rest).1);
    }
}
