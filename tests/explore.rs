//! `shotdamp explore`: the server answers the page's requests with the library's curves,
//! validates them as experiment files are validated, refuses what has no business reaching it
//! (other keys, files, no token), survives garbage, and its exported setup reproduces its
//! curves through `shotdamp run`. The page in a real browser: `browser::explore`.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use serde_json::{json, Value};

/// A running `shotdamp explore` on a free port of 127.0.0.1; killed when dropped.
pub struct Served {
    child: Child,
    /// The page's address with its token.
    pub url: String,
    /// The port.
    pub port: u16,
    /// The token.
    pub token: String,
}

impl Served {
    /// Starts `shotdamp explore FILE --port 0` in the repository and reads the address it
    /// prints.
    pub fn start(file: &str) -> Served {
        Served::start_with(&PathBuf::from(env!("CARGO_MANIFEST_DIR")), &[file])
    }

    /// `shotdamp ARGS explore --port 0` (ARGS: global options and the file) in `dir`.
    pub fn start_with(dir: &Path, args: &[&str]) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_shotdamp"))
            .current_dir(dir)
            .arg("explore")
            .args(args)
            .args(["--port", "0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start shotdamp explore");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut line).expect("the address");
        let url = line.trim().to_string();
        let port =
            url.split(':').nth(2).and_then(|s| s.split('/').next()).and_then(|p| p.parse().ok()).expect("a port");
        let token = url.split("token=").nth(1).expect("a token").to_string();
        Served { child, url, port, token }
    }

    /// Sends raw bytes, returns the status and body (status 0 when the server closed early).
    pub fn raw(&self, bytes: &[u8]) -> (u16, String) {
        let mut s = TcpStream::connect(("127.0.0.1", self.port)).expect("connect");
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        let _ = s.write_all(bytes);
        // Nothing more comes: a body shorter than its Content-Length ends here.
        let _ = s.shutdown(std::net::Shutdown::Write);
        let mut out = Vec::new();
        let _ = s.read_to_end(&mut out);
        let text = String::from_utf8_lossy(&out).into_owned();
        let status = text.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
        let body = text.split_once("\r\n\r\n").map(|(_, b)| b.to_string()).unwrap_or_default();
        (status, body)
    }

    /// A request with the token.
    pub fn call(&self, method: &str, path: &str, body: &str) -> (u16, String) {
        let head = format!(
            "{method} {path}?token={} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n",
            self.token,
            body.len()
        );
        self.raw(format!("{head}{body}").as_bytes())
    }

    /// The server's process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// The server's resident memory, kB (Linux).
    pub fn rss_kb(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap_or_default();
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .unwrap_or(0)
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The compliance table `shotdamp run` writes for an exported file, as curve -> rows of
/// (frequency, compliance per mass).
pub fn run_exported(toml: &str, dir: &Path) -> std::collections::BTreeMap<String, Vec<(f64, Vec<f64>)>> {
    let file = dir.join("explored.toml");
    std::fs::write(&file, toml).unwrap();
    let out = dir.join("run");
    let status = Command::new(env!("CARGO_BIN_EXE_shotdamp"))
        .current_dir(dir)
        .args(["run", "explored.toml", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(0), "shotdamp run on the exported file");
    let csv = find(&out, "compliance.csv").expect("a compliance table");
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let masses: Vec<usize> =
        (0..header.len()).filter(|&i| header[i].starts_with('c') && header[i][1..].parse::<usize>().is_ok()).collect();
    let mut out: std::collections::BTreeMap<String, Vec<(f64, Vec<f64>)>> = Default::default();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let ys = masses.iter().map(|&i| f[i].parse().unwrap()).collect();
        out.entry(f[0].to_string()).or_default().push((f[1].parse().unwrap(), ys));
    }
    out
}

fn find(dir: &Path, name: &str) -> Option<PathBuf> {
    for e in std::fs::read_dir(dir).ok()?.flatten() {
        let p = e.path();
        if p.is_dir() {
            if let Some(f) = find(&p, name) {
                return Some(f);
            }
        } else if p.file_name().is_some_and(|n| n == name) {
            return Some(p);
        }
    }
    None
}

/// Every simulated curve of a sweep answer equals the run's table, number for number.
pub fn assert_same_curves(answer: &Value, table: &std::collections::BTreeMap<String, Vec<(f64, Vec<f64>)>>) {
    let sims: Vec<&Value> = answer["curves"].as_array().unwrap().iter().filter(|c| c["kind"] == "sweep").collect();
    assert!(!sims.is_empty());
    for c in sims {
        let id = c["id"].as_str().unwrap();
        let rows = table.get(id).unwrap_or_else(|| panic!("curve {id} in the run's table ({:?})", table.keys()));
        let freqs = c["freq_hz"].as_array().unwrap();
        assert_eq!(rows.len(), freqs.len(), "{id}");
        for (i, (f, ys)) in rows.iter().enumerate() {
            assert_eq!(freqs[i].as_f64(), Some(*f), "{id} point {i}");
            for (m, y) in ys.iter().enumerate() {
                assert_eq!(c["compliance"][m][i].as_f64(), Some(*y), "{id} at {f} Hz, mass {}", m + 1);
            }
        }
    }
}

fn request(set: Value, start: &str) -> Value {
    json!({ "model": 1, "set": set, "band": { "start": 47.0, "stop": 51.0, "step": 0.25 }, "start": start })
}

#[test]
fn the_exported_setup_reproduces_the_curves_through_run() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    let (code, setup) = s.call("GET", "/api/setup", "");
    assert_eq!(code, 200, "{setup}");
    let setup: Value = serde_json::from_str(&setup).unwrap();
    assert_eq!(setup["models"].as_array().unwrap().len(), 3);
    assert_eq!(setup["cases"].as_array().unwrap().len(), 2);
    let set = json!([
        ["cases[*].dampers[*].clearance_mm", 0.5],
        ["structure.damping.modal_ratios", 0.005],
        ["cases[single].dampers[0].clearance_mm", 0.8]
    ]);
    for start in ["rest", "continuation"] {
        let req = request(set.clone(), start).to_string();
        let (code, body) = s.call("POST", "/api/sweep", &req);
        assert_eq!(code, 200, "{body}");
        let answer: Value = serde_json::from_str(&body).unwrap();
        let kinds: Vec<&str> = answer["curves"].as_array().unwrap().iter().filter_map(|c| c["kind"].as_str()).collect();
        assert!(kinds.contains(&"linear") && kinds.contains(&"stuck"), "{kinds:?}");
        let (code, toml) = s.call("POST", "/api/export", &req);
        assert_eq!(code, 200, "{toml}");
        assert!(toml.contains("clearance_mm = 0.8") && toml.contains("0.005"), "{toml}");
        let dir = tempfile::tempdir().unwrap();
        assert_same_curves(&answer, &run_exported(&toml, dir.path()));
    }
}

