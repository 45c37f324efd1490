//! Repeated natural frequencies: the paper's chain beside identical oscillators joined to
//! nothing (a block-diagonal structure whose oscillators share one frequency, as the
//! symmetric structures engineers bring do) is simulated, and its chain moves exactly as the
//! paper's chain alone: the Fig. 5 sweeps of the third mode with three beds reproduced to
//! 1e-10. Before, every point was NaN with "numerically singular (eigenvector condition
//! 3.3e17 ...)".

use nalgebra::DMatrix;
use shotdamp::model::structure::chain_stiffness;
use shotdamp::model::{Clearance, Damper, Damping, Structure};
use shotdamp::sim::settle::sweep;
use shotdamp::sim::{SteadyOptions, System};

/// The paper's chain (modal damping 0.01) beside `k` identical oscillators of 1 kg on 10 kN/m
/// (15.9 Hz, between the chain's first and second modes), the force on m1, a bed of 10 % of
/// each chain mass at 0.2 mm on each chain mass.
fn beside(k: usize) -> System {
    let n = 3 + k;
    let mut stiffness = DMatrix::<f64>::identity(n, n) * 1e4;
    stiffness.view_mut((0, 0), (3, 3)).copy_from(&chain_stiffness(&[24.3e3, 21.8e3, 19.8e3]));
    let masses: Vec<f64> = [0.74, 0.71, 0.64].into_iter().chain(std::iter::repeat_n(1.0, k)).collect();
    let structure = Structure::from_matrices(&masses, stiffness, Damping::ModalRatios(vec![0.01; n]));
    let dampers = (0..3).map(|h| Damper::new(h, 0.1 * masses[h], Clearance::from_m(0.2e-3))).collect();
    System::plastic(structure, dampers, 0, 2.6)
}

fn amplitudes(sys: &System) -> Vec<(f64, Vec<f64>, usize)> {
    let freqs: Vec<f64> = (0..25).map(|i| 44.0 + 0.5 * i as f64).collect();
    sweep::from_rest(sys, &freqs, &SteadyOptions::default(), &|| {})
        .into_iter()
        .map(|p| {
            let s = p.result.unwrap_or_else(|e| panic!("{} Hz: {e}", p.freq_hz));
            (p.freq_hz, s.amplitude, s.period)
        })
        .collect()
}

#[test]
fn the_chain_beside_identical_oscillators_moves_as_the_chain_alone() {
    let alone = amplitudes(&beside(0));
    for k in [2usize, 8, 29] {
        let with = amplitudes(&beside(k));
        let mut worst: f64 = 0.0;
        for ((f, a, pa), (_, b, pb)) in alone.iter().zip(&with) {
            assert_eq!(pa, pb, "{k} oscillators, {f} Hz: period");
            for m in 0..3 {
                let rel = (a[m] - b[m]).abs() / a[m].abs();
                worst = worst.max(rel);
                assert!(rel <= 1e-10, "{k} oscillators, {f} Hz, m{}: {} vs {} ({rel:e})", m + 1, a[m], b[m]);
            }
            // The oscillators are not driven and joined to nothing: they stay at rest.
            for (o, x) in b.iter().enumerate().skip(3) {
                assert!(x.abs() <= 1e-12 * a[0], "{k} oscillators, {f} Hz, oscillator {o}: {x}");
            }
        }
        println!("{k} identical oscillators beside the chain: largest relative difference {worst:e} over 25 points");
    }
}

/// Every configuration of the chain beside two identical oscillators (a repeated pair of
/// eigenvalues of the state matrix, twice: the pair's two conjugates) is decomposed with a
/// well-conditioned basis.
#[test]
fn a_symmetric_structure_with_a_repeated_pair_decomposes_well() {
    let sys = beside(2);
    let d = shotdamp::sim::Dynamics::new(&sys, 2.0 * std::f64::consts::PI * 48.0).expect("decomposes");
    for mask in 0..8 {
        let c = d.config(mask).modes.condition;
        assert!(c < 1e4, "configuration {mask:#b}: eigenvector condition {c:e}");
    }
}

