//! Periodic orbits by shooting against long simulations and the bouncing ball's closed forms.

use crate::common;
use crate::common::paper;

use shotdamp::model::Clearance;
use std::f64::consts::PI;

use nalgebra::DVector;
use shotdamp::model::frf::receptance;
use shotdamp::model::sdof::EquivalentSdof;
use shotdamp::model::{Damper, GRAVITY};
use shotdamp::sim::orbits::continuation::{continue_branch, ContinuationOptions, Special};
use shotdamp::sim::orbits::periodic::{seed, solve, summarize, NewtonOptions, Problem};
use shotdamp::sim::{steady_state, Dynamics, SetupError, State, SteadyOptions, System};

/// A long simulation to a tight steady state, then the orbit through its state.
fn orbit_against_simulation(sys: &System, f: f64) {
    let d = Dynamics::new(sys, 2.0 * PI * f).unwrap();
    let tight = SteadyOptions { tol: 1e-11, consecutive: 5, max_periods: 20_000, ..SteadyOptions::default() };
    let st = steady_state(&d, State::at_rest(&d), &tight);
    assert!(st.converged && st.period == 1, "{f} Hz: the simulation settles");
    let (problem, u0) = seed(&d, &st.final_state, 1, 1e-4, d.omega, false).unwrap();
    // Start Newton well away from the simulated point (0.03 rad, 0.03 L, 0.03 omega L).
    let guess = u0.add_scalar(0.03);
    let orbit = solve(&problem, &d, &guess, &NewtonOptions::default()).unwrap();
    assert!(orbit.stable, "{f} Hz: {:?}", orbit.multipliers);
    let sum = summarize(&d, &problem, &orbit);
    for (a, b) in sum.amplitude.iter().zip(&st.amplitude) {
        assert!((a - b).abs() < 1e-8 * b, "{f} Hz: orbit {a} vs simulation {b}");
    }
    let scale = u0.amax();
    assert!((&orbit.u - &u0).amax() < 1e-8 * scale, "{f} Hz: section states differ by {:e}", (&orbit.u - &u0).amax());
}

#[test]
fn sdof_orbits_equal_long_sdof_simulations() {
    let d = [Damper::new(1, 0.071, Clearance::from_m(0.4e-3))];
    let e = EquivalentSdof::new(&paper(), &d, 2, 0, 2.6);
    let sys = System::plastic(e.structure(), vec![e.damper()], 0, e.force);
    for f in [48.0, 49.0, 51.0] {
        orbit_against_simulation(&sys, f);
    }
}

#[test]
fn mdof_orbits_equal_long_mdof_simulations() {
    let sys = System::plastic(paper(), vec![Damper::new(1, 0.071, Clearance::from_m(0.4e-3))], 0, 2.6);
    for f in [48.0, 49.0] {
        orbit_against_simulation(&sys, f);
    }
}

#[test]
fn newton_converges_quadratically() {
    let sys = System::plastic(paper(), vec![Damper::new(1, 0.071, Clearance::from_m(0.4e-3))], 0, 2.6);
    let d = Dynamics::new(&sys, 2.0 * PI * 49.0).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    let (problem, u0) = seed(&d, &st.final_state, 1, 1e-4, d.omega, false).unwrap();
    let orbit = solve(&problem, &d, &u0, &NewtonOptions::default()).unwrap();
    // One Newton step from the orbit displaced by eps along a fixed direction: the residual
    // after the step scales as eps^order.
    let one_step = NewtonOptions { tol: 0.0, max_iter: 1, ..NewtonOptions::default() };
    let after = |eps: f64| -> (f64, f64) {
        let guess = orbit.u.add_scalar(eps);
        match solve(&problem, &d, &guess, &one_step) {
            Err(shotdamp::sim::orbits::periodic::OrbitError::NoConvergence(r)) => (r[0], r[1]),
            other => panic!("{other:?}"),
        }
    };
    let steps: Vec<(f64, f64)> = [1e-2, 1e-3, 1e-4].iter().map(|&e| after(e)).collect();
    for w in steps.windows(2) {
        let before = (w[0].0 / w[1].0).log10();
        let order = (w[0].1 / w[1].1).log10() / before;
        assert!((before - 1.0).abs() < 0.05, "the starting residual is linear in eps: {steps:?}");
        assert!(order > 1.9 && order < 2.1, "order {order}: (residual before, after one step) {steps:?}");
    }
}

fn ball(gamma: f64, restitution: f64) -> Result<Dynamics, SetupError> {
    common::bouncing_ball(gamma, restitution)
}

/// The period-1 orbit of the ball at `gamma`, seeded by a long simulation.
fn ball_orbit(gamma: f64, restitution: f64) -> (Problem, DVector<f64>, Dynamics) {
    let d = ball(gamma, restitution).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions { max_periods: 400, ..SteadyOptions::default() });
    let amp = gamma * GRAVITY / d.omega.powi(2);
    let (problem, u) = seed(&d, &st.final_state, 1, amp, d.omega, restitution > 0.0).unwrap();
    (problem, u, d)
}