#[test]
fn a_request_is_validated_as_a_file_is_and_reaches_no_file() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    let bad = |set: Value| {
        let (code, body) = s.call("POST", "/api/sweep", &request(set, "rest").to_string());
        (
            code,
            serde_json::from_str::<Value>(&body).map(|v| v["error"].as_str().unwrap_or("").to_string()).unwrap_or(body),
        )
    };
    // The experiment's own message: the key and what is allowed.
    let (code, m) = bad(json!([["cases[*].dampers[*].clearance_mm", -1.0]]));
    assert_eq!(code, 422);
    assert!(m.contains("cases[0].dampers[0].clearance_mm") && m.contains(">= 0"), "{m}");
    let (code, m) = bad(json!([["structure.damping.modal_ratios", 2.0]]));
    assert_eq!(code, 422, "{m}");
    // Keys that could name a file, or anything not a control, are refused before any use.
    for key in ["structure.finite_element.stiffness", "extends", "models", "analysis.kind", "reference"] {
        let (code, m) = bad(json!([[key, "/etc/passwd"]]));
        assert_eq!(code, 422, "{key}: {m}");
        assert!(m.contains("not a key the explorer sets"), "{key}: {m}");
    }
    let (code, m) = bad(json!([["cases[*].dampers[*].bed", "/etc/passwd"]]));
    assert!(code == 422 && m.contains("bed law"), "{m}");
    let (code, m) = bad(json!([["excitation.force_n", "2.6"]]));
    assert!(code == 422 && m.contains("finite number"), "{m}");
    // Bounded in points.
    let wide = json!({ "set": [], "band": { "start": 1.0, "stop": 60.0, "step": 0.001 }, "start": "rest" });
    let (code, body) = s.call("POST", "/api/sweep", &wide.to_string());
    assert!(code == 422 && body.contains("at most 2001 points"), "{body}");
    // No token, another token: refused.
    let (code, _) = s.raw(b"GET /api/setup HTTP/1.1\r\n\r\n");
    assert_eq!(code, 403);
    let (code, _) = s.raw(b"GET /api/setup?token=00000000000000000000000000000000 HTTP/1.1\r\n\r\n");
    assert_eq!(code, 403);
    // Paths outside the page's own are not found, whatever they look like.
    for path in ["/../Cargo.toml", "/etc/passwd", "/src/lib.rs", "/%2e%2e/Cargo.toml"] {
        let (code, _) = s.call("GET", path, "");
        assert_eq!(code, 404, "{path}");
    }
    let (code, page) = s.call("GET", "/", "");
    assert!(code == 200 && page.contains(&s.token) && page.contains("uplot.js"), "{code}");
}

