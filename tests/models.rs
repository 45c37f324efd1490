//! The structure fitted to the paper's measured modes, model variants, and the damping
//! calibrated against a measured (digitised) curve, end to end.

use crate::common;

use common::{repo, shotdamp};

fn stdout(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn the_paper_data_fit_to_its_stated_residuals() {
    let exps = shotdamp::experiment::loader::load(
        &repo().join("experiments/fig04b_no_damper.toml"),
        &repo().join("reference"),
    )
    .unwrap();
    let ids: Vec<&str> = exps.iter().map(|e| e.model.as_ref().unwrap().id.as_str()).collect();
    assert_eq!(ids, ["stated", "coil", "fitted"]);
    let fit = exps[2].fit.as_ref().expect("the fitted model carries its fit");
    // Exactly the measured frequencies, shapes within 0.021 (paper section 3).
    for (w, r) in fit.omegas.iter().zip(&fit.frequency_residuals) {
        assert!((r / w).abs() < 1e-9, "frequency residual {r} at {w}");
    }
    let worst = fit.shape_residuals.iter().flatten().fold(0.0_f64, |a, r| a.max(r.abs()));
    assert!(worst < 0.0212 && worst > 0.02, "largest shape residual {worst}");
    assert!(fit.unique(), "spread {}", fit.spread);
    assert!(fit.stiffness.clone().cholesky().is_some());
    // The fitted ground stiffness of m1 is near k_1 + k_0 (the shaker's coil spring):
    // K_11 - k_2 against 24.3 + 6.6 kN/m, within 10 %.
    let k = &fit.stiffness;
    let ground_1 = k[(0, 0)] + k[(0, 1)] + k[(0, 2)];
    assert!((ground_1 / (24.3e3 + 6.6e3) - 1.0).abs() < 0.1, "ground spring of m1: {ground_1}");
    // The coil model adds exactly k_0 at m1.
    let dk = &exps[1].structure.stiffness - &exps[0].structure.stiffness;
    assert_eq!(dk[(0, 0)], 6.6e3);
    assert_eq!(dk.iter().filter(|v| **v != 0.0).count(), 1);
}

#[test]
fn modal_prints_the_fit() {
    let out = shotdamp().arg("modal").arg("experiments/fig04b_no_damper.toml").output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    for want in [
        "model \"fitted\"",
        "stiffness fitted to the measured modes",
        "(the same matrix: unique)",
        "largest shape residual 0.0211",
        "243.900000",
    ] {
        assert!(text.contains(want), "expected {want:?} in:\n{text}");
    }
}

/// A model-less experiment whose structure is fitted to `fit` (TOML of `[structure.fit]`).
fn fitted_experiment(dir: &std::path::Path, fit: &str) -> std::path::PathBuf {
    let path = dir.join("fit.toml");
    let text = format!(
        "[experiment]\nid = \"fit\"\ntitle = \"t\"\nfigure = \"t\"\ncaption = \"-\"\nclaim = \"-\"\n\n[structure]\nmasses_kg = [0.74, 0.71, 0.64]\n\n[structure.fit]\n{fit}\n\n[structure.damping]\nmodal_ratios = [0.01, 0.01, 0.01]\n\n[excitation]\nmass = 1\nforce_n = 2.6\n\n[analysis]\nkind = \"modal\"\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn bad_modal_data_is_an_input_error() {
    let shapes = "shapes = [[0.37, 0.77, 1.0], [1.0, 0.57, -0.91], [-0.96, 1.0, -0.47]]";
    let cases = [
        (format!("omegas_rad_per_s = [81.9, -243.9, 312.3]\n{shapes}"), "natural frequency 2 is -243.9"),
        (format!("omegas_rad_per_s = [81.9, 312.3, 243.9]\n{shapes}"), "strictly increasing"),
        (format!("omegas_rad_per_s = [81.9, 243.9]\n{shapes}"), "need 3 frequencies"),
        (
            "omegas_rad_per_s = [81.9, 243.9, 312.3]\nshapes = [[0.37, 0.77, 1.0], [0.37, 0.77, 1.0], [-0.96, 1.0, -0.47]]"
                .to_string(),
            "not linearly independent",
        ),
        (format!("omegas_rad_per_s = [81.9, 243.9, 312.3]\n{shapes}\nfrequency_weight = -1.0"), "frequency weight"),
    ];
    for (fit, want) in cases {
        let dir = tempfile::tempdir().unwrap();
        let path = fitted_experiment(dir.path(), &fit);
        let out = shotdamp().arg("modal").arg(&path).output().unwrap();
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("fit.toml") && err.contains("structure.fit") && err.contains(want), "{want:?} in {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn damping_calibration_recovers_known_damping_from_a_digitised_curve() {
    // The stated chain with known damping, computed by shotdamp itself ...
    let dir = tempfile::tempdir().unwrap();
    let known = [0.006, 0.013, 0.021];
    let file = dir.path().join("known.toml");
    std::fs::write(
        &file,
        "[experiment]\nid = \"known\"\ntitle = \"t\"\nfigure = \"t\"\ncaption = \"-\"\nclaim = \"-\"\n\n[structure]\nmasses_kg = [0.74, 0.71, 0.64]\nchain_stiffness_n_per_m = [24.3e3, 21.8e3, 19.8e3]\n\n[structure.damping]\nmodal_ratios = [0.006, 0.013, 0.021]\n\n[excitation]\nmass = 1\nforce_n = 2.6\n\n[analysis]\nkind = \"linear_frf\"\nfreq_hz = { start = 2.0, stop = 60.0, points = 1161 }\n\n[[cases]]\nid = \"bare\"\nlabel = \"no damper\"\ndampers = []\n",
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let out = shotdamp().arg("run").arg(&file).arg("--out").arg(&out_dir).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // ... exported as a WebPlotDigitizer CSV of three datasets (every 3rd point) ...
    let table = std::fs::read_to_string(out_dir.join("known/data/compliance.csv")).unwrap();
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let mut csv = String::from("m1,,m2,,m3,\nX,Y,X,Y,X,Y\n");
    for line in lines.step_by(3) {
        let c: Vec<&str> = line.split(',').collect();
        let f = c[col("freq_hz")];
        csv += &format!("{f},{},{f},{},{f},{}\n", c[col("c1")], c[col("c2")], c[col("c3")]);
    }
    let wpd = dir.path().join("fig4b.csv");
    std::fs::write(&wpd, csv).unwrap();
    let digitised = dir.path().join("fig4b.toml");
    let out = shotdamp()
        .args(["reference", "import"])
        .arg(&wpd)
        .args(["--figure", "Fig. 4(b)", "--by", "test", "--from", "shotdamp's own response"])
        .args(["--x-pixel", "0.05", "--y-pixel", "0.01", "--y-log"])
        .args(["--map", "m1=bare:1", "--map", "m2=bare:2", "--map", "m3=bare:3"])
        .arg("--out")
        .arg(&digitised)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // ... and calibrated: the known ratios come back to 1 %.
    let out = shotdamp().arg("damping").arg(&file).arg("--curve").arg(&digitised).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let line = text.lines().find(|l| l.contains("modal_ratios = [")).unwrap_or_else(|| panic!("{text}"));
    let inside = line.split_once("modal_ratios = [").unwrap().1.trim_end_matches(']');
    let got: Vec<f64> = inside.split(',').map(|v| v.trim().parse().unwrap()).collect();
    for (g, k) in got.iter().zip(known) {
        assert!((g / k - 1.0).abs() < 0.01, "calibrated {got:?} against {known:?}\n{text}");
    }
    assert!(text.contains("rms residual"), "{text}");
}
