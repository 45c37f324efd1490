//! A bed as one mass (docs/model.md section 2): the functions the engine watches for it and
//! what its impacts do to it and its host. The law of an impact (plastic, or with restitution
//! and a sticking speed) and the law's derivative for the linearised flow are in `bed.rs`;
//! the bed as a column of grains is `column.rs`.

use super::segment::Watch;
use super::state::{Bed, Event, EventKind, State};
use super::system::{Dynamics, System};

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
    let mut hit_beds: Vec<(usize, bool)> =
        hits.iter().filter_map(Watch::impact).filter(|&(j, _)| !in_column(j)).collect();
    hit_beds.sort_by_key(|h| h.0);
    for &(j, top) in &hit_beds {
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
