//! The steady state as a certified periodic orbit (docs/simulator.md, "Steady states").
//!
//! From the start state the motion is integrated one forcing period at a time, keeping each
//! period's events. Once the sequence of events has repeated with some period `p` (the
//! smallest, up to `max_subharmonic`) for `consecutive` cycles, a stroboscopic section is put
//! at the forcing phase farthest from every event of the last cycle, and Newton's method
//! solves for the fixed point of the `p`-period map from the current state. The orbit is
//! accepted when it is stable and has the same events per cycle as the motion that led to it
//! (so it is the motion's attractor, not another orbit nearby). Otherwise the transient goes
//! on and the search tries again later (and, after an unstable `p`-orbit, also with `2p`),
//! until `max_periods` are spent: then the point is flagged with the reason.

use std::collections::VecDeque;
use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::steady::{
    amplitude_scale, finish, run_to_whole_period, torus_window, Certificate, NoSteady, Outcome, Recorder, Steady,
    SteadyMethod, SteadyOptions, WholePeriods, TORUS_MARGIN, TORUS_TOL,
};
use crate::sim::motion::engine::{Engine, Event, Quiet, State};
use crate::sim::motion::observe::{EventLog, Extrema};
use crate::sim::motion::state::{Mark, Pattern};
use crate::sim::motion::system::Dynamics;
use crate::sim::orbits::periodic::{
    quadratic_constant, signature, solve, solve_with, NewtonOptions, Orbit, OrbitError, Section,
};
use crate::sim::orbits::strobe::{quiet_phase, Rest, Strobe};

/// One forcing period of the transient.
struct Period {
    events: Vec<Event>,
    /// Its events counted per bed and kind.
    sig: Pattern,
    /// The amplitude scale at its end.
    scale: f64,
}

/// The smallest `p` for which the last `reps` cycles of `p` periods have the same events (in
/// number, per bed and kind: their order can change while the timings still drift).
fn pattern(history: &VecDeque<Period>, max_p: usize, reps: usize) -> Option<usize> {
    (1..=max_p).find(|&p| history.len() >= reps * p && (p..reps * p).all(|i| history[i].sig == history[i - p].sig))
}

/// Counts of each event kind per bed: what "the same events per cycle" compares.
fn counts(events: &[Event]) -> Pattern {
    let mut sig = signature(events);
    sig.sort_unstable();
    let mut out: Pattern = Vec::new();
    for (bed, kind) in sig {
        match out.last_mut() {
            Some((b, k, c)) if *b == bed && *k == kind => *c += 1,
            _ => out.push((bed, kind, 1)),
        }
    }
    out
}

/// A failed attempt.
enum Miss {
    /// The orbit is unstable; `lead` is its multiplier of largest modulus.
    Unstable {
        radius: f64,
        lead: Complex64,
    },
    /// Newton's iterates went round a cycle ([`OrbitError::Cycling`]).
    Cycling(String),
    Other(String),
}

/// The argument of an unstable orbit's leading multiplier when it and its conjugate lie just
/// outside the unit circle (a torus is born there: a Neimark-Sacker bifurcation), else `None`.
fn torus_angle(radius: f64, lead: Complex64) -> Option<f64> {
    let angle = lead.arg().abs();
    (radius > 1.0 && radius <= 1.0 + TORUS_MARGIN && angle > 1e-3 && angle < PI - 1e-3).then_some(angle)
}

/// [`attempt`], and where it finds the p-orbit unstable, the 2p-orbit with the same events
/// (after a period doubling the events per period can stay the same): an unstable p-orbit
/// may have a stable 2p-orbit beside it. So where Newton on the p-map went round a cycle
/// ([`OrbitError::Cycling`]): a motion near a 2p-orbit whose events per period repeat sends
/// Newton's p-steps round (the size family's 32-mass chain at 47.9 Hz). There the motion is
/// still on its way, and its 2p-orbit may have a graze more (a short flight that grows in),
/// so that orbit is taken as a followed one is ([`accept`]): with the motion's events twice,
/// or other events within [`FOLLOW_NEAR`] of the motion.
fn attempt_or_doubled(
    d: &Dynamics,
    at: &State,
    p: usize,
    length: f64,
    wanted: &[(usize, Mark, usize)],
    opts: &SteadyOptions,
) -> Result<(Strobe, Orbit, Option<Recorded>), Miss> {
    let result = attempt(d, at, p, length, wanted, 0.0, opts);
    let near = match &result {
        Err(Miss::Unstable { .. }) => 0.0,
        Err(Miss::Cycling(_)) => FOLLOW_NEAR,
        _ => return result,
    };
    if 2 * p <= opts.max_subharmonic {
        let doubled: Pattern = wanted.iter().map(|&(b, k, c)| (b, k, 2 * c)).collect();
        if let Ok(found) = attempt(d, at, 2 * p, length, &doubled, near, opts) {
            return Ok(found);
        }
    }
    result
}

