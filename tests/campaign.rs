//! The hostile campaign's second half (docs/reliability.md): mutated finite-element inputs
//! (the plate's experiment file, stiffness, mass and .dof files) through the binary under the
//! campaign's bounds, and mutated explorer requests (sweeps, points, exports; slow, oversized
//! and malformed ones) against one server under a 4 GB address-space limit. By hand:
//!
//!     FUZZ_FE=600 FUZZ_REQUESTS=1000 cargo test --release --locked --test all -- --ignored --nocapture campaign::
//!
//! The property: every run exits 0, 1 or 2 (2 with a message naming a file), never a signal,
//! a panic, the time limit (60 s) or the memory limit; the server answers every request (never
//! 500, never silence past 60 s) and is alive at the end.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use serde_json::json;

use crate::common;
use crate::fuzz::{apply, bounded_run, mutation, repo_file, Mutation, FACTORS};

fn count(k: &str, d: usize) -> usize {
    std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d)
}

fn runner(seed: u8) -> proptest::test_runner::TestRunner {
    let rng = proptest::test_runner::TestRng::from_seed(proptest::test_runner::RngAlgorithm::ChaCha, &[seed; 32]);
    proptest::test_runner::TestRunner::new_with_rng(ProptestConfig::default(), rng)
}

#[test]
#[ignore = "a campaign of tens of minutes: run by hand (docs/reliability.md)"]
fn finite_element_files() {
    let n = count("FUZZ_FE", 20);
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    common::copy_tree(&common::repo().join("reference"), &root.join("reference"));
    let data = root.join("plate");
    std::fs::create_dir_all(&data).unwrap();
    // The plate over a short band (three points, continued): every file a mutation can reach.
    let toml = String::from_utf8(repo_file("examples/plate/plate.toml")).unwrap().replace("data/", "").replace(
        "freq_hz = { start = 30.0, stop = 48.0, step = 0.25 }",
        "freq_hz = { start = 38.0, stop = 39.0, step = 0.5 }",
    );
    let bases: Vec<(&str, Vec<u8>)> = vec![
        ("plate.toml", toml.into_bytes()),
        ("plate.sti", repo_file("examples/plate/data/plate.sti")),
        ("plate.mas", repo_file("examples/plate/data/plate.mas")),
        ("plate.dof", repo_file("examples/plate/data/plate.dof")),
    ];
    for (name, bytes) in &bases {
        std::fs::write(data.join(name), bytes).unwrap();
    }
    let mut runner = runner(count("FUZZ_SEED", 0) as u8);
    let scale = (any::<usize>(), 0..FACTORS.len()).prop_map(|(n, f)| Mutation::ScaleNumber(n, f));
    let strategy = proptest::collection::vec(prop_oneof![3 => scale, 2 => mutation()], 1..3);
    let mut tally = std::collections::BTreeMap::<String, usize>::new();
    let (mut peak, mut slowest, mut failures) = (0u64, 0.0f64, Vec::new());
    for i in 0..n {
        let (name, base) = &bases[i % bases.len()];
        let muts = strategy.new_tree(&mut runner).unwrap().current();
        std::fs::write(data.join(name), apply(base, &muts)).unwrap();
        let args: Vec<String> = ["run", "plate/plate.toml", "--out", "out", "--jobs", "1"].map(String::from).to_vec();
        let (code, wall, kib, stderr) = bounded_run(root, &args, 60, 4_000_000_000);
        peak = peak.max(kib);
        slowest = slowest.max(wall);
        let key = match code {
            Some(c @ 0..=2) => format!("exit {c}"),
            Some(c) => format!("exit {c} (unexpected)"),
            None => "killed (signal, time or memory)".into(),
        };
        *tally.entry(key.clone()).or_default() += 1;
        let message = stderr.lines().rev().find(|l| l.starts_with("error: ")).unwrap_or("");
        let ok = match code {
            Some(0 | 1) => !stderr.contains("panicked"),
            Some(2) => message.contains("plate") || message.contains("(command line)"),
            _ => false,
        };
        if !ok {
            failures.push(format!(
                "{name} {muts:?}: {key} after {wall:.0} s: {}",
                stderr.lines().take(3).collect::<Vec<_>>().join(" / ")
            ));
        }
        std::fs::write(data.join(name), base).unwrap();
        let _ = std::fs::remove_dir_all(root.join("out"));
        if (i + 1) % 50 == 0 {
            println!(
                "after {} runs: {tally:?}; {} failures; peak {:.0} MiB",
                i + 1,
                failures.len(),
                peak as f64 / 1024.0
            );
        }
    }
    println!(
        "finite-element campaign: {n} mutated files; {tally:?}; peak memory {:.0} MiB; slowest run {slowest:.1} s",
        peak as f64 / 1024.0
    );
    for f in &failures {
        println!("FAILURE {f}");
    }
    assert!(failures.is_empty(), "{} failures", failures.len());
}

