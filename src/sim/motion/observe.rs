//! Observers that measure the motion exactly as the simulator computes it: extrema of the
//! displacements, event counts, and the energy balance.

use nalgebra::DVector;

use super::engine::{Bed, Event, EventKind, Observer, State};
use super::segment::{Point, Segment, Watch};
use super::system::Dynamics;

/// The masses whose extremes an [`Extrema`] follows: every one, or those of a set (an
/// analysis of a structure of many coordinates that reads a few of them: a design on a
/// reduced plate reads its bands' points and its containers' hosts, 5 of 47 coordinates, and
/// following all of them took a sixth of its time). A mass not followed has no amplitude (NaN).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Observe {
    /// `None`: every mass; otherwise bit `i` of word `i / 64` set for mass `i`.
    bits: Option<[u64; 4]>,
}

impl Observe {
    /// Every mass.
    pub const ALL: Observe = Observe { bits: None };

    /// The masses of `masses` (0-based, below [`MAX_DOF`](super::system::MAX_DOF)).
    pub fn only(masses: impl IntoIterator<Item = usize>) -> Observe {
        let mut bits = [0u64; 4];
        for i in masses {
            debug_assert!(i < 256, "mass {i}");
            if let Some(w) = bits.get_mut(i / 64) {
                *w |= 1 << (i % 64);
            }
        }
        Observe { bits: Some(bits) }
    }

    /// Whether every mass is followed.
    pub fn is_all(&self) -> bool {
        self.bits.is_none()
    }

    /// Whether mass `i` is followed.
    #[inline]
    pub fn contains(&self, i: usize) -> bool {
        self.bits.is_none_or(|b| b.get(i / 64).is_some_and(|w| w & (1 << (i % 64)) != 0))
    }
}

impl Default for Observe {
    fn default() -> Self {
        Observe::ALL
    }
}

impl std::fmt::Debug for Observe {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.bits {
            None => write!(f, "all"),
            Some(_) => write!(f, "only {:?}", (0..256).filter(|&i| self.contains(i)).collect::<Vec<_>>()),
        }
    }
}

/// Extrema of every displacement relative to the supports (and bed states) over the observed
/// time, found from the roots of the velocities in closed form, plus event counts.
#[derive(Debug, Clone)]
pub struct Extrema {
    /// Lowest displacement of each mass, m.
    pub min: Vec<f64>,
    /// Highest displacement of each mass, m.
    pub max: Vec<f64>,
    /// Per bed: bottom impacts, top impacts, lift-offs.
    pub bottom_impacts: Vec<usize>,
    /// Impacts on the top of each bed's container.
    pub top_impacts: Vec<usize>,
    /// Lift-offs of each bed.
    pub liftoffs: Vec<usize>,
    /// Highest flight of each bed above its container bottom, m.
    pub max_flight: Vec<f64>,
    /// The masses followed (the others keep no extremes).
    pub(super) observe: Observe,
    /// Sample times, points and values of one segment (buffers reused from segment to segment).
    times: Vec<f64>,
    points: Vec<Point>,
    at: Vec<f64>,
    /// Every mass's velocity at every sample (`k * n + i`), and a point's displacements.
    all: Vec<f64>,
    one: Vec<f64>,
}

impl Extrema {
    /// Empty extrema for `n` masses and `beds` beds.
    pub fn new(n: usize, beds: usize) -> Extrema {
        Extrema::observing(n, beds, Observe::ALL)
    }

    /// Empty extrema for `n` masses and `beds` beds, following the masses of `observe`.
    pub fn observing(n: usize, beds: usize, observe: Observe) -> Extrema {
        Extrema {
            observe,
            min: vec![f64::INFINITY; n],
            max: vec![f64::NEG_INFINITY; n],
            bottom_impacts: vec![0; beds],
            top_impacts: vec![0; beds],
            liftoffs: vec![0; beds],
            max_flight: vec![0.0; beds],
            times: Vec::new(),
            points: Vec::new(),
            all: Vec::new(),
            one: Vec::new(),
            at: Vec::new(),
        }
    }

    /// Half the peak-to-peak displacement of each mass; NaN for a mass never seen (a run that
    /// stopped before anything was recorded: not measured, never an amplitude of -inf) or not
    /// followed.
    pub fn amplitudes(&self) -> Vec<f64> {
        self.min.iter().zip(&self.max).map(|(lo, hi)| if hi >= lo { 0.5 * (hi - lo) } else { f64::NAN }).collect()
    }

