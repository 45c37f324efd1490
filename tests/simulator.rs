//! The simulator against independent physics: linear limits, the energy balance, the
//! plastic bouncing ball, a second integrator, grazes and chatter.

#![allow(clippy::needless_range_loop)]
use crate::common::paper;
use shotdamp::model::Clearance;
use std::f64::consts::PI;

use nalgebra::DVector;
use shotdamp::model::frf::compliance_curve;
use shotdamp::model::{Damper, Damping, Structure, GRAVITY};
use shotdamp::sim::{
    steady_state, Bed, Dynamics, Engine, Event, EventKind, Observer, SetupError, State, SteadyOptions, Stop, System,
};

fn dampers(hosts: &[usize], clearance: f64) -> Vec<Damper> {
    let m = [0.74, 0.71, 0.64];
    hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_m(clearance))).collect()
}

fn steady(sys: &System, f_hz: f64, opts: &SteadyOptions) -> shotdamp::sim::Steady {
    let d = Dynamics::new(sys, 2.0 * PI * f_hz).unwrap();
    steady_state(&d, State::at_rest(&d), opts)
}

#[test]
fn zero_clearance_reproduces_the_stuck_frf() {
    let sys = System::plastic(paper(), dampers(&[0, 1, 2], 0.0), 0, 2.6);
    let stuck = sys.structure.mass_matrix_with(&[(0, 0.074), (1, 0.071), (2, 0.064)]);
    for f in [10.0, 30.0, 49.0] {
        let r = steady(&sys, f, &SteadyOptions::default());
        assert!(r.converged && r.period == 1);
        let lin = &compliance_curve(&sys.structure, &stuck, 0, &[2.0 * PI * f])[0];
        for i in 0..3 {
            let c = r.amplitude[i] / 2.6;
            assert!((c - lin[i]).abs() < 1e-6 * lin[i], "{f} Hz m{}: {c} vs {}", i + 1, lin[i]);
        }
    }
}

#[test]
fn vanishing_bed_mass_reproduces_the_bare_frf() {
    let mut ds = dampers(&[0, 1, 2], f64::INFINITY);
    for d in &mut ds {
        d.mass *= 1e-9;
    }
    let sys = System::plastic(paper(), ds, 0, 2.6);
    for f in [10.0, 30.0, 49.0] {
        let r = steady(&sys, f, &SteadyOptions::default());
        assert!(r.converged, "{f} Hz");
        let lin = &compliance_curve(&sys.structure, &sys.structure.mass_matrix(), 0, &[2.0 * PI * f])[0];
        for i in 0..3 {
            let c = r.amplitude[i] / 2.6;
            assert!((c - lin[i]).abs() < 1e-6 * lin[i], "{f} Hz m{}: {c} vs {}", i + 1, lin[i]);
        }
    }
}

#[test]
fn energy_balances_over_steady_periods() {
    let opts = SteadyOptions { energy: true, ..SteadyOptions::default() };
    for (hosts, clearance, f) in [
        (vec![0, 1, 2], f64::INFINITY, 49.5),
        (vec![1], 0.5e-3, 48.8),
        (vec![0], f64::INFINITY, 34.0),
        (vec![0, 1, 2], 0.2e-3, 47.0),
    ] {
        let sys = System::plastic(paper(), dampers(&hosts, clearance), 0, 2.6);
        let r = steady(&sys, f, &opts);
        let e = r.energy.unwrap();
        assert!(e.impact > 0.0, "impacts dissipate at {f} Hz");
        assert!(e.relative_residual() < 1e-9, "{f} Hz: {e:?} residual {}", e.relative_residual());
    }
}

/// Records every event.
#[derive(Default)]
struct Log(Vec<Event>);
impl Observer for Log {
    fn event(&mut self, ev: &Event, _after: &State) {
        self.0.push(*ev);
    }
}

/// A 1000 kg host driven to amplitude A = Gamma g / omega^2 with a 1 microgram bed on it.
fn bouncing_ball(gamma: f64) -> (Dynamics, State, f64) {
    let omega = 2.0 * PI * 10.0;
    let host = Structure::chain(&[1000.0], &[1e6], Damping::ModalRatios(vec![0.05]));
    let h = shotdamp::model::frf::receptance(&host, &host.mass_matrix(), 0, omega).unwrap()[0];
    let amplitude = gamma * GRAVITY / (omega * omega);
    let force = amplitude / h.norm();
    let sys = System::plastic(host, vec![Damper::new(0, 1e-9, Clearance::NO_TOP)], 0, force);
    let d = Dynamics::new(&sys, omega).unwrap();
    // Start on the forced motion, bed resting: no transient.
    let (x, v) = d.particular(1, 0.0);
    let s = State { t: 0.0, x, v, beds: vec![Bed::Bottom] };
    // Host displacement = A sin(omega t + arg X).
    (d, s, h.arg())
}

