//! Stored design answers (`shotdamp design --store`) in the report: `shotdamp report`
//! evaluates the stored layouts again, and its checks fail when a stored objective is not what
//! the layout gives now, when the design problem changed since the search, or when there is no
//! stored answer. Models as scenarios of one search.

mod common;

use std::path::Path;

/// A small design (the 5-storey frame, two candidates, coarse bands, one start) that searches
/// in a few seconds.
fn tiny(text: &str) -> String {
    text.replace("candidates = [1, 2, 3, 4, 5]", "candidates = [4, 5]")
        .replace("max_beds = 2", "max_beds = 2\nstarts = 1\nmax_iters = 8\nreport = true")
        .replace(
            "freq_hz = { start = 5.0, stop = 8.0, step = 0.1 }",
            "freq_hz = { start = 5.0, stop = 8.0, step = 0.5 }",
        )
        .replace(
            "freq_hz = { start = 16.0, stop = 21.0, step = 0.2 }",
            "freq_hz = { start = 16.0, stop = 21.0, step = 1.0 }",
        )
}

fn report(root: &Path, out: &str) -> (Option<i32>, String) {
    let o = common::shotdamp()
        .arg("report")
        .arg("--experiments")
        .arg(root.join("experiments"))
        .arg("--designs")
        .arg(root.join("designs"))
        .arg("--reference")
        .arg(root.join("reference"))
        .arg("--out")
        .arg(root.join(out))
        .arg("--bless")
        .output()
        .unwrap();
    (o.status.code(), format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr)))
}

#[test]
fn stored_answers_are_evaluated_again_and_tied_to_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    // One cheap experiment (the report needs one), no reference files.
    let exps = root.join("experiments");
    common::copy_shared(&exps);
    std::fs::write(
        exps.join("modal.toml"),
        "extends = \"shared/paper_structure.toml\"\n[experiment]\nid = \"modal\"\ntitle = \"modes\"\nfigure = \"Fig. 0\"\ncaption = \"c\"\nclaim = \"c\"\n[analysis]\nkind = \"modal\"\n[[cases]]\nid = \"bare\"\nlabel = \"bare\"\ndampers = []\n",
    )
    .unwrap();
    std::fs::create_dir_all(root.join("designs")).unwrap();
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let text = tiny(&std::fs::read_to_string(common::repo().join("designs/five_storey.toml")).unwrap());
    let design = root.join("designs/frame.toml");
    std::fs::write(&design, &text).unwrap();

    // No stored answer yet: the report fails and names the command.
    let (code, log) = report(root, "r0");
    assert_eq!(code, Some(1), "{log}");
    assert!(log.contains("stored_design") && log.contains("--store"), "{log}");

    // Search and store.
    let o = common::shotdamp()
        .arg("design")
        .arg(&design)
        .arg("--store")
        .arg("--reference")
        .arg(root.join("reference"))
        .arg("--out")
        .arg(root.join("d"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let stored = root.join("reference/designs/design_five_storey.json");
    let json = std::fs::read_to_string(&stored).unwrap();
    let answer: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(answer["placements"].as_array().unwrap().len(), 3, "{json}");
    assert!(answer["provenance"].as_str().unwrap().contains("--store"));

    // The report evaluates it again: every check passes, the page has the design's tables.
    let (code, log) = report(root, "r1");
    assert_eq!(code, Some(0), "{log}");
    let page = root.join("r1/design_five_storey");
    for t in ["design_placements.csv", "design_cases.csv", "design_clearance.csv"] {
        assert!(page.join("data").join(t).is_file(), "{t}");
    }
    let index = std::fs::read_to_string(root.join("r1/index.html")).unwrap();
    assert!(index.contains("The paper's conclusion") && index.contains("design_five_storey"));

    // A stored objective that the layout does not give: stored_objectives fails.
    let first = answer["placements"][0]["objective"].as_f64().unwrap();
    let mut tampered = answer.clone();
    tampered["placements"][0]["objective"] = serde_json::json!(first * 1.001);
    std::fs::write(&stored, serde_json::to_string_pretty(&tampered).unwrap()).unwrap();
    let (code, log) = report(root, "r2");
    assert_eq!(code, Some(1), "{log}");
    assert!(log.contains("stored_objectives"), "{log}");
    std::fs::write(&stored, &json).unwrap();

    // The design file edited since the search: stored_problem fails.
    std::fs::write(&design, text.replace("force_n = 2.0", "force_n = 2.5")).unwrap();
    let (code, log) = report(root, "r3");
    assert_eq!(code, Some(1), "{log}");
    assert!(log.contains("stored_problem"), "{log}");
}

#[test]
fn models_become_scenarios_of_one_search() {
    let root = common::repo();
    let exps =
        shotdamp::experiment::load(&root.join("designs/third_mode_every_model.toml"), &root.join("reference")).unwrap();
    assert_eq!(exps.len(), 1, "one search, not one per model");
    assert!(exps[0].model.is_none());
    let shotdamp::experiment::Analysis::Design { spec, steady } = &exps[0].analysis else { panic!("a design") };
    assert_eq!(spec.model_structures.len(), 3);
    let p = shotdamp::analysis::design::problem(&exps[0], spec, steady);
    assert_eq!(p.scenarios.len(), 3);
    let per_model = shotdamp::experiment::load(&root.join("designs/third_mode.toml"), &root.join("reference")).unwrap();
    for (s, e) in p.scenarios.iter().zip(&per_model) {
        assert_eq!(s.structure, e.structure, "{}", s.name);
        assert!(s.name.starts_with(&e.model.as_ref().unwrap().label), "{}", s.name);
    }
    // Asked of a file without models: an input error naming the key.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(root.join("designs/five_storey.toml")).unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, text.replacen("[[design.bands]]", "[design.scenarios]\nmodels = true\n\n[[design.bands]]", 1))
        .unwrap();
    let err = shotdamp::experiment::load(&bad, &root.join("reference")).unwrap_err().to_string();
    assert!(err.contains("design.scenarios.models") && err.contains("bad.toml"), "{err}");
}

/// `shotdamp design --time-limit`: at its limit the search keeps each placement's best layout
/// so far (here 0 s: the coarse clearance scans only), writes them with a warning on the page
/// and in the summary, and stores nothing even with `--store`; a negative limit is refused.
#[test]
fn a_time_limit_writes_the_best_so_far_marked_and_stores_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let text = tiny(&std::fs::read_to_string(common::repo().join("designs/five_storey.toml")).unwrap());
    let design = root.join("frame.toml");
    std::fs::write(&design, &text).unwrap();
    let run = |limit: &str, out: &str| {
        common::shotdamp()
            .arg("design")
            .arg(&design)
            .arg("--store")
            .arg(format!("--time-limit={limit}"))
            .arg("--reference")
            .arg(root.join("reference"))
            .arg("--out")
            .arg(root.join(out))
            .output()
            .unwrap()
    };
    let o = run("0", "d");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("warning: the search stopped at its time limit"), "{stdout}");
    assert!(!stdout.contains("stored:"), "{stdout}");
    assert!(!root.join("reference/designs/design_five_storey.json").exists());
    let rows = std::fs::read_to_string(root.join("d/design_five_storey/data/design_placements.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 3, "{rows}");
    let page = std::fs::read_to_string(root.join("d/design_five_storey/index.html")).unwrap();
    assert!(page.contains("stopped at its time limit"));

    let o = run("-1", "e");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--time-limit = -1") && err.contains("0 or more"), "{err}");
    assert!(!root.join("e").exists());
}
