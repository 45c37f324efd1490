//! Moving supports (docs/model.md section 2.3): the supports accelerate as `A sin(omega t)`.
//! Verified by (1) the closed form of a bare oscillator on a shaken base; (2) a chain whose
//! damping is stiffness-proportional, which the moving ground pulls only through its first
//! spring and dashpot: the same motion as a force `k_1 (1 + i omega beta) X_g` on the first
//! mass, shifted in time by that force's phase (beds, impacts and Floquet multipliers
//! included), and the displacements relative to the supports read off that forced motion by
//! sampling; (3) the energy balance with the supports' work.

use std::f64::consts::PI;

use crate::common;

use nalgebra::DMatrix;
use num_complex::Complex64;
use shotdamp::model::{Clearance, Damper, Damping, Structure};
use shotdamp::sim::motion::observe::Sampler;
use shotdamp::sim::{steady_state, Dynamics, Engine, State, SteadyOptions, System};

/// `sys` with the supports moving at `accel` (m/s^2) instead of its force.
fn on_base(sys: System, accel: f64) -> System {
    sys.on_supports(accel)
}

#[test]
fn a_bare_oscillator_on_a_shaken_base_moves_as_the_closed_form() {
    // m u'' + c u' + k u = -m A sin(w t): |U| = A / |wn^2 - w^2 + 2 i zeta wn w|.
    let (m, fnat, zeta, accel) = (2.0, 20.0, 0.03, 3.0);
    let wn = 2.0 * PI * fnat;
    let s = Structure::from_matrices(&[m], DMatrix::from_element(1, 1, m * wn * wn), Damping::ModalRatios(vec![zeta]));
    let sys = on_base(System::plastic(s, Vec::new(), 0, 0.0), accel);
    for ratio in [0.5, 0.9, 1.0, 1.1, 2.0] {
        let w = ratio * wn;
        let dy = Dynamics::new(&sys, w).expect("dynamics");
        let st = steady_state(&dy, State::at_rest(&dy), &SteadyOptions::default());
        let closed = accel / Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w).norm();
        assert!(st.converged, "ratio {ratio}: {st:?}");
        assert!((st.amplitude[0] - closed).abs() < 1e-9 * closed, "ratio {ratio}: {} vs {closed}", st.amplitude[0]);
    }
}

/// The paper's chain with stiffness-proportional damping and a container on every mass.
fn chain(d_mm: f64) -> (Structure, Vec<Damper>) {
    let m = [0.74, 0.71, 0.64];
    let s = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::Rayleigh { alpha: 0.0, beta: 2e-5 });
    let dampers = (0..3).map(|h| Damper::new(h, 0.08 * m[h], Clearance::from_mm(d_mm))).collect();
    (s, dampers)
}