/// One attempt: the section through the state `at`, Newton on the `p`-period map, and the
/// checks that make the orbit the motion's own: stable, with the motion's events per cycle
/// (`wanted`), or other events within `near` of the motion on the section (0: never). With
/// the orbit, its record when Newton's final evaluation was recorded and the orbit's period
/// is `p`.
fn attempt(
    d: &Dynamics,
    at: &State,
    p: usize,
    length: f64,
    wanted: &[(usize, Mark, usize)],
    near: f64,
    opts: &SteadyOptions,
) -> Result<(Strobe, Orbit, Option<Recorded>), Miss> {
    let (strobe, u0) = Strobe::through(d, at, p, length);
    let newton = NewtonOptions { tol: opts.orbit_tol, max_iter: opts.max_newton, ..NewtonOptions::default() };
    let (orbit, recorded) = solve_recorded(&strobe, d, &u0, &newton, opts).map_err(|e| match e {
        OrbitError::Cycling { .. } => Miss::Cycling(e.to_string()),
        _ => Miss::Other(e.to_string()),
    })?;
    if !orbit.stable {
        let lead = orbit.multipliers.first().copied().unwrap_or_default();
        return Err(Miss::Unstable { radius: orbit.spectral_radius(), lead });
    }
    if counts(&orbit.events) != wanted && (&orbit.u - &u0).amax() > near {
        return Err(Miss::Other("the orbit found has other events than the motion".into()));
    }
    let (short, orbit) = minimal(d, strobe, orbit, &newton);
    let recorded = recorded.filter(|_| short.periods == p);
    Ok((short, orbit, recorded))
}

/// A record of one orbit taken beside Newton's final evaluation: the observers and the state
/// at the record's end.
type Recorded = (Recorder, State);

/// Newton's method on `strobe` whose evaluations that are likely the last also record the
/// motion ([`solve_with`]): when one is, the orbit's record needs no run of its own.
fn solve_recorded(
    strobe: &Strobe,
    d: &Dynamics,
    u0: &DVector<f64>,
    newton: &NewtonOptions,
    opts: &SteadyOptions,
) -> Result<(Orbit, Option<Recorded>), OrbitError> {
    solve_with(strobe, d, u0, newton, |u, likely_last| {
        if !likely_last {
            return Ok((strobe.map(d, u)?, None));
        }
        let mut rec = Recorder::new(d, &strobe.state(d, u), opts);
        let (ret, end) = strobe.map_observed(d, u, &mut rec)?;
        Ok((ret, Some((rec, end))))
    })
}

/// The orbit on the map of its least period: a `p`-orbit that closes after a divisor `q` of
/// `p` (the events of a period-1 motion can look period-`p` when one of them jitters across
/// the sampling instant during the transient) is solved again on the `q`-period map.
fn minimal(d: &Dynamics, strobe: Strobe, orbit: Orbit, newton: &NewtonOptions) -> (Strobe, Orbit) {
    let p = strobe.periods;
    for q in (1..p).filter(|q| p % q == 0) {
        let short = Strobe { periods: q, ..strobe.clone() };
        let Ok(ret) = short.map(d, &orbit.u) else { continue };
        if (&ret.image - &orbit.u).amax() > 1e-6 {
            continue;
        }
        if let Ok(o) = solve(&short, d, &orbit.u, newton) {
            if o.stable {
                return (short, o);
            }
        }
    }
    (strobe, orbit)
}

/// Attempts in a row that found a torus ([`torus_angle`]): how many, the periods simulated at
/// the first of them, the last one's leading multiplier (modulus, argument) and its orbit's
/// periods.
#[derive(Debug, Clone, Copy, Default)]
struct TorusRun {
    attempts: usize,
    first: usize,
    radius: f64,
    angle: f64,
    p: usize,
}

