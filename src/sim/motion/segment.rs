//! One smooth piece of motion between events, in closed form, and the event functions
//! evaluated on it with their first three derivatives and a bound on the fourth.

use nalgebra::DVector;
use num_complex::Complex64;

use super::buf::Terms;
use super::system::{Dynamics, Step};

/// The homogeneous part's coefficients from a start state: `c = V^-1 (z0 - z_p(t0))`.
#[derive(Debug, Clone)]
pub struct Segment {
    /// Start time, s.
    pub t0: f64,
    /// The configuration: bit `j` set when bed `j` rides its host.
    pub mask: usize,
    /// Its configuration's number ([`Dynamics::slot`]).
    pub slot: usize,
    /// Number of representative terms.
    pub len: usize,
    /// Coefficients `c_r` of the representative terms.
    pub c: Terms<Complex64>,
    /// Their moduli (for derivative bounds).
    pub c_abs: Terms<f64>,
    /// `sin(omega t0)` and `cos(omega t0)`, for the point at the start.
    sin_cos0: (f64, f64),
}

/// Largest `|lambda| dt` over which [`Segment::move_near`] carries a point by series.
pub const NEAR: f64 = 1e-3;

/// `c_r e^{lambda_r (t - t0)}` and the forcing phase at one time: everything an evaluation
/// at that time shares.
#[derive(Debug, Clone)]
pub struct Point {
    /// The time, s.
    pub t: f64,
    /// `c_r e^{lambda_r (t - t0)}` of each representative term.
    pub e: Terms<Complex64>,
    /// Their moduli.
    pub e_abs: Terms<f64>,
    /// `sin(omega t)`.
    pub sin: f64,
    /// `cos(omega t)`.
    pub cos: f64,
}

impl Point {
    /// Moves the point `step.dt` later, to time `t` (which the caller keeps equal to `self.t +
    /// step.dt` up to rounding): each term times its factor, the forcing phase rotated. It
    /// agrees with [`Segment::point`] at that time to a few roundings per step.
    pub fn advance(&mut self, step: &Step, t: f64) {
        // Slices taken once: the loop then runs on plain memory, inline or not.
        let n = step.len;
        let (e, e_abs) = (&mut self.e[..n], &mut self.e_abs[..n]);
        let (factor, decay) = (&step.factor[..n], &step.decay[..n]);
        for r in 0..n {
            e[r] *= factor[r];
            e_abs[r] *= decay[r];
        }
        let (sin, cos) = (self.sin, self.cos);
        self.sin = sin * step.cos + cos * step.sin;
        self.cos = cos * step.cos - sin * step.sin;
        self.t = t;
    }
}

impl Segment {
    /// Starts a segment in configuration `mask` at `t0` from displacements `x0`, velocities `v0`.
    pub fn start(d: &Dynamics, mask: usize, t0: f64, x0: &DVector<f64>, v0: &DVector<f64>) -> Segment {
        let n = x0.len();
        let slot = d.slot(mask);
        let (cfg, forced) = (&d.configs[slot], d.forced(slot));
        // The start's departure from the forced response (`Dynamics::particular`, inline).
        let (sn, cs) = (d.omega * t0).sin_cos();
        let mut z_buf = Terms::<f64>::zeros(2 * n);
        let z = &mut z_buf[..];
        for i in 0..n {
            let xp = forced[i].p * cs + forced[i].q * sn + cfg.modes.offset[i];
            let vp = (forced[i].q * cs - forced[i].p * sn) * d.omega;
            z[i] = x0[i] - xp;
            z[n + i] = v0[i] - vp;
        }
        let len = cfg.modes.lambda.len();
        // Built in place and filled (moving filled buffers into it would copy them).
        let mut seg =
            Segment { t0, mask, slot, len, c: Terms::zeros(len), c_abs: Terms::zeros(len), sin_cos0: (sn, cs) };
        // `c = V^-1 z` column by column (contiguous), each coefficient summed over the start
        // coordinates in order from zero, as `Sum` adds.
        let (inverse, stride) = (cfg.modes.inverse.as_slice(), cfg.modes.inverse.nrows());
        for (j, zj) in z.iter().enumerate() {
            let column = &inverse[j * stride..j * stride + len];
            for (c, w) in seg.c.iter_mut().zip(column) {
                *c += w * zj;
            }
        }
        for (c, c_abs) in seg.c.iter().zip(seg.c_abs.iter_mut()) {
            // Only bounds use the modulus: the square root of the sum of squares (no `hypot`:
            // the coefficients are far from overflow).
            *c_abs = (c.re * c.re + c.im * c.im).sqrt();
        }
        seg
    }

