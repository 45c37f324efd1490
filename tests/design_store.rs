//! Stored design answers (`shotdamp design --store`) in the report: `shotdamp report`
//! evaluates the stored layouts again, and its checks fail when a stored objective is not what
//! the layout gives now, when the design problem changed since the search, or when there is no
//! stored answer. Models as scenarios of one search.

use crate::common;

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
    let o = design_cmd(&design, root, "d").arg("--store").output().unwrap();
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
        shotdamp::experiment::loader::load(&root.join("designs/third_mode_every_model.toml"), &root.join("reference"))
            .unwrap();
    assert_eq!(exps.len(), 1, "one search, not one per model");
    assert!(exps[0].model.is_none());
    let shotdamp::experiment::Analysis::Design { spec, steady } = &exps[0].analysis else { panic!("a design") };
    assert_eq!(spec.model_structures.len(), 3);
    let p = shotdamp::analysis::design::problem(&exps[0], spec, steady);
    assert_eq!(p.scenarios.len(), 3);
    let per_model =
        shotdamp::experiment::loader::load(&root.join("designs/third_mode.toml"), &root.join("reference")).unwrap();
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
    let err = shotdamp::experiment::loader::load(&bad, &root.join("reference")).unwrap_err().to_string();
    assert!(err.contains("design.scenarios.models") && err.contains("bad.toml"), "{err}");
}

