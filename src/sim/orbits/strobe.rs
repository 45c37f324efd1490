//! The stroboscopic section of the forced motion with any number of beds (docs/periodic.md):
//! the state at the times `t = (phase + 2 pi k) / omega`. A periodic orbit of `p` forcing
//! periods is a fixed point of the `p`-period map `P` from one section time to the one `p`
//! periods later.
//!
//! On the section each bed is resting on its bottom, pressed against its top, or free; which,
//! is part of the motion's pattern and fixed for a section (the section is placed at a forcing
//! phase away from every event, so that small changes of the state keep it). The coordinates
//! are the masses' displacements over a length scale `L` and velocities over `omega L`, then
//! for each free bed its height above the container bottom over `L` and its velocity relative
//! to the container over `omega L`; a resting bed has none. `P` is the simulator itself, and
//! its exact Jacobian comes with it from the linearised flow ([`super::tangent`]), so
//! Newton's method costs about one map evaluation per iteration and the Floquet multipliers
//! are the eigenvalues of that Jacobian at the orbit. No I/O.

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::periodic::{OrbitError, Return, Section};
use super::tangent::{Tangent, GRAZE};
use crate::sim::motion::engine::{Bed, Engine, Event, Observer, Quiet, State};
use crate::sim::motion::observe::{Both, EventLog, Extrema};
use crate::sim::motion::system::{Dynamics, LARGE_ABOVE};

/// Where a bed is on the section.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rest {
    /// On the bottom of its container.
    Bottom,
    /// Against the top.
    Top,
    /// In flight.
    Free,
}

impl Rest {
    /// The bed's place in a simulator state.
    pub fn of(b: &Bed) -> Rest {
        match b {
            Bed::Bottom => Rest::Bottom,
            Bed::Top => Rest::Top,
            Bed::Free { .. } => Rest::Free,
        }
    }
}

/// The forcing phase (from the start of the cycle, in `[0, 2 pi p)`) farthest from every
/// event of the cycle, the events taken as repeating with the cycle.
pub fn quiet_phase(events: &[Event], t_start: f64, omega: f64, p: usize) -> f64 {
    let span = 2.0 * PI * p as f64;
    let mut phases: Vec<f64> = events.iter().map(|e| (omega * (e.t - t_start)).clamp(0.0, span)).collect();
    if phases.is_empty() {
        return 0.5 * span;
    }
    phases.sort_by(f64::total_cmp);
    let mut best = (span - phases[phases.len() - 1] + phases[0], phases[phases.len() - 1]);
    for w in phases.windows(2) {
        if w[1] - w[0] > best.0 {
            best = (w[1] - w[0], w[0]);
        }
    }
    (best.1 + 0.5 * best.0).rem_euclid(span)
}

/// A stroboscopic section.
#[derive(Debug, Clone, PartialEq)]
pub struct Strobe {
    /// Forcing phase of the section, rad in `[0, 2 pi)`.
    pub phase: f64,
    /// Forcing periods per orbit.
    pub periods: usize,
    /// Where each bed is on the section.
    pub beds: Vec<Rest>,
    /// Length scale of the coordinates, m.
    pub length: f64,
}

impl Strobe {
    /// A section through the state `s` (its forcing phase and bed places).
    pub fn through(d: &Dynamics, s: &State, periods: usize, length: f64) -> (Strobe, DVector<f64>) {
        let strobe = Strobe {
            phase: (d.omega * s.t).rem_euclid(2.0 * PI),
            periods,
            beds: s.beds.iter().map(Rest::of).collect(),
            length,
        };
        let u = strobe.coordinates_unchecked(d, s);
        (strobe, u)
    }

    /// The same orbit on a section at the quietest phase of its events (a continuation moves
    /// the events; when one reaches the section, the section is moved).
    pub fn resection(&self, d: &Dynamics, u: &DVector<f64>, events: &[Event]) -> Option<(Strobe, DVector<f64>)> {
        let mut s = self.state(d, u);
        let t0 = s.t;
        let phase = quiet_phase(events, t0, d.omega, self.periods);
        Engine::new(d).advance(&mut s, t0 + phase / d.omega, &mut Quiet).ok()?;
        Some(Strobe::through(d, &s, self.periods, self.length))
    }

    /// Half the peak-to-peak displacement of each mass over one orbit from `u`, m, and the
    /// events over it.
    pub fn amplitudes(&self, d: &Dynamics, u: &DVector<f64>) -> Option<Vec<f64>> {
        let mut s = self.state(d, u);
        let mut ext = Extrema::new(d.system.dof(), d.system.dampers.len());
        let t_end = s.t + self.periods as f64 * 2.0 * PI / d.omega;
        Engine::new(d).advance(&mut s, t_end, &mut ext).ok()?;
        Some(ext.amplitudes())
    }

    /// The time `periods` forcing periods after `t`: where the map from a section state at
    /// `t` ends, and where a record of one orbit from it ends.
    pub fn end_time(&self, d: &Dynamics, t: f64) -> f64 {
        t + self.periods as f64 * 2.0 * PI / d.omega
    }

