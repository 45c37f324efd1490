//! The linearised flow: the derivative of the state at the end of a run with respect to the
//! state at its start, carried exactly through the closed-form segments and the events.
//!
//! The full state is `xi = (x_1..x_n, v_1..v_n, y_1, u_1, ..., y_N, u_N)`: the masses'
//! displacements and velocities and every bed's position and velocity. A bed that rests on
//! its bottom or top has no freedom of its own: its rows are copies of its host's (its
//! position differs by a constant, which a derivative does not see).
//!
//! - Between events, in configuration `S`, the masses obey `z' = A_S z + forcing`, so a
//!   variation moves with `Phi(tau) = V e^(Lambda tau) V^-1`, from the eigendecomposition the
//!   simulator already holds; a free bed's variation moves as `dy += tau du`.
//! - At an event at time `t_e` where an event function `h` reaches zero, with jump map `g`
//!   (the momentum exchange of an impact) of derivative `G`, and vector fields `f-` before
//!   and `f+` after, a variation jumps by the saltation matrix
//!   `S = G + (f+ - G f-) grad(h)^T / (grad(h) . f-)`: the event time moves with the
//!   variation, and during that shift the motion follows the other vector field.
//!   A lift-off (a contact force reaching zero) changes neither the state nor the
//!   accelerations (the contact force was zero), so its saltation matrix is the identity.
//!
//! No I/O; the result is checked against central differences of the same map in the tests.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::carried::Carried;
use crate::sim::motion::engine::{Bed, Observer, State};
use crate::sim::motion::segment::{Segment, Watch};
use crate::sim::motion::system::Dynamics;

/// Smallest relative impact speed, over `omega L`, below which an orbit counts as grazing
/// (its map is not smooth: the derivative grows without bound as the speed goes to zero).
pub const GRAZE: f64 = 1e-6;

/// The derivative of the full state with respect to `k` chosen start coordinates.
#[derive(Debug, Clone)]
pub struct Tangent {
    /// `D x k`, `D = 2n + 2N`. Above 8 degrees of freedom with more than one column its
    /// masses' rows are carried in modal coordinates during a run and stale until
    /// [`Tangent::matrix`] forms them.
    pub m: DMatrix<f64>,
    /// The masses' rows in the modal coordinates of the present configuration, while a run
    /// carries them so (`sim::orbits::carried`).
    carried: Option<Carried>,
    /// Whether runs carry the masses' rows in modal coordinates.
    modal: bool,
    /// A row of the derivative (one number per column), and a vector of the masses' rows (an
    /// impact's outer product's, the forced response's derivative) (modal coordinates only).
    row_buf: Vec<f64>,
    row_buf2: Vec<f64>,
    lift: Vec<f64>,
    /// Modal coordinates only: the beds attached in the last segment, whose rows copy their
    /// hosts' only when read (at an event, and when the rows are formed).
    attached: Vec<bool>,
    /// Smallest relative speed of an impact on the way, m/s (a graze has speed 0: the
    /// derivative is unbounded there).
    pub min_impact_speed: f64,
    /// Events at which two or more beds hit at the same time (the map is not smooth there).
    pub simultaneous: usize,
    /// For a map that ends at an impact (the impact section): the bed and the number of its
    /// bottom impacts after which the derivative is taken at the moving event time and frozen.
    pub until: Option<(usize, usize)>,
    seen: usize,
    /// Once frozen: the derivative of the event time with respect to the coordinates, s.
    pub dt: Option<nalgebra::RowDVector<f64>>,
    /// The column that is the derivative in the forcing frequency (at fixed start state and
    /// time), if any: between events it gains the frequency derivative of the forced response.
    omega_column: Option<usize>,
    n: usize,
    /// Buffers reused at every segment and event: the transition matrix, the product with
    /// it, the vector fields before and after an event, and the event function's gradient.
    phi: DMatrix<f64>,
    top: DMatrix<f64>,
    planes: Planes,
    f_minus: DVector<f64>,
    f_plus: DVector<f64>,
    g_f: DVector<f64>,
    grad: nalgebra::RowDVector<f64>,
}