    pub(super) fn take(&mut self, i: usize, x: f64) {
        self.min[i] = self.min[i].min(x);
        self.max[i] = self.max[i].max(x);
    }
}

/// For each sign change of `f` between successive sample times `times` (where it takes the
/// values `at`) in a window `k` that `wanted(k)` accepts, the root refined by Newton with
/// bisection, handed to `found` with the quantity `f` returns beside its value and derivative
/// at the last evaluation (the extremum sought, within rounding of the root). A sample where
/// `f` is exactly zero is a root: `found` gets `sample(k)` there.
pub(super) fn each_root(
    f: &impl Fn(f64) -> (f64, f64, f64),
    times: &[f64],
    at: &[f64],
    sample: impl Fn(usize) -> f64,
    wanted: impl Fn(usize) -> bool,
    mut found: impl FnMut(f64),
) {
    for (k, (w, t)) in times.windows(2).zip(at.windows(2)).enumerate() {
        let ((ta, tb), (fa, fb)) = ((w[0], w[1]), (t[0], t[1]));
        if fa == 0.0 {
            found(sample(k));
        } else if fa * fb < 0.0 && wanted(k) {
            found(refine(f, ta, tb, fa, fb));
        }
    }
}

/// The root of `f` in `[lo, hi]`, where `f(lo) = flo` and `f(hi) = fhi` has the other sign,
/// and the quantity `f` returns beside value and derivative at the last point evaluated
/// (within rounding of the root); the first iterate is the secant's root (the samples are
/// close: Newton then starts near the root).
fn refine(f: &impl Fn(f64) -> (f64, f64, f64), mut lo: f64, mut hi: f64, mut flo: f64, fhi: f64) -> f64 {
    let secant = lo - flo * (hi - lo) / (fhi - flo);
    let mut t = if secant > lo && secant < hi { secant } else { 0.5 * (lo + hi) };
    let mut extra = f64::NAN;
    for _ in 0..60 {
        let (v, dv, x) = f(t);
        extra = x;
        if v == 0.0 {
            break;
        }
        if (v < 0.0) == (flo < 0.0) {
            lo = t;
            flo = v;
        } else {
            hi = t;
        }
        let newton = if dv != 0.0 { t - v / dv } else { f64::NAN };
        // Converged: Newton's correction is below the time's resolution.
        if (newton - t).abs() <= 1e-15 * (1.0 + t.abs()) {
            break;
        }
        t = if newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        if hi - lo < 1e-15 * (1.0 + t.abs()) {
            let (_, _, x) = f(t);
            extra = x;
            break;
        }
    }
    extra
}

/// Sample times every sixteenth of the shortest period from `t_a` to `t_b` (both ends) and
/// the segment's points there: the ends evaluated directly, the samples between carried from
/// the start by one step's factors (a step costs what one evaluation does).
pub(super) fn samples(d: &Dynamics, seg: &Segment, t_a: f64, t_b: f64, times: &mut Vec<f64>, points: &mut Vec<Point>) {
    let m = (((t_b - t_a) / (d.min_period / 16.0)).ceil() as usize).max(2);
    times.clear();
    times.extend((0..=m).map(|k| if k == m { t_b } else { t_a + (t_b - t_a) * k as f64 / m as f64 }));
    points.clear();
    points.push(seg.point(d, t_a));
    let step = (m > 2).then(|| seg.step(d, (t_b - t_a) / m as f64));
    for k in 1..m {
        match &step {
            Some(step) => {
                let mut next = points[k - 1].clone();
                next.advance(step, times[k]);
                points.push(next);
            }
            None => points.push(seg.point(d, times[k])),
        }
    }
    points.push(seg.point(d, t_b));
}

/// Derivative `order` of mass `i`'s displacement relative to the supports at `pt`: the
/// simulator's own under a force; less the supports' motion when they move.
pub(super) fn shown(d: &Dynamics, seg: &Segment, pt: &Point, i: usize, order: usize) -> f64 {
    match d.system.base {
        None => seg.deriv(d, pt, i, order),
        Some(_) => seg.deriv(d, pt, i, order) - d.support_motion(i, order, pt.sin, pt.cos),
    }
}

