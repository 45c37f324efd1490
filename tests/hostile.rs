//! The hostile retest's defects, each through the binary: one explorer request that took the
//! server down or held it, slow clients that locked everyone out, a valid low frequency that
//! filled the memory, finite-element files that are not a structure (indefinite, floating,
//! too large, a named pipe), a changed file of a report. Memory is asserted as the run's peak
//! resident size (VmHWM), under an address-space limit of 4 GB where `prlimit` exists.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common::{repo, shotdamp};
use crate::explore::Served;

/// 4 GB: the address-space limit the runs here are held to.
const LIMIT: &str = "--as=4294967296";

/// `shotdamp ARGS` in `dir`, under the 4 GB address-space limit where `prlimit` exists.
fn limited(dir: &Path, args: &[&str]) -> Command {
    let mut c = if Command::new("prlimit").arg("--version").output().is_ok() {
        let mut c = Command::new("prlimit");
        c.arg(LIMIT).arg(env!("CARGO_BIN_EXE_shotdamp"));
        c
    } else {
        Command::new(env!("CARGO_BIN_EXE_shotdamp"))
    };
    c.current_dir(dir).args(args).stdout(Stdio::null()).stderr(Stdio::piped());
    c
}

/// A process's peak resident memory so far, kB (0 once it is gone).
fn peak_kb(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}

/// Waits for `child` at most `limit`, following its peak memory (of the process itself, or
/// of the one `prlimit` runs in its place: the same pid, `prlimit` execs it). The exit code
/// (None when it had to be killed), stderr and the peak, kB.
fn watch(mut child: Child, limit: Duration) -> (Option<i32>, String, u64) {
    let t0 = Instant::now();
    let mut peak = 0;
    let status = loop {
        peak = peak.max(peak_kb(child.id()));
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut err);
    }
    (status, err, peak)
}

fn point(freq_hz: f64) -> String {
    json!({ "setup": { "band": { "start": 44, "stop": 56, "step": 0.5 }, "start": "rest" }, "case": "triple", "freq_hz": freq_hz, "periods": 8 })
        .to_string()
}

#[test]
fn a_point_far_below_the_structure_s_frequencies_is_refused_and_the_server_stays() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    for f in [1e-4, 1e-6] {
        let t0 = Instant::now();
        let (code, body) = s.call("POST", "/api/point", &point(f));
        assert_eq!(code, 422, "{f} Hz: {body}");
        assert!(
            body.contains("request")
                && body.contains("freq_hz")
                && body.contains("times the structure's highest natural frequency"),
            "{body}"
        );
        assert!(t0.elapsed() < Duration::from_secs(5), "{f} Hz took {:?}", t0.elapsed());
    }
    assert_eq!(s.call("GET", "/api/setup", "").0, 200);
    let kb = peak_kb(s.pid());
    assert!(kb < 400_000, "peak {kb} kB");
}

#[test]
fn a_point_at_the_lowest_frequency_ends_within_the_time_limit_in_bounded_memory() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    // The floor, as the refusal states it ("i.e. F Hz").
    let (_, body) = s.call("POST", "/api/point", &point(1e-9));
    let floor: f64 = body
        .split("i.e. ")
        .nth(1)
        .and_then(|r| r.split(" Hz").next())
        .and_then(|f| f.parse().ok())
        .unwrap_or_else(|| panic!("no floor in {body}"));
    let t0 = Instant::now();
    let (code, body) = s.call("POST", "/api/point", &point(floor * 1.01));
    let took = t0.elapsed();
    // Answered, or stopped by the time limit (30 s) with its reason.
    assert!(code == 200 || (code == 503 && body.contains("stopped after 30 s")), "{code}: {body}");
    assert!(took < Duration::from_secs(40), "{took:?}");
    let kb = peak_kb(s.pid());
    println!("a point at {:.3e} Hz: {code} in {took:?}, peak {kb} kB", floor * 1.01);
    assert!(kb < 1_000_000, "peak {kb} kB");
    assert_eq!(s.call("GET", "/api/setup", "").0, 200);
}