    /// The shared quantities at time `t`.
    pub fn point(&self, d: &Dynamics, t: f64) -> Point {
        let mut pt = Point { t, e: Terms::zeros(self.len), e_abs: Terms::zeros(self.len), sin: 0.0, cos: 0.0 };
        self.point_into(d, t, &mut pt);
        pt
    }

    /// [`Segment::point`] written over `pt` (any point: its buffers are reused, which spares
    /// the copies of returning a point).
    pub fn point_into(&self, d: &Dynamics, t: f64, pt: &mut Point) {
        pt.t = t;
        pt.e.set_len(self.len);
        pt.e_abs.set_len(self.len);
        let (c, c_abs) = (&self.c[..], &self.c_abs[..]);
        let (e, e_abs) = (&mut pt.e[..], &mut pt.e_abs[..]);
        if t == self.t0 {
            // At the start every exponential is exactly 1 (`exp(0)`, `sin_cos(0)`) and the
            // forcing phase is the start's: the same numbers without evaluating them again.
            for ((e, a), (c, c_abs)) in e.iter_mut().zip(e_abs.iter_mut()).zip(c.iter().zip(c_abs)) {
                *e = c * Complex64::new(1.0, 0.0);
                *a = c_abs * 1.0;
            }
            (pt.sin, pt.cos) = self.sin_cos0;
            return;
        }
        let cfg = &d.configs[self.slot];
        let s = t - self.t0;
        let terms = e.iter_mut().zip(e_abs.iter_mut()).zip(c.iter().zip(c_abs)).zip(&cfg.modes.lambda);
        for (((e, a), (c, c_abs)), l) in terms {
            let decay = (l.re * s).exp();
            let (si, co) = (l.im * s).sin_cos();
            *e = c * Complex64::new(decay * co, decay * si);
            *a = c_abs * decay;
        }
        (pt.sin, pt.cos) = (d.omega * t).sin_cos();
    }

    /// The factors that carry a point of this segment `dt` later ([`Point::advance`]).
    pub fn step(&self, d: &Dynamics, dt: f64) -> Step {
        d.step(self.slot, dt)
    }