impl TorusRun {
    /// Whether, after `simulated` periods, a motion still spiralling out from the orbit would
    /// show: its distance from the orbit grows by e every `1 / (radius - 1)` orbits, so three
    /// such times since the first attempt.
    fn grown(&self, simulated: usize) -> bool {
        simulated as f64 >= self.first as f64 + 3.0 * self.p as f64 / (self.radius - 1.0)
    }
}

/// Runs the motion on from `s` in windows of `w` periods until two windows in a row give the
/// same amplitudes to [`TORUS_TOL`] (relative to the largest): the motion has reached its
/// torus, it is no longer spiralling out from the unstable orbit. `false` when the budget of
/// `max_periods` ends first.
fn onto_torus(
    engine: &Engine,
    s: &mut State,
    w: usize,
    simulated: &mut usize,
    opts: &SteadyOptions,
) -> Result<bool, crate::sim::motion::engine::Stop> {
    let d = engine.d;
    let period = 2.0 * PI / d.omega;
    let mut last: Option<Vec<f64>> = None;
    while *simulated + w <= opts.max_periods {
        crate::sim::motion::cancel::check();
        let mut ext = Extrema::observing(d.system.dof(), d.system.dampers.len(), opts.observe);
        engine.advance(s, s.t + w as f64 * period, &mut ext)?;
        *simulated += w;
        let amp = ext.amplitudes();
        if let Some(prev) = &last {
            // The masses measured (a mass not followed has no amplitude).
            let seen = || amp.iter().zip(prev).enumerate().filter(|(i, _)| opts.observe.contains(*i)).map(|(_, p)| p);
            let scale = seen().map(|(a, _)| *a).fold(f64::MIN_POSITIVE, f64::max);
            if seen().all(|(a, b)| (a - b).abs() <= TORUS_TOL * scale) {
                return Ok(true);
            }
        }
        last = Some(amp);
    }
    Ok(false)
}

/// Runs from `start` to a certified periodic orbit and records one orbit of it.
pub fn orbit_steady(d: &Dynamics, start: State, opts: &SteadyOptions) -> Steady {
    let engine = Engine::new(d);
    let period = 2.0 * PI / d.omega;
    let mut s = start;
    let mut k = (s.t / period).ceil() as usize;
    let reps = opts.consecutive.max(2);
    let keep = opts.max_subharmonic * reps;
    let mut history: VecDeque<Period> = VecDeque::with_capacity(keep + 1);
    let mut simulated = 0;
    let mut next_try = opts.min_periods;
    let mut attempts = 0;
    let mut failure = None;
    let mut stop = None;
    let mut torus = TorusRun::default();
    let mut record_periods = opts.record_periods;
    let mut whole = WholePeriods::new(&s);
    while simulated < opts.max_periods {
        crate::sim::motion::cancel::check();
        let mut log = EventLog::default();
        whole.begin(&s);
        let end = k as f64 * period;
        if let Err(e) = engine.advance(&mut s, end, &mut log) {
            stop = Some(e);
            break;
        }
        whole.completed(end);
        let sig = counts(&log.0);
        history.push_front(Period { events: log.0, sig, scale: amplitude_scale(d, &s) });
        history.truncate(keep);
        simulated += 1;
        k += 1;
        if simulated < next_try {
            continue;
        }
        let Some(p) = pattern(&history, opts.max_subharmonic, reps) else {
            continue;
        };
        attempts += 1;
        // The last cycle, oldest period first, and the section at its quietest phase.
        let cycle: Vec<Event> = history.iter().take(p).rev().flat_map(|h| h.events.iter().copied()).collect();
        let t_start = s.t - p as f64 * period;
        let length = history.iter().take(p).map(|h| h.scale).fold(0.0, f64::max);
        let wanted = counts(&cycle);
        let mut at = s.clone();
        let phase = quiet_phase(&cycle, t_start, d.omega, p);
        if let Err(e) = engine.advance(&mut at, s.t + phase / d.omega, &mut crate::sim::motion::engine::Quiet) {
            stop = Some(e);
            break;
        }
        match attempt_or_doubled(d, &at, p, length, &wanted, opts) {
            Ok((strobe, orbit, recorded)) => {
                return on_whole_period(d, record(d, &strobe, &orbit, simulated, attempts, opts, recorded))
            }
            Err(Miss::Unstable { radius, lead }) => {
                failure = Some(NoSteady::Unstable { radius });
                torus = match torus_angle(radius, lead) {
                    Some(angle) => TorusRun {
                        attempts: torus.attempts + 1,
                        first: if torus.attempts > 0 { torus.first } else { simulated },
                        radius,
                        angle,
                        p,
                    },
                    None => TorusRun::default(),
                };
            }
            Err(Miss::Other(why) | Miss::Cycling(why)) => {
                failure = Some(NoSteady::NoOrbit(why));
                torus = TorusRun::default();
            }
        }
        if opts.torus_attempts > 0 && torus.attempts >= opts.torus_attempts && torus.grown(simulated) {
            let TorusRun { attempts: run, radius, angle, p, .. } = torus;
            let w = torus_window(angle, p, opts.record_periods);
            match onto_torus(&engine, &mut s, w, &mut simulated, opts) {
                Err(e) => {
                    stop = Some(e);
                    break;
                }
                Ok(true) => {
                    failure = Some(NoSteady::Torus { radius, angle, attempts: run, periods: simulated });
                    record_periods = 2 * w;
                    break;
                }
                // The amplitudes never settled within the budget: spent like any other point.
                Ok(false) => break,
            }
        }
        next_try = simulated + (reps * p).max(simulated / 2);
    }
    let failure = if stop.is_some() {
        None
    } else {
        match failure {
            Some(f @ (NoSteady::Unstable { .. } | NoSteady::Torus { .. })) => Some(f),
            _ => Some(NoSteady::Budget { periods: simulated }),
        }
    };
    let outcome = Outcome {
        method: SteadyMethod::Orbit,
        converged: false,
        certificate: None,
        failure,
        transient_periods: simulated,
        period: 0,
        record: record_periods,
        last_whole: whole.last(stop.is_some()),
        stop,
    };
    // An unsettled point still reports what its motion does over the next periods.
    let t_end = s.t + record_periods as f64 * period;
    finish(d, s, t_end, opts, outcome)
}