/// The amplitude of derivative `order` of the supports' motion under mass `i` (0 when they
/// stand still).
pub(super) fn supports_amplitude(d: &Dynamics, i: usize, order: usize) -> f64 {
    let s = |sin: f64, cos: f64| d.support_motion(i, order, sin, cos);
    s(1.0, 0.0).hypot(s(0.0, 1.0))
}

impl Extrema {
    /// Every mass's lowest and highest displacement over the samples (`at` a buffer of their
    /// length).
    fn masses(&mut self, d: &Dynamics, seg: &Segment, times: &[f64], points: &[Point], at: &mut [f64]) {
        let (n, m) = (d.system.dof(), times.len() - 1);
        // Displacements relative to the supports: the simulator's own under a force; less the
        // supports' motion when they move.
        let shown = |pt: &Point, i: usize, order: usize| shown(d, seg, pt, i, order);
        // The samples' displacements (ends) and velocities of all masses at once: the numbers
        // `Segment::deriv` gives one by one ([`Segment::all_into`]), less the supports' motion.
        let (mut all, mut one) = (std::mem::take(&mut self.all), std::mem::take(&mut self.one));
        all.resize((m + 1) * n, 0.0);
        one.resize(n, 0.0);
        let less_supports = |pt: &Point, order: usize, out: &mut [f64]| {
            if d.system.base.is_some() {
                out.iter_mut().enumerate().for_each(|(i, o)| *o -= d.support_motion(i, order, pt.sin, pt.cos));
            }
        };
        // A few masses followed: each one's own numbers (the same, one by one).
        let observe = self.observe;
        let few = !observe.is_all();
        for (pt, out) in points.iter().zip(all.chunks_exact_mut(n)) {
            if few {
                out.iter_mut()
                    .enumerate()
                    .filter(|(i, _)| observe.contains(*i))
                    .for_each(|(i, o)| *o = shown(pt, i, 1));
            } else {
                seg.all_into(d, pt, 1, out);
                less_supports(pt, 1, out);
            }
        }
        for k in [0, m] {
            if few {
                (0..n).filter(|&i| observe.contains(i)).for_each(|i| self.take(i, shown(&points[k], i, 0)));
                continue;
            }
            seg.all_into(d, &points[k], 0, &mut one);
            less_supports(&points[k], 0, &mut one);
            one.iter().enumerate().for_each(|(i, &x)| self.take(i, x));
        }
        // A window whose velocity changes sign is refined only when its extremum could pass
        // the lowest or highest displacement so far: from its start `t_k` the displacement
        // stays within `x_k + max(v_k, 0) dt + A dt^2 / 2` and `x_k + min(v_k, 0) dt - A dt^2
        // / 2`, `A` a bound on the acceleration from `t_k` on ([`Segment::bound`], with the
        // supports' when they move), less a margin far above the sums' rounding: the
        // extremes found are those every window's refinement would give, to the bit.
        let supports = |i: usize| supports_amplitude(d, i, 2);
        for i in (0..n).filter(|&i| observe.contains(i)) {
            let v = |t: f64| {
                let pt = seg.point(d, t);
                (shown(&pt, i, 1), shown(&pt, i, 2), shown(&pt, i, 0))
            };
            at.iter_mut().enumerate().for_each(|(k, a)| *a = all[k * n + i]);
            let (lo, hi) = (std::cell::Cell::new(self.min[i]), std::cell::Cell::new(self.max[i]));
            let wanted = |k: usize| {
                let (pt, vk, dt) = (&points[k], at[k], times[k + 1] - times[k]);
                let (x, a) = (shown(pt, i, 0), seg.bound(d, pt, i, 2) + supports(i));
                let margin = 1e-9 * (lo.get().abs() + hi.get().abs()) + 1e-12 * seg.bound(d, pt, i, 0);
                x + vk.max(0.0) * dt + 0.5 * a * dt * dt + margin >= hi.get()
                    || x + vk.min(0.0) * dt - 0.5 * a * dt * dt - margin <= lo.get()
            };
            let found = |x: f64| {
                lo.set(lo.get().min(x));
                hi.set(hi.get().max(x));
            };
            each_root(&v, times, at, |k| shown(&points[k], i, 0), wanted, found);
            (self.min[i], self.max[i]) = (lo.get(), hi.get());
        }
        (self.all, self.one) = (all, one);
    }

