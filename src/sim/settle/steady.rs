//! Steady state under harmonic forcing (docs/model.md section 3): what is asked
//! ([`SteadyOptions`]), what is found ([`Steady`], with the orbit's [`Certificate`] or the
//! reason there is none), and the record of the motion both methods end with. The methods:
//!
//! - `Orbit` (the default, [`super::orbit_search`]): integrate from the start only until the
//!   motion's pattern of events repeats, then solve for the periodic orbit by Newton's method
//!   on the stroboscopic map, and certify it (residual, Floquet multipliers, stability);
//! - `Transient` ([`super::transient`]): integrate until the once-per-period samples stop
//!   changing to a tolerance (its cost and its error both grow as 1/damping), then record;
//! - `Certify`: the transient method, then its settled motion certified as a periodic orbit
//!   where it is one ([`super::orbit_search::certify`]); the record stays the transient's.
//!   A column of grains has certified orbits only this way.

use num_complex::Complex64;

use nalgebra::DVector;

use super::statistic::{Measure, Measured, Motion};
use crate::sim::motion::engine::{Bed, Engine, Event, Observer, State, Stop};
pub use crate::sim::motion::observe::Observe;
use crate::sim::motion::observe::{stored_energy, Energy, Extrema};
use crate::sim::motion::peaks::{PeakValues, Peaks};
use crate::sim::motion::segment::{Segment, Watch};
use crate::sim::motion::system::Dynamics;
use crate::sim::orbits::strobe::Strobe;

/// How a steady state is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SteadyMethod {
    /// Solve for the periodic orbit once the motion's pattern is established.
    Orbit,
    /// Wait for the transient to die out.
    Transient,
    /// Wait for the transient to die out, then certify the settled motion as a periodic orbit
    /// where it is one ([`super::orbit_search::certify`]): the record is the transient
    /// method's, the certificate is added. The way to certified orbits of a column of grains,
    /// whose Jacobian comes from central differences.
    Certify,
}

impl SteadyMethod {
    /// The method's name in experiment files and tables.
    pub fn name(&self) -> &'static str {
        match self {
            SteadyMethod::Orbit => "orbit",
            SteadyMethod::Transient => "transient",
            SteadyMethod::Certify => "certify",
        }
    }
}

/// How a steady state is sought.
#[derive(Clone, Copy, PartialEq)]
pub struct SteadyOptions {
    /// How the steady state is found.
    pub method: SteadyMethod,
    /// Transient: relative change of the once-per-period state that counts as settled.
    pub tol: f64,
    /// Transient: settled for this many periods in a row. Orbit: the motion's pattern of
    /// events has repeated this many times.
    pub consecutive: usize,
    /// Periods simulated before the motion is judged (both methods).
    pub min_periods: usize,
    /// Most periods simulated before giving up (both methods).
    pub max_periods: usize,
    /// Transient: periods recorded once settled (rounded up to a multiple of the motion's
    /// period). Orbit: one orbit is recorded (it is exact).
    pub record_periods: usize,
    /// Orbit: Newton's method stops when the fixed-point residual, relative to the amplitude
    /// scale, is below this.
    pub orbit_tol: f64,
    /// Orbit: most Newton iterations per attempt.
    pub max_newton: usize,
    /// Longest subharmonic recognised, in forcing periods.
    pub max_subharmonic: usize,
    /// Also integrate the energy balance over the recorded periods.
    pub energy: bool,
    /// Orbit: once this many attempts in a row have found only an unstable orbit whose largest
    /// multipliers are a complex pair just outside the unit circle (modulus at most
    /// [`TORUS_MARGIN`] above 1), the motion is taken as quasi-periodic, on a torus around that
    /// orbit, once it has also run for `3 / (modulus - 1)` orbits since the first of those
    /// attempts (a motion still spiralling out from the orbit would have grown e^3-fold): it
    /// is run on in windows of one turn ([`torus_window`]) until two in a row give the same
    /// amplitudes to [`TORUS_TOL`], and two turns are recorded. 0: never (spend `max_periods`).
    pub torus_attempts: usize,
    /// Continuation sweeps: where the previous point is a certified orbit, first solve for the
    /// orbit at the new frequency by Newton's method from the previous orbit (same section
    /// phase, period and bed places), and accept it when it is stable and has the same events
    /// per cycle; otherwise (a fold, a bifurcation, a change of events) run the transient
    /// search from the previous final state as without this option.
    pub follow: bool,
    /// The masses whose amplitudes are measured (default: all; the others' are NaN). The
    /// torus test compares those only.
    pub observe: Observe,
    /// How a point with no certified orbit is classified and measured
    /// ([`super::irregular`]): record length and the interval's tolerance.
    pub measure: Measure,
    /// Whether the record also finds each storey's drift and each floor's absolute
    /// acceleration ([`crate::sim::motion::peaks`]; [`Steady::peaks`]).
    pub peaks: bool,
}

