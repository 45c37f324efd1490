//! The event loop under a record: each record interval is run as one or more pieces of closed
//! form (one per configuration between events), each piece walked in stretches of at most a
//! sixteenth of the shortest period, and the first event on each stretch found by a certified
//! search: a stretch is clear of a watch's root when both ends are on the allowed side by more
//! than a bound on the watch's second derivative times `h^2 / 8` (the most a function can
//! dip below the chord between its ends); otherwise it is halved, and a root is narrowed to
//! [`ROOT_WIDTH`].

use nalgebra::DVector;

use super::measure::Measure;
use super::piece::{At, Flight, Particular, Piece};
use super::{BedTally, RecordError, RecordOptions, RecordResponse, RecordStop};
use crate::model::ground::GroundMotion;
use crate::sim::motion::system::{Dynamics, System};

/// The width to which an event's time is narrowed, s.
const ROOT_WIDTH: f64 = 1e-13;

/// The narrowest stretch a watch's graze is resolved to, s: a watch that comes within its
/// tolerance of its bound and leaves again inside a stretch this short is a touch, not an
/// event.
const GRAZE_WIDTH: f64 = 1e-12;

/// Where a bed is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Bed {
    /// Riding on an end of its container: the top (`true`) or the bottom.
    Riding(bool),
    /// In flight, at a position and velocity relative to the ground at the run's time.
    Flying { y: f64, w: f64 },
}

/// What an event function watches; each is `>= 0` while nothing happens.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Watch {
    /// A flying bed's distance from the bottom (`false`) or the top of its container.
    Gap(usize, bool),
    /// A riding bed's contact force per unit mass on the bottom (`false`) or the top.
    Contact(usize, bool),
}

/// The run's fixed parts.
struct Setup<'a> {
    system: &'a System,
    dynamics: Dynamics,
    parts: Vec<Particular>,
    follow: Vec<f64>,
    /// Tolerances of a gap, m, and of a contact force per unit mass, m/s^2 (rounding's scale,
    /// far below anything physical).
    tol_gap: Vec<f64>,
    tol_contact: f64,
}

