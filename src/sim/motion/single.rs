//! A bed as one mass (docs/model.md section 2): the functions the engine watches for it and
//! what its impacts do to it and its host. The law of an impact (plastic, or with restitution
//! and a sticking speed) and the law's derivative for the linearised flow are in `bed.rs`;
//! the bed as a column of grains is `column.rs`.

use nalgebra::{DMatrix, DVector, Dim, Dyn, Matrix, RowDVector, StorageMut};

use super::segment::Watch;
use super::state::{Bed, Event, EventKind, State};
use super::system::{Dynamics, MAX_GRAINS};

/// The functions to watch for single bed `j` in state `s`, pushed onto `w`: the contact force
/// of a resting bed, the gaps to the bottom and the top of a flying one.
pub(in crate::sim) fn watches(d: &Dynamics, s: &State, j: usize, w: &mut Vec<Watch>) {
    let dm = &d.system.dampers[j];
    let host = dm.host;
    match s.beds[j] {
        // A bed in a container without clearance cannot move relative to it.
        Bed::Bottom | Bed::Top if dm.clearance.is_zero() => {}
        resting @ (Bed::Bottom | Bed::Top) => {
            w.push(Watch::Contact { bed: j, host, sigma: Bed::contact_sign(resting == Bed::Top) })
        }
        Bed::Free { t0, y0, u0 } => {
            w.push(Watch::GapBottom { bed: j, host, y0, u0, tf: t0 });
            if dm.clearance.is_bounded() {
                w.push(Watch::GapTop { bed: j, host, d: dm.clearance.m(), y0, u0, tf: t0 });
            }
        }
    }
}

/// What an impact on a host meets: the host's effective mass, the beds riding with it, and
/// (for a mass matrix that is not diagonal) how the other degrees of freedom follow it.
pub(in crate::sim) struct HostSide {
    /// The effective mass `1 / (M_S^-1)_pp` of the host with the riders attached (lumped:
    /// its mass plus the beds resting on it), kg.
    pub mass: f64,
    /// The beds riding their hosts whose velocities the impact changes: those on the host
    /// (lumped), or every resting bed (coupled).
    pub riders: Vec<usize>,
    /// Coupled mass only: `M_S^-1 e_p / (M_S^-1)_pp`, the velocity change of every degree of
    /// freedom per unit change of the host's (an impulse on `p` moves them all).
    pub follow: Option<Vec<f64>>,
}

impl HostSide {
    /// Adds the velocity change the host's `dv` brings to the other degrees of freedom of
    /// `v` (nothing for lumped masses).
    pub fn carry(&self, p: usize, dv: f64, v: &mut [f64]) {
        if let Some(f) = &self.follow {
            for (r, (vr, fr)) in v.iter_mut().zip(f).enumerate() {
                if r != p {
                    *vr += fr * dv;
                }
            }
        }
    }
}

/// What an impact on host `p` meets when the beds `resting(k)` ride their hosts (the caller
/// excludes the beds taking part in the impact): docs/model.md sections 2 and 5. Lumped
/// masses: the host's mass with the beds resting on it, added in bed order. A coupled mass
/// matrix: the effective mass of configuration `M_S`'s degree of freedom `p`.
pub(in crate::sim) fn host_side(d: &Dynamics, p: usize, resting: impl Fn(usize) -> bool) -> HostSide {
    let sys = &d.system;
    let beds = sys.dampers.len();
    if sys.structure.is_lumped() {
        let riders: Vec<usize> = (0..beds).filter(|&k| resting(k) && sys.dampers[k].host == p).collect();
        let mass = sys.structure.masses[p] + riders.iter().map(|&k| sys.dampers[k].mass).sum::<f64>();
        return HostSide { mass, riders, follow: None };
    }
    let riders: Vec<usize> = (0..beds).filter(|&k| resting(k)).collect();
    let mask = riders.iter().fold(0usize, |m, &k| m | (1 << k));
    let inv = &d.config(mask).modes.mass_inv;
    let pp = inv[(p, p)];
    let follow = (0..d.dof).map(|r| inv[(r, p)] / pp).collect();
    HostSide { mass: 1.0 / pp, riders, follow: Some(follow) }
}

/// Applies the impacts of single beds among `hits` at `s.t`, in the order of the beds: each
/// exchanges momentum with its host by its law and sticks to the end it hit (`side[j]`, a
/// candidate for the contacts the engine settles next) or flies off again. The events are
/// pushed onto `events`.
pub(in crate::sim) fn impacts(
    d: &Dynamics,
    s: &mut State,
    hits: &[Watch],
    side: &mut [Option<bool>],
    events: &mut Vec<Event>,
) {
    let sys = &d.system;
    let in_column = |j: usize| !sys.columns.is_empty() && sys.column_of(j).is_some();
    // The hit beds in bed order (on the stack: at most two watches per bed).
    let mut buf = [(0usize, false); 2 * MAX_GRAINS];
    let mut count = 0;
    for h in hits.iter().filter_map(Watch::impact).filter(|&(j, _)| !in_column(j)) {
        buf[count] = h;
        count += 1;
    }
    let hit_beds = &mut buf[..count];
    hit_beds.sort_by_key(|h| h.0);
    for &(j, top) in hit_beds.iter() {
        let Bed::Free { t0, y0, u0 } = s.beds[j] else {
            continue;
        };
        let dm = sys.dampers[j];
        let p = dm.host;
        let (_, u) = Bed::flight(dm.gravity(), t0, y0, u0, s.t);
        // The host's effective mass includes beds already resting on it.
        let host = host_side(d, p, |k| k != j && side[k].is_some());
        let vp = s.v[p];
        let rel = u - vp;
        let x = sys.impact_law(j).exchange(host.mass, vp, dm.mass, u);
        s.v[p] = x.host;
        host.carry(p, x.host - vp, s.v.as_mut_slice());
        if x.sticks {
            side[j] = Some(top);
        } else {
            let (y_contact, _) = Bed::end_motion(top, s.x[p], s.v[p], dm.clearance);
            s.beds[j] = Bed::Free { t0: s.t, y0: y_contact, u0: x.bed };
        }
        events.push(Event {
            t: s.t,
            bed: j,
            kind: EventKind::Impact { top, speed: rel.abs(), attached: x.sticks },
            loss: x.loss,
        });
    }
}