/// One raw request to `port`: its status (0 when the server closed without an answer) and how
/// long the answer took. `pause`: a slow client's gap between parts of the request.
fn send(port: u16, bytes: &[u8], pause: Option<Duration>) -> (u16, Duration) {
    let t0 = Instant::now();
    let Ok(mut s) = TcpStream::connect(("127.0.0.1", port)) else { return (0, t0.elapsed()) };
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    match pause {
        Some(p) => {
            for part in bytes.chunks(bytes.len().div_ceil(3).max(1)) {
                if s.write_all(part).is_err() {
                    break;
                }
                std::thread::sleep(p);
            }
        }
        None => {
            let _ = s.write_all(bytes);
        }
    }
    let _ = s.shutdown(std::net::Shutdown::Write);
    let mut out = Vec::new();
    let _ = s.read_to_end(&mut out);
    let text = String::from_utf8_lossy(&out);
    (text.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0), t0.elapsed())
}

#[test]
#[ignore = "a campaign of minutes: run by hand (docs/reliability.md)"]
fn explorer_requests() {
    let n = count("FUZZ_REQUESTS", 50);
    let bin = env!("CARGO_BIN_EXE_shotdamp");
    let mut child = std::process::Command::new("prlimit")
        .args(["--as=4294967296", "--", bin, "explore", "experiments/fig05_third_mode.toml", "--port", "0"])
        .current_dir(common::repo())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufRead::read_line(&mut std::io::BufReader::new(child.stdout.take().unwrap()), &mut line).unwrap();
    let url = line.trim().to_string();
    let port: u16 = url.split(':').nth(2).and_then(|s| s.split('/').next()).and_then(|p| p.parse().ok()).unwrap();
    let token = url.split("token=").nth(1).unwrap().to_string();
    let mut runner = runner(count("FUZZ_SEED", 0) as u8);
    let good_sweep = json!({ "set": [["cases[*].dampers[*].clearance_mm", 0.3]], "band": { "start": 46.0, "stop": 50.0, "step": 0.5 }, "start": "rest" }).to_string();
    let good_point = json!({ "setup": { "band": { "start": 44, "stop": 56, "step": 0.5 }, "start": "rest" }, "case": "triple", "freq_hz": 48.0, "periods": 2 }).to_string();
    let scale = (any::<usize>(), 0..FACTORS.len()).prop_map(|(n, f)| Mutation::ScaleNumber(n, f));
    let strategy = proptest::collection::vec(prop_oneof![3 => scale, 1 => mutation()], 1..3);
    let mut tally = std::collections::BTreeMap::<u16, usize>::new();
    let (mut slowest, mut failures) = (Duration::ZERO, Vec::new());
    for i in 0..n {
        let muts = strategy.new_tree(&mut runner).unwrap().current();
        let (path, base) = match i % 3 {
            0 => ("/api/sweep", &good_sweep),
            1 => ("/api/point", &good_point),
            _ => ("/api/export", &good_sweep),
        };
        let mut body = apply(base.as_bytes(), &muts);
        // Every tenth oversized, every tenth slow.
        if i % 10 == 3 {
            body.extend(std::iter::repeat_n(b' ', 70 * 1024));
        }
        let pause = (i % 10 == 7).then_some(Duration::from_millis(300));
        let head = format!("POST {path}?token={token} HTTP/1.1\r\nContent-Length: {}\r\n\r\n", body.len());
        let (status, took) = send(port, &[head.into_bytes(), body].concat(), pause);
        slowest = slowest.max(took);
        *tally.entry(status).or_default() += 1;
        if status == 0 || status == 500 || took > Duration::from_secs(60) {
            failures.push(format!("{path} {muts:?}: {status} after {took:?}"));
        }
        if child.try_wait().unwrap().is_some() {
            failures.push(format!("{path} {muts:?}: the server ended"));
            break;
        }
    }
    let alive = send(port, format!("GET /api/setup?token={token} HTTP/1.1\r\n\r\n").as_bytes(), None).0 == 200;
    let peak = std::fs::read_to_string(format!("/proc/{}/status", child.id()))
        .unwrap_or_default()
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:").map(|v| v.trim().to_string()))
        .unwrap_or_default();
    let _ = child.kill();
    let _ = child.wait();
    println!("explorer campaign: {n} requests; statuses {tally:?}; slowest answer {slowest:?}; server peak {peak}; alive at the end: {alive}");
    for f in &failures {
        println!("FAILURE {f}");
    }
    assert!(failures.is_empty() && alive, "{} failures", failures.len());
}
