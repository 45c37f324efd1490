//! One configuration's motion in closed form while the ground's acceleration is linear in
//! time (docs/model.md section 5, "Recorded ground motions"): the structure's relative displacement is
//! a sum of its configuration's modes plus a particular solution linear in time, a flying
//! bed's relative position a cubic. Everything the event search and the measurements read.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use crate::sim::motion::system::Modes;

/// What one configuration adds to its decomposition under a ground acceleration: the load per
/// unit ground acceleration `L_c` (the bare structure's `L` and each riding bed's `m r_p` at
/// its host), `G = K^-1 L_c` and `H = K^-1 C G`, which give the particular solution of a
/// linear ground acceleration `a + s (t - t0)`: `x_p(t) = s_w - G a + H s - G s (t - t0)`
/// (`s_w` the static offset under the riding beds' weights).
#[derive(Debug, Clone)]
pub(super) struct Particular {
    /// `L_c`, kg.
    pub load: DVector<f64>,
    /// `G = K^-1 L_c`, m per m/s^2.
    pub g: DVector<f64>,
    /// `H = K^-1 C G`, m per m/s^3.
    pub h: DVector<f64>,
}

impl Particular {
    /// The particular parts of a configuration whose load per unit ground acceleration is
    /// `load`.
    pub fn of(load: DVector<f64>, k_inv: &DMatrix<f64>, c: &DMatrix<f64>) -> Particular {
        let g = k_inv * &load;
        let h = k_inv * (c * &g);
        Particular { load, g, h }
    }
}

/// A bed in flight on a piece: its host, gravity along its motion, the host's share of the
/// ground's motion `r_p`, and its relative position and velocity at the piece's start.
#[derive(Debug, Clone, Copy)]
pub(super) struct Flight {
    /// The bed.
    pub bed: usize,
    /// Its mass, kg.
    pub mass: f64,
    /// Gravity along its motion, m/s^2.
    pub gravity: f64,
    /// `r` at its host.
    pub follow: f64,
    /// Position relative to the ground at the start, m.
    pub y0: f64,
    /// Velocity relative to the ground at the start, m/s.
    pub w0: f64,
}

/// One configuration from a start time on, under the ground acceleration `a0 + slope (t -
/// t0)`.
#[derive(Debug, Clone)]
pub(super) struct Piece<'a> {
    pub modes: &'a Modes,
    /// The ground's acceleration at the start, m/s^2, and its slope, m/s^3.
    pub a0: f64,
    pub slope: f64,
    /// The homogeneous terms' coefficients and their moduli.
    c: Vec<Complex64>,
    c_abs: Vec<f64>,
    /// The particular solution at the start and its (constant) velocity.
    q0: DVector<f64>,
    q1: DVector<f64>,
    /// The beds in flight.
    pub flights: Vec<Flight>,
}

/// The factors that carry a piece's terms `dt` later ([`Piece::factors`]).
#[derive(Debug, Clone)]
pub(super) struct Factors {
    /// The shift, s.
    pub dt: f64,
    e: Vec<Complex64>,
    decay: Vec<f64>,
}

/// The terms `c_r e^{lambda_r s}` at one time `s` after a piece's start, and their moduli.
#[derive(Debug, Clone, Default)]
pub(super) struct At {
    /// Time since the piece's start, s.
    pub s: f64,
    e: Vec<Complex64>,
    e_abs: Vec<f64>,
}

