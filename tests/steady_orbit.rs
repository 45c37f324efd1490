//! Steady states as periodic orbits of the stroboscopic map, for any number of beds: the exact
//! Jacobian against central differences, linear limits against the structure's eigenvalues,
//! one-bed orbits against the impact-section solver, the bouncing ball's period doubling, and
//! the orbits against long transient runs.

use crate::common;
use crate::common::paper_with as paper;

use shotdamp::model::Clearance;
use std::f64::consts::PI;

use num_complex::Complex64;
use shotdamp::model::Damper;
use shotdamp::sim::orbits::continuation::{continue_branch, Special};
use shotdamp::sim::orbits::periodic::{fd_jacobian, multipliers, seed, solve, summarize, NewtonOptions, Section};
use shotdamp::sim::orbits::strobe::Strobe;
use shotdamp::sim::settle::steady::SteadyMethod;
use shotdamp::sim::{steady_state, Dynamics, SetupError, State, SteadyOptions, System};

fn system(hosts: &[usize], clearance: f64, zeta: f64) -> System {
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_m(clearance))).collect();
    System::plastic(paper(zeta), dampers, 0, 2.6)
}

fn orbit_point(sys: &System, f: f64) -> (Dynamics, shotdamp::sim::Steady) {
    let d = Dynamics::new(sys, 2.0 * PI * f).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    (d, st)
}

/// The section through a certified orbit, and its coordinates.
fn section(d: &Dynamics, st: &shotdamp::sim::Steady) -> (Strobe, nalgebra::DVector<f64>) {
    st.section(d).expect("a certified orbit")
}

#[test]
fn exact_jacobian_equals_central_differences() {
    // Three beds without top; one bed with a top it reaches; three beds with tops.
    for (sys, f) in [
        (system(&[0, 1, 2], f64::INFINITY, 0.01), 49.5),
        (system(&[1], 0.5e-3, 0.01), 48.2),
        (system(&[0, 1, 2], 0.35e-3, 0.01), 49.0),
        (system(&[0, 1, 2], 0.2e-3, 0.002), 50.0),
    ] {
        let (d, st) = orbit_point(&sys, f);
        assert!(st.converged, "{f} Hz: {:?}", st.failure);
        let (strobe, u) = section(&d, &st);
        let base = strobe.map(&d, &u).unwrap();
        let (exact, smooth) = base.jacobian.clone().unwrap();
        assert!(smooth);
        let (fd, fd_smooth) = fd_jacobian(&strobe, &d, &u, &base).unwrap();
        assert!(fd_smooth, "{f} Hz: the differences keep the events");
        let scale = exact.amax();
        let diff = (&exact - &fd).amax();
        assert!(diff < 1e-6 * scale, "{f} Hz: |J - J_fd| = {diff:e} against |J| = {scale:e}");
    }
}

/// With zero clearance the beds are rigidly attached: the map is linear and its multipliers
/// are exp(lambda_r T) of the structure with the beds' masses added.
#[test]
fn linear_multipliers_are_exponentials_of_the_eigenvalues() {
    for zeta in [0.01, 0.002] {
        let sys = system(&[0, 1, 2], 0.0, zeta);
        let (d, st) = orbit_point(&sys, 40.0);
        assert!(st.converged && st.period == 1);
        let cert = st.certificate.unwrap();
        assert_eq!(cert.multipliers.len(), 6);
        let t = 2.0 * PI / d.omega;
        let mut expected: Vec<Complex64> = (0..6)
            .map(|r| {
                let cfg = &d.configs[7];
                let k = r / 2;
                let l = if r % 2 == 0 { cfg.modes.lambda[k] } else { cfg.modes.lambda[k].conj() };
                (l * t).exp()
            })
            .collect();
        expected.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(a.im.total_cmp(&b.im)));
        let mut got = cert.multipliers.clone();
        got.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(a.im.total_cmp(&b.im)));
        for (a, b) in got.iter().zip(&expected) {
            assert!((a - b).norm() < 1e-9, "zeta {zeta}: multiplier {a} against exp(lambda T) = {b}");
        }
        assert!(cert.residual < 1e-10, "a linear map is solved in one step: residual {:e}", cert.residual);
    }
}

/// One bed: the stroboscopic orbit is the orbit of the impact section (another section,
/// another solver) to 1e-9.
#[test]
fn one_bed_orbits_equal_impact_section_orbits() {
    for (clearance, f) in [(0.4e-3, 48.0), (0.4e-3, 49.0), (f64::INFINITY, 49.5)] {
        let sys = system(&[1], clearance, 0.01);
        let (d, st) = orbit_point(&sys, f);
        assert!(st.converged && st.period == 1, "{f} Hz: {:?}", st.failure);
        let (problem, u0) = seed(&d, &st.final_state, 1, st.amplitude[1], d.omega, false).unwrap();
        let orbit = solve(&problem, &d, &u0, &NewtonOptions::default()).unwrap();
        let sum = summarize(&d, &problem, &orbit);
        for (a, b) in sum.amplitude.iter().zip(&st.amplitude) {
            assert!((a - b).abs() < 1e-9 * b, "{f} Hz: impact section {a} against stroboscopic {b}");
        }
        // The same multipliers up to the extra zero ones of the larger section.
        let cert = st.certificate.unwrap();
        let r_impact = orbit.spectral_radius();
        assert!((cert.spectral_radius() - r_impact).abs() < 1e-7, "{} vs {r_impact}", cert.spectral_radius());
    }
}

