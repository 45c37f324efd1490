//! The event-driven simulator: closed-form segments, certified event location, plastic (or
//! restitution) impacts, and contact resolution after every event (docs/model.md section 2).

pub use super::state::{Bed, Event, EventKind, State};

use super::roots::{first_root_from, fresh_window, lower_root, TIME_TOL};
use super::segment::{Point, Reads, Segment, Taylor, Watch};
use super::system::{Dynamics, MAX_GRAINS, STEP_FRACTION};

/// Why a run stopped early.
#[derive(Debug, Clone, PartialEq)]
pub enum Stop {
    /// More events than allowed within one forcing period: chatter (or a Zeno sequence with
    /// restitution).
    Chatter {
        /// Time reached, s.
        t: f64,
        /// Events counted within the forcing period that ended the run.
        events: usize,
    },
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::Chatter { t, events } => {
                write!(f, "chatter: {events} events within one forcing period, stopped at t = {t:.6} s")
            }
        }
    }
}

impl std::error::Error for Stop {}

/// Receives the motion as it is computed.
pub trait Observer {
    /// A smooth segment of the motion, valid on `[t_a, t_b]`.
    fn segment(&mut self, _d: &Dynamics, _seg: &Segment, _beds: &[Bed], _t_a: f64, _t_b: f64) {}
    /// An event, after it has been applied to `after`.
    fn event(&mut self, _ev: &Event, _after: &State) {}
    /// Whether [`Observer::jump`] is wanted (it costs a copy of the state at every event).
    fn wants_jumps(&self) -> bool {
        false
    }
    /// The state just before and just after the events at one time, and the event functions
    /// that reached zero there (for the linearised flow: saltation at events).
    fn jump(&mut self, _d: &Dynamics, _before: &State, _after: &State, _hits: &[Watch]) {}
    /// Whether the observer has seen what it waits for: [`Engine::advance`] then returns
    /// right after the events that finished it (before `t_end`).
    fn done(&self) -> bool {
        false
    }
}

/// An observer that ignores everything.
pub struct Quiet;
impl Observer for Quiet {}

/// Tunables of the event search.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Search step as a fraction of the shortest period.
    pub step_fraction: f64,
    /// Most events within one forcing period (counted from the first event of a window one
    /// period long, in one `advance` call) before the call stops with [`Stop::Chatter`]. A call
    /// of many periods (a record, a torus's window) is not stopped by the events of all its
    /// periods together, only by a burst within one.
    pub max_events: usize,
    /// Whether the search skips coarse windows where no event can be (above
    /// [`LARGE_ABOVE`](super::system::LARGE_ABOVE) degrees of freedom, at the default step;
    /// `sim::motion::coarse`). Off, it steps through ordinary windows only: the same events (a test
    /// compares the two).
    pub coarse: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings { step_fraction: STEP_FRACTION, max_events: 2000, coarse: true }
    }
}

/// Tolerance on a contact acceleration that counts as zero, m/s^2.
const ACCEL_TOL: f64 = 1e-8;
/// Value, slope and curvature of a watched function that count as zero at a segment's
/// start (a contact just made or just broken), in its units.
fn fresh_tol(w: &Watch, omega: f64) -> [f64; 3] {
    match w {
        Watch::Contact { .. } => [ACCEL_TOL, ACCEL_TOL * omega, ACCEL_TOL * omega * omega],
        _ => [1e-15, 1e-12, ACCEL_TOL],
    }
}

/// [`fresh_tol`]'s slope and curvature raised to the rounding of the closed form where that is
/// larger: a few roundings of the sum of the terms' moduli, grown by the eigenvectors'
/// condition (a state is carried to the terms' coefficients and back). A structure of many
/// degrees of freedom rounds more: on a 64-mass chain a relative velocity of 2e-12 m/s left by
/// rounding after a lift-off counted as an impact, again and again at one instant.
fn rounded_tol(w: &Watch, tol: [f64; 3], seg: &Segment, d: &Dynamics, pt: &Point) -> [f64; 3] {
    let Some((host, first, _)) = w.reads() else {
        return tol;
    };
    let rounding = rounding(seg, d);
    [
        tol[0],
        tol[1].max(rounding * seg.bound(d, pt, host, first + 1)),
        tol[2].max(rounding * seg.bound(d, pt, host, first + 2)),
    ]
}

