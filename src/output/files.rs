//! Files that several processes on several hosts write into one folder: names that never
//! collide, writes that a reader sees whole or not at all (also after a crash), and a lock
//! per shard of a study (one writer at a time; a lock whose holder is gone is recognised).

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use crate::error::{Error, Result};

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |e| Error::io(path, e)
}

/// A name no other process on any host writes at the same time: host, process id (in
/// containers every process may be PID 1) and a random number.
pub(crate) fn unique() -> String {
    use std::hash::{BuildHasher, Hasher};
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u128(SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).map_or(0, |d| d.as_nanos()));
    let me = Holder::me();
    format!("{}-{}-{:016x}", sanitise(&me.host), me.pid, h.finish())
}

fn sanitise(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect()
}

/// A temporary name beside `path` (hidden: readers skip it).
pub(crate) fn temporary(path: &Path) -> PathBuf {
    path.with_file_name(format!(
        ".{}.tmp-{}",
        path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
        unique()
    ))
}

/// Writes `bytes` to a new file `tmp`, flushed to the disk.
pub(crate) fn write_synced(tmp: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write as _;
    let mut f = std::fs::OpenOptions::new().write(true).create_new(true).open(tmp).map_err(io(tmp))?;
    f.write_all(bytes).map_err(io(tmp))?;
    f.sync_all().map_err(io(tmp))
}

/// Flushes a folder's entries (a rename into it) to the disk, where the system allows it.
pub(crate) fn sync_dir(dir: &Path) {
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Writes `bytes` to `path` through a temporary file beside it (a name unique across hosts and
/// processes), flushed to the disk, and a rename: a reader sees the whole file or none, also
/// after a crash.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temporary(path);
    if let Err(e) = write_synced(&tmp, bytes) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    if let Err(e) = std::fs::rename(&tmp, path) {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    if let Some(parent) = path.parent() {
        sync_dir(parent);
    }
    Ok(())
}

/// Who holds a lock: host, process id and PID namespace, and since when.
#[derive(Debug, Clone, PartialEq)]
pub struct Holder {
    /// Host name.
    pub host: String,
    /// Process id.
    pub pid: u32,
    /// The PID namespace (`/proc/self/ns/pid`): a process id means something only inside it.
    pub namespace: String,
    /// Seconds since 1970 when the lock was taken.
    pub since: u64,
}

impl Holder {
    /// This process.
    pub fn me() -> Holder {
        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .ok()
            .or_else(|| std::env::var("HOSTNAME").ok())
            .map(|h| h.trim().to_string())
            .filter(|h| !h.is_empty())
            .unwrap_or_else(|| "unknown-host".into());
        let namespace = std::fs::read_link("/proc/self/ns/pid").map(|p| p.display().to_string()).unwrap_or_default();
        let since = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).map_or(0, |d| d.as_secs());
        Holder { host, pid: std::process::id(), namespace, since }
    }

    fn text(&self) -> String {
        format!("host {}\npid {}\nnamespace {}\nsince {}\n", self.host, self.pid, self.namespace, self.since)
    }

    fn parse(text: &str) -> Option<Holder> {
        let get = |k: &str| text.lines().find_map(|l| l.strip_prefix(k).map(|v| v.trim().to_string()));
        Some(Holder {
            host: get("host ")?,
            pid: get("pid ")?.parse().ok()?,
            namespace: get("namespace").unwrap_or_default(),
            since: get("since ")?.parse().ok()?,
        })
    }

    /// Whether this holder is certainly gone: a process of this host and PID namespace that
    /// no longer runs. (Elsewhere only the age of the lock can tell.)
    fn gone(&self) -> bool {
        let me = Holder::me();
        self.host == me.host
            && self.namespace == me.namespace
            && !self.namespace.is_empty()
            && !Path::new(&format!("/proc/{}", self.pid)).exists()
    }
}

impl std::fmt::Display for Holder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "host {}, pid {}, since {} s after 1970", self.host, self.pid, self.since)
    }
}

/// How often a lock's holder touches it.
pub const HEARTBEAT: Duration = Duration::from_secs(20);

/// A lock not touched for this long is stale, whoever holds it (its host may have died).
pub const STALE_AFTER: Duration = Duration::from_secs(300);

/// One writer at a time: a lock file created exclusively, holding its [`Holder`], touched
/// every [`HEARTBEAT`] while its holder runs and removed when it ends. A lock is stale when
/// its holder ran on this host (and PID namespace) and no longer runs, or when it was not
/// touched for [`STALE_AFTER`] (a host that died); a stale lock is taken over.
pub struct ShardLock {
    path: PathBuf,
    holder: Holder,
    stop: Option<std::sync::mpsc::Sender<()>>,
    beat: Option<std::thread::JoinHandle<()>>,
}