    /// [`Section::map`] with `extra` observing the same run (which it does not change), and
    /// the state at its end.
    pub fn map_observed(
        &self,
        d: &Dynamics,
        u: &DVector<f64>,
        extra: &mut impl Observer,
    ) -> Result<(Return, State), OrbitError> {
        let mut s = self.state(d, u);
        let t_end = self.end_time(d, s.t);
        let mut log = EventLog::default();
        if !d.system.columns.is_empty() {
            // The linearised flow has no saltation for grain-grain collisions: the Jacobian
            // comes from central differences of the map ([`Section::jacobian`]).
            Engine::new(d).advance(&mut s, t_end, &mut Both(&mut log, extra))?;
            let image = self.coordinates(d, &s)?;
            return Ok((Return { image, events: log.0, jacobian: None, d_omega: None }, s));
        }
        let mut tangent = Tangent::new(d, self.embedding(d));
        let mut both = Both(&mut tangent, &mut log);
        Engine::new(d).advance(&mut s, t_end, &mut Both(&mut both, extra))?;
        let image = self.coordinates(d, &s)?;
        let jacobian = self.restrict(d, tangent.matrix(d));
        let smooth = tangent.simultaneous == 0 && tangent.min_impact_speed > GRAZE * self.rate(d);
        Ok((Return { image, events: log.0, jacobian: Some((jacobian, smooth)), d_omega: None }, s))
    }

    /// Number of coordinates.
    pub fn dim(&self, n: usize) -> usize {
        2 * n + 2 * self.beds.iter().filter(|b| **b == Rest::Free).count()
    }

    /// The section time of the first period, s.
    pub fn time(&self, d: &Dynamics) -> f64 {
        self.phase / d.omega
    }

    fn rate(&self, d: &Dynamics) -> f64 {
        d.omega * self.length
    }

    /// The coordinates of a state (whose beds are where the section says).
    pub(crate) fn coordinates_unchecked(&self, d: &Dynamics, s: &State) -> DVector<f64> {
        let n = d.system.dof();
        let (l, w) = (self.length, self.rate(d));
        let mut u = DVector::zeros(self.dim(n));
        for i in 0..n {
            u[i] = s.x[i] / l;
            u[n + i] = s.v[i] / w;
        }
        let mut c = 2 * n;
        for (j, rest) in self.beds.iter().enumerate() {
            if *rest == Rest::Free {
                let p = d.system.dampers[j].host;
                let (y, v) = s.bed_motion(d, j);
                u[c] = (y - s.x[p]) / l;
                u[c + 1] = (v - s.v[p]) / w;
                c += 2;
            }
        }
        u
    }

    /// The coordinates of a state, or [`OrbitError::PatternChanged`] when a bed is not where
    /// the section says (an event has crossed the section).
    pub fn coordinates(&self, d: &Dynamics, s: &State) -> Result<DVector<f64>, OrbitError> {
        if s.beds.iter().map(Rest::of).ne(self.beds.iter().copied()) {
            return Err(OrbitError::PatternChanged);
        }
        Ok(self.coordinates_unchecked(d, s))
    }

    /// `d xi / d u`: the full state's dependence on the coordinates (resting beds move with
    /// their hosts).
    fn embedding(&self, d: &Dynamics) -> DMatrix<f64> {
        let n = d.system.dof();
        let (l, w) = (self.length, self.rate(d));
        let mut e = DMatrix::zeros(Tangent::full_dim(d), self.dim(n));
        for i in 0..n {
            e[(i, i)] = l;
            e[(n + i, n + i)] = w;
        }
        let mut c = 2 * n;
        for (j, rest) in self.beds.iter().enumerate() {
            let p = d.system.dampers[j].host;
            let r = 2 * n + 2 * j;
            e[(r, p)] = l;
            e[(r + 1, n + p)] = w;
            if *rest == Rest::Free {
                e[(r, c)] = l;
                e[(r + 1, c + 1)] = w;
                c += 2;
            }
        }
        e
    }

    /// `(d u / d xi) m`: the derivative `m` of the full state taken to the section's
    /// coordinates. Row by row, as the product with the sparse `d u / d xi` (displacements over
    /// the length scale, velocities over the rate, a free bed's place relative to its host's)
    /// sums it: the terms in the order of the full state's rows, zeros left out.
    fn restrict(&self, d: &Dynamics, m: &DMatrix<f64>) -> DMatrix<f64> {
        let n = d.system.dof();
        let (l, w) = (self.length, self.rate(d));
        let (inv_l, inv_w) = (1.0 / l, 1.0 / w);
        let mut out = DMatrix::zeros(self.dim(n), m.ncols());
        for col in 0..m.ncols() {
            for i in 0..n {
                out[(i, col)] = inv_l * m[(i, col)];
                out[(n + i, col)] = inv_w * m[(n + i, col)];
            }
            let mut c = 2 * n;
            for (j, rest) in self.beds.iter().enumerate() {
                if *rest == Rest::Free {
                    let p = d.system.dampers[j].host;
                    let row = 2 * n + 2 * j;
                    out[(c, col)] = -inv_l * m[(p, col)] + inv_l * m[(row, col)];
                    out[(c + 1, col)] = -inv_w * m[(n + p, col)] + inv_w * m[(row + 1, col)];
                    c += 2;
                }
            }
        }
        out
    }
}