/// What an impact of a single bed contributes to the saltation matrix of the linearised flow
/// (src/sim/orbits/tangent.rs), in the rows of the full state (`row(j)`: the row of bed `j`'s
/// position, its velocity the next): the derivative `G` of the momentum exchange, and the
/// event function `h` (`y_j - x_p` at the bottom, `x_p + d - y_j` at the top).
pub(in crate::sim) struct ImpactJump {
    /// The exchange's derivative: `v_p' = (1 - a) v_p + a u`, `u' = b v_p + (1 - b) u`.
    pub(in crate::sim) a: f64,
    pub(in crate::sim) b: f64,
    /// Rows of the host's velocity and of the bed's velocity.
    pub(in crate::sim) host_v: usize,
    pub(in crate::sim) bed_u: usize,
    /// Velocity rows of the beds riding (lumped: on the host) and of their hosts: they take
    /// their hosts' new velocities.
    pub(in crate::sim) riders_u: Vec<(usize, usize)>,
    /// Coupled mass only: the other degrees of freedom's velocity rows and how much of the
    /// host's velocity change each takes ([`HostSide::follow`]).
    pub(in crate::sim) follow: Vec<(usize, f64)>,
    /// Rows of the host's and the bed's positions, and the sign of `h` in them.
    pub(in crate::sim) host_x: usize,
    pub(in crate::sim) bed_y: usize,
    pub(in crate::sim) sign: f64,
    /// The relative speed of the impact, m/s.
    pub rel: f64,
}

impl ImpactJump {
    /// The jump of bed `j` hitting its top (`top`) or bottom in state `before`; `n` masses,
    /// `row(k)` the row of bed `k`'s position.
    pub(in crate::sim) fn new(
        d: &Dynamics,
        before: &State,
        j: usize,
        top: bool,
        n: usize,
        row: impl Fn(usize) -> usize,
    ) -> Self {
        let sys = &d.system;
        let p = sys.dampers[j].host;
        // The host moves with the beds already resting on it.
        let host = host_side(d, p, |k| k != j && before.beds[k].attached());
        let (_, u) = before.bed_motion(d, j);
        let rel = u - before.v[p];
        let (a, b) = sys.impact_law(j).derivative(host.mass, sys.dampers[j].mass, rel);
        let follow = match &host.follow {
            Some(f) => f.iter().enumerate().filter(|&(r, _)| r != p).map(|(r, &fr)| (n + r, fr)).collect(),
            None => Vec::new(),
        };
        ImpactJump {
            a,
            b,
            host_v: n + p,
            bed_u: row(j) + 1,
            riders_u: host.riders.iter().map(|&k| (row(k) + 1, n + sys.dampers[k].host)).collect(),
            follow,
            host_x: p,
            bed_y: row(j),
            sign: if top { -1.0 } else { 1.0 },
            rel,
        }
    }

    /// Applies `G` to the rows of `m` (plastic: both velocities the common one; a coupled
    /// mass matrix carries the host's change to every degree of freedom; riding beds take
    /// their hosts' new velocities), column by column in place.
    pub(in crate::sim) fn apply_g<C: Dim, S: StorageMut<f64, Dyn, C>>(&self, m: &mut Matrix<f64, Dyn, C, S>) {
        for c in 0..m.ncols() {
            let (vp, uj) = (m[(self.host_v, c)], m[(self.bed_u, c)]);
            let new_v = vp * (1.0 - self.a) + uj * self.a;
            m[(self.host_v, c)] = new_v;
            m[(self.bed_u, c)] = vp * self.b + uj * (1.0 - self.b);
            let dv = new_v - vp;
            for &(r, fr) in &self.follow {
                m[(r, c)] += fr * dv;
            }
            for &(r, host_v) in &self.riders_u {
                m[(r, c)] = m[(host_v, c)];
            }
        }
    }

    /// The rate of `h` under the vector field `f`.
    pub(in crate::sim) fn rate(&self, f: &DVector<f64>) -> f64 {
        self.sign * (f[self.bed_y] - f[self.host_x])
    }

    /// The gradient of `h` carried by the derivative `m`: `grad(h)^T m`, into `out`.
    pub(in crate::sim) fn gradient_into(&self, m: &DMatrix<f64>, out: &mut RowDVector<f64>) {
        for c in 0..m.ncols() {
            out[c] = (m[(self.bed_y, c)] - m[(self.host_x, c)]) * self.sign;
        }
    }
}