    /// Moves `pt` (a point of this segment) to `t`: by the series of each factor
    /// `e^{lambda_r (t - pt.t)}` and of the forcing's rotation when `t` is that near
    /// (`|lambda| |t - pt.t|` at most [`NEAR`]: the series' remainders are below 2e-21
    /// relative), else by evaluating it there ([`Segment::point`]). For the certified search's
    /// last advances, which are short.
    pub fn move_near(&self, d: &Dynamics, pt: &mut Point, t: f64) {
        let dt = t - pt.t;
        if (dt * 2.0 * std::f64::consts::PI / d.min_period).abs() > NEAR {
            self.point_into(d, t, pt);
            return;
        }
        let cfg = &d.configs[self.slot];
        let one = Complex64::new(1.0, 0.0);
        let terms = pt.e.iter_mut().zip(pt.e_abs.iter_mut()).zip(&cfg.modes.lambda[..self.len]);
        for ((e, a), l) in terms {
            let z = l * dt;
            let factor = one + z * (one + z / 2.0 * (one + z / 3.0 * (one + z / 4.0 * (one + z / 5.0))));
            let x = z.re;
            let decay = 1.0 + x * (1.0 + x / 2.0 * (1.0 + x / 3.0 * (1.0 + x / 4.0 * (1.0 + x / 5.0))));
            *e *= factor;
            *a *= decay;
        }
        let x = d.omega * dt;
        let x2 = x * x;
        let sn = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0));
        let cs = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0));
        let (sin, cos) = (pt.sin, pt.cos);
        pt.sin = sin * cs + cos * sn;
        pt.cos = cos * cs - sin * sn;
        pt.t = t;
    }

    /// Derivative `order` of the displacement of mass `p`.
    pub fn deriv(&self, d: &Dynamics, pt: &Point, p: usize, order: usize) -> f64 {
        let cfg = &d.configs[self.slot];
        let row = &cfg.modes.vl[p][order];
        let hom: f64 = row[..self.len].iter().zip(&pt.e[..]).map(|(a, e)| a.re * e.re - a.im * e.im).sum();
        self.with_forced(d, pt, p, order, hom)
    }

    /// The homogeneous terms' sum `hom` of derivative `order` of mass `p` plus the forced
    /// response's and (displacements) the static offset.
    #[inline(always)]
    fn with_forced(&self, d: &Dynamics, pt: &Point, p: usize, order: usize, hom: f64) -> f64 {
        let cfg = &d.configs[self.slot];
        let f = &d.forced(self.slot)[p];
        let (pp, qq) = (f.p, f.q);
        let w = d.omega_pow[order];
        let forced = match order % 4 {
            0 => pp * pt.cos + qq * pt.sin,
            1 => -pp * pt.sin + qq * pt.cos,
            2 => -(pp * pt.cos + qq * pt.sin),
            _ => pp * pt.sin - qq * pt.cos,
        } * w;
        hom + forced + if order == 0 { cfg.modes.offset[p] } else { 0.0 }
    }

    /// A bound on `|x_p^(order)|` from this point on (the homogeneous terms decay).
    pub fn bound(&self, d: &Dynamics, pt: &Point, p: usize, order: usize) -> f64 {
        let cfg = &d.configs[self.slot];
        let row = &cfg.modes.vl_abs[p][order];
        let hom: f64 = row[..self.len].iter().zip(&pt.e_abs[..]).map(|(a, e)| a * e).sum();
        hom + d.omega_pow[order] * d.forced(self.slot)[p].amp
    }

    /// Four successive derivatives of the displacement of mass `p` from `order` on (each what
    /// [`Segment::deriv`] gives) and [`Segment::bound`] of order `bound_order`, in one pass
    /// over the terms.
    #[inline]
    pub fn derivs4_bound(
        &self,
        d: &Dynamics,
        pt: &Point,
        p: usize,
        order: usize,
        bound_order: usize,
    ) -> ([f64; 4], f64) {
        let rows = Rows::of(d, self.slot, pt, p, order, bound_order);
        // Each sum from -0, term by term, as `Iterator::sum` adds.
        let (mut h, mut b) = ([-0.0; 4], -0.0);
        for r in 0..pt.e.len() {
            rows.add(pt, r, &mut h, &mut b);
        }
        (self.particular4(d, pt, p, order, h), b + d.omega_pow[bound_order] * d.forced(self.slot)[p].amp)
    }

    /// `h` (sums of the terms for four successive derivatives of mass `p`'s displacement from
    /// `order` on) plus the forced response's and the static offset's.
    #[inline(always)]
    fn particular4(&self, d: &Dynamics, pt: &Point, p: usize, order: usize, h: [f64; 4]) -> [f64; 4] {
        let f = &d.forced(self.slot)[p];
        let (pp, qq) = (f.p, f.q);
        let mut out = [0.0; 4];
        for (i, o) in out.iter_mut().enumerate() {
            let forced = match (order + i) % 4 {
                0 => pp * pt.cos + qq * pt.sin,
                1 => -pp * pt.sin + qq * pt.cos,
                2 => -(pp * pt.cos + qq * pt.sin),
                _ => pp * pt.sin - qq * pt.cos,
            } * d.omega_pow[order + i];
            *o = h[i] + forced + if order + i == 0 { d.configs[self.slot].modes.offset[p] } else { 0.0 };
        }
        out
    }

    /// [`Segment::derivs4_bound`] of the slow terms at each coarse level (the first `slow[k]`
    /// terms, which are ordered by `|lambda|` above [`super::system::LARGE_ABOVE`] degrees of
    /// freedom), with the forced response, and a bound from this point on of the fast terms'
    /// contribution to derivative `order` (the rest): into `out[k]`, in one pass over the
    /// terms. `slow` does not increase with `k`.
    pub fn derivs4_levels(
        &self,
        d: &Dynamics,
        pt: &Point,
        (p, order, bound_order): (usize, usize, usize),
        slow: &[usize],
        out: &mut [Split],
    ) {
        let (e, e_abs) = (&pt.e[..], &pt.e_abs[..]);
        let rows = Rows::of(d, self.slot, pt, p, order, bound_order);
        let rv = &d.configs[self.slot].modes.vl_abs[p][order][..e.len()];
        let (mut h, mut b, mut a) = ([-0.0; 4], -0.0, -0.0);
        let mut r = 0;
        for k in (0..slow.len()).rev() {
            while r < slow[k] {
                rows.add(pt, r, &mut h, &mut b);
                a += rv[r] * e_abs[r];
                r += 1;
            }
            out[k] = Split { x: h, bound4: b, fast: a };
        }
        let total = a + (r..e.len()).map(|r| rv[r] * e_abs[r]).sum::<f64>();
        // The fast part as the total less the slow part, plus what the two sums' rounding
        // can take from it (each within len roundings of the total).
        let margin = 4.0 * (e.len() as f64 + 2.0) * f64::EPSILON * total;
        let forcing = d.omega_pow[bound_order] * d.forced(self.slot)[p].amp;
        let particular = self.particular4(d, pt, p, order, [0.0; 4]);
        for s in out[..slow.len()].iter_mut() {
            for (x, q) in s.x.iter_mut().zip(particular) {
                *x += q;
            }
            s.bound4 += forcing;
            s.fast = (total - s.fast).max(0.0) + margin;
        }
    }

    /// Displacements and velocities of all masses at a point.
    pub fn state(&self, d: &Dynamics, pt: &Point) -> (DVector<f64>, DVector<f64>) {
        let n = d.system.dof();
        (DVector::from_fn(n, |i, _| self.deriv(d, pt, i, 0)), DVector::from_fn(n, |i, _| self.deriv(d, pt, i, 1)))
    }

    /// The same as [`Segment::state`], written into `x` and `v` (of the right length): the
    /// same sums, term by term for all masses at once.
    pub fn state_into(&self, d: &Dynamics, pt: &Point, x: &mut DVector<f64>, v: &mut DVector<f64>) {
        self.all_into(d, pt, 0, x.as_mut_slice());
        self.all_into(d, pt, 1, v.as_mut_slice());
    }

    /// [`Segment::deriv`] of order 0 or 1 of every mass, into `out` (one per mass): the
    /// terms summed for all masses at once (contiguous rows, [`super::system::Modes::by_term`]),
    /// each mass's sum in [`Segment::deriv`]'s order, so the same numbers.
    pub fn all_into(&self, d: &Dynamics, pt: &Point, order: usize, out: &mut [f64]) {
        let n = out.len();
        let cfg = &d.configs[self.slot];
        let [re, im] = &cfg.modes.by_term[order];
        out.fill(-0.0);
        for (r, e) in pt.e[..self.len].iter().enumerate() {
            let (rows_re, rows_im) = (&re[r * n..r * n + n], &im[r * n..r * n + n]);
            for ((o, a_re), a_im) in out.iter_mut().zip(rows_re).zip(rows_im) {
                *o += a_re * e.re - a_im * e.im;
            }
        }
        for (p, o) in out.iter_mut().enumerate() {
            *o = self.with_forced(d, pt, p, order, *o);
        }
    }
}