    /// Each flying bed's highest flight above its bottom over the samples.
    fn flights(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], times: &[f64], points: &[Point], at: &mut [f64]) {
        let (m, t_a, t_b) = (times.len() - 1, times[0], times[times.len() - 1]);
        // Highest flight: the apex of y - x_p, at a root of the relative velocity. A window
        // whose gap cannot exceed the highest one so far is not refined: from its start
        // `t_k` the gap is at most `gap_k + max(rel_v, 0) dt + max(rel_a, 0) dt^2 / 2 + J
        // dt^3 / 6`, `J` the bound on the host's jerk from `t_k` on (the bed's is zero).
        for (j, bed) in beds.iter().enumerate() {
            if let Bed::Free { t0, y0, u0 } = *bed {
                let (p, g) = (d.system.dampers[j].host, d.system.dampers[j].gravity());
                let gap = |t: f64, pt: &Point| Bed::flight(g, t0, y0, u0, t).0 - seg.deriv(d, pt, p, 0);
                let rel = |t: f64| {
                    let pt = seg.point(d, t);
                    let (_, u) = Bed::flight(g, t0, y0, u0, t);
                    (u - seg.deriv(d, &pt, p, 1), -g - seg.deriv(d, &pt, p, 2), gap(t, &pt))
                };
                at.iter_mut()
                    .zip(points)
                    .for_each(|(a, pt)| *a = Bed::flight(g, t0, y0, u0, pt.t).1 - seg.deriv(d, pt, p, 1));
                let best = std::cell::Cell::new(gap(t_a, &points[0]).max(gap(t_b, &points[m])));
                let ceiling = |k: usize| {
                    let (pt, dt) = (&points[k], times[k + 1] - times[k]);
                    let acc = -g - seg.deriv(d, pt, p, 2);
                    let jerk = seg.bound(d, pt, p, 3);
                    gap(pt.t, pt) + dt * (at[k].max(0.0) + dt * (acc.max(0.0) / 2.0 + dt * jerk / 6.0))
                };
                each_root(
                    &rel,
                    times,
                    at,
                    |k| gap(times[k], &points[k]),
                    // With a margin far above rounding and far below any flight (1e-15 m).
                    |k| ceiling(k) * (1.0 + 1e-6) + 1e-15 >= best.get(),
                    |g| best.set(best.get().max(g)),
                );
                self.max_flight[j] = self.max_flight[j].max(best.get());
            }
        }
    }
}

/// Fine sample steps in a coarse window of the record ([`Extrema::coarse`]).
pub(super) const COARSE_STEPS: usize = 16;

impl Extrema {
    /// Above 8 degrees of freedom, on a segment on which no bed flies and the supports stand
    /// still: the parts of `[t_a, t_b]` where some followed mass could reach a new extreme,
    /// after every followed mass's displacement at the start of each window of
    /// [`COARSE_STEPS`] fine steps has been taken (a value the motion reaches, so a lower
    /// bound of its highest displacement and an upper bound of its lowest). A window is left
    /// out when from its start `t_k` the displacement stays within `x_k + max(v_k, 0) dt + A
    /// dt^2 / 2` and `x_k + min(v_k, 0) dt - A dt^2 / 2` (`A` the bound on the acceleration
    /// from `t_k` on) of those bounds, less the margin of the fine search: it holds no new
    /// extreme. `None` where the fine samples are few or the rule does not apply: the whole
    /// segment is sampled finely.
    fn coarse(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) -> Option<Vec<(f64, f64)>> {
        let n = d.system.dof();
        let m = ((t_b - t_a) / (d.min_period / 16.0)).ceil() as usize;
        let flying = beds.iter().any(|b| matches!(b, Bed::Free { .. }));
        if n <= super::buf::INLINE_MASSES || d.system.base.is_some() || flying || m < 4 * COARSE_STEPS {
            return None;
        }
        let windows = m.div_ceil(COARSE_STEPS);
        let h = (t_b - t_a) / windows as f64;
        let edge = |k: usize| if k == windows { t_b } else { t_a + h * k as f64 };
        let followed: Vec<usize> = (0..n).filter(|&i| self.observe.contains(i)).collect();
        // Each window's start: displacement, velocity and acceleration bound of each followed
        // mass; the displacements taken as reached.
        let step = seg.step(d, h);
        let mut pt = seg.point(d, t_a);
        let mut starts: Vec<(f64, f64, f64, f64)> = Vec::with_capacity(windows * followed.len());
        for k in 0..windows {
            if k > 0 {
                pt.advance(&step, edge(k));
            }
            for &i in &followed {
                let (x, v) = (seg.deriv(d, &pt, i, 0), seg.deriv(d, &pt, i, 1));
                starts.push((x, v, seg.bound(d, &pt, i, 2), seg.bound(d, &pt, i, 0)));
                self.take(i, x);
            }
        }
        let end = seg.point(d, t_b);
        followed.iter().for_each(|&i| self.take(i, seg.deriv(d, &end, i, 0)));
        let mut out: Vec<(f64, f64)> = Vec::new();
        for k in 0..windows {
            let dt = edge(k + 1) - edge(k);
            let open = followed.iter().enumerate().any(|(r, &i)| {
                let (x, v, a, scale) = starts[k * followed.len() + r];
                let (lo, hi) = (self.min[i], self.max[i]);
                let margin = 1e-9 * (lo.abs() + hi.abs()) + 1e-12 * scale;
                x + v.max(0.0) * dt + 0.5 * a * dt * dt + margin >= hi
                    || x + v.min(0.0) * dt - 0.5 * a * dt * dt - margin <= lo
            });
            if open {
                match out.last_mut() {
                    Some(last) if last.1 == edge(k) => last.1 = edge(k + 1),
                    _ => out.push((edge(k), edge(k + 1))),
                }
            }
        }
        Some(out)
    }

