//! Finite-element structures from experiment files: the paper's chain written as Matrix
//! Market files runs as the chain; the plate CalculiX meshed (examples/plate) agrees with
//! CalculiX's own natural frequencies and its reduction passes its check; bad files and keys
//! are input errors that say what is wrong. The test marked `#[ignore]` runs CalculiX itself
//! (CI installs it: `apt-get install calculix-ccx`).

use crate::common;

use std::path::{Path, PathBuf};

use common::{csv_rows, repo, shotdamp};

const HEAD: &str = "[experiment]\nid = \"fe\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n";

/// A sweep of the paper's third mode with one damper on m2 and with three (Fig. 5's cases),
/// on `structure` (the `[structure]` keys).
fn fig05_sweep(structure: &str) -> String {
    format!(
        "{HEAD}[structure]\n{structure}\n[structure.damping]\nmodal_ratios = [0.01, 0.01, 0.01]\n[excitation]\nmass = 1\nforce_n = 2.6\n[analysis]\nkind = \"sweep\"\nfreq_hz = {{ start = 44.0, stop = 56.0, step = 0.5 }}\n[[cases]]\nid = \"single\"\nlabel = \"one\"\ndampers = [{{ mass = 2, mass_kg = 0.071, clearance_mm = 0.2 }}]\n[[cases]]\nid = \"triple\"\nlabel = \"three\"\ndampers = [{{ mass = 1, mass_kg = 0.074, clearance_mm = 0.2 }}, {{ mass = 2, mass_kg = 0.071, clearance_mm = 0.2 }}, {{ mass = 3, mass_kg = 0.064, clearance_mm = 0.2 }}]\n"
    )
}

/// Runs `shotdamp run` on `text` written to `dir/name.toml`; the exit code, stderr and the
/// output folder.
fn run(dir: &Path, name: &str, text: &str) -> (Option<i32>, String, PathBuf) {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let out_dir = dir.join(format!("out_{name}"));
    let out = shotdamp().arg("run").arg(&path).arg("--out").arg(&out_dir).output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned(), out_dir)
}

#[test]
fn the_paper_s_chain_as_matrix_market_files_reproduces_the_fig5_sweeps() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("m.mtx"),
        "%%MatrixMarket matrix coordinate real symmetric\n% the paper's masses, kg\n3 3 3\n1 1 0.74\n2 2 0.71\n3 3 0.64\n",
    )
    .unwrap();
    // A general file: both triangles.
    std::fs::write(
        d.join("k.mtx"),
        "%%MatrixMarket matrix coordinate real general\n3 3 7\n1 1 46100\n2 1 -21800\n1 2 -21800\n2 2 41600\n3 2 -19800\n2 3 -19800\n3 3 19800\n",
    )
    .unwrap();
    let chain = "masses_kg = [0.74, 0.71, 0.64]\nchain_stiffness_n_per_m = [24.3e3, 21.8e3, 19.8e3]";
    // Every degree of freedom a point: nothing to reduce.
    let fe = "[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{ row = 1 }, { row = 2 }, { row = 3 }]\nmodes = 0";
    let (code, err, a) = run(d, "chain", &fig05_sweep(chain));
    assert_eq!(code, Some(0), "{err}");
    let (code, err, b) = run(d, "files", &fig05_sweep("").replace("[structure]\n\n", &format!("[structure]\n{fe}\n")));
    assert_eq!(code, Some(0), "{err}");
    let read = |o: &Path| csv_rows(&std::fs::read_to_string(o.join("fe/data/compliance.csv")).unwrap());
    let (ta, tb) = (read(&a), read(&b));
    assert_eq!(ta.len(), 2 * 25 + 1, "a header, 25 frequencies of two cases");
    assert_eq!(ta[0], tb[0]);
    let mut compared = 0;
    for (ra, rb) in ta[1..].iter().zip(&tb[1..]) {
        for (h, (x, y)) in ta[0].iter().zip(ra.iter().zip(rb)) {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) if x.is_finite() => {
                    assert!((x - y).abs() <= 1e-12 * x.abs().max(1e-300), "{h}: {x} vs {y}");
                    compared += 1;
                }
                _ => assert_eq!(x, y, "{h}"),
            }
        }
    }
    assert!(compared > 500, "{compared} numbers compared");
    // The reduction is exact here, and checked.
    let (status, worst) = reduction_check(&b);
    assert!(status == "pass" && worst <= 1e-12, "{status} {worst}");
}

/// The reduction check's status and computed value in a report folder.
fn reduction_check(out: &Path) -> (String, f64) {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("checks.json")).unwrap()).unwrap();
    let c = json["checks"].as_array().unwrap().iter().find(|c| c["name"] == "reduction").expect("a reduction check");
    (c["status"].as_str().unwrap().to_string(), c["computed"].as_f64().unwrap())
}

/// CalculiX's natural frequencies from its `.dat` file, Hz.
pub(crate) fn ccx_frequencies(dat: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(dat).unwrap();
    let mut out = Vec::new();
    let mut inside = false;
    for line in text.lines() {
        if line.contains("E I G E N V A L U E   O U T P U T") {
            inside = true;
            continue;
        }
        if line.contains("P A R T I C I P A T I O N") {
            break;
        }
        let w: Vec<&str> = line.split_whitespace().collect();
        if inside && w.len() == 5 && w[0].parse::<usize>().is_ok() {
            out.push(w[3].parse::<f64>().unwrap());
        }
    }
    out
}