#[test]
fn plastic_bouncing_ball_flight_durations() {
    for (gamma, flight) in [(1.2, 2.402305), (1.5, 3.566217), (2.0, 4.658851), (2.5, 5.386636), (3.0, 5.967608)] {
        let (d, mut s, phi) = bouncing_ball(gamma);
        let mut log = Log::default();
        let period = 2.0 * PI / d.omega;
        Engine::new(&d).advance(&mut s, 6.0 * period, &mut log).unwrap();
        let lifts: Vec<f64> =
            log.0.iter().filter(|e| matches!(e.kind, EventKind::LiftOff { .. })).map(|e| e.t).collect();
        let lands: Vec<f64> =
            log.0.iter().filter(|e| matches!(e.kind, EventKind::Impact { .. })).map(|e| e.t).collect();
        assert!(lifts.len() >= 4 && lands.len() >= 4, "Gamma {gamma}: {log:?}", log = log.0);
        for (l, i) in lifts.iter().zip(&lands).skip(1) {
            let phase = (d.omega * l + phi).rem_euclid(2.0 * PI);
            assert!((phase.sin() - 1.0 / gamma).abs() < 1e-8, "Gamma {gamma}: lift-off at sin = {}", phase.sin());
            let dur = d.omega * (i - l);
            assert!((dur - flight).abs() < 1e-4, "Gamma {gamma}: flight {dur} rad vs {flight}");
        }
    }
}

/// The same model integrated by an adaptive Runge-Kutta method (Dormand-Prince 5(4)) with
/// events found by bisection on the step, and contacts released by the rule of docs/model.md section 2 (most
/// negative first). It shares nothing with the closed-form simulator but the model.
mod rk {
    use super::*;