impl Setup<'_> {
    /// The value of `watch` on `piece` at `at` (`flight_of[j]`: bed `j`'s flight's index).
    fn watch(&self, piece: &Piece, at: &At, watch: Watch, flight_of: &[usize]) -> f64 {
        match watch {
            Watch::Gap(j, top) => {
                let d = &self.system.dampers[j];
                let y = piece.flight(&piece.flights[flight_of[j]], at.s)[0];
                let x = piece.deriv(at, d.host, 0);
                if top {
                    x + d.clearance.m() - y
                } else {
                    y - x
                }
            }
            Watch::Contact(j, top) => {
                let d = &self.system.dampers[j];
                let a = piece.deriv(at, d.host, 2) + self.follow[d.host] * piece.ground(at.s) + d.gravity();
                if top {
                    -a
                } else {
                    a
                }
            }
        }
    }

    /// A bound on the second derivative of `watch` over `[a.s, b.s]`.
    fn bound(&self, piece: &Piece, a: &At, b: &At, watch: Watch) -> f64 {
        match watch {
            Watch::Gap(j, _) => {
                let d = &self.system.dampers[j];
                let r = self.follow[d.host];
                let bed = (d.gravity() + r * piece.ground(a.s)).abs().max((d.gravity() + r * piece.ground(b.s)).abs());
                bed + piece.bound(a, b, d.host, 2)
            }
            Watch::Contact(j, _) => piece.bound(a, b, self.system.dampers[j].host, 4),
        }
    }

    fn tolerance(&self, watch: Watch) -> f64 {
        match watch {
            Watch::Gap(j, _) => self.tol_gap[j],
            Watch::Contact(..) => self.tol_contact,
        }
    }

    /// The first time in `(a.s, b.s]` a watch falls below its tolerance, and which.
    fn first(
        &self,
        piece: &Piece,
        watches: &[Watch],
        flight_of: &[usize],
        (a, wa): (&At, &[f64]),
        (b, wb): (&At, &[f64]),
    ) -> Option<(f64, usize)> {
        let width = b.s - a.s;
        let violated = (0..watches.len()).find(|&i| wb[i] < -self.tolerance(watches[i]));
        match violated {
            None => {
                let clear = (0..watches.len()).all(|i| {
                    let w = watches[i];
                    wa[i].min(wb[i]) + self.tolerance(w) > self.bound(piece, a, b, w) * width * width / 8.0
                });
                if clear || width < GRAZE_WIDTH {
                    return None;
                }
            }
            Some(i) if width < ROOT_WIDTH => return Some((b.s, i)),
            Some(_) => {}
        }
        let m = piece.at(a.s + 0.5 * width);
        let wm: Vec<f64> = watches.iter().map(|&w| self.watch(piece, &m, w, flight_of)).collect();
        self.first(piece, watches, flight_of, (a, wa), (&m, &wm))
            .or_else(|| self.first(piece, watches, flight_of, (&m, &wm), (b, wb)))
    }

    /// The relative accelerations at a state of configuration `mask` with the ground at `ag`:
    /// `M_c^-1 (w_c - K x - C v - L_c a_g)`.
    fn accel(&self, mask: usize, x: &DVector<f64>, v: &DVector<f64>, ag: f64) -> DVector<f64> {
        let modes = &self.dynamics.configs[self.dynamics.slot(mask)].modes;
        let load = &self.parts[self.dynamics.slot(mask)].load;
        let force = self.system.weight_load(mask) - &*self.dynamics.k * x - &*self.dynamics.c * v - load * ag;
        &modes.mass_inv * force
    }

    /// The stored energy relative to the ground: kinetic, strain, and the beds' height.
    fn energy(&self, mask: usize, x: &DVector<f64>, v: &DVector<f64>, beds: &[Bed]) -> f64 {
        let m = self.system.mass_matrix(mask);
        let mut e = 0.5 * (v.transpose() * m * v)[0] + 0.5 * (x.transpose() * &*self.dynamics.k * x)[0];
        for (d, bed) in self.system.dampers.iter().zip(beds) {
            let y = match *bed {
                Bed::Riding(top) => x[d.host] + if top { d.clearance.m() } else { 0.0 },
                Bed::Flying { y, w } => {
                    e += 0.5 * d.mass * w * w;
                    y
                }
            };
            e += d.mass * d.gravity() * y;
        }
        e
    }
}

fn mask_of(beds: &[Bed]) -> usize {
    beds.iter().enumerate().filter(|(_, b)| matches!(b, Bed::Riding(_))).fold(0, |m, (j, _)| m | (1 << j))
}