/// `shotdamp design --time-limit`: at its limit the search keeps each placement's best layout
/// so far (here 0 s: the coarse clearance scans only), writes them with a warning on the page
/// and in the summary, and stores nothing even with `--store`; the answer and the front page
/// open with the stop, no sentence rests on what was not computed (the clearance profile),
/// the file's drive levels are evaluated all the same, and the exit code is 3 (partial); a
/// negative limit is refused.
#[test]
fn a_time_limit_writes_the_best_so_far_marked_and_stores_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let text = tiny(&std::fs::read_to_string(common::repo().join("designs/five_storey.toml")).unwrap())
        .replace("max_beds = 2\n", "max_beds = 2\ndrive_levels_n = [2.0, 5.0]\n");
    assert!(text.contains("drive_levels_n"));
    let design = root.join("frame.toml");
    std::fs::write(&design, &text).unwrap();
    let run = |limit: &str, out: &str| {
        design_cmd(&design, root, out)
            .arg("--store")
            .arg("--confirm")
            .arg(format!("--time-limit={limit}"))
            .output()
            .unwrap()
    };
    let o = run("0", "d");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("warning: the search stopped at its time limit"), "{stdout}");
    assert!(stdout.contains("partial: design_five_storey stopped at the time limit"), "{stdout}");
    assert!(!stdout.contains("stored:"), "{stdout}");
    assert!(!root.join("reference/designs/design_five_storey.json").exists());
    let rows = std::fs::read_to_string(root.join("d/design_five_storey/data/design_placements.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 3, "{rows}");
    let page = std::fs::read_to_string(root.join("d/design_five_storey/index.html")).unwrap();
    assert!(page.contains("stopped at its time limit"));
    let answer = page.split("<p class=\"answer\"><b>Answer.</b> ").nth(1).expect("an answer");
    assert!(answer.starts_with("Not a converged answer: the search stopped at its time limit"), "{answer}");
    // Nothing stated that was not computed: no profile, so no word on the optimum's width.
    assert!(!answer.contains("narrow optimum") && !answer.contains("within 5 % of the best"), "{answer}");
    assert!(answer.contains("was not computed"), "{answer}");
    let front = std::fs::read_to_string(root.join("d/index.html")).unwrap();
    let first = front.split("<h1>").nth(1).unwrap();
    assert!(first.split("</p>").next().unwrap().contains("Partial answer"), "the front page opens with the stop");
    // Nothing that searches more layouts runs after a stopped search (a user who asked for a
    // minute does not wait for the clearance profile), and the page says so; the drive levels
    // the file asks for are the best layout's, one evaluation a level.
    assert!(page.contains("the clearance profile, the near-optimum map"), "the page says what it skipped");
    for skipped in ["design_clearance.csv", "design_near_optimum.csv"] {
        assert!(!root.join("d/design_five_storey/data").join(skipped).exists(), "{skipped}");
    }
    let levels = std::fs::read_to_string(root.join("d/design_five_storey/data/design_drive_levels.csv")).unwrap();
    assert_eq!(levels.lines().count(), 1 + 2, "the best layout at 2 and 5 N: {levels}");
    // How far each placement got, from the placements table: its converged column counted.
    assert!(rows.lines().next().unwrap().ends_with(",converged"), "{rows}");
    let converged = rows.lines().skip(1).filter(|l| l.ends_with(",yes")).count();
    assert!(
        answer.contains(&format!("{converged} of the 3 placements were searched to convergence")),
        "{converged}: {answer}"
    );
    // Far above its limit, a design is refused unless confirmed: nothing is written.
    let o = design_cmd(&design, root, "f").arg("--time-limit=0").output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--time-limit") && err.contains("--confirm"), "{err}");
    assert!(!root.join("f").exists());

    let o = run("-1", "e");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--time-limit = -1") && err.contains("0 or more"), "{err}");
    assert!(!root.join("e").exists());
}

/// Ctrl-C during `shotdamp design`: the first interrupt stops the searches at their next
/// evaluation and the report of the best layouts so far is written, marked, with nothing
/// stored, and the exit status says the run was interrupted (130); a second interrupt
/// abandons the run and removes its staging folder.
#[cfg(target_os = "linux")]
#[test]
fn an_interrupted_design_writes_its_best_so_far_and_a_second_interrupt_abandons_it() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let design = root.join("frame.toml");
    std::fs::copy(common::repo().join("designs/five_storey.toml"), &design).unwrap();
    let start = |out: &str| {
        let child = std::process::Command::new(assert_cmd::cargo::cargo_bin("shotdamp"))
            .current_dir(root)
            .arg("design")
            .arg(&design)
            .arg("--store")
            .arg("--reference")
            .arg(root.join("reference"))
            .arg("--out")
            .arg(root.join(out))
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let staging = root.join(format!(".{out}.tmp-{}", child.id()));
        let started = std::time::Instant::now();
        while !staging.exists() && started.elapsed().as_secs() < 20 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(staging.exists(), "the run writes into a staging folder");
        std::thread::sleep(std::time::Duration::from_millis(300));
        (child, staging)
    };
    let interrupt = |child: &std::process::Child| {
        std::process::Command::new("kill").arg("-INT").arg(child.id().to_string()).status().unwrap();
    };

    let (child, _) = start("d");
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted: the searches stop"), "{stderr}");
    assert!(stdout.contains("warning: the search was interrupted"), "{stdout}");
    assert!(!stdout.contains("stored:") && !root.join("reference/designs/design_five_storey.json").exists());
    let page = std::fs::read_to_string(root.join("d/design_five_storey/index.html")).unwrap();
    assert!(page.contains("the search was interrupted"));
    let rows = std::fs::read_to_string(root.join("d/design_five_storey/data/design_placements.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 15, "every placement's best so far: {rows}");

    let (child, staging) = start("e");
    interrupt(&child);
    std::thread::sleep(std::time::Duration::from_millis(50));
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!staging.exists() && !root.join("e").exists(), "the second interrupt abandons the run");
}

/// Forces as scenarios: the page draws the reduction against the drive level, for the best
/// layout and the file's case, one row per layout and force, the objective each the worst
/// band's measure relative to the bare structure's at that force.
#[test]
fn force_scenarios_give_the_reduction_against_the_drive_level() {
    let dir = tempfile::tempdir().unwrap();
    let (page, _) = coarse_design(dir.path(), "scenarios = { force_n = [1.0, 2.0, 4.0] }");
    let table = std::fs::read_to_string(page.join("data/design_drive_levels.csv")).unwrap();
    let rows: Vec<Vec<&str>> = table.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(table.lines().next(), Some("layout,scenario,force_n,objective"), "{table}");
    assert_eq!(rows.len(), 2 * 3, "best and the case, three forces each: {table}");
    let forces: Vec<f64> = rows.iter().take(3).map(|r| r[2].parse().unwrap()).collect();
    assert_eq!(forces, [1.0, 2.0, 4.0]);
    // The best layout's objective at each force is the placements table's worst over them.
    let worst = rows.iter().take(3).map(|r| r[3].parse::<f64>().unwrap()).fold(0.0, f64::max);
    let best = best_objective(&page);
    assert!((worst - best).abs() <= 1e-12 * best, "{worst} vs {best}");
    // The figure in the smaller of PNG and SVG.
    assert!(page.join("design_drive_levels.png").exists() != page.join("design_drive_levels.svg").exists());
}

/// `drive_levels_n`: the best layout and the cases evaluated again at each force after the
/// search (not part of its objective): the nominal force's row is the search's objective.
#[test]
fn drive_levels_evaluate_the_best_layout_at_each_force_after_the_search() {
    let dir = tempfile::tempdir().unwrap();
    let (page, design) = coarse_design(dir.path(), "drive_levels_n = [4.0, 1.0, 2.0]");
    let text = std::fs::read_to_string(&design).unwrap();
    let table = std::fs::read_to_string(page.join("data/design_drive_levels.csv")).unwrap();
    let rows: Vec<Vec<&str>> = table.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let forces: Vec<f64> = rows.iter().take(3).map(|r| r[2].parse().unwrap()).collect();
    assert_eq!(forces, [1.0, 2.0, 4.0], "in increasing force: {table}");
    // The file's force is 2 N: that row is the best layout's objective.
    let at_two: f64 = rows[1][3].parse().unwrap();
    let best = best_objective(&page);
    assert_eq!(at_two, best, "{table}");
    // A bad drive level is an input error naming the key.
    std::fs::write(&design, text.replace("[4.0, 1.0, 2.0]", "[4.0, -1.0]")).unwrap();
    let o = common::shotdamp().arg("design").arg(&design).arg("--dry-run").output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("design.drive_levels_n[1] = -1"), "{err}");
}