/// A modal analysis of the plate of `data` (a folder of plate.sti, .mas, .dof), reduced at
/// its free edge, every fixed-interface mode below `cutoff_hz` kept.
fn plate_modal(data: &Path, cutoff_hz: f64) -> String {
    let d = data.display();
    format!(
        "{HEAD}[structure.finite_element]\nformat = \"calculix\"\nstiffness = \"{d}/plate.sti\"\nmass = \"{d}/plate.mas\"\ndofs = \"{d}/plate.dof\"\nup = \"z\"\npoints = [{{ node = 224, dof = 3 }}, {{ node = 290, dof = 3 }}, {{ node = 257, dof = 3 }}]\ncutoff_hz = {cutoff_hz}\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 3\nforce_n = 0.2\n[analysis]\nkind = \"modal\"\n"
    )
}

fn column(rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let c = rows[0].iter().position(|h| h == name).unwrap_or_else(|| panic!("{name} in {:?}", rows[0]));
    rows[1..].iter().map(|r| r[c].parse().unwrap()).collect()
}

/// The full model's and the reduced model's frequencies of the plate in `data`.
fn plate_frequencies(dir: &Path, data: &Path, cutoff_hz: f64) -> (Vec<f64>, Vec<f64>) {
    let (code, err, out) = run(dir, &format!("plate{}", cutoff_hz as u64), &plate_modal(data, cutoff_hz));
    assert_eq!(code, Some(0), "{err}");
    let rows = csv_rows(&std::fs::read_to_string(out.join("fe/data/reduction_frequencies.csv")).unwrap());
    (column(&rows, "full_hz"), column(&rows, "reduced_hz"))
}

#[test]
fn the_shipped_plate_agrees_with_calculix_and_its_reduction_converges() {
    let dir = tempfile::tempdir().unwrap();
    let data = repo().join("examples/plate/data");
    let ccx = ccx_frequencies(&data.join("plate_modes.dat"));
    assert_eq!(ccx.len(), 10);
    // The full model's modes (shift-invert Lanczos on CalculiX's matrices) are CalculiX's
    // own, to the seven digits its .dat file prints.
    let (full, _) = plate_frequencies(dir.path(), &data, 20000.0);
    assert!(full.len() >= 10);
    for (i, (a, b)) in full.iter().zip(&ccx).enumerate() {
        assert!((a - b).abs() <= 1e-6 * b, "mode {}: {a} Hz against CalculiX's {b} Hz", i + 1);
    }
    // Craig-Bampton bounds each frequency from above and converges as modes are kept.
    let mut last = f64::INFINITY;
    for cutoff in [1000.0, 2500.0, 8000.0] {
        let (full, red) = plate_frequencies(dir.path(), &data, cutoff);
        let err = (0..3).map(|i| (red[i] - full[i]) / full[i]).fold(0.0, f64::max);
        for i in 0..3 {
            assert!(red[i] >= full[i] * (1.0 - 1e-12), "{cutoff} Hz, mode {}", i + 1);
        }
        assert!(err < last, "{cutoff} Hz: {err} not below {last}");
        last = err;
    }
    assert!(last < 1e-5, "the lowest three modes within {last} at 8000 Hz");
}

/// The full-model frequencies of the cantilevered beam CalculiX solved (examples/plate/beam.inp,
/// matrices in `data`), Hz.
fn beam_frequencies(dir: &Path, data: &Path) -> Vec<f64> {
    let d = data.display();
    let text = format!(
        "{HEAD}[structure.finite_element]\nformat = \"calculix\"\nstiffness = \"{d}/beam.sti\"\nmass = \"{d}/beam.mas\"\ndofs = \"{d}/beam.dof\"\nup = \"z\"\npoints = [{{ node = 41, dof = 3 }}]\nmodes = 11\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 1.0\n[analysis]\nkind = \"modal\"\n"
    );
    let (code, err, out) = run(dir, "beam", &text);
    assert_eq!(code, Some(0), "{err}");
    column(&csv_rows(&std::fs::read_to_string(out.join("fe/data/reduction_frequencies.csv")).unwrap()), "full_hz")
}

#[test]
fn the_beam_bends_as_euler_and_bernoulli_say() {
    // A steel cantilever 500 x 20 x 10 mm (20 x 1 x 1 fully integrated twenty-node bricks):
    // its vertical bending frequencies are (beta_n L)^2 / (2 pi L^2) sqrt(E I / (rho A)).
    // Expected: above them by less than 1 %, the mesh's discretisation error (measured:
    // +0.69, +0.61, +0.50 % for modes 1-3 on this mesh; +0.37, +0.21, -0.04 % on 40 x 2 x 1,
    // converging), shear and rotary inertia (Timoshenko) lowering the third by a few tenths of
    // a percent.
    let dir = tempfile::tempdir().unwrap();
    let full = beam_frequencies(dir.path(), &repo().join("examples/plate/data"));
    let (l, h, e, rho) = (0.5_f64, 0.01_f64, 210e9_f64, 7850.0_f64);
    let root = (e * h * h / (12.0 * rho)).sqrt() / (l * l) / (2.0 * std::f64::consts::PI);
    for (n, beta_l) in [(1, 1.875_104_07_f64), (2, 4.694_091_13), (3, 7.854_757_44)] {
        let euler = beta_l * beta_l * root;
        let nearest = full.iter().copied().min_by(|a, b| (a - euler).abs().total_cmp(&(b - euler).abs())).unwrap();
        let rel = (nearest - euler) / euler;
        assert!(rel > 0.0 && rel < 0.01, "bending mode {n}: {nearest} Hz against Euler-Bernoulli's {euler} Hz ({rel})");
    }
}

