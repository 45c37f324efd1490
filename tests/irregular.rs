//! Irregular motion classified and measured (docs/simulator.md, "Irregular motion"): the
//! largest Lyapunov exponent from the exact tangent flow against a second method, on a torus
//! and on a periodic orbit against its Floquet multiplier; the statistic against a record ten
//! times longer; the energy balance over an irregular record.

use std::f64::consts::PI;

use shotdamp::model::{Clearance, Damper};
use shotdamp::sim::settle::irregular::measure;
use shotdamp::sim::settle::statistic::{Measure, Motion};
use shotdamp::sim::{steady_state, Bed, Dynamics, Engine, Quiet, State, SteadyOptions, System};

use crate::common::paper;

/// A point run for `periods` periods without looking for an orbit, then measured.
fn measured(d: &Dynamics, periods: usize, m: Measure) -> shotdamp::sim::Steady {
    let opts = SteadyOptions {
        method: shotdamp::sim::settle::steady::SteadyMethod::Transient,
        tol: 0.0,
        max_periods: periods,
        min_periods: periods,
        measure: m,
        ..SteadyOptions::default()
    };
    let st = shotdamp::sim::settle::transient::transient_steady(d, State::at_rest(d), &opts);
    measure(d, st, &opts)
}

/// A 1 kg table with a bed of `ratio` of its mass, restitution `e`, driven at 10 Hz to a bare
/// acceleration amplitude `gamma` g.
fn heavy_ball(gamma: f64, e: f64, ratio: f64) -> Dynamics {
    use shotdamp::model::{frf::receptance, Clearance, Damper, Damping, Structure, GRAVITY};
    let omega = 2.0 * PI * 10.0;
    let host = Structure::chain(&[1.0], &[1e3], Damping::ModalRatios(vec![0.05]));
    let h = receptance(&host, &host.mass_matrix(), 0, omega).expect("receptance")[0];
    let force = gamma * GRAVITY / (omega * omega) / h.norm();
    let sys = shotdamp::sim::System::plastic(host, vec![Damper::new(0, ratio, Clearance::NO_TOP)], 0, force)
        .with_law(shotdamp::sim::motion::bed::ImpactLaw::with_restitution(e, 1e-3));
    Dynamics::new(&sys, omega).unwrap()
}

/// The weighted distance of two states of one bed system (velocities over omega; the bed's
/// position and velocity at the states' common time).
fn separation(d: &Dynamics, a: &State, b: &State) -> (Vec<f64>, f64) {
    let w = d.omega;
    let (ya, ua) = a.bed_motion(d, 0);
    let (yb, ub) = b.bed_motion(d, 0);
    let v = vec![b.x[0] - a.x[0], (b.v[0] - a.v[0]) / w, yb - ya, (ub - ua) / w];
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    (v, n)
}

