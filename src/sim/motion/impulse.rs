//! Free response after an impulse (Fig. 10b, docs/model.md section 3): no force, the structure at
//! rest in static equilibrium with every bed on its bottom, an initial velocity given to one
//! mass and the beds resting on it; sampled histories, the exact event list and the energy
//! terms. No I/O.

use super::engine::{Bed, Engine, Stop};
use super::observe::{energy_of, stored_energy, Both, Energy, Sampler};
use super::state::State;
use super::system::{Dynamics, SetupError, System};

/// What is given to the struck mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kick {
    /// An initial velocity (m/s) of the mass and of the beds resting on it.
    Velocity(f64),
    /// An impulse (N s), shared by the mass and the beds resting on it: `I / (m_k + m_d)`.
    Impulse(f64),
}

/// How an impulse response is computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpulseOptions {
    /// 0-based struck mass.
    pub mass: usize,
    /// What the struck mass is given.
    pub kick: Kick,
    /// Simulated time, s.
    pub duration: f64,
    /// Sampling interval, s (samples at `k dt`, `k = 0..=duration/dt`).
    pub dt: f64,
}

/// The free response.
#[derive(Debug, Clone)]
pub struct ImpulseRun {
    /// The histories and the events.
    pub samples: Sampler,
    /// Velocity given to the struck mass, m/s.
    pub initial_velocity: f64,
    /// Energy above the rest state at the start, J (the kinetic energy given).
    pub initial_energy: f64,
    /// Energy above the rest state at each sample, J.
    pub remaining: Vec<f64>,
    /// Energy lost in impacts up to each sample, J.
    pub impact_loss_until: Vec<f64>,
    /// Totals over the run: viscous loss (integrated), impact loss, energy left at the end.
    pub viscous_loss: f64,
    /// Energy lost in impacts over the run, J.
    pub impact_loss: f64,
    /// Energy above the rest state at the end, J.
    pub final_energy: f64,
    /// Static displacement of every mass at rest with the beds on their bottoms, m.
    pub rest: Vec<f64>,
    /// Set when the run stopped early.
    pub stop: Option<Stop>,
}

impl ImpulseRun {
    /// `|E0 - remaining - viscous - impact| / E0`.
    pub fn energy_residual(&self) -> f64 {
        (self.initial_energy - self.final_energy - self.viscous_loss - self.impact_loss).abs() / self.initial_energy
    }
}

/// The free response of `sys` (its force is ignored) after a kick.
pub fn free_response(sys: &System, opts: &ImpulseOptions) -> Result<ImpulseRun, SetupError> {
    let mut free = sys.clone();
    free.force = 0.0;
    free.base = None;
    // Without forcing, omega only sets the scale of the event tolerances: the highest natural
    // frequency of the bare structure.
    let scale = crate::model::modal::symmetric_modes(&sys.structure.mass_matrix(), &sys.structure.stiffness)
        .omegas
        .last()
        .copied()
        .unwrap_or(1.0)
        .max(1.0);
    let d = Dynamics::new(&free, scale)?;
    let mut s = State::at_rest(&d);
    let rest: Vec<f64> = s.x.iter().copied().collect();
    let e_rest = stored_energy(&d, &s);
    let k = opts.mass;
    let resting: f64 = free
        .dampers
        .iter()
        .zip(&s.beds)
        .filter(|(dm, b)| dm.host == k && matches!(b, Bed::Bottom))
        .map(|(dm, _)| dm.mass)
        .sum();
    let v0 = match (opts.kick, &free.structure.coupled_mass) {
        (Kick::Velocity(v), _) => v,
        (Kick::Impulse(i), None) => i / (free.structure.masses[k] + resting),
        (Kick::Impulse(i), Some(_)) => {
            // A coupled mass matrix: the impulse moves every degree of freedom,
            // `v = M_S^-1 e_k I` with the resting beds attached (docs/model.md section 5).
            let inv = &d.config(s.mask()).modes.mass_inv;
            for r in 0..d.dof {
                if r != k {
                    s.v[r] = inv[(r, k)] * i;
                }
            }
            inv[(k, k)] * i
        }
    };
    s.v[k] = v0;
    let initial_energy = stored_energy(&d, &s) - e_rest;
    let m = (opts.duration / opts.dt + 1e-9).floor() as usize;
    let times: Vec<f64> = (0..=m).map(|i| i as f64 * opts.dt).collect();
    let mut samples = Sampler::new(times);
    let mut energy = Energy::default();
    let stop = Engine::new(&d).advance(&mut s, opts.duration, &mut Both(&mut samples, &mut energy)).err();
    let remaining: Vec<f64> = (0..samples.x.len())
        .map(|i| energy_of(&d, &samples.x[i], &samples.v[i], &samples.y[i], &samples.u[i]) - e_rest)
        .collect();
    let mut impact_loss_until = Vec::with_capacity(remaining.len());
    let mut ev = samples.events.iter().peekable();
    let mut acc = 0.0;
    for &t in samples.times.iter().take(remaining.len()) {
        while let Some(e) = ev.next_if(|e| e.t <= t) {
            acc += e.loss;
        }
        impact_loss_until.push(acc);
    }
    Ok(ImpulseRun {
        initial_velocity: v0,
        initial_energy,
        remaining,
        impact_loss_until,
        viscous_loss: energy.viscous,
        impact_loss: energy.impact,
        final_energy: stored_energy(&d, &s) - e_rest,
        rest,
        stop,
        samples,
    })
}