#[test]
fn a_chain_on_a_shaken_base_moves_as_under_the_equivalent_force_on_its_first_mass() {
    let (mut checked, mut worst) = (0, [0.0f64; 3]);
    // (clearance mm, frequency Hz, support acceleration m/s^2): near each mode.
    for (d_mm, f_hz, accel) in [(0.35, 13.0, 4.0), (0.35, 14.5, 4.0), (0.5, 37.0, 20.0), (0.5, 54.0, 25.0)] {
        let (s, dampers) = chain(d_mm);
        let w = 2.0 * PI * f_hz;
        let base = on_base(System::plastic(s.clone(), dampers.clone(), 0, 0.0), accel);
        // The ground pulls mass 1 with k1 (x_g + beta v_g): phasor k1 (1 + i w beta) X_g.
        let xg = -accel / (w * w);
        let pull = Complex64::new(24.3e3 * xg, 24.3e3 * 2e-5 * w * xg);
        let (amp, phase) = (pull.norm(), pull.arg());
        let forced = System::plastic(s, dampers, 0, amp);
        let (db, df) = (Dynamics::new(&base, w).expect("dynamics"), Dynamics::new(&forced, w).expect("dynamics"));
        let sb = steady_state(&db, State::at_rest(&db), &SteadyOptions::default());
        let sf = steady_state(&df, State::at_rest(&df), &SteadyOptions::default());
        let (Some(cb), Some(cf)) = (&sb.certificate, &sf.certificate) else {
            panic!("{f_hz} Hz: both certified: {:?} {:?}", sb.failure, sf.failure);
        };
        assert_eq!((sb.period, &sb.bottom_impacts, &sb.top_impacts), (sf.period, &sf.bottom_impacts, &sf.top_impacts));
        assert!(sb.bottom_impacts.iter().sum::<f64>() > 0.0, "{f_hz} Hz: impacts");
        // The same orbit: the multipliers do not see the shift.
        let mut gap = 0.0f64;
        for z in &cb.multipliers {
            let near = cf.multipliers.iter().map(|y| (z - y).norm()).fold(f64::INFINITY, f64::min);
            gap = gap.max(near / z.norm().max(1e-3));
        }
        worst[0] = worst[0].max(gap);
        assert!(gap < 1e-9, "{f_hz} Hz: {:?} vs {:?}", cb.multipliers, cf.multipliers);
        // The base's state at time t is the forced one's at t + phase / w: advance the forced
        // orbit there and compare displacements and velocities.
        let (sec, shift) = (&cb.section, phase / w);
        let mut s = cf.section.clone();
        let period = 2.0 * PI / w * sb.period as f64;
        let target = sec.t + shift + ((s.t - sec.t - shift) / period).ceil() * period;
        Engine::new(&df)
            .advance(&mut s, target, &mut shotdamp::sim::motion::observe::EventLog(Vec::new()))
            .expect("advance");
        let scale = sec.x.amax();
        worst[1] = worst[1].max((&s.x - &sec.x).amax() / scale);
        assert!((&s.x - &sec.x).amax() < 1e-10 * scale, "{f_hz} Hz: {} vs {}", s.x, sec.x);
        assert!((&s.v - &sec.v).amax() < 1e-10 * scale * w, "{f_hz} Hz: {} vs {}", s.v, sec.v);
        // The reported amplitude is relative to the supports: x_f(t) - X_g sin(w t - phase),
        // sampled densely over one period of the forced orbit.
        let samples = 40_000;
        let times: Vec<f64> = (0..=samples).map(|k| s.t + period * k as f64 / samples as f64).collect();
        let mut sampler = Sampler::new(times.clone());
        let mut s2 = s.clone();
        Engine::new(&df).advance(&mut s2, s.t + period, &mut sampler).expect("one period");
        for i in 0..3 {
            let rel: Vec<f64> = sampler.x.iter().zip(&times).map(|(x, t)| x[i] - xg * (w * t - phase).sin()).collect();
            let sampled = 0.5
                * (rel.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
                    - rel.iter().fold(f64::INFINITY, |a, &b| a.min(b)));
            worst[2] = worst[2].max((sb.amplitude[i] - sampled).abs() / sampled);
            // Sampling misses an extremum by at most (w dt)^2 / 8 = 3e-9 of the motion.
            assert!(
                (sb.amplitude[i] - sampled).abs() < 2e-8 * sampled,
                "{f_hz} Hz, mass {}: {} reported, {sampled} sampled",
                i + 1,
                sb.amplitude[i]
            );
        }
        checked += 1;
    }
    println!(
        "multipliers within {:.1e}, states within {:.1e}, relative amplitudes within {:.1e} of the sampled",
        worst[0], worst[1], worst[2]
    );
    assert_eq!(checked, 4);
}

#[test]
fn the_energy_balance_closes_with_the_supports_work() {
    let (s, dampers) = chain(0.35);
    let mut sys = on_base(System::plastic(s.with_damping(Damping::ModalRatios(vec![0.01; 3])), dampers, 0, 0.0), 5.0);
    sys.laws = vec![shotdamp::sim::motion::bed::ImpactLaw::with_restitution(0.4, 1e-3); 3];
    for f in [12.0, 13.5, 36.0] {
        let dy = Dynamics::new(&sys, 2.0 * PI * f).expect("dynamics");
        let st = steady_state(&dy, State::at_rest(&dy), &SteadyOptions { energy: true, ..SteadyOptions::default() });
        let e = st.energy.expect("energy");
        assert!(e.impact > 0.0 && e.relative_residual() < 1e-9, "{f} Hz: {e:?}");
    }
}