/// (a) The exponent of a chaotic point from the tangent flow (saltation matrices at impacts)
/// against a second method that uses no derivative: two trajectories 1e-9 m apart, the
/// distance renormalised every period (Benettin et al. 1980), over the same 2000 periods.
#[test]
fn the_exponent_of_chaos_agrees_with_two_nearby_trajectories() {
    let d = heavy_ball(5.0, 0.8, 0.2);
    let m = Measure::periods(2000, 0.0);
    let st = measured(&d, 200, m);
    let got = st.measured.clone().unwrap();
    assert_eq!(st.motion, Motion::Chaotic, "{got:?}");
    assert!(got.lyapunov - got.lyapunov_half_width > 1.0, "{got:?}");
    // The same record again, with a neighbour.
    let opts = SteadyOptions {
        method: shotdamp::sim::settle::steady::SteadyMethod::Transient,
        tol: 0.0,
        max_periods: 200,
        min_periods: 200,
        ..SteadyOptions::default()
    };
    let start = shotdamp::sim::settle::transient::transient_steady(&d, State::at_rest(&d), &opts).final_state;
    let (engine, period, delta) = (Engine::new(&d), 2.0 * PI / d.omega, 1e-9);
    let mut a = start.clone();
    let mut dir = [1.0, 1.0, 1.0, 1.0].map(|x: f64| x / 2.0);
    let (mut sum, mut k) = (0.0, (a.t / period).round());
    let (discarded, periods) = (got.discarded, got.discarded + got.periods);
    for i in 0..periods {
        let mut b = a.clone();
        b.x[0] += delta * dir[0];
        b.v[0] += delta * dir[1] * d.omega;
        if let Bed::Free { .. } = a.beds[0] {
            let (y, u) = a.bed_motion(&d, 0);
            b.beds[0] = Bed::Free { t0: a.t, y0: y + delta * dir[2], u0: u + delta * dir[3] * d.omega };
        }
        k += 1.0;
        engine.advance(&mut a, k * period, &mut Quiet).unwrap();
        engine.advance(&mut b, k * period, &mut Quiet).unwrap();
        let (v, n) = separation(&d, &a, &b);
        if i >= discarded {
            sum += (n / delta).ln();
        }
        dir = [v[0] / n, v[1] / n, v[2] / n, v[3] / n];
    }
    let second = sum / (got.periods as f64 * period);
    assert!(
        (second - got.lyapunov).abs() <= got.lyapunov_half_width,
        "two trajectories {second:.4}/s, tangent {:.4} +- {:.4}/s",
        got.lyapunov,
        got.lyapunov_half_width
    );
}

/// A record too short for two batches gives no interval, and no class: the chaotic point of
/// (a) measured over 24 periods (18 kept after the alignment) is unclassified, its statistic
/// stated without an interval; over 2000 it is chaos again. Before the class existed such a
/// record was called quasi-periodic or a transient by an interval it did not have.
#[test]
fn a_record_too_short_for_an_interval_is_unclassified() {
    let d = heavy_ball(5.0, 0.8, 0.2);
    let short = measured(&d, 200, Measure::periods(24, 0.0));
    let got = short.measured.clone().unwrap();
    assert_eq!(short.motion, Motion::Unclassified, "{got:?}");
    assert!(got.periods < 2 * shotdamp::sim::settle::statistic::MIN_BATCH, "{got:?}");
    assert!(got.lyapunov.is_finite() && got.lyapunov_half_width.is_nan(), "{got:?}");
    assert!(got.statistic[0].is_finite() && got.half_width[0].is_nan(), "{got:?}");
    let long = measured(&d, 200, Measure::periods(2000, 0.0));
    assert_eq!(long.motion, Motion::Chaotic, "{:?}", long.measured);
}

/// (b) On a torus (Fig. 8's stated chain, one bed on m1 at 33.6 Hz, recognised as one by the
/// orbit search) the exponent is indistinguishable from 0.
#[test]
fn a_torus_has_an_exponent_indistinguishable_from_zero() {
    let m = [0.74, 0.71, 0.64];
    let sys = System::plastic(paper(), vec![Damper::new(0, 0.1 * m[0], Clearance::NO_TOP)], 0, 2.6);
    let d = Dynamics::new(&sys, 2.0 * PI * 33.6).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    let got = st.measured.clone().expect("measured");
    assert!(matches!(st.failure, Some(shotdamp::sim::settle::steady::NoSteady::Torus { .. })), "{:?}", st.failure);
    assert_eq!(st.motion, Motion::QuasiPeriodic, "{got:?}");
    assert!(got.lyapunov.abs() <= got.lyapunov_half_width, "{got:?}");
    // A record five times longer narrows the interval around 0: under 0.5 % of growth or decay
    // a period (a periodic orbit of this chain decays by about 2 % a period, chaos grows by
    // tens of per cent).
    let opts = SteadyOptions { measure: Measure::periods(2000, 0.0), ..SteadyOptions::default() };
    let long = measure(&d, shotdamp::sim::Steady { measured: None, ..st.clone() }, &opts).measured.unwrap();
    let period = 2.0 * PI / d.omega;
    assert!(long.lyapunov.abs() <= long.lyapunov_half_width, "{long:?}");
    assert!(long.lyapunov_half_width * period < 5e-3, "{long:?}");
}

