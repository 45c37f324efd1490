//! What an engineer checks on a building besides the floors' displacements: each storey's
//! drift (a floor's displacement less the floor's below it, the first storey's less the
//! ground's) and each floor's absolute acceleration (what the contents feel: the simulator's
//! coordinates follow the supports, docs/model.md 2.3, so it is their second derivative
//! under a force and on moving supports alike). Both are found over the observed time as
//! [`super::observe::Extrema`] finds the displacements' extremes: samples every sixteenth of
//! the shortest period, each window where the quantity's derivative changes sign refined to
//! its root in closed form, so the extremes are exact to rounding (no time step).

use super::engine::{Bed, Observer};
use super::observe::{each_root, samples};
use super::segment::{Point, Segment};
use super::system::Dynamics;

/// Fine samples of one piece of a segment (a long segment is observed in pieces, so that
/// the memory held stays bounded at any frequency).
const PIECE: usize = 4096;

/// Extremes of the storeys' drifts and the floors' absolute accelerations over the observed
/// time.
#[derive(Debug, Clone)]
pub struct Peaks {
    /// Lowest and highest drift of each storey, m (empty: the structure is not a chain).
    pub drift: Vec<(f64, f64)>,
    /// Lowest and highest absolute acceleration of each mass, m/s^2.
    pub acceleration: Vec<(f64, f64)>,
    times: Vec<f64>,
    points: Vec<Point>,
    at: Vec<f64>,
}

/// The storeys' drift and the floors' absolute acceleration, as amplitudes (half the
/// peak-to-peak value) and as peaks (the largest magnitude).
#[derive(Debug, Clone, PartialEq)]
pub struct PeakValues {
    /// Half the peak-to-peak drift of each storey, m (empty: not a chain).
    pub drift: Vec<f64>,
    /// Half the peak-to-peak absolute acceleration of each mass, m/s^2.
    pub acceleration: Vec<f64>,
    /// The largest magnitude of each storey's drift, m.
    pub drift_peak: Vec<f64>,
    /// The largest magnitude of each mass's absolute acceleration, m/s^2.
    pub acceleration_peak: Vec<f64>,
}

impl Peaks {
    /// Empty extremes of the first `masses` coordinates (a reduced model's points), with the
    /// storeys' drifts when `storeys` (a chain: storey `i` joins mass `i - 1`, or the
    /// ground, to mass `i`).
    pub fn new(masses: usize, storeys: bool) -> Peaks {
        let empty = (f64::INFINITY, f64::NEG_INFINITY);
        Peaks {
            drift: if storeys { vec![empty; masses] } else { Vec::new() },
            acceleration: vec![empty; masses],
            times: Vec::new(),
            points: Vec::new(),
            at: Vec::new(),
        }
    }

    /// Amplitudes and peaks; NaN where nothing was observed.
    pub fn values(&self) -> PeakValues {
        let half =
            |v: &[(f64, f64)]| v.iter().map(|&(lo, hi)| if hi >= lo { 0.5 * (hi - lo) } else { f64::NAN }).collect();
        let peak = |v: &[(f64, f64)]| {
            v.iter().map(|&(lo, hi)| if hi >= lo { lo.abs().max(hi.abs()) } else { f64::NAN }).collect()
        };
        PeakValues {
            drift: half(&self.drift),
            acceleration: half(&self.acceleration),
            drift_peak: peak(&self.drift),
            acceleration_peak: peak(&self.acceleration),
        }
    }

    /// Extremes over one piece `[t_a, t_b]` of a segment.
    fn piece(&mut self, d: &Dynamics, seg: &Segment, t_a: f64, t_b: f64) {
        let (mut times, mut points, mut at) =
            (std::mem::take(&mut self.times), std::mem::take(&mut self.points), std::mem::take(&mut self.at));
        samples(d, seg, t_a, t_b, &mut times, &mut points);
        at.resize(times.len(), 0.0);
        // Displacement derivatives relative to the supports (the drifts'), and absolute ones.
        let relative = |pt: &Point, i: usize, k: usize| match d.system.base {
            None => seg.deriv(d, pt, i, k),
            Some(_) => seg.deriv(d, pt, i, k) - d.support_motion(i, k, pt.sin, pt.cos),
        };
        let drift =
            |pt: &Point, i: usize, k: usize| relative(pt, i, k) - if i > 0 { relative(pt, i - 1, k) } else { 0.0 };
        let acceleration = |pt: &Point, i: usize, k: usize| seg.deriv(d, pt, i, k + 2);
        for i in 0..self.drift.len() {
            self.drift[i] = extremes(self.drift[i], &|pt: &Point, k| drift(pt, i, k), seg, d, &times, &points, &mut at);
        }
        for i in 0..self.acceleration.len() {
            self.acceleration[i] = extremes(
                self.acceleration[i],
                &|pt: &Point, k| acceleration(pt, i, k),
                seg,
                d,
                &times,
                &points,
                &mut at,
            );
        }
        (self.times, self.points, self.at) = (times, points, at);
    }
}

/// `so_far` widened by the extremes of the quantity whose derivative `k` at a point `q`
/// gives, over the samples: its values at both ends and at every root of its derivative.
#[allow(clippy::too_many_arguments)]
fn extremes(
    so_far: (f64, f64),
    q: &dyn Fn(&Point, usize) -> f64,
    seg: &Segment,
    d: &Dynamics,
    times: &[f64],
    points: &[Point],
    at: &mut [f64],
) -> (f64, f64) {
    let (mut lo, mut hi) = so_far;
    let mut take = |x: f64| {
        lo = lo.min(x);
        hi = hi.max(x);
    };
    take(q(&points[0], 0));
    take(q(&points[points.len() - 1], 0));
    at.iter_mut().zip(points).for_each(|(a, pt)| *a = q(pt, 1));
    let f = |t: f64| {
        let pt = seg.point(d, t);
        (q(&pt, 1), q(&pt, 2), q(&pt, 0))
    };
    each_root(&f, times, at, |k| q(&points[k], 0), |_| true, &mut take);
    (lo, hi)
}

impl Observer for Peaks {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, _beds: &[Bed], t_a: f64, t_b: f64) {
        if t_b <= t_a {
            return;
        }
        let span = PIECE as f64 * d.min_period / 16.0;
        let pieces = ((t_b - t_a) / span).ceil().max(1.0) as usize;
        for p in 0..pieces {
            let a = if p == 0 { t_a } else { t_a + (t_b - t_a) * p as f64 / pieces as f64 };
            let b = if p + 1 == pieces { t_b } else { t_a + (t_b - t_a) * (p + 1) as f64 / pieces as f64 };
            self.piece(d, seg, a, b);
        }
    }
}
