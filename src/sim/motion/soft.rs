//! A second method for beds of grains (docs/model.md section 2.1, "A second method"): the same
//! structure and grains, but every contact (grain and container end, grain and grain) is a
//! linear spring-dashpot, and the motion is integrated with small explicit steps. Event-driven
//! binary collisions can mislead for grains that touch (Muller and Poschel); this model has no
//! collision rule at all, only forces, so where the two agree the rule does not matter.
//!
//! Contact with overlap `delta > 0` pushes with `k delta + c delta'` (never pulls). For a pair
//! of reduced mass `mu` the contact lasts `t_c = pi / sqrt(k / mu - (c / 2 mu)^2)` and returns
//! the relative velocity scaled by `e` ([`restitution_of`]: the contact ends when its force,
//! not its overlap, returns to zero), and the damping ratio is chosen so that `e` is the
//! restitution of the event-driven law (a contact that never pulls has `e >= e^-2`, so
//! nearly plastic beds have no soft counterpart). There is no sticking speed: slow contacts
//! simply stay pressed. Steps are `t_c / steps_per_contact` of
//! the grain-grain contact (semi-implicit Euler). The structure must have a diagonal mass
//! matrix (a chain). No I/O.

use std::f64::consts::PI;

use super::system::{Dynamics, System};

/// How the soft contacts are made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftOptions {
    /// Contact stiffness, N/m (the same for every contact).
    pub stiffness: f64,
    /// Steps per grain-grain contact duration.
    pub steps_per_contact: usize,
}

/// The restitution of a linear spring-dashpot contact of damping ratio `zeta` (< 1) that
/// never pulls: the contact ends when the force `k delta + c delta'` returns to zero, at
/// phase `phi = pi - atan2(2 beta w_d, w_0^2 - 2 beta^2)` of the damped oscillation, before
/// the overlap does (Schwager and Poschel, Phys. Rev. E 75, 051304 (2007)), so
/// `e = -exp(-beta phi / w_d) (cos phi - (beta / w_d) sin phi)` with `beta = zeta w_0`.
pub fn restitution_of(zeta: f64) -> f64 {
    let wd = (1.0 - zeta * zeta).sqrt();
    let phi = PI - (2.0 * zeta * wd).atan2(1.0 - 2.0 * zeta * zeta);
    -(-zeta * phi / wd).exp() * (phi.cos() - zeta / wd * phi.sin())
}

/// Least restitution a contact that never pulls can have with `zeta < 1`: `e^-2` at critical
/// damping.
pub const MIN_RESTITUTION: f64 = 0.1353352832366127;

