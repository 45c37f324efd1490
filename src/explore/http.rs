//! The explorer's server: plain HTTP/1.1 on one address (127.0.0.1 unless told otherwise),
//! one thread per connection (at most [`MAX_CONNECTIONS`] at once), every request bounded in
//! size and time and answered once, then the connection closed. A request must arrive whole
//! within [`READ_TIMEOUT`] (not per read: a client sending a byte now and then is cut off),
//! and when every place is taken the connection that has waited longest for its request is
//! closed to make room: slow clients cannot lock the page's users out. A computation is
//! abandoned at its next simulated period when it passes [`MAX_TIME`] or a newer request
//! supersedes it ([`crate::sim::motion::cancel`]). Every path needs the
//! session's random token (`?token=...`), as notebook servers do, so other users of the
//! machine cannot drive it. Nothing a request carries names a file: the page's files are
//! compiled in, and the computations read only the experiment opened at the start.

use std::io::{Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::page;
use super::{PointRequest, Request, Session, MAX_TIME};
use crate::error::{Error, Result};
use crate::sim::motion::cancel;

/// Most connections served at once; more are answered 503 at once.
pub const MAX_CONNECTIONS: usize = 32;

/// Longest request line and headers, bytes.
const MAX_HEAD: usize = 16 * 1024;

/// Longest request body, bytes.
const MAX_BODY: usize = 64 * 1024;

/// How long a connection may take to send its whole request.
pub const READ_TIMEOUT: Duration = Duration::from_secs(10);

/// Connections beyond [`MAX_CONNECTIONS`] that may be closing at once (each one made room by
/// closing a slow one, which then ends at once).
const MAX_CLOSING: usize = MAX_CONNECTIONS;

/// The highest request number (`seq`) a page may send: the largest integer a JavaScript
/// number holds exactly. Numbers never wrap.
pub const MAX_SEQ: u64 = (1 << 53) - 1;

/// What a cancelled computation unwinds with (never through the panic hook: nothing is
/// printed).
struct Cancelled;

/// What every connection shares.
struct Shared {
    session: Session,
    token: String,
    /// Sweeps asked for so far: a computation whose number is no longer the latest stops.
    sweeps: Arc<AtomicU64>,
    /// Point views asked for so far (the same rule, apart from the sweeps).
    points: Arc<AtomicU64>,
    /// One computation at a time (each uses every core).
    compute: Mutex<()>,
    open: AtomicUsize,
    /// Connections still sending their request: number, when accepted, a handle to close it.
    waiting: Mutex<Vec<(u64, Instant, TcpStream)>>,
}

/// A bound address, not yet serving: bound before the session is opened, so that a port in
/// use is said at once.
pub struct Listener {
    listener: TcpListener,
}

/// A server: a bound address and the session it serves.
pub struct Server {
    listener: TcpListener,
    shared: Arc<Shared>,
}

/// A response: status, content type and body.
struct Reply {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
}

impl Reply {
    fn json(status: u16, v: &Value) -> Reply {
        Reply { status, kind: "application/json", body: v.to_string().into_bytes() }
    }

    fn error(status: u16, message: impl Into<String>) -> Reply {
        Reply::json(status, &json!({ "error": message.into() }))
    }
}

/// A random token of 128 bits, hex: from the operating system's generator, or (where it cannot
/// be read) from the randomly keyed hashers of the standard library.
fn token() -> String {
    let mut bytes = [0u8; 16];
    let read = std::fs::File::open("/dev/urandom").and_then(|mut f| f.read_exact(&mut bytes));
    if read.is_err() {
        use std::hash::{BuildHasher, Hasher};
        for (i, chunk) in bytes.chunks_mut(8).enumerate() {
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_usize(i);
            h.write_u128(
                std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos()),
            );
            chunk.copy_from_slice(&h.finish().to_le_bytes());
        }
    }
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

impl Listener {
    /// Binds `host:port` (port 0: any free port).
    pub fn bind(host: IpAddr, port: u16) -> Result<Listener> {
        let addr = SocketAddr::new(host, port);
        let listener = TcpListener::bind(addr).map_err(|e| Error::Io { path: addr.to_string().into(), error: e })?;
        Ok(Listener { listener })
    }

    /// The server of `session` on this address.
    pub fn serving(self, session: Session) -> Server {
        let shared = Arc::new(Shared {
            session,
            token: token(),
            sweeps: Arc::new(AtomicU64::new(0)),
            points: Arc::new(AtomicU64::new(0)),
            compute: Mutex::new(()),
            open: AtomicUsize::new(0),
            waiting: Mutex::new(Vec::new()),
        });
        Server { listener: self.listener, shared }
    }
}

impl Shared {
    /// Closes the connection that has waited longest for its request, if any: true when one
    /// was closed (its thread then ends at once).
    fn close_slowest(&self) -> bool {
        let mut waiting = self.waiting.lock().unwrap_or_else(|e| e.into_inner());
        let Some(i) = (0..waiting.len()).min_by_key(|&i| waiting[i].1) else { return false };
        let (_, _, stream) = waiting.swap_remove(i);
        let _ = stream.shutdown(std::net::Shutdown::Both);
        true
    }

    /// The connection numbered `id` has its request (or is done): no longer closed for room.
    fn arrived(&self, id: u64) {
        self.waiting.lock().unwrap_or_else(|e| e.into_inner()).retain(|w| w.0 != id);
    }
}

impl Server {
    /// The page's address, with its token.
    pub fn url(&self) -> Result<String> {
        let addr = self.listener.local_addr().map_err(|e| Error::Io { path: "(server)".into(), error: e })?;
        Ok(format!("http://{addr}/?token={}", self.shared.token))
    }

    /// Serves until the process ends.
    pub fn serve(self) -> Result<()> {
        for (id, stream) in (0u64..).zip(self.listener.incoming()) {
            let Ok(mut stream) = stream else { continue };
            let shared = Arc::clone(&self.shared);
            let open = shared.open.fetch_add(1, Ordering::SeqCst);
            // Every place taken: the slowest sender makes room, unless every place computes.
            let room = open < MAX_CONNECTIONS || (open < MAX_CONNECTIONS + MAX_CLOSING && shared.close_slowest());
            if !room {
                shared.open.fetch_sub(1, Ordering::SeqCst);
                let _ = write(&mut stream, &Reply::error(503, "too many connections"));
                continue;
            }
            if let Ok(handle) = stream.try_clone() {
                shared.waiting.lock().unwrap_or_else(|e| e.into_inner()).push((id, Instant::now(), handle));
            }
            let spawned = std::thread::Builder::new().name("explore".into()).spawn(move || {
                let _ = connection(&shared, stream, id);
                shared.arrived(id);
                shared.open.fetch_sub(1, Ordering::SeqCst);
            });
            if spawned.is_err() {
                self.shared.arrived(id);
                self.shared.open.fetch_sub(1, Ordering::SeqCst);
            }
        }
        Ok(())
    }
}

/// One connection: one request read, answered, closed.
fn connection(shared: &Shared, mut stream: TcpStream, id: u64) -> std::io::Result<()> {
    stream.set_write_timeout(Some(READ_TIMEOUT))?;
    let read = read_request(&mut stream, Instant::now() + READ_TIMEOUT);
    shared.arrived(id);
    let reply = match read {
        Ok((method, target, body)) => route(shared, &method, &target, &body),
        Err(r) => r,
    };
    write(&mut stream, &reply)
}

fn write(stream: &mut TcpStream, r: &Reply) -> std::io::Result<()> {
    let reason = match r.status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        409 => "Conflict",
        408 => "Request Timeout",
        413 => "Payload Too Large",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Internal Server Error",
    };
    let head = format!(
        "HTTP/1.1 {} {reason}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nContent-Security-Policy: default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:\r\nConnection: close\r\n\r\n",
        r.status,
        r.kind,
        r.body.len()
    );
    stream.write_all(head.as_bytes())?;
    stream.write_all(&r.body)?;
    stream.flush()
}