/// A settled motion (`st`, from the transient rule) certified as a periodic orbit, when it is
/// one: the events of one cycle from its final state place a stroboscopic section at their
/// quietest phase, Newton's method solves for the fixed point of the cycle's map from there,
/// and the orbit is the motion's own when it is stable, has the motion's events per cycle,
/// lies within [`CERTIFY_NEAR`] of the motion on the section, and its map is smooth there
/// (with a column of grains the Jacobian comes from central differences, which must not
/// straddle a change of events). Then `st` gets the orbit's [`Certificate`]; its record and
/// every number read from it stay as they are. Either way its method is
/// [`SteadyMethod::Certify`].
pub fn certify(d: &Dynamics, st: Steady, opts: &SteadyOptions) -> Steady {
    let st = Steady { method: SteadyMethod::Certify, ..st };
    if !st.converged || st.stop.is_some() || st.certificate.is_some() || st.period == 0 {
        return st;
    }
    let p = st.period;
    let period = 2.0 * PI / d.omega;
    let engine = Engine::new(d);
    let start = st.final_state.clone();
    let mut end = start.clone();
    let mut log = EventLog::default();
    if engine.advance(&mut end, start.t + p as f64 * period, &mut log).is_err() {
        return st;
    }
    let phase = quiet_phase(&log.0, start.t, d.omega, p);
    let mut at = start.clone();
    if engine.advance(&mut at, start.t + phase / d.omega, &mut crate::sim::motion::engine::Quiet).is_err() {
        return st;
    }
    let length = st.amplitude.iter().copied().fold(0.0, f64::max).max(1e-12);
    let wanted = counts(&log.0);
    let Ok((strobe, orbit, _)) = attempt(d, &at, p, length, &wanted, 0.0, opts) else {
        return st;
    };
    let u_motion = strobe.coordinates_unchecked(d, &at);
    if !orbit.smooth || strobe.periods != p || (&orbit.u - u_motion).amax() > CERTIFY_NEAR {
        return st;
    }
    Steady { certificate: Some(certificate(d, &strobe, &orbit, 1)), ..st }
}

/// How far (max-norm, in the section's scaled units: displacements over the motion's
/// amplitude) a certified orbit may lie from the settled motion it certifies: the transient
/// rule settles to far less, so an orbit farther away is another one.
pub const CERTIFY_NEAR: f64 = 1e-4;

