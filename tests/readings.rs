//! The readings of a claim about "amplitude reductions around resonance": each computed value
//! is what the sweep's own table gives by hand.

use crate::common;

use common::{repo, shotdamp};

const EXPERIMENT: &str = r#"
[experiment]
id = "readings"
title = "t"
figure = "Fig. 5"
caption = "-"
claim = "-"

[structure]
masses_kg = [0.74, 0.71, 0.64]
chain_stiffness_n_per_m = [24.3e3, 21.8e3, 19.8e3]

[structure.damping]
modal_ratios = [0.01, 0.01, 0.01]

[excitation]
mass = 1
force_n = 2.6

[analysis]
kind = "sweep"
freq_hz = { start = 46.0, stop = 50.0, step = 0.1 }

[[cases]]
id = "single"
label = "one damper on m2"
dampers = [{ mass = 2, mass_ratio = 0.1, clearance_mm = 0.2 }]

[[cases]]
id = "triple"
label = "dampers on m1, m2, m3"
dampers = [
    { mass = 1, mass_ratio = 0.1, clearance_mm = 0.2 },
    { mass = 2, mass_ratio = 0.1, clearance_mm = 0.2 },
    { mass = 3, mass_ratio = 0.1, clearance_mm = 0.2 },
]
"#;

fn check(reading: &str) -> String {
    format!(
        "\n[[checks]]\nkind = \"peak_ratio\"\nreading = \"{reading}\"\ncase = \"single\"\nover_case = \"triple\"\nmass = 2\nreference = \"paper-text.toml#reduction_min\"\nrange_to = \"reduction_max\"\nrel_tol = 0.0\nknown_deviation = \"whatever it is\"\n"
    )
}

#[test]
fn each_reading_is_the_value_of_the_sweep_table_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("readings.toml");
    let text = format!("{EXPERIMENT}{}{}{}", check("peak_over_peak"), check("at_resonance"), check("band_max"));
    std::fs::write(&file, text).unwrap();
    let out_dir = dir.path().join("out");
    let out = shotdamp()
        .arg("--reference")
        .arg(repo().join("reference"))
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));

    // The table: (freq, c2, regular) per case.
    let table = std::fs::read_to_string(out_dir.join("readings/data/compliance.csv")).unwrap();
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(String::from).collect()).collect();
    let curve = |id: &str| -> Vec<(f64, f64, bool, bool)> {
        rows.iter()
            .filter(|r| r[col("curve")] == id)
            .map(|r| {
                let conv = r[col("converged")] == "1";
                (
                    r[col("freq_hz")].parse().unwrap(),
                    r[col("c2")].parse().unwrap(),
                    conv,
                    conv && r[col("period")] == "1",
                )
            })
            .collect()
    };
    let (single, triple) = (curve("single"), curve("triple"));
    assert_eq!(single.len(), 41);
    let peak = |c: &[(f64, f64, bool, bool)]| {
        c.iter().filter(|p| p.2).map(|p| (p.0, p.1)).max_by(|a, b| a.1.total_cmp(&b.1)).unwrap()
    };
    let at = |c: &[(f64, f64, bool, bool)], f: f64| c.iter().find(|p| p.0 == f).unwrap().1;
    let (fs, ps) = peak(&single);
    let peak_over_peak = ps / peak(&triple).1;
    let at_resonance = ps / at(&triple, fs);
    let band_max = single
        .iter()
        .filter(|p| p.3 && p.1 >= ps / std::f64::consts::SQRT_2)
        .filter_map(|p| triple.iter().find(|q| q.0 == p.0 && q.3).map(|q| p.1 / q.1))
        .fold(0.0, f64::max);

    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out_dir.join("checks.json")).unwrap()).unwrap();
    let computed = |prefix: &str| {
        json["checks"].as_array().unwrap().iter().find(|c| c["name"].as_str().unwrap().starts_with(prefix)).unwrap()
            ["computed"]
            .as_f64()
            .unwrap()
    };
    for (name, by_hand) in [
        ("peak ratio single / triple", peak_over_peak),
        ("ratio single / triple at single's resonance", at_resonance),
        ("largest ratio single / triple over single's resonance band", band_max),
    ] {
        let c = computed(name);
        // The CSV holds every digit of f64: the same numbers.
        assert!((c / by_hand - 1.0).abs() < 1e-12, "{name}: {c} against {by_hand} by hand");
    }
    // The readings differ: at the single damper's resonance the three dampers' response is
    // not at its own peak.
    assert!(at_resonance > peak_over_peak, "{at_resonance} {peak_over_peak}");

    // A study over the same point (damping 0.01, d = 0.2 mm) gives the same three numbers.
    let study = dir.path().join("study.toml");
    std::fs::write(
        &study,
        "[study]\nid = \"one\"\ntitle = \"t\"\nexperiment = \"readings.toml\"\n[[vary]]\nname = \"damping\"\nkey = \"structure.damping.modal_ratios\"\nvalues = [0.01]\n[[vary]]\nname = \"clearance_mm\"\nkey = \"cases[*].dampers[*].clearance_mm\"\nvalues = [0.2]\n",
    )
    .unwrap();
    let st = dir.path().join("st");
    let out = shotdamp()
        .arg("--reference")
        .arg(repo().join("reference"))
        .args(["study", study.to_str().unwrap(), "--out", st.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = common::csv_rows(&std::fs::read_to_string(st.join("one.csv")).unwrap());
    let col = |n: &str| rows[0].iter().position(|h| h == n).unwrap();
    for (name, by_hand) in [("peak_over_peak", peak_over_peak), ("at_resonance", at_resonance), ("band_max", band_max)]
    {
        let row = rows.iter().find(|r| r[col("reading")] == name).unwrap();
        let v: f64 = row[col("value")].parse().unwrap();
        assert!((v / by_hand - 1.0).abs() < 1e-12, "study {name}: {v} against {by_hand} by hand");
    }
}

#[test]
fn an_unknown_reading_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("readings.toml");
    std::fs::write(&file, format!("{EXPERIMENT}{}", check("mean"))).unwrap();
    let out = shotdamp().arg("--reference").arg(repo().join("reference")).arg("modal").arg(&file).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("checks[0].reading = \"mean\"") && err.contains("band_max"), "{err}");
}