/// Reads into `chunk` what arrives before `deadline`: the count (0 at the end of the stream),
/// or the reply for a request that did not arrive in time.
fn read_by(stream: &mut TcpStream, chunk: &mut [u8], deadline: Instant) -> std::result::Result<usize, Reply> {
    let late = || Reply::error(408, format!("the request did not arrive within {} s", READ_TIMEOUT.as_secs()));
    let left = deadline.checked_duration_since(Instant::now()).filter(|d| !d.is_zero()).ok_or_else(late)?;
    stream.set_read_timeout(Some(left)).map_err(|_| late())?;
    match stream.read(chunk) {
        Ok(n) => Ok(n),
        Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => Err(late()),
        Err(_) => Ok(0),
    }
}

/// Reads one request by `deadline`: method, target and body, or the reply that refuses it.
fn read_request(stream: &mut TcpStream, deadline: Instant) -> std::result::Result<(String, String, Vec<u8>), Reply> {
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 4096];
    let end = loop {
        if let Some(i) = buf.windows(4).position(|w| w == b"\r\n\r\n") {
            break i;
        }
        if buf.len() > MAX_HEAD {
            return Err(Reply::error(431, format!("the request's head is longer than {MAX_HEAD} bytes")));
        }
        match read_by(stream, &mut chunk, deadline)? {
            0 => return Err(Reply::error(400, "the request ended before its head did")),
            n => buf.extend_from_slice(&chunk[..n]),
        }
    };
    if end > MAX_HEAD {
        return Err(Reply::error(431, format!("the request's head is longer than {MAX_HEAD} bytes")));
    }
    let head = std::str::from_utf8(&buf[..end]).map_err(|_| Reply::error(400, "the request's head is not UTF-8"))?;
    let mut lines = head.split("\r\n");
    let mut first = lines.next().unwrap_or("").split(' ');
    let (Some(method), Some(target), Some(version)) = (first.next(), first.next(), first.next()) else {
        return Err(Reply::error(400, "the request line is not METHOD TARGET VERSION"));
    };
    if !version.starts_with("HTTP/1.") || first.next().is_some() {
        return Err(Reply::error(400, "an HTTP/1.x request line"));
    }
    let mut length: Option<usize> = None;
    for line in lines {
        let Some((name, value)) = line.split_once(':') else {
            return Err(Reply::error(400, "a header line without ':'"));
        };
        if name.trim().eq_ignore_ascii_case("content-length") {
            if length.is_some() {
                return Err(Reply::error(400, "Content-Length is given twice: give it once"));
            }
            let n = value.trim();
            if n.is_empty() || !n.bytes().all(|b| b.is_ascii_digit()) {
                return Err(Reply::error(400, "Content-Length is not a number"));
            }
            length =
                Some(n.parse().map_err(|_| Reply::error(413, format!("the body is longer than {MAX_BODY} bytes")))?);
        }
        if name.trim().eq_ignore_ascii_case("transfer-encoding") {
            return Err(Reply::error(400, "Transfer-Encoding is not supported: send Content-Length"));
        }
    }
    let length = length.unwrap_or(0);
    if length > MAX_BODY {
        return Err(Reply::error(413, format!("the body is longer than {MAX_BODY} bytes")));
    }
    let mut body = buf[end + 4..].to_vec();
    if body.len() > length {
        return Err(Reply::error(400, "more body than Content-Length says"));
    }
    while body.len() < length {
        let want = (length - body.len()).min(chunk.len());
        match read_by(stream, &mut chunk[..want], deadline)? {
            0 => return Err(Reply::error(400, "the body ended before Content-Length bytes")),
            n => body.extend_from_slice(&chunk[..n]),
        }
    }
    Ok((method.to_string(), target.to_string(), body))
}