#[test]
fn the_server_survives_a_thousand_malformed_and_oversized_requests() {
    let s = Served::start("experiments/fig05_third_mode.toml");
    let good = request(json!([]), "rest").to_string();
    assert_eq!(s.call("POST", "/api/sweep", &good).0, 200);
    let rss_before = s.rss_kb();
    let token = s.token.clone();
    let big = "x".repeat(70 * 1024);
    let mut codes = std::collections::BTreeMap::new();
    for i in 0..1000 {
        let bytes: Vec<u8> = match i % 10 {
            0 => b"\x00\x01\x02garbage\r\n\r\n".to_vec(),
            1 => format!("POST /api/sweep?token={token} HTTP/1.1\r\nContent-Length: 5\r\n\r\n{{{{{{{{").into_bytes(),
            2 => format!("POST /api/sweep?token={token} HTTP/1.1\r\nContent-Length: {}\r\n\r\n{big}", big.len())
                .into_bytes(),
            3 => format!("GET /{} HTTP/1.1\r\n\r\n", "a".repeat(20_000)).into_bytes(),
            4 => format!("POST /api/sweep?token={token} HTTP/1.1\r\nContent-Length: 99999999999999999999\r\n\r\n")
                .into_bytes(),
            5 => format!("POST /api/point?token={token} HTTP/1.1\r\nContent-Length: 2\r\n\r\n[]").into_bytes(),
            6 => format!("POST /api/sweep?token={token} HTTP/1.1\r\nContent-Length: 10\r\n\r\nshort").into_bytes(),
            7 => {
                let body =
                    json!({ "set": [[7, 7]], "band": { "start": -1, "stop": "x", "step": 0 }, "start": 3 }).to_string();
                format!("POST /api/sweep?token={token} HTTP/1.1\r\nContent-Length: {}\r\n\r\n{body}", body.len())
                    .into_bytes()
            }
            8 => format!("DELETE /api/sweep?token={token} HTTP/1.1\r\n\r\n").into_bytes(),
            _ => {
                let body = json!({ "setup": { "set": [], "band": { "start": 47, "stop": 48, "step": 1 }, "start": "rest" }, "case": "nope", "freq_hz": -3 }).to_string();
                format!("POST /api/point?token={token} HTTP/1.1\r\nContent-Length: {}\r\n\r\n{body}", body.len())
                    .into_bytes()
            }
        };
        let (code, _) = s.raw(&bytes);
        *codes.entry(code).or_insert(0) += 1;
        assert!(code != 200 && code != 500, "request {i} answered {code}");
        if i % 10 == 3 {
            assert_eq!(code, 431, "a head of 20 kB");
        }
    }
    // Still answering, with the same curves as before.
    let (code, again) = s.call("POST", "/api/sweep", &good);
    assert_eq!(code, 200);
    let (_, first) = s.call("POST", "/api/sweep", &good);
    let strip = |t: &str| {
        serde_json::from_str::<Value>(t)
            .map(|mut v| {
                v["ms"] = json!(0);
                v
            })
            .unwrap()
    };
    assert_eq!(strip(&again), strip(&first));
    // Memory: 200 sweeps more and the server stays within a few MB of where it was.
    for _ in 0..200 {
        assert_eq!(s.call("POST", "/api/sweep", &good).0, 200);
    }
    let rss_after = s.rss_kb();
    println!("answers to 1000 bad requests: {codes:?}; resident memory {rss_before} kB before, {rss_after} kB after 200 more sweeps");
    assert!(rss_after < rss_before + 20_000, "{rss_before} -> {rss_after} kB");
}