/// The damping ratio whose contact returns `e` ([`restitution_of`] inverted by bisection),
/// or `None` when `e` is below [`MIN_RESTITUTION`] or not below 1.
pub fn damping_ratio(e: f64) -> Option<f64> {
    if !(MIN_RESTITUTION..1.0).contains(&e) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0 - 1e-12);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if restitution_of(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Contact duration of a linear contact of reduced mass `mu`, stiffness `k`, damping ratio
/// `zeta` (< 1), s.
pub fn contact_time(mu: f64, k: f64, zeta: f64) -> f64 {
    PI / ((k / mu) * (1.0 - zeta * zeta).max(1e-12)).sqrt()
}

/// The amplitude (half the peak-to-peak displacement) of each mass over the last `record` of
/// `periods` forcing periods from rest, with every bed (a single bed is a column of one) made
/// of soft contacts (each container with its own restitution); and the number of steps taken.
/// `None` when a bed's restitution is below [`MIN_RESTITUTION`] (a contact that never pulls
/// cannot be that inelastic). The step is `1 / steps_per_contact` of the shortest grain-grain
/// contact.
pub fn amplitude(
    sys: &System,
    omega: f64,
    opts: &SoftOptions,
    periods: usize,
    record: usize,
) -> Option<(Vec<f64>, u64)> {
    let n = sys.dof();
    let m0 = &sys.structure.masses;
    // A coupled mass matrix's inverse (lumped masses divide).
    let m0_inv = sys.structure.coupled_mass.as_ref().and_then(|m| m.clone().try_inverse());
    let k = &sys.structure.stiffness;
    let c = &sys.structure.damping;
    // Beds in columns: (first, last) bed of each container's grains.
    let groups = sys.groups();
    let nb = sys.dampers.len();
    let kc = opts.stiffness;
    let (dashpots, dt) = dashpots(sys, &groups, m0_inv.as_ref(), opts)?;
    // Start at rest in static equilibrium with every grain on its bottom (the event-driven
    // start), the grains at zero overlap.
    let rest = Dynamics::unforced(sys).map(|d| d.config((1usize << nb) - 1).modes.offset.clone());
    let mut x: Vec<f64> = rest.map(|o| o.iter().copied().collect()).unwrap_or_else(|_| vec![0.0; n]);
    let mut v = vec![0.0; n];
    let mut y: Vec<f64> = sys.dampers.iter().map(|d| x[d.host]).collect();
    let mut u = vec![0.0; nb];
    let period = 2.0 * PI / omega;
    let steps = (periods as f64 * period / dt).ceil() as u64;
    let record_from = ((periods - record.min(periods)) as f64 * period / dt) as u64;
    let mut lo = vec![f64::INFINITY; n];
    let mut hi = vec![f64::NEG_INFINITY; n];
    let mut fx = vec![0.0; n];
    let mut fy = vec![0.0; nb];
    // Moving supports: their load in the coordinates that follow them at the hosts, and the
    // displacement that turns those into displacements relative to the supports.
    let base = sys.base.as_ref().map(|b| {
        let (load, _) = b.load_phasor(k, c, &sys.structure.mass_matrix(), omega);
        (load, b.displacement(omega), b.follow.clone())
    });
    // A contact between a lower body (position a, velocity va) and an upper one: the force
    // pushing them apart (>= 0).
    let push = |overlap: f64, rate: f64, c: f64| if overlap > 0.0 { (kc * overlap + c * rate).max(0.0) } else { 0.0 };
    for step in 0..steps {
        let t = step as f64 * dt;
        fx.iter_mut().for_each(|f| *f = 0.0);
        fx[sys.driven] += sys.force * (omega * t).sin();
        if let Some((load, _, _)) = &base {
            let (s, co) = (omega * t).sin_cos();
            fx.iter_mut().zip(load).for_each(|(f, l)| *f += l.re * s + l.im * co);
        }
        for i in 0..n {
            for j in 0..n {
                fx[i] -= k[(i, j)] * x[j] + c[(i, j)] * v[j];
            }
        }
        for (j, f) in fy.iter_mut().enumerate() {
            *f = -sys.dampers[j].mass * sys.dampers[j].gravity();
        }
        for (g, &(c_wall, c_pair)) in groups.iter().zip(&dashpots) {
            let dm = sys.dampers[g.start];
            let p = dm.host;
            // Bottom and lowest grain.
            let j0 = g.start;
            let f = push(x[p] - y[j0], v[p] - u[j0], c_wall);
            fy[j0] += f;
            fx[p] -= f;
            // Neighbouring grains.
            for j in g.start + 1..g.end {
                let f = push(y[j - 1] - y[j], u[j - 1] - u[j], c_pair);
                fy[j] += f;
                fy[j - 1] -= f;
            }
            // Top and highest grain.
            if dm.clearance.is_bounded() {
                let j1 = g.end - 1;
                let f = push(y[j1] - (x[p] + dm.clearance.m()), u[j1] - v[p], c_wall);
                fy[j1] -= f;
                fx[p] += f;
            }
        }
        match &m0_inv {
            None => {
                for i in 0..n {
                    v[i] += dt * fx[i] / m0[i];
                }
            }
            Some(inv) => {
                for (i, vi) in v.iter_mut().enumerate() {
                    *vi += dt * (0..n).map(|j| inv[(i, j)] * fx[j]).sum::<f64>();
                }
            }
        }
        for i in 0..n {
            x[i] += dt * v[i];
        }
        for j in 0..nb {
            u[j] += dt * fy[j] / sys.dampers[j].mass;
            y[j] += dt * u[j];
        }
        if step >= record_from {
            // After the step: at `t + dt`.
            let support = base.as_ref().map_or(0.0, |(_, xg, _)| xg * (omega * (t + dt)).sin());
            for i in 0..n {
                let rel = match &base {
                    None => x[i],
                    Some((_, _, follow)) => x[i] - follow[i] * support,
                };
                lo[i] = lo[i].min(rel);
                hi[i] = hi[i].max(rel);
            }
        }
    }
    Some((lo.iter().zip(&hi).map(|(a, b)| 0.5 * (b - a)).collect(), steps))
}

/// Each container's dashpots (its contacts with the walls, and between its grains), from its
/// own restitution's damping ratio, and the step: `1 / steps_per_contact` of the shortest
/// grain-grain contact. `None` below [`MIN_RESTITUTION`].
fn dashpots(
    sys: &System,
    groups: &[std::ops::Range<usize>],
    m0_inv: Option<&nalgebra::DMatrix<f64>>,
    opts: &SoftOptions,
) -> Option<(Vec<(f64, f64)>, f64)> {
    let (m0, kc) = (&sys.structure.masses, opts.stiffness);
    let mut dashpots = Vec::with_capacity(groups.len());
    let mut dt = f64::INFINITY;
    for g in groups {
        let dm = sys.dampers[g.start];
        let zeta = damping_ratio(sys.impact_law(g.start).restitution())?;
        // The host's effective mass (a coupled mass matrix: `1 / (M0^-1)_pp`).
        let m0p = m0_inv.map_or(m0[dm.host], |inv| 1.0 / inv[(dm.host, dm.host)]);
        let (mu_wall, mu_pair) = (dm.mass * m0p / (dm.mass + m0p), 0.5 * dm.mass);
        dashpots.push((2.0 * zeta * (kc * mu_wall).sqrt(), 2.0 * zeta * (kc * mu_pair).sqrt()));
        dt = dt.min(contact_time(mu_pair, kc, zeta) / opts.steps_per_contact as f64);
    }
    Some((dashpots, dt))
}
