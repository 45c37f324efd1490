//! A bed as a column of equal grains (docs/model.md, "Bed models"): which functions the
//! engine watches for its grains, and what happens when grains meet each other or an end of
//! their container.
//!
//! The grains are points stacked in order (a grain's size only shifts the column and is
//! taken out of the positions, so the clearance is the free travel of the column). A grain
//! that rests on the bottom or on grains resting there, or is pressed to the top, moves with
//! the host (an enduring contact, pressed by a force, is rigid); free grains fly. Contacts
//! between free grains carry no force and are binary: when grains meet, or a stack in flight
//! lands, the collisions are resolved in sequence, lowest touching pair first, sweeping up
//! the column again until no touching pair approaches. Each collision conserves momentum and
//! reverses the relative velocity scaled by the restitution `e`, or, slower than the
//! sticking speed (or with `e = 0`), is plastic and joins the two bodies for the rest of the
//! resolution. This sticking rule ends inelastic collapse: every bouncing collision loses at
//! least `(1 - e^2) m v_s^2 / 4` (grain mass `m`, sticking speed `v_s`) and every plastic one
//! joins two of at most `n + 1` bodies, so one resolution has at most
//! `n + 2 K / ((1 - e^2) m v_s^2 / 2)` collisions for relative kinetic energy `K`
//! ([`MAX_COLLISIONS`] is a guard far above that for the sticking speeds allowed).

use std::ops::Range;

use super::segment::Watch;
use super::state::{Bed, Event, EventKind, State};
use super::system::Dynamics;

/// Most collisions in one resolution before the rest are made plastic (a guard; the bound of
/// the module's documentation is far below it).
pub const MAX_COLLISIONS: usize = 100_000;

/// The functions to watch for the grains of column `col` in state `s`, pushed onto `w`.
pub(in crate::sim) fn watches(d: &Dynamics, s: &State, col: Range<usize>, w: &mut Vec<Watch>) {
    let dm = &d.system.dampers[col.start];
    let host = dm.host;
    if dm.clearance.is_zero() {
        return;
    }
    for j in col.clone() {
        let below = (j > col.start).then(|| s.beds[j - 1]);
        let above = (j + 1 < col.end).then(|| s.beds[j + 1]);
        match s.beds[j] {
            // One contact function for each resting stack: its grains lift off together.
            Bed::Bottom if above != Some(Bed::Bottom) => w.push(Watch::Contact { bed: j, host, sigma: 1.0 }),
            Bed::Top if below != Some(Bed::Top) => w.push(Watch::Contact { bed: j, host, sigma: -1.0 }),
            Bed::Bottom | Bed::Top => {}
            Bed::Free { t0, y0, u0 } => {
                match below {
                    None | Some(Bed::Bottom) => w.push(Watch::GapBottom { bed: j, host, y0, u0, tf: t0 }),
                    Some(Bed::Free { t0: tl, y0: yl, u0: ul }) if s.beds[j - 1] != s.beds[j] => w.push(Watch::Pair {
                        lower: j - 1,
                        upper: j,
                        lower_flight: [tl, yl, ul],
                        upper_flight: [t0, y0, u0],
                    }),
                    _ => {}
                }
                if matches!(above, None | Some(Bed::Top)) && dm.clearance.is_bounded() {
                    w.push(Watch::GapTop { bed: j, host, d: dm.clearance.m(), y0, u0, tf: t0 });
                }
            }
        }
    }
}

/// Union-find over the bodies of one resolution.
struct Bodies {
    parent: Vec<usize>,
    mass: Vec<f64>,
    vel: Vec<f64>,
}

impl Bodies {
    fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    fn join(&mut self, a: usize, b: usize, v: f64) -> usize {
        let (keep, gone) = (a.min(b), a.max(b));
        self.parent[gone] = keep;
        self.mass[keep] += self.mass[gone];
        self.vel[keep] = v;
        keep
    }
}

