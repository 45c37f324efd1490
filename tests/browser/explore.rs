//! The explorer page in a real browser, driven by WebDriver (Debian's `chromedriver` with
//! headless Chromium; the protocol's JSON over HTTP, written here): the page draws Fig. 5,
//! the clearance slider is moved with the keyboard, the redrawn curves equal `shotdamp run`'s
//! table for the page's exported setup, 50 more moves give the redraw latency, a click on a
//! plot shows that frequency's motion, and a screenshot is saved for a person to look at.
//!
//! Needs `chromium` and `chromium-driver` (or `SHOTDAMP_CHROMEDRIVER`); `.ci/run` installs both:
//! `cargo test --release --locked --test all -- --ignored browser::`.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::explore::{assert_same_curves, run_exported, Served};

fn chromedriver() -> PathBuf {
    if let Some(p) = std::env::var_os("SHOTDAMP_CHROMEDRIVER") {
        return PathBuf::from(p);
    }
    let p = PathBuf::from("/usr/bin/chromedriver");
    assert!(
        p.is_file(),
        "no chromedriver: install it (apt-get install -y chromium-driver) or set SHOTDAMP_CHROMEDRIVER"
    );
    p
}

/// A WebDriver session on a chromedriver of its own; both end when dropped.
pub(super) struct Driver {
    child: Child,
    port: u16,
    session: String,
    _profile: tempfile::TempDir,
}