/// A few roundings of a sum of `seg`'s terms, grown by its eigenvectors' condition: relative
/// to the sum of the terms' moduli ([`Segment::bound`]).
fn rounding(seg: &Segment, d: &Dynamics) -> f64 {
    32.0 * f64::EPSILON * seg.len as f64 * d.configs[seg.slot].modes.condition
}

/// Degrees of freedom above which a contact acceleration and its rate count as zero up to the
/// closed form's rounding where that exceeds [`ACCEL_TOL`] (on the paper's three masses the
/// rounding is about 2e-11 m/s^2; on a 64-mass chain near resonance 3e-8 m/s^2, and a lift-off
/// the event search found was undone again and again by a contact force computed as 1.3e-8).
const ROUNDED_CONTACTS_ABOVE: usize = super::system::LARGE_ABOVE;

/// A watch's data at a segment's start from the state and the host's rows
/// ([`Dynamics::host_derivs`], the source [`Engine::settle`] decides contacts from), not from
/// the closed form. The closed form carries the state to the terms' coefficients and back and
/// leaves rounding: a gap's value and rate after a plastic impact on the lid (7e-11 m/s on a
/// 64-mass chain, which counted as the next impact, again and again at one instant), and a
/// host's acceleration off by whatever the eigenvectors carry (1.8e-3 m/s^2 on a reduced plate
/// whose fastest fixed-interface modes are near 8 kHz while its eigenvectors came from the
/// state matrix, where the rows and the full products agree to 1e-9: a lift-off decided on
/// -1.1e-3 m/s^2 met a gap curving down at once, and the bed landed and lifted off again at one
/// instant, 2000 times; [`super::eigen::decompose_second_order`] removed most of it, this the
/// rest: the decision and the search read one number).
/// A bed that leaves its host at this instant (`tf` the state's time) gets its gap and rate
/// from the state (zero when it lifts off or sticks) and their next two derivatives from the
/// rows; a bed riding its host, its contact acceleration and next two derivatives.
fn exact_start(w: &Watch, d: &Dynamics, s: &State, ta: &mut Taylor) {
    let host = |bed: usize| d.host_derivs(s.mask(), bed, s.t, &s.x, &s.v);
    match *w {
        Watch::GapBottom { bed, host: p, y0, u0, tf } if tf == s.t => {
            let [a, jerk, _] = host(bed);
            ta.h = [y0 - s.x[p], u0 - s.v[p], -(a + d.system.dampers[bed].gravity()), -jerk];
        }
        Watch::GapTop { bed, host: p, d: clearance, y0, u0, tf } if tf == s.t => {
            let [a, jerk, _] = host(bed);
            ta.h = [s.x[p] + clearance - y0, s.v[p] - u0, a + d.system.dampers[bed].gravity(), jerk];
        }
        Watch::Contact { bed, sigma, .. } => {
            let [a, jerk, snap] = host(bed);
            ta.h[..3].copy_from_slice(&[sigma * (a + d.system.dampers[bed].gravity()), sigma * jerk, sigma * snap]);
        }
        _ => {}
    }
}

/// What counts as a zero contact acceleration of host `host`, its rate and its second
/// derivative at point `pt` of `seg`: [`ACCEL_TOL`] times 1, `omega` and `omega^2`, raised to
/// the closed form's rounding above [`ROUNDED_CONTACTS_ABOVE`] degrees of freedom.
fn contact_zero(seg: &Segment, d: &Dynamics, pt: &Point, host: usize) -> [f64; 3] {
    let plain = [ACCEL_TOL, ACCEL_TOL * d.omega, ACCEL_TOL * d.omega * d.omega];
    if d.dof <= ROUNDED_CONTACTS_ABOVE {
        return plain;
    }
    let r = rounding(seg, d);
    [
        plain[0].max(r * seg.bound(d, pt, host, 2)),
        plain[1].max(r * seg.bound(d, pt, host, 3)),
        plain[2].max(r * seg.bound(d, pt, host, 4)),
    ]
}