/// The response of `system`'s structure and beds to `record` along the structure's
/// coordinates (the system's force and harmonic base motion are not used), from rest with
/// every bed on its container's bottom.
pub fn respond(system: &System, record: &GroundMotion, options: RecordOptions) -> Result<RecordResponse, RecordError> {
    let samples = record.accel_m_s2.len();
    let dt = record.dt_s;
    if samples < 2 || !(dt > 0.0 && dt.is_finite()) {
        return Err(RecordError::Record { samples, dt_s: dt });
    }
    if !system.columns.is_empty() {
        return Err(RecordError::Columns);
    }
    let structure = &system.structure;
    let n = structure.dof();
    let k_inv = structure.stiffness.clone().try_inverse().ok_or(RecordError::Unsupported)?;
    let dynamics = Dynamics::unforced(system).map_err(RecordError::Setup)?;
    // How the coordinates follow the supports and the inertia load per unit acceleration.
    let supports = crate::model::BaseMotion::of(structure, 1.0);
    let (follow, load0) = (supports.follow, DVector::from_vec(supports.load));
    let parts = dynamics
        .configs
        .iter()
        .map(|cfg| {
            let mut load = load0.clone();
            for (j, d) in system.dampers.iter().enumerate() {
                if cfg.mask & (1 << j) != 0 {
                    load[d.host] += d.mass * follow[d.host];
                }
            }
            Particular::of(load, &k_inv, &structure.damping)
        })
        .collect();
    let peak_ground = record.accel_m_s2.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let tol_gap = system
        .dampers
        .iter()
        .map(|d| 1e-12 * if d.clearance.is_bounded() { d.clearance.m().max(1e-6) } else { 1e-3 })
        .collect();
    let setup = Setup {
        system,
        tol_contact: 1e-10 * (crate::model::GRAVITY + peak_ground),
        tol_gap,
        follow: follow.clone(),
        parts,
        dynamics,
    };
    let h_nominal = (setup.dynamics.min_period / 16.0).min(dt);

    let beds_n = system.dampers.len();
    let mut beds = vec![Bed::Riding(false); beds_n];
    let mut mask = mask_of(&beds);
    let mut x = setup.dynamics.configs[setup.dynamics.slot(mask)].modes.offset.clone();
    let mut v = DVector::zeros(n);
    let energy0 = setup.energy(mask, &x, &v, &beds);
    let mut tally = vec![BedTally::default(); beds_n];
    let shown = structure.physical();
    let mut measure = Measure::new((n, shown), structure.is_chain(), follow, structure.damping.clone());
    let mut out_t = vec![0.0];
    let mut out_u = vec![x.iter().take(shown).copied().collect::<Vec<f64>>()];
    let acc0 = setup.accel(mask, &x, &v, record.accel_m_s2[0]);
    let mut out_a = vec![(0..shown).map(|i| acc0[i] + setup.follow[i] * record.accel_m_s2[0]).collect::<Vec<f64>>()];
    let mut energy_impacts = 0.0;
    let mut events = 0usize;
    let mut stop = RecordStop::Completed;
    let mut t = 0.0;
    let stride = (samples - 1).div_ceil(options.max_history.max(2) - 1);

    'record: for kk in 0..samples - 1 {
        let t_k = kk as f64 * dt;
        let t_end = (kk + 1) as f64 * dt;
        let (a_k, a_next) = (record.accel_m_s2[kk], record.accel_m_s2[kk + 1]);
        let slope = (a_next - a_k) / dt;
        loop {
            let ag = a_k + slope * (t - t_k);
            // A riding bed whose contact would pull leaves at once (the one pulled hardest
            // first: the others' contact forces change with the configuration).
            loop {
                let acc = setup.accel(mask, &x, &v, ag);
                let pulled = beds
                    .iter()
                    .enumerate()
                    .filter_map(|(j, b)| match *b {
                        Bed::Riding(top) => {
                            let d = &system.dampers[j];
                            let a = acc[d.host] + setup.follow[d.host] * ag + d.gravity();
                            let force = if top { -a } else { a };
                            (force < -setup.tol_contact).then_some((j, top, force))
                        }
                        Bed::Flying { .. } => None,
                    })
                    .min_by(|a, b| a.2.total_cmp(&b.2));
                let Some((j, top, _)) = pulled else { break };
                let d = &system.dampers[j];
                beds[j] = Bed::Flying { y: x[d.host] + if top { d.clearance.m() } else { 0.0 }, w: v[d.host] };
                tally[j].lift_offs += 1;
                events += 1;
                mask = mask_of(&beds);
            }
            let slot = setup.dynamics.slot(mask);
            let modes = &setup.dynamics.configs[slot].modes;
            let mut flight_of = vec![usize::MAX; beds_n];
            let mut flights = Vec::new();
            let mut watches = Vec::new();
            for (j, b) in beds.iter().enumerate() {
                let d = &system.dampers[j];
                match *b {
                    Bed::Riding(top) => watches.push(Watch::Contact(j, top)),
                    Bed::Flying { y, w } => {
                        flight_of[j] = flights.len();
                        flights.push(Flight {
                            bed: j,
                            mass: d.mass,
                            gravity: d.gravity(),
                            follow: setup.follow[d.host],
                            y0: y,
                            w0: w,
                        });
                        watches.push(Watch::Gap(j, false));
                        if d.clearance.is_bounded() {
                            watches.push(Watch::Gap(j, true));
                        }
                    }
                }
            }
            let part = &setup.parts[slot];
            let piece = Piece::start(modes, part, (&x, &v), (ag, slope), flights);
            let span = t_end - t;
            let stretches = (span / h_nominal).ceil().max(1.0) as usize;
            let h = span / stretches as f64;
            let values =
                |at: &At| -> Vec<f64> { watches.iter().map(|&w| setup.watch(&piece, at, w, &flight_of)).collect() };
            // Equal stretches: their ends and quadrature nodes by multiplication (the
            // interval's end exactly).
            let step = piece.factors(h);
            let nodes = Measure::nodes(&piece, h);
            let mut a = piece.at(0.0);
            let mut wa = values(&a);
            let mut found = None;
            for i in 1..=stretches {
                let b = if i == stretches { piece.at(span) } else { piece.shifted(&a, &step) };
                let wb = values(&b);
                if let Some((s, w)) = setup.first(&piece, &watches, &flight_of, (&a, &wa), (&b, &wb)) {
                    let e = piece.at(s);
                    measure.stretch(&piece, part, (&a, &e), None);
                    found = Some((e, watches[w]));
                    break;
                }
                measure.stretch(&piece, part, (&a, &b), Some(&nodes));
                (a, wa) = (b, wb);
            }
            // The state where the piece ends: at the event, or at the interval's end.
            let end = found.as_ref().map_or(&a, |(e, _)| e);
            (x, v) = piece.state(end);
            for f in &piece.flights {
                let [y, w, _] = piece.flight(f, end.s);
                beds[f.bed] = Bed::Flying { y, w };
            }
            let Some((e, watch)) = found else {
                t = t_end;
                break;
            };
            t += e.s;
            events += 1;
            match watch {
                Watch::Contact(j, top) => {
                    let d = &system.dampers[j];
                    beds[j] = Bed::Flying { y: x[d.host] + if top { d.clearance.m() } else { 0.0 }, w: v[d.host] };
                    tally[j].lift_offs += 1;
                }
                Watch::Gap(j, top) => {
                    let d = &system.dampers[j];
                    let Bed::Flying { w, .. } = beds[j] else { unreachable!("a gap is watched only in flight") };
                    let h = d.host;
                    let speed = (w - v[h]).abs();
                    let host_mass = 1.0 / modes.mass_inv[(h, h)];
                    let ex = system.impact_law(j).exchange(host_mass, v[h], d.mass, w);
                    let impulse = host_mass * (ex.host - v[h]);
                    v += modes.mass_inv.column(h) * impulse;
                    energy_impacts += ex.loss;
                    tally[j].impacts += 1;
                    tally[j].energy_lost += ex.loss;
                    tally[j].peak_impact_speed = tally[j].peak_impact_speed.max(speed);
                    let wall = x[h] + if top { d.clearance.m() } else { 0.0 };
                    beds[j] = if ex.sticks { Bed::Riding(top) } else { Bed::Flying { y: wall, w: ex.bed } };
                }
            }
            mask = mask_of(&beds);
            if events > options.max_events {
                stop = RecordStop::Events { t_s: t };
                break 'record;
            }
        }
        if (kk + 1) % stride == 0 || kk + 2 == samples {
            out_t.push(t);
            out_u.push(x.iter().take(shown).copied().collect());
            let acc = setup.accel(mask, &x, &v, a_next);
            out_a.push((0..shown).map(|i| acc[i] + setup.follow[i] * a_next).collect());
        }
    }
    let energy_stored = setup.energy(mask, &x, &v, &beds) - energy0;
    let [rms_displacement, rms_drift, rms_accel] = measure.rms();
    let [peak_displacement, peak_drift, peak_accel] = measure.peak;
    Ok(RecordResponse {
        t: out_t,
        u: out_u,
        accel: out_a,
        peak_displacement,
        peak_drift,
        peak_accel,
        rms_displacement,
        rms_drift,
        rms_accel,
        energy_input: measure.input,
        energy_viscous: measure.viscous,
        energy_impacts,
        energy_stored,
        beds: tally,
        events,
        stop,
    })
}