/// (c) On a stable periodic orbit the exponent is the log of the largest Floquet multiplier's
/// modulus over the orbit's period (the paper's chain, one bed on m2 at 44 Hz).
#[test]
fn on_a_periodic_orbit_the_exponent_is_the_floquet_multipliers() {
    let m = [0.74, 0.71, 0.64];
    let sys = System::plastic(paper(), vec![Damper::new(1, 0.1 * m[1], Clearance::NO_TOP)], 0, 2.6);
    for f in [52.0, 44.0, 40.0] {
        let d = Dynamics::new(&sys, 2.0 * PI * f).unwrap();
        let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
        let cert = st.certificate.clone().expect("a certified orbit");
        let floquet = cert.spectral_radius().ln() / (st.period as f64 * 2.0 * PI / d.omega);
        // Measured as if it had not settled: from the orbit, over the default record.
        let opts = SteadyOptions { measure: Measure::periods(2000, 0.0), ..SteadyOptions::default() };
        let again = measure(&d, shotdamp::sim::Steady { converged: false, certificate: None, ..st }, &opts);
        let got = again.measured.clone().unwrap();
        assert_eq!(again.motion, Motion::Transient, "{f} Hz: contracting: {got:?}");
        // Within its interval, which is narrow: the structure's slowest decay (a damped mode,
        // -0.79/s) is told from a torus (0) and from chaos (> 0).
        assert!(
            (got.lyapunov - floquet).abs() <= got.lyapunov_half_width && got.lyapunov_half_width < 0.3 * floquet.abs(),
            "{f} Hz: exponent {:.5} +- {:.5}/s, Floquet {floquet:.5}/s",
            got.lyapunov,
            got.lyapunov_half_width
        );
    }
}

/// (d) The statistic of a chaotic point agrees within its interval with that of a record ten
/// times longer; (f) the energy put in by the force equals what the damping and the impacts
/// took plus the change in stored energy over the irregular record.
#[test]
fn the_statistic_of_chaos_is_that_of_a_ten_times_longer_record_and_energy_balances() {
    let d = heavy_ball(5.0, 0.8, 0.2);
    let short = measured(&d, 200, Measure::periods(2000, 0.0)).measured.unwrap();
    let long = measured(&d, 200, Measure::periods(20_000, 0.0)).measured.unwrap();
    let (a, b) = (short.statistic[0], long.statistic[0]);
    assert!(
        (a - b).abs() <= short.half_width[0],
        "{a:e} +- {:e} against {b:e} +- {:e}",
        short.half_width[0],
        long.half_width[0]
    );
    // The long interval is narrower (about sqrt(10)).
    assert!(long.half_width[0] < 0.6 * short.half_width[0], "{short:?} {long:?}");
    assert!(long.largest[0] >= short.largest[0] * 0.999);
    let opts = SteadyOptions {
        method: shotdamp::sim::settle::steady::SteadyMethod::Transient,
        tol: 0.0,
        max_periods: 200,
        min_periods: 200,
        energy: true,
        measure: Measure::periods(1000, 0.0),
        ..SteadyOptions::default()
    };
    let st = shotdamp::sim::settle::transient::transient_steady(&d, State::at_rest(&d), &opts);
    let st = measure(&d, st, &opts);
    let e = st.energy.expect("energy terms");
    assert_eq!(st.recorded_periods, 1000);
    assert!(e.impact > 0.1 * e.work, "{e:?}");
    assert!(e.relative_residual() < 1e-9, "{e:?}: {:e}", e.relative_residual());
}