#[test]
fn a_bare_chain_s_drifts_and_floor_accelerations_on_a_shaken_base_are_the_closed_form() {
    // The drift u_i - u_(i-1) and the absolute acceleration u_i'' + a_g of each storey of a
    // bare chain against the complex response `(K - w^2 M + i w C)^-1 M r` (frf).
    let accel = 2.0;
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.02; 3]));
    assert!(s.is_chain());
    let sys = on_base(System::plastic(s.clone(), Vec::new(), 0, 0.0), accel);
    let opts = SteadyOptions { peaks: true, ..SteadyOptions::default() };
    let mut worst = 0.0f64;
    for f in [5.0, 13.0, 30.0, 36.8, 54.0, 90.0] {
        let w = 2.0 * PI * f;
        let dy = Dynamics::new(&sys, w).expect("dynamics");
        let st = steady_state(&dy, State::at_rest(&dy), &opts);
        let p = st.peaks.expect("peaks asked for");
        let closed = &shotdamp::model::frf::support_peaks_curve(&s, &s.mass_matrix(), &[w])[0];
        for i in 0..3 {
            for (got, want) in [(p.drift[i], accel * closed.0[i]), (p.acceleration[i], accel * closed.1[i])] {
                worst = worst.max((got - want).abs() / want);
                assert!((got - want).abs() < 1e-9 * want, "{f} Hz, storey {}: {got} vs {want}", i + 1);
            }
            // The first storey's drift is the first floor's displacement relative to the ground.
            assert_eq!(p.drift[0], st.amplitude[0]);
            // Harmonic motion: the peak is the amplitude.
            assert!((p.drift_peak[i] - p.drift[i]).abs() < 1e-9 * p.drift[i]);
        }
    }
    println!("drifts and absolute accelerations within {worst:.1e} of the closed form");
}

#[test]
fn with_beds_the_drifts_and_floor_accelerations_bound_a_dense_sampling_of_the_orbit() {
    // Impacts make the accelerations jump: the extremes found between events must hold every
    // sampled value and be reached by the samples to within a sample step's curvature.
    let opts = SteadyOptions { peaks: true, ..SteadyOptions::default() };
    // (clearance mm, frequency Hz, support acceleration m/s^2), near modes 1 and 2.
    for (d_mm, f, accel) in [(0.35, 13.0, 4.0), (0.5, 37.0, 20.0)] {
        let (s, dampers) = chain(d_mm);
        let sys = on_base(System::plastic(s, dampers, 0, 0.0), accel);
        let w = 2.0 * PI * f;
        let dy = Dynamics::new(&sys, w).expect("dynamics");
        let st = steady_state(&dy, State::at_rest(&dy), &opts);
        let (Some(c), Some(p)) = (&st.certificate, &st.peaks) else { panic!("{f} Hz: a certified orbit with peaks") };
        assert!(st.bottom_impacts.iter().sum::<f64>() > 0.0, "{f} Hz: impacts");
        let period = 2.0 * PI / w * st.period as f64;
        let samples = 40_000;
        let t0 = c.section.t;
        let times: Vec<f64> = (0..=samples).map(|k| t0 + period * k as f64 / samples as f64).collect();
        let mut sampler = Sampler::new(times.clone());
        let mut s2 = c.section.clone();
        Engine::new(&dy).advance(&mut s2, t0 + period, &mut sampler).expect("one period");
        let xg = |t: f64| -accel / (w * w) * (w * t).sin();
        let span = |v: &[f64]| {
            let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
            0.5 * (hi - lo)
        };
        for i in 0..3 {
            let rel = |k: usize, j: usize| sampler.x[k][j] - xg(times[k]);
            let drift: Vec<f64> =
                (0..times.len()).map(|k| rel(k, i) - if i > 0 { rel(k, i - 1) } else { 0.0 }).collect();
            let acc: Vec<f64> = sampler.a.iter().map(|a| a[i]).collect();
            // An extreme lies between two samples: the samples reach it to within the largest
            // change from one sample to the next.
            let step = |v: &[f64]| v.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max);
            for (what, found, q) in [("drift", p.drift[i], &drift), ("acceleration", p.acceleration[i], &acc)] {
                let sampled = span(q);
                assert!(
                    found >= sampled * (1.0 - 1e-12),
                    "{f} Hz storey {} {what}: {found} below sampled {sampled}",
                    i + 1
                );
                assert!(found - sampled <= step(q), "{f} Hz storey {} {what}: {found} vs sampled {sampled}", i + 1);
                // The drift is continuous: its samples are close (the acceleration jumps at events).
                assert!(what != "drift" || step(q) < 2e-3 * sampled, "{f} Hz storey {}: samples too coarse", i + 1);
            }
        }
    }
}