impl ShardLock {
    /// Takes the lock at `path`, or returns who holds it. A stale lock is taken over.
    pub fn try_take(path: &Path) -> Result<std::result::Result<ShardLock, Holder>> {
        for _ in 0..100 {
            let me = Holder::me();
            match std::fs::OpenOptions::new().write(true).create_new(true).open(path) {
                Ok(mut f) => {
                    use std::io::Write as _;
                    f.write_all(me.text().as_bytes()).and_then(|()| f.sync_all()).map_err(io(path))?;
                    return Ok(Ok(ShardLock::start(path.to_path_buf(), me)));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => return Err(Error::io(path, e)),
            }
            let Ok(text) = std::fs::read_to_string(path) else { continue };
            let age = std::fs::metadata(path)
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| SystemTime::now().duration_since(t).ok())
                .unwrap_or_default();
            let holder = Holder::parse(&text);
            // A lock being written by its taker has no complete text for a moment.
            let stale = match &holder {
                Some(h) => h.gone() || age > STALE_AFTER,
                None => age > Duration::from_secs(5),
            };
            if !stale {
                match holder {
                    Some(h) => return Ok(Err(h)),
                    None => {
                        std::thread::sleep(Duration::from_millis(20));
                        continue;
                    }
                }
            }
            // Taken over through a rename to a unique name: of two processes that find it
            // stale at once, one renames it, the other finds it gone and tries again.
            let aside = temporary(path);
            if std::fs::rename(path, &aside).is_ok() {
                let _ = std::fs::remove_file(&aside);
            }
        }
        Err(Error::Destination {
            path: path.to_path_buf(),
            message: "could not be taken: it changed hands 100 times; try again".into(),
        })
    }

    fn start(path: PathBuf, holder: Holder) -> ShardLock {
        let (stop, rx) = std::sync::mpsc::channel::<()>();
        let p = path.clone();
        let beat = std::thread::spawn(move || {
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = rx.recv_timeout(HEARTBEAT) {
                if let Ok(f) = std::fs::File::options().append(true).open(&p) {
                    let _ = f.set_modified(SystemTime::now());
                }
            }
        });
        ShardLock { path, holder, stop: Some(stop), beat: Some(beat) }
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for ShardLock {
    /// Stops the heartbeat and removes the lock if it is still this process's.
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(b) = self.beat.take() {
            let _ = b.join();
        }
        if std::fs::read_to_string(&self.path).ok().and_then(|t| Holder::parse(&t)).as_ref() == Some(&self.holder) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Today's date (UTC) as YYYY-MM-DD.
pub fn today_utc() -> String {
    let secs = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    civil_date((secs / 86_400) as i64)
}

/// Days since 1970-01-01 to the civil date YYYY-MM-DD (H. Hinnant's algorithm).
fn civil_date(days: i64) -> String {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lock_is_exclusive_and_released_and_a_dead_holders_lock_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.lock");
        let a = ShardLock::try_take(&path).unwrap().ok().unwrap();
        let held = ShardLock::try_take(&path).unwrap().err().unwrap();
        assert_eq!(held.pid, std::process::id());
        drop(a);
        assert!(!path.exists(), "released");
        // A holder of this host whose process no longer runs (pids stay below 2^22).
        let dead = Holder { pid: 4_194_999, ..Holder::me() };
        std::fs::write(&path, dead.text()).unwrap();
        let b = ShardLock::try_take(&path)
            .unwrap()
            .unwrap_or_else(|h| panic!("a dead holder's lock is taken over, not held by {h}"));
        assert_eq!(Holder::parse(&std::fs::read_to_string(b.path()).unwrap()).unwrap().pid, std::process::id());
        drop(b);
        // A live holder on another host: only its age makes it stale.
        let far = Holder { host: "elsewhere".into(), pid: 1, ..Holder::me() };
        std::fs::write(&path, far.text()).unwrap();
        assert!(ShardLock::try_take(&path).unwrap().is_err(), "fresh: held");
        let old = SystemTime::now() - STALE_AFTER - Duration::from_secs(1);
        std::fs::File::options().append(true).open(&path).unwrap().set_modified(old).unwrap();
        assert!(ShardLock::try_take(&path).unwrap().is_ok(), "not touched for STALE_AFTER: taken over");
    }

    #[test]
    fn temporary_names_differ_within_one_process() {
        let p = Path::new("/x/study.json");
        assert_ne!(temporary(p), temporary(p));
    }

    #[test]
    fn civil_dates() {
        assert_eq!(super::civil_date(0), "1970-01-01");
        assert_eq!(super::civil_date(11_016), "2000-02-29");
        assert_eq!(super::civil_date(20_782), "2026-11-25");
        assert_eq!(super::civil_date(-1), "1969-12-31");
    }
}