#[test]
fn without_a_cutoff_the_modes_below_twice_the_highest_frequency_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let data = repo().join("examples/plate/data");
    // A linear response up to 300 Hz: the fixed-interface modes below 600 Hz.
    let text = plate_modal(&data, 1.0)
        .replace("cutoff_hz = 1\n", "")
        .replace("kind = \"modal\"", "kind = \"linear_frf\"\nfreq_hz = { start = 20.0, stop = 300.0, step = 10.0 }");
    let (_, err, out) = run(dir.path(), "default", &text);
    let rows = csv_rows(
        &std::fs::read_to_string(out.join("fe/data/reduction_frequencies.csv"))
            .unwrap_or_else(|e| panic!("{e}: {err}")),
    );
    let (_, with_cutoff) = plate_frequencies(dir.path(), &data, 600.0);
    assert_eq!(rows.len() - 1, with_cutoff.len(), "{err}");
}

#[test]
fn the_plate_example_runs_and_its_reduction_passes_its_check() {
    let dir = tempfile::tempdir().unwrap();
    let out = shotdamp().args(["run", "examples/plate/plate.toml", "--out"]).arg(dir.path()).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let (status, worst_checked) = reduction_check(dir.path());
    assert_eq!(status, "pass");
    let rows = csv_rows(
        &std::fs::read_to_string(dir.path().join("plate_first_bending/data/reduction_compliance.csv")).unwrap(),
    );
    let worst = column(&rows, "rel_diff").into_iter().fold(0.0, f64::max);
    assert!(worst > 0.0 && worst <= 1e-3, "{worst}");
    assert_eq!(worst, worst_checked);
    // A closed form: near a resonance whose frequency the reduction has a relative error
    // delta, the damped compliance changes by about delta / zeta of its peak (30-48 Hz holds
    // the first mode only; zeta = 0.01; the grid's 0.25 Hz steps read the peak within 10 %).
    let freqs = csv_rows(
        &std::fs::read_to_string(dir.path().join("plate_first_bending/data/reduction_frequencies.csv")).unwrap(),
    );
    let delta = column(&freqs, "rel_diff")[0];
    assert!((worst / (delta / 0.01) - 1.0).abs() < 0.1, "{worst} against delta / zeta = {}", delta / 0.01);

    // The sweep measures and tabulates the four points alone (the reduction's 16 modal
    // coordinates are no displacement of a point), and what it gives there is what a sweep
    // following every coordinate gives: the first points continued up from 30 Hz.
    let rows = csv_rows(&std::fs::read_to_string(dir.path().join("plate_first_bending/data/compliance.csv")).unwrap());
    let head: Vec<&str> =
        rows[0].iter().map(String::as_str).filter(|h| h.starts_with('c') && h[1..].parse::<usize>().is_ok()).collect();
    assert_eq!(head, ["c1", "c2", "c3", "c4"]);
    let exp = shotdamp::experiment::loader::load(&repo().join("examples/plate/plate.toml"), &repo().join("reference"))
        .unwrap()
        .remove(0);
    assert_eq!(exp.structure.dof(), 20);
    let case = exp.cases.iter().find(|c| c.id == "corners").unwrap();
    let sys = shotdamp::sim::System::plastic(
        exp.structure.clone(),
        case.dampers(),
        exp.excitation.mass,
        exp.excitation.force,
    );
    let every = shotdamp::sim::SteadyOptions::default();
    let up = shotdamp::sim::settle::sweep::Direction::Up;
    let points = shotdamp::sim::settle::sweep::continued(&sys, &[30.0, 30.25, 30.5], up, &every, &|| {});
    let curve = rows[0].iter().position(|h| h == "curve").unwrap();
    let table: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[curve] == "corners:up").take(3).collect();
    for (p, row) in points.iter().zip(table) {
        let st = p.result.as_ref().unwrap();
        assert_eq!(st.amplitude.len(), 20, "every coordinate followed");
        for (k, h) in head.iter().enumerate() {
            let at = rows[0].iter().position(|x| x == h).unwrap();
            let (got, want) = (row[at].parse::<f64>().unwrap(), st.amplitude[k] / exp.excitation.force);
            assert!((got - want).abs() <= 1e-9 * want, "{} Hz, {h}: {got} vs {want}", p.freq_hz);
        }
    }
}

