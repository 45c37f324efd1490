//! The whole report in a real browser: headless Chromium loads every page from a local HTTP
//! server, checks that every image shows and every link resolves, the server records any
//! request it cannot answer, Chromium's log shows no console error, and a screenshot of the
//! index is saved for a person to look at.
//!
//! Needs Chromium (`apt-get install chromium`, or the path in `SHOTDAMP_BROWSER`), so it is
//! ignored by default; `.ci/run` installs Chromium and runs it:
//! `cargo test --release --locked --test all -- --ignored browser::`.

mod explore;

use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex};

fn browser() -> PathBuf {
    if let Some(p) = std::env::var_os("SHOTDAMP_BROWSER") {
        return PathBuf::from(p);
    }
    for p in ["/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"] {
        if Path::new(p).is_file() {
            return PathBuf::from(p);
        }
    }
    panic!("no Chromium found: install it (apt-get install -y chromium) or set SHOTDAMP_BROWSER");
}

/// The pages of a report: the index, every experiment's page and the page of each of its
/// models.
fn pages(root: &Path) -> Vec<String> {
    let dirs = |p: &Path| {
        let mut d: Vec<_> =
            std::fs::read_dir(p).unwrap().filter_map(|e| e.ok()).filter(|e| e.path().is_dir()).collect();
        d.sort_by_key(|e| e.file_name());
        d
    };
    let mut out = vec!["index.html".to_string()];
    for d in dirs(root) {
        let id = d.file_name().to_string_lossy().into_owned();
        if d.path().join("index.html").is_file() {
            out.push(format!("{id}/index.html"));
        }
        for m in dirs(&d.path()) {
            if m.path().join("index.html").is_file() {
                out.push(format!("{id}/{}/index.html", m.file_name().to_string_lossy()));
            }
        }
    }
    out
}

/// The page that visits every report page in an iframe and writes what it found.
fn harness(pages: &[String]) -> String {
    let list: Vec<String> = pages.iter().map(|p| format!("\"/{p}\"")).collect();
    format!(
        r#"<!DOCTYPE html><html><body><pre id="result">pending</pre><iframe id="f" width="1366" height="900"></iframe><iframe id="v" width="1400" height="900"></iframe>
<script>
const pages = [{}];
const problems = [];
let links = 0, images = 0, matrix = null;
// The index's verdict matrix, whole, in a 1400 x 900 window without scrolling.
async function verdicts() {{
  const v = document.getElementById('v');
  await new Promise(res => {{ v.onload = res; v.src = '/index.html'; }});
  const t = v.contentDocument.getElementById('verdicts');
  if (!t) {{ problems.push('index: no verdict matrix'); return; }}
  const r = t.getBoundingClientRect();
  matrix = {{ rows: t.tBodies[0].rows.length, top: r.top, bottom: r.bottom, right: r.right }};
}}
async function check(page) {{
  const f = document.getElementById('f');
  await new Promise(res => {{ f.onload = res; f.src = page; }});
  const doc = f.contentDocument;
  for (const img of doc.images) {{
    images++;
    if (!img.complete || img.naturalWidth === 0) problems.push(page + ': broken image ' + img.getAttribute('src'));
  }}
  for (const a of doc.querySelectorAll('a[href]')) {{
    const url = new URL(a.getAttribute('href'), doc.baseURI);
    if (url.origin !== location.origin) {{ problems.push(page + ': link leaves the report: ' + url); continue; }}
    links++;
    const r = await fetch(url, {{ method: 'HEAD' }});
    if (!r.ok) problems.push(page + ': broken link ' + a.getAttribute('href') + ' (' + r.status + ')');
  }}
}}
(async () => {{
  try {{ await verdicts(); for (const p of pages) await check(p); }} catch (e) {{ problems.push('harness: ' + e); }}
  document.getElementById('result').textContent = JSON.stringify({{ pages: pages.length, images, links, matrix, problems }});
}})();
</script></body></html>"#,
        list.join(", ")
    )
}

/// Serves `root` (and the harness) on a local port; records requests it could not answer.
fn serve(root: PathBuf, harness: String) -> (u16, Arc<Mutex<Vec<String>>>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let failures = Arc::new(Mutex::new(Vec::new()));
    let log = failures.clone();
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut stream) = stream else { continue };
            let mut line = String::new();
            let mut reader = BufReader::new(stream.try_clone().unwrap());
            if reader.read_line(&mut line).is_err() {
                continue;
            }
            // Drain the headers.
            let mut h = String::new();
            while reader.read_line(&mut h).is_ok_and(|n| n > 2) {
                h.clear();
            }
            let mut parts = line.split_whitespace();
            let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
            let path = target.split(['?', '#']).next().unwrap_or("/").trim_start_matches('/').to_string();
            let body: Option<(Vec<u8>, &str)> = if path == "__harness.html" {
                Some((harness.clone().into_bytes(), "text/html"))
            } else {
                let file = root.join(&path);
                let kind = match file.extension().and_then(|e| e.to_str()) {
                    Some("html") => "text/html",
                    Some("css") => "text/css",
                    Some("png") => "image/png",
                    Some("svg") => "image/svg+xml",
                    Some("json") => "application/json",
                    Some("xml") => "application/xml",
                    Some("csv") => "text/csv",
                    _ => "application/octet-stream",
                };
                std::fs::read(&file).ok().filter(|_| file.is_file() && !path.contains("..")).map(|b| (b, kind))
            };
            let _ = match body {
                Some((b, kind)) => {
                    let head = format!(
                        "HTTP/1.1 200 OK\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
                        b.len()
                    );
                    stream.write_all(head.as_bytes()).and_then(|_| {
                        if method == "HEAD" {
                            Ok(())
                        } else {
                            stream.write_all(&b)
                        }
                    })
                }
                None => {
                    if path != "favicon.ico" {
                        log.lock().unwrap().push(format!("{method} /{path}: not found"));
                    }
                    stream.write_all(b"HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n")
                }
            };
        }
    });
    (port, failures)
}