impl<'a> Piece<'a> {
    /// The piece of configuration `modes` (with `part` its particular parts) from a state `(x, v)`, under the ground acceleration `a0 + slope (t - t0)`.
    pub fn start(
        modes: &'a Modes,
        part: &Particular,
        (x, v): (&DVector<f64>, &DVector<f64>),
        (a0, slope): (f64, f64),
        flights: Vec<Flight>,
    ) -> Piece<'a> {
        let n = x.len();
        let q0 = &modes.offset - &part.g * a0 + &part.h * slope;
        let q1 = -&part.g * slope;
        let len = modes.lambda.len();
        let mut c = vec![Complex64::new(0.0, 0.0); len];
        for j in 0..2 * n {
            let z = if j < n { x[j] - q0[j] } else { v[j - n] - q1[j - n] };
            for (r, c) in c.iter_mut().enumerate() {
                *c += modes.inverse[(r, j)] * z;
            }
        }
        let c_abs = c.iter().map(|c| c.norm()).collect();
        Piece { modes, a0, slope, c, c_abs, q0, q1, flights }
    }

    /// The terms at `s` after the start.
    pub fn at(&self, s: f64) -> At {
        let mut at = At::default();
        self.at_into(s, &mut at);
        at
    }

    /// [`Piece::at`] written over `at`.
    pub fn at_into(&self, s: f64, at: &mut At) {
        at.s = s;
        at.e.clear();
        at.e_abs.clear();
        for ((c, c_abs), l) in self.c.iter().zip(&self.c_abs).zip(&self.modes.lambda) {
            let decay = (l.re * s).exp();
            let (si, co) = (l.im * s).sin_cos();
            at.e.push(c * Complex64::new(decay * co, decay * si));
            at.e_abs.push(c_abs * decay);
        }
    }

    /// The factors `e^{lambda_r dt}` and their moduli, which carry the terms `dt` later by
    /// multiplication alone ([`Piece::shifted`]).
    pub fn factors(&self, dt: f64) -> Factors {
        let e = self.modes.lambda.iter().map(|l| (l * dt).exp()).collect();
        let decay = self.modes.lambda.iter().map(|l| (l.re * dt).exp()).collect();
        Factors { dt, e, decay }
    }

    /// The terms at `from.s + factors.dt`, from those at `from` by multiplication: within a
    /// few roundings of [`Piece::at`] per shift.
    pub fn shifted(&self, from: &At, factors: &Factors) -> At {
        At {
            s: from.s + factors.dt,
            e: from.e.iter().zip(&factors.e).map(|(e, f)| e * f).collect(),
            e_abs: from.e_abs.iter().zip(&factors.decay).map(|(e, f)| e * f).collect(),
        }
    }

    /// The ground's acceleration at `s` after the start, m/s^2.
    pub fn ground(&self, s: f64) -> f64 {
        self.a0 + self.slope * s
    }

    /// Derivative `order` (0 to 6) of coordinate `p`'s displacement relative to the ground.
    pub fn deriv(&self, at: &At, p: usize, order: usize) -> f64 {
        let row = &self.modes.vl[p][order];
        let hom: f64 = row.iter().zip(&at.e).map(|(a, e)| a.re * e.re - a.im * e.im).sum();
        hom + match order {
            0 => self.q0[p] + self.q1[p] * at.s,
            1 => self.q1[p],
            _ => 0.0,
        }
    }

    /// A bound on `|x_p^(order)|` over `[a.s, b.s]` (each term's modulus at the larger end).
    pub fn bound(&self, a: &At, b: &At, p: usize, order: usize) -> f64 {
        let row = &self.modes.vl_abs[p][order];
        let hom: f64 = row.iter().zip(a.e_abs.iter().zip(&b.e_abs)).map(|(r, (ea, eb))| r * ea.max(*eb)).sum();
        hom + if order == 1 { self.q1[p].abs() } else { 0.0 }
    }

    /// Position, velocity and acceleration relative to the ground of flight `f` at `s`.
    pub fn flight(&self, f: &Flight, s: f64) -> [f64; 3] {
        let (a, k) = (self.a0 * f.follow, self.slope * f.follow);
        [
            f.y0 + f.w0 * s - 0.5 * (f.gravity + a) * s * s - k * s * s * s / 6.0,
            f.w0 - (f.gravity + a) * s - 0.5 * k * s * s,
            -(f.gravity + a) - k * s,
        ]
    }

    /// Displacements and velocities of every coordinate at `at`.
    pub fn state(&self, at: &At) -> (DVector<f64>, DVector<f64>) {
        let n = self.q0.len();
        (DVector::from_fn(n, |p, _| self.deriv(at, p, 0)), DVector::from_fn(n, |p, _| self.deriv(at, p, 1)))
    }
}