/// With the plate's fixed-interface modes kept up to 4 kHz (30 coordinates) the beds at the
/// two symmetric corners leave and land at one instant, each impact moving the other host at
/// once through the coupled mass matrix. Every point near the resonance must end as the
/// simulator's physics says (settled, or no steady state within the periods allowed), never
/// as a run of events at one instant stopped as chatter (it was 30 of 146 points).
#[test]
fn symmetric_beds_on_a_stiff_reduced_plate_do_not_chatter() {
    let dir = tempfile::tempdir().unwrap();
    let data = repo().join("examples/plate/data");
    let text = std::fs::read_to_string(repo().join("examples/plate/plate.toml"))
        .unwrap()
        .replace("\"data/", &format!("\"{}/", data.display()))
        .replace("cutoff_hz = 2500.0", "cutoff_hz = 4000.0")
        .replace("start = 30.0, stop = 48.0, step = 0.25", "start = 34.75, stop = 35.75, step = 0.5");
    let (code, err, out) = run(dir.path(), "plate4k", &text);
    assert_eq!(code, Some(0), "{err}");
    let rows = csv_rows(&std::fs::read_to_string(out.join("plate_first_bending/data/compliance.csv")).unwrap());
    let stop = rows[0].iter().position(|c| c == "stop").unwrap();
    let curve = rows[0].iter().position(|c| c == "curve").unwrap();
    let corners: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[curve].starts_with("corners")).collect();
    assert_eq!(corners.len(), 6);
    // Near the peak some points find no steady state within the periods allowed (as with
    // the example's 2.5 kHz cutoff): a finding about the motion, not a stop of the simulator.
    for r in &corners {
        assert!(r[stop].is_empty() || r[stop].starts_with("no steady state"), "{r:?}");
    }
    let bare: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[curve] == "bare").collect();
    assert!(bare.iter().all(|r| r[stop].is_empty()), "{bare:?}");
}

/// On the plate design's reduction (fixed-interface modes below 8 kHz; at its first four
/// points 46 coordinates, at all five 47) two layouts the design search met stopped as
/// chatter, from rest: a bed freed on a contact acceleration of -1.1e-3 m/s^2 from
/// the host's rows met a gap curving down at once in the closed form (the bed landed and left
/// again at one instant, 2000 times), and the closed form of a configuration reproduced its
/// start's velocities only to 2e-6 m/s (two beds passed impacts to each other through the
/// coupled mass matrix every 4e-11 s). Each point must end as the physics says: settled, or no
/// steady state within the periods allowed.
#[test]
fn beds_on_the_plate_design_s_reduction_do_not_chatter_at_one_instant() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("designs/plate.toml")).unwrap();
    let examples = repo().join("examples");
    let structure = text[text.find("[structure]").unwrap()..text.find("[analysis]").unwrap()]
        .replace("../examples", &examples.display().to_string());
    // The design's first four points alone, and all five.
    let four = structure.replace("    { name = \"long free edge middle\", node = 219, dof = 3 },\n", "");
    assert_ne!(four, structure);
    let cases = [
        (&four, "[36.5, 36.75]", "{ mass = 3, mass_kg = 0.057872, clearance_mm = 15.116551 }, { mass = 4, mass_kg = 0.036328, clearance_mm = 15.116551 }"),
        (&structure, "[126.0, 127.5]", "{ mass = 2, mass_kg = 0.007467, clearance_mm = 27.876889 }, { mass = 3, mass_kg = 0.052734, clearance_mm = 27.876889 }, { mass = 4, mass_kg = 0.033999, clearance_mm = 27.876889 }"),
    ];
    for (i, (structure, freq, dampers)) in cases.into_iter().enumerate() {
        let file = format!(
            "{HEAD}{structure}[analysis]\nkind = \"sweep\"\nfreq_hz = {freq}\nsteady = {{ max_periods = 150 }}\n[[cases]]\nid = \"beds\"\nlabel = \"beds\"\ndampers = [{dampers}]\n"
        );
        let (code, err, out) = run(dir.path(), &format!("plate_chatter{i}"), &file);
        assert_eq!(code, Some(0), "case {i}: {err}");
        let rows = csv_rows(&std::fs::read_to_string(out.join("fe/data/compliance.csv")).unwrap());
        let stop = rows[0].iter().position(|c| c == "stop").unwrap();
        let curve = rows[0].iter().position(|c| c == "curve").unwrap();
        let beds: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[curve] == "beds").collect();
        assert!(!beds.is_empty());
        for r in beds {
            assert!(r[stop].is_empty() || r[stop].starts_with("no steady state"), "case {i}: {r:?}");
        }
    }
}