/// The rows of four successive displacement derivatives of one mass and of the bound's order,
/// cut to a point's terms: what [`Segment::derivs4_bound`] and [`Segment::derivs4_levels`]
/// sum term by term.
struct Rows<'a> {
    d: [&'a [Complex64]; 4],
    bound: &'a [f64],
}

impl<'a> Rows<'a> {
    /// Mass `p`'s rows of orders `order..order + 4` and `bound_order` in configuration `slot`.
    #[inline(always)]
    fn of(d: &'a Dynamics, slot: usize, pt: &Point, p: usize, order: usize, bound_order: usize) -> Rows<'a> {
        let modes = &d.configs[slot].modes;
        let (rows, len) = (&modes.vl[p][order..order + 4], pt.e.len());
        Rows {
            d: [&rows[0][..len], &rows[1][..len], &rows[2][..len], &rows[3][..len]],
            bound: &modes.vl_abs[p][bound_order][..len],
        }
    }

    /// Adds term `r` of `pt` to the four sums `h` and the bound `b`.
    #[inline(always)]
    fn add(&self, pt: &Point, r: usize, h: &mut [f64; 4], b: &mut f64) {
        let z = pt.e[r];
        for (h, row) in h.iter_mut().zip(self.d) {
            *h += row[r].re * z.re - row[r].im * z.im;
        }
        *b += self.bound[r] * pt.e_abs[r];
    }
}

/// What an event function measures. Each is >= 0 while nothing happens.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Watch {
    /// Contact force per unit bed mass, `sigma (xddot_p + g_a)` (sigma +1 bottom, -1 top;
    /// `g_a` gravity along the bed's motion).
    Contact {
        /// The bed.
        bed: usize,
        /// Its host mass (0-based).
        host: usize,
        /// +1 on the bottom, -1 against the top.
        sigma: f64,
    },
    /// Gap above the container bottom, `y - x_p`, of a free bed.
    GapBottom {
        /// The bed.
        bed: usize,
        /// Its host mass (0-based).
        host: usize,
        /// Position at the start of the flight, m.
        y0: f64,
        /// Velocity at the start of the flight, m/s.
        u0: f64,
        /// Time the flight started, s.
        tf: f64,
    },
    /// Gap below the container top, `x_p + d - y`, of a free bed.
    GapTop {
        /// The bed.
        bed: usize,
        /// Its host mass (0-based).
        host: usize,
        /// The clearance, m.
        d: f64,
        /// Position at the start of the flight, m.
        y0: f64,
        /// Velocity at the start of the flight, m/s.
        u0: f64,
        /// Time the flight started, s.
        tf: f64,
    },
    /// Gap between two neighbouring free grains of a column, `y_upper - y_lower`: both fly
    /// under gravity alone, so it is linear in time. Flights `[t0, y0, u0]` as in
    /// [`super::state::Bed::Free`].
    Pair {
        /// The lower grain.
        lower: usize,
        /// The grain above it.
        upper: usize,
        /// The lower grain's flight `[t0, y0, u0]`.
        lower_flight: [f64; 3],
        /// The upper grain's flight `[t0, y0, u0]`.
        upper_flight: [f64; 3],
    },
}

