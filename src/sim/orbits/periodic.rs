//! Periodic orbits as fixed points of the event-driven flow (docs/model.md section 4), for a
//! structure with one damper: the equivalent SDOF model of a mode, or the full structure.
//!
//! The Poincare section is the impact of the bed on the container bottom. There the bed moves
//! with its host (plastic impacts) or leaves it with a known relative velocity (restitution),
//! so the state on the section is the forcing phase `phi = omega t`, the displacements and
//! velocities of every mass, and (with restitution) the bed's relative velocity. One return
//! map `P` runs the same simulator from that state to the `k`-th bottom impact after it; a
//! periodic orbit of `p` forcing periods solves `P(u) - u = (2 pi p, 0, ...)`.
//!
//! Newton's method solves it with the Jacobian of `P` by central differences: `P` is computed
//! in closed form with event times refined far below 1e-13 s, so with a step of 1e-5 in
//! scaled units (phase in rad, displacements over a length scale `L`, velocities over
//! `omega_ref L`) the truncation error (~1e-10) and the rounding error (~1e-14 / 1e-5) of the
//! differences stay near 1e-9: Newton then converges quadratically to ~1e-13. The same
//! Jacobian at the solution is the linearised return map: its eigenvalues are the orbit's
//! Floquet multipliers (the plastic collapse of the bed's relative motion contributes the
//! zero ones), so it decides stability. No I/O.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::tangent::Tangent;
use crate::sim::motion::eigen::{self, EigenError};
use crate::sim::motion::engine::{Bed, Engine, Event, EventKind, Observer, State, Stop};
use crate::sim::motion::observe::Both;
use crate::sim::motion::state::Mark;
use crate::sim::motion::system::{Dynamics, SetupError};

/// Central-difference step in scaled units (see the module documentation).
pub const FD_STEP: f64 = 1e-5;

/// Why no orbit was found.
#[derive(Debug, Clone, PartialEq)]
pub enum OrbitError {
    /// The dynamics could not be set up at this parameter.
    Setup(SetupError),
    /// The system has no damper or more than one.
    Dampers(usize),
    /// The bed did not come back to the bottom `k` times within `p + 1` periods: there is no
    /// orbit of this type here (e.g. the bed no longer lifts off).
    NoReturn,
    /// The simulation stopped early (chatter).
    Stopped(Stop),
    /// The Newton matrix is singular.
    Singular,
    /// Newton's method did not converge; the residuals of its iterations.
    NoConvergence(Vec<f64>),
    /// Newton's method was cycling: its next iterate came back to within [`CYCLE_NEAR`] of
    /// an earlier one from an iterate whose residual was at least half that of the iterate
    /// before it (no progress), so it would go round again ([`solve_with`]).
    Cycling {
        /// The residuals of its iterations.
        residuals: Vec<f64>,
        /// The earlier iterate it came back to (0-based).
        to: usize,
    },
    /// A bed is not where the stroboscopic section says it is: an event crossed the section.
    PatternChanged,
    /// The orbit was found but its multipliers could not be computed within their bound.
    Multipliers(EigenError),
}

impl std::fmt::Display for OrbitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OrbitError::Setup(e) => write!(f, "{e}"),
            OrbitError::Dampers(n) => write!(f, "periodic orbits need exactly one damper ({n} given)"),
            OrbitError::NoReturn => write!(f, "no return to the bottom: no orbit of this type"),
            OrbitError::Stopped(s) => write!(f, "simulation stopped: {s:?}"),
            OrbitError::Singular => write!(f, "singular Newton matrix"),
            OrbitError::NoConvergence(r) => {
                let r: Vec<String> = r.iter().map(|x| format!("{x:.1e}")).collect();
                write!(f, "Newton did not converge (residuals {})", r.join(", "))
            }
            OrbitError::Cycling { residuals, to } => {
                let r: Vec<String> = residuals.iter().map(|x| format!("{x:.1e}")).collect();
                write!(f, "Newton was cycling (back to iterate {} after residuals {})", to + 1, r.join(", "))
            }
            OrbitError::PatternChanged => write!(f, "an event crossed the section (the motion's pattern changed)"),
            OrbitError::Multipliers(e) => write!(f, "no Floquet multipliers: {e}"),
        }
    }
}