/// A reduction that keeps more coordinates than the simulator takes is refused when its modes
/// are counted, before any is computed: named by the key that keeps them, with the count and
/// the modes that would fit; a modal analysis, which takes any size, reduces it.
#[test]
fn a_reduction_too_large_to_simulate_is_refused_before_it_is_computed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = repo().join("examples/plate/data");
    let sweep = |keep: &str| {
        plate_modal(&data, 1000.0).replace("cutoff_hz = 1000", keep).replace(
            "kind = \"modal\"",
            "kind = \"sweep\"\nfreq_hz = { start = 30.0, stop = 40.0, step = 1.0 }\n[[cases]]\nid = \"a\"\nlabel = \"a\"\ndampers = [{ mass = 1, mass_kg = 0.05, clearance_mm = 1.0 }]",
        )
    };
    for (keep, said) in [
        ("modes = 300", "structure.finite_element.modes = 300: it keeps 300 fixed-interface modes, with the 3 points 303 coordinates: analysis kind \"sweep\" runs the exact simulator, which takes at most 256 (modes = 253 at most"),
        ("modes = 5000", "structure.finite_element.modes = 5000: it keeps 1407 fixed-interface modes, with the 3 points 1410 coordinates"),
        ("cutoff_hz = 200000.0", "structure.finite_element.cutoff_hz = 200000: it keeps "),
    ] {
        let (code, err, out) = run(d, "large", &sweep(keep));
        assert_eq!(code, Some(2), "{keep}: {err}");
        assert!(err.contains(said), "{keep}: expected \"{said}\" in: {err}");
        assert!(!out.exists(), "{keep}: nothing is written");
    }
    let (code, err, _) = run(d, "modal", &plate_modal(&data, 1000.0).replace("cutoff_hz = 1000", "modes = 300"));
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn bad_finite_element_files_and_keys_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = repo().join("examples/plate/data");
    let good = plate_modal(&data, 1000.0);
    let cases: Vec<(String, &str)> = vec![
        (good.replace("format = \"calculix\"", "format = \"nastran\""), "finite_element.format = \"nastran\": one of \"calculix\", \"matrix-market\", \"abaqus\""),
        (good.replace("node = 224, dof = 3", "node = 99999, dof = 3"), "the node is not in the model's degrees of freedom"),
        (good.replace("node = 290, dof = 3", "node = 224, dof = 3"), "the same degree of freedom as points[0]"),
        (good.replace("up = \"z\"", "up = \"down\""), "finite_element.up = \"down\""),
        (good.replace("cutoff_hz = 1000", "modes = 4\ncutoff_hz = 1000"), "give at most one: modes = N"),
        (good.replace("cutoff_hz = 1000", ""), "a modal analysis has none: give one"),
        (good.replace("[structure.finite_element]", "[structure]\nmasses_kg = [1.0]\n[structure.finite_element]"), "structure.masses_kg = (with finite_element)"),
        (good.replace("up = \"z\"", "up = \"x\"").replace("kind = \"modal\"", "kind = \"sweep\"\nfreq_hz = { start = 30.0, stop = 40.0, step = 1.0 }\n[[cases]]\nid = \"a\"\nlabel = \"a\"\ndampers = [{ mass = 1, mass_kg = 0.05, clearance_mm = 1.0 }]"), "cases[0].dampers[0].mass = 1: point \"node 224 z\" does not move along the vertical"),
        (good.replace("kind = \"modal\"", "kind = \"sweep\"\nfreq_hz = { start = 30.0, stop = 40.0, step = 1.0 }\n[[cases]]\nid = \"a\"\nlabel = \"a\"\ndampers = [{ mass = 5, mass_kg = 0.05, clearance_mm = 1.0 }]"), "a container sits on one of the finite-element points, numbered 1 to 3"),
        (good.replace("mass = 3\nforce", "mass = 5\nforce"), "excitation.mass = 5"),
    ];
    for (i, (text, said)) in cases.iter().enumerate() {
        let (code, err, _) = run(d, &format!("bad{i}"), text);
        assert_eq!(code, Some(2), "case {i}: {err}");
        assert!(err.contains(said), "case {i}: expected \"{said}\" in: {err}");
    }
    let (code, err, _) = run(d, "missing", &good.replace("/plate.dof", "/none.dof"));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("structure.finite_element.dofs = ") && err.contains("none.dof\": cannot be read"), "{err}");
    // Bad files: a truncated line, a non-positive mass, an asymmetric general file.
    let copy = d.join("copy");
    std::fs::create_dir_all(&copy).unwrap();
    for f in ["plate.sti", "plate.mas", "plate.dof"] {
        std::fs::copy(data.join(f), copy.join(f)).unwrap();
    }
    let sti = std::fs::read_to_string(copy.join("plate.sti")).unwrap();
    std::fs::write(copy.join("plate.sti"), sti.replacen("\n", "\n7 7\n", 1)).unwrap();
    let (code, err, _) = run(d, "truncated", &plate_modal(&copy, 1000.0));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("plate.sti") && err.contains("line 2") && err.contains("truncated"), "{err}");
    std::fs::write(copy.join("plate.sti"), sti).unwrap();
    let mas = std::fs::read_to_string(copy.join("plate.mas")).unwrap();
    let first = mas.lines().next().unwrap().to_string();
    std::fs::write(copy.join("plate.mas"), mas.replacen(&first, "1 1 -1.0", 1)).unwrap();
    let (code, err, _) = run(d, "massless", &plate_modal(&copy, 1000.0));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("plate.mas") && err.contains("row 1 (node") && err.contains("positive mass"), "{err}");
    std::fs::write(d.join("m.mtx"), "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n2 2 1.0\n")
        .unwrap();
    std::fs::write(
        d.join("k.mtx"),
        "%%MatrixMarket matrix coordinate real general\n2 2 4\n1 1 2.0\n2 1 -1.0\n1 2 -1.5\n2 2 2.0\n",
    )
    .unwrap();
    let mm = format!(
        "{HEAD}[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{{ row = 1 }}]\nmodes = 1\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 1.0\n[analysis]\nkind = \"modal\"\n"
    );
    let (code, err, _) = run(d, "asymmetric", &mm);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("k.mtx") && err.contains("not symmetric: entry (2, 1) is -1 but (1, 2) is -1.5"), "{err}");
    // A header claiming a billion rows over two entries is refused before anything of that size
    // is allocated (it took all the memory).
    let huge = "%%MatrixMarket matrix coordinate real symmetric\n999999999 999999999 2\n1 1 1.0\n2 2 1.0\n";
    std::fs::write(d.join("k.mtx"), huge).unwrap();
    std::fs::write(d.join("m.mtx"), huge).unwrap();
    let (code, err, _) = run(d, "huge", &mm);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("k.mtx: the stiffness matrix has 2 entries for 999999999 degrees of freedom"), "{err}");
}