/// Most distinct host sums [`Reads`] keeps (more are computed each time).
const READS: usize = 8;

/// The host displacement derivatives that watches read in one window of the event search,
/// each summed once: a flying bed's gaps below and above read the same sums of its host, as
/// do beds resting on one host. The numbers are those [`Watch::taylor`] gives, to the bit.
#[derive(Debug, Default)]
pub struct Reads {
    len: usize,
    keys: [(usize, usize, usize, u64); READS],
    sums: [([f64; 4], f64); READS],
}

impl Reads {
    /// Forgets every sum (a new window).
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// [`Watch::taylor`] at `pt`, a point of `seg`: its host's sums taken from an earlier call
    /// (since [`Reads::clear`]) with the same host, orders and time, whose point must then be
    /// the same one (the search's window start, or a point evaluated directly at that time).
    #[inline]
    pub fn taylor(&mut self, w: &Watch, seg: &Segment, d: &Dynamics, pt: &Point) -> Taylor {
        let Some((host, order, bound_order)) = w.reads() else {
            return w.taylor(seg, d, pt);
        };
        let key = (host, order, bound_order, pt.t.to_bits());
        let (x, bound4) = match self.keys[..self.len].iter().position(|k| *k == key) {
            Some(i) => self.sums[i],
            None => {
                let sums = seg.derivs4_bound(d, pt, host, order, bound_order);
                if self.len < READS {
                    (self.keys[self.len], self.sums[self.len]) = (key, sums);
                    self.len += 1;
                }
                sums
            }
        };
        w.compose(d, pt.t, x, bound4)
    }
}