/// Resolves the collisions of column `col` at `s.t` started by `hits` (docs at the top of the
/// module). On return the host's velocity includes the exchanges; grains joined to the host
/// are marked in `side` (`Some(false)`: on the bottom, `Some(true)`: at the top) for the
/// engine's contact settling; the other grains it touched fly from their common position.
pub(in crate::sim) fn resolve(
    d: &Dynamics,
    s: &mut State,
    col: Range<usize>,
    hits: &[Watch],
    side: &mut [Option<bool>],
    events: &mut Vec<Event>,
) {
    let sys = &d.system;
    let n = col.len();
    let g0 = col.start;
    let dm = sys.dampers[g0];
    let p = dm.host;
    let law = sys.impact_law(g0);
    let (touching, involved) = links(s, col.clone(), hits);
    // Bodies: grains 0..n, the host n (with every bed resting on it, this column's too).
    let host = n;
    let host_side = super::single::host_side(d, p, |k| !col.contains(&k) && side[k].is_some());
    let mut b = Bodies { parent: (0..=n).collect(), mass: vec![dm.mass; n + 1], vel: vec![0.0; n + 1] };
    b.mass[host] = if sys.structure.is_lumped() {
        // Added one bed at a time (the order the column's collisions have always used).
        host_side.riders.iter().fold(sys.structure.masses[p], |m, &k| m + sys.dampers[k].mass)
    } else {
        host_side.mass
    };
    b.vel[host] = s.v[p];
    let mut y = vec![0.0; n];
    for (i, j) in col.clone().enumerate() {
        let (yi, ui) = s.bed_motion(d, j);
        y[i] = yi;
        b.vel[i] = ui;
    }
    for (i, j) in col.clone().enumerate() {
        if s.beds[j].attached() {
            let r = b.find(host);
            let v = b.vel[r];
            b.join(r, i, v);
        }
    }
    // Sweeps up the column until no touching pair approaches.
    let mut collisions = 0;
    loop {
        let mut any = false;
        for (k, _) in touching.iter().enumerate().filter(|(_, &t)| t) {
            let lower = if k == 0 { host } else { k - 1 };
            let upper = if k == n { host } else { k };
            let (a, c) = (b.find(lower), b.find(upper));
            if a == c {
                continue;
            }
            let rel = b.vel[c] - b.vel[a];
            if rel >= 0.0 || rel.is_nan() {
                continue;
            }
            any = true;
            collisions += 1;
            let x = if collisions > MAX_COLLISIONS {
                super::bed::ImpactLaw::PLASTIC.exchange(b.mass[a], b.vel[a], b.mass[c], b.vel[c])
            } else {
                law.exchange(b.mass[a], b.vel[a], b.mass[c], b.vel[c])
            };
            let host_root = b.find(host);
            let (bed, kind) = if a == host_root {
                (g0 + k, EventKind::Impact { top: false, speed: -rel, attached: x.sticks })
            } else if c == host_root {
                (g0 + k - 1, EventKind::Impact { top: true, speed: -rel, attached: x.sticks })
            } else {
                (g0 + k, EventKind::Collision { lower: g0 + k - 1, speed: -rel, stuck: x.sticks })
            };
            events.push(Event { t: s.t, bed, kind, loss: x.loss });
            if x.sticks {
                b.join(a, c, x.host);
            } else {
                b.vel[a] = x.host;
                b.vel[c] = x.bed;
            }
        }
        if !any {
            break;
        }
    }
    // The host's new velocity, the grains joined to it, and the flights of the others.
    let host_root = b.find(host);
    let vp = s.v[p];
    s.v[p] = b.vel[host_root];
    host_side.carry(p, s.v[p] - vp, s.v.as_mut_slice());
    let floor_run = touching.iter().take(n).take_while(|&&t| t).count();
    let lid_run = touching.iter().skip(1).rev().take_while(|&&t| t).count();
    for (i, &inv) in involved.iter().enumerate() {
        let j = g0 + i;
        if !inv && !s.beds[j].attached() {
            continue;
        }
        let r = b.find(i);
        let at_floor = i < floor_run;
        let at_lid = i >= n - lid_run;
        if r == host_root {
            side[j] = Some(!at_floor && at_lid);
            continue;
        }
        side[j] = None;
        let y0 = if at_floor {
            s.x[p]
        } else if at_lid {
            s.x[p] + dm.clearance.m()
        } else {
            // The lowest grain of the touching run: one position for the whole run.
            let mut low = i;
            while low > 0 && touching[low] {
                low -= 1;
            }
            y[low]
        };
        s.beds[j] = Bed::Free { t0: s.t, y0, u0: b.vel[r] };
    }
}

/// Which links of column `col` touch now (link k joins the node below grain k, the bottom for
/// k = 0, and grain k, the top for k = n), with those `hits` hit; and the grains the
/// resolution may change: those of runs of touching links that contain a hit.
fn links(s: &State, col: Range<usize>, hits: &[Watch]) -> (Vec<bool>, Vec<bool>) {
    let n = col.len();
    let g0 = col.start;
    let mut touching = vec![false; n + 1];
    let mut hit = vec![false; n + 1];
    for (i, j) in col.clone().enumerate() {
        match s.beds[j] {
            Bed::Bottom => touching[i] = true,
            Bed::Top => touching[i + 1] = true,
            Bed::Free { .. } => {
                if i > 0 && s.beds[j - 1] == s.beds[j] {
                    touching[i] = true;
                }
            }
        }
    }
    for w in hits {
        let link = match *w {
            Watch::GapBottom { bed, .. } if col.contains(&bed) => bed - g0,
            Watch::GapTop { bed, .. } if col.contains(&bed) => bed - g0 + 1,
            Watch::Pair { upper, .. } if col.contains(&upper) => upper - g0,
            _ => continue,
        };
        touching[link] = true;
        hit[link] = true;
    }
    // Runs of touching links that contain a hit: the grains the resolution may change.
    let mut involved = vec![false; n];
    let mut k = 0;
    while k <= n {
        if !touching[k] {
            k += 1;
            continue;
        }
        let start = k;
        while k <= n && touching[k] {
            k += 1;
        }
        if hit[start..k].iter().any(|&h| h) {
            // Links start..k touch grains start-1 ..= k-1 (within the column).
            involved[start.saturating_sub(1)..k.min(n)].iter_mut().for_each(|g| *g = true);
        }
    }
    (touching, involved)
}