#[test]
fn a_newer_sweep_stops_the_one_in_flight() {
    let s = std::sync::Arc::new(Served::start("experiments/fig05_third_mode.toml"));
    // 2,001 frequencies from rest on both cases, at modal damping 0.0005 (a twentieth of the
    // assumed 0.01: long transients): about 1.1 s of work on two cores, against 0.2 s at 0.01,
    // which ended before the newer request arrived. A sweep stops at its next point, so the
    // one in flight ends when each thread's current point does.
    let set = json!([["structure.damping.modal_ratios", 0.0005]]);
    let long = json!({ "seq": 10, "set": set, "band": { "start": 40.0, "stop": 60.0, "step": 0.01 }, "start": "rest" });
    let first = {
        let s = std::sync::Arc::clone(&s);
        std::thread::spawn(move || {
            let t0 = std::time::Instant::now();
            let (code, body) = s.call("POST", "/api/sweep", &long.to_string());
            (code, body, t0.elapsed())
        })
    };
    std::thread::sleep(Duration::from_millis(300));
    let short = json!({ "seq": 11, "set": [], "band": { "start": 47.0, "stop": 48.0, "step": 0.5 }, "start": "rest" });
    let (code, body) = s.call("POST", "/api/sweep", &short.to_string());
    assert_eq!(code, 200, "{body}");
    let (code, body, took) = first.join().unwrap();
    assert_eq!(code, 409, "{body}");
    assert!(body.contains("superseded"), "{body}");
    // An older request arriving late is refused at once.
    let late = json!({ "seq": 9, "set": [], "band": { "start": 47.0, "stop": 48.0, "step": 0.5 }, "start": "rest" });
    let (code, _) = s.call("POST", "/api/sweep", &late.to_string());
    assert_eq!(code, 409);
    println!("the long sweep stopped after {took:?}");
}

#[test]
fn the_file_s_reference_curves_are_markers() {
    let dir = tempfile::tempdir().unwrap();
    let exps = crate::common::experiments(dir.path(), &["fig04b_no_damper.toml"]);
    let refs = dir.path().join("reference");
    std::fs::create_dir_all(refs.join("independent-solver")).unwrap();
    std::fs::create_dir_all(refs.join("digitised")).unwrap();
    let repo = crate::common::repo();
    std::fs::copy(repo.join("reference/paper-text.toml"), refs.join("paper-text.toml")).unwrap();
    std::fs::copy(repo.join("reference/independent-solver/P_bare.csv"), refs.join("independent-solver/P_bare.csv"))
        .unwrap();
    std::fs::write(
        refs.join("digitised/fig4b.toml"),
        "[meta]\nprovenance = \"digitised figure\"\nfigure = \"Fig. 4(b)\"\nsource = \"a test\"\ndigitised_by = \"test\"\ntool = \"hand\"\nimported_from = \"none\"\nx_unit = \"Hz\"\ny_unit = \"m/N\"\nx_log = false\ny_log = true\nx_pixel = 0.05\ny_pixel = 0.01\n\n[[curve]]\nname = \"m1\"\ncase = \"bare\"\nmass = 1\nx = [10.0, 13.0, 20.0]\ny = [1e-4, 1e-3, 2e-5]\n",
    )
    .unwrap();
    let file = exps.join("fig04b_no_damper.toml");
    let text = std::fs::read_to_string(&file).unwrap()
        + "\n[[checks]]\nkind = \"tube\"\nmodels = [\"stated\"]\nreference = \"digitised/fig4b.toml\"\ncurve = \"m1\"\nx_tol_px = 2\ny_tol_px = 2\n";
    std::fs::write(&file, text).unwrap();
    let (file, refs) = (file.to_string_lossy().into_owned(), refs.to_string_lossy().into_owned());
    let s = Served::start_with(dir.path(), &["--reference", &refs, &file]);
    let req = json!({ "model": 0, "set": [], "band": { "start": 5.0, "stop": 25.0, "step": 0.5 }, "start": "rest" });
    let (code, body) = s.call("POST", "/api/sweep", &req.to_string());
    assert_eq!(code, 200, "{body}");
    let answer: Value = serde_json::from_str(&body).unwrap();
    let refs = answer["references"].as_array().unwrap();
    let digitised = refs
        .iter()
        .find(|r| r["label"].as_str().is_some_and(|l| l.contains("digitised")))
        .expect("the digitised curve");
    assert_eq!(digitised["freq_hz"], json!([10.0, 13.0, 20.0]));
    assert_eq!(digitised["compliance"][0], json!([1e-4, 1e-3, 2e-5]));
    assert!(digitised["compliance"][1].as_array().unwrap().iter().all(Value::is_null), "only its mass");
    let solver = refs
        .iter()
        .find(|r| r["label"].as_str().is_some_and(|l| l.contains("P_bare.csv")))
        .expect("the solver's curve");
    assert_eq!(solver["compliance"].as_array().map(Vec::len), Some(3));
}

