//! The exact response of a bare (linear) structure to a recorded ground motion
//! (docs/model.md section 5, "Recorded ground motions"): the ground's acceleration linear between
//! samples, the structure's state carried from sample to sample by the matrix exponential of
//! its first-order system augmented with the ground's acceleration and its slope, so each
//! step is exact (no time-stepping error; the exponential to rounding). Each interval is cut
//! into `sub` equal pieces, and the largest drift and floor acceleration between their ends
//! are found on the cubic that matches each end's value and rate (an error of order
//! `(omega h)^4 / 384` of the amplitude at a piece of length `h`). No I/O.
//!
//! The structure moves relative to supports that accelerate with the record along every
//! coordinate it follows (`r`: ones for a chain; a reduced model's supports as they say):
//! `M uddot + C udot + K u = -L a_g(t)` (`L = M r` for a chain), the absolute acceleration
//! `uddot + r a_g`.

use nalgebra::{DMatrix, DVector};

use super::ground::GroundMotion;
use super::structure::Structure;

/// A structure's response to a record at the record's samples, and its peaks.
#[derive(Debug, Clone)]
pub struct Response {
    /// The sample times, s.
    pub t: Vec<f64>,
    /// Per sample: each coordinate's displacement relative to the supports, m.
    pub u: Vec<DVector<f64>>,
    /// Per sample: each coordinate's absolute acceleration, m/s^2.
    pub accel: Vec<DVector<f64>>,
    /// The largest magnitude of each coordinate's relative displacement, m.
    pub peak_displacement: Vec<f64>,
    /// The largest magnitude of each storey's drift, m (empty: not a chain).
    pub peak_drift: Vec<f64>,
    /// The largest magnitude of each coordinate's absolute acceleration, m/s^2.
    pub peak_accel: Vec<f64>,
    /// The energy the ground put in over the record, `-integral udot^T L a_g dt`, J.
    pub energy_input: f64,
    /// The energy the damping took out, `integral udot^T C udot dt`, J.
    pub energy_viscous: f64,
    /// The energy stored at the record's end, kinetic (relative) and strain, J.
    pub energy_stored: f64,
}

/// Why a response cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResponseError {
    /// The mass matrix is singular.
    #[error("the mass matrix is singular: no acceleration follows from the forces")]
    SingularMass,
    /// The record has fewer than two samples or a step that is not positive.
    #[error("the record needs two samples or more at a positive step (it has {samples} at {dt_s} s)")]
    Record {
        /// Its samples.
        samples: usize,
        /// Its step, s.
        dt_s: f64,
    },
}

/// The first-order system `z' = A z + b a_g`, `z = [u; udot]`, and what reads the absolute
/// acceleration off a state: `-M^-1 (K u + C udot) + (r - M^-1 L) a_g`.
struct FirstOrder {
    a: DMatrix<f64>,
    b: DVector<f64>,
    /// The load per unit ground acceleration `L`, the damping matrix, for the energies.
    load: DVector<f64>,
    c: DMatrix<f64>,
    /// `-M^-1 [K C]`: the relative acceleration's part from the state.
    read: DMatrix<f64>,
    /// `r - M^-1 L`: the absolute acceleration's part from the ground's (0 for a chain).
    direct: DVector<f64>,
}

impl FirstOrder {
    fn of(structure: &Structure) -> Result<FirstOrder, ResponseError> {
        let n = structure.dof();
        let m = structure.mass_matrix();
        let m_inv = m.clone().try_inverse().ok_or(ResponseError::SingularMass)?;
        let supports = super::base::BaseMotion::of(structure, 1.0);
        let (r, load) = (DVector::from_vec(supports.follow), DVector::from_vec(supports.load));
        let mut read = DMatrix::zeros(n, 2 * n);
        read.view_mut((0, 0), (n, n)).copy_from(&(-&m_inv * &structure.stiffness));
        read.view_mut((0, n), (n, n)).copy_from(&(-&m_inv * &structure.damping));
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, 2 * n)).copy_from(&read);
        let rel = &m_inv * &load;
        let mut b = DVector::zeros(2 * n);
        b.rows_mut(n, n).copy_from(&(-&rel));
        Ok(FirstOrder { a, b, read, direct: r - rel, load, c: structure.damping.clone() })
    }

    /// The map of one step `h`: `[z; a_g; slope]` at its start to `z` at its end (the
    /// exponential of the system augmented with `a_g' = slope, slope' = 0`).
    fn step(&self, h: f64) -> DMatrix<f64> {
        let s = self.a.nrows();
        let mut aug = DMatrix::zeros(s + 2, s + 2);
        aug.view_mut((0, 0), (s, s)).copy_from(&self.a);
        aug.view_mut((0, s), (s, 1)).copy_from(&self.b);
        aug[(s, s + 1)] = 1.0;
        (aug * h).exp().rows(0, s).into_owned()
    }
}