/// A 1000 kg table driven to amplitude A = Gamma g / omega^2 with a 1 microgram plastic bed.
fn ball(gamma: f64) -> Result<Dynamics, SetupError> {
    bouncing_ball(gamma, 0.0)
}

fn bouncing_ball(gamma: f64, e: f64) -> Result<Dynamics, SetupError> {
    common::bouncing_ball(gamma, e)
}

#[test]
fn bouncing_ball_period_doubles_on_the_stroboscopic_section() {
    let d = ball(3.5).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    assert!(st.converged && st.period == 1, "{:?}", st.failure);
    let (strobe, u) = section(&d, &st);
    let family = |g: f64| ball(g);
    let opts = common::ball_continuation(3.5, 3.9);
    let branch = continue_branch(&family, strobe, 3.5, &u, true, &opts).unwrap();
    let pd = branch
        .special
        .iter()
        .find_map(|s| if let Special::PeriodDoubling { p } = s { Some(*p) } else { None })
        .unwrap_or_else(|| panic!("no period doubling: end {:?}", branch.end));
    let expected = (PI * PI + 4.0).sqrt();
    assert!((pd - expected).abs() < 1e-3, "period doubling at {pd}, expected {expected}");
    // Past it the search reports the stable period-2 orbit.
    let d = ball(3.8).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    assert!(st.converged && st.period == 2, "period {} ({:?})", st.period, st.failure);
    let m = multipliers(&strobe_jacobian(&d, &st)).unwrap();
    assert!(m.iter().all(|z| z.norm() < 1.0));
}

fn strobe_jacobian(d: &Dynamics, st: &shotdamp::sim::Steady) -> nalgebra::DMatrix<f64> {
    let (strobe, u) = section(d, st);
    strobe.map(d, &u).unwrap().jacobian.unwrap().0
}