    /// The record of `[t_a, t_b]` of one segment sampled every sixteenth of the shortest period.
    pub(super) fn fine(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        // The closed form is evaluated at every sample time for every mass and bed; sign
        // changes of the velocities (and relative velocities of flying beds) are then refined
        // one by one.
        let (mut times, mut points, mut at) =
            (std::mem::take(&mut self.times), std::mem::take(&mut self.points), std::mem::take(&mut self.at));
        samples(d, seg, t_a, t_b, &mut times, &mut points);
        at.clear();
        at.resize(times.len(), 0.0);
        self.masses(d, seg, &times, &points, &mut at);
        self.flights(d, seg, beds, &times, &points, &mut at);
        (self.times, self.points, self.at) = (times, points, at);
    }
}

/// Memory one piece of the record may hold, bytes (its fine samples' points and velocities,
/// or its coarse windows' starts).
const PIECE_BYTES: usize = 32 << 20;

/// Fine samples of one piece of a segment: a segment longer than this many sixteenths of the
/// shortest period (a low forcing frequency's period holds up to 1.6 million) is recorded in
/// pieces of at most this many, one after another, so that the record's memory is bounded
/// at any frequency. At least 4096 (no segment of the paper's structure at its frequencies
/// is that long: its record is the unpieced one, bit for bit).
pub fn piece_samples(d: &Dynamics, seg: &Segment) -> usize {
    let per_sample = seg.len * 24 + d.system.dof() * 8 + 64;
    (PIECE_BYTES / per_sample).max(4096)
}

impl Observer for Extrema {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        if t_b <= t_a {
            return;
        }
        let span = piece_samples(d, seg) as f64 * d.min_period / 16.0;
        let pieces = ((t_b - t_a) / span).ceil().max(1.0) as usize;
        for p in 0..pieces {
            let a = if p == 0 { t_a } else { t_a + (t_b - t_a) * p as f64 / pieces as f64 };
            let b = if p + 1 == pieces { t_b } else { t_a + (t_b - t_a) * (p + 1) as f64 / pieces as f64 };
            match self.coarse(d, seg, beds, a, b) {
                Some(windows) => windows.into_iter().for_each(|(a, b)| self.fine(d, seg, beds, a, b)),
                None => self.fine(d, seg, beds, a, b),
            }
            if pieces > 1 {
                super::cancel::check();
            }
        }
    }

    fn event(&mut self, ev: &Event, _after: &State) {
        match ev.kind {
            EventKind::Impact { top: false, .. } => self.bottom_impacts[ev.bed] += 1,
            EventKind::Impact { top: true, .. } => self.top_impacts[ev.bed] += 1,
            EventKind::LiftOff { .. } => self.liftoffs[ev.bed] += 1,
            EventKind::Collision { .. } => {}
        }
    }
}