/// Which derivative of each bed's contact acceleration decided, at time `t`, whether it stays
/// on its container or leaves it ([`Engine::settle`]): 0 its value, 1 its rate (the value
/// counted as zero), 2 the rate's rate. The event search after that instant counts the same
/// lower derivatives as zero, so that it cannot undo the decision on rounding (on a reduced
/// plate two beds at symmetric corners lifted off and landed again at one instant, 2000
/// times, each decision reversed by a residue of 1e-7 m/s^2 in a derivative the other had
/// counted as zero; on the six-storey frame a horizontal bed left its wall and hit it again
/// at one instant, its contact force 7e-9 m/s^2 in the closed form and 1.1e-8 from the
/// state). Where the decision was made on the value (order 0) nothing changes: the searches
/// after an ordinary event are those of before, bit for bit.
#[derive(Debug, Clone, Copy)]
struct Decided {
    t: f64,
    order: [u8; MAX_GRAINS],
}

impl Default for Decided {
    fn default() -> Self {
        Decided { t: f64::NAN, order: [0; MAX_GRAINS] }
    }
}

impl Decided {
    /// The derivatives of watch `w`'s function at `t` that count as zero after the decision:
    /// `tol` with those entries raised to infinity.
    fn raise(&self, w: &Watch, t: f64, mut tol: [f64; 3]) -> [f64; 3] {
        if self.t != t {
            return tol;
        }
        let k = self.order[w.bed()] as usize;
        let below = match w {
            // h = (n, n', n'', ...): the first k count as zero.
            Watch::Contact { .. } => 0..k,
            // h = (gap, gap', -n, -n'): gap and gap' are exact zeros; -n counts as zero when k >= 1.
            Watch::GapBottom { .. } | Watch::GapTop { .. } => 2..(2 + k).min(3),
            Watch::Pair { .. } => 0..0,
        };
        for i in below {
            tol[i] = f64::INFINITY;
        }
        tol
    }
}

/// Buffers a run reuses at every event, kept per thread from run to run.
#[derive(Default)]
struct Scratch {
    watches: Vec<Watch>,
    hits: Vec<Watch>,
    applied: Vec<Event>,
    before: Option<State>,
    decided: Decided,
}

thread_local! {
    static SCRATCH: std::cell::Cell<Option<Scratch>> = const { std::cell::Cell::new(None) };
}

/// The simulator for one system at one forcing frequency.
pub struct Engine<'a> {
    /// The closed-form dynamics the engine steps.
    pub d: &'a Dynamics,
    /// Its limits and tolerances.
    pub settings: Settings,
}