/// `objective = "worst_over_drive_levels"`: the search minimises the worst over the drive
/// levels (they become the scenarios' forces), so the best layout's objective is the largest
/// of its levels' rows; without two levels, or beside force scenarios, it is refused.
#[test]
fn an_objective_over_the_drive_levels_is_the_worst_of_them() {
    let dir = tempfile::tempdir().unwrap();
    let (page, design) =
        coarse_design(dir.path(), "drive_levels_n = [1.0, 4.0]\nobjective = \"worst_over_drive_levels\"");
    let table = std::fs::read_to_string(page.join("data/design_drive_levels.csv")).unwrap();
    let rows: Vec<Vec<&str>> = table.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let forces: Vec<f64> = rows.iter().take(2).map(|r| r[2].parse().unwrap()).collect();
    assert_eq!(forces, [1.0, 4.0], "{table}");
    let worst = rows.iter().take(2).map(|r| r[3].parse::<f64>().unwrap()).fold(0.0, f64::max);
    let best = best_objective(&page);
    assert!((worst - best).abs() <= 1e-12 * best, "{worst} vs {best}: {table}");
    let text = std::fs::read_to_string(&design).unwrap();
    for (edit, said) in [
        (text.replace("drive_levels_n = [1.0, 4.0]", "drive_levels_n = [1.0]"), "two forces or more"),
        (
            text.replace(
                "drive_levels_n = [1.0, 4.0]",
                "drive_levels_n = [1.0, 4.0]\nscenarios = { force_n = [2.0, 3.0] }",
            ),
            "leave design.scenarios.force_n out",
        ),
        (text.replace("worst_over_drive_levels", "best_of_both"), "\"nominal\" (default"),
    ] {
        std::fs::write(&design, edit).unwrap();
        let o = common::shotdamp().arg("design").arg(&design).arg("--dry-run").output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("design.objective") && err.contains(said), "{err}");
    }
}

/// The tiny five-storey design with `extra` added to `[design]`, its searches a single
/// iteration from one start, run into `root/d`: its page folder and the design file.
fn coarse_design(root: &Path, extra: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let text = tiny(&std::fs::read_to_string(common::repo().join("designs/five_storey.toml")).unwrap())
        .replace("max_iters = 8", "max_iters = 1")
        .replace("max_beds = 2", &format!("max_beds = 2\n{extra}"));
    let design = root.join("frame.toml");
    std::fs::write(&design, &text).unwrap();
    let o = design_cmd(&design, root, "d").output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    (root.join("d/design_five_storey"), design)
}

/// The lowest objective of a design page's placements table.
fn best_objective(page: &Path) -> f64 {
    let placements = std::fs::read_to_string(page.join("data/design_placements.csv")).unwrap();
    let header: Vec<&str> = placements.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "objective").unwrap();
    placements
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(col).unwrap().parse::<f64>().unwrap())
        .fold(f64::INFINITY, f64::min)
}

/// `shotdamp design DESIGN --reference ROOT/reference --out ROOT/OUT`, to add to and run.
/// `shotdamp design --dry-run` on a file that is not a design is refused as the run is (it
/// printed nothing and exited 0), naming the file, the key and the value.
#[test]
fn a_dry_run_of_a_file_that_is_not_a_design_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = common::repo().join("experiments/fig05_clearance_scan.toml");
    for dry in [true, false] {
        let mut c = common::shotdamp();
        c.arg("design").arg(&file).arg("--reference").arg(common::repo().join("reference"));
        c.arg("--out").arg(dir.path().join("d"));
        if dry {
            c.arg("--dry-run");
        }
        let o = c.output().unwrap();
        assert_eq!(o.status.code(), Some(2), "dry run {dry}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("fig05_clearance_scan.toml")
                && err.contains("analysis.kind")
                && err.contains("kind = \"design\""),
            "{err}"
        );
        assert!(!dir.path().join("d").exists());
    }
}