/// Row of `y_j` in the full state (`u_j` is the next one).
fn bed_row(n: usize, j: usize) -> usize {
    2 * n + 2 * j
}

impl Tangent {
    /// Starts from `m0` (`D x k`): how the start state depends on the chosen coordinates.
    pub fn new(d: &Dynamics, m0: DMatrix<f64>) -> Tangent {
        let (n, k, full) = (d.system.dof(), m0.ncols(), Tangent::full_dim(d));
        let modal = n > PLAIN_DOF && k > 1;
        // The transition and its product are not formed in modal coordinates.
        let (square, rows) = if modal { (0, 0) } else { (2 * n, 2 * n) };
        Tangent {
            carried: None,
            modal,
            row_buf: vec![0.0; k],
            row_buf2: vec![0.0; k],
            lift: Vec::new(),
            attached: Vec::new(),
            phi: DMatrix::zeros(square, square),
            top: DMatrix::zeros(rows, k),
            planes: Planes::default(),
            f_minus: DVector::zeros(full),
            f_plus: DVector::zeros(full),
            g_f: DVector::zeros(full),
            grad: nalgebra::RowDVector::zeros(k),
            m: m0,
            min_impact_speed: f64::INFINITY,
            simultaneous: 0,
            until: None,
            seen: 0,
            dt: None,
            omega_column: None,
            n: d.system.dof(),
        }
    }

    /// Ends at the `count`-th bottom impact of `bed`: the derivative of the state just after
    /// it, at its own (moving) time, and of that time ([`Tangent::dt`]).
    pub fn until_impact(mut self, bed: usize, count: usize) -> Tangent {
        self.until = Some((bed, count));
        self
    }

    /// Column `col` of the start's derivative is the derivative in the forcing frequency
    /// `omega`: in each segment `z = Phi(tau) (z_a - z_p(t_a)) + z_p(t)`, so that column gains
    /// `dz_p(t_b)/domega - Phi(tau) dz_p(t_a)/domega` (the forced response `z_p` is the only
    /// part of the flow that depends on `omega`; the event functions do not, so the saltation
    /// at events is the same as for a change of the start state).
    pub fn with_omega_column(mut self, col: usize) -> Tangent {
        self.omega_column = Some(col);
        self
    }

    /// The start is at a forcing phase that varies too: column `col` of the start's derivative
    /// is that of the phase, `-f(xi_0, t_0) / omega` (starting later from the same state is
    /// starting on time from the state shifted back along the flow).
    /// A bed that rests at the start but is pulled off (negative contact force) leaves at
    /// once: the flow after the start is the one with that bed free.
    pub fn phase_column(d: &Dynamics, start: &State, m0: &mut DMatrix<f64>, col: usize) {
        let mut s = start.clone();
        let (a, _) = d.accelerations(s.mask(), s.t, &s.x, &s.v);
        for j in 0..s.beds.len() {
            let p = d.system.dampers[j].host;
            let Some(top) = s.beds[j].end() else { continue };
            let sigma = Bed::contact_sign(top);
            if !d.system.dampers[j].clearance.is_zero() && sigma * (a[p] + d.system.dampers[j].gravity()) < 0.0 {
                let (y0, u0) = s.bed_motion(d, j);
                s.beds[j] = Bed::Free { t0: s.t, y0, u0 };
            }
        }
        let mut f = DVector::zeros(Tangent::full_dim(d));
        Tangent::field(d, &s, &mut f);
        for r in 0..m0.nrows() {
            m0[(r, col)] = -f[r] / d.omega;
        }
    }

    /// Dimension of the full state of `d`.
    pub fn full_dim(d: &Dynamics) -> usize {
        2 * d.system.dof() + 2 * d.system.dampers.len()
    }

    /// The rows of attached beds copy their host's.
    fn slave(&mut self, d: &Dynamics, beds: &[Bed]) {
        self.slave_where(d, beds, |_| true);
    }