/// How far (max-norm, in the section's scaled units: displacements over the motion's
/// amplitude) from its first guess a followed orbit whose events per cycle differ from the
/// previous orbit's may lie and still be taken as the same branch. On Fig. 5's band
/// (tests/follow.rs) such orbits within 0.25 are the transient search's own; one at 0.29 is
/// not (a period-1 orbit beside the period-2 motion the transient reaches).
pub const FOLLOW_NEAR: f64 = 0.1;

/// A certified steady state at its forcing frequency (a point of a continuation sweep).
pub struct Known<'a> {
    /// The steady state found at the previous frequency.
    pub steady: &'a Steady,
    /// Its forcing frequency, Hz.
    pub freq_hz: f64,
}

/// The orbit of `prev` (a certified steady state) continued to the dynamics `d` (the same
/// system forced at `freq_hz`): Newton's method on the section of `prev`'s orbit (same forcing
/// phase, period and bed places). The first guess is `prev`'s section state, extrapolated by
/// the polynomial through it and the `before` points (oldest first, up to two) that lie on the
/// same section, directly or as `moved` states. When an event crosses the section between the
/// two frequencies, the section is moved to the quietest phase of `prev`'s events, with every
/// such point's state ([`Moved`], returned for the next points), and Newton runs there.
/// `None` unless the orbit found is stable and is the same branch: it has `prev`'s events per
/// cycle, or other events (a graze crossed between the two frequencies) and lies within
/// [`FOLLOW_NEAR`] of the first guess (not another orbit farther off); then the caller runs
/// the transient search. Its `transient_periods` is 0, and its final state is where its orbit
/// closes (not run on to a whole period: `sweep::continued` does that only when it continues
/// by the transient search).
pub fn follow(
    prev: &Known,
    before: &[Known],
    moved: &[Moved],
    d: &Dynamics,
    freq_hz: f64,
    opts: &SteadyOptions,
) -> Option<(Steady, Vec<Moved>)> {
    let cert = prev.steady.certificate.as_ref()?;
    if !prev.steady.converged || prev.steady.stop.is_some() {
        return None;
    }
    let at = prev.steady.section_state()?;
    let length = prev.steady.amplitude.iter().copied().fold(0.0, f64::max).max(1e-12);
    let period = prev.steady.period;
    // The same section (forcing phase, period, bed places) at the new frequency.
    let strobe = Strobe { phase: cert.phase, periods: period, beds: at.beds.iter().map(Rest::of).collect(), length };
    let on_section = |s: &State| s.beds.iter().map(Rest::of).eq(strobe.beds.iter().copied());
    // The points on this section, newest first (their states, at their own frequencies): an
    // earlier point found on another section of the branch enters by its state moved to this
    // one, when the section was moved ([`Moved`]).
    let mut states: Vec<(f64, &State)> = vec![(prev.freq_hz, at)];
    for b in before.iter().rev() {
        let same = b.steady.certificate.as_ref().is_some_and(|c| c.phase == cert.phase && c.pattern == cert.pattern)
            && b.steady.period == period;
        let here = b.steady.section_state().filter(|s| same && on_section(s));
        let carried = || {
            moved
                .iter()
                .find(|m| {
                    m.freq_hz == b.freq_hz && m.phase == cert.phase && m.periods == period && on_section(&m.state)
                })
                .map(|m| &m.state)
        };
        match here.or_else(carried) {
            Some(old) => states.push((b.freq_hz, old)),
            None => break,
        }
    }
    let nodes: Vec<(f64, DVector<f64>)> =
        states.iter().map(|&(f, s)| (f, strobe.coordinates_unchecked(d, s))).collect();
    // Beds that never leave their floors: the orbit is the forced response of the structure
    // with the beds riding (exact while their contact forces stay positive; Newton checks it).
    // Otherwise the polynomial through the previous orbits.
    let resting = resting_guess(d, &strobe, at, &cert.pattern);
    let guess_exact = resting.is_some();
    let u0 = resting.unwrap_or_else(|| extrapolate(&nodes, freq_hz));
    // Newton converges near this orbit about as fast as near the previous one: its last
    // evaluation (the one worth recording) is predicted from the previous constant.
    let newton = NewtonOptions {
        tol: opts.orbit_tol,
        max_iter: opts.max_newton,
        quadratic: cert.quadratic,
        guess_exact,
        ..NewtonOptions::default()
    };
    // A stable orbit is the branch's next point when [`accept`] takes it; where the branch
    // lost its stability through a multiplier at -1, the stable 2p-orbit born there is.
    let take = |strobe: &Strobe, (orbit, recorded): (Orbit, Option<Recorded>), u0: &DVector<f64>| {
        if orbit.stable {
            accept(d, strobe, orbit, recorded, u0, &cert.pattern, opts)
        } else {
            doubled(d, strobe, &orbit, &cert.pattern, &newton, opts)
        }
    };
    match solve_recorded(&strobe, d, &u0, &newton, opts) {
        Ok(found) => take(&strobe, found, &u0).map(|st| (st, Vec::new())),
        // An event has crossed the section between the two frequencies: the same branch on a
        // section at the quietest phase of the previous orbit's events.
        Err(OrbitError::PatternChanged) => {
            let (strobe, moved) = moved_section(d, &strobe, &states)?;
            let nodes: Vec<(f64, DVector<f64>)> = moved
                .iter()
                .take_while(|m| m.state.beds.iter().map(Rest::of).eq(strobe.beds.iter().copied()))
                .map(|m| (m.freq_hz, strobe.coordinates_unchecked(d, &m.state)))
                .collect();
            let u0 = extrapolate(&nodes, freq_hz);
            let newton = NewtonOptions { guess_exact: false, ..newton };
            let found = solve_recorded(&strobe, d, &u0, &newton, opts).ok()?;
            take(&strobe, found, &u0).map(|st| (st, moved))
        }
        Err(_) => None,
    }
}