/// Runs CalculiX on the plate's decks (examples/plate/ccx.sh) and checks what it writes:
/// shotdamp's full-model frequencies from the new matrices against CalculiX's own, the
/// unsupported plate's mass matrix summing to three times the plate's mass (one per
/// translational direction), and the square plate's files equal to the shipped ones. Needs `ccx`: `cargo test --release --test all -- --ignored fe::`.
#[test]
#[ignore]
fn calculix_meshes_and_solves_the_plate() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ccx");
    let status = std::process::Command::new("bash")
        .arg(repo().join("examples/plate/ccx.sh"))
        .arg(&out)
        .status()
        .expect("bash runs examples/plate/ccx.sh");
    assert!(status.success(), "examples/plate/ccx.sh failed (is calculix-ccx installed?)");
    let ccx = ccx_frequencies(&out.join("plate_modes.dat"));
    assert_eq!(ccx.len(), 10);
    let (full, red) = plate_frequencies(dir.path(), &out, 20000.0);
    for (i, (a, b)) in full.iter().zip(&ccx).enumerate() {
        assert!((a - b).abs() <= 1e-6 * b, "mode {}: {a} Hz against CalculiX's {b} Hz", i + 1);
    }
    // Where the modes are kept (a cutoff far above them) the reduced model's are CalculiX's.
    for (i, (a, b)) in red.iter().zip(&ccx).take(3).enumerate() {
        assert!((a - b).abs() <= 1e-6 * b, "reduced mode {}: {a} Hz against CalculiX's {b} Hz", i + 1);
    }
    let mut sum = 0.0;
    for line in std::fs::read_to_string(out.join("plate_free.mas")).unwrap().lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let v: f64 = w[2].parse().unwrap();
        sum += if w[0] == w[1] { v } else { 2.0 * v };
    }
    // The beam's new matrices give the frequencies of the shipped ones.
    let (fresh, shipped) =
        (beam_frequencies(dir.path(), &out), beam_frequencies(dir.path(), &repo().join("examples/plate/data")));
    for (a, b) in fresh.iter().zip(&shipped) {
        assert!((a - b).abs() <= 1e-12 * b, "{a} vs {b}");
    }
    let plate = 0.30 * 0.20 * 0.004 * 7850.0;
    assert!((sum / 3.0 - plate).abs() <= 1e-9 * plate, "{} kg against {plate} kg", sum / 3.0);
    // The square plate's new matrices and frequencies are the shipped ones (to the last digits
    // CalculiX prints).
    let shipped = repo().join("examples/plate/data");
    for f in ["square.sti", "square.mas", "square.dof"] {
        let numbers = |p: &Path| -> Vec<f64> {
            let text = std::fs::read_to_string(p).unwrap();
            text.split_whitespace().map(|w| w.parse::<f64>().unwrap()).collect()
        };
        let (fresh, old) = (numbers(&out.join(f)), numbers(&shipped.join(f)));
        assert_eq!(fresh.len(), old.len(), "{f}");
        for (a, b) in fresh.iter().zip(&old) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{f}: {a} against the shipped {b}");
        }
    }
    let (fresh, old) =
        (ccx_frequencies(&out.join("square_modes.dat")), ccx_frequencies(&shipped.join("square_modes.dat")));
    assert_eq!(fresh, old, "square_modes.dat");
}

/// A shot mass is stated against the plate's mass moving vertically (its clamped nodes'
/// share excluded), never against the reduced mass matrix's trace, whose coordinates are
/// modal: the plate design's 94 g are 5.1 % of the plate (they read 0.22 %).
#[test]
fn a_finite_element_structure_s_mass_is_its_mass_moving_vertically() {
    let exps = shotdamp::experiment::loader::load(&repo().join("examples/plate/plate.toml"), &repo().join("reference"))
        .unwrap();
    let fe = exps[0].finite_element.as_ref().unwrap();
    assert_eq!(exps[0].structure_mass(), Some(fe.mass_along_up));
    let plate = 0.30 * 0.20 * 0.004 * 7850.0;
    assert!(fe.mass_along_up < plate && fe.mass_along_up > 0.95 * plate, "{} kg of {plate} kg", fe.mass_along_up);
    let trace = exps[0].structure.mass_matrix().trace();
    assert!((trace - plate).abs() > 0.5 * plate, "the trace is no mass: {trace} kg");
    let chain = shotdamp::experiment::loader::load(
        &repo().join("experiments/fig05_third_mode.toml"),
        &repo().join("reference"),
    )
    .unwrap();
    let sum: f64 = chain[0].structure.masses.iter().sum();
    assert_eq!(chain[0].structure_mass(), Some(sum));
}

#[test]
fn a_reduced_model_s_modes_are_read_at_its_points() {
    // Eq. 12-13 scale each mode to 1 at a mass: on a reduced model, at one of its points, never
    // at a modal coordinate (modes that hardly move the points then get a huge equivalent mass,
    // which is what they are to a damper there).
    let exps = shotdamp::experiment::loader::load(&repo().join("examples/plate/plate.toml"), &repo().join("reference"))
        .unwrap();
    let s = &exps[0].structure;
    assert_eq!(s.points, Some(4));
    let modes = shotdamp::model::modal::modal_summary(s, &[]);
    assert_eq!(modes.len(), 20);
    for m in &modes {
        assert!(m.reference_mass < 4, "mode {}: read at coordinate {}", m.number, m.reference_mass + 1);
        assert!((m.shape[m.reference_mass] - 1.0).abs() < 1e-15);
    }
    // The first bending mode is read at the free edge's middle, as the chain's modes are.
    assert_eq!(modes[0].reference_mass, 2);
}