/// Energy terms over the observed time: work of the force, viscous loss, impact loss.
#[derive(Debug, Clone, Default)]
pub struct Energy {
    /// Work of the force, J.
    pub work: f64,
    /// Energy dissipated by the structure's damping, J.
    pub viscous: f64,
    /// Energy lost in impacts, J.
    pub impact: f64,
}

/// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const GL_NODES: [f64; 8] = [
    -0.960_289_856_497_536_3,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL_WEIGHTS: [f64; 8] = [
    0.101_228_536_290_376_26,
    0.222_381_034_453_374_47,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362,
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_47,
    0.101_228_536_290_376_26,
];

impl Observer for Energy {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, _beds: &[Bed], t_a: f64, t_b: f64) {
        if t_b <= t_a {
            return;
        }
        let pieces = (((t_b - t_a) / (d.min_period / 16.0)).ceil() as usize).max(1);
        let h = (t_b - t_a) / pieces as f64;
        let k = d.system.driven;
        for piece in 0..pieces {
            let a = t_a + h * piece as f64;
            for (node, w) in GL_NODES.iter().zip(GL_WEIGHTS) {
                let t = a + 0.5 * h * (node + 1.0);
                let pt = seg.point(d, t);
                let (_, v) = seg.state(d, &pt);
                if d.system.base.is_some() {
                    self.work += 0.5 * h * w * d.power(t, &v);
                } else {
                    let (f, _) = d.force(t);
                    self.work += 0.5 * h * w * f * v[k];
                }
                self.viscous += 0.5 * h * w * (v.transpose() * &*d.c * &v)[(0, 0)];
            }
        }
    }

    fn event(&mut self, ev: &Event, _after: &State) {
        self.impact += ev.loss;
    }
}

/// Stored energy: kinetic (masses and beds), elastic, and the beds' gravitational energy.
pub fn stored_energy(d: &Dynamics, s: &State) -> f64 {
    let (y, u): (Vec<f64>, Vec<f64>) = (0..s.beds.len()).map(|j| s.bed_motion(d, j)).unzip();
    energy_of(d, s.x.as_slice(), s.v.as_slice(), &y, &u)
}

/// Stored energy from displacements `x`, velocities `v` of the masses and positions `y`,
/// velocities `u` of the beds (in the frame of the bare structure's static equilibrium).
pub fn energy_of(d: &Dynamics, x: &[f64], v: &[f64], y: &[f64], u: &[f64]) -> f64 {
    let structure = &d.system.structure;
    let n = x.len();
    let kinetic: f64 = match &structure.coupled_mass {
        None => v.iter().zip(&structure.masses).map(|(v, m)| 0.5 * m * v * v).sum(),
        Some(m0) => (0..n).map(|i| (0..n).map(|j| 0.5 * v[i] * m0[(i, j)] * v[j]).sum::<f64>()).sum(),
    };
    let elastic: f64 = (0..n).map(|i| (0..n).map(|j| 0.5 * x[i] * d.k[(i, j)] * x[j]).sum::<f64>()).sum();
    let beds: f64 = d
        .system
        .dampers
        .iter()
        .zip(y.iter().zip(u))
        .map(|(dm, (y, u))| 0.5 * dm.mass * u * u + dm.mass * dm.gravity() * y)
        .sum();
    kinetic + elastic + beds
}

/// Every event, in order.
#[derive(Debug, Clone, Default)]
pub struct EventLog(pub Vec<Event>);

impl Observer for EventLog {
    fn event(&mut self, ev: &Event, _after: &State) {
        self.0.push(*ev);
    }
}

/// Both observers at once.
pub struct Both<'a, A: Observer, B: Observer>(pub &'a mut A, pub &'a mut B);

impl<A: Observer, B: Observer> Observer for Both<'_, A, B> {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        self.0.segment(d, seg, beds, t_a, t_b);
        self.1.segment(d, seg, beds, t_a, t_b);
    }
    fn event(&mut self, ev: &Event, after: &State) {
        self.0.event(ev, after);
        self.1.event(ev, after);
    }
    fn wants_jumps(&self) -> bool {
        self.0.wants_jumps() || self.1.wants_jumps()
    }
    fn jump(&mut self, d: &Dynamics, before: &State, after: &State, hits: &[Watch]) {
        self.0.jump(d, before, after, hits);
        self.1.jump(d, before, after, hits);
    }
    fn done(&self) -> bool {
        self.0.done() || self.1.done()
    }
}