impl std::fmt::Debug for SteadyOptions {
    /// The derived form; `observe` only when it is not every mass (a stored design answer
    /// fingerprints this text: those stored before the field existed stay valid).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("SteadyOptions");
        d.field("method", &self.method)
            .field("tol", &self.tol)
            .field("consecutive", &self.consecutive)
            .field("min_periods", &self.min_periods)
            .field("max_periods", &self.max_periods)
            .field("record_periods", &self.record_periods)
            .field("orbit_tol", &self.orbit_tol)
            .field("max_newton", &self.max_newton)
            .field("max_subharmonic", &self.max_subharmonic)
            .field("energy", &self.energy)
            .field("torus_attempts", &self.torus_attempts)
            .field("follow", &self.follow);
        if self.peaks {
            d.field("peaks", &self.peaks);
        }
        if !self.observe.is_all() {
            d.field("observe", &self.observe);
        }
        // Only when it is not the default (the fingerprints of stored answers, which the report
        // evaluates again with the measurement, stay those of their files).
        if self.measure != Measure::default() {
            d.field("measure", &self.measure);
        }
        d.finish()
    }
}

impl Default for SteadyOptions {
    fn default() -> Self {
        // The independent solver's settings (reference/independent-solver/PROVENANCE.md).
        SteadyOptions {
            method: SteadyMethod::Orbit,
            tol: 1e-7,
            consecutive: 5,
            min_periods: 20,
            max_periods: 1500,
            record_periods: 10,
            max_subharmonic: 8,
            energy: false,
            torus_attempts: 4,
            orbit_tol: 1e-11,
            max_newton: 10,
            follow: false,
            observe: Observe::ALL,
            measure: Measure::default(),
            peaks: false,
        }
    }
}

/// How far outside the unit circle a complex pair of multipliers may lie for the motion
/// around the orbit to be taken as a torus ([`SteadyOptions::torus_attempts`]).
pub const TORUS_MARGIN: f64 = 0.05;

/// Two windows of one turn of a torus in a row whose amplitudes agree to this (relative to
/// the largest) mean the motion is on the torus ([`SteadyOptions::torus_attempts`]).
pub const TORUS_TOL: f64 = 1e-2;

/// Forcing periods of the long record of a motion that never settles
/// ([`super::long_record`]).
pub const LONG_RECORD_PERIODS: usize = 200;

/// The long record's second half agrees with the whole record to this, relative to the
/// largest amplitude: the record's amplitude has converged.
pub const LONG_RECORD_TOL: f64 = 1e-2;

/// Longest window of a torus, forcing periods.
pub const TORUS_WINDOW_MAX: usize = 200;

/// One turn of a torus whose orbit has `p` periods and whose leading multipliers turn by
/// `angle` rad per orbit, in forcing periods: `ceil(2 pi / angle) p`, at least `record_periods`,
/// at most [`TORUS_WINDOW_MAX`].
pub fn torus_window(angle: f64, p: usize, record_periods: usize) -> usize {
    let turn = (2.0 * std::f64::consts::PI / angle.abs()).ceil().min(TORUS_WINDOW_MAX as f64) as usize;
    (turn * p).clamp(record_periods.min(TORUS_WINDOW_MAX), TORUS_WINDOW_MAX)
}

/// Energy terms over the recorded periods, J.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyBalance {
    /// Work of the force, J.
    pub work: f64,
    /// Energy dissipated by the structure's damping, J.
    pub viscous: f64,
    /// Energy lost in impacts, J.
    pub impact: f64,
    /// Stored energy at the end minus at the start of the record.
    pub stored_change: f64,
}

