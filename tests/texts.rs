//! Numbers in the experiments' texts (deviations, notes, known deviations) are tied to the
//! computation: a number a text quotes from a run is a placeholder filled from that run, so
//! every number left in a text must be an input (of the experiment, its structure files or a
//! study of it), a value of the paper's text, a percentage of one of them, a small integer
//! (ordinals, mode numbers, counts) or a section, equation, figure or year. A stale number
//! typed by hand fails here.

use crate::common;

use std::path::{Path, PathBuf};

use common::{repo, shotdamp};
use shotdamp::experiment::texts::{parse, Piece};

/// Every number of a TOML value, ranges `{ start, stop, step | count }` expanded.
fn numbers(v: &toml::Value, out: &mut Vec<f64>) {
    match v {
        toml::Value::Integer(i) => out.push(*i as f64),
        toml::Value::Float(f) => out.push(*f),
        toml::Value::Array(a) => a.iter().for_each(|x| numbers(x, out)),
        toml::Value::Table(t) => {
            let get = |k: &str| t.get(k).and_then(|x| x.as_float().or(x.as_integer().map(|i| i as f64)));
            if let (Some(a), Some(b)) = (get("start"), get("stop")) {
                let n = match (get("step"), get("count")) {
                    (Some(s), _) if s > 0.0 => ((b - a) / s + 1e-9).floor() as usize + 1,
                    (_, Some(c)) => c as usize,
                    _ => 0,
                };
                for k in 0..n.min(10_000) {
                    out.push(if n > 1 { a + (b - a) * k as f64 / (n - 1) as f64 } else { a });
                    if let Some(s) = get("step") {
                        out.push(a + s * k as f64);
                    }
                }
            }
            t.values().for_each(|x| numbers(x, out));
        }
        _ => {}
    }
}

/// Numbers written in a text, with the word before each: (value, preceding text).
fn tokens(text: &str) -> Vec<(f64, String)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let start = i;
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            if i + 1 < b.len() && b[i] == b'.' && b[i + 1].is_ascii_digit() {
                i += 1;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
            // Part of a name (m2, k_0, omega_2, d02): not a number.
            let named = start > 0 && (b[start - 1].is_ascii_alphabetic() || b[start - 1] == b'_');
            if !named {
                let before = text[..start].chars().rev().take(12).collect::<String>().chars().rev().collect();
                out.push((text[start..i].parse().unwrap(), before));
            }
        } else {
            i += 1;
        }
    }
    out
}

/// The numbers a text may write literally.
struct Allowed {
    values: Vec<f64>,
}

impl Allowed {
    fn allows(&self, x: f64, before: &str) -> bool {
        let small_integer = x.fract() == 0.0 && x <= 20.0;
        let year = x.fract() == 0.0 && (1900.0..=2100.0).contains(&x);
        let reference = ["section ", "Section ", "Eq. ", "Eqs. ", "Fig. ", "Figs. ", "and "]
            .iter()
            .any(|w| before.ends_with(w) && (w != &"and " || before.contains("section")));
        small_integer
            || year
            || reference
            || self
                .values
                .iter()
                .any(|v| (v - x).abs() <= 1e-9 * x.abs().max(1.0) || (100.0 * v - x).abs() <= 1e-9 * x.abs().max(1.0))
    }
}

fn toml_numbers(path: &Path, out: &mut Vec<f64>) {
    let text = std::fs::read_to_string(path).unwrap();
    let value: toml::Value = toml::from_str(&text).unwrap();
    numbers(&value, out);
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(files(&p));
        } else if p.extension().is_some_and(|x| x == "toml") {
            out.push(p);
        }
    }
    out.sort();
    out
}

/// What an experiment file's texts may write: its own numbers, those of the shared structure
/// and model files, of the studies of it, and every number of the paper's text.
fn allowed_for(file: &Path) -> Allowed {
    let mut values = Vec::new();
    toml_numbers(file, &mut values);
    for f in files(&repo().join("experiments/shared")) {
        toml_numbers(&f, &mut values);
    }
    let name = file.file_name().unwrap().to_string_lossy().to_string();
    for f in files(&repo().join("studies")) {
        if std::fs::read_to_string(&f).unwrap().contains(&name) {
            toml_numbers(&f, &mut values);
        }
    }
    let paper = std::fs::read_to_string(repo().join("reference/paper-text.toml")).unwrap();
    values.extend(tokens(&paper).into_iter().map(|t| t.0));
    Allowed { values }
}