    pub struct Rk<'a> {
        pub sys: &'a System,
        pub omega: f64,
    }

    #[derive(Clone, Debug)]
    pub struct St {
        pub t: f64,
        pub x: DVector<f64>,
        pub v: DVector<f64>,
        /// Per bed: None attached, Some((y, u)) free; and the side (true = top).
        pub free: Vec<Option<(f64, f64)>>,
        pub top: Vec<bool>,
    }

    impl<'a> Rk<'a> {
        fn mass(&self, s: &St) -> DVector<f64> {
            let mut m = DVector::from_vec(self.sys.structure.masses.clone());
            for (j, d) in self.sys.dampers.iter().enumerate() {
                if s.free[j].is_none() {
                    m[d.host] += d.mass;
                }
            }
            m
        }

        fn accel(&self, s: &St, t: f64, x: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
            let k = &self.sys.structure.stiffness;
            let c = &self.sys.structure.damping;
            let mut f = -(k * x) - c * v;
            f[self.sys.driven] += self.sys.force * (self.omega * t).sin();
            for (j, d) in self.sys.dampers.iter().enumerate() {
                if s.free[j].is_none() {
                    f[d.host] -= d.mass * GRAVITY;
                }
            }
            f.component_div(&self.mass(s))
        }

        /// One Dormand-Prince 5(4) step of length h: the fifth-order state and the max-norm of
        /// the difference from the embedded fourth-order one (free beds move exactly).
        pub fn step(&self, s: &St, h: f64) -> (St, f64) {
            const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
            const A: [[f64; 6]; 7] = [
                [0.0; 6],
                [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
                [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
                [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
                [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
                [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
                [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
            ];
            const B5: [f64; 7] = [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0];
            const B4: [f64; 7] = [
                5179.0 / 57600.0,
                0.0,
                7571.0 / 16695.0,
                393.0 / 640.0,
                -92097.0 / 339200.0,
                187.0 / 2100.0,
                1.0 / 40.0,
            ];
            let mut kx: Vec<DVector<f64>> = Vec::with_capacity(7);
            let mut kv: Vec<DVector<f64>> = Vec::with_capacity(7);
            for stage in 0..7 {
                let mut x = s.x.clone();
                let mut v = s.v.clone();
                for (k, a) in A[stage].iter().enumerate().take(stage) {
                    x += &kx[k] * (h * a);
                    v += &kv[k] * (h * a);
                }
                kv.push(self.accel(s, s.t + C[stage] * h, &x, &v));
                kx.push(v);
            }
            let combine = |b: &[f64; 7], k: &Vec<DVector<f64>>, base: &DVector<f64>| {
                let mut out = base.clone();
                for (bi, ki) in b.iter().zip(k) {
                    out += ki * (h * bi);
                }
                out
            };
            let mut n = s.clone();
            n.t = s.t + h;
            n.x = combine(&B5, &kx, &s.x);
            n.v = combine(&B5, &kv, &s.v);
            let err = (&n.x - combine(&B4, &kx, &s.x)).amax().max((&n.v - combine(&B4, &kv, &s.v)).amax() / self.omega);
            for f in n.free.iter_mut().flatten() {
                f.0 += f.1 * h - 0.5 * GRAVITY * h * h;
                f.1 -= GRAVITY * h;
            }
            (n, err)
        }

        /// Event functions (negative = event due).
        pub fn gaps(&self, s: &St) -> Vec<f64> {
            let a = self.accel(s, s.t, &s.x, &s.v);
            let mut g = Vec::new();
            for (j, d) in self.sys.dampers.iter().enumerate() {
                let p = d.host;
                match s.free[j] {
                    None => g.push(if s.top[j] { -(a[p] + GRAVITY) } else { a[p] + GRAVITY }),
                    Some((y, _)) => {
                        g.push(y - s.x[p]);
                        g.push(if d.clearance.is_bounded() { s.x[p] + d.clearance.m() - y } else { 1.0 });
                    }
                }
            }
            g
        }

        /// Applies whatever is due at a state on an event.
        pub fn resolve(&self, s: &mut St) {
            for (j, d) in self.sys.dampers.iter().enumerate() {
                let p = d.host;
                if let Some((y, u)) = s.free[j] {
                    let at_bottom = y - s.x[p] <= 1e-12 && u - s.v[p] <= 0.0;
                    let at_top = d.clearance.is_bounded() && s.x[p] + d.clearance.m() - y <= 1e-12 && u - s.v[p] >= 0.0;
                    if at_bottom || at_top {
                        let m = self.sys.structure.masses[p];
                        s.v[p] = (m * s.v[p] + d.mass * u) / (m + d.mass);
                        s.free[j] = None;
                        s.top[j] = at_top;
                    }
                }
            }
            loop {
                let a = self.accel(s, s.t, &s.x, &s.v);
                let worst = self
                    .sys
                    .dampers
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| s.free[*j].is_none())
                    .map(|(j, d)| (j, if s.top[j] { -(a[d.host] + GRAVITY) } else { a[d.host] + GRAVITY }))
                    .filter(|(_, n)| *n < -1e-9)
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                match worst {
                    Some((j, _)) => {
                        let d = &self.sys.dampers[j];
                        let y = if s.top[j] { s.x[d.host] + d.clearance.m() } else { s.x[d.host] };
                        s.free[j] = Some((y, s.v[d.host]));
                    }
                    None => break,
                }
            }
        }

        /// Integrates to `t_end` with adaptive steps (local error below `tol` of the motion's
        /// scale `scale`), locating events by bisection of the step to 1e-14 s.
        pub fn run(&self, mut s: St, t_end: f64, tol: f64, scale: f64) -> St {
            let mut h = 2.0 * std::f64::consts::PI / self.omega / 200.0;
            while s.t < t_end - 1e-15 {
                let hh = h.min(t_end - s.t);
                let (n, err) = self.step(&s, hh);
                // Step size control (order 5): accept below the tolerance, then adapt.
                let ratio = (err / (tol * scale)).max(1e-10);
                if ratio > 1.0 {
                    h = hh * (0.9 * ratio.powf(-0.2)).max(0.2);
                    continue;
                }
                h = hh * (0.9 * ratio.powf(-0.2)).min(5.0);
                if self.gaps(&n).iter().all(|g| *g > 0.0) {
                    s = n;
                    continue;
                }
                let (mut lo, mut hi) = (0.0, hh);
                while hi - lo > 1e-14 {
                    let mid = 0.5 * (lo + hi);
                    if self.gaps(&self.step(&s, mid).0).iter().all(|g| *g > 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                s = self.step(&s, hi).0;
                self.resolve(&mut s);
            }
            s
        }
    }
}

#[test]
fn runge_kutta_agrees_with_the_closed_form() {
    let cases: [(&[usize], f64, f64); 5] = [
        (&[0], f64::INFINITY, 34.5),
        (&[0, 1], f64::INFINITY, 49.0),
        (&[0, 1, 2], f64::INFINITY, 49.5),
        (&[1], 0.5e-3, 49.0),
        (&[0, 1, 2], 0.2e-3, 46.5),
    ];
    for (hosts, clearance, f) in cases {
        let sys = System::plastic(paper(), dampers(hosts, clearance), 0, 2.6);
        let omega = 2.0 * PI * f;
        let d = Dynamics::new(&sys, omega).unwrap();
        let mut s = State::at_rest(&d);
        let t_end = 0.25;
        let mut log = Log::default();
        Engine::new(&d).advance(&mut s, t_end, &mut log).unwrap();
        assert!(log.0.len() > 4, "{f} Hz: the beds must move ({} events)", log.0.len());
        let rk = rk::Rk { sys: &sys, omega };
        let s0 = State::at_rest(&d);
        let start = rk::St {
            t: 0.0,
            x: s0.x.clone(),
            v: s0.v.clone(),
            free: vec![None; hosts.len()],
            top: vec![false; hosts.len()],
        };
        let scale = s.x.amax().max(1e-6);
        let end = rk.run(start, t_end, 1e-12, scale);
        let dx = (&s.x - &end.x).amax() / scale;
        let dv = (&s.v - &end.v).amax() / (scale * omega);
        // They agree to ~1e-11 after about a dozen impacts; 1e-9 leaves room for rounding.
        assert!(dx < 1e-9 && dv < 1e-9, "{f} Hz, hosts {hosts:?}, d {clearance}: dx {dx:e} dv {dv:e}");
    }
}

#[test]
fn a_graze_of_the_top_is_found() {
    // From a settled state of a bed without top, measure the apex of the next flights; then
    // put the top a hair (1e-9 relative, ~1e-13 m) below that apex: the bed touches it for
    // about 0.1 microseconds, and the impact must be found. A hair above: no impact.
    let sys = System::plastic(paper(), dampers(&[1], f64::INFINITY), 0, 2.6);
    let r = steady(&sys, 49.0, &SteadyOptions::default());
    let omega = 2.0 * PI * 49.0;
    let t_end = r.final_state.t + 2.0 * 2.0 * PI / omega;
    let d = Dynamics::new(&sys, omega).unwrap();
    let mut ext = shotdamp::sim::motion::observe::Extrema::new(3, 1);
    let mut s = r.final_state.clone();
    Engine::new(&d).advance(&mut s, t_end, &mut ext).unwrap();
    let apex = ext.max_flight[0];
    assert!(apex > 1e-5, "the bed flies: {apex}");
    for (factor, expect_top) in [(1.0 - 1e-9, true), (1.0 + 1e-9, false)] {
        let sys = System::plastic(paper(), dampers(&[1], apex * factor), 0, 2.6);
        let d = Dynamics::new(&sys, omega).unwrap();
        let mut s = r.final_state.clone();
        let mut log = Log::default();
        Engine::new(&d).advance(&mut s, t_end, &mut log).unwrap();
        let tops = log.0.iter().filter(|e| matches!(e.kind, EventKind::Impact { top: true, .. })).count();
        assert_eq!(tops > 0, expect_top, "clearance {factor} x apex: {tops} top impacts");
    }
}

#[test]
fn chatter_stops_with_a_flag() {
    // Restitution without a sticking threshold on a bouncing ball: infinitely many ever
    // smaller bounces (a Zeno sequence) must end with a flag, not a hang.
    let (d0, s, _) = bouncing_ball(2.0);
    let law = |stick_speed| shotdamp::sim::motion::bed::ImpactLaw::with_restitution(0.5, stick_speed);
    let sys = (*d0.system).clone().with_law(law(0.0));
    let d = Dynamics::new(&sys, d0.omega).unwrap();
    let mut s = s;
    let r = Engine::new(&d).advance(&mut s, 50.0 * 2.0 * PI / d.omega, &mut shotdamp::sim::Quiet);
    assert!(matches!(r, Err(Stop::Chatter { .. })), "{r:?}");
    // With a sticking threshold the same motion runs to the end.
    let sys = sys.with_law(law(1e-3));
    let d = Dynamics::new(&sys, d0.omega).unwrap();
    let (x, v) = d.particular(1, 0.0);
    let mut s = State { t: 0.0, x, v, beds: vec![Bed::Bottom] };
    Engine::new(&d).advance(&mut s, 50.0 * 2.0 * PI / d.omega, &mut shotdamp::sim::Quiet).unwrap();
}

#[test]
fn many_periods_of_ordinary_impacts_in_one_call_are_not_chatter() {
    // The bound counts events within one forcing period: a long record of a motion with a few
    // events a period (here a lift-off and a landing) runs to its end however many periods it
    // spans; before, 2000 events in one call stopped it as chatter whatever its length, and
    // the record of a plate's steady state lost its last periods that way.
    let (d, mut s, _) = bouncing_ball(1.2);
    let period = 2.0 * PI / d.omega;
    let mut log = Log::default();
    Engine::new(&d).advance(&mut s, 1100.0 * period, &mut log).unwrap();
    assert!(log.0.len() > 2000, "{} events", log.0.len());
    assert!((s.t - 1100.0 * period).abs() < 1e-9);
}

#[test]
fn more_beds_than_the_limit_are_refused_before_any_decomposition() {
    use shotdamp::sim::motion::system::MAX_BEDS;
    let ok = System::plastic(paper(), dampers(&[0; MAX_BEDS], f64::INFINITY), 0, 2.6);
    assert!(Dynamics::new(&ok, 2.0 * PI * 20.0).is_ok());
    let many = System::plastic(paper(), dampers(&[0; MAX_BEDS + 1], f64::INFINITY), 0, 2.6);
    match Dynamics::new(&many, 2.0 * PI * 20.0) {
        Err(e @ SetupError::TooManyBeds { beds, .. }) => {
            assert_eq!(beds, MAX_BEDS + 1);
            assert!(e.to_string().contains(&format!("at most {MAX_BEDS}")), "{e}");
        }
        other => panic!("expected TooManyBeds, got {:?}", other.map(|_| ())),
    }
    // Columns count n + 1 configurations each: three of 20 grains fit, three of 30 do not.
    let three = System::plastic(paper(), dampers(&[0, 1, 2], 0.3e-3), 0, 2.6);
    let fits = Dynamics::new(&three.clone().with_grains(&[20, 20, 20]), 2.0 * PI * 20.0).unwrap();
    assert_eq!(fits.configs.len(), 21 * 21 * 21);
    assert!(matches!(
        Dynamics::new(&three.with_grains(&[30, 30, 30]), 2.0 * PI * 20.0),
        Err(SetupError::TooManyBeds { beds: 90, .. })
    ));
}

#[test]
fn carried_points_agree_with_direct_evaluation() {
    // A segment of the paper's chain with beds riding two masses; points carried by a step's
    // factors (equally spaced samples) and by the short-step series must equal the closed form
    // evaluated directly, to a few roundings of each term.
    use shotdamp::sim::motion::segment::{Segment, NEAR};
    let sys = System::plastic(paper(), dampers(&[0, 2], 1e-3), 0, 2.6);
    let d = Dynamics::new(&sys, 2.0 * PI * 47.0).unwrap();
    let x0 = DVector::from_vec(vec![1e-4, -2e-4, 3e-4]);
    let v0 = DVector::from_vec(vec![0.02, 0.01, -0.03]);
    let seg = Segment::start(&d, 0b01, 0.013, &x0, &v0);
    let close = |a: &shotdamp::sim::motion::segment::Point, b: &shotdamp::sim::motion::segment::Point, what: &str| {
        for p in 0..3 {
            for order in 0..4 {
                let (u, w) = (seg.deriv(&d, a, p, order), seg.deriv(&d, b, p, order));
                let scale = seg.bound(&d, b, p, order);
                assert!((u - w).abs() <= 1e-13 * scale, "{what}: mass {p} order {order}: {u} vs {w}");
            }
        }
    };
    let dt = d.min_period / 16.0;
    let step = seg.step(&d, dt);
    let mut carried = seg.point(&d, 0.013);
    for k in 1..=32 {
        let t = 0.013 + dt * k as f64;
        carried.advance(&step, t);
        close(&carried, &seg.point(&d, t), &format!("step {k}"));
    }
    // The series over short steps, from the longest it takes down to rounding-level ones.
    let rate = 2.0 * PI / d.min_period;
    let from = seg.point(&d, 0.02);
    for h in [NEAR / rate, 1e-6, 1e-9, 1e-13] {
        let t = 0.02 + h;
        let mut near = from.clone();
        seg.move_near(&d, &mut near, t);
        close(&near, &seg.point(&d, t), &format!("series over {h:e} s"));
    }
}