/// One coarse level's part of a displacement derivative ([`Segment::derivs4_levels`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Split {
    /// Four successive derivatives of the slow terms and the forced response.
    pub x: [f64; 4],
    /// A bound on the next-but-three derivative of the slow terms and the forced response from
    /// the point on.
    pub bound4: f64,
    /// A bound on the fast terms' part of the first of the four from the point on.
    pub fast: f64,
}

/// A function value with three derivatives at a point, and a bound on the fourth derivative
/// valid from that point on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Taylor {
    /// The value and its first three derivatives in time.
    pub h: [f64; 4],
    /// A bound on the fourth derivative from the point on.
    pub bound4: f64,
}

impl Watch {
    /// The bed this function watches.
    pub fn bed(&self) -> usize {
        match *self {
            Watch::Contact { bed, .. } | Watch::GapBottom { bed, .. } | Watch::GapTop { bed, .. } => bed,
            Watch::Pair { upper, .. } => upper,
        }
    }

    /// The bed and side (`true`: top) of an impact this function signals; `None` for a
    /// contact force.
    pub fn impact(&self) -> Option<(usize, bool)> {
        match *self {
            Watch::GapBottom { bed, .. } => Some((bed, false)),
            Watch::GapTop { bed, .. } => Some((bed, true)),
            Watch::Contact { .. } | Watch::Pair { .. } => None,
        }
    }

    /// The lower and upper grains of a grain-grain collision this function signals.
    pub fn pair(&self) -> Option<(usize, usize)> {
        match *self {
            Watch::Pair { lower, upper, .. } => Some((lower, upper)),
            _ => None,
        }
    }

    /// The host's displacement derivatives a function reads: `(host, first order, bound
    /// order)`; `None` for a grain pair (gravity alone).
    #[inline]
    pub fn reads(&self) -> Option<(usize, usize, usize)> {
        match *self {
            Watch::Contact { host, .. } => Some((host, 2, 6)),
            Watch::GapBottom { host, .. } | Watch::GapTop { host, .. } => Some((host, 0, 4)),
            Watch::Pair { .. } => None,
        }
    }

    /// Value, derivatives and bound at a point of a segment.
    #[inline]
    pub fn taylor(&self, seg: &Segment, d: &Dynamics, pt: &Point) -> Taylor {
        match *self {
            Watch::Contact { host, .. } => {
                let (x, bound4) = seg.derivs4_bound(d, pt, host, 2, 6);
                self.compose(d, pt.t, x, bound4)
            }
            Watch::GapBottom { host, .. } | Watch::GapTop { host, .. } => {
                let (x, bound4) = seg.derivs4_bound(d, pt, host, 0, 4);
                self.compose(d, pt.t, x, bound4)
            }
            Watch::Pair { .. } => self.compose(d, pt.t, [0.0; 4], 0.0),
        }
    }