/// docs/explore.md's example of the HTTP API is what the server does: its request, sent as
/// written, answers 200 with every key the documented answer shows, the curves it names, and
/// the first curve's numbers to the digits written there.
#[test]
fn the_documented_api_example_is_what_the_server_answers() {
    let doc = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/explore.md")).unwrap();
    let api = doc.split("## The HTTP API").nth(1).expect("docs/explore.md has an HTTP API section");
    let blocks: Vec<&str> = api.split("```json").skip(1).map(|b| b.split("```").next().unwrap_or("")).collect();
    assert!(blocks.len() >= 2, "a request and its answer");
    let documented: Value = serde_json::from_str(blocks[1]).expect("the documented answer is JSON");
    let s = Served::start("experiments/fig05_third_mode.toml");
    let (code, body) = s.call("POST", "/api/sweep", blocks[0].trim());
    assert_eq!(code, 200, "{body}");
    let answer: Value = serde_json::from_str(&body).unwrap();
    let keys = |v: &Value| v.as_object().map(|o| o.keys().cloned().collect::<Vec<_>>()).unwrap_or_default();
    for k in keys(&documented) {
        assert!(answer.get(&k).is_some(), "the answer has no `{k}`");
    }
    let curves = answer["curves"].as_array().unwrap();
    for (i, want) in documented["curves"].as_array().unwrap().iter().enumerate() {
        let id = want["id"].as_str().unwrap();
        let got = curves.iter().find(|c| c["id"] == want["id"]).unwrap_or_else(|| panic!("no curve {id}"));
        for k in keys(want) {
            let (w, g) = (&want[&k], &got[&k]);
            assert!(g.is_array() == w.is_array() && !g.is_null() || w.is_null(), "{id}.{k}: {g} against {w}");
            if i > 0 {
                continue;
            }
            // The first curve whole: numbers to the digits written, the rest exactly.
            let flat = |v: &Value| -> Vec<Value> {
                match v {
                    Value::Array(a) => {
                        a.iter().flat_map(|x| x.as_array().cloned().unwrap_or_else(|| vec![x.clone()])).collect()
                    }
                    x => vec![x.clone()],
                }
            };
            for (x, y) in flat(w).iter().zip(flat(g)) {
                match (x.as_f64(), y.as_f64()) {
                    (Some(a), Some(b)) if x.is_f64() => {
                        assert!((a - b).abs() <= 5e-5 * b.abs(), "{id}.{k}: {b} documented {a}")
                    }
                    _ => assert_eq!(*x, y, "{id}.{k}"),
                }
            }
        }
    }
    assert_eq!(answer["unit"], documented["unit"]);
    assert_eq!(answer["masses"], documented["masses"]);
}