fn http(port: u16, method: &str, path: &str, body: Option<&Value>) -> Value {
    let body = body.map(Value::to_string).unwrap_or_default();
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect to chromedriver");
    s.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    let req = format!(
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    s.write_all(req.as_bytes()).unwrap();
    // chromedriver may keep the connection open: read the head, then as many bytes as it says
    // (a fixed length, or chunks up to the empty one).
    let mut buf = Vec::new();
    let mut byte = [0u8; 65536];
    let complete = |buf: &[u8]| -> Option<String> {
        let text = String::from_utf8_lossy(buf);
        let (head, rest) = text.split_once("\r\n\r\n")?;
        let lower = head.to_ascii_lowercase();
        if lower.contains("transfer-encoding: chunked") {
            let mut data = String::new();
            let mut r = rest;
            loop {
                let (size, after) = r.split_once("\r\n")?;
                let n = usize::from_str_radix(size.trim(), 16).ok()?;
                if n == 0 {
                    return Some(data);
                }
                data.push_str(after.get(..n)?);
                r = after.get(n + 2..)?;
            }
        }
        let n: usize =
            lower.lines().find_map(|l| l.strip_prefix("content-length:")).and_then(|v| v.trim().parse().ok())?;
        (rest.len() >= n).then(|| rest[..n].to_string())
    };
    let payload = loop {
        let got = s.read(&mut byte).unwrap();
        buf.extend_from_slice(&byte[..got]);
        if let Some(p) = complete(&buf) {
            break p;
        }
        assert!(got > 0, "chromedriver closed the connection: {:.300}", String::from_utf8_lossy(&buf));
    };
    serde_json::from_str(&payload).unwrap_or_else(|e| panic!("{method} {path}: {e}: {payload:.300}"))
}

impl Driver {
    pub(super) fn start() -> Driver {
        let port = TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
        let child = Command::new(chromedriver())
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromedriver");
        let t0 = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(t0.elapsed() < Duration::from_secs(20), "chromedriver did not start");
            std::thread::sleep(Duration::from_millis(50));
        }
        let profile = tempfile::tempdir().unwrap();
        let mut chrome = json!({
            "args": ["--headless", "--no-sandbox", "--disable-gpu", "--window-size=1400,1400",
                     "--no-first-run", "--disable-background-networking", "--disable-component-update",
                     format!("--user-data-dir={}", profile.path().display())]
        });
        if let Some(b) = std::env::var_os("SHOTDAMP_BROWSER") {
            chrome["binary"] = json!(b.to_string_lossy());
        }
        let caps =
            json!({ "capabilities": { "alwaysMatch": { "browserName": "chrome", "goog:chromeOptions": chrome } } });
        let r = http(port, "POST", "/session", Some(&caps));
        let session =
            r["value"]["sessionId"].as_str().unwrap_or_else(|| panic!("a WebDriver session: {r}")).to_string();
        Driver { child, port, session, _profile: profile }
    }

    pub(super) fn call(&self, method: &str, path: &str, body: Option<&Value>) -> Value {
        let r = http(self.port, method, &format!("/session/{}{path}", self.session), body);
        let failed = r["value"]["error"].is_string() && r["value"]["message"].is_string();
        assert!(!failed, "{method} {path}: {r}");
        r["value"].clone()
    }

    pub(super) fn script(&self, js: &str, args: Value) -> Value {
        self.call("POST", "/execute/sync", Some(&json!({ "script": js, "args": args })))
    }

    fn script_async(&self, js: &str) -> Value {
        self.call("POST", "/execute/async", Some(&json!({ "script": js, "args": [] })))
    }

    /// Waits until `js` returns true.
    fn until(&self, js: &str, what: &str) {
        let t0 = Instant::now();
        while self.script(js, json!([])) != json!(true) {
            if t0.elapsed() > Duration::from_secs(60) {
                let state = self.script(
                    "const e = window.explorer; return e && { drawn: e.drawn, latencies: e.latencies.length, errors: e.errors, status: document.getElementById('status').textContent, error: document.getElementById('error').textContent, messages: e.messages }",
                    json!([]),
                );
                panic!("waited a minute for {what}: {state}");
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    fn element(&self, css: &str) -> String {
        let e = self.call("POST", "/element", Some(&json!({ "using": "css selector", "value": css })));
        e.as_object().and_then(|o| o.values().next()).and_then(Value::as_str).expect("an element").to_string()
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = http(self.port, "DELETE", &format!("/session/{}", self.session), None);
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Standard base64 to bytes (the screenshot WebDriver returns).
fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        _ => 63,
    };
    let clean: Vec<u8> = text.bytes().filter(|c| !c.is_ascii_whitespace() && *c != b'=').collect();
    let mut out = Vec::with_capacity(clean.len() * 3 / 4);
    for chunk in clean.chunks(4) {
        let v: Vec<u32> = chunk.iter().map(|&c| value(c) as u32).collect();
        let n = v.iter().fold(0u32, |acc, x| (acc << 6) | x) << (6 * (4 - v.len()));
        out.extend_from_slice(&n.to_be_bytes()[1..v.len()]);
    }
    out
}

const CLEARANCE: &str = "input[type=range][data-path='cases[*].dampers[*].clearance_mm']";

#[test]
#[ignore = "needs Chromium and chromedriver: cargo test --release --locked --test all -- --ignored browser::"]
fn the_explorer_redraws_fig5_live_and_its_export_reproduces_it() {
    let served = Served::start("experiments/fig05_third_mode.toml");
    let d = Driver::start();
    d.call("POST", "/url", Some(&json!({ "url": served.url })));
    d.until("return !!(window.explorer && window.explorer.ready)", "the first drawing");
    assert_eq!(d.script("return document.querySelectorAll('.uplot').length", json!([])), json!(3), "one plot per mass");
    // Move the clearance slider with the keyboard, as a person would.
    let slider = d.element(CLEARANCE);
    let before = d.script("return window.explorer.drawn", json!([])).as_u64().unwrap();
    d.call("POST", &format!("/element/{slider}/click"), Some(&json!({})));
    for _ in 0..40 {
        d.call("POST", &format!("/element/{slider}/value"), Some(&json!({ "text": "\u{E014}" })));
    }
    d.until(&format!("return window.explorer.drawn > {before} && window.explorer.latencies.length > 0"), "the redraw");
    // Wait for the last of the moves' answers: the slider's value is the one drawn.
    std::thread::sleep(Duration::from_millis(500));
    d.until("const e = window.explorer; const n = e.drawn; return new Promise(r => setTimeout(() => r(e.drawn === n), 300))", "quiet");
    let value = d
        .script(&format!("return Number(document.querySelector(\"{CLEARANCE}\").nextElementSibling.value)"), json!([]));
    assert!(value.as_f64().is_some_and(|v| (v - 0.35).abs() > 0.01), "the slider moved: {value}");
    let data = d.script("return window.explorer.data", json!([]));
    let toml = d.script_async(
        "const done = arguments[arguments.length - 1]; window.explorer.exportToml().then(done, e => done(String(e)))",
    );
    let toml = toml.as_str().expect("exported text");
    assert!(
        toml.contains(&format!("clearance_mm = {}", value.as_f64().unwrap())),
        "the export has the slider's clearance {value}"
    );
    let dir = tempfile::tempdir().unwrap();
    assert_same_curves(&data, &run_exported(toml, dir.path()));
    // 50 moves, each waited for: the page's own measure from the input to the end of drawing.
    d.script("window.explorer.latencies = []", json!([]));
    for i in 0..50 {
        let drawn = d.script("return window.explorer.drawn", json!([])).as_u64().unwrap();
        let key = if i % 2 == 0 { "\u{E012}" } else { "\u{E014}" };
        d.call("POST", &format!("/element/{slider}/value"), Some(&json!({ "text": key })));
        d.until(&format!("return window.explorer.drawn > {drawn}"), "a redraw");
    }
    let mut lat: Vec<f64> = d
        .script("return window.explorer.latencies", json!([]))
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_f64)
        .collect();
    lat.sort_by(f64::total_cmp);
    assert_eq!(lat.len(), 50);
    let points: usize = data["curves"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["kind"] == "sweep")
        .map(|c| c["freq_hz"].as_array().map_or(0, Vec::len))
        .sum();
    println!(
        "redraw latency over 50 slider moves ({points} simulated points each): median {:.1} ms, min {:.1}, max {:.1}",
        lat[25], lat[0], lat[49]
    );
    // A click on the first plot shows that frequency's motion.
    let over = d.element(".uplot .u-over");
    d.call("POST", &format!("/element/{over}/click"), Some(&json!({})));
    d.until("return !!window.explorer.point", "the point's motion");
    let point = d.script("return window.explorer.point", json!([]));
    assert!(point["phase_deg"].as_array().is_some_and(|p| p.len() > 100), "{point:.300}");
    assert!(point["x"].as_array().is_some_and(|x| x.len() == 3));
    let errors = d.script("return [window.explorer.errors, window.explorer.messages]", json!([]));
    assert_eq!(errors[0], json!(0), "script errors on the page: {errors}");
    let shot = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("explore.png");
    let png = base64(d.call("GET", "/screenshot", None).as_str().unwrap());
    std::fs::write(&shot, &png).unwrap();
    assert!(png.len() > 10_000 && png.starts_with(b"\x89PNG"), "screenshot at {}", shot.display());
    println!("screenshot: {}", shot.display());
}