impl EnergyBalance {
    /// `|work - viscous - impact - stored_change| / |work|`.
    pub fn relative_residual(&self) -> f64 {
        (self.work - self.viscous - self.impact - self.stored_change).abs() / self.work.abs().max(f64::MIN_POSITIVE)
    }
}

/// What certifies a steady state found as a periodic orbit.
#[derive(Debug, Clone, PartialEq)]
pub struct Certificate {
    /// Max-norm of `P(u) - u` on the section, relative to the amplitude scale.
    pub residual: f64,
    /// Floquet multipliers: eigenvalues of the Jacobian of the map at the orbit, largest
    /// modulus first.
    pub multipliers: Vec<Complex64>,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
    /// No graze and no simultaneous impacts on the orbit (its map is smooth there).
    pub smooth: bool,
    /// Newton iterations of the successful attempt, and attempts made.
    pub iterations: usize,
    /// Attempts made.
    pub attempts: usize,
    /// How fast Newton converged on this orbit ([`crate::sim::orbits::periodic::quadratic_constant`] of
    /// its residuals): the next followed point predicts its last evaluation from it.
    pub quadratic: f64,
    /// Forcing phase of the section, rad.
    pub phase: f64,
    /// The orbit's events per cycle, counted per bed and kind (what a followed point must
    /// keep, [`SteadyOptions::follow`]).
    pub pattern: crate::sim::motion::state::Pattern,
    /// The state on the orbit at the section (where a followed point starts from).
    pub section: State,
}

impl Certificate {
    /// The largest multiplier modulus.
    pub fn spectral_radius(&self) -> f64 {
        self.multipliers.iter().map(|z| z.norm()).fold(0.0, f64::max)
    }
}

/// Why a point has no steady state.
#[derive(Debug, Clone, PartialEq)]
pub enum NoSteady {
    /// The motion did not settle (transient) or its pattern of events never repeated long
    /// enough to solve for an orbit (orbit) within this many periods.
    Budget {
        /// Forcing periods simulated.
        periods: usize,
    },
    /// Every orbit found with the motion's pattern was unstable (chaotic or quasi-periodic
    /// motion near it): the largest multiplier modulus of the last one.
    Unstable {
        /// The largest multiplier modulus of the last orbit.
        radius: f64,
    },
    /// Newton's method found no orbit with the motion's pattern: the last reason.
    NoOrbit(String),
    /// Quasi-periodic motion recognised early ([`SteadyOptions::torus_attempts`]): at
    /// `attempts` attempts in a row the orbit with the motion's events was unstable through a
    /// complex pair of multipliers of modulus `radius` (just above 1) and argument `angle`
    /// (rad); after `periods` periods two windows of one turn gave the same amplitudes.
    Torus {
        /// Modulus of the complex pair.
        radius: f64,
        /// Their argument, rad.
        angle: f64,
        /// Attempts in a row that found it.
        attempts: usize,
        /// Forcing periods simulated.
        periods: usize,
    },
    /// Not periodic after `after` periods (a bed with restitution or a column of grains): the
    /// amplitudes are those of a record of `periods` periods, whose second half differs from
    /// the whole by `spread` (relative to the largest amplitude; converged when at most
    /// [`LONG_RECORD_TOL`]).
    Aperiodic {
        /// Periods of the long record.
        periods: usize,
        /// Its second half against the whole, relative to the largest amplitude.
        spread: f64,
        /// Periods simulated before the record.
        after: usize,
    },
}

impl std::fmt::Display for NoSteady {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoSteady::Budget { periods } => write!(f, "no steady state within {periods} periods"),
            NoSteady::Unstable { radius } => {
                write!(f, "only unstable orbits (largest multiplier {radius:.4}): chaotic or quasi-periodic motion")
            }
            NoSteady::NoOrbit(why) => write!(f, "no periodic orbit found: {why}"),
            NoSteady::Torus { radius, angle, attempts, periods } => write!(
                f,
                "quasi-periodic (a torus): complex multipliers of modulus {radius:.4} at +-{angle:.3} rad at {attempts} attempts in a row; amplitudes of two turns agree after {periods} periods"
            ),
            NoSteady::Aperiodic { periods, spread, after } => write!(
                f,
                "aperiodic after {after} periods: amplitude of a {periods}-period record, its second half within {:.2} % ({})",
                100.0 * spread,
                if *spread <= LONG_RECORD_TOL { "converged" } else { "NOT converged" }
            ),
        }
    }
}