impl std::error::Error for OrbitError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            OrbitError::Setup(e) => Some(e),
            OrbitError::Stopped(s) => Some(s),
            OrbitError::Multipliers(e) => Some(e),
            _ => None,
        }
    }
}

impl From<SetupError> for OrbitError {
    fn from(e: SetupError) -> OrbitError {
        OrbitError::Setup(e)
    }
}

impl From<Stop> for OrbitError {
    fn from(s: Stop) -> OrbitError {
        OrbitError::Stopped(s)
    }
}

impl From<EigenError> for OrbitError {
    fn from(e: EigenError) -> OrbitError {
        OrbitError::Multipliers(e)
    }
}

/// The kind of orbit sought and the scales of the section's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Problem {
    /// Bottom impacts per orbit (the section is crossed `returns` times per orbit).
    pub returns: usize,
    /// Forcing periods per orbit.
    pub periods: usize,
    /// Length scale of the displacements, m.
    pub length: f64,
    /// Rate scale of the velocities, rad/s.
    pub rate: f64,
    /// Whether the bed's relative velocity after impact is a coordinate (restitution).
    pub bounce: bool,
}

/// The image of one section state under the return map.
#[derive(Debug, Clone)]
pub struct Return {
    /// `P(u)` in scaled coordinates (the phase unwrapped: `omega t` at the return).
    pub image: DVector<f64>,
    /// The events from the start to the return (the return impact last).
    pub events: Vec<Event>,
    /// The Jacobian of `P` at `u` when the map computes it exactly, and whether it is smooth
    /// there (no graze, no simultaneous impacts).
    pub jacobian: Option<(DMatrix<f64>, bool)>,
    /// `dP/domega` at fixed `u` (omega the forcing frequency, rad/s), when the map computes it.
    pub d_omega: Option<DVector<f64>>,
}

/// A Poincare section and its return map `P`: what Newton's method and continuation need.
/// A periodic orbit is a fixed point `P(u) - u = shift`.
pub trait Section {
    /// The offset of a fixed point's image (the impact section's phase advances by `2 pi p`).
    fn shift(&self, dim: usize) -> DVector<f64>;
    /// The simulator state of a section point.
    fn state(&self, d: &Dynamics, u: &DVector<f64>) -> State;
    /// The return map.
    fn map(&self, d: &Dynamics, u: &DVector<f64>) -> Result<Return, OrbitError>;

    /// The image `P(u)` alone (no Jacobian, no events): the same numbers as `map(d, u).image`,
    /// for finite differences in the parameter.
    fn image(&self, d: &Dynamics, u: &DVector<f64>) -> Result<DVector<f64>, OrbitError> {
        self.map(d, u).map(|r| r.image)
    }

    /// `G(u)` alone, from [`Section::image`].
    fn residual_only(&self, d: &Dynamics, u: &DVector<f64>) -> Result<DVector<f64>, OrbitError> {
        Ok(&self.image(d, u)? - u - self.shift(u.len()))
    }

    /// `G(u) = P(u) - u - shift`.
    fn residual(&self, d: &Dynamics, u: &DVector<f64>) -> Result<(DVector<f64>, Return), OrbitError> {
        let r = self.map(d, u)?;
        let g = &r.image - u - self.shift(u.len());
        Ok((g, r))
    }

    /// The multipliers of a fixed point whose return `ret` ran without an event, when the
    /// section knows them in closed form; `None`: from the Jacobian's eigenvalues.
    fn closed_multipliers(&self, _d: &Dynamics, _ret: &Return) -> Option<Vec<Complex64>> {
        None
    }

    /// The Jacobian of `P` at `u` (`base` is `P(u)`): exact when the map provides it,
    /// otherwise by central differences.
    fn jacobian(&self, d: &Dynamics, u: &DVector<f64>, base: &Return) -> Result<(DMatrix<f64>, bool), OrbitError> {
        match &base.jacobian {
            Some(j) => Ok(j.clone()),
            None => fd_jacobian(self, d, u, base),
        }
    }
}