/// The square plate of examples/plate/square.toml (CalculiX, clamped on every edge: modes in
/// equal pairs), reduced at its centre: its pairs stay equal in the reduced model, its
/// frequencies are CalculiX's full model's, its first is the thin-plate value above by the
/// mesh's error, and the pairs (a nodal line through the centre) are out of reach of a
/// damper there.
#[test]
fn the_square_plate_from_calculix_keeps_its_equal_pairs() {
    let repo = crate::common::repo();
    let exps =
        shotdamp::experiment::loader::load(&repo.join("examples/plate/square.toml"), &repo.join("reference")).unwrap();
    let modes = shotdamp::model::modal::modal_summary(&exps[0].structure, &[]);
    let f: Vec<f64> = modes.iter().map(|m| m.freq_hz).collect();
    for (a, b) in [(1, 2), (6, 7), (8, 9)] {
        assert!((f[a] - f[b]).abs() <= 1e-9 * f[a], "modes {} and {}: {} and {} Hz", a + 1, b + 1, f[a], f[b]);
    }
    assert!((f[2] - f[3]).abs() > 0.1 * f[2], "distinct modes stay apart");
    let ccx = crate::fe::ccx_frequencies(&repo.join("examples/plate/data/square_modes.dat"));
    assert!(ccx.len() >= 9);
    for (i, (a, b)) in f.iter().zip(&ccx).enumerate() {
        assert!((a - b).abs() <= 1e-3 * b, "mode {}: {a} Hz reduced against CalculiX's {b} Hz", i + 1);
    }
    // Read at the centre (Eq. 12-13: a damper there), the first mode has the plate's
    // equivalent mass there; the pairs have a nodal line through the centre, so their
    // equivalent mass there is that of a mode the centre does not move (its rounding only).
    assert!(modes[0].modal_mass > 0.1 && modes[0].modal_mass < 1.0, "{} kg", modes[0].modal_mass);
    for i in [1, 2, 6, 7, 8, 9] {
        assert!(modes[i].modal_mass > 1e6, "mode {}: {} kg at the centre", i + 1, modes[i].modal_mass);
        // ... and it is said so: the centre moves by less than rounding of the mode's largest
        // coordinate, so the modal table gives no modal mass for it.
        assert!(!modes[i].at_points, "mode {}", i + 1);
    }
    assert!(modes[0].at_points && modes[5].at_points && !modes[3].at_points);
    // Leissa (Vibration of Plates, 1969, table 4.23): a square plate clamped on every edge has
    // lambda^2 = 35.99 and 73.41 (the first pair), f = lambda^2 / (2 pi a^2) sqrt(D / (rho h)).
    let (a, h, e, nu, rho) = (0.2_f64, 0.004_f64, 210e9_f64, 0.3_f64, 7850.0_f64);
    let d = e * h.powi(3) / (12.0 * (1.0 - nu * nu));
    let thin = 35.99 / (2.0 * std::f64::consts::PI * a * a) * (d / (rho * h)).sqrt();
    let over = (ccx[0] - thin) / thin;
    assert!(over > 0.0 && over < 0.05, "first mode {} Hz against the thin plate's {thin} Hz ({over})", ccx[0]);
    assert!(((ccx[1] / ccx[0]) / (73.41 / 35.99) - 1.0).abs() < 0.015, "{} / {}", ccx[1], ccx[0]);
}

/// The same plate with shot at its centre, at a point where the bed's motion never settles,
/// one where it does and one on the bare peak: every point simulated (no stop on the repeated
/// eigenvalues), classified, and the reduction's check passes.
#[test]
fn the_square_plate_with_shot_runs_at_every_point() {
    let dir = tempfile::tempdir().unwrap();
    let examples = crate::common::repo().join("examples/plate");
    let text = std::fs::read_to_string(examples.join("square.toml")).unwrap();
    let start = text.find("freq_hz = {").unwrap();
    let end = start + text[start..].find('}').unwrap() + 1;
    let body = format!("{}freq_hz = [848.0, 912.0, 936.0]{}", &text[..start], &text[end..]);
    let path = dir.path().join("square.toml");
    std::fs::write(&path, body.replace("\"data/", &format!("\"{}/data/", examples.display()))).unwrap();
    let out =
        crate::common::shotdamp().arg("run").arg(&path).arg("--out").arg(dir.path().join("out")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = crate::common::csv_rows(
        &std::fs::read_to_string(dir.path().join("out/square_plate/data/compliance.csv")).unwrap(),
    );
    let col = |name: &str| rows[0].iter().position(|c| c == name).unwrap();
    let classes: Vec<(&str, &str)> = rows[1..]
        .iter()
        .filter(|r| r[col("curve")] == "centre")
        .map(|r| (r[col("freq_hz")].as_str(), r[col("motion")].as_str()))
        .collect();
    assert_eq!(classes, [("848.0", "chaotic"), ("912.0", "periodic"), ("936.0", "periodic")]);
    for r in &rows[1..] {
        let c: f64 = r[col("c1")].parse().unwrap();
        assert!(c.is_finite() && c > 0.0, "{r:?}");
        assert!(r[col("stop")].is_empty() || r[col("stop")].starts_with("no steady state"), "{r:?}");
    }
}