impl std::error::Error for NoSteady {}

/// The steady state of one forcing frequency.
#[derive(Debug, Clone)]
pub struct Steady {
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// How it was found.
    pub method: SteadyMethod,
    /// Settled (transient) or a stable orbit found (orbit) within `max_periods`.
    pub converged: bool,
    /// Orbit method: the orbit's certificate (when one was found).
    pub certificate: Option<Certificate>,
    /// Why there is no steady state (when `converged` is false and no chatter stopped it).
    pub failure: Option<NoSteady>,
    /// Periods simulated before recording.
    pub transient_periods: usize,
    /// Period of the motion in forcing periods (1, or a subharmonic); 0 when none was found.
    pub period: usize,
    /// Half peak-to-peak displacement of each mass, m.
    pub amplitude: Vec<f64>,
    /// Per bed, per forcing period: bottom impacts, top impacts, lift-offs.
    pub bottom_impacts: Vec<f64>,
    /// Per bed, per forcing period: top impacts.
    pub top_impacts: Vec<f64>,
    /// Per bed, per forcing period: lift-offs.
    pub liftoffs: Vec<f64>,
    /// Highest flight of each bed above its bottom over the record, m.
    pub max_flight: Vec<f64>,
    /// Periods recorded.
    pub recorded_periods: usize,
    /// Energy terms over the record (when asked for).
    pub energy: Option<EnergyBalance>,
    /// Set when the simulation stopped early (chatter).
    pub stop: Option<Stop>,
    /// The state at the end of the record (to continue a sweep from).
    pub final_state: State,
    /// What the motion is ([`Motion`]).
    pub motion: Motion,
    /// A point with no certified orbit: its statistic, interval and Lyapunov exponent
    /// ([`super::irregular`]); its `amplitude` is then the statistic.
    pub measured: Option<Measured>,
    /// The storeys' drifts and the floors' absolute accelerations over the record, when
    /// [`SteadyOptions::peaks`] asks for them (a point with no certified orbit: over its
    /// whole measured record, so the largest amplitude there, not the statistic).
    pub peaks: Option<PeakValues>,
}

impl Steady {
    /// The section through a steady state found as an orbit (at its certificate's phase).
    pub fn section(&self, d: &Dynamics) -> Option<(Strobe, DVector<f64>)> {
        let s = self.section_state()?;
        let length = self.amplitude.iter().copied().fold(0.0, f64::max).max(1e-12);
        Some(Strobe::through(d, s, self.period, length))
    }

    /// The state on the orbit at its certificate's section phase.
    pub fn section_state(&self) -> Option<&State> {
        self.certificate.as_ref().map(|c| &c.section)
    }
}

/// The size of the motion in a state: the largest `hypot(x_i - x_rest,i, v_i / omega)` (for
/// harmonic motion, the amplitude), with a floor that keeps it positive.
pub fn amplitude_scale(d: &Dynamics, s: &State) -> f64 {
    let all = (1usize << d.system.dampers.len()) - 1;
    let rest = &d.config(all).modes.offset;
    (0..d.system.dof()).map(|i| (s.x[i] - rest[i]).hypot(s.v[i] / d.omega)).fold(1e-15, f64::max)
}

/// How a search for a steady state ended, before its record.
pub(crate) struct Outcome {
    pub method: SteadyMethod,
    pub converged: bool,
    pub certificate: Option<Certificate>,
    pub failure: Option<NoSteady>,
    pub transient_periods: usize,
    pub period: usize,
    /// Forcing periods to record.
    pub record: usize,
    pub stop: Option<Stop>,
    /// Where the search stopped early (`stop`): the state at the start of the last whole
    /// forcing period it ran, and that period's end time. The point's record is that period.
    pub last_whole: Option<(State, f64)>,
}