/// The Jacobian of `P` by central differences, and whether every perturbed run kept the event
/// sequence of `base` (otherwise the orbit is at a grazing or switching point and the
/// differences straddle a kink).
pub fn fd_jacobian<S: Section + ?Sized>(
    section: &S,
    d: &Dynamics,
    u: &DVector<f64>,
    base: &Return,
) -> Result<(DMatrix<f64>, bool), OrbitError> {
    let m = u.len();
    let sig = signature(&base.events);
    let mut j = DMatrix::zeros(m, m);
    let mut smooth = true;
    for c in 0..m {
        let mut up = u.clone();
        up[c] += FD_STEP;
        let mut dn = u.clone();
        dn[c] -= FD_STEP;
        let (a, b) = (section.map(d, &up)?, section.map(d, &dn)?);
        smooth &= signature(&a.events) == sig && signature(&b.events) == sig;
        j.set_column(c, &((&a.image - &b.image) / (2.0 * FD_STEP)));
    }
    Ok((j, smooth))
}

/// Records events up to the `k`-th bottom impact, with the state after it.
struct Returns {
    wanted: usize,
    seen: usize,
    events: Vec<Event>,
    at: Option<State>,
}

impl Observer for Returns {
    fn event(&mut self, ev: &Event, after: &State) {
        if self.at.is_some() {
            return;
        }
        self.events.push(*ev);
        if matches!(ev.kind, EventKind::Impact { top: false, .. }) && ev.bed == 0 {
            self.seen += 1;
            if self.seen == self.wanted {
                self.at = Some(after.clone());
            }
        }
    }
    fn done(&self) -> bool {
        self.at.is_some()
    }
}

/// The kinds of the events in order: what makes two runs "the same motion".
pub fn signature(events: &[Event]) -> Vec<(usize, Mark)> {
    events.iter().map(|e| (e.bed, e.kind.mark())).collect()
}

impl Problem {
    /// Number of section coordinates.
    pub fn dim(&self, n: usize) -> usize {
        2 * n + 1 + self.bounce as usize
    }

    /// The section coordinates of a state just after a bottom impact.
    pub fn coordinates(&self, d: &Dynamics, s: &State) -> DVector<f64> {
        let n = d.system.dof();
        let mut u = DVector::zeros(self.dim(n));
        u[0] = d.omega * s.t;
        for i in 0..n {
            u[1 + i] = s.x[i] / self.length;
            u[1 + n + i] = s.v[i] / (self.length * self.rate);
        }
        if self.bounce {
            let host = d.system.dampers[0].host;
            let (_, ub) = s.bed_motion(d, 0);
            u[2 * n + 1] = (ub - s.v[host]) / (self.length * self.rate);
        }
        u
    }
}

impl Section for Problem {
    fn shift(&self, dim: usize) -> DVector<f64> {
        let mut s = DVector::zeros(dim);
        s[0] = 2.0 * std::f64::consts::PI * self.periods as f64;
        s
    }

    /// The simulator state of a section point.
    fn state(&self, d: &Dynamics, u: &DVector<f64>) -> State {
        let n = d.system.dof();
        let t = u[0] / d.omega;
        let x = DVector::from_fn(n, |i, _| u[1 + i] * self.length);
        let v = DVector::from_fn(n, |i, _| u[1 + n + i] * self.length * self.rate);
        let host = d.system.dampers[0].host;
        let bed = if self.bounce && u[2 * n + 1] > 0.0 {
            Bed::Free { t0: t, y0: x[host], u0: v[host] + u[2 * n + 1] * self.length * self.rate }
        } else {
            Bed::Bottom
        };
        State { t, x, v, beds: vec![bed] }
    }