impl<'a> Engine<'a> {
    /// An engine over `d` with the default settings.
    pub fn new(d: &'a Dynamics) -> Engine<'a> {
        Engine { d, settings: Settings::default() }
    }

    /// The functions to watch in the state's configuration, into `w` (cleared first).
    fn watches(&self, s: &State, w: &mut Vec<Watch>) {
        w.clear();
        for col in &self.d.system.columns {
            super::column::watches(self.d, s, col.clone(), w);
        }
        for j in 0..s.beds.len() {
            if self.d.system.columns.is_empty() || self.d.system.column_of(j).is_none() {
                super::single::watches(self.d, s, j, w);
            }
        }
    }

    /// Advances `s` to `t_end`, applying every event on the way, or to the first event after
    /// which the observer is [`Observer::done`].
    pub fn advance(&self, s: &mut State, t_end: f64, obs: &mut impl Observer) -> Result<(), Stop> {
        // The buffers of the thread's previous run (none inside another run, which an observer
        // could start): a run allocates nothing once they have grown.
        let mut scratch = SCRATCH.with(|c| c.take()).unwrap_or_default();
        let result = self.advance_with(s, t_end, obs, &mut scratch);
        SCRATCH.with(|c| c.set(Some(scratch)));
        result
    }

    fn advance_with(
        &self,
        s: &mut State,
        t_end: f64,
        obs: &mut impl Observer,
        scratch: &mut Scratch,
    ) -> Result<(), Stop> {
        let mut events = 0;
        // The events are counted in windows of one forcing period (no limit on the window in a
        // free decay, omega = 0), the first starting with the call.
        let period = if self.d.omega > 0.0 { 2.0 * std::f64::consts::PI / self.d.omega } else { f64::INFINITY };
        let mut window = s.t;
        // Reused at every event: the watches, those that fire, the events applied, the state
        // before.
        let Scratch { watches, hits, applied, before, decided } = scratch;
        decided.t = f64::NAN;
        while s.t < t_end {
            let seg = Segment::start(self.d, s.mask(), s.t, &s.x, &s.v);
            self.watches(s, watches);
            match self.next_event(&seg, watches, s, t_end, hits, decided) {
                None => {
                    obs.segment(self.d, &seg, &s.beds, s.t, t_end);
                    let pt = seg.point(self.d, t_end);
                    seg.state_into(self.d, &pt, &mut s.x, &mut s.v);
                    s.t = t_end;
                }
                Some(te) => {
                    obs.segment(self.d, &seg, &s.beds, s.t, te);
                    let pt = seg.point(self.d, te);
                    // Above ROUNDED_CONTACTS_ABOVE degrees of freedom an event at the
                    // segment's start leaves the state as it is: carried to the terms'
                    // coefficients and back it would change by the closed form's rounding
                    // (1e-9 m/s on a reduced plate, where a coupled mass matrix passes each
                    // bed's impact on to the other hosts at once), and a run of impacts at one
                    // instant would feed on it for ever.
                    if te != s.t || self.d.dof <= ROUNDED_CONTACTS_ABOVE {
                        seg.state_into(self.d, &pt, &mut s.x, &mut s.v);
                        s.t = te;
                    }
                    let jumps = obs.wants_jumps();
                    if jumps {
                        match before {
                            Some(b) => b.clone_from(s),
                            None => *before = Some(s.clone()),
                        }
                    }
                    self.apply(s, hits, applied, decided, &|p| contact_zero(&seg, self.d, &pt, p));
                    for ev in applied.iter() {
                        obs.event(ev, s);
                    }
                    if let Some(before) = before.as_ref().filter(|_| jumps) {
                        obs.jump(self.d, before, s, hits);
                    }
                    if obs.done() {
                        return Ok(());
                    }
                    if s.t >= window + period {
                        window = s.t;
                        events = 0;
                    }
                    events += 1;
                    if events > self.settings.max_events {
                        return Err(Stop::Chatter { t: s.t, events });
                    }
                }
            }
        }
        Ok(())
    }

    /// Where watch `w`'s search for its next zero starts: just past a fresh zero (within
    /// `span`), or at `s.t`; `None` when it fires at `s.t`.
    #[inline]
    fn search_start(
        &self,
        w: &Watch,
        seg: &Segment,
        s: &State,
        first: &Point,
        decided: &Decided,
        span: f64,
    ) -> Option<f64> {
        let (d, t_a) = (self.d, s.t);
        let mut ta = w.taylor(seg, d, first);
        let big = d.dof > ROUNDED_CONTACTS_ABOVE;
        if big {
            exact_start(w, d, s, &mut ta);
        }
        let mut tol = fresh_tol(w, d.omega);
        if let Watch::Contact { host, .. } = *w {
            tol[0] = contact_zero(seg, d, first, host)[0];
        }
        tol = decided.raise(w, t_a, tol);
        if ta.h[0] <= tol[0] {
            let tol = rounded_tol(w, tol, seg, d, first);
            fresh_window(&ta, TIME_TOL, tol, span).map(|win| t_a + win)
        } else {
            Some(t_a)
        }
    }

    /// The earliest event in `(t_a, t_b]`, with the watches that fire there in `hits`
    /// (cleared first).
    fn next_event(
        &self,
        seg: &Segment,
        watches: &[Watch],
        s: &State,
        t_b: f64,
        hits: &mut Vec<Watch>,
        decided: &Decided,
    ) -> Option<f64> {
        let t_a = s.t;
        hits.clear();
        if watches.is_empty() {
            return None;
        }
        let d = self.d;
        let step = d.min_period * self.settings.step_fraction;
        // Where each watch's search starts: just past a fresh zero, or at t_a.
        let mut on_stack = [0.0; 32];
        let mut on_heap = Vec::new();
        let starts: &mut [f64] = if watches.len() <= on_stack.len() {
            &mut on_stack
        } else {
            on_heap.resize(watches.len(), 0.0);
            &mut on_heap
        };
        let mut n_starts = 0;
        let first = seg.point(d, t_a);
        for w in watches {
            let Some(start) = self.search_start(w, seg, s, &first, decided, step.min(t_b - t_a)) else {
                hits.push(*w);
                return Some(t_a);
            };
            starts[n_starts] = start;
            n_starts += 1;
        }
        // The windows' starts are equally spaced: with the default step each point is carried
        // from the one before by the step's factors (no exponential, sine or cosine).
        let carry = (self.settings.step_fraction == STEP_FRACTION).then(|| d.window_step(seg.slot));
        // Above LARGE_ABOVE degrees of freedom, windows of many steps skipped whole where no
        // function can reach zero (`sim::motion::coarse`), once every watch's search has started.
        let coarse = self.settings.coarse && d.dof > super::system::LARGE_ABOVE;
        let levels = carry.filter(|_| coarse).map(|_| d.levels(seg.slot)).filter(|l| !l.is_empty());
        let searching = starts[..n_starts].iter().fold(t_a, |m, &s| m.max(s));
        let mut best: Option<f64> = None;
        let mut a = t_a;
        let mut current = first;
        // A point the inner loop overwrites when a watch's window starts inside a step.
        let mut spare: Option<Point> = None;
        // Whether `current` must still be carried one ordinary step to `a`.
        let mut behind = false;
        // Ordinary windows before the next try of a coarse one: after each failed try twice as
        // many as after the one before (at most MAX_WAIT), none after a skip.
        let (mut wait, mut backoff) = (0usize, 1usize);
        // The host sums read in one window, each once (a flying bed's two gaps read the same),
        // above LARGE_ABOVE degrees of freedom: on a small structure a sum costs less than
        // looking it up.
        let mut reads = (d.dof > super::system::LARGE_ABOVE).then(Reads::default);
        while a < t_b {
            if behind {
                match carry {
                    Some(st) => current.advance(st, a),
                    None => seg.point_into(d, a, &mut current),
                }
            }
            if let Some(levels) = levels.filter(|_| a >= searching) {
                if wait > 0 {
                    wait -= 1;
                } else if let Some(k) = super::coarse::clear_level(seg, d, watches, &current, levels, t_b - a) {
                    let st = &levels.steps[k];
                    if st.dt >= t_b - a {
                        return None;
                    }
                    a += st.dt;
                    current.advance(st, a);
                    (behind, backoff) = (false, 1);
                    continue;
                } else {
                    wait = backoff;
                    backoff = (2 * backoff).min(super::coarse::MAX_WAIT);
                }
            }
            let b = (a + step).min(t_b);
            behind = true;
            let pt = &current;
            if let Some(reads) = reads.as_mut() {
                reads.clear();
            }
            for (w, &start) in watches.iter().zip(&starts[..n_starts]) {
                let lo = a.max(start);
                if lo >= b {
                    continue;
                }
                let base = if lo == a {
                    pt
                } else {
                    match spare.as_mut() {
                        Some(p) => seg.point_into(d, lo, p),
                        None => spare = Some(seg.point(d, lo)),
                    }
                    spare.as_ref().unwrap_or(pt)
                };
                let ta = match reads.as_mut() {
                    Some(reads) => reads.taylor(w, seg, d, base),
                    None => w.taylor(seg, d, base),
                };
                let Some(tau) = lower_root(&ta, b - lo) else {
                    continue;
                };
                // The search advances from point to point, the last advances short: each
                // point is carried from the one before when that near.
                let mut near = base.clone();
                let mut eval = |t: f64| {
                    seg.move_near(d, &mut near, t);
                    w.taylor(seg, d, &near)
                };
                if let Some(r) = first_root_from(&mut eval, lo, ta, tau, b) {
                    earliest(&mut best, hits, r, *w);
                }
            }
            if best.is_some() {
                return best;
            }
            a = b;
        }
        None
    }

    /// Applies impacts and releases at `s.t` and settles the contacts. The events, into
    /// `events` (cleared first); which derivative decided each bed, into `decided`.
    /// `zero(p)`: the contact acceleration of host `p` and its two derivatives that count as
    /// zero.
    fn apply(
        &self,
        s: &mut State,
        hits: &[Watch],
        events: &mut Vec<Event>,
        decided: &mut Decided,
        zero: &dyn Fn(usize) -> [f64; 3],
    ) {
        let d = self.d;
        let sys = &d.system;
        events.clear();
        // Contact candidates: every attached bed plus beds that just landed plastically.
        let nb = s.beds.len();
        let mut side_buf = [None; MAX_GRAINS];
        let side = &mut side_buf[..nb];
        for (sd, b) in side.iter_mut().zip(&s.beds) {
            *sd = b.end();
        }
        // Single beds: their impacts (src/sim/motion/single.rs).
        super::single::impacts(d, s, hits, side, events);
        // Columns: the collisions the hits started, in sequence (src/sim/motion/column.rs).
        for col in &sys.columns {
            let touched = hits.iter().any(|w| match w.impact() {
                Some((j, _)) => col.contains(&j),
                None => w.pair().is_some_and(|(_, u)| col.contains(&u)),
            });
            if touched {
                super::column::resolve(d, s, col.clone(), hits, side, events);
            }
        }
        // Settle: the largest set of candidates whose contact forces are consistent.
        let mut cand_buf = [0usize; MAX_GRAINS];
        let mut nc = 0;
        for j in (0..nb).filter(|&j| side[j].is_some() && !sys.dampers[j].clearance.is_zero()) {
            cand_buf[nc] = j;
            nc += 1;
        }
        let candidates = &cand_buf[..nc];
        let locked: usize =
            (0..nb).filter(|&j| side[j].is_some() && sys.dampers[j].clearance.is_zero()).fold(0, |m, j| m | (1 << j));
        // Beds whose contact force the event search found at zero now: its value here is
        // rounding (above [`ROUNDED_CONTACTS_ABOVE`] degrees of freedom the closed form's, on
        // any structure the root's: a force falling at 1560 m/s^3 is 8e-9 m/s^2 a few
        // picoseconds from its root), and its rate decides. (Decided on its value, a force of
        // 1.1e-8 m/s^2 from the state kept a horizontal bed on its wall while the search,
        // finding 7e-9 in the closed form and a falling rate, saw the lift-off again at the
        // same instant: 2000 times, a stop for chatter after 44,000 periods.)
        let at_zero = hits.iter().fold(0usize, |m, w| match *w {
            Watch::Contact { bed, .. } => m | (1 << bed),
            _ => m,
        });
        let attached = self.settle(s, candidates, (side, locked, at_zero), decided, &|p, j| {
            let [tol, rate_tol, curvature_tol] = zero(p);
            [if at_zero & (1 << j) != 0 { f64::INFINITY } else { tol }, rate_tol, curvature_tol]
        });
        for &j in candidates {
            let top = side[j].unwrap_or(false);
            let p = sys.dampers[j].host;
            if attached & (1 << j) != 0 {
                s.beds[j] = Bed::on_end(top);
            } else {
                let (y0, _) = Bed::end_motion(top, s.x[p], s.v[p], sys.dampers[j].clearance);
                let was_attached = s.beds[j].attached();
                s.beds[j] = Bed::Free { t0: s.t, y0, u0: s.v[p] };
                if was_attached {
                    events.push(Event { t: s.t, bed: j, kind: EventKind::LiftOff { top }, loss: 0.0 });
                } else if let Some(ev) =
                    events.iter_mut().rev().find(|e| e.bed == j && matches!(e.kind, EventKind::Impact { .. }))
                {
                    if let EventKind::Impact { attached, .. } = &mut ev.kind {
                        *attached = false;
                    }
                }
            }
        }
    }

    /// The attached mask after an event: among subsets of the candidates, largest first (ties
    /// by bed index), the first in which every attached bed is pressed on (contact force >= 0)
    /// and every detached candidate moves away (relative acceleration >= 0); signs near zero
    /// (`zero(host, bed)`: the force and its two derivatives that count as zero) are decided by
    /// the next derivative. The grains of a column resting on one end are one
    /// candidate (their contact forces share the host's acceleration).
    ///
    /// Above [`ROUNDED_CONTACTS_ABOVE`] degrees of freedom which derivative decides a unit is
    /// fixed once, in the configuration with every candidate attached, and kept in every
    /// subset: a contact force at zero and the relative acceleration the same bed has when it
    /// leaves differ by a positive factor (1 + bed mass / the host's effective mass, 14 at the
    /// corner of a reduced plate), so one absolute tolerance applied to both would call the
    /// same zero a push in one subset and nothing in the other, and no subset would do. The
    /// deciding orders of the chosen subset go to `decided`.
    fn settle(
        &self,
        s: &State,
        candidates: &[usize],
        contacts: (&[Option<bool>], usize, usize),
        decided: &mut Decided,
        zero: &dyn Fn(usize, usize) -> [f64; 3],
    ) -> usize {
        let (side, locked, at_zero) = contacts;
        let d = self.d;
        let sys = &d.system;
        let mut unit_buf = [(0usize, 0usize); MAX_GRAINS];
        let mut m: usize = 0;
        for &j in candidates {
            let unit = if sys.columns.is_empty() { None } else { sys.column_of(j) };
            let last = m.checked_sub(1).map(|i| unit_buf[i]);
            match (unit, last) {
                (Some(col), Some((first, _))) if col.contains(&first) && side[first] == side[j] => {
                    unit_buf[m - 1].1 |= 1 << j
                }
                _ => {
                    unit_buf[m] = (j, 1 << j);
                    m += 1;
                }
            }
        }
        let units = &unit_buf[..m];
        let mask_of = |bits: usize| {
            units.iter().enumerate().filter(|(i, _)| bits & (1 << i) != 0).fold(locked, |acc, (_, u)| acc | u.1)
        };
        let sigma = |j: usize| if side[j] == Some(true) { -1.0 } else { 1.0 };
        let big = d.dof > ROUNDED_CONTACTS_ABOVE;
        // Up to ROUNDED_CONTACTS_ABOVE a contact force is zero within ACCEL_TOL, or whatever
        // it is where the search found it at zero (`contact_zero`'s, bit for bit).
        let small_tol = |j: usize| if at_zero & (1 << j) != 0 { f64::INFINITY } else { ACCEL_TOL };
        // Up to ROUNDED_CONTACTS_ABOVE every mass's accelerations and jerks in each subset
        // (the paper's structures' numbers, bit for bit); above it the hosts' own derivatives
        // from their rows ([`Dynamics::host_derivs`]).
        let at = (!big).then(|| d.at_state(s.t, &s.x, &s.v));
        let host = |mask: usize, j: usize| d.host_derivs(mask, j, s.t, &s.x, &s.v);
        decided.t = f64::NAN;
        // Above ROUNDED_CONTACTS_ABOVE: the derivative that decides each unit.
        let mut order_buf = [0u8; MAX_GRAINS];
        let orders = &mut order_buf[..m];
        if big {
            let all = mask_of((1 << m) - 1);
            for (o, &(j, _)) in orders.iter_mut().zip(units) {
                let p = sys.dampers[j].host;
                let [tol, rate_tol, _] = zero(p, j);
                let [a, jerk, _] = host(all, j);
                *o = if (sigma(j) * (a + sys.dampers[j].gravity())).abs() > tol {
                    0
                } else if (sigma(j) * jerk).abs() > rate_tol {
                    1
                } else {
                    2
                };
            }
        }
        let orders = &*orders;
        // Up to ROUNDED_CONTACTS_ABOVE the order that decided each unit in the subset tried.
        let mut small_orders = [0u8; MAX_GRAINS];
        for bits in subsets_largest_first(m) {
            let mask = mask_of(bits);
            let small = at.as_ref().map(|at| d.accelerations_in(mask, at));
            let ok = units.iter().enumerate().all(|(i, &(j, _))| {
                let p = sys.dampers[j].host;
                let sign = match &small {
                    Some((a, jerk)) => {
                        let n = sigma(j) * (a[p] + sys.dampers[j].gravity());
                        let dn = sigma(j) * jerk[p];
                        // The value counted as zero where the search found it so.
                        let (order, sign) = if n.abs() > small_tol(j) {
                            (0, n.signum())
                        } else if dn.abs() > ACCEL_TOL * d.omega {
                            (1, dn.signum())
                        } else {
                            (2, 0.0)
                        };
                        small_orders[i] = order;
                        sign
                    }
                    None => {
                        let [a, jerk, snap] = host(mask, j);
                        let n = sigma(j) * (a + sys.dampers[j].gravity());
                        match orders[i] {
                            0 => n.signum(),
                            1 => (sigma(j) * jerk).signum(),
                            _ if (sigma(j) * snap).abs() > zero(p, j)[2] => (sigma(j) * snap).signum(),
                            _ => 0.0,
                        }
                    }
                };
                if bits & (1 << i) != 0 {
                    sign >= 0.0
                } else {
                    sign <= 0.0
                }
            });
            if ok {
                *decided = Decided { t: s.t, ..Decided::default() };
                for (i, &(_, u)) in units.iter().enumerate() {
                    // Every unit of the subset taken was judged.
                    let o = if small.is_some() { small_orders[i] } else { orders[i] };
                    let mut bits = u;
                    while bits != 0 {
                        decided.order[bits.trailing_zeros() as usize] = o;
                        bits &= bits - 1;
                    }
                }
                return mask;
            }
        }
        // No consistent set (not expected): release every candidate with a negative force.
        let all = mask_of((1 << m) - 1);
        let (a, _) = d.accelerations(all, s.t, &s.x, &s.v);
        units.iter().fold(locked, |acc, &(j, u)| {
            let p = sys.dampers[j].host;
            let sigma = if side[j] == Some(true) { -1.0 } else { 1.0 };
            if sigma * (a[p] + sys.dampers[j].gravity()) >= 0.0 {
                acc | u
            } else {
                acc
            }
        })
    }
}

/// The subsets of `m` units as bit sets, most units first, those of one size in increasing
/// order (each size's sets in turn by Gosper's rule: the next larger number with as many bits).
fn subsets_largest_first(m: usize) -> impl Iterator<Item = usize> {
    let end = 1usize << m;
    (0..=m).rev().flat_map(move |k| {
        let first = (1usize << k) - 1;
        std::iter::successors(Some(first), move |&x| {
            if x == 0 {
                return None;
            }
            let low = x & x.wrapping_neg();
            let r = x + low;
            Some((((r ^ x) >> 2) / low) | r)
        })
        .take_while(move |&x| x < end)
    })
}

/// The Taylor data of a watch at one time (for tests and diagnostics).
pub fn watch_at(d: &Dynamics, seg: &Segment, w: &Watch, t: f64) -> Taylor {
    let pt: Point = seg.point(d, t);
    w.taylor(seg, d, &pt)
}

/// Keeps the earliest root found so far in `best` and the watches that fire there in `hits`:
/// a root within `10 TIME_TOL` of the best joins it, an earlier one replaces it.
#[inline]
fn earliest(best: &mut Option<f64>, hits: &mut Vec<Watch>, r: f64, w: Watch) {
    match *best {
        Some(t) if (r - t).abs() <= 10.0 * TIME_TOL => hits.push(w),
        Some(t) if r > t => {}
        _ => {
            *best = Some(r);
            hits.clear();
            hits.push(w);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::subsets_largest_first;

    #[test]
    fn subsets_come_largest_first_then_in_increasing_order() {
        for m in 0..10 {
            let mut want: Vec<usize> = (0..(1usize << m)).collect();
            want.sort_by_key(|&bits| (std::cmp::Reverse(bits.count_ones()), bits));
            assert_eq!(subsets_largest_first(m).collect::<Vec<_>>(), want, "m = {m}");
        }
    }
}