/// Whether `given` is the token, compared in time independent of where they differ.
fn same_token(given: &str, token: &str) -> bool {
    given.len() == token.len() && given.bytes().zip(token.bytes()).fold(0u8, |acc, (a, b)| acc | (a ^ b)) == 0
}

fn route(shared: &Shared, method: &str, target: &str, body: &[u8]) -> Reply {
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let given = query.split('&').find_map(|kv| kv.strip_prefix("token=")).unwrap_or("");
    if !same_token(given, &shared.token) {
        return Reply::error(403, "this page needs the token of the address shotdamp explore printed");
    }
    match (method, path) {
        ("GET", "/") | ("GET", "/index.html") => {
            // The page's own files carry the token too (a hex string: nothing to escape).
            Reply {
                status: 200,
                kind: "text/html; charset=utf-8",
                body: page::HTML.replace("TOKEN", &shared.token).into(),
            }
        }
        ("GET", "/app.js") => Reply { status: 200, kind: "text/javascript; charset=utf-8", body: page::APP_JS.into() },
        ("GET", "/app.css") => Reply { status: 200, kind: "text/css; charset=utf-8", body: page::APP_CSS.into() },
        ("GET", "/uplot.js") => {
            Reply { status: 200, kind: "text/javascript; charset=utf-8", body: page::UPLOT_JS.into() }
        }
        ("GET", "/uplot.css") => Reply { status: 200, kind: "text/css; charset=utf-8", body: page::UPLOT_CSS.into() },
        ("GET", "/licenses.txt") => {
            Reply { status: 200, kind: "text/plain; charset=utf-8", body: page::LICENSES.into() }
        }
        ("GET", "/api/setup") => Reply::json(200, shared.session.setup()),
        ("POST", "/api/sweep") => sweep(shared, body),
        ("POST", "/api/point") => point(shared, body),
        ("POST", "/api/export") => export(shared, body),
        (
            _,
            "/" | "/index.html" | "/app.js" | "/app.css" | "/uplot.js" | "/uplot.css" | "/licenses.txt" | "/api/setup",
        ) => Reply::error(405, "use GET"),
        (_, "/api/sweep" | "/api/point" | "/api/export") => Reply::error(405, "use POST"),
        _ => Reply::error(404, format!("no page {path}")),
    }
}

