//! Accelerations at a state: of every mass in a configuration ([`Dynamics::accelerations`],
//! its jerks and snaps), and, for the contact decisions of large structures (above
//! [`LARGE_ABOVE`](super::system::LARGE_ABOVE) degrees of freedom), of a container's host
//! alone with its next two derivatives, from one row per container of the state matrix's
//! first three powers.
//!
//! Configuration `S` moves as `z' = A z + B u(t)`, `z = (x, v)`, `A = [0 I; -M^-1 K -M^-1 C]`,
//! `B = [0; M^-1]`, `u = w_S + f(t)` (the attached beds' weights and the drive). The host `p`'s
//! acceleration is row `n + p` of `z'`, so with `h_1 = e_{n+p}^T A`, `h_{k+1} = h_k A` and
//! `g_k = h_k B` (`g_0 = e_{n+p}^T B`, row `p` of `M^-1`):
//!
//! - acceleration `h_1 z + g_0 u`,
//! - jerk `h_2 z + g_1 u + g_0 u'`,
//! - snap `h_3 z + g_2 u + g_1 u' + g_0 u''`,
//!
//! the same quantities as [`Dynamics::accelerations_in`] and [`Dynamics::snaps_in`] at the
//! host (to rounding: other sums), at a cost of a few dot products of length `2n` instead of
//! the products with `M^-1`, `K` and `C` those make for every mass (on a reduced plate of 46
//! coordinates they took a fifth of a design's time). The rows depend on the configuration
//! only, not on the forcing frequency: they are computed with its decomposition.

use nalgebra::{DMatrix, DVector};

use super::buf::PerMass;
use super::host_rows::HostRow;
use super::system::Dynamics;

/// The parts of the accelerations at one state that do not depend on the configuration
/// ([`Dynamics::at_state`]).
#[derive(Debug, Clone)]
pub struct AtState {
    f: f64,
    fdot: f64,
    sin: f64,
    cos: f64,
    cv: PerMass,
    kx: PerMass,
    kv: PerMass,
}