/// The plate design's structure (designs/plate.toml) over each of its three bands: the reduced
/// model's damped compliance is the full model's to the default tolerance relative to the
/// band's own peak, resonances included (undamped, a grid point 0.011 Hz from the second
/// bending mode compared two near-infinities and read as 55 % apart). The last band's
/// frequencies are listed one by one.
#[test]
fn the_plate_design_s_reduction_holds_in_each_of_its_bands() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("designs/plate.toml")).unwrap();
    let examples = repo().join("examples");
    let structure = &text[text.find("[structure]").unwrap()..text.find("[analysis]").unwrap()];
    let listed: Vec<String> = (0..41).map(|i| format!("{}", 215.0 + i as f64)).collect();
    let listed = format!("[{}]", listed.join(", "));
    for (i, band) in
        ["{ start = 33.0, stop = 43.0, step = 0.25 }", "{ start = 115.0, stop = 140.0, step = 0.5 }", &listed]
            .into_iter()
            .enumerate()
    {
        let file = format!(
            "{HEAD}{}[analysis]\nkind = \"linear_frf\"\nfreq_hz = {band}\n[[cases]]\nid = \"bare\"\nlabel = \"bare\"\ndampers = []\n",
            structure.replace("../examples", &examples.display().to_string()),
        );
        let (code, err, out) = run(dir.path(), &format!("plate_band{i}"), &file);
        assert_eq!(code, Some(0), "band {i}: {err}");
        let (status, worst) = reduction_check(&out);
        assert!(status == "pass" && worst < 1e-3, "band {i}: {status} {worst}");
    }
}

/// A design on the plate (designs/plate.toml's structure, two candidates, one band, few
/// evaluations) with `screen` as its `[design.screen]` table (empty: none) and the file's
/// model reduced below `cutoff_hz`.
fn small_plate_design(cutoff_hz: f64, screen: &str) -> String {
    let text = std::fs::read_to_string(repo().join("designs/plate.toml")).unwrap();
    let structure = &text[text.find("[structure]").unwrap()..text.find("[excitation]").unwrap()];
    let structure = structure
        .replace("../examples", &repo().join("examples").display().to_string())
        .replace("cutoff_hz = 8000.0", &format!("cutoff_hz = {cutoff_hz:?}"));
    format!(
        "{HEAD}{structure}[excitation]\nmass = 1\nforce_n = 0.2\n[analysis]\nkind = \"design\"\n[design]\ncandidates = [1, 2]\nmax_beds = 1\nshot_kg = 0.0942\nclearance_mm = [0.5, 50.0]\nsweeps = [\"up\"]\nstarts = 1\nmax_iters = 3\n{screen}\n[[design.bands]]\nname = \"first bending\"\nfreq_hz = {{ start = 36.0, stop = 40.0, step = 1.0 }}\nmasses = [1]\n[[cases]]\nid = \"bare\"\nlabel = \"bare\"\ndampers = []\n"
    )
}

/// The placements table of a design's output folder: each row's named columns.
fn placements(out: &Path, columns: &[&str]) -> Vec<Vec<f64>> {
    let rows = csv_rows(&std::fs::read_to_string(out.join("fe/data/design_placements.csv")).unwrap());
    let head = &rows[0];
    let at: Vec<usize> = columns.iter().map(|c| head.iter().position(|h| h == c).unwrap_or(usize::MAX)).collect();
    rows[1..]
        .iter()
        .map(|r| at.iter().map(|&i| r.get(i).map_or(f64::NAN, |v| v.parse().unwrap_or(f64::NAN))).collect())
        .collect()
}