impl Section for Strobe {
    fn shift(&self, dim: usize) -> DVector<f64> {
        DVector::zeros(dim)
    }

    /// Above [`LARGE_ABOVE`] degrees of freedom, an orbit on which every bed rides its host
    /// without an event is the forced response of one configuration: its map's Jacobian is
    /// that configuration's transition over the orbit, `V e^(Lambda T) V^-1` scaled, so its
    /// multipliers are `e^(lambda T)` for every eigenvalue `lambda` of that configuration
    /// (each representative and, for a pair, its conjugate), `T` the orbit's duration. No
    /// eigenvalue problem of the Jacobian (a third of a followed point's time on a 32-mass
    /// chain); the paper's structures keep theirs, bit for bit.
    fn closed_multipliers(&self, d: &Dynamics, ret: &Return) -> Option<Vec<Complex64>> {
        let riding = self.beds.iter().all(|r| *r != Rest::Free);
        if d.system.dof() <= LARGE_ABOVE || !ret.events.is_empty() || !riding || !d.system.columns.is_empty() {
            return None;
        }
        let mask = (0..self.beds.len()).fold(0, |m, j| m | (1 << j));
        let duration = self.periods as f64 * 2.0 * PI / d.omega;
        let mut out: Vec<Complex64> = Vec::with_capacity(2 * d.system.dof());
        for l in &d.config(mask).modes.lambda {
            out.push((l * duration).exp());
            if l.im != 0.0 {
                out.push((l.conj() * duration).exp());
            }
        }
        out.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
        Some(out)
    }

    fn state(&self, d: &Dynamics, u: &DVector<f64>) -> State {
        let n = d.system.dof();
        let (l, w) = (self.length, self.rate(d));
        let t = self.time(d);
        let x = DVector::from_fn(n, |i, _| u[i] * l);
        let v = DVector::from_fn(n, |i, _| u[n + i] * w);
        let mut c = 2 * n;
        let beds = self
            .beds
            .iter()
            .enumerate()
            .map(|(j, rest)| match rest {
                Rest::Bottom => Bed::Bottom,
                Rest::Top => Bed::Top,
                Rest::Free => {
                    let p = d.system.dampers[j].host;
                    let bed = Bed::Free { t0: t, y0: x[p] + u[c] * l, u0: v[p] + u[c + 1] * w };
                    c += 2;
                    bed
                }
            })
            .collect();
        State { t, x, v, beds }
    }

    fn map(&self, d: &Dynamics, u: &DVector<f64>) -> Result<Return, OrbitError> {
        self.map_observed(d, u, &mut Quiet).map(|(r, _)| r)
    }

    /// The image without the linearised flow (the tangent only observes).
    fn image(&self, d: &Dynamics, u: &DVector<f64>) -> Result<DVector<f64>, OrbitError> {
        let mut s = self.state(d, u);
        let t_end = self.end_time(d, s.t);
        Engine::new(d).advance(&mut s, t_end, &mut crate::sim::motion::engine::Quiet)?;
        self.coordinates(d, &s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::system::System;
    use crate::sim::orbits::periodic::multipliers;

    /// On a 12-mass chain whose three beds ride through the orbit (a weak force), the
    /// multipliers in closed form are the eigenvalues of the map's Jacobian.
    #[test]
    fn a_riding_orbits_multipliers_are_its_configurations_exponentials() {
        let n = 12;
        let s = Structure::chain(&vec![0.2; n], &vec![8e4; n], Damping::ModalRatios(vec![0.02; n]));
        let dampers = (n - 3..n).map(|h| Damper::new(h, 0.02, Clearance::from_m(5e-3))).collect();
        let d = Dynamics::new(&System::plastic(s, dampers, 0, 0.05), 2.0 * PI * 20.0).unwrap();
        let strobe = Strobe { phase: 0.3, periods: 1, beds: vec![Rest::Bottom; 3], length: 1e-4 };
        let t = strobe.time(&d);
        let (x, v) = d.particular(7, t);
        let st = State { t, x, v, beds: vec![Bed::on_end(false); 3] };
        let u = strobe.coordinates(&d, &st).unwrap();
        let ret = strobe.map(&d, &u).unwrap();
        assert!(ret.events.is_empty(), "the beds ride");
        let (j, _) = ret.jacobian.clone().unwrap();
        let schur = multipliers(&j).unwrap();
        let closed = strobe.closed_multipliers(&d, &ret).unwrap();
        assert_eq!(closed.len(), schur.len());
        for z in &closed {
            let nearest = schur.iter().map(|w| (w - z).norm()).fold(f64::INFINITY, f64::min);
            assert!(nearest <= 1e-12, "{z}: nearest {nearest:e}");
        }
        for (a, b) in closed.iter().zip(&schur) {
            assert!((a.norm() - b.norm()).abs() <= 1e-12);
        }
    }
}
