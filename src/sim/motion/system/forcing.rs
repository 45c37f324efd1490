//! The forcing of a configuration's closed form at a time: its particular solution and its
//! derivative in the frequency, the force, the load on each mass, the power put in and the
//! supports' motion.

use nalgebra::DVector;

use super::Dynamics;
use crate::sim::motion::forced::Forced;

impl Dynamics {
    /// The forced (particular) displacement and velocity of `mask` at time `t`.
    pub fn particular(&self, mask: usize, t: f64) -> (DVector<f64>, DVector<f64>) {
        let slot = self.slot(mask);
        let (cfg, f) = (&self.configs[slot], self.forced(slot));
        let (s, c) = (self.omega * t).sin_cos();
        let n = self.dof;
        let x = DVector::from_fn(n, |i, _| f[i].p * c + f[i].q * s + cfg.modes.offset[i]);
        let v = DVector::from_fn(n, |i, _| (f[i].q * c - f[i].p * s) * self.omega);
        (x, v)
    }

    /// The derivatives of [`Dynamics::particular`] in the forcing frequency at fixed `t`.
    pub fn particular_d_omega(&self, mask: usize, t: f64) -> (DVector<f64>, DVector<f64>) {
        let f = self.forced(self.slot(mask));
        let w = self.omega;
        let (s, c) = (w * t).sin_cos();
        // x_p = P cos(w t) + Q sin(w t) + s, v_p = w (Q cos(w t) - P sin(w t)).
        let n = self.dof;
        let x = DVector::from_fn(n, |i, _| f[i].dp * c + f[i].dq * s + (f[i].q * c - f[i].p * s) * t);
        let v = DVector::from_fn(n, |i, _| {
            let Forced { p, q, dp, dq, .. } = f[i];
            (q * c - p * s) + (dq * c - dp * s) * w - (p * c + q * s) * (w * t)
        });
        (x, v)
    }

    /// The force on the driven mass at `t` and its time derivative (0 under moving supports:
    /// [`Dynamics::load_at`]).
    pub fn force(&self, t: f64) -> (f64, f64) {
        let (s, c) = (self.omega * t).sin_cos();
        (self.system.force * s, self.system.force * self.omega * c)
    }

    /// The moving supports' load on coordinate `i` and its time derivative, given `sin(omega
    /// t)` and `cos(omega t)`; 0 under a force.
    #[inline]
    pub fn load_at(&self, i: usize, sin: f64, cos: f64) -> (f64, f64) {
        match self.load.get(i) {
            Some(l) => (l.re * sin + l.im * cos, self.omega * (l.re * cos - l.im * sin)),
            None => (0.0, 0.0),
        }
    }

    /// The power the drive puts into the structure at `t` with velocities `v`: the force times
    /// the driven mass's velocity, or the supports' load on every coordinate.
    pub fn power(&self, t: f64, v: &DVector<f64>) -> f64 {
        if self.load.is_empty() {
            return self.force(t).0 * v[self.system.driven];
        }
        let (s, c) = (self.omega * t).sin_cos();
        (0..v.len()).map(|i| self.load_at(i, s, c).0 * v[i]).sum()
    }

    /// Derivative `order` of the supports' displacement along coordinate `i`, `r_i x_g(t)`,
    /// at a forcing phase (`sin(omega t)`, `cos(omega t)`): what turns the simulator's
    /// coordinates into displacements relative to the supports (0 under a force).
    #[inline]
    pub fn support_motion(&self, i: usize, order: usize, sin: f64, cos: f64) -> f64 {
        let Some(b) = &self.system.base else {
            return 0.0;
        };
        let phase = match order % 4 {
            0 => sin,
            1 => cos,
            2 => -sin,
            _ => -cos,
        };
        b.follow[i] * self.support * self.omega_pow[order] * phase
    }
}