/// Row `i` of `m` times `z`, accumulated column by column; `sign` -1 negates `m`.
fn row(m: &DMatrix<f64>, i: usize, z: &[f64], sign: f64) -> f64 {
    (1..m.ncols()).fold(sign * m[(i, 0)] * z[0], |acc, j| sign * m[(i, j)] * z[j] + acc)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Dynamics {
    /// Accelerations and jerks of all masses in configuration `mask` at state `(x, v)`, time
    /// `t` (the first `n` entries): `a = M^-1 (w - C v - K x + f)`, `j = M^-1 (-C a - K v + f')`,
    /// each product summed over the columns in order, without allocating.
    pub fn accelerations(&self, mask: usize, t: f64, x: &DVector<f64>, v: &DVector<f64>) -> (PerMass, PerMass) {
        self.accelerations_in(mask, &self.at_state(t, x, v))
    }

    /// What [`Dynamics::accelerations`] shares between configurations at one state: the force
    /// and its rate, `C v`, `K x` and `K v`.
    pub fn at_state(&self, t: f64, x: &DVector<f64>, v: &DVector<f64>) -> AtState {
        let n = self.system.dof();
        let (sin, cos) = (self.omega * t).sin_cos();
        let (f, fdot) = (self.system.force * sin, self.system.force * self.omega * cos);
        let (mut cv, mut kx, mut kv) = (PerMass::zeros(n), PerMass::zeros(n), PerMass::zeros(n));
        for (i, ((cv, kx), kv)) in cv.iter_mut().zip(kx.iter_mut()).zip(kv.iter_mut()).enumerate() {
            *cv = row(&self.c, i, v.as_slice(), 1.0);
            *kx = row(&self.k, i, x.as_slice(), 1.0);
            *kv = row(&self.k, i, v.as_slice(), 1.0);
        }
        AtState { f, fdot, sin, cos, cv, kx, kv }
    }

    /// [`Dynamics::accelerations`] in configuration `mask` at a state prepared by
    /// [`Dynamics::at_state`] (the same numbers: the same sums in the same order).
    pub fn accelerations_in(&self, mask: usize, st: &AtState) -> (PerMass, PerMass) {
        let n = self.system.dof();
        let cfg = self.config(mask);
        let mut rhs_buf = PerMass::zeros(n);
        let rhs = &mut rhs_buf[..];
        let a = self.accelerations_from(mask, (st.f, st.sin, st.cos), &st.cv, &st.kx, rhs);
        // `rhs` is spent: it holds the right-hand side of the jerks.
        let rhs_dot = rhs;
        for (i, (r, kv)) in rhs_dot.iter_mut().zip(&st.kv[..]).enumerate() {
            *r = row(&self.c, i, &a, -1.0) - kv;
        }
        rhs_dot[self.system.driven] += st.fdot;
        for (i, r) in rhs_dot.iter_mut().enumerate().take(self.load.len()) {
            *r += self.load_at(i, st.sin, st.cos).1;
        }
        let mut jerk = PerMass::zeros(n);
        for (i, ji) in jerk.iter_mut().enumerate() {
            *ji = row(&cfg.modes.mass_inv, i, rhs_dot, 1.0);
        }
        (a, jerk)
    }

    /// The accelerations alone of [`Dynamics::accelerations`] (the same numbers: the same sums
    /// in the same order), without the jerks and the products only they need: what the
    /// vector field at an impact reads.
    pub fn accelerations_only(&self, mask: usize, t: f64, x: &DVector<f64>, v: &DVector<f64>) -> PerMass {
        let n = self.system.dof();
        let (sin, cos) = (self.omega * t).sin_cos();
        let f = self.system.force * sin;
        let (mut cv, mut kx, mut rhs) = (PerMass::zeros(n), PerMass::zeros(n), PerMass::zeros(n));
        for (i, (cv, kx)) in cv.iter_mut().zip(kx.iter_mut()).enumerate() {
            *cv = row(&self.c, i, v.as_slice(), 1.0);
            *kx = row(&self.k, i, x.as_slice(), 1.0);
        }
        self.accelerations_from(mask, (f, sin, cos), &cv, &kx, &mut rhs)
    }

    /// `M^-1 (w - C v - K x + f)` in configuration `mask` from `C v`, `K x` and the drive
    /// `(f, sin, cos)` at the state; `rhs` (of length `n`, zeros) is left holding the
    /// right-hand side.
    #[inline(always)]
    fn accelerations_from(
        &self,
        mask: usize,
        (f, sin, cos): (f64, f64, f64),
        cv: &[f64],
        kx: &[f64],
        rhs: &mut [f64],
    ) -> PerMass {
        let cfg = self.config(mask);
        for (j, d) in self.system.dampers.iter().enumerate() {
            if mask & (1 << j) != 0 {
                rhs[d.host] -= d.mass * d.gravity();
            }
        }
        for (r, (cv, kx)) in rhs.iter_mut().zip(cv.iter().zip(kx)) {
            *r = *r - cv - kx;
        }
        rhs[self.system.driven] += f;
        for (i, r) in rhs.iter_mut().enumerate().take(self.load.len()) {
            *r += self.load_at(i, sin, cos).0;
        }
        let mut a = PerMass::zeros(rhs.len());
        for (i, ai) in a.iter_mut().enumerate() {
            *ai = row(&cfg.modes.mass_inv, i, rhs, 1.0);
        }
        a
    }

    /// The fourth derivatives of the displacements in configuration `mask`, given the state's
    /// accelerations `a` and jerks `jerk` there ([`Dynamics::accelerations_in`]):
    /// `M^-1 (-C jerk - K a + f'')`, `f'' = -omega^2 f` (gravity is constant).
    pub fn snaps_in(&self, mask: usize, st: &AtState, a: &[f64], jerk: &[f64]) -> PerMass {
        let n = self.system.dof();
        let cfg = self.config(mask);
        let mut rhs = PerMass::zeros(n);
        for (i, r) in rhs.iter_mut().enumerate() {
            *r = row(&self.c, i, jerk, -1.0) - row(&self.k, i, a, 1.0);
        }
        rhs[self.system.driven] -= self.omega * self.omega * st.f;
        for (i, r) in rhs.iter_mut().enumerate().take(self.load.len()) {
            *r -= self.omega * self.omega * self.load_at(i, st.sin, st.cos).0;
        }
        let mut snap = PerMass::zeros(n);
        for (i, s) in snap.iter_mut().enumerate() {
            *s = row(&cfg.modes.mass_inv, i, &rhs, 1.0);
        }
        snap
    }

    /// The acceleration, jerk and snap of bed `j`'s host in configuration `mask` at time `t`,
    /// displacements `x`, velocities `v` (see the module's note): from the configuration's
    /// rows above [`LARGE_ABOVE`](super::system::LARGE_ABOVE) degrees of freedom, from every mass's accelerations
    /// ([`Dynamics::accelerations_in`], [`Dynamics::snaps_in`]) up to it.
    pub fn host_derivs(&self, mask: usize, j: usize, t: f64, x: &DVector<f64>, v: &DVector<f64>) -> [f64; 3] {
        let Some(row): Option<&HostRow> = self.config(mask).modes.host_rows.get(j) else {
            let (p, at) = (self.system.dampers[j].host, self.at_state(t, x, v));
            let (a, jerk) = self.accelerations_in(mask, &at);
            let snap = self.snaps_in(mask, &at, &a, &jerk);
            return [a[p], jerk[p], snap[p]];
        };
        let n = x.len();
        let z = |h: &[f64]| dot(&h[..n], x.as_slice()) + dot(&h[n..], v.as_slice());
        let (sin, cos) = (self.omega * t).sin_cos();
        // `g u`, `g u'`, `g u''` of one row `g`.
        let sys = &self.system;
        let drive = |g: &[f64]| {
            let weights: f64 = sys
                .dampers
                .iter()
                .enumerate()
                .filter(|(k, _)| mask & (1 << k) != 0)
                .map(|(_, b)| -b.mass * b.gravity() * g[b.host])
                .sum();
            let (mut f, mut df) = (sys.force * sin * g[sys.driven], sys.force * self.omega * cos * g[sys.driven]);
            if sys.base.is_some() {
                for (i, gi) in g.iter().enumerate() {
                    let (l, dl) = self.load_at(i, sin, cos);
                    f += l * gi;
                    df += dl * gi;
                }
            }
            [weights + f, df, -self.omega * self.omega * f]
        };
        let [d0, d1, d2] = [drive(&row.g[0]), drive(&row.g[1]), drive(&row.g[2])];
        [z(&row.h[0]) + d0[0], z(&row.h[1]) + d1[0] + d0[1], z(&row.h[2]) + d2[0] + d1[1] + d0[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::system::System;

    /// The rows give every configuration's host accelerations, jerks and snaps of the full
    /// products, to rounding, with the beds' weights and the drive's phase in them.
    #[test]
    fn the_rows_give_the_full_products_derivatives() {
        let n = 12;
        let masses: Vec<f64> = (0..n).map(|i| 0.2 + 0.01 * i as f64).collect();
        let s = Structure::chain(&masses, &vec![8e4; n], Damping::ModalRatios(vec![0.02; n]));
        let dampers = [n - 3, n - 1, n - 1].iter().map(|&h| Damper::new(h, 0.02, Clearance::from_m(5e-4))).collect();
        let d = Dynamics::new(&System::plastic(s, dampers, 2, 3.0), 2.0 * std::f64::consts::PI * 30.0).unwrap();
        let x = DVector::from_fn(n, |i, _| 1e-4 * ((i as f64) * 0.7).sin());
        let v = DVector::from_fn(n, |i, _| 1e-2 * ((i as f64) * 1.3).cos());
        for mask in 0..8 {
            for t in [0.0, 0.0123] {
                let at = d.at_state(t, &x, &v);
                let (a, jerk) = d.accelerations_in(mask, &at);
                let snap = d.snaps_in(mask, &at, &a, &jerk);
                // The accelerations alone are the same numbers, to the bit.
                let only = d.accelerations_only(mask, t, &x, &v);
                assert!(only.iter().zip(a.iter()).all(|(p, q)| p.to_bits() == q.to_bits()), "mask {mask} t {t}");
                for j in 0..3 {
                    let p = d.system.dampers[j].host;
                    let got = d.host_derivs(mask, j, t, &x, &v);
                    for (k, want) in [a[p], jerk[p], snap[p]].into_iter().enumerate() {
                        let scale = [a[p].abs(), jerk[p].abs(), snap[p].abs()][k].max(1.0);
                        assert!(
                            (got[k] - want).abs() <= 1e-12 * scale,
                            "mask {mask} t {t} bed {j} order {k}: {} vs {want}",
                            got[k]
                        );
                    }
                }
            }
        }
    }
}