/// An experiment file on the paper's chain (stated values written out) whose supports
/// accelerate at `excitation`, with `analysis` and the bare case plus `case`'s dampers.
fn shaken_file(dir: &std::path::Path, id: &str, excitation: &str, analysis: &str, dampers: &str) -> std::path::PathBuf {
    let file = dir.join(format!("{id}.toml"));
    let text = format!(
        "[experiment]\nid = \"{id}\"\ntitle = \"t\"\nfigure = \"-\"\ncaption = \"c\"\nclaim = \"c\"\n\
         [structure]\nmasses_kg = [0.74, 0.71, 0.64]\nchain_stiffness_n_per_m = [24300.0, 21800.0, 19800.0]\n\
         [structure.damping]\nmodal_ratios = [0.01, 0.01, 0.01]\n[excitation]\n{excitation}\n[analysis]\n{analysis}\n\
         [[cases]]\nid = \"bare\"\nlabel = \"bare\"\ndampers = []\n[[cases]]\nid = \"shot\"\nlabel = \"shot\"\ndampers = [{dampers}]\n"
    );
    std::fs::write(&file, text).expect("write");
    file
}

/// `|(K - w^2 M + i w C)^-1 M 1|` of the paper's chain with `added` mass on mass 1..3,
/// written here without the library (modal damping from its own modes).
fn shaken_chain(added: [f64; 3], f_hz: f64) -> Vec<Complex64> {
    use nalgebra::{DMatrix, DVector, SymmetricEigen};
    let m0: [f64; 3] = [0.74, 0.71, 0.64];
    let k = [24300.0, 21800.0, 19800.0];
    let mut kk = DMatrix::<f64>::zeros(3, 3);
    for i in 0..3 {
        kk[(i, i)] += k[i];
        if i + 1 < 3 {
            kk[(i, i)] += k[i + 1];
            kk[(i, i + 1)] -= k[i + 1];
            kk[(i + 1, i)] -= k[i + 1];
        }
    }
    let bare = DMatrix::from_diagonal(&DVector::from_column_slice(&m0));
    // C = M Phi diag(2 zeta w) Phi^T M with Phi mass-normalised: from M^-1/2 K M^-1/2.
    let s = DMatrix::from_diagonal(&DVector::from_iterator(3, m0.iter().map(|m| 1.0 / m.sqrt())));
    let eig = SymmetricEigen::new(&s * &kk * &s);
    let phi = &s * &eig.eigenvectors;
    let z = DMatrix::from_diagonal(&DVector::from_iterator(3, eig.eigenvalues.iter().map(|l| 2.0 * 0.01 * l.sqrt())));
    let c = &bare * &phi * z * phi.transpose() * &bare;
    let m = DMatrix::from_diagonal(&DVector::from_iterator(3, (0..3).map(|i| m0[i] + added[i])));
    let w = 2.0 * PI * f_hz;
    let dyn_stiff = DMatrix::from_fn(3, 3, |i, j| Complex64::new(kk[(i, j)] - w * w * m[(i, j)], w * c[(i, j)]));
    let load = DVector::from_fn(3, |i, _| Complex64::new(m[(i, i)], 0.0));
    dyn_stiff.lu().solve(&load).expect("regular").iter().copied().collect()
}

/// `shotdamp COMMAND FILE --out OUT`, which must succeed, and the rows of its table `table`
/// (a path under `OUT`).
fn run_for_table(command: &str, file: &std::path::Path, out: &std::path::Path, table: &str) -> Vec<Vec<String>> {
    let o = common::shotdamp().arg(command).arg(file).arg("--out").arg(out).output().expect("runs");
    assert!(o.status.success(), "{}: {}", file.display(), String::from_utf8_lossy(&o.stderr));
    common::csv_rows(&std::fs::read_to_string(out.join(table)).expect(table))
}