#[test]
fn slow_clients_do_not_lock_the_page_s_users_out() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    // 40 connections that send a byte now and then and never finish their request.
    let slow: Vec<TcpStream> = (0..40)
        .map(|_| {
            let mut c = TcpStream::connect(("127.0.0.1", s.port)).unwrap();
            let _ = c.write_all(b"P");
            c
        })
        .collect();
    let dribble = {
        let mut slow: Vec<TcpStream> = slow.iter().map(|c| c.try_clone().unwrap()).collect();
        std::thread::spawn(move || {
            for _ in 0..4 {
                std::thread::sleep(Duration::from_millis(1500));
                for c in &mut slow {
                    let _ = c.write_all(b"O");
                }
            }
        })
    };
    std::thread::sleep(Duration::from_millis(500));
    for _ in 0..3 {
        let t0 = Instant::now();
        let (code, _) = s.call("GET", "/api/setup", "");
        assert_eq!(code, 200, "a user's request among 40 slow ones");
        assert!(t0.elapsed() < Duration::from_secs(3), "{:?}", t0.elapsed());
        std::thread::sleep(Duration::from_millis(700));
    }
    dribble.join().unwrap();
    // Each slow one is closed within the 10 s a request has to arrive (or made room earlier).
    for mut c in slow {
        c.set_read_timeout(Some(Duration::from_secs(15))).unwrap();
        let mut out = Vec::new();
        let t0 = Instant::now();
        let _ = c.read_to_end(&mut out);
        assert!(t0.elapsed() < Duration::from_secs(12), "a slow connection stayed open");
    }
}

#[test]
fn a_request_s_bad_value_is_the_request_s_and_its_head_is_read_strictly() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    let body = json!({ "set": [["cases[*].dampers[*].bed", "restitution"]], "band": { "start": 47, "stop": 48, "step": 0.5 }, "start": "rest" }).to_string();
    let (code, answer) = s.call("POST", "/api/sweep", &body);
    assert_eq!(code, 422, "{answer}");
    let m = serde_json::from_str::<Value>(&answer).unwrap()["error"].as_str().unwrap().to_string();
    assert!(
        m.starts_with("request (on experiments/fig05_third_mode.toml, model 0; values set: set[0] cases[*].dampers[*].bed = \"restitution\")"),
        "{m}"
    );
    assert!(m.contains("restitution"), "{m}");
    // Two Content-Length headers: refused, whichever would win.
    let twice = format!(
        "POST /api/sweep?token={} HTTP/1.1\r\nContent-Length: 2\r\nContent-Length: {}\r\n\r\n{body}",
        s.token,
        body.len()
    );
    let (code, answer) = s.raw(twice.as_bytes());
    assert!(code == 400 && answer.contains("Content-Length is given twice"), "{code} {answer}");
    // A request number past what the page can count is refused; the numbering goes on.
    let top = json!({ "seq": u64::MAX, "set": [], "band": { "start": 47, "stop": 48, "step": 0.5 }, "start": "rest" });
    let (code, answer) = s.call("POST", "/api/sweep", &top.to_string());
    assert!(code == 400 && answer.contains("a whole number from 0 to 9007199254740991"), "{code} {answer}");
    let plain = json!({ "set": [], "band": { "start": 47, "stop": 48, "step": 0.5 }, "start": "rest" });
    assert_eq!(s.call("POST", "/api/sweep", &plain.to_string()).0, 200);
    assert_eq!(s.call("POST", "/api/sweep", &plain.to_string()).0, 200);
}

#[test]
fn a_port_in_use_is_said_before_anything_is_computed() {
    let taken = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let t0 = Instant::now();
    let out = shotdamp()
        .current_dir(repo())
        .args(["explore", "experiments/fig10a_three_dampers.toml", "--port", &port])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains(&format!("127.0.0.1:{port}")) && err.contains("in use"), "{err}");
    assert!(!err.contains("explore: reading"), "nothing is read before the port: {err}");
    println!("refused in {:?}", t0.elapsed());
}

#[test]
fn a_valid_low_frequency_runs_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let exps = crate::common::experiments(dir.path(), &["fig08_number_of_dampers.toml"]);
    let file = exps.join("fig08_number_of_dampers.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let grid = text.lines().find(|l| l.starts_with("freq_hz")).expect("a grid").to_string();
    std::fs::write(&file, text.replace(&grid, "freq_hz = { start = 0.0006, stop = 0.00061, step = 0.00001 }")).unwrap();
    let reference = repo().join("reference");
    let reference = reference.to_str().unwrap();
    let child = limited(
        dir.path(),
        &["run", "experiments/fig08_number_of_dampers.toml", "--reference", reference, "--out", "out", "--jobs", "8"],
    )
    .spawn()
    .unwrap();
    let (code, err, kb) = watch(child, Duration::from_secs(600));
    println!("fig08 at 0.6 mHz: exit {code:?}, peak {kb} kB");
    assert!(code == Some(0) || code == Some(1), "{code:?}: {err}");
    assert!(kb < 1_000_000, "peak {kb} kB");
}