    /// The return map.
    fn map(&self, d: &Dynamics, u: &DVector<f64>) -> Result<Return, OrbitError> {
        let start = self.state(d, u);
        let m = u.len();
        // The coordinates' columns and, last, the forcing frequency's: the start time
        // `u_0 / omega` moves with it by `-t_0 / omega`: minus `t_0` times the phase column.
        let e = self.embedding(d, &start);
        let mut m0 = e.clone().insert_column(m, 0.0);
        m0.set_column(m, &(e.column(0) * -start.t));
        let mut tangent = Tangent::new(d, m0).until_impact(0, self.returns).with_omega_column(m);
        let (at, events) = self.run_to_return(d, start, &mut tangent)?;
        // Every row formed (a large structure's run carries the masses' rows in modal
        // coordinates; the freeze at the event formed them already).
        tangent.matrix(d);
        let (jacobian, d_omega) = match tangent.dt.as_ref() {
            Some(dt) => {
                let full = self.restriction(d) * &tangent.m;
                let mut j = full.columns(0, m).into_owned();
                j.set_row(0, &(dt.columns(0, m) * d.omega));
                let mut dw = full.column(m).into_owned();
                // The image's phase is omega t_return.
                dw[0] = dt[m] * d.omega + at.t;
                let smooth = tangent.simultaneous == 0
                    && tangent.min_impact_speed > super::tangent::GRAZE * self.length * self.rate;
                (Some((j, smooth)), Some(dw))
            }
            None => (None, None),
        };
        Ok(Return { image: self.coordinates(d, &at), events, jacobian, d_omega })
    }

    /// The image without the linearised flow (the tangent only observes: the motion and the
    /// return are the same).
    fn image(&self, d: &Dynamics, u: &DVector<f64>) -> Result<DVector<f64>, OrbitError> {
        let (at, _) = self.run_to_return(d, self.state(d, u), &mut crate::sim::motion::engine::Quiet)?;
        Ok(self.coordinates(d, &at))
    }
}

impl Problem {
    /// Runs from `start` to the `returns`-th impact, `extra` observing beside the return
    /// recorder: the state at the return and the events up to it.
    fn run_to_return<O: Observer>(
        &self,
        d: &Dynamics,
        start: State,
        extra: &mut O,
    ) -> Result<(State, Vec<Event>), OrbitError> {
        if d.system.dampers.len() != 1 {
            return Err(OrbitError::Dampers(d.system.dampers.len()));
        }
        let mut s = start;
        let period = 2.0 * std::f64::consts::PI / d.omega;
        let limit = s.t + (self.periods as f64 + 1.0) * period;
        let mut rec = Returns { wanted: self.returns, seen: 0, events: Vec::new(), at: None };
        // Stops at the return impact.
        Engine::new(d).advance(&mut s, limit, &mut Both(&mut rec, extra))?;
        let at = rec.at.ok_or(OrbitError::NoReturn)?;
        Ok((at, rec.events))
    }

    /// `d xi / d u` at the start state `s`: the phase column moves the start along the flow;
    /// the bed rests on its host unless it bounces.
    fn embedding(&self, d: &Dynamics, s: &State) -> DMatrix<f64> {
        let n = d.system.dof();
        let (l, w) = (self.length, self.length * self.rate);
        let host = d.system.dampers[0].host;
        let mut e = DMatrix::zeros(Tangent::full_dim(d), self.dim(n));
        Tangent::phase_column(d, s, &mut e, 0);
        for i in 0..n {
            e[(i, 1 + i)] = l;
            e[(n + i, 1 + n + i)] = w;
        }
        e[(2 * n, 1 + host)] = l;
        e[(2 * n + 1, 1 + n + host)] = w;
        if self.bounce {
            e[(2 * n + 1, 2 * n + 1)] = w;
        }
        e
    }

    /// `d u / d xi` just after the return impact (the phase row comes from the event time).
    fn restriction(&self, d: &Dynamics) -> DMatrix<f64> {
        let n = d.system.dof();
        let (l, w) = (self.length, self.length * self.rate);
        let host = d.system.dampers[0].host;
        let mut r = DMatrix::zeros(self.dim(n), Tangent::full_dim(d));
        for i in 0..n {
            r[(1 + i, i)] = 1.0 / l;
            r[(1 + n + i, n + i)] = 1.0 / w;
        }
        if self.bounce {
            r[(2 * n + 1, 2 * n + 1)] = 1.0 / w;
            r[(2 * n + 1, n + host)] = -1.0 / w;
        }
        r
    }
}

