//! The simulator's state and its events (docs/model.md section 2): where each bed is, the
//! masses' displacements and velocities, and what happens at an event. A room below the
//! engine and the bed models, which all read it.

use nalgebra::DVector;

use super::system::Dynamics;
use crate::model::Clearance;

/// Where a bed is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bed {
    /// Resting on the container bottom.
    Bottom,
    /// Pressed against the container top.
    Top,
    /// In flight since `t0`, from position `y0` with velocity `u0`.
    Free {
        /// Time the flight started, s.
        t0: f64,
        /// Position then, m.
        y0: f64,
        /// Velocity then, m/s.
        u0: f64,
    },
}

impl Bed {
    /// True when the bed moves with its host.
    pub fn attached(&self) -> bool {
        !matches!(self, Bed::Free { .. })
    }

    /// The end it rests on: `Some(true)` the top, `Some(false)` the bottom, `None` in flight.
    pub fn end(&self) -> Option<bool> {
        match self {
            Bed::Bottom => Some(false),
            Bed::Top => Some(true),
            Bed::Free { .. } => None,
        }
    }

    /// Resting on the top (`top`) or on the bottom.
    pub fn on_end(top: bool) -> Bed {
        if top {
            Bed::Top
        } else {
            Bed::Bottom
        }
    }

    /// Position and velocity of a bed resting on an end of a container of clearance `d` whose
    /// host is at `x` with velocity `v`: the bottom is at the host, the top `d` above it.
    pub fn end_motion(top: bool, x: f64, v: f64, d: Clearance) -> (f64, f64) {
        (if top { x + d.m() } else { x }, v)
    }

    /// The sign of a resting bed's contact force watch (docs/model.md section 2): the
    /// bottom pushes up (+1), the top down (-1).
    pub fn contact_sign(top: bool) -> f64 {
        if top {
            -1.0
        } else {
            1.0
        }
    }

    /// Position and velocity at `t` of a free bed under gravity `g` along its motion.
    pub fn flight(g: f64, t0: f64, y0: f64, u0: f64, t: f64) -> (f64, f64) {
        super::bed::flight(g, t0, y0, u0, t)
    }
}

/// The full state: time, primary masses, beds.
#[derive(Debug, PartialEq)]
pub struct State {
    /// Time, s.
    pub t: f64,
    /// Displacements of the masses from the bare structure's static equilibrium, m.
    pub x: DVector<f64>,
    /// Velocities of the masses, m/s.
    pub v: DVector<f64>,
    /// Each bed's state.
    pub beds: Vec<Bed>,
}

impl Clone for State {
    fn clone(&self) -> State {
        State { t: self.t, x: self.x.clone(), v: self.v.clone(), beds: self.beds.clone() }
    }

    /// A copy into the buffers already held (the simulator keeps the state before each
    /// event this way).
    fn clone_from(&mut self, source: &State) {
        self.t = source.t;
        if self.x.len() == source.x.len() && self.v.len() == source.v.len() {
            self.x.copy_from(&source.x);
            self.v.copy_from(&source.v);
        } else {
            self.x = source.x.clone();
            self.v = source.v.clone();
        }
        self.beds.clone_from(&source.beds);
    }
}

impl State {
    /// The configuration mask: bit j set when bed j is attached.
    pub fn mask(&self) -> usize {
        self.beds.iter().enumerate().filter(|(_, b)| b.attached()).fold(0, |m, (j, _)| m | (1 << j))
    }

    /// At rest in static equilibrium with every bed on its bottom (docs/model.md section 3).
    pub fn at_rest(d: &Dynamics) -> State {
        let n = d.system.dof();
        let all = (1usize << d.system.dampers.len()) - 1;
        let x = d.config(all).modes.offset.clone();
        State { t: 0.0, x, v: DVector::zeros(n), beds: vec![Bed::Bottom; d.system.dampers.len()] }
    }

    /// Bed position and velocity (attached beds move with their host).
    pub fn bed_motion(&self, d: &Dynamics, j: usize) -> (f64, f64) {
        let dm = &d.system.dampers[j];
        match self.beds[j] {
            Bed::Free { t0, y0, u0 } => Bed::flight(dm.gravity(), t0, y0, u0, self.t),
            resting => Bed::end_motion(resting == Bed::Top, self.x[dm.host], self.v[dm.host], dm.clearance),
        }
    }
}

/// What happened at an event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventKind {
    /// The bed left the bottom (`top = false`) or the top.
    LiftOff {
        /// True when it left the top.
        top: bool,
    },
    /// The bed hit the bottom or the top with this relative speed (m/s) and stayed attached
    /// (`attached`) or separated at once.
    Impact {
        /// True on the top.
        top: bool,
        /// Relative speed before the impact, m/s.
        speed: f64,
        /// True when the bed stays on the container.
        attached: bool,
    },
    /// Two grains of a column met (the event's bed is the upper one) at this relative speed,
    /// m/s, and bounced apart or stuck together (`stuck`).
    Collision {
        /// The lower grain (the upper one is the event's bed).
        lower: usize,
        /// Relative speed before the collision, m/s.
        speed: f64,
        /// True when the two move on together.
        stuck: bool,
    },
}

/// What kind of event an event is, without its numbers (speeds, times): what a motion's
/// pattern of events counts. Ordered lift-offs, impacts, collisions; bottom before top.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Mark {
    /// A lift-off from the bottom (`top = false`) or the top.
    LiftOff {
        /// From the top.
        top: bool,
    },
    /// An impact on the bottom or the top, the bed staying on (`attached`) or not.
    Impact {
        /// On the top.
        top: bool,
        /// The bed stays on the container.
        attached: bool,
    },
    /// A grain-grain collision with the grain `lower`, bouncing or sticking.
    Collision {
        /// The lower grain.
        lower: usize,
        /// The two move on together.
        stuck: bool,
    },
}

impl EventKind {
    /// The event's [`Mark`].
    pub fn mark(&self) -> Mark {
        match *self {
            EventKind::LiftOff { top } => Mark::LiftOff { top },
            EventKind::Impact { top, attached, .. } => Mark::Impact { top, attached },
            EventKind::Collision { lower, stuck, .. } => Mark::Collision { lower, stuck },
        }
    }
}

/// How many events of each kind each bed has in a cycle: `(bed, mark, count)`, ordered by
/// bed and mark. What "the same events per cycle" compares.
pub type Pattern = Vec<(usize, Mark, usize)>;

/// One event of one bed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// Time, s.
    pub t: f64,
    /// The bed (a grain of a column, or a single bed).
    pub bed: usize,
    /// What happened.
    pub kind: EventKind,
    /// Kinetic energy lost in the event, J.
    pub loss: f64,
}