/// What a steady state's record observes: the extrema (amplitudes, impacts, flights) and,
/// when asked for, the energy terms. It can ride along any run over the record's span (a
/// Newton evaluation of the orbit it records: the same motion, so the same numbers).
pub(crate) struct Recorder {
    ext: Extrema,
    energy: Option<Energy>,
    peaks: Option<Peaks>,
    /// The stored energy at the record's start.
    e0: f64,
}

impl Recorder {
    /// A record starting at `s`, of the masses and the energy `opts` asks for.
    pub(crate) fn new(d: &Dynamics, s: &State, opts: &SteadyOptions) -> Recorder {
        let energy_on = opts.energy;
        let ext = Extrema::observing(d.system.dof(), d.system.dampers.len(), opts.observe);
        let energy = energy_on.then(Energy::default);
        let peaks = opts.peaks.then(|| peaks_of(d));
        Recorder { ext, energy, peaks, e0: if energy_on { stored_energy(d, s) } else { 0.0 } }
    }

    /// The steady state from this record, which ended in `s` (or stopped with `stop`).
    pub(crate) fn steady(self, d: &Dynamics, s: State, stop: Option<Stop>, o: Outcome) -> Steady {
        let stop = o.stop.or(stop);
        let motion = match (&stop, &o.failure) {
            (Some(_), _) => Motion::Chatter,
            (None, _) if o.converged => Motion::Periodic,
            (None, Some(NoSteady::Torus { .. })) => Motion::QuasiPeriodic,
            (None, Some(NoSteady::Aperiodic { .. })) => Motion::Aperiodic,
            (None, _) => Motion::Transient,
        };
        let ext = self.ext;
        let record = o.record.max(1);
        let per = |v: &[usize]| v.iter().map(|&c| c as f64 / record as f64).collect::<Vec<_>>();
        Steady {
            omega: d.omega,
            method: o.method,
            converged: o.converged && stop.is_none(),
            certificate: o.certificate,
            failure: o.failure,
            transient_periods: o.transient_periods,
            period: o.period,
            amplitude: ext.amplitudes(),
            bottom_impacts: per(&ext.bottom_impacts),
            top_impacts: per(&ext.top_impacts),
            liftoffs: per(&ext.liftoffs),
            max_flight: ext.max_flight.clone(),
            recorded_periods: o.record,
            energy: self.energy.map(|e| EnergyBalance {
                work: e.work,
                viscous: e.viscous,
                impact: e.impact,
                stored_change: stored_energy(d, &s) - self.e0,
            }),
            stop,
            final_state: s,
            motion,
            measured: None,
            peaks: self.peaks.map(|p| p.values()),
        }
    }
}

/// An empty [`Peaks`] of a system's physical coordinates (a reduced model's points), with
/// storeys when its structure is a chain.
pub(crate) fn peaks_of(d: &Dynamics) -> Peaks {
    let s = &d.system.structure;
    Peaks::new(s.physical(), s.is_chain())
}

impl Observer for Recorder {
    fn segment(&mut self, d: &Dynamics, seg: &Segment, beds: &[Bed], t_a: f64, t_b: f64) {
        self.ext.segment(d, seg, beds, t_a, t_b);
        self.energy.segment(d, seg, beds, t_a, t_b);
        self.peaks.segment(d, seg, beds, t_a, t_b);
    }
    fn event(&mut self, ev: &Event, after: &State) {
        self.ext.event(ev, after);
        self.energy.event(ev, after);
    }
    fn wants_jumps(&self) -> bool {
        self.ext.wants_jumps() || self.energy.wants_jumps()
    }
    fn jump(&mut self, d: &Dynamics, before: &State, after: &State, hits: &[Watch]) {
        self.ext.jump(d, before, after, hits);
        self.energy.jump(d, before, after, hits);
    }
}

/// Runs `s` on to the next whole forcing period, where a continuation sweep's next point
/// starts ([`super::sweep::restart`]).
pub(crate) fn run_to_whole_period(d: &Dynamics, s: &mut State) -> Result<(), Stop> {
    let period = 2.0 * std::f64::consts::PI / d.omega;
    let whole = (s.t / period).ceil() * period;
    Engine::new(d).advance(s, whole, &mut crate::sim::motion::engine::Quiet)
}