/// A periodic orbit.
#[derive(Debug, Clone)]
pub struct Orbit {
    /// Section coordinates of the fixed point.
    pub u: DVector<f64>,
    /// The state just after the section impact.
    pub state: State,
    /// Events over one orbit from the section (the closing bottom impact last).
    pub events: Vec<Event>,
    /// Max-norm of the residual at each Newton iteration (the last one converged).
    pub residuals: Vec<f64>,
    /// The linearised return map (Jacobian of `P`) at the fixed point.
    pub jacobian: DMatrix<f64>,
    /// Its eigenvalues: the Floquet multipliers.
    pub multipliers: Vec<Complex64>,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
    /// The perturbed runs of the Jacobian kept the event sequence.
    pub smooth: bool,
    /// `dP/domega` at the fixed point, when the map computes it (see [`Return::d_omega`]).
    pub d_omega: Option<DVector<f64>>,
}

impl Orbit {
    /// The largest multiplier modulus.
    pub fn spectral_radius(&self) -> f64 {
        self.multipliers.iter().map(|z| z.norm()).fold(0.0, f64::max)
    }
}

/// Newton's method settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Converged when the max-norm of the residual is below this (scaled units).
    pub tol: f64,
    /// Most Newton iterations.
    pub max_iter: usize,
    /// Largest Newton step (max-norm, scaled units); longer steps are shortened.
    pub max_step: f64,
    /// The expected ratio `r_next / r^2` of successive residuals (Newton's quadratic
    /// convergence) from which an evaluation is predicted to be the last: `quadratic * r^2`
    /// below the tolerance ([`solve_with`]'s `likely_last`). It decides only which
    /// evaluations a caller records, never the orbit found.
    pub quadratic: f64,
    /// The guess is expected to be the orbit itself (to rounding): its first evaluation is
    /// then the one a caller records. Like `quadratic`, it never changes the orbit found.
    pub guess_exact: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions { tol: 1e-11, max_iter: 12, max_step: 0.5, quadratic: 1.0, guess_exact: false }
    }
}

/// How near (max-norm, scaled units) Newton's next iterate may come to an earlier one before
/// the iteration counts as cycling ([`OrbitError::Cycling`]; [`solve_with`]). Where the map's
/// events change under Newton's steps, its iterates can go round a cycle: on the size family's
/// 32-mass chain at 47.9 Hz (a period-2 motion, solved on the period-1 map) the residuals ran
/// 4.0e-2, 1.6e-2, 0.43, 0.13, 3.8e-2, 1.6e-2, 0.43, ..., the fifth iterate within 6.7e-4 of
/// the second, and never converged.
pub const CYCLE_NEAR: f64 = 1e-3;

/// `Some(j)` when `next` comes back to within [`CYCLE_NEAR`] of an earlier iterate `j`
/// (`iterates[j]`, the current one not among them) while the current residual is at least
/// half that of the iterate before `j`: the step repeats one already taken, so Newton would
/// go round again. A converging iteration never qualifies (near the solution its residuals
/// fall by more than half at every step), nor one whose residual is within a thousand times
/// the tolerance `tol` (rounding may still carry it below).
fn cycle_to(iterates: &[DVector<f64>], residuals: &[f64], next: &DVector<f64>, tol: f64) -> Option<usize> {
    let last = *residuals.last()?;
    if last <= 1e3 * tol {
        return None;
    }
    let near = |a: &DVector<f64>| a.iter().zip(next.iter()).all(|(a, b)| (b - a).abs() <= CYCLE_NEAR);
    (1..iterates.len()).find(|&j| last >= 0.5 * residuals[j - 1] && near(&iterates[j]))
}

/// Residuals below this are at the rounding level of the map (scaled units): a ratio that
/// ends on one bounds the convergence constant from above instead of measuring it.
pub const RESIDUAL_FLOOR: f64 = 1e-14;

/// The ratio `r_{k+1} / r_k^2` of Newton's last two residuals above the rounding level
/// ([`RESIDUAL_FLOOR`]), as measured on one solution: how fast Newton converges near this
/// orbit. Where every step lands at the rounding level (a map that is affine near the orbit,
/// such as one whose beds never leave their container floors), the smallest such ratio, an
/// upper bound; 1 when no step was taken.
pub fn quadratic_constant(residuals: &[f64]) -> f64 {
    let ratio = |w: &[f64]| w[1] / (w[0] * w[0]);
    let measured = residuals.windows(2).rev().find(|w| w[1] > RESIDUAL_FLOOR).map(ratio);
    let bound = residuals.windows(2).map(ratio).fold(f64::INFINITY, f64::min);
    measured.unwrap_or(if bound.is_finite() { bound } else { 1.0 })
}