/// `shotdamp design --dry-run`: one line a design, with the usual evaluations under the bound,
/// a cost measured on layouts of the coarse scans and a span of time; in seconds; nothing
/// written. The run prints the same line before it searches.
#[test]
fn a_dry_run_prints_one_estimate_measured_in_seconds() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let started = std::time::Instant::now();
    let o = design_cmd(&common::repo().join("designs/five_storey.toml"), root, "d").arg("--dry-run").output().unwrap();
    let took = started.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(0));
    let said = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = said.lines().filter(|l| l.starts_with("design design_five_storey:")).collect();
    assert_eq!(lines.len(), 1, "{said}");
    let line = lines[0];
    let number = |after: &str| -> u64 {
        let rest = &line[line.find(after).unwrap_or_else(|| panic!("{after}: {line}")) + after.len()..];
        rest.chars().take_while(|c| c.is_ascii_digit()).collect::<String>().parse().unwrap()
    };
    let (low, most) = (number("usually "), number("(at most "));
    let high: u64 =
        line[line.find("usually ").unwrap()..].split('-').nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!(0 < low && low < high && high < most, "{line}");
    assert!(
        line.contains("measured") && line.contains("layouts of the coarse scans") && line.contains("about"),
        "{line}"
    );
    assert!(took < 30.0, "the dry run took {took} s");
    assert!(!root.join("d").exists());
}

fn design_cmd(design: &Path, root: &Path, out: &str) -> assert_cmd::Command {
    let mut c = common::shotdamp();
    c.arg("design").arg(design).arg("--reference").arg(root.join("reference")).arg("--out").arg(root.join(out));
    c
}

#[test]
fn a_sharded_search_merges_into_the_whole_search_s_report() {
    // The tiny design with two starts and a Pareto budget: 6 placement searches, split 4 ways
    // (one shard gets one); the merged report is the whole search's, file for file.
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("reference")).unwrap();
    let text = tiny(&std::fs::read_to_string(common::repo().join("designs/five_storey.toml")).unwrap())
        .replace("starts = 1", "starts = 2\npareto_mass_ratios = [0.05]")
        .replace("report = true", "");
    let design = root.join("frame.toml");
    std::fs::write(&design, &text).unwrap();
    let o = design_cmd(&design, root, "whole").output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let parts = root.join("parts");
    for i in 0..4 {
        let o = common::shotdamp()
            .arg("design")
            .arg(&design)
            .arg("--reference")
            .arg(root.join("reference"))
            .arg(format!("--shard={i}/4"))
            .arg("--parts")
            .arg(&parts)
            .arg("--jobs=1")
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }
    // A folder that misses a shard is refused, naming it.
    let some = root.join("some");
    std::fs::create_dir_all(&some).unwrap();
    for i in [0, 1, 3] {
        let name = format!("design-part-{i}-of-4.json");
        std::fs::copy(parts.join(&name), some.join(&name)).unwrap();
    }
    let o = design_cmd(&design, root, "m1").arg("--merge").arg(&some).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("shard = 2/4") && err.contains("--shard 2/4"), "{err}");
    // So is a part of another version of the design.
    let changed = root.join("changed.toml");
    std::fs::write(&changed, text.replace("max_iters = 8", "max_iters = 9")).unwrap();
    let o = design_cmd(&changed, root, "m2").arg("--merge").arg(&parts).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("fingerprint") && err.contains("another version of the design"), "{err}");
    let o = design_cmd(&design, root, "merged").arg("--merge").arg(&parts).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let (whole, merged) = (root.join("whole"), root.join("merged"));
    let mut compared = 0;
    for entry in walk(&whole) {
        let rel = entry.strip_prefix(&whole).unwrap();
        let other = merged.join(rel);
        assert_eq!(std::fs::read(&entry).unwrap(), std::fs::read(&other).unwrap(), "{}", rel.display());
        compared += 1;
    }
    assert_eq!(walk(&merged).len(), compared);
    assert!(compared > 10, "{compared} files");
}

/// Every file below `dir`.
fn walk(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}