/// A design's hand-over ([`Measure::handed_over`]): a torus handed to the measurement after 100
/// periods is measured within the steady state's one budget, at a fraction of the cost of the
/// measurement after the whole search, and its statistic agrees with that one within their
/// intervals; a point whose orbit the search had not found when it was handed over (after 5
/// periods, before its first attempt) is handed back when its exponent shows it contracts, and
/// the search then finds the orbit the search alone finds.
#[test]
fn a_point_handed_over_early_gives_the_same_answer_within_one_budget() {
    let m = [0.74, 0.71, 0.64];
    let sys = System::plastic(paper(), vec![Damper::new(0, 0.1 * m[0], Clearance::NO_TOP)], 0, 2.6);
    let d = Dynamics::new(&sys, 2.0 * PI * 33.6).unwrap();
    let whole = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    let opts = SteadyOptions { measure: Measure::handed_over(100, 0.01), ..SteadyOptions::default() };
    let early = steady_state(&d, State::at_rest(&d), &opts);
    let (a, b) = (whole.measured.clone().unwrap(), early.measured.clone().expect("measured"));
    assert_eq!(early.motion, Motion::QuasiPeriodic, "{b:?}");
    let spent = |s: &shotdamp::sim::Steady, x: &shotdamp::sim::settle::statistic::Measured| {
        s.transient_periods - x.discarded + s.recorded_periods
    };
    assert!(spent(&early, &b) <= opts.max_periods, "{} periods", spent(&early, &b));
    assert!(2 * spent(&early, &b) < spent(&whole, &a), "{} against {}", spent(&early, &b), spent(&whole, &a));
    for i in 0..3 {
        let (x, y) = (a.statistic[i], b.statistic[i]);
        assert!(
            (x - y).abs() <= a.half_width[i] + b.half_width[i],
            "m{}: {x:e} +- {:e} against {y:e} +- {:e}",
            i + 1,
            a.half_width[i],
            b.half_width[i]
        );
    }
    let sys = System::plastic(paper(), vec![Damper::new(1, 0.1 * m[1], Clearance::NO_TOP)], 0, 2.6);
    for f in [52.0, 44.0, 40.0] {
        let d = Dynamics::new(&sys, 2.0 * PI * f).unwrap();
        let plain = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
        let opts = SteadyOptions { measure: Measure::handed_over(5, 0.01), ..SteadyOptions::default() };
        let handed = steady_state(&d, State::at_rest(&d), &opts);
        assert!(
            plain.converged && handed.converged,
            "{f} Hz: {:?} {:?} {:?} plain {}",
            handed.failure,
            handed.motion,
            handed.measured,
            plain.transient_periods
        );
        assert_eq!((handed.motion, handed.period), (Motion::Periodic, plain.period), "{f} Hz");
        // Handed back after at least ALIGN + STEP periods of the measurement.
        assert!(
            handed.transient_periods > 150,
            "{f} Hz: handed back after the measurement: {}",
            handed.transient_periods
        );
        for i in 0..3 {
            let (x, y) = (plain.amplitude[i], handed.amplitude[i]);
            assert!((x - y).abs() <= 1e-9 * x, "{f} Hz, m{}: {x:e} against {y:e}", i + 1);
        }
    }
}

/// The 20-storey frame of `examples/tall/frame20.toml`, at its damped mode-1 peak and two
/// points that never settle (one near each mode): every point with shot has a class, and
/// either a certified orbit or a statistic with a finite interval from a stated number of
/// measured periods; a chaotic point's exponent interval lies above 0.
#[test]
fn every_point_of_the_twenty_storey_frame_is_an_answer() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(crate::common::repo().join("examples/tall/frame20.toml")).unwrap();
    let start = text.find("freq_hz = [").unwrap();
    let end = start + text[start..].find(']').unwrap() + 1;
    let file = dir.path().join("frame20.toml");
    std::fs::write(&file, format!("{}freq_hz = [1.875, 2.15, 5.75]{}", &text[..start], &text[end..])).unwrap();
    let out =
        crate::common::shotdamp().arg("run").arg(&file).arg("--out").arg(dir.path().join("out")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.path().join("out/frame_20_storey/data/compliance.csv")).unwrap();
    let rows = crate::common::csv_rows(&csv);
    let col = |name: &str| rows[0].iter().position(|c| c == name).unwrap();
    let shot: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[col("curve")] == "top3_20").collect();
    assert_eq!(shot.len(), 3);
    let mut chaotic = 0;
    for r in shot {
        let num = |name: &str| r[col(name)].parse::<f64>().unwrap();
        match r[col("motion")].as_str() {
            "periodic" => assert_eq!(r[col("converged")], "1", "{r:?}"),
            "chaotic" => {
                chaotic += 1;
                assert!(num("c20_half_width").is_finite() && num("c20_half_width") > 0.0, "{r:?}");
                assert!(num("c20_half_width") < 0.1 * num("c20"), "{r:?}");
                assert!(num("measured_periods") >= 400.0, "{r:?}");
                assert!(num("lyapunov_per_s") - num("lyapunov_half_width") > 0.0, "{r:?}");
            }
            other => panic!("an unexpected class {other}: {r:?}"),
        }
    }
    assert_eq!(chaotic, 2, "2.15 Hz and 5.75 Hz never settle on this frame");
}