/// The stuck chain's closed form at `f_hz` for storey `i` (0-based), per unit ground
/// acceleration, by the name of its table column: with `u = -h A`, the compliance `|h_i|`,
/// the storey's drift `|h_i - h_(i-1)|` and the floor's absolute acceleration `|w^2 h_i + 1|`
/// (a riding bed moves with its floor).
fn stuck_storey(added: [f64; 3], f_hz: f64, i: usize) -> [(&'static str, f64); 3] {
    let h = shaken_chain(added, f_hz);
    let drift = if i == 0 { h[0] } else { h[i] - h[i - 1] };
    [("c", h[i].norm()), ("drift", drift.norm()), ("acc", (h[i] * (2.0 * PI * f_hz).powi(2) + 1.0).norm())]
}

#[test]
fn an_experiment_file_shakes_the_supports_and_reports_relative_compliance() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Beds that never lift off ride as added mass: under 1 g at every host (A = 0.05 m/s^2).
    let dampers =
        "{ mass = 1, mass_ratio = 0.1, clearance_mm = 0.35 }, { mass = 3, mass_ratio = 0.1, clearance_mm = 0.35 }";
    let grid = "freq_hz = { start = 10.0, stop = 60.0, step = 2.5 }";
    for (kind, excitation) in [
        ("sweep", "base_acceleration_m_s2 = 0.05"),
        ("linear_frf", "base_acceleration_g = 0.0050985810"),
        ("sweep", "base_acceleration_g = 0.0050985810"),
    ] {
        let file = shaken_file(dir.path(), "shaken", excitation, &format!("kind = \"{kind}\"\n{grid}"), dampers);
        let out_dir = dir.path().join(format!("out_{kind}"));
        let _ = std::fs::remove_dir_all(&out_dir);
        let rows = run_for_table("run", &file, &out_dir, "shaken/data/compliance.csv");
        let col = |name: &str| rows[0].iter().position(|h| h == name).expect(name);
        let (curve, freq) = (col("curve"), col("freq_hz"));
        let mut seen = 0;
        for row in &rows[1..] {
            let f: f64 = row[freq].parse().expect("frequency");
            let added = if row[curve] == "bare" { [0.0; 3] } else { [0.074, 0.0, 0.064] };
            for i in 0..3 {
                for (name, want) in stuck_storey(added, f, i) {
                    let got: f64 = row[col(&format!("{name}{}", i + 1))].parse().expect("a number");
                    assert!(
                        (got - want).abs() < 1e-7 * want,
                        "{kind} {}, {f} Hz, {name}{}: {got} vs {want}",
                        row[curve],
                        i + 1
                    );
                }
            }
            seen += 1;
        }
        assert_eq!(seen, 2 * 21, "{kind}");
        let page = std::fs::read_to_string(out_dir.join("shaken/index.html")).expect("page");
        assert!(page.contains("supports accelerate as A = 0.05") && page.contains("m/(m/s^2)"), "{kind}");
    }
}

#[test]
fn a_design_on_moving_supports_is_per_unit_ground_acceleration_with_its_storeys() {
    // Beds that never lift off (A = 0.05 m/s^2, the hosts far below 1 g) ride as added mass:
    // the design's objective and its storeys' drifts and floors' accelerations are the stuck
    // chain's closed form, written here without the library.
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("shaken_design.toml");
    std::fs::write(
        &file,
        "[experiment]\nid = \"shaken_design\"\ntitle = \"t\"\nfigure = \"-\"\ncaption = \"c\"\nclaim = \"c\"\n\
         [structure]\nmasses_kg = [0.74, 0.71, 0.64]\nchain_stiffness_n_per_m = [24300.0, 21800.0, 19800.0]\n\
         [structure.damping]\nmodal_ratios = [0.01, 0.01, 0.01]\n[excitation]\nbase_acceleration_m_s2 = 0.05\n\
         [analysis]\nkind = \"design\"\n[design]\ncandidates = [3]\nshot_kg = 0.064\nclearance_mm = [0.2, 1.0]\n\
         sweeps = [\"rest\"]\nstarts = 1\n[[design.bands]]\nname = \"mode 1\"\nfreq_hz = [12.0, 13.0, 14.0]\nmasses = [3]\n",
    )
    .expect("write");
    let out_dir = dir.path().join("out");
    let rows = run_for_table("design", &file, &out_dir, "shaken_design/data/design_storeys.csv");
    let col = |name: &str| rows[0].iter().position(|h| h == name).expect(name);
    let mut seen = 0;
    for row in &rows[1..] {
        let f: f64 = row[col("freq_hz")].parse().expect("frequency");
        let added = if row[col("layout")] == "bare" { [0.0; 3] } else { [0.0, 0.0, 0.064] };
        for i in 0..3 {
            for (name, want) in stuck_storey(added, f, i).into_iter().skip(1) {
                let got: f64 = row[col(&format!("{name}{}", i + 1))].parse().expect("a number");
                assert!((got - want).abs() < 1e-7 * want, "{}, {f} Hz, {name}{}: {got} vs {want}", row[0], i + 1);
            }
        }
        seen += 1;
    }
    assert_eq!(seen, 6);
    // The objective: the stuck chain's peak of m3 over the bare one's, per m/s^2 (finite).
    let peak =
        |added: [f64; 3]| [12.0, 13.0, 14.0].iter().map(|&f| shaken_chain(added, f)[2].norm()).fold(0.0, f64::max);
    let want = peak([0.0, 0.0, 0.064]) / peak([0.0; 3]);
    let page = std::fs::read_to_string(out_dir.join("shaken_design/index.html")).expect("page");
    let placements = std::fs::read_to_string(out_dir.join("shaken_design/data/design_placements.csv")).expect("table");
    let p = common::csv_rows(&placements);
    let got: f64 = p[1][p[0].iter().position(|h| h == "objective").expect("objective")].parse().expect("a number");
    assert!((got - want).abs() < 1e-7 * want, "objective {got} vs {want}");
    assert!(page.contains("largest storey drift") && page.contains("largest absolute floor acceleration"), "answer");
}