/// The texts of an experiment file: (key, text).
fn texts(file: &Path) -> Vec<(String, String)> {
    let value: toml::Value = toml::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    let mut out = Vec::new();
    let mut add = |key: String, v: &toml::Value| match v {
        toml::Value::String(s) => out.push((key, s.clone())),
        toml::Value::Table(t) => {
            t.iter().for_each(|(m, s)| out.push((format!("{key}.{m}"), s.as_str().unwrap().into())))
        }
        _ => {}
    };
    let meta = &value["experiment"];
    if let Some(d) = meta.get("deviation") {
        add("experiment.deviation".into(), d);
    }
    for (i, n) in meta.get("notes").and_then(|n| n.as_array()).into_iter().flatten().enumerate() {
        add(format!("experiment.notes[{i}]"), n);
    }
    for (i, c) in value.get("checks").and_then(|c| c.as_array()).into_iter().flatten().enumerate() {
        if let Some(d) = c.get("known_deviation") {
            add(format!("checks[{i}].known_deviation"), d);
        }
    }
    out
}

/// The numbers of a text that are neither placeholders nor allowed.
fn stale(text: &str, allowed: &Allowed) -> Vec<f64> {
    let pieces = parse(text).unwrap();
    pieces
        .iter()
        .filter_map(|p| match p {
            Piece::Literal(s) => Some(s),
            Piece::Value(_) => None,
        })
        .flat_map(|s| tokens(s))
        .filter(|(x, before)| !allowed.allows(*x, before))
        .map(|t| t.0)
        .collect()
}

fn experiment_files() -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> = std::fs::read_dir(repo().join("experiments"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    all.extend(files(&repo().join("designs")));
    all.sort();
    all
}

#[test]
fn every_number_in_a_text_is_an_input_a_paper_value_or_a_placeholder() {
    let mut found = Vec::new();
    let mut n_texts = 0;
    for file in experiment_files() {
        let allowed = allowed_for(&file);
        for (key, text) in texts(&file) {
            n_texts += 1;
            for x in stale(&text, &allowed) {
                found.push(format!("{}: {key}: {x} (\"{text}\")", file.display()));
            }
        }
    }
    assert!(n_texts > 40, "{n_texts} texts");
    assert!(found.is_empty(), "numbers typed by hand, not tied to the computation:\n{}", found.join("\n"));
}

#[test]
fn a_stale_number_typed_into_a_deviation_is_caught() {
    let file = repo().join("experiments/fig05_third_mode.toml");
    let allowed = allowed_for(&file);
    let (_, text) = texts(&file).into_iter().find(|(k, _)| k == "experiment.deviation.stated").unwrap();
    assert!(stale(&text, &allowed).is_empty());
    // The ratio as it once was typed: 1.7 (today's value, rounded), then a drifted 1.8.
    for typed in ["1.7", "1.8"] {
        let hand = text.replacen("{peak:1}", typed, 1);
        assert_ne!(hand, text);
        assert_eq!(stale(&hand, &allowed), vec![typed.parse::<f64>().unwrap()], "{hand}");
    }
}

/// The filled texts give the run's own numbers: a known deviation quoting its check's value
/// (`{small:1}`) prints that value, rounded as stated; a text naming an experiment not in the
/// run says so instead of guessing.
#[test]
fn placeholders_are_filled_from_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let out = shotdamp()
        .args(["run", "experiments/fig05_clearance_scan.toml", "experiments/fig05_low_damping.toml", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(out.status.code().is_some_and(|c| c <= 1), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out_dir.join("checks.json")).unwrap()).unwrap();
    let mut seen = 0;
    for c in json["checks"].as_array().unwrap() {
        if c["experiment"] == "fig05_low_damping" && c["id"] == "small" {
            let reason = c["reason"].as_str().unwrap();
            let v = c["computed"].as_f64().unwrap();
            assert!(reason.contains(&format!("{v:.1}")), "{reason} should quote {v:.1}");
            assert!(!reason.contains('{'), "{reason}");
            seen += 1;
        }
    }
    assert_eq!(seen, 3, "one per model");
    let page = std::fs::read_to_string(out_dir.join("fig05_low_damping/stated/index.html")).unwrap();
    assert!(page.contains("[{fig05_third_mode#peak:1}: its experiment is not in this run]"));
}

/// A placeholder naming a check the experiment does not have is an input error at load.
#[test]
fn an_unknown_placeholder_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let exps = common::experiments(dir.path(), &["fig05_low_damping.toml"]);
    let file = exps.join("fig05_low_damping.toml");
    let text = std::fs::read_to_string(&file).unwrap().replacen("{small:1}", "{smal:1}", 1);
    std::fs::write(&file, text).unwrap();
    let out = shotdamp().arg("modal").arg(&file).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("{smal:1}") && err.contains("no check of this experiment has id \"smal\""), "{err}");
}