/// The orbit's multipliers from a Jacobian, largest modulus first (bounded: see
/// [`eigen::eigenvalues`]).
pub fn multipliers(j: &DMatrix<f64>) -> Result<Vec<Complex64>, OrbitError> {
    let mut l = eigen::eigenvalues(j)?;
    l.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    Ok(l)
}

/// Finds the fixed point of `problem` near `guess` at the dynamics `d`.
pub fn solve<S: Section + ?Sized>(
    problem: &S,
    d: &Dynamics,
    guess: &DVector<f64>,
    opts: &NewtonOptions,
) -> Result<Orbit, OrbitError> {
    solve_with(problem, d, guess, opts, |u, _| Ok((problem.map(d, u)?, ()))).map(|(o, ())| o)
}

/// [`solve`] with each evaluation of the map run by `eval(u, likely_last)`, which returns the
/// map at `u` and whatever it recorded beside it; that of the final evaluation (at the orbit)
/// comes back with the orbit. `likely_last` is set when the previous residual `r` was so
/// small that Newton's quadratic convergence should end at this evaluation
/// (`opts.quadratic * r^2` below the tolerance), or, for the first evaluation, when the guess
/// is taken as exact (`opts.guess_exact`), so that a caller can record only then.
pub fn solve_with<S: Section + ?Sized, X>(
    problem: &S,
    d: &Dynamics,
    guess: &DVector<f64>,
    opts: &NewtonOptions,
    mut eval: impl FnMut(&DVector<f64>, bool) -> Result<(Return, X), OrbitError>,
) -> Result<(Orbit, X), OrbitError> {
    let mut u = guess.clone();
    let mut residuals: Vec<f64> = Vec::new();
    let mut iterates: Vec<DVector<f64>> = Vec::new();
    for _ in 0..=opts.max_iter {
        let likely_last = match residuals.last() {
            Some(r) => opts.quadratic * r * r < opts.tol,
            None => opts.guess_exact,
        };
        let (ret, x) = eval(&u, likely_last)?;
        let g = &ret.image - &u - problem.shift(u.len());
        let norm = g.amax();
        residuals.push(norm);
        let (j, smooth) = problem.jacobian(d, &u, &ret)?;
        if norm < opts.tol {
            return finish(problem, d, u, ret, residuals, j, smooth).map(|o| (o, x));
        }
        let a = &j - DMatrix::identity(u.len(), u.len());
        let mut du = a.lu().solve(&(-g)).ok_or(OrbitError::Singular)?;
        let step = du.amax();
        if step > opts.max_step {
            du *= opts.max_step / step;
        }
        let next = &u + du;
        if let Some(to) = cycle_to(&iterates, &residuals, &next, opts.tol) {
            return Err(OrbitError::Cycling { residuals, to });
        }
        iterates.push(std::mem::replace(&mut u, next));
    }
    Err(OrbitError::NoConvergence(residuals))
}

/// Assembles an orbit at a converged point.
pub fn finish<S: Section + ?Sized>(
    problem: &S,
    d: &Dynamics,
    u: DVector<f64>,
    ret: Return,
    residuals: Vec<f64>,
    jacobian: DMatrix<f64>,
    smooth: bool,
) -> Result<Orbit, OrbitError> {
    let multipliers = match problem.closed_multipliers(d, &ret) {
        Some(m) => m,
        None => multipliers(&jacobian)?,
    };
    let stable = multipliers.iter().all(|z| z.norm() < 1.0);
    Ok(Orbit {
        state: problem.state(d, &u),
        u,
        events: ret.events,
        residuals,
        jacobian,
        multipliers,
        stable,
        smooth,
        d_omega: ret.d_omega,
    })
}