/// The largest magnitude of the cubic through `(0, y0)` and `(h, y1)` with slopes `d0` and
/// `d1` over `[0, h]` (its ends and its stationary points inside).
pub fn hermite_peak(y0: f64, d0: f64, y1: f64, d1: f64, h: f64) -> f64 {
    // y(s) = y0 + d0 h s + c2 s^2 + c3 s^3, s in [0, 1].
    let (p0, p1) = (d0 * h, d1 * h);
    let c2 = 3.0 * (y1 - y0) - 2.0 * p0 - p1;
    let c3 = 2.0 * (y0 - y1) + p0 + p1;
    let y = |s: f64| y0 + s * (p0 + s * (c2 + s * c3));
    let mut best = y0.abs().max(y1.abs());
    // y'(s) = p0 + 2 c2 s + 3 c3 s^2.
    let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, p0);
    let mut roots = Vec::with_capacity(2);
    if qa.abs() < 1e-300 {
        if qb != 0.0 {
            roots.push(-qc / qb);
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let q = -0.5 * (qb + qb.signum() * disc.sqrt());
            roots.push(q / qa);
            if q != 0.0 {
                roots.push(qc / q);
            }
        }
    }
    for s in roots.into_iter().filter(|s| *s > 0.0 && *s < 1.0) {
        best = best.max(y(s).abs());
    }
    best
}

/// The response of `structure` (bare, linear) to `record`, each record interval cut into
/// `sub` pieces (at least 1) for the peaks between samples.
pub fn linear_response(structure: &Structure, record: &GroundMotion, sub: usize) -> Result<Response, ResponseError> {
    let samples = record.accel_m_s2.len();
    if samples < 2 || !(record.dt_s > 0.0 && record.dt_s.is_finite()) {
        return Err(ResponseError::Record { samples, dt_s: record.dt_s });
    }
    let n = structure.dof();
    let sys = FirstOrder::of(structure)?;
    let sub = sub.max(1);
    let h = record.dt_s / sub as f64;
    let phi = sys.step(h);
    let s = 2 * n;
    let storeys = if structure.is_chain() { n } else { 0 };
    let mut z = DVector::<f64>::zeros(s);
    let mut aug = DVector::<f64>::zeros(s + 2);
    let mut out = Response {
        t: Vec::with_capacity(samples),
        u: Vec::with_capacity(samples),
        accel: Vec::with_capacity(samples),
        peak_displacement: vec![0.0; n],
        peak_drift: vec![0.0; storeys],
        peak_accel: vec![0.0; n],
        energy_input: 0.0,
        energy_viscous: 0.0,
        energy_stored: 0.0,
    };
    // The energies by Simpson's rule on each piece (its middle state from the half step's
    // map): an error of order `(omega h)^4 / 2880` of the piece's share.
    let half = sys.step(0.5 * h);
    let powers = |z: &DVector<f64>, ag: f64| {
        let v = z.rows(n, n);
        (-(v.dot(&sys.load)) * ag, (v.transpose() * &sys.c * v)[0])
    };
    // The absolute acceleration and its rate at a state where the ground's acceleration is
    // `ag` and its slope `slope`.
    let accel_of = |z: &DVector<f64>, ag: f64| &sys.read * z + &sys.direct * ag;
    let jerk_of = |z: &DVector<f64>, ag: f64, slope: f64| {
        let zdot = &sys.a * z + &sys.b * ag;
        &sys.read * zdot + &sys.direct * slope
    };
    let drift = |v: &DVector<f64>, i: usize| v[i] - if i > 0 { v[i - 1] } else { 0.0 };
    let keep = |out: &mut Response, t: f64, z: &DVector<f64>, ag: f64| {
        out.t.push(t);
        out.u.push(z.rows(0, n).into_owned());
        out.accel.push(accel_of(z, ag));
    };
    keep(&mut out, 0.0, &z, record.accel_m_s2[0]);
    for k in 0..samples - 1 {
        let (a0, a1) = (record.accel_m_s2[k], record.accel_m_s2[k + 1]);
        let slope = (a1 - a0) / record.dt_s;
        for p in 0..sub {
            let ag = a0 + slope * h * p as f64;
            aug.rows_mut(0, s).copy_from(&z);
            aug[s] = ag;
            aug[s + 1] = slope;
            let next = &phi * &aug;
            let ag_next = if p + 1 == sub { a1 } else { a0 + slope * h * (p + 1) as f64 };
            let middle = &half * &aug;
            let [(i0, v0), (im, vm), (i1, v1)] =
                [powers(&z, ag), powers(&middle, ag + 0.5 * slope * h), powers(&next, ag_next)];
            out.energy_input += h / 6.0 * (i0 + 4.0 * im + i1);
            out.energy_viscous += h / 6.0 * (v0 + 4.0 * vm + v1);
            // Peaks on each piece: displacement (rate: velocity), drift, absolute acceleration.
            let (acc0, acc1) = (accel_of(&z, ag), accel_of(&next, ag_next));
            let (jerk0, jerk1) = (jerk_of(&z, ag, slope), jerk_of(&next, ag_next, slope));
            for i in 0..n {
                let d = hermite_peak(z[i], z[n + i], next[i], next[n + i], h);
                out.peak_displacement[i] = out.peak_displacement[i].max(d);
                let a = hermite_peak(acc0[i], jerk0[i], acc1[i], jerk1[i], h);
                out.peak_accel[i] = out.peak_accel[i].max(a);
            }
            let (v0, v1) = (z.rows(n, n).into_owned(), next.rows(n, n).into_owned());
            for i in 0..storeys {
                let dr = hermite_peak(drift(&z, i), drift(&v0, i), drift(&next, i), drift(&v1, i), h);
                out.peak_drift[i] = out.peak_drift[i].max(dr);
            }
            z = next;
        }
        keep(&mut out, (k + 1) as f64 * record.dt_s, &z, a1);
    }
    let (u, v) = (z.rows(0, n), z.rows(n, n));
    out.energy_stored =
        0.5 * (v.transpose() * structure.mass_matrix() * v)[0] + 0.5 * (u.transpose() * &structure.stiffness * u)[0];
    Ok(out)
}