/// How far past -1 a followed orbit's leading multiplier may lie for the sweep to look for the
/// 2p-orbit born at the period doubling (farther, the step likely crossed more than one
/// bifurcation, and the transient search decides). On the 32-mass chain of the size family a
/// step of 0.2 Hz left the multiplier at -1.009 (48.3 Hz) and at -1.956 (47.9 Hz): both
/// 2p-orbits found are the ones the transient reaches (265 and 47 periods) to 1e-7.
pub const FLIP_MARGIN: f64 = 1.0;

/// The first guesses of the 2p-orbit after a period doubling: the unstable p-orbit moved
/// along the eigenvector of its multiplier beyond -1 (max-norm 1) by each of these, in the
/// section's scaled units. The 2p-orbit lies about `sqrt(|mu| - 1)` times a constant of the
/// bifurcation away; Newton on the 2p map converges to it from beyond about 0.6 of that
/// distance, and to the p-orbit (also a fixed point of the 2p map) from nearer.
pub const FLIP_STEPS: [f64; 3] = [0.3, 0.1, 0.02];

/// The stable 2p-orbit born where the followed p-orbit `orbit` on `strobe` lost its stability
/// by a real multiplier crossing -1 (a period doubling): Newton on the 2p-period map from
/// `orbit` moved along that multiplier's eigenvector by each of [`FLIP_STEPS`] (the two signs
/// give the same orbit half its period apart), taken as [`accept`] takes a followed orbit
/// (stable, with `pattern`'s events twice, or within [`FOLLOW_NEAR`] of its first guess) when
/// it is not the p-orbit again. `None` otherwise: the transient search decides.
fn doubled(
    d: &Dynamics,
    strobe: &Strobe,
    orbit: &Orbit,
    pattern: &[(usize, Mark, usize)],
    newton: &NewtonOptions,
    opts: &SteadyOptions,
) -> Option<Steady> {
    let lead = *orbit.multipliers.first()?;
    let flip = lead.re < -1.0 && lead.im.abs() <= 1e-9 * lead.norm() && lead.norm() <= 1.0 + FLIP_MARGIN;
    if !flip || 2 * strobe.periods > opts.max_subharmonic {
        return None;
    }
    // The eigenvector by inverse iteration, shifted just off the eigenvalue.
    let n = orbit.u.len();
    let shifted = &orbit.jacobian - DMatrix::<f64>::identity(n, n) * (lead.re * (1.0 + 1e-9));
    let lu = shifted.lu();
    let mut v = DVector::from_element(n, 1.0);
    for _ in 0..2 {
        v = lu.solve(&v)?;
        let top = v.amax();
        if !(top.is_finite() && top > 0.0) {
            return None;
        }
        v /= top;
    }
    let twice = Strobe { periods: 2 * strobe.periods, ..strobe.clone() };
    let pattern: Pattern = pattern.iter().map(|&(b, k, c)| (b, k, 2 * c)).collect();
    let newton = NewtonOptions { guess_exact: false, ..*newton };
    FLIP_STEPS.iter().find_map(|&step| {
        let u0 = &orbit.u + &v * step;
        let (o, recorded) = solve_recorded(&twice, d, &u0, &newton, opts).ok()?;
        // Newton found the p-orbit again (a fixed point of the 2p map too, ill-conditioned
        // there: within about the tolerance over `mu^2 - 1`).
        if (&o.u - &orbit.u).amax() <= 1e-6 {
            return None;
        }
        accept(d, &twice, o, recorded, &u0, &pattern, opts)
    })
}