/// An observer that may be absent: what is asked for only sometimes (the energy terms, the
/// storeys' peaks) rides along as an `Option` (nothing is observed when it is `None`).
impl<O: Observer> Observer for Option<O> {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        if let Some(o) = self {
            o.segment(d, seg, beds, t_a, t_b);
        }
    }
    fn event(&mut self, ev: &Event, after: &State) {
        if let Some(o) = self {
            o.event(ev, after);
        }
    }
    fn wants_jumps(&self) -> bool {
        self.as_ref().is_some_and(|o| o.wants_jumps())
    }
    fn jump(&mut self, d: &Dynamics, before: &State, after: &State, hits: &[Watch]) {
        if let Some(o) = self {
            o.jump(d, before, after, hits);
        }
    }
    fn done(&self) -> bool {
        self.as_ref().is_some_and(|o| o.done())
    }
}

/// A state as a flat vector for distances: displacements, velocities / omega, and for each
/// bed its height above the bottom and relative velocity / omega.
pub fn flat(d: &Dynamics, s: &State) -> DVector<f64> {
    let n = d.system.dof();
    let nb = s.beds.len();
    let mut z = DVector::zeros(2 * n + 2 * nb);
    for i in 0..n {
        z[i] = s.x[i];
        z[n + i] = s.v[i] / d.omega;
    }
    for j in 0..nb {
        let p = d.system.dampers[j].host;
        let (y, u) = s.bed_motion(d, j);
        z[2 * n + j] = y - s.x[p];
        z[2 * n + nb + j] = (u - s.v[p]) / d.omega;
    }
    z
}

/// Time histories at given (sorted) times: displacement, velocity and acceleration of every
/// mass (the acceleration of the configuration in force at that time, so it jumps at events),
/// position, velocity and state of every bed, and the events in between.
#[derive(Debug, Clone, Default)]
pub struct Sampler {
    /// Sample times, s, ascending.
    pub times: Vec<f64>,
    next: usize,
    /// Per sample, per mass.
    pub x: Vec<Vec<f64>>,
    /// Per sample, per mass: velocity, m/s.
    pub v: Vec<Vec<f64>>,
    /// Per sample, per mass: acceleration, m/s^2.
    pub a: Vec<Vec<f64>>,
    /// Per sample, per bed: position and velocity.
    pub y: Vec<Vec<f64>>,
    /// Per sample, per bed: velocity, m/s.
    pub u: Vec<Vec<f64>>,
    /// Per sample, per bed: 'B' bottom, 'T' top, 'F' free.
    pub state: Vec<Vec<char>>,
    /// Every event between the first and the last sample.
    pub events: Vec<Event>,
}

impl Sampler {
    /// A sampler at `times` (s, ascending).
    pub fn new(times: Vec<f64>) -> Sampler {
        Sampler { times, ..Sampler::default() }
    }
}