    /// The rows of the attached beds `which` selects copy their host's.
    fn slave_where(&mut self, d: &Dynamics, beds: &[Bed], which: impl Fn(usize) -> bool) {
        let n = self.n;
        for (j, b) in beds.iter().enumerate() {
            if b.attached() && which(j) {
                let p = d.system.dampers[j].host;
                let r = bed_row(n, j);
                if let Some(carried) = self.carried.as_mut() {
                    for (row, from) in [(r, p), (r + 1, n + p)] {
                        carried.row(d, from, &mut self.row_buf);
                        for (c, v) in self.row_buf.iter().enumerate() {
                            self.m[(row, c)] = *v;
                        }
                    }
                    continue;
                }
                for c in 0..self.m.ncols() {
                    self.m[(r, c)] = self.m[(p, c)];
                    self.m[(r + 1, c)] = self.m[(n + p, c)];
                }
            }
        }
    }

    /// The derivative with every row formed (the masses' rows from their modal coordinates,
    /// if a run carried them so): what a run's caller reads.
    pub fn matrix(&mut self, d: &Dynamics) -> &DMatrix<f64> {
        self.materialise(d);
        &self.m
    }

    /// Forms the masses' rows from their modal coordinates and stops carrying them.
    fn materialise(&mut self, d: &Dynamics) {
        if let Some(carried) = self.carried.take() {
            carried.physical_into(d, self.m.rows_mut(0, 2 * self.n));
            let n = self.n;
            for (j, _) in self.attached.iter().enumerate().filter(|(_, a)| **a) {
                let (p, r) = (d.system.dampers[j].host, bed_row(n, j));
                for c in 0..self.m.ncols() {
                    self.m[(r, c)] = self.m[(p, c)];
                    self.m[(r + 1, c)] = self.m[(n + p, c)];
                }
            }
        }
    }

    /// The full vector field at a state (masses' velocities and accelerations in the state's
    /// configuration, beds' velocities and accelerations), into `f` (of the full dimension).
    fn field(d: &Dynamics, s: &State, f: &mut DVector<f64>) {
        let n = d.system.dof();
        let nb = s.beds.len();
        let a = d.accelerations_only(s.mask(), s.t, &s.x, &s.v);
        for i in 0..n {
            f[i] = s.v[i];
            f[n + i] = a[i];
        }
        for j in 0..nb {
            let p = d.system.dampers[j].host;
            let (_, u) = s.bed_motion(d, j);
            f[bed_row(n, j)] = u;
            f[bed_row(n, j) + 1] = if s.beds[j].attached() { a[p] } else { -d.system.dampers[j].gravity() };
        }
    }
}

impl Tangent {
    /// A segment in modal coordinates: into the segment's configuration, then each term
    /// turned and decayed; the frequency's column gains the forced response's derivative as
    /// in the physical form, `z_p'(t_b) - Phi z_p'(t_a)`.
    fn carry(&mut self, d: &Dynamics, seg: &Segment, t_a: f64, t_b: f64) {
        let n = self.n;
        let slot = d.slot(seg.mask);
        match self.carried.as_mut() {
            Some(carried) => carried.change(d, slot),
            None => self.carried = Some(Carried::enter(d, slot, self.m.rows(0, 2 * n))),
        }
        let Some(carried) = self.carried.as_mut() else { return };
        // The forced response's frequency derivative at `t` as one vector (into `self.lift`,
        // reused: no allocation a segment).
        let stacked = |(x, v): (DVector<f64>, DVector<f64>), out: &mut Vec<f64>| {
            out.clear();
            out.extend(x.iter().chain(v.iter()));
        };
        match self.omega_column {
            Some(c) => {
                stacked(d.particular_d_omega(seg.mask, t_a), &mut self.lift);
                carried.add_to_column(d, c, &self.lift, -1.0);
                carried.advance(d, t_b - t_a);
                stacked(d.particular_d_omega(seg.mask, t_b), &mut self.lift);
                carried.add_to_column(d, c, &self.lift, 1.0);
            }
            None => carried.advance(d, t_b - t_a),
        }
    }