fn parse<T: serde::de::DeserializeOwned>(body: &[u8]) -> std::result::Result<T, Reply> {
    serde_json::from_slice(body).map_err(|e| Reply::error(400, format!("the request is not what the page sends: {e}")))
}

/// Runs `work` as the latest of `counter`'s computations: it stops at its next simulated
/// point when a newer one is asked for or after [`MAX_TIME`]. `seq` is the page's number for
/// the request (increasing; requests can arrive out of order, so an older one than the
/// newest seen is refused at once); without one, the request is the newest.
fn latest(
    shared: &Shared,
    counter: &Arc<AtomicU64>,
    seq: Option<u64>,
    work: impl FnOnce(&(dyn Fn() + Sync)) -> Result<Value>,
) -> Reply {
    if let Some(s) = seq.filter(|&s| s > MAX_SEQ) {
        return Reply::error(400, format!("seq = {s}: a whole number from 0 to {MAX_SEQ}"));
    }
    let mine = match seq {
        Some(s) if s > 0 => {
            if counter.fetch_max(s, Ordering::SeqCst) >= s {
                return Reply::error(409, "superseded by a newer request");
            }
            s
        }
        _ => counter.fetch_add(1, Ordering::SeqCst) + 1,
    };
    let _one = shared.compute.lock().unwrap_or_else(|e| e.into_inner());
    if counter.load(Ordering::SeqCst) != mine {
        return Reply::error(409, "superseded by a newer request");
    }
    let deadline = Instant::now() + MAX_TIME;
    let latest = Arc::clone(counter);
    let stop: cancel::Hook = Arc::new(move || {
        if latest.load(Ordering::Relaxed) != mine || Instant::now() > deadline {
            resume_unwind(Box::new(Cancelled));
        }
    });
    // Checked at every point of a sweep, and at every simulated period on this thread.
    match catch_unwind(AssertUnwindSafe(|| cancel::within(Arc::clone(&stop), || work(&*stop)))) {
        Ok(Ok(v)) => Reply::json(200, &v),
        Ok(Err(e)) => Reply::error(422, e.to_string()),
        Err(p) if p.is::<Cancelled>() && counter.load(Ordering::SeqCst) != mine => {
            Reply::error(409, "superseded by a newer request")
        }
        Err(p) if p.is::<Cancelled>() => Reply::error(
            503,
            format!("stopped after {} s: a narrower band, a wider step or fewer periods", MAX_TIME.as_secs()),
        ),
        Err(_) => Reply::error(500, "the computation failed (an internal error; the server goes on)"),
    }
}

fn sweep(shared: &Shared, body: &[u8]) -> Reply {
    let req: Request = match parse(body) {
        Ok(r) => r,
        Err(r) => return r,
    };
    latest(shared, &shared.sweeps, Some(req.seq), |stop| shared.session.run(&req, stop))
}

fn point(shared: &Shared, body: &[u8]) -> Reply {
    let req: PointRequest = match parse(body) {
        Ok(r) => r,
        Err(r) => return r,
    };
    latest(shared, &shared.points, None, |_| shared.session.point(&req))
}

fn export(shared: &Shared, body: &[u8]) -> Reply {
    let req: Request = match parse(body) {
        Ok(r) => r,
        Err(r) => return r,
    };
    match shared.session.export(&req) {
        Ok(text) => Reply { status: 200, kind: "application/toml; charset=utf-8", body: text.into_bytes() },
        Err(e) => Reply::error(422, e.to_string()),
    }
}
