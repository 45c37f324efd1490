//! A point from rest (docs/simulator.md, "Steady state and what is measured"): where the
//! structure's forced motion with every bed riding its floor keeps every contact, that motion
//! is the steady state and is certified at once; elsewhere the motion is run from rest.

use std::f64::consts::PI;

use super::steady::{Steady, SteadyMethod, SteadyOptions};
use super::steady_state;
use crate::sim::motion::engine::{Bed, Engine, State};
use crate::sim::motion::observe::EventLog;
use crate::sim::motion::system::Dynamics;

/// The steady state of a point started at rest ([`State::at_rest`]): the riding motion
/// (the structure's forced motion with every bed riding) where it is one, else the motion run
/// from rest to its steady state.
pub fn steady_from_rest(d: &Dynamics, opts: &SteadyOptions) -> Steady {
    riding(d, opts).unwrap_or_else(|| steady_state(d, State::at_rest(d), opts))
}

/// The forced motion of the structure with every bed on its floor (the configuration's
/// particular solution, which a motion from rest approaches as long as no bed leaves),
/// certified as the steady state: `None` unless one forcing period of it has no event (no
/// contact force reaches zero) and Newton's method confirms it as a stable periodic orbit
/// without events. Only for the periodic-orbit method without columns of grains. A host whose
/// forced acceleration amplitude reaches its bed's gravity says `None` at once (for any
/// container angle and support motion that filter only ever skips the check).
fn riding(d: &Dynamics, opts: &SteadyOptions) -> Option<Steady> {
    if opts.method != SteadyMethod::Orbit || !d.system.columns.is_empty() {
        return None;
    }
    let beds = d.system.dampers.len();
    let all = (1 << beds) - 1;
    // A bed whose host's forced acceleration amplitude reaches its gravity leaves its floor
    // (the contact force is `m_b (g_a + a_host)`): no period needs running to know.
    let forced = d.forced(d.slot(all));
    let w2 = d.omega * d.omega;
    if d.system.dampers.iter().any(|b| w2 * forced[b.host].amp >= b.gravity()) {
        return None;
    }
    let (x, v) = d.particular(all, 0.0);
    let mut s = State { t: 0.0, x, v, beds: vec![Bed::Bottom; beds] };
    let mut log = EventLog::default();
    Engine::new(d).advance(&mut s, 2.0 * PI / d.omega, &mut log).ok()?;
    if !log.0.is_empty() {
        return None;
    }
    // Judged as soon as two periods have had the same (no) events.
    let near = SteadyOptions { min_periods: 0, consecutive: 2, ..*opts };
    let mut st = steady_state(d, s, &near);
    let rides = st.certificate.as_ref().is_some_and(|c| c.pattern.is_empty());
    if !(st.converged && rides) {
        return None;
    }
    st.transient_periods += 1;
    Some(st)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::frf::receptance;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::System;

    /// The paper's structure, a bed of 10 % of its host's mass with no lid on each mass,
    /// driven at m1 by 2.6 N.
    fn three_beds() -> System {
        let m = [0.74, 0.71, 0.64];
        let s = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
        let beds = (0..3).map(|j| Damper::new(j, 0.1 * m[j], Clearance::from_m(f64::INFINITY))).collect();
        System::plastic(s, beds, 0, 2.6)
    }

    #[test]
    fn a_point_whose_beds_ride_is_the_forced_response_with_the_beds_on_as_from_rest() {
        let sys = three_beds();
        let opts = SteadyOptions::default();
        for f in [30.0, 54.0, 58.0] {
            let omega = 2.0 * PI * f;
            let d = Dynamics::new(&sys, omega).unwrap();
            let st = steady_from_rest(&d, &opts);
            assert!(st.converged, "{f} Hz");
            assert_eq!(st.transient_periods, 3, "{f} Hz: one period checked, two judged");
            assert!(st.liftoffs.iter().all(|&n| n == 0.0), "{f} Hz: the beds ride");
            // A second method: the complex solve of the structure with the beds' masses added.
            let x = receptance(&sys.structure, &sys.mass_matrix(7), 0, omega).unwrap();
            // And the motion run from rest to its steady state, at least 20 periods.
            let slow = steady_state(&d, State::at_rest(&d), &opts);
            assert!(slow.transient_periods >= 20);
            for i in 0..3 {
                let exact = 2.6 * x[i].norm();
                assert!(
                    (st.amplitude[i] - exact).abs() <= 1e-9 * exact,
                    "{f} Hz m{}: {} vs {exact}",
                    i + 1,
                    st.amplitude[i]
                );
                assert!((st.amplitude[i] - slow.amplitude[i]).abs() <= 1e-9 * exact, "{f} Hz m{}", i + 1);
            }
        }
    }

    #[test]
    fn a_large_structure_s_riding_record_finds_the_exact_amplitudes() {
        // 16 masses (the record's coarse windows apply above 8), beds on the last three.
        let n = 16;
        let s = Structure::chain(&vec![0.13; n], &vec![1.2e5; n], Damping::ModalRatios(vec![0.01; n]));
        let beds = (n - 3..n).map(|j| Damper::new(j, 0.013, Clearance::from_m(f64::INFINITY))).collect();
        let sys = System::plastic(s, beds, 0, 0.5);
        for f in [20.0, 45.0] {
            let omega = 2.0 * PI * f;
            let d = Dynamics::new(&sys, omega).unwrap();
            let st = steady_from_rest(&d, &SteadyOptions::default());
            assert!(st.converged && st.transient_periods == 3, "{f} Hz: the beds ride");
            let x = receptance(&sys.structure, &sys.mass_matrix(7), 0, omega).unwrap();
            let top = x.iter().map(|c| c.norm()).fold(0.0, f64::max) * 0.5;
            for i in 0..n {
                let exact = 0.5 * x[i].norm();
                assert!(
                    (st.amplitude[i] - exact).abs() <= 1e-9 * top,
                    "{f} Hz m{}: {} vs {exact}",
                    i + 1,
                    st.amplitude[i]
                );
            }
        }
    }

    #[test]
    fn where_a_bed_leaves_its_floor_the_point_is_run_from_rest() {
        let sys = three_beds();
        let opts = SteadyOptions::default();
        let d = Dynamics::new(&sys, 2.0 * PI * 49.5).unwrap();
        let st = steady_from_rest(&d, &opts);
        let slow = steady_state(&d, State::at_rest(&d), &opts);
        assert!(st.liftoffs.iter().any(|&n| n > 0.0));
        assert_eq!(st.transient_periods, slow.transient_periods);
        assert_eq!(st.amplitude, slow.amplitude);
    }
}