    /// The function's Taylor data at time `t` from its host's displacement derivatives `x`
    /// (those [`Watch::reads`]) and their bound.
    #[inline]
    pub fn compose(&self, d: &Dynamics, t: f64, x: [f64; 4], bound4: f64) -> Taylor {
        match *self {
            Watch::Contact { bed, sigma, .. } => {
                let g = d.system.dampers[bed].gravity();
                Taylor { h: [sigma * (x[0] + g), sigma * x[1], sigma * x[2], sigma * x[3]], bound4 }
            }
            Watch::GapBottom { bed, y0, u0, tf, .. } => {
                let g = d.system.dampers[bed].gravity();
                let (y, u) = super::bed::flight(g, tf, y0, u0, t);
                Taylor { h: [y - x[0], u - x[1], -g - x[2], -x[3]], bound4 }
            }
            Watch::GapTop { bed, d: clearance, y0, u0, tf, .. } => {
                let g = d.system.dampers[bed].gravity();
                let (y, u) = super::bed::flight(g, tf, y0, u0, t);
                Taylor { h: [x[0] + clearance - y, x[1] - u, x[2] + g, x[3]], bound4 }
            }
            Watch::Pair { upper, lower_flight: [tl, yl, ul], upper_flight: [tu, yu, uu], .. } => {
                let g = d.system.dampers[upper].gravity();
                let (a, va) = super::bed::flight(g, tl, yl, ul, t);
                let (b, vb) = super::bed::flight(g, tu, yu, uu, t);
                Taylor { h: [b - a, vb - va, 0.0, 0.0], bound4: 0.0 }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::system::System;
    use nalgebra::DVector;
    use std::f64::consts::PI;

    /// The host sums kept for a window give every watch the Taylor data it computes alone, to
    /// the bit: a flying bed's two gaps, a bed resting on the same host, another host, and
    /// another point in the same window.
    #[test]
    fn shared_host_sums_give_each_watch_its_own_numbers() {
        let n = 12;
        let s = Structure::chain(&vec![0.2; n], &vec![1e5; n], Damping::Rayleigh { alpha: 1.0, beta: 1e-5 });
        let dampers = [n - 1, n - 1, n - 3].iter().map(|&h| Damper::new(h, 0.02, Clearance::from_m(1e-3))).collect();
        let d = Dynamics::new(&System::plastic(s, dampers, 0, 1.0), 2.0 * PI * 20.0).unwrap();
        let x = DVector::from_fn(n, |i, _| 1e-4 * (i as f64 * 0.7).sin());
        let v = DVector::from_fn(n, |i, _| 1e-2 * (i as f64 * 1.3).cos());
        let seg = Segment::start(&d, 0b010, 0.01, &x, &v);
        let (y0, u0, tf) = (2e-4, 0.05, 0.009);
        let watches = [
            Watch::GapBottom { bed: 0, host: n - 1, y0, u0, tf },
            Watch::GapTop { bed: 0, host: n - 1, d: 1e-3, y0, u0, tf },
            Watch::Contact { bed: 1, host: n - 1, sigma: 1.0 },
            Watch::GapBottom { bed: 2, host: n - 3, y0, u0, tf },
            Watch::GapTop { bed: 2, host: n - 3, d: 1e-3, y0, u0, tf },
        ];
        // Both points in one window (no clear between them): the time tells their sums apart.
        let mut reads = Reads::default();
        for t in [0.01, 0.0103] {
            let pt = seg.point(&d, t);
            for _ in 0..2 {
                for w in &watches {
                    let (got, want) = (reads.taylor(w, &seg, &d, &pt), w.taylor(&seg, &d, &pt));
                    assert!(got.h.iter().zip(&want.h).all(|(a, b)| a.to_bits() == b.to_bits()), "{w:?} at {t}");
                    assert_eq!(got.bound4.to_bits(), want.bound4.to_bits());
                }
            }
        }
    }
}