/// `[design.screen]`: the searches run on a coarser reduction and each placement's best is
/// judged on the file's model. A screen that keeps the file's own modes is the unscreened
/// search, layout for layout and bit for bit; a coarser one judges its layouts on the file's
/// model (both objectives in the table, a finding in the warnings); bad keys are input errors.
#[test]
fn a_screened_design_searches_the_coarse_model_and_judges_on_the_file_s() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let design = |name: &str, text: &str| {
        let path = d.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let out_dir = d.join(format!("out_{name}"));
        let out = shotdamp().arg("design").arg(&path).arg("--out").arg(&out_dir).output().unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned(), out_dir)
    };
    let cols = ["objective", "bed_kg", "clearance_mm", "screened_objective"];
    let (code, err, plain) = design("plain", &small_plate_design(2500.0, ""));
    assert_eq!(code, Some(0), "{err}");
    let plain = placements(&plain, &cols);
    assert!(plain.iter().all(|r| r[3].is_nan()), "no screen, no screened column: {plain:?}");
    let (code, err, same) = design("same", &small_plate_design(2500.0, "[design.screen]\ncutoff_hz = 2500.0\n"));
    assert_eq!(code, Some(0), "{err}");
    let same = placements(&same, &cols);
    assert_eq!(same.len(), 2);
    for (s, p) in same.iter().zip(&plain) {
        assert_eq!(s[..3], p[..3], "the same model screened is the unscreened search");
        assert_eq!(s[3].to_bits(), s[0].to_bits(), "its screened objective is the judged one");
    }
    // The screen's budget of periods at the design's own (500): the same search again.
    let (code, err, budget) =
        design("budget", &small_plate_design(2500.0, "[design.screen]\ncutoff_hz = 2500.0\nmax_periods = 500\n"));
    assert_eq!(code, Some(0), "{err}");
    for (b, s) in placements(&budget, &cols).iter().zip(&same) {
        assert_eq!(
            b.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            s.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    }
    let coarse_text = small_plate_design(2500.0, "[design.screen]\nmodes = 0\n");
    let (code, err, coarse) = design("coarse", &coarse_text);
    assert_eq!(code, Some(0), "{err}");
    // Sharded, the shards search on the screen as the whole run does: the merge is its report.
    let file = d.join("coarse.toml");
    let parts = d.join("parts");
    for i in 0..2 {
        let o = shotdamp()
            .arg("design")
            .arg(&file)
            .arg(format!("--shard={i}/2"))
            .arg("--parts")
            .arg(&parts)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let merged = d.join("out_merged");
    let o = shotdamp().arg("design").arg(&file).arg("--merge").arg(&parts).arg("--out").arg(&merged).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["design_placements.csv", "design_clearance.csv", "design_compliance.csv"] {
        let read = |root: &Path| std::fs::read(root.join("fe/data").join(f)).unwrap();
        assert_eq!(read(&coarse), read(&merged), "{f}");
    }
    let report = std::fs::read_to_string(coarse.join("fe/index.html")).unwrap_or_default()
        + &std::fs::read_to_string(coarse.join("index.html")).unwrap_or_default();
    let coarse = placements(&coarse, &cols);
    assert!(coarse.iter().all(|r| r[0].is_finite() && r[3].is_finite() && r[0] != r[3]), "{coarse:?}");
    assert!(report.contains("searched on a coarser reduction (the lowest 0 fixed-interface modes: 5 coordinates)"));
    for (text, said) in [
        (
            small_plate_design(2500.0, "[design.screen]\nmodes = 2\ncutoff_hz = 300.0\n"),
            "design.screen = modes / cutoff_hz",
        ),
        (small_plate_design(2500.0, "[design.screen]\ncutoff_hz = -3.0\n"), "design.screen.cutoff_hz = -3"),
        (small_plate_design(2500.0, "[design.screen]\nmodes = 0\nmax_periods = 0\n"), "design.screen.max_periods = 0"),
        (small_plate_design(2500.0, "[design.screen]\nmodes = 0\nwidth = 1\n"), "unknown field `width`"),
        (
            small_plate_design(2500.0, "[design.screen]\nmodes = 300\n"),
            "design.screen.modes = 300: it keeps 300 fixed-interface modes, with the 5 points 305 coordinates: the design's search on the reduction of [design.screen] runs the exact simulator, which takes at most 256 (modes = 251 at most",
        ),
    ] {
        let (code, err, _) = design("bad", &text);
        assert_eq!(code, Some(2), "{err}");
        assert!(err.contains(said), "expected \"{said}\" in: {err}");
    }
}

/// A model validated again from the same files is not reduced again (the explorer's requests,
/// a study's samples, a design's phases): the second load finds the first's reduction and
/// gives the same matrices; a matrix file edited since is reduced again.
#[test]
fn a_model_is_reduced_once_until_its_files_change() {
    use shotdamp::experiment::fe::made;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let write_k = |comment: &str| {
        std::fs::write(
            d.join("k.mtx"),
            format!("%%MatrixMarket matrix coordinate real symmetric\n%{comment}\n3 3 5\n1 1 46100\n2 1 -21800\n2 2 41600\n3 2 -19800\n3 3 19800\n"),
        )
        .unwrap()
    };
    write_k(" first");
    std::fs::write(
        d.join("m.mtx"),
        "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 0.74\n2 2 0.71\n3 3 0.64\n",
    )
    .unwrap();
    // Reduced at m1 and m3: the middle mass's mode kept.
    let fe = "[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{ row = 1 }, { row = 3 }]\nmodes = 1";
    let text = format!(
        "{HEAD}[structure]\n{fe}\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 2.6\n[analysis]\nkind = \"sweep\"\nfreq_hz = {{ start = 44.0, stop = 46.0, step = 1.0 }}\n[[cases]]\nid = \"one\"\nlabel = \"one\"\ndampers = [{{ mass = 2, mass_kg = 0.071, clearance_mm = 0.2 }}]\n"
    );
    let path = d.join("reduced.toml");
    std::fs::write(&path, text).unwrap();
    let load = || shotdamp::experiment::loader::load(&path, &repo().join("reference")).unwrap();
    let first = load();
    assert_eq!(made::found_in(d), vec![0], "one reduction made");
    let again = load();
    assert_eq!(made::found_in(d), vec![1], "found, not made again");
    let (a, b) = (&first[0].structure, &again[0].structure);
    assert_eq!(a.mass_matrix(), b.mass_matrix());
    assert_eq!(format!("{:?}", a.stiffness), format!("{:?}", b.stiffness));
    // The stiffness file edited (a comment only): its bytes differ, so it is read and reduced
    // again, to the same numbers.
    write_k(" edited");
    let edited = load();
    assert_eq!(made::found_in(d), vec![1, 0]);
    assert_eq!(edited[0].structure.mass_matrix(), a.mass_matrix());
}