fn chromium(args: &[String]) -> (String, String) {
    let profile = tempfile::tempdir().unwrap();
    let out = Command::new(browser())
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .output()
        .expect("run chromium");
    (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
#[ignore = "needs Chromium: cargo test --release --locked --test all -- --ignored browser::"]
fn the_report_reads_in_a_real_browser() {
    // SHOTDAMP_REPORT names a report `shotdamp report` has already written (CI reads the one
    // it has just regenerated, instead of writing the whole report a second time).
    let dir = tempfile::tempdir().unwrap();
    let report = match std::env::var_os("SHOTDAMP_REPORT") {
        Some(given) => PathBuf::from(given),
        None => {
            let report = dir.path().join("report");
            let status = Command::new(env!("CARGO_BIN_EXE_shotdamp"))
                .current_dir(env!("CARGO_MANIFEST_DIR"))
                .args(["report", "--out"])
                .arg(&report)
                .status()
                .unwrap();
            assert!(status.code().is_some_and(|c| c <= 1), "the report was written");
            report
        }
    };
    assert!(report.join("index.html").is_file(), "no report at {}", report.display());
    let pages = pages(&report);
    assert!(pages.len() > 5, "{pages:?}");
    let (port, failures) = serve(report.clone(), harness(&pages));
    let base = format!("http://127.0.0.1:{port}");
    let (dom, log) =
        chromium(&["--virtual-time-budget=120000".into(), "--dump-dom".into(), format!("{base}/__harness.html")]);
    let result =
        dom.split("<pre id=\"result\">").nth(1).and_then(|s| s.split("</pre>").next()).unwrap_or("").to_string();
    let json: serde_json::Value = serde_json::from_str(&result.replace("&quot;", "\""))
        .unwrap_or_else(|e| panic!("harness result {result:?}: {e}"));
    assert_eq!(json["pages"].as_u64(), Some(pages.len() as u64));
    assert!(json["images"].as_u64().unwrap_or(0) > 10, "{json}");
    assert!(json["links"].as_u64().unwrap_or(0) > 50, "{json}");
    assert_eq!(json["problems"].as_array().map(|a| a.len()), Some(0), "{json}");
    // Every paper figure's row of the verdict matrix is on the first screen at 1400 x 900.
    let m = &json["matrix"];
    assert!(m["rows"].as_u64().unwrap_or(0) >= 8, "{json}");
    assert!(m["top"].as_f64().is_some_and(|t| t >= 0.0), "{json}");
    assert!(m["bottom"].as_f64().is_some_and(|b| b <= 900.0), "the matrix ends below the first screen: {json}");
    assert!(m["right"].as_f64().is_some_and(|r| r <= 1400.0), "the matrix is wider than the screen: {json}");
    let not_found = failures.lock().unwrap().clone();
    assert!(not_found.is_empty(), "requests not answered: {not_found:?}");
    let console: Vec<&str> = log.lines().filter(|l| l.contains("CONSOLE") || l.contains("Uncaught")).collect();
    assert!(console.is_empty(), "console messages: {console:?}");
    // A screenshot of the index at a laptop's size, for a person to look at.
    let shot = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-index.png");
    let _ = std::fs::remove_file(&shot);
    chromium(&[
        format!("--screenshot={}", shot.display()),
        "--window-size=1366,900".into(),
        format!("{base}/index.html"),
    ]);
    assert!(std::fs::metadata(&shot).is_ok_and(|m| m.len() > 10_000), "screenshot at {}", shot.display());
    println!("screenshot: {}; verdict matrix at 1400 x 900: {m}", shot.display());
    // Reading speed from disk: every page opened as a file, each once, after a blank page;
    // its time is the browser's own (Navigation Timing: from the request to the end of the
    // load event, every image decoded). The index within 1 s, every other page within 2 s.
    let d = explore::Driver::start();
    d.call("POST", "/url", Some(&serde_json::json!({ "url": "about:blank" })));
    let mut times = Vec::new();
    for p in &pages {
        let url = format!("file://{}", report.join(p).display());
        d.call("POST", "/url", Some(&serde_json::json!({ "url": url })));
        let js = "const n = performance.getEntriesByType('navigation')[0]; return n.loadEventEnd - n.startTime;";
        let ms = d.script(js, serde_json::json!([])).as_f64().unwrap_or(f64::INFINITY);
        times.push((ms, p.clone()));
    }
    let limit = |p: &str| if p == "index.html" { 1000.0 } else { 2000.0 };
    let slow: Vec<String> = times
        .iter()
        .filter(|(ms, p)| ms.is_nan() || *ms >= limit(p))
        .map(|(ms, p)| format!("{p}: {ms:.0} ms (at most {:.0})", limit(p)))
        .collect();
    assert!(slow.is_empty(), "pages that render too slowly from disk: {slow:?}");
    times.sort_by(|a, b| b.0.total_cmp(&a.0));
    let index = times.iter().find(|(_, p)| p == "index.html").map_or(f64::NAN, |t| t.0);
    println!("render times from disk: index {index:.0} ms; slowest {:?}", &times[..times.len().min(3)]);
}