/// A followed orbit taken as the branch's next point (recorded), or `None`: it must be stable
/// and have the previous orbit's events per cycle (`pattern`), or other events (a graze
/// crossed between the two frequencies: a bed starts or stops lifting off, or reaching the
/// top, where the orbit moves continuously) within [`FOLLOW_NEAR`] of its first guess `u0`
/// (an orbit farther from the prediction than the branch's own steps is another motion).
fn accept(
    d: &Dynamics,
    strobe: &Strobe,
    orbit: Orbit,
    recorded: Option<Recorded>,
    u0: &DVector<f64>,
    pattern: &[(usize, Mark, usize)],
    opts: &SteadyOptions,
) -> Option<Steady> {
    if !orbit.stable || counts(&orbit.events) != pattern && (&orbit.u - u0).amax() > FOLLOW_NEAR {
        return None;
    }
    let st = record(d, strobe, &orbit, 0, 1, opts, recorded);
    (st.converged && st.stop.is_none()).then_some(st)
}

/// A state of an earlier orbit of a followed branch moved to the branch's current section
/// (after an event crossed the section it was found on), so that the branch's next points
/// still extrapolate through several orbits.
#[derive(Debug, Clone)]
pub struct Moved {
    /// The orbit's forcing frequency, Hz.
    pub freq_hz: f64,
    /// The section's forcing phase, rad.
    pub phase: f64,
    /// Forcing periods per orbit.
    pub periods: usize,
    /// The orbit's state on that section.
    pub state: State,
}

/// The section of `strobe`'s branch moved to the quietest phase of the newest orbit's events
/// (`states`: the orbits' states on `strobe`, newest first, at their own frequencies), and
/// every orbit's state there: each orbit run on, at its own frequency, by the phase shift.
fn moved_section(d: &Dynamics, strobe: &Strobe, states: &[(f64, &State)]) -> Option<(Strobe, Vec<Moved>)> {
    let p = strobe.periods;
    let (f0, at) = *states.first()?;
    let d0 = d.at_omega(2.0 * PI * f0).ok()?;
    let mut s = at.clone();
    let mut log = EventLog::default();
    Engine::new(&d0).advance(&mut s, strobe.end_time(&d0, at.t), &mut log).ok()?;
    let shift = quiet_phase(&log.0, at.t, d0.omega, p);
    let phase = (strobe.phase + shift).rem_euclid(2.0 * PI);
    let mut moved = Vec::with_capacity(states.len());
    for (i, &(f, st)) in states.iter().enumerate() {
        let di;
        let dyn_f = if i == 0 {
            &d0
        } else {
            di = d.at_omega(2.0 * PI * f).ok()?;
            &di
        };
        let mut s = st.clone();
        Engine::new(dyn_f).advance(&mut s, st.t + shift / dyn_f.omega, &mut Quiet).ok()?;
        moved.push(Moved { freq_hz: f, phase, periods: p, state: s });
    }
    let beds = moved[0].state.beds.iter().map(Rest::of).collect();
    Some((Strobe { phase, periods: p, beds, length: strobe.length }, moved))
}