#[test]
fn what_moving_supports_cannot_drive_is_refused_naming_the_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sweep = "kind = \"sweep\"\nfreq_hz = { start = 10.0, stop = 20.0, step = 5.0 }";
    let d = "{ mass = 2, mass_ratio = 0.1, clearance_mm = 0.35 }";
    let sdof = "kind = \"sdof_periodic\"\nmode = 1\nfreq_hz = { start = 10.0, stop = 20.0, step = 5.0 }";
    for (excitation, analysis, key, words) in [
        ("mass = 1\nforce_n = 2.6\nbase_acceleration_m_s2 = 1.0", sweep, "excitation.force_n", "give no force"),
        (
            "base_acceleration_m_s2 = 1.0\nbase_acceleration_g = 0.1",
            sweep,
            "excitation.base_acceleration_g",
            "not both",
        ),
        ("base_acceleration_g = -0.1", sweep, "excitation.base_acceleration_g", "positive and finite"),
        ("base_acceleration_m_s2 = 1e9", sweep, "excitation.base_acceleration_m_s2", "at most"),
        ("", sweep, "excitation.force_n", "base_acceleration_m_s2"),
        ("base_acceleration_m_s2 = 1.0", sdof, "excitation.base_acceleration_m_s2", "sdof_periodic"),
    ] {
        let file = shaken_file(dir.path(), "bad", excitation, analysis, d);
        let out = common::shotdamp()
            .args(["run", file.to_str().expect("utf-8"), "--out"])
            .arg(dir.path().join("o"))
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{excitation}: {err}");
        assert!(err.contains("bad.toml") && err.contains(key) && err.contains(words), "{excitation}: {err}");
    }
}