/// The paper's chain with a piece of two masses joined to each other and to nothing else, the
/// piece's first mass a point: it floats free (a zero stiffness at that point). And a mass
/// matrix whose coupling exceeds its diagonal (indefinite).
#[test]
fn finite_element_matrices_that_are_not_a_structure_are_refused_naming_file_and_point() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mm = |name: &str, entries: &[(usize, usize, f64)]| {
        let mut t = format!("%%MatrixMarket matrix coordinate real symmetric\n5 5 {}\n", entries.len());
        for (i, j, v) in entries {
            t.push_str(&format!("{i} {j} {v}\n"));
        }
        std::fs::write(d.join(name), t).unwrap();
    };
    let k = [
        (1, 1, 46100.0),
        (2, 1, -21800.0),
        (2, 2, 41600.0),
        (3, 2, -19800.0),
        (3, 3, 19800.0),
        (4, 4, 1e4),
        (5, 4, -1e4),
        (5, 5, 1e4),
    ];
    mm("k.mtx", &k);
    mm("m.mtx", &[(1, 1, 0.74), (2, 2, 0.71), (3, 3, 0.64), (4, 4, 0.5), (5, 5, 0.5)]);
    let text = |points: &str| {
        format!(
            "[experiment]\nid = \"fe\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{points}]\nmodes = 1\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 1.0\n[analysis]\nkind = \"modal\"\n"
        )
    };
    let run = |name: &str, points: &str| {
        std::fs::write(d.join(format!("{name}.toml")), text(points)).unwrap();
        let out = shotdamp().current_dir(d).args(["run", &format!("{name}.toml"), "--out", name]).output().unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (code, err) = run("floating", "{ row = 1 }, { row = 4, name = \"loose\" }");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("k.mtx: the stiffness matrix is not positive definite at point \"loose\" (row 4, points[1])")
            && err.contains("floats free"),
        "{err}"
    );
    // Held at neither of its masses: its interior is not held.
    let (code, err) = run("interior", "{ row = 1 }");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("k.mtx: the stiffness matrix is not positive definite")
            && (err.contains("at row 4") || err.contains("at row 5")),
        "{err}"
    );
    mm("m.mtx", &[(1, 1, 0.74), (2, 2, 0.71), (3, 3, 0.64), (4, 4, 0.5), (5, 4, 0.9), (5, 5, 0.5)]);
    mm(
        "k.mtx",
        &[
            (1, 1, 46100.0),
            (2, 1, -21800.0),
            (2, 2, 41600.0),
            (3, 2, -19800.0),
            (3, 3, 20800.0),
            (4, 3, -1e3),
            (4, 4, 2e4),
            (5, 4, -1e4),
            (5, 5, 2e4),
        ],
    );
    let (code, err) = run("mass", "{ row = 1 }");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("m.mtx: the mass matrix is not positive definite")
            && (err.contains("at row 4") || err.contains("at row 5")),
        "{err}"
    );
}

/// A Matrix Market model of 40,000 degrees of freedom, each row tied to two others far away:
/// its envelope is known before the factor is allocated, and refused.
#[test]
fn a_finite_element_model_too_large_to_reduce_is_refused_before_it_fills_the_memory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 40_000usize;
    let mut state = 12345u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 33) as usize % n
    };
    let mut entries: std::collections::BTreeMap<(usize, usize), f64> = std::collections::BTreeMap::new();
    for i in 0..n {
        entries.insert((i, i), 10.0);
        for _ in 0..2 {
            let j = next();
            if j != i {
                entries.insert((i.max(j), i.min(j)), -1.0);
            }
        }
    }
    let mut k = format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {}\n", entries.len());
    for ((i, j), v) in &entries {
        k.push_str(&format!("{} {} {v}\n", i + 1, j + 1));
    }
    std::fs::write(d.join("k.mtx"), k).unwrap();
    let mut m = format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {n}\n");
    for i in 1..=n {
        m.push_str(&format!("{i} {i} 1.0\n"));
    }
    std::fs::write(d.join("m.mtx"), m).unwrap();
    std::fs::write(
        d.join("big.toml"),
        "[experiment]\nid = \"big\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{ row = 1 }]\nmodes = 4\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 1.0\n[analysis]\nkind = \"modal\"\n",
    )
    .unwrap();
    let t0 = Instant::now();
    let child = limited(d, &["run", "big.toml", "--out", "out"]).spawn().unwrap();
    let (code, err, kb) = watch(child, Duration::from_secs(120));
    println!("40,000 degrees of freedom: {code:?} in {:?}, peak {kb} kB", t0.elapsed());
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("big.toml: structure.finite_element = 40000 degrees of freedom: is too large to reduce here"),
        "{err}"
    );
    assert!(kb < 1_000_000, "peak {kb} kB");
}