    /// An impact's saltation on a derivative whose masses' rows are in modal coordinates:
    /// the same arithmetic as the physical form (`G`, then `w grad(h)^T / h_dot`), with the
    /// masses' rows changed by two outer products. `w` is `f+ - G f-` (in `self.g_f`).
    fn impact_carried(&mut self, d: &Dynamics, jump: &crate::sim::motion::single::ImpactJump, h_dot: f64) {
        let Some(carried) = self.carried.as_mut() else { return };
        let n = self.n;
        let (xp, vp) = (&mut self.row_buf, &mut self.row_buf2);
        carried.row(d, jump.host_x, xp);
        carried.row(d, jump.host_v, vp);
        // The gradient before the exchange (as `ImpactJump::gradient_into`).
        for (c, g) in self.grad.iter_mut().enumerate() {
            *g = (self.m[(jump.bed_y, c)] - xp[c]) * jump.sign;
        }
        // The exchange (as `ImpactJump::apply_g`): the host's velocity row changes by `dv`
        // (into `xp`, no longer needed), every following row by its share of it; the bed's
        // velocity row takes its new value.
        for c in 0..vp.len() {
            let (v, u) = (vp[c], self.m[(jump.bed_u, c)]);
            let new_v = v * (1.0 - jump.a) + u * jump.a;
            self.m[(jump.bed_u, c)] = v * jump.b + u * (1.0 - jump.b);
            xp[c] = new_v - v;
        }
        self.lift.clear();
        self.lift.resize(2 * n, 0.0);
        self.lift[jump.host_v] = 1.0;
        for &(r, fr) in &jump.follow {
            self.lift[r] += fr;
        }
        carried.add_outer(d, &self.lift, xp);
        for &(r, host_v) in &jump.riders_u {
            carried.row(d, host_v, vp);
            for (c, v) in vp.iter().enumerate() {
                self.m[(r, c)] = *v;
            }
        }
        if h_dot != 0.0 {
            let w = &self.g_f;
            for (c, g) in self.grad.iter().enumerate() {
                xp[c] = g / h_dot;
            }
            carried.add_outer(d, &w.as_slice()[..2 * n], xp);
            for r in 2 * n..self.m.nrows() {
                for c in 0..self.m.ncols() {
                    self.m[(r, c)] += w[r] / h_dot * self.grad[c];
                }
            }
        }
    }
}

/// `Phi(tau)` of configuration `mask`, into `out` (`2n x 2n`): the derivative of `(x, v)`
/// after `tau` with respect to `(x, v)` at the start.
fn transition_into(d: &Dynamics, mask: usize, tau: f64, out: &mut DMatrix<f64>) {
    let cfg = d.config(mask);
    let n = d.system.dof();
    let len = cfg.modes.lambda.len();
    let mut e = crate::sim::motion::buf::Terms::<Complex64>::zeros(len);
    for (e, l) in e.iter_mut().zip(&cfg.modes.lambda) {
        *e = (l * tau).exp();
    }
    let mut scaled = crate::sim::motion::buf::Terms::<Complex64>::zeros(len);
    // The inverse's column `j` holds the terms' coefficients of start coordinate `j`, in order
    // (column-major storage: a contiguous run).
    let (inverse, stride) = (cfg.modes.inverse.as_slice(), cfg.modes.inverse.nrows());
    for i in 0..2 * n {
        let row = if i < n { &cfg.modes.vl[i][0] } else { &cfg.modes.vl[i - n][1] };
        for ((s, w), e) in scaled.iter_mut().zip(&row[..len]).zip(&e[..]) {
            *s = w * e;
        }
        for j in 0..2 * n {
            let column = &inverse[j * stride..j * stride + len];
            // The real part of the sum over the terms, added in order from -0 (as `Sum` does).
            out[(i, j)] = column.iter().zip(&scaled[..len]).fold(-0.0, |acc, (w, s)| acc + (s.re * w.re - s.im * w.im));
        }
    }
}