/// A uniform chain of `n` masses (0.5 kg, 20 kN/m springs) as Matrix Market files in `dir`.
fn chain_files(dir: &std::path::Path, n: usize) {
    let m: String = (1..=n).map(|i| format!("{i} {i} 0.5\n")).collect();
    std::fs::write(dir.join("m.mtx"), format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {n}\n{m}"))
        .expect("write");
    let mut k = String::new();
    for i in 1..=n {
        k += &format!("{i} {i} {}\n", if i < n { 40000.0 } else { 20000.0 });
        if i < n {
            k += &format!("{} {i} -20000\n", i + 1);
        }
    }
    std::fs::write(
        dir.join("k.mtx"),
        format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {}\n{k}", 2 * n - 1),
    )
    .expect("write");
}

#[test]
fn a_reduced_finite_element_chain_on_shaken_supports_moves_as_the_whole_chain() {
    // Eight masses; the reduced model keeps masses 2, 5 and 8 and every fixed-interface mode
    // (exact): its supports' load T^T M r and its points' share of r must give the whole
    // chain's motion relative to the ground, beds included.
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    chain_files(d, 8);
    let head = "[experiment]\nid = \"c\"\ntitle = \"t\"\nfigure = \"-\"\ncaption = \"c\"\nclaim = \"c\"\n";
    let tail = "[structure.damping]\nmodal_ratios = [0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02]\n[excitation]\nbase_acceleration_m_s2 = 1.5\n[analysis]\nkind = \"sweep\"\nfreq_hz = { start = 5.5, stop = 6.3, step = 0.1 }\n";
    let whole = format!(
        "{head}[structure]\nmasses_kg = [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]\nchain_stiffness_n_per_m = [20000.0, 20000.0, 20000.0, 20000.0, 20000.0, 20000.0, 20000.0, 20000.0]\n{tail}[[cases]]\nid = \"shot\"\nlabel = \"shot\"\ndampers = [{{ mass = 8, mass_kg = 0.05, clearance_mm = 5.0 }}]\n"
    );
    let reduced = format!(
        "{head}[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{{ row = 2 }}, {{ row = 5 }}, {{ row = 8 }}]\nmodes = 5\n{tail}[[cases]]\nid = \"shot\"\nlabel = \"shot\"\ndampers = [{{ mass = 3, mass_kg = 0.05, clearance_mm = 5.0 }}]\n"
    );
    let mut tables = Vec::new();
    for (name, text) in [("whole", whole), ("reduced", reduced)] {
        let file = d.join(format!("{name}.toml"));
        std::fs::write(&file, text).expect("write");
        let out_dir = d.join(format!("out_{name}"));
        let out = common::shotdamp()
            .args(["run", file.to_str().expect("utf-8"), "--out"])
            .arg(&out_dir)
            .output()
            .expect("runs");
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        tables.push(common::csv_rows(&std::fs::read_to_string(out_dir.join("c/data/compliance.csv")).expect("table")));
    }
    let (a, b) = (&tables[0], &tables[1]);
    let col = |t: &Vec<Vec<String>>, name: &str| t[0].iter().position(|h| h == name).expect(name);
    let (mut compared, mut impacting, mut worst) = (0, 0, 0.0f64);
    for (ra, rb) in a[1..].iter().zip(&b[1..]) {
        assert_eq!(ra[col(a, "impacts_per_period_d1")], rb[col(b, "impacts_per_period_d1")]);
        if ra[col(a, "converged")] != "1" || ra[col(a, "period")] != "1" {
            continue;
        }
        impacting += usize::from(ra[col(a, "impacts_per_period_d1")].parse::<f64>().expect("impacts") > 0.0);
        for (whole_mass, point) in [(2, 1), (5, 2), (8, 3)] {
            let x: f64 = ra[col(a, &format!("c{whole_mass}"))].parse().expect("number");
            let y: f64 = rb[col(b, &format!("c{point}"))].parse().expect("number");
            worst = worst.max((x - y).abs() / x);
            assert!((x - y).abs() < 1e-10 * x, "{} Hz, m{whole_mass}: {x} whole, {y} reduced", ra[1]);
            compared += 1;
        }
    }
    println!("{compared} amplitudes ({impacting} points with impacts) within {worst:.1e} of the whole chain's");
    assert!(compared >= 9 && impacting >= 2, "{compared} compared, {impacting} with impacts");
}

#[test]
fn soft_contacts_on_shaken_supports_give_the_stuck_chain_below_lift_off() {
    // A bed that never lifts off (the hosts far below 1 g) rides as added mass: the soft-contact
    // model's amplitude relative to the supports, over A, is the stuck chain's closed form,
    // within the contact springs' compliance and the explicit steps' error.
    use shotdamp::sim::motion::soft::{amplitude, SoftOptions};
    let s = crate::common::paper();
    let bed = Damper::new(2, 0.064, Clearance::from_mm(0.35));
    let accel = 0.05;
    let sys = System::plastic(s, vec![bed], 0, 0.0)
        .with_law(shotdamp::sim::motion::bed::ImpactLaw::with_restitution(0.5, 1e-3))
        .on_supports(accel);
    let opts = SoftOptions { stiffness: 1e8, steps_per_contact: 20 };
    let mut worst = 0.0f64;
    for f in [12.0, 20.0] {
        let (amp, _) = amplitude(&sys, 2.0 * PI * f, &opts, 400, 20).expect("a soft contact");
        let want: Vec<f64> = shaken_chain([0.0, 0.0, 0.064], f).iter().map(|z| z.norm()).collect();
        for i in 0..3 {
            let rel = (amp[i] / accel - want[i]).abs() / want[i];
            worst = worst.max(rel);
            assert!(rel < 2e-4, "{f} Hz, m{}: {} vs {}", i + 1, amp[i] / accel, want[i]);
        }
    }
    println!("soft contacts within {worst:.1e} of the stuck chain");
}
