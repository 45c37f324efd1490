//! A bed as one mass (docs/model.md section 2): the functions the engine watches for it and
//! what its impacts do to it and its host. The law of an impact (plastic, or with restitution
//! and a sticking speed) and the law's derivative for the linearised flow are in `bed.rs`;
//! the bed as a column of grains is `column.rs`.

use nalgebra::{DMatrix, DVector, Dim, Dyn, Matrix, RowDVector, StorageMut};

use super::segment::Watch;
use super::state::{Bed, Event, EventKind, State};
use super::system::{Dynamics, System, MAX_GRAINS};

/// The functions to watch for single bed `j` in state `s`, pushed onto `w`: the contact force
/// of a resting bed, the gaps to the bottom and the top of a flying one.
pub(super) fn watches(d: &Dynamics, s: &State, j: usize, w: &mut Vec<Watch>) {
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

/// The mass an impact of bed `j` meets: its host's, with every other bed resting on that host
/// (`resting(k)`) moving with it, and those beds.
pub(super) fn host_mass(sys: &System, j: usize, resting: impl Fn(usize) -> bool) -> (f64, Vec<usize>) {
    let p = sys.dampers[j].host;
    let riders: Vec<usize> =
        (0..sys.dampers.len()).filter(|&k| k != j && resting(k) && sys.dampers[k].host == p).collect();
    (sys.structure.masses[p] + riders.iter().map(|&k| sys.dampers[k].mass).sum::<f64>(), riders)
}

/// Applies the impacts of single beds among `hits` at `s.t`, in the order of the beds: each
/// exchanges momentum with its host by its law and sticks to the end it hit (`side[j]`, a
/// candidate for the contacts the engine settles next) or flies off again. The events are
/// pushed onto `events`.
pub(super) fn impacts(d: &Dynamics, s: &mut State, hits: &[Watch], side: &mut [Option<bool>], events: &mut Vec<Event>) {
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
        let (_, u) = Bed::flight(t0, y0, u0, s.t);
        // The host's effective mass includes beds already resting on it.
        let (m_host, _) = host_mass(sys, j, |k| side[k].is_some());
        let vp = s.v[p];
        let rel = u - vp;
        let x = sys.impact_law(j).exchange(m_host, vp, dm.mass, u);
        s.v[p] = x.host;
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
/// (src/sim/tangent.rs), in the rows of the full state (`row(j)`: the row of bed `j`'s
/// position, its velocity the next): the derivative `G` of the momentum exchange, and the
/// event function `h` (`y_j - x_p` at the bottom, `x_p + d - y_j` at the top).
pub(super) struct ImpactJump {
    /// The exchange's derivative: `v_p' = (1 - a) v_p + a u`, `u' = b v_p + (1 - b) u`.
    a: f64,
    b: f64,
    /// Rows of the host's velocity and of the bed's velocity.
    host_v: usize,
    bed_u: usize,
    /// Velocity rows of the beds resting on the host (they take its new velocity).
    riders_u: Vec<usize>,
    /// Rows of the host's and the bed's positions, and the sign of `h` in them.
    host_x: usize,
    bed_y: usize,
    sign: f64,
    /// The relative speed of the impact, m/s.
    pub rel: f64,
}

impl ImpactJump {
    /// The jump of bed `j` hitting its top (`top`) or bottom in state `before`; `n` masses,
    /// `row(k)` the row of bed `k`'s position.
    pub(super) fn new(
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
        let (mh, riders) = host_mass(sys, j, |k| before.beds[k].attached());
        let (_, u) = before.bed_motion(d, j);
        let rel = u - before.v[p];
        let (a, b) = sys.impact_law(j).derivative(mh, sys.dampers[j].mass, rel);
        ImpactJump {
            a,
            b,
            host_v: n + p,
            bed_u: row(j) + 1,
            riders_u: riders.iter().map(|&k| row(k) + 1).collect(),
            host_x: p,
            bed_y: row(j),
            sign: if top { -1.0 } else { 1.0 },
            rel,
        }
    }

    /// Applies `G` to the rows of `m` (plastic: both velocities the common one; beds riding on
    /// the host take the host's new velocity), column by column in place.
    pub(super) fn apply_g<C: Dim, S: StorageMut<f64, Dyn, C>>(&self, m: &mut Matrix<f64, Dyn, C, S>) {
        for c in 0..m.ncols() {
            let (vp, uj) = (m[(self.host_v, c)], m[(self.bed_u, c)]);
            let new_v = vp * (1.0 - self.a) + uj * self.a;
            m[(self.host_v, c)] = new_v;
            m[(self.bed_u, c)] = vp * self.b + uj * (1.0 - self.b);
            for &r in &self.riders_u {
                m[(r, c)] = new_v;
            }
        }
    }

    /// The rate of `h` under the vector field `f`.
    pub(super) fn rate(&self, f: &DVector<f64>) -> f64 {
        self.sign * (f[self.bed_y] - f[self.host_x])
    }

    /// The gradient of `h` carried by the derivative `m`: `grad(h)^T m`, into `out`.
    pub(super) fn gradient_into(&self, m: &DMatrix<f64>, out: &mut RowDVector<f64>) {
        for c in 0..m.ncols() {
            out[c] = (m[(self.bed_y, c)] - m[(self.host_x, c)]) * self.sign;
        }
    }
}