/// `Phi(tau) z` of configuration `mask` for one vector `z` (`2n`), into `out`: the terms'
/// coefficients of `z`, advanced by `e^(lambda tau)`, summed back to displacements and
/// velocities ([`transition_into`]'s product, without the matrix).
fn transition_apply(d: &Dynamics, mask: usize, tau: f64, z: &[f64], out: &mut [f64]) {
    let cfg = d.config(mask);
    let n = d.system.dof();
    let len = cfg.modes.lambda.len();
    let (inverse, stride) = (cfg.modes.inverse.as_slice(), cfg.modes.inverse.nrows());
    let mut c = crate::sim::motion::buf::Terms::<Complex64>::zeros(len);
    for (j, zj) in z.iter().enumerate() {
        for (c, w) in c.iter_mut().zip(&inverse[j * stride..j * stride + len]) {
            *c += w * zj;
        }
    }
    for (c, l) in c.iter_mut().zip(&cfg.modes.lambda) {
        *c *= (l * tau).exp();
    }
    for (i, o) in out.iter_mut().enumerate().take(2 * n) {
        let row = if i < n { &cfg.modes.vl[i][0] } else { &cfg.modes.vl[i - n][1] };
        *o = row[..len].iter().zip(&c[..len]).fold(-0.0, |acc, (w, s)| acc + (s.re * w.re - s.im * w.im));
    }
}

/// Degrees of freedom above which the linearised flow multiplies with nalgebra's blocked
/// matrix product (SIMD, cache-aware) instead of the plain loops that keep the paper's
/// small structures' numbers bit for bit (the configurations hold the parts of their inverse
/// from the same size on).
const PLAIN_DOF: usize = crate::sim::motion::system::LARGE_ABOVE;

/// Buffers of the blocked transition: the scaled eigenvector rows, real and imaginary parts
/// (`2n x terms`).
#[derive(Debug, Clone, Default)]
struct Planes {
    s_re: DMatrix<f64>,
    s_im: DMatrix<f64>,
}

/// [`transition_into`] by blocked products: `Phi = Re(S) Re(W) - Im(S) Im(W)` with
/// `S = V_w e^(Lambda tau)` (the weighted displacement and velocity rows) and `W` the rows of
/// `V^-1` of the terms (their parts held by the configuration, [`Modes::inverse_parts`]).
/// `S` is filled a term at a time from the rows stored by term (contiguous).
///
/// [`Modes::inverse_parts`]: crate::sim::motion::system::Modes::inverse_parts
fn transition_blocked(d: &Dynamics, mask: usize, tau: f64, planes: &mut Planes, out: &mut DMatrix<f64>) {
    let cfg = d.config(mask);
    let n = d.system.dof();
    let len = cfg.modes.lambda.len();
    let p = planes;
    if p.s_re.shape() != (2 * n, len) {
        p.s_re = DMatrix::zeros(2 * n, len);
        p.s_im = DMatrix::zeros(2 * n, len);
    }
    let (s_re, s_im) = (p.s_re.as_mut_slice(), p.s_im.as_mut_slice());
    for (r, l) in cfg.modes.lambda.iter().enumerate() {
        let e = (l * tau).exp();
        // Column `r` of `S`: the displacement rows (order 0), then the velocity rows (order 1).
        for order in 0..2 {
            let [w_re, w_im] = &cfg.modes.by_term[order];
            let (w_re, w_im) = (&w_re[r * n..(r + 1) * n], &w_im[r * n..(r + 1) * n]);
            let at = r * 2 * n + order * n;
            let (o_re, o_im) = (&mut s_re[at..at + n], &mut s_im[at..at + n]);
            for (((o_re, o_im), &a), &b) in o_re.iter_mut().zip(o_im.iter_mut()).zip(w_re).zip(w_im) {
                // (a + ib)(e.re + i e.im), as the complex product computes it.
                *o_re = a * e.re - b * e.im;
                *o_im = a * e.im + b * e.re;
            }
        }
    }
    let [i_re, i_im] = &cfg.modes.inverse_parts;
    out.gemm(1.0, &p.s_re, i_re, 0.0);
    out.gemm(-1.0, &p.s_im, i_im, 1.0);
}