/// Fig. 5's study point on the stated chain at damping 0.005, d = 0.3 mm, 0.2 Hz steps: the three
/// dampers' response at the single damper's resonance (48.4 Hz) is a motion with no stable
/// periodic orbit. Each reading's `settled` flag is what the sweep table gives by hand; the
/// study carries it into its table, its summary counts it apart, its map marks it.
#[test]
fn each_readings_settled_flag_is_the_sweep_table_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("readings.toml");
    let experiment = EXPERIMENT
        .replace("[0.01, 0.01, 0.01]", "[0.005, 0.005, 0.005]")
        .replace("clearance_mm = 0.2", "clearance_mm = 0.3")
        .replace("start = 46.0, stop = 50.0, step = 0.1", "start = 44.0, stop = 56.0, step = 0.2");
    let text = format!("{experiment}{}{}{}", check("peak_over_peak"), check("at_resonance"), check("band_max"));
    std::fs::write(&file, text).unwrap();
    let out_dir = dir.path().join("out");
    let out = shotdamp()
        .arg("--reference")
        .arg(repo().join("reference"))
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));

    let rows = common::csv_rows(&std::fs::read_to_string(out_dir.join("readings/data/compliance.csv")).unwrap());
    let col = |n: &str| rows[0].iter().position(|h| h == n).unwrap();
    // (freq, c2, converged, converged and period-1) per point.
    let curve = |id: &str| -> Vec<(f64, f64, bool, bool)> {
        rows[1..]
            .iter()
            .filter(|r| r[col("curve")] == id)
            .map(|r| {
                let conv = r[col("converged")] == "1";
                (
                    r[col("freq_hz")].parse().unwrap(),
                    r[col("c2")].parse().unwrap(),
                    conv,
                    conv && r[col("period")] == "1",
                )
            })
            .collect()
    };
    let (single, triple) = (curve("single"), curve("triple"));
    assert_eq!(single.len(), 61);
    // A peak over settled points is settled when no unsettled point is higher.
    let peak = |c: &[(f64, f64, bool, bool)]| *c.iter().filter(|p| p.2).max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    let peak_settled = |c: &[(f64, f64, bool, bool)]| c.iter().all(|p| p.2 || p.1 <= peak(c).1);
    let (fs, ps, ..) = peak(&single);
    let at = triple.iter().find(|p| p.0 == fs).unwrap();
    let by_hand_peak = peak_settled(&single) && peak_settled(&triple);
    let by_hand_at = peak_settled(&single) && at.3;
    // The band: single within 1/sqrt(2) of its peak; settled when the points skipped there
    // (not period-1 on either side) would not raise the largest ratio.
    let band: Vec<(f64, bool)> = single
        .iter()
        .zip(&triple)
        .filter(|(p, _)| p.1 >= ps / std::f64::consts::SQRT_2)
        .map(|(p, q)| (p.1 / q.1, p.3 && q.3))
        .collect();
    let kept = band.iter().filter(|b| b.1).map(|b| b.0).fold(0.0, f64::max);
    let by_hand_band = peak_settled(&single) && band.iter().all(|b| b.1 || b.0 <= kept);
    // This point is the case the flag exists for.
    assert!(!at.2, "the three dampers at {fs} Hz were expected not to settle");
    assert!(!by_hand_at && !by_hand_band && by_hand_peak);

    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out_dir.join("checks.json")).unwrap()).unwrap();
    let settled = |prefix: &str| {
        json["checks"].as_array().unwrap().iter().find(|c| c["name"].as_str().unwrap().starts_with(prefix)).unwrap()
            ["settled"]
            .as_bool()
            .unwrap()
    };
    assert_eq!(settled("peak ratio single / triple"), by_hand_peak);
    assert_eq!(settled("ratio single / triple at single's resonance"), by_hand_at);
    assert_eq!(settled("largest ratio single / triple over single's resonance band"), by_hand_band);
    let page = std::fs::read_to_string(out_dir.join("readings/index.html")).unwrap();
    assert_eq!(page.matches("rests on a point that did not settle").count(), 2, "the check table marks both");

    // A study over the point: the flag in its table, counted apart in its summary, marked in
    // its map.
    let study = dir.path().join("study.toml");
    std::fs::write(
        &study,
        "[study]\nid = \"one\"\ntitle = \"t\"\nexperiment = \"readings.toml\"\nmap = [\"clearance_mm\", \"damping\"]\n[[vary]]\nname = \"damping\"\nkey = \"structure.damping.modal_ratios\"\nvalues = [0.005]\n[[vary]]\nname = \"clearance_mm\"\nkey = \"cases[*].dampers[*].clearance_mm\"\nvalues = [0.3]\n",
    )
    .unwrap();
    let st = dir.path().join("st");
    let out = shotdamp()
        .arg("--reference")
        .arg(repo().join("reference"))
        .args(["study", study.to_str().unwrap(), "--out", st.to_str().unwrap()])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stdout).to_string();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = common::csv_rows(&std::fs::read_to_string(st.join("one.csv")).unwrap());
    let col = |n: &str| rows[0].iter().position(|h| h == n).unwrap();
    for (name, by_hand) in [("peak_over_peak", by_hand_peak), ("at_resonance", by_hand_at), ("band_max", by_hand_band)]
    {
        let row = rows.iter().find(|r| r[col("reading")] == name).unwrap();
        assert_eq!(row[col("settled")], if by_hand { "1" } else { "0" }, "{name}");
    }
    let summary = common::csv_rows(&std::fs::read_to_string(st.join("one_summary.csv")).unwrap());
    let scol = |n: &str| summary[0].iter().position(|h| h == n).unwrap();
    for (check, by_hand) in [by_hand_peak, by_hand_at, by_hand_band].into_iter().enumerate() {
        let r = &summary[check + 1];
        assert_eq!(r[scol("unsettled")], if by_hand { "0" } else { "1" }, "check {check}");
        if !by_hand {
            // Counted apart: not among the samples where it holds or fails.
            assert_eq!(r[scol("holds")], "0", "check {check}");
            assert_eq!(r[scol("fraction")], "NaN", "check {check}");
        }
    }
    assert!(said.contains("on an unsettled point"), "{said}");
    let map = std::fs::read_to_string(st.join("figures/one_check-1.svg")).unwrap();
    let doc = roxmltree::Document::parse(&map).unwrap();
    // The title (wrapped over lines) says what the strokes mean.
    let words: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .flat_map(|t| t.split_whitespace())
        .collect();
    assert!(words.join(" ").contains("the value rests on a point that did not settle"), "the map's legend");
    // Three strokes across the cell in the colour of unsettled values (the legend names it).
    let strokes = doc
        .descendants()
        .filter(|n| n.is_element() && !matches!(n.tag_name().name(), "g" | "svg"))
        .filter(|n| n.ancestors().find_map(|a| a.attribute("stroke")) == Some("#8250DF"))
        .count();
    assert_eq!(strokes, 3, "three strokes in the map");
}