/// A section point from a state by running to the next bottom impact, and the number of
/// bottom impacts in the `periods` forcing periods after it (a seed for [`solve`]).
pub fn seed(
    d: &Dynamics,
    start: &State,
    periods: usize,
    length: f64,
    rate: f64,
    bounce: bool,
) -> Option<(Problem, DVector<f64>)> {
    let probe = Problem { returns: 1, periods, length, rate, bounce };
    let engine = Engine::new(d);
    let period = 2.0 * std::f64::consts::PI / d.omega;
    let mut s = start.clone();
    let mut first = Returns { wanted: 1, seen: 0, events: Vec::new(), at: None };
    let limit = s.t + 2.0 * period;
    engine.advance(&mut s, limit, &mut first).ok()?;
    let at = first.at?;
    let mut u = probe.coordinates(d, &at);
    // The forcing is periodic: keep the phase in [0, 2 pi).
    u[0] = u[0].rem_euclid(2.0 * std::f64::consts::PI);
    // Count the bottom impacts over the orbit's periods, short of the closing one (a state
    // settled to a tolerance closes its orbit a little early or late).
    let mut s = at.clone();
    let mut count = Returns { wanted: usize::MAX, seen: 0, events: Vec::new(), at: None };
    engine.advance(&mut s, at.t + periods as f64 * period * (1.0 - 1e-3), &mut count).ok()?;
    Some((Problem { returns: count.seen + 1, ..probe }, u))
}

/// What is read off an orbit (the right-hand axis of the paper's Fig. 9 and the response).
#[derive(Debug, Clone, PartialEq)]
pub struct OrbitSummary {
    /// Half the peak-to-peak displacement of each mass over the orbit, m.
    pub amplitude: Vec<f64>,
    /// Phase lag of the force behind the bottom impact, rad in [0, 2 pi): the force is
    /// `F sin(tau - phi)` with `tau = omega (t - t_impact)`.
    pub phi: f64,
    /// Forcing phase from the bottom impact to the lift-off from the bottom (0: the bed leaves
    /// at once), rad.
    pub tau0: Option<f64>,
    /// ... to the impact on the top, rad.
    pub tau1: Option<f64>,
    /// ... to the release from the top (Type I), rad.
    pub tau2: Option<f64>,
    /// The motion type read from the events.
    pub kind: String,
}

/// The motion type from one orbit's events of the bed (paper section 2.2): I rests on the
/// top; II hits the top and falls at once; III never reaches the top; more impacts per
/// orbit are named.
pub fn motion_type(events: &[Event], finite: bool, periods: usize) -> String {
    let (mut bottom, mut top_stick, mut top_bounce) = (0, 0, 0);
    for e in events {
        match e.kind {
            EventKind::Impact { top: false, .. } => bottom += 1,
            EventKind::Impact { top: true, attached: true, .. } => top_stick += 1,
            EventKind::Impact { top: true, attached: false, .. } => top_bounce += 1,
            EventKind::LiftOff { .. } | EventKind::Collision { .. } => {}
        }
    }
    let base = if top_stick > 0 {
        "I"
    } else if top_bounce > 0 {
        "II"
    } else if finite {
        "III"
    } else {
        "III (no top)"
    };
    let mut s = base.to_string();
    if bottom > periods || top_stick + top_bounce > periods {
        s += &format!(", {bottom} bottom and {} top impacts", top_stick + top_bounce);
    }
    if periods > 1 {
        s += &format!(", period {periods}");
    }
    s
}