impl Observer for Tangent {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        let tau = t_b - t_a;
        if tau <= 0.0 || self.dt.is_some() {
            return;
        }
        let n = self.n;
        if self.modal {
            self.carry(d, seg, t_a, t_b);
        } else if self.m.ncols() == 1 && self.omega_column.is_none() {
            // One vector (a Lyapunov exponent's): carried through the terms without forming
            // `Phi`, in O(n terms) instead of O(n^2 terms).
            transition_apply(d, seg.mask, tau, &self.m.as_slice()[..2 * n], self.top.as_mut_slice());
        } else if n > PLAIN_DOF {
            // Large structures: blocked products (the transition's and `Phi` times the masses'
            // rows), several times faster than the loops below from 16 degrees of freedom.
            transition_blocked(d, seg.mask, tau, &mut self.planes, &mut self.phi);
            self.top.gemm(1.0, &self.phi, &self.m.rows(0, 2 * n), 0.0);
        } else {
            transition_into(d, seg.mask, tau, &mut self.phi);
            // `Phi` times the masses' rows, summed in plain loops (the matrices are at most 16
            // square; a general product's packing costs more than the arithmetic here).
            let (dim, rows) = (2 * n, self.m.nrows());
            let (phi, m, top) = (self.phi.as_slice(), self.m.as_slice(), self.top.as_mut_slice());
            for (c, out) in top.chunks_exact_mut(dim).enumerate() {
                let column = &m[c * rows..c * rows + dim];
                for (i, o) in out.iter_mut().enumerate() {
                    let mut acc = 0.0;
                    for (k, mk) in column.iter().enumerate() {
                        acc += phi[k * dim + i] * mk;
                    }
                    *o = acc;
                }
            }
        }
        if !self.modal {
            self.m.rows_mut(0, 2 * n).copy_from(&self.top);
        }
        let phi = &self.phi;
        if let (Some(c), false) = (self.omega_column, self.modal) {
            let (xa, va) = d.particular_d_omega(seg.mask, t_a);
            let (xb, vb) = d.particular_d_omega(seg.mask, t_b);
            let za = DVector::from_fn(2 * n, |i, _| if i < n { xa[i] } else { va[i - n] });
            let moved = phi * za;
            for i in 0..n {
                self.m[(i, c)] += xb[i] - moved[i];
                self.m[(n + i, c)] += vb[i] - moved[n + i];
            }
        }
        for (j, b) in beds.iter().enumerate() {
            if !b.attached() {
                let r = bed_row(n, j);
                for c in 0..self.m.ncols() {
                    self.m[(r, c)] += tau * self.m[(r + 1, c)];
                }
            }
        }
        if self.carried.is_some() {
            // The attached beds' rows are copied when next read.
            self.attached.clear();
            self.attached.extend(beds.iter().map(Bed::attached));
        } else {
            self.slave(d, beds);
        }
    }

    fn wants_jumps(&self) -> bool {
        true
    }

    fn jump(&mut self, d: &Dynamics, before: &State, after: &State, hits: &[Watch]) {
        if self.dt.is_some() {
            return;
        }
        if self.carried.is_some() {
            // The rows of beds leaving their hosts now, copied from their hosts' (deferred
            // while they rode; those still riding are copied when next read).
            self.slave_where(d, &before.beds, |j| !after.beds[j].attached());
        }
        let mut impacts = hits.iter().filter_map(Watch::impact);
        let Some((j, top)) = impacts.next() else {
            // Lift-offs: no jump in the state or the vector field.
            if self.carried.is_none() {
                self.slave(d, &after.beds);
            }
            self.attached.clear();
            self.attached.extend(after.beds.iter().map(Bed::attached));
            return;
        };
        if impacts.next().is_some() {
            self.simultaneous += 1;
        }
        let n = self.n;
        // The bed model's part (src/sim/motion/single.rs): G and the event function h.
        let jump = crate::sim::motion::single::ImpactJump::new(d, before, j, top, n, |k| bed_row(n, k));
        let freezes = matches!(self.until, Some((bed, count)) if bed == j && !top && self.seen + 1 == count);
        if freezes {
            // The derivative at the event's own time needs every row.
            self.materialise(d);
        }
        self.min_impact_speed = self.min_impact_speed.min(jump.rel.abs());
        Tangent::field(d, before, &mut self.f_minus);
        Tangent::field(d, after, &mut self.f_plus);
        // w = f+ - G f-, into g_f.
        self.g_f.copy_from(&self.f_minus);
        jump.apply_g(&mut self.g_f);
        for (g, fp) in self.g_f.iter_mut().zip(self.f_plus.iter()) {
            *g = fp - *g;
        }
        // The rate of h before the event, and its gradient carried by the derivative so far.
        let h_dot = jump.rate(&self.f_minus);
        if self.carried.is_some() {
            self.impact_carried(d, &jump, h_dot);
            self.attached.clear();
            self.attached.extend(after.beds.iter().map(Bed::attached));
            if let Some((bed, _)) = self.until {
                if bed == j && !top {
                    self.seen += 1;
                }
            }
            return;
        }
        let w = &self.g_f;
        jump.gradient_into(&self.m, &mut self.grad);
        jump.apply_g(&mut self.m);
        if h_dot != 0.0 {
            for c in 0..self.m.ncols() {
                for r in 0..self.m.nrows() {
                    self.m[(r, c)] += w[r] / h_dot * self.grad[c];
                }
            }
        }
        self.slave(d, &after.beds);
        if let Some((bed, count)) = self.until {
            if bed == j && !top {
                self.seen += 1;
                if self.seen == count {
                    // The state at the event's own time: add the flow after it over the shift.
                    let dt = -&self.grad / h_dot;
                    self.m += &self.f_plus * &dt;
                    self.dt = Some(dt);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::system::System;

    /// One vector carried through the terms is the transition matrix times it, to rounding,
    /// on a small and a large structure, in every configuration.
    #[test]
    fn one_vector_is_the_transition_times_it() {
        for n in [3, 12] {
            let s = Structure::chain(&vec![0.2; n], &vec![8e4; n], Damping::ModalRatios(vec![0.02; n]));
            let dampers = (n - 3..n).map(|h| Damper::new(h, 0.02, Clearance::from_m(5e-4))).collect();
            let d = Dynamics::new(&System::plastic(s, dampers, 0, 2.0), 2.0 * std::f64::consts::PI * 30.0).unwrap();
            let mut phi = DMatrix::zeros(2 * n, 2 * n);
            let z: Vec<f64> = (0..2 * n).map(|i| 1.0 + 0.37 * i as f64 - 0.05 * (i * i) as f64).collect();
            let mut out = vec![0.0; 2 * n];
            for mask in 0..8 {
                for tau in [1.3e-4, 0.021] {
                    transition_into(&d, mask, tau, &mut phi);
                    let want = &phi * DVector::from_column_slice(&z);
                    transition_apply(&d, mask, tau, &z, &mut out);
                    let scale = want.amax();
                    let diff = want.iter().zip(&out).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                    assert!(diff <= 1e-12 * scale, "n {n} mask {mask} tau {tau}: {diff:e} of {scale}");
                }
            }
        }
    }

    /// The derivative carried in modal coordinates (large structures) is the one the
    /// transition matrices give, to rounding, through runs with lift-offs and impacts: every
    /// column, the frequency's, and frozen at an impact's own time.
    #[test]
    fn the_modal_derivative_is_the_physical_one() {
        // Three beds (the changes of configuration by their transfers) and seven (128
        // configurations: more than transfers are kept for, changed through the physical rows).
        for beds in [3, 7] {
            modal_against_physical(beds);
        }
    }

    fn modal_against_physical(beds: usize) {
        use crate::sim::motion::engine::Engine;
        use crate::sim::motion::observe::{Both, EventLog};
        let n = 12;
        let s = Structure::chain(&vec![0.2; n], &vec![8e4; n], Damping::ModalRatios(vec![0.02; n]));
        let dampers = (n - beds..n).map(|h| Damper::new(h, 0.02, Clearance::from_m(5e-4))).collect();
        let d = Dynamics::new(&System::plastic(s, dampers, 0, 200.0), 2.0 * std::f64::consts::PI * 12.0).unwrap();
        assert_eq!(d.transfer(0, 1).is_some(), beds == 3);
        let full = Tangent::full_dim(&d);
        let m0 =
            DMatrix::from_fn(full, full + 1, |r, c| if r == c { 1.0 } else { 0.01 * ((r * 5 + c * 3) % 7) as f64 });
        let physical = |t: Tangent| {
            let k = t.m.ncols();
            Tangent { modal: false, phi: DMatrix::zeros(2 * n, 2 * n), top: DMatrix::zeros(2 * n, k), ..t }
        };
        let run = |mut t: Tangent, until: f64| {
            let mut s = State::at_rest(&d);
            let mut log = EventLog::default();
            Engine::new(&d).advance(&mut s, until, &mut Both(&mut t, &mut log)).unwrap();
            let m = t.matrix(&d).clone();
            (m, t.dt, log.0.len())
        };
        let period = 1.0 / 12.0;
        for (until, bottom) in [(6.0 * period, None), (2.5 * period, None), (6.0 * period, Some(2))] {
            let make = || {
                let t = Tangent::new(&d, m0.clone()).with_omega_column(full);
                match bottom {
                    Some(count) => t.until_impact(0, count),
                    None => t,
                }
            };
            let modal = make();
            assert!(modal.modal);
            let (a, dt_a, events) = run(modal, until);
            let (b, dt_b, _) = run(physical(make()), until);
            assert!(events >= 4, "{events} events until {until}");
            assert_eq!(dt_a.is_some(), bottom.is_some());
            let scale = b.amax();
            let diff = (&a - &b).amax();
            assert!(diff <= 1e-11 * scale, "until {until}: {diff:e} of {scale:e}");
            if let (Some(x), Some(y)) = (dt_a, dt_b) {
                assert!((&x - &y).amax() <= 1e-11 * y.amax());
            }
        }
    }

    /// The blocked transition is the plain one's number to rounding, on a structure large
    /// enough to take it, in every configuration, at a short and a long step.
    #[test]
    fn the_blocked_transition_is_the_plain_one() {
        let n = 12;
        let s = Structure::chain(&vec![0.2; n], &vec![8e4; n], Damping::ModalRatios(vec![0.02; n]));
        let dampers = (n - 3..n).map(|h| Damper::new(h, 0.02, Clearance::from_m(5e-4))).collect();
        let d = Dynamics::new(&System::plastic(s, dampers, 0, 2.0), 2.0 * std::f64::consts::PI * 30.0).unwrap();
        let (mut plain, mut blocked) = (DMatrix::zeros(2 * n, 2 * n), DMatrix::zeros(2 * n, 2 * n));
        let mut planes = Planes::default();
        for mask in 0..8 {
            for tau in [1.3e-4, 0.021] {
                transition_into(&d, mask, tau, &mut plain);
                transition_blocked(&d, mask, tau, &mut planes, &mut blocked);
                let scale = plain.amax();
                let diff = (&plain - &blocked).amax();
                assert!(scale > 0.1 && diff <= 1e-13 * scale, "mask {mask} tau {tau}: {diff:e} of {scale}");
            }
        }
    }
}