/// The orbit method against the transient method run long and tight, over the Fig. 8 and
/// Fig. 5 sweeps: wherever the transient settles, the compliances agree to 1e-7 and the orbit
/// is stable.
#[test]
fn orbits_equal_long_transients_over_the_fig8_and_fig5_sweeps() {
    let long =
        SteadyOptions { method: SteadyMethod::Transient, tol: 1e-10, max_periods: 20_000, ..SteadyOptions::default() };
    let orbit = SteadyOptions::default();
    let fig8: Vec<f64> = (0..=520).map(|i| ((80.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let fig5: Vec<f64> = (0..=120).map(|i| ((440.0 + i as f64) / 10.0 * 1e9).round() / 1e9).collect();
    let cases: Vec<(&str, System, &[f64])> = vec![
        ("Fig. 8 B", system(&[0], f64::INFINITY, 0.01), &fig8),
        ("Fig. 8 C", system(&[0, 1], f64::INFINITY, 0.01), &fig8),
        ("Fig. 8 D", system(&[0, 1, 2], f64::INFINITY, 0.01), &fig8),
        ("Fig. 5 single", system(&[1], 0.35e-3, 0.01), &fig5),
        ("Fig. 5 triple", system(&[0, 1, 2], 0.35e-3, 0.01), &fig5),
    ];
    for (name, sys, freqs) in cases {
        let a = shotdamp::sim::settle::sweep::from_rest(&sys, freqs, &long, &|| {});
        let b = shotdamp::sim::settle::sweep::from_rest(&sys, freqs, &orbit, &|| {});
        let mut compared = 0;
        for (p, q) in a.iter().zip(&b) {
            let (Ok(t), Ok(o)) = (&p.result, &q.result) else { panic!("{name} {} Hz: setup", p.freq_hz) };
            if !(t.converged && t.period >= 1) {
                continue;
            }
            assert!(
                o.converged,
                "{name} {} Hz: the transient settles, the orbit search fails: {:?}",
                p.freq_hz, o.failure
            );
            // The transient rule can name a multiple of the true period: a slowly decaying
            // complex multiplier pair makes samples k periods apart nearly repeat (Fig. 8 B at
            // 34.7 Hz: period 2, named 8 by the transient rule, amplitudes equal to 1e-11).
            assert!(t.period % o.period == 0, "{name} {} Hz: period {} against {}", p.freq_hz, o.period, t.period);
            let cert = o.certificate.as_ref().unwrap();
            assert!(cert.stable && cert.residual <= 1e-10, "{name} {} Hz: {cert:?}", p.freq_hz);
            for (x, y) in o.amplitude.iter().zip(&t.amplitude) {
                assert!((x - y).abs() <= 1e-7 * y, "{name} {} Hz: orbit {x} against transient {y}", p.freq_hz);
            }
            compared += 1;
        }
        assert!(compared * 10 >= freqs.len() * 9, "{name}: {compared} of {} points compared", freqs.len());
    }
}

/// The impact section's exact Jacobian (the return at an impact, whose time moves with the
/// start) against central differences: the full structure, the SDOF model, a bouncing bed.
#[test]
fn impact_section_jacobian_equals_central_differences() {
    use shotdamp::model::sdof::EquivalentSdof;
    let e = EquivalentSdof::new(&paper(0.01), &[Damper::new(1, 0.071, Clearance::from_m(0.5e-3))], 2, 0, 2.6);
    let sdof = System::plastic(e.structure(), vec![e.damper()], 0, e.force);
    let bouncy = bouncing_ball(1.3, 0.5).unwrap();
    for (name, d, bounce) in [
        ("3-mass, d = 0.4 mm", Dynamics::new(&system(&[1], 0.4e-3, 0.01), 2.0 * PI * 49.0).unwrap(), false),
        ("SDOF, d = 0.5 mm", Dynamics::new(&sdof, 2.0 * PI * 49.66).unwrap(), false),
        ("ball, e = 0.5, Gamma = 1.3", bouncy, true),
        // Above Gamma = sqrt(1 + pi^2) the plastic ball leaves the table at once after landing:
        // the start's phase column must follow the flow with the ball already free.
        ("plastic ball leaving at once, Gamma = 3.5", ball(3.5).unwrap(), false),
    ] {
        let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
        assert!(st.converged, "{name}: {:?}", st.failure);
        let length = st.amplitude.iter().copied().fold(0.0, f64::max);
        let (problem, u) = seed(&d, &st.final_state, st.period, length, d.omega, bounce).unwrap();
        let base = problem.map(&d, &u).unwrap();
        let (exact, _) = base.jacobian.clone().expect("the impact section's map gives its Jacobian");
        let (fd, fd_smooth) = fd_jacobian(&problem, &d, &u, &base).unwrap();
        assert!(fd_smooth, "{name}: the differences keep the events");
        let diff = (&exact - &fd).amax();
        assert!(
            diff < 1e-6 * exact.amax(),
            "{name}: |J - J_fd| = {diff:e} against |J| = {:e}\n{exact}{fd}",
            exact.amax()
        );
    }
}

/// The impact section's exact derivative in the forcing frequency (what continuation in
/// frequency needs beside the Jacobian) against central differences in omega at fixed start.
#[test]
fn impact_section_frequency_derivative_equals_central_differences() {
    use shotdamp::model::sdof::EquivalentSdof;
    let e = EquivalentSdof::new(&paper(0.01), &[Damper::new(1, 0.071, Clearance::from_m(0.5e-3))], 2, 0, 2.6);
    let sdof = System::plastic(e.structure(), vec![e.damper()], 0, e.force);
    for (name, d, bounce) in [
        ("3-mass, d = 0.4 mm", Dynamics::new(&system(&[1], 0.4e-3, 0.01), 2.0 * PI * 49.0).unwrap(), false),
        ("3-mass, d = 0.4 mm, 47 Hz", Dynamics::new(&system(&[1], 0.4e-3, 0.01), 2.0 * PI * 47.0).unwrap(), false),
        ("SDOF, d = 0.5 mm", Dynamics::new(&sdof, 2.0 * PI * 49.66).unwrap(), false),
        ("ball, e = 0.5, Gamma = 1.3", bouncing_ball(1.3, 0.5).unwrap(), true),
        ("plastic ball leaving at once, Gamma = 3.5", ball(3.5).unwrap(), false),
    ] {
        let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
        assert!(st.converged, "{name}: {:?}", st.failure);
        let length = st.amplitude.iter().copied().fold(0.0, f64::max);
        let (problem, u) = seed(&d, &st.final_state, st.period, length, d.omega, bounce).unwrap();
        let exact = problem.map(&d, &u).unwrap().d_omega.expect("the impact section's map gives dP/domega");
        let h = 1e-6 * d.omega;
        let image = |w: f64| problem.image(&d.at_omega(w).unwrap(), &u).unwrap();
        let fd = (image(d.omega + h) - image(d.omega - h)) / (2.0 * h);
        let diff = (&exact - &fd).amax();
        assert!(diff < 1e-6 * exact.amax(), "{name}: |dP/dw - fd| = {diff:e} against {:e}\n{exact}{fd}", exact.amax());
        // Not trivially zero: the phase row alone is about t_return.
        assert!(exact.amax() > 1e-3, "{name}: {exact}");
    }
}