/// The start of the forcing period a search is running and the last whole period it
/// completed, with its end time: what a point stopped early records ([`finish`]). The states
/// are copied into kept buffers (no allocation after the first period).
pub(crate) struct WholePeriods {
    current: State,
    last: Option<(State, f64)>,
}

impl WholePeriods {
    /// Before the first period, from `s`.
    pub(crate) fn new(s: &State) -> WholePeriods {
        WholePeriods { current: s.clone(), last: None }
    }

    /// A period starts at `s`.
    pub(crate) fn begin(&mut self, s: &State) {
        self.current.clone_from(s);
    }

    /// The period begun last ended, at `end`.
    pub(crate) fn completed(&mut self, end: f64) {
        match &mut self.last {
            Some((l, t)) => {
                std::mem::swap(l, &mut self.current);
                *t = end;
            }
            None => self.last = Some((self.current.clone(), end)),
        }
    }

    /// The last whole period, for [`Outcome::last_whole`] where the search `stopped`.
    pub(crate) fn last(self, stopped: bool) -> Option<(State, f64)> {
        self.last.filter(|_| stopped)
    }
}

/// Records the motion from `s` to `t_end` and assembles the steady state. A search that
/// stopped early (chatter) records instead the last whole period it ran, where it has one
/// (run again from its start: the same events, so no stop), and keeps `s`, where it stopped,
/// as its final state (a continuation sweep's next point starts there: on the reduced plate
/// starting from the end of the recorded period instead, or from the start of a first period
/// that stopped, repeated the same burst at every later frequency); with none its amplitudes
/// are NaN (not measured).
pub(crate) fn finish(d: &Dynamics, mut s: State, t_end: f64, opts: &SteadyOptions, mut o: Outcome) -> Steady {
    if o.stop.is_some() {
        if let Some((mut from, end)) = o.last_whole.take() {
            let mut rec = Recorder::new(d, &from, opts);
            let again = Engine::new(d).advance(&mut from, end, &mut rec).err();
            o.record = 1;
            return Steady { final_state: s, ..rec.steady(d, from, again, o) };
        }
    }
    let mut rec = Recorder::new(d, &s, opts);
    let stop = if o.stop.is_none() { Engine::new(d).advance(&mut s, t_end, &mut rec).err() } else { None };
    rec.steady(d, s, stop, o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::System;

    #[test]
    fn a_point_stopped_early_records_its_last_whole_period_or_is_not_measured() {
        let structure =
            Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
        let sys = System::plastic(structure, vec![Damper::new(1, 0.07, Clearance::from_m(5e-4))], 0, 2.6);
        let d = Dynamics::new(&sys, 2.0 * std::f64::consts::PI * 50.0).unwrap();
        let period = 2.0 * std::f64::consts::PI / d.omega;
        let start = State::at_rest(&d);
        // A stand-in for a run stopped in the period after the one from `start`.
        let mut stopped = start.clone();
        Engine::new(&d).advance(&mut stopped, 1.5 * period, &mut crate::sim::Quiet).unwrap();
        let outcome = |last_whole| Outcome {
            method: SteadyMethod::Orbit,
            converged: false,
            certificate: None,
            failure: None,
            transient_periods: 1,
            period: 0,
            record: 10,
            stop: Some(Stop::Chatter { t: stopped.t, events: 2001 }),
            last_whole,
        };
        let st =
            finish(&d, stopped.clone(), f64::NAN, &SteadyOptions::default(), outcome(Some((start.clone(), period))));
        // The same numbers as a record of that period.
        let mut rec = Recorder::new(&d, &start, &SteadyOptions::default());
        let mut s = start.clone();
        Engine::new(&d).advance(&mut s, period, &mut rec).unwrap();
        let direct = rec.steady(&d, s, None, outcome(None));
        assert_eq!(st.amplitude, direct.amplitude);
        assert!(st.amplitude.iter().all(|a| a.is_finite() && *a > 0.0), "{:?}", st.amplitude);
        assert_eq!((st.recorded_periods, st.converged), (1, false));
        assert!(st.stop.is_some());
        assert_eq!(st.final_state, stopped);
        // Without a whole period: not measured.
        let none = finish(&d, stopped.clone(), f64::NAN, &SteadyOptions::default(), outcome(None));
        assert!(none.amplitude.iter().all(|a| a.is_nan()));
    }
}