#[test]
fn plastic_ball_sticks_below_sqrt_1_plus_pi2_and_not_above() {
    let boundary = (1.0 + PI * PI).sqrt();
    for gamma in [1.5, 2.5, 3.2, boundary - 0.005, boundary + 0.005, 3.5] {
        let (problem, u, d) = ball_orbit(gamma, 0.0);
        assert_eq!(problem.returns, 1, "Gamma {gamma}: one impact per period");
        let orbit = solve(&problem, &d, &u, &NewtonOptions::default()).unwrap();
        assert!(orbit.stable, "Gamma {gamma}: {:?}", orbit.multipliers);
        let sum = summarize(&d, &problem, &orbit);
        let tau0 = sum.tau0.unwrap();
        if gamma < boundary {
            // Rests on the table after landing, lifts off where the table's acceleration is -g.
            assert!(tau0 > 1e-3, "Gamma {gamma}: sticks for {tau0} rad");
        } else {
            assert!(tau0 < 1e-9, "Gamma {gamma}: leaves at once ({tau0} rad)");
        }
    }
}

fn ball_family(restitution: f64) -> impl Fn(f64) -> Result<Dynamics, SetupError> + Sync {
    move |gamma| ball(gamma, restitution)
}

fn options(p_min: f64, p_max: f64) -> ContinuationOptions {
    common::ball_continuation(p_min, p_max)
}

fn period_doubling(branch: &shotdamp::sim::orbits::continuation::Branch) -> Option<f64> {
    branch.special.iter().find_map(|s| if let Special::PeriodDoubling { p } = s { Some(*p) } else { None })
}

fn fold(branch: &shotdamp::sim::orbits::continuation::Branch) -> Option<f64> {
    branch.special.iter().find_map(|s| if let Special::Fold { p } = s { Some(*p) } else { None })
}

#[test]
fn plastic_ball_period_doubles_at_sqrt_pi2_plus_4() {
    let (problem, u, _) = ball_orbit(3.5, 0.0);
    let family = ball_family(0.0);
    let branch = continue_branch(&family, problem, 3.5, &u, true, &options(3.5, 3.9)).unwrap();
    let pd = period_doubling(&branch).unwrap_or_else(|| panic!("no period doubling: end {:?}", branch.end));
    let expected = (PI * PI + 4.0).sqrt();
    assert!((pd - expected).abs() < 1e-3, "period doubling at {pd}, expected {expected}");
}

/// The period-1 orbit of the ball with restitution from its closed form: it leaves the table
/// at u+ = g T / 2 and lands a period later at -g T / 2, so the table's velocity at impact is
/// V = g T (1 - e) / (2 (1 + e)) = A omega cos(theta): cos(theta) = Gamma_1 / Gamma.
fn restitution_guess(gamma: f64, e: f64) -> (Problem, DVector<f64>) {
    let d = ball(gamma, e).unwrap();
    let omega = d.omega;
    let h = receptance(&d.system.structure, &d.system.structure.mass_matrix(), 0, omega).unwrap()[0];
    let g1 = PI * (1.0 - e) / (1.0 + e);
    // The table moves as A sin(omega t + arg H); take the impact where it decelerates.
    let theta = (g1 / gamma).acos();
    let t0 = (theta - h.arg()).rem_euclid(2.0 * PI) / omega;
    let (x, v) = d.particular(0, t0);
    let amp = gamma * GRAVITY / (omega * omega);
    let period = 2.0 * PI / omega;
    let w = GRAVITY * period / 2.0 - v[0];
    let problem = Problem { returns: 1, periods: 1, length: amp, rate: omega, bounce: true };
    (problem, DVector::from_vec(vec![omega * t0, x[0] / amp, v[0] / (amp * omega), w / (amp * omega)]))
}

#[test]
// The expected values are the closed forms evaluated to 5 decimals (1.04720 is pi / 3).
#[allow(clippy::approx_constant)]
fn ball_with_restitution_exists_from_gamma_1_and_period_doubles_at_gamma_pd() {
    for (e, g1, gpd) in [(0.5, 1.04720, 1.52682), (0.3, 1.69163, 2.12733)] {
        let start = 0.5 * (g1 + gpd);
        let (problem, u) = restitution_guess(start, e);
        let family = ball_family(e);
        let d = ball(start, e).unwrap();
        let orbit = solve(&problem, &d, &u, &NewtonOptions::default()).unwrap();
        assert!(orbit.stable, "e = {e}, Gamma {start}: {:?}", orbit.multipliers);
        let up = continue_branch(&family, problem, start, &orbit.u, true, &options(0.5 * g1, 1.2 * gpd)).unwrap();
        let pd = period_doubling(&up).unwrap_or_else(|| panic!("e = {e}: no period doubling, end {:?}", up.end));
        assert!((pd - gpd).abs() < 1e-3, "e = {e}: period doubling at {pd}, expected {gpd}");
        let down = continue_branch(&family, problem, start, &orbit.u, false, &options(0.5 * g1, 1.2 * gpd)).unwrap();
        let f = fold(&down).unwrap_or_else(|| panic!("e = {e}: no fold, end {:?}", down.end));
        assert!((f - g1).abs() < 1e-3, "e = {e}: the orbit exists from {f}, expected {g1}");
    }
}