#[test]
fn a_named_pipe_as_a_matrix_file_is_refused_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = repo().join("examples/plate/data");
    for f in ["plate.mas", "plate.dof"] {
        std::fs::copy(data.join(f), d.join(f)).unwrap();
    }
    let made = Command::new("mkfifo").arg(d.join("plate.sti")).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("no mkfifo here: skipped");
        return;
    }
    let plate = std::fs::read_to_string(repo().join("examples/plate/plate.toml")).unwrap();
    std::fs::write(d.join("plate.toml"), plate.replace("data/", "")).unwrap();
    for command in ["run", "modal"] {
        let mut c = Command::new(env!("CARGO_BIN_EXE_shotdamp"));
        c.current_dir(d).arg(command).arg("plate.toml").stdout(Stdio::null()).stderr(Stdio::piped());
        if command == "run" {
            c.args(["--out", "out"]);
        }
        let (code, err, _) = watch(c.spawn().unwrap(), Duration::from_secs(20));
        assert_eq!(code, Some(2), "{command}: {err}");
        assert!(
            err.contains("structure.finite_element.stiffness = \"plate.sti\": cannot be read (not a regular file"),
            "{err}"
        );
    }
}

#[test]
fn the_structure_s_mass_is_printed_and_shot_far_lighter_than_it_is_questioned() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plate = std::fs::read_to_string(repo().join("examples/plate/plate.toml")).unwrap();
    let data = repo().join("examples/plate/data");
    let text = plate.replace("\"data/", &format!("\"{}/", data.display())).replace(
        "freq_hz = { start = 30.0, stop = 48.0, step = 0.25 }",
        "freq_hz = { start = 38.0, stop = 39.0, step = 0.5 }",
    );
    std::fs::write(d.join("si.toml"), &text).unwrap();
    let out = shotdamp().current_dir(d).args(["modal", "si.toml"]).output().unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("finite-element model: 1410 degrees of freedom")
            && said.contains("the mass moving along the vertical (z) is 1.842"),
        "{said}"
    );
    // The same files read as N-mm-t: the plate moves 1.84 t, the shot 47 g.
    std::fs::write(d.join("t.toml"), text.replace("up = \"z\"", "up = \"z\"\nunits = \"N-mm-t\"")).unwrap();
    let out = shotdamp().current_dir(d).args(["run", "t.toml", "--out", "t"]).output().unwrap();
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(
        said.contains("warning: t.toml: the finite-element structure's mass moving along the vertical is 1842.")
            && said.contains("less than 1e-3 of it"),
        "{said}"
    );
}

#[test]
fn a_file_of_a_report_changed_after_shotdamp_wrote_it_is_not_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let exps = crate::common::experiments(dir.path(), &["fig04b_no_damper.toml"]);
    let _ = exps;
    let reference = repo().join("reference");
    let run = || {
        shotdamp()
            .current_dir(dir.path())
            .args(["run", "experiments/fig04b_no_damper.toml", "--out", "r", "--reference"])
            .arg(&reference)
            .output()
            .unwrap()
    };
    assert_eq!(run().status.code(), Some(0));
    // Unchanged: replaced as before.
    assert_eq!(run().status.code(), Some(0));
    let index = dir.path().join("r/index.html");
    let mut page = std::fs::read_to_string(&index).unwrap();
    page.push_str("<!-- my notes -->");
    std::fs::write(&index, &page).unwrap();
    let out = run();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("index.html (changed since shotdamp wrote it)"), "{err}");
    assert_eq!(std::fs::read_to_string(&index).unwrap(), page, "the user's edit is kept");
}