/// The section coordinates of the forced response with every bed on its container floor,
/// when the previous orbit had no event (its beds rode their hosts throughout): that response
/// is the orbit as long as no contact force reaches zero on it.
fn resting_guess(d: &Dynamics, strobe: &Strobe, at: &State, pattern: &[(usize, Mark, usize)]) -> Option<DVector<f64>> {
    if !pattern.is_empty() || strobe.beds.iter().any(|b| *b != Rest::Bottom) {
        return None;
    }
    let mask = (1usize << strobe.beds.len()) - 1;
    let t = strobe.time(d);
    let (x, v) = d.particular(mask, t);
    let s = State { t, x, v, beds: at.beds.clone() };
    Some(strobe.coordinates_unchecked(d, &s))
}

/// The value at `x` of the polynomial through `nodes` (abscissa, value; newest first), each
/// node's weight the Lagrange basis at `x`; only the newest is used when `x` lies more than
/// two node spacings away (a far extrapolation is no better guess than the nearest orbit).
fn extrapolate(nodes: &[(f64, DVector<f64>)], x: f64) -> DVector<f64> {
    let near = nodes.windows(2).take_while(|w| {
        let r = (x - w[0].0) / (w[0].0 - w[1].0);
        r.is_finite() && r.abs() <= 2.0
    });
    let k = 1 + near.count();
    let nodes = &nodes[..k];
    let mut out = DVector::zeros(nodes[0].1.len());
    for (i, (xi, ui)) in nodes.iter().enumerate() {
        let w: f64 =
            nodes.iter().enumerate().filter(|(j, _)| *j != i).map(|(_, (xj, _))| (x - xj) / (xi - xj)).product();
        out.axpy(w, ui, 1.0);
    }
    out
}

/// The certificate of an orbit found on `strobe` after `attempts` attempts.
fn certificate(d: &Dynamics, strobe: &Strobe, orbit: &Orbit, attempts: usize) -> Certificate {
    Certificate {
        residual: orbit.residuals.last().copied().unwrap_or(f64::NAN),
        multipliers: orbit.multipliers.clone(),
        stable: orbit.stable,
        smooth: orbit.smooth,
        iterations: orbit.residuals.len().saturating_sub(1),
        attempts,
        quadratic: quadratic_constant(&orbit.residuals),
        phase: strobe.phase,
        pattern: counts(&orbit.events),
        section: strobe.state(d, &orbit.u),
    }
}

/// Records one orbit from its section state (or takes `recorded`, the same run observed
/// beside Newton's final evaluation); the record ends where the orbit closes.
fn record(
    d: &Dynamics,
    strobe: &Strobe,
    orbit: &Orbit,
    simulated: usize,
    attempts: usize,
    opts: &SteadyOptions,
    recorded: Option<Recorded>,
) -> Steady {
    let p = strobe.periods;
    let certificate = certificate(d, strobe, orbit, attempts);
    let start = certificate.section.clone();
    let t_end = strobe.end_time(d, start.t);
    let outcome = Outcome {
        method: SteadyMethod::Orbit,
        converged: true,
        certificate: Some(certificate),
        failure: None,
        transient_periods: simulated,
        period: p,
        record: p,
        stop: None,
        last_whole: None,
    };
    match recorded {
        Some((rec, end)) => rec.steady(d, end, None, outcome),
        None => finish(d, start, t_end, opts, outcome),
    }
}

/// `st` with its final state run on to the next whole forcing period (where a continuation
/// sweep restarts, [`super::sweep::restart`]).
fn on_whole_period(d: &Dynamics, mut st: Steady) -> Steady {
    if st.stop.is_none() {
        if let Err(e) = run_to_whole_period(d, &mut st.final_state) {
            st.stop = Some(e);
            st.converged = false;
        }
    }
    st
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extrapolation_is_exact_for_quadratics_and_falls_back_when_far() {
        let q = |x: f64| DVector::from_vec(vec![1.0 + 2.0 * x - 0.5 * x * x, -x * x]);
        let nodes: Vec<(f64, DVector<f64>)> = [3.0, 2.5, 1.5].iter().map(|&x| (x, q(x))).collect();
        let got = extrapolate(&nodes, 3.75);
        assert!((&got - q(3.75)).amax() < 1e-12, "{got}");
        // Two nodes: the secant.
        let got = extrapolate(&nodes[..2], 3.25);
        let secant = &nodes[0].1 + (&nodes[0].1 - &nodes[1].1) * 0.5;
        assert!((&got - secant).amax() < 1e-12);
        // Farther than two spacings from the newest: the newest alone.
        assert_eq!(extrapolate(&nodes, 5.0), nodes[0].1);
    }
}