/// Amplitudes, phases and type of an orbit.
pub fn summarize(d: &Dynamics, problem: &Problem, orbit: &Orbit) -> OrbitSummary {
    let n = d.system.dof();
    let mut ext = crate::sim::motion::observe::Extrema::new(n, 1);
    let mut s = orbit.state.clone();
    let t0 = s.t;
    let period = 2.0 * std::f64::consts::PI / d.omega * problem.periods as f64;
    let _ = Engine::new(d).advance(&mut s, t0 + period, &mut ext);
    let phase = |e: &Event| d.omega * (e.t - t0);
    let first = |pred: &dyn Fn(&EventKind) -> bool| orbit.events.iter().find(|e| pred(&e.kind)).map(phase);
    OrbitSummary {
        amplitude: ext.amplitudes(),
        phi: (-orbit.u[0]).rem_euclid(2.0 * std::f64::consts::PI),
        tau0: first(&|k| matches!(k, EventKind::LiftOff { top: false })),
        tau1: first(&|k| matches!(k, EventKind::Impact { top: true, .. })),
        tau2: first(&|k| matches!(k, EventKind::LiftOff { top: true })),
        kind: motion_type(&orbit.events, d.system.dampers[0].clearance.is_bounded(), problem.periods),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_errors_compose_with_their_causes() {
        use std::error::Error;
        let setup: OrbitError = SetupError::Singular { mask: 0b101 }.into();
        let cause = setup.source().map(|c| c.to_string());
        assert_eq!(
            cause.as_deref(),
            Some("configuration 0b101: dynamic stiffness is singular at the forcing frequency")
        );
        let stopped: OrbitError = Stop::Chatter { t: 1.5, events: 2001 }.into();
        assert!(stopped.source().is_some_and(|c| c.to_string().starts_with("chatter: 2001 events")));
        let eigen: OrbitError = EigenError::NotFinite.into();
        assert!(eigen.to_string().contains("NaN") && eigen.source().is_some());
        assert!(OrbitError::Singular.source().is_none());
        // Every solver error is a std error, so `?` carries it into a boxed error.
        fn boxed() -> Result<(), Box<dyn Error + Send + Sync>> {
            Err(SetupError::TooLarge { masses: 300 })?
        }
        assert!(boxed().is_err());
    }

    #[test]
    fn the_quadratic_constant_is_measured_above_rounding_and_bounded_below_it() {
        // Quadratic convergence r_{k+1} = 3 r_k^2 down to rounding: the last step above the
        // floor measures 3 (the step that lands at rounding only bounds it).
        let r = [1e-2, 3e-4, 2.7e-7, 2.187e-13, 1e-16];
        assert!((quadratic_constant(&r) - 3.0).abs() < 1e-9, "{}", quadratic_constant(&r));
        // An affine map: one step lands at rounding; the ratio is an upper bound, tiny.
        let affine = [2.6e-4, 2.2e-16];
        assert!((quadratic_constant(&affine) - 2.2e-16 / (2.6e-4 * 2.6e-4)).abs() < 1e-12);
        // No step taken: Newton's textbook constant 1.
        assert_eq!(quadratic_constant(&[1e-13]), 1.0);
        assert_eq!(quadratic_constant(&[]), 1.0);
    }

    #[test]
    fn the_predicted_last_evaluation_follows_the_constant() {
        // The section is a linear map u -> A u + b on R^1; Newton lands on the fixed point in
        // one step and confirms at the next evaluation. With the textbook constant the second
        // evaluation is not predicted to be the last; with an affine map's constant it is.
        struct Line;
        impl Section for Line {
            fn shift(&self, dim: usize) -> DVector<f64> {
                DVector::zeros(dim)
            }
            fn state(&self, d: &Dynamics, _u: &DVector<f64>) -> State {
                State::at_rest(d)
            }
            fn map(&self, _d: &Dynamics, u: &DVector<f64>) -> Result<Return, OrbitError> {
                let j = DMatrix::from_element(1, 1, 0.5);
                Ok(Return {
                    image: u * 0.5 + DVector::from_element(1, 1.0),
                    events: Vec::new(),
                    jacobian: Some((j, true)),
                    d_omega: None,
                })
            }
        }
        let structure = crate::model::Structure::chain(&[1.0], &[1e4], crate::model::Damping::ModalRatios(vec![0.01]));
        let sys = crate::sim::motion::system::System::plastic(structure, Vec::new(), 0, 1.0);
        let d = Dynamics::new(&sys, 100.0).expect("a one-mass chain decomposes");
        let guess = DVector::from_element(1, 1.8);
        let flags = |quadratic: f64| {
            let opts = NewtonOptions { quadratic, ..NewtonOptions::default() };
            let mut seen = Vec::new();
            let (orbit, ()) = solve_with(&Line, &d, &guess, &opts, |u, last| {
                seen.push(last);
                Ok((Line.map(&d, u)?, ()))
            })
            .expect("a contraction converges");
            assert!((orbit.u[0] - 2.0).abs() < 1e-12);
            seen
        };
        assert_eq!(flags(1.0), vec![false, false]);
        assert_eq!(flags(quadratic_constant(&[0.1, 2e-16])), vec![false, true]);
    }
}