/// Coverage: do the 95 % intervals hold the value they estimate about 95 % of the time? On
/// the chaotic point of the six-storey frame of `designs/six_storey.toml` (all its shot on
/// the roof at 20 mm, 5 N at 5.3 Hz), the roof's per-period amplitudes over 100,000 periods
/// after 200 from rest, as a measurement records them; the 95th percentile of all of them
/// (its own interval about a tenth of a short record's) is the value. The run cut into 250
/// records of 400 periods, each judged as the measurement judges its shortest kept record (20
/// batch percentiles): between 90 % and 99 % of the intervals hold the value (the binomial
/// spread of 250 records at 95 % is 1.4 %); records of 38 periods, judged in the
/// measurement's batches of at least 10 periods, hold it in 85-97 % (in 20 batches of one or
/// two periods they would hold it in under 70 %). `cargo run --release --example interval_coverage`
/// prints the table for more record lengths and batch counts and for a second motion,
/// on which the shortest records' intervals hold less often (docs/simulator.md).
#[test]
fn the_intervals_of_a_chaotic_point_hold_its_long_run_statistic_at_their_stated_rate() {
    use shotdamp::sim::motion::observe::{Extrema, Observe};
    use shotdamp::sim::settle::statistic::{batch_quantile, batch_quantile_in, quantile, BATCHES, PERCENTILE};
    let d = crate::common::six_storey_roof(5.3);
    let (engine, period) = (Engine::new(&d), 2.0 * PI / d.omega);
    let mut s = State::at_rest(&d);
    engine.advance(&mut s, 200.0 * period, &mut Quiet).expect("the transient runs");
    let amplitudes: Vec<f64> = (201..=100_200)
        .map(|k| {
            let mut e = Extrema::observing(6, 1, Observe::only([5]));
            engine.advance(&mut s, k as f64 * period, &mut e).expect("the record runs");
            e.amplitudes()[5]
        })
        .collect();
    let value = quantile(&amplitudes, PERCENTILE);
    let records: Vec<&[f64]> = amplitudes.chunks_exact(400).collect();
    let held = records
        .iter()
        .filter(|r| {
            let (s, h) = batch_quantile(r, PERCENTILE);
            (s - value).abs() <= h
        })
        .count();
    let rate = held as f64 / records.len() as f64;
    assert!((0.90..=0.99).contains(&rate), "{held} of {} intervals hold {value:e}", records.len());
    // Short records (a small budget: 38 kept periods) are cut into batches of at least 10
    // periods (3 here), and their intervals hold the value about as often (89.7 % over 400,000
    // periods); cut into 20 batches of one or two periods they held it in 58 %.
    let short: Vec<&[f64]> = amplitudes.chunks_exact(38).collect();
    let rate = |batches: Option<usize>| {
        let held = short
            .iter()
            .filter(|r| {
                let (s, h) = match batches {
                    Some(b) => batch_quantile_in(r, PERCENTILE, b),
                    None => batch_quantile(r, PERCENTILE),
                };
                (s - value).abs() <= h
            })
            .count();
        held as f64 / short.len() as f64
    };
    let (now, twenty) = (rate(None), rate(Some(BATCHES)));
    assert!((0.85..=0.97).contains(&now), "short records: {now}");
    assert!(twenty < 0.7, "short records in 20 batches: {twenty}");
}