impl Observer for Sampler {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        let n = d.system.dof();
        while self.next < self.times.len() && self.times[self.next] <= t_b {
            let t = self.times[self.next];
            if t >= t_a {
                let pt = seg.point(d, t);
                let (x, v) = seg.state(d, &pt);
                let a: Vec<f64> = (0..n).map(|i| seg.deriv(d, &pt, i, 2)).collect();
                let mut y = Vec::with_capacity(beds.len());
                let mut u = Vec::with_capacity(beds.len());
                let mut st = Vec::with_capacity(beds.len());
                for (j, b) in beds.iter().enumerate() {
                    let dm = &d.system.dampers[j];
                    let (pos, vel, c) = match *b {
                        Bed::Free { t0, y0, u0 } => {
                            let (pos, vel) = Bed::flight(dm.gravity(), t0, y0, u0, t);
                            (pos, vel, 'F')
                        }
                        resting => {
                            let top = resting == Bed::Top;
                            let (pos, vel) = Bed::end_motion(top, x[dm.host], v[dm.host], dm.clearance);
                            (pos, vel, if top { 'T' } else { 'B' })
                        }
                    };
                    y.push(pos);
                    u.push(vel);
                    st.push(c);
                }
                self.x.push(x.iter().copied().collect());
                self.v.push(v.iter().copied().collect());
                self.a.push(a);
                self.y.push(y);
                self.u.push(u);
                self.state.push(st);
            }
            self.next += 1;
        }
    }

    fn event(&mut self, ev: &Event, _after: &State) {
        self.events.push(*ev);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::engine::Engine;
    use crate::sim::motion::system::System;

    #[test]
    fn a_record_that_saw_nothing_has_no_amplitude() {
        // A run stopped before its record: NaN (not measured), never -inf.
        assert!(Extrema::new(3, 1).amplitudes().iter().all(|a| a.is_nan()));
    }

    /// The record sampled finely over every segment, as up to 8 degrees of freedom.
    struct Fine(Extrema);
    impl Observer for Fine {
        fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
            if t_b > t_a {
                self.0.fine(d, seg, beds, t_a, t_b);
            }
        }
    }

    /// The record as [`Extrema`] takes it, and the share of the time it sampled finely.
    struct Windows(Extrema, f64, f64);
    impl Observer for Windows {
        fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
            let windows = self.0.coarse(d, seg, beds, t_a, t_b).unwrap_or_else(|| vec![(t_a, t_b)]);
            self.1 += windows.iter().map(|(a, b)| b - a).sum::<f64>();
            self.2 += t_b - t_a;
            windows.into_iter().for_each(|(a, b)| self.0.fine(d, seg, beds, a, b));
        }
    }

    #[test]
    fn coarse_windows_find_the_extremes_of_the_fine_record() {
        // 16 masses whose modes lie far above the forcing (230 Hz to 4.8 kHz, as a finely
        // meshed plate's kept modes lie above its first band), the beds on the last three
        // riding their floors (a weak force): the coarse windows' case. Started at rest, so
        // that the free vibration of every mode puts extremes inside many windows, and on the
        // periodic motion, where only the windows near its extremes open.
        let n = 16;
        let s = Structure::chain(&vec![0.13; n], &vec![3e7; n], Damping::ModalRatios(vec![0.01; n]));
        let beds = (n - 3..n).map(|j| Damper::new(j, 0.013, Clearance::from_m(f64::INFINITY))).collect();
        let sys = System::plastic(s, beds, 0, 0.05);
        for (f, from_rest) in [(20.0, true), (20.0, false), (45.0, true), (45.0, false)] {
            let d = Dynamics::new(&sys, 2.0 * PI * f).unwrap();
            let start = if from_rest {
                State::at_rest(&d)
            } else {
                let (x, v) = d.particular(7, 0.0);
                State { t: 0.0, x, v, beds: vec![Bed::Bottom; 3] }
            };
            let t_end = 3.0 / f;
            let (mut coarse, mut fine) = (start.clone(), start);
            let mut windows = Windows(Extrema::new(n, 3), 0.0, 0.0);
            Engine::new(&d).advance(&mut coarse, t_end, &mut windows).unwrap();
            let share = windows.1 / windows.2;
            // On the periodic motion the stiff modes are quiet: windows far from its extremes
            // stay closed.
            assert!(from_rest || share < 0.25, "{f} Hz: {share} of the time sampled finely");
            let ext = windows.0;
            // The record itself takes the same windows.
            let mut record = Extrema::new(n, 3);
            let mut again = fine.clone();
            Engine::new(&d).advance(&mut again, t_end, &mut record).unwrap();
            assert!(record.max == ext.max && record.min == ext.min, "{f} Hz: the record's own windows");
            let mut reference = Fine(Extrema::new(n, 3));
            Engine::new(&d).advance(&mut fine, t_end, &mut reference).unwrap();
            assert!(ext.liftoffs.iter().chain(&reference.0.liftoffs).all(|&k| k == 0), "{f} Hz: the beds ride");
            let scale = reference.0.max.iter().chain(&reference.0.min).fold(0.0f64, |a, x| a.max(x.abs()));
            for i in 0..n {
                for (a, b, what) in [(ext.max[i], reference.0.max[i], "max"), (ext.min[i], reference.0.min[i], "min")] {
                    assert!(
                        (a - b).abs() <= 1e-12 * scale,
                        "{f} Hz from rest {from_rest}: m{} {what} {a:e} vs {b:e}",
                        i + 1
                    );
                }
            }
        }
    }
}
