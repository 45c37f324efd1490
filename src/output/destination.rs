//! Output folders. A report is written into a new staging folder beside its destination and
//! renamed into place at the end, so a failed or interrupted run leaves the previous report
//! intact. shotdamp replaces only a folder that it wrote itself (it carries the marker file
//! [`MARKER`] and the list [`MANIFEST`] of every entry it wrote) or an empty one: a folder of
//! someone else's files, a report folder into which anyone put an entry shotdamp did not
//! write, or a path that is a file, is refused before the run starts (and again just before
//! the new report replaces the old). Nothing of the user's is moved, renamed or deleted.
//!
//! Staging folders are `.NAME.tmp-PID` beside the destination; the next run into the same
//! destination removes those of processes that no longer run (never a live one).

use std::path::{Component, Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use crate::error::{Error, Result};

/// `true` once a report of this process has been moved into place. Held while a report is
/// moved into place, and by an interrupt handler while it removes a staging folder, so that a
/// signal comes either before the commit (the staging folder goes, the previous report stays)
/// or after it (the new report stays and the run ends by itself).
static COMMITTED: Mutex<bool> = Mutex::new(false);

/// The commit lock (see `COMMITTED`); a poisoned lock is taken as it is.
pub fn commit_lock() -> MutexGuard<'static, bool> {
    COMMITTED.lock().unwrap_or_else(|e| e.into_inner())
}

/// `path` made absolute with every symbolic link of its existing part resolved, and `..` of
/// the part that does not exist yet folded: two spellings of one place give one path.
pub fn resolved(path: &Path) -> Result<PathBuf> {
    let abs = absolute(path)?;
    let mut existing = abs.clone();
    let mut rest: Vec<std::ffi::OsString> = Vec::new();
    loop {
        if let Ok(c) = std::fs::canonicalize(&existing) {
            let mut out = c;
            for r in rest.iter().rev() {
                match Path::new(r).components().next() {
                    Some(Component::ParentDir) => {
                        out.pop();
                    }
                    Some(Component::CurDir) | None => {}
                    _ => out.push(r),
                }
            }
            return Ok(out);
        }
        match (existing.file_name().map(|n| n.to_os_string()), existing.parent()) {
            (Some(name), Some(parent)) => {
                rest.push(name);
                existing = parent.to_path_buf();
            }
            _ => return Ok(abs),
        }
    }
}

/// Refuses an output folder that is, contains or lies inside one of the command's inputs
/// (`(what, path)`: e.g. `("REPORT_A", a)`), before anything runs: no command writes into
/// what it reads.
pub fn refuse_overlap(out: &Path, inputs: &[(&str, &Path)]) -> Result<()> {
    let o = resolved(out)?;
    for (what, input) in inputs {
        let i = resolved(input)?;
        let relation = if o == i {
            "is"
        } else if i.starts_with(&o) {
            "contains"
        } else if o.starts_with(&i) {
            "lies inside"
        } else {
            continue;
        };
        return Err(Error::Destination {
            path: out.to_path_buf(),
            message: format!(
                "{relation} {what} ({}), one of this command's inputs: shotdamp never writes into its own inputs. Give --out a folder outside them",
                input.display()
            ),
        });
    }
    Ok(())
}

/// `out` made absolute (against the working directory).
fn absolute(out: &Path) -> Result<PathBuf> {
    if out.is_absolute() {
        Ok(out.to_path_buf())
    } else {
        Ok(std::env::current_dir().map_err(|e| Error::io(".", e))?.join(out))
    }
}

/// The staging folder this process will write a report for `out` into (known before it
/// exists, so that an interrupt handler can be in place before it is created).
pub fn staging_path(out: &Path) -> Result<PathBuf> {
    Ok(sibling(&absolute(out)?, "tmp", std::process::id()))
}

/// The marker file every report folder carries.
pub const MARKER: &str = ".shotdamp-report";

/// The marker's text (fixed, so that a tracked copy never shows as changed).
pub const MARKER_TEXT: &str = "This folder was written by shotdamp. shotdamp replaces it on its next run into this folder,\nand refuses to while it holds anything shotdamp did not write (.shotdamp-files lists what it wrote).\n";

/// The list of every entry (file, folder, link) shotdamp wrote into a report folder, one path
/// relative to the folder a line (`/` between parts, a folder's path ending in `/`), sorted.
/// Written last, just before the report is moved into place; read before the folder is
/// replaced, so that an entry added by anyone else is found and the folder refused.
pub const MANIFEST: &str = ".shotdamp-files";

/// The entries a marked folder without a [`MANIFEST`] may hold: the tracked `reports/` of a
/// fresh checkout (the marker and the README).
const BARE_MARKED: [&str; 2] = [MARKER, "README.md"];

/// The README every report folder carries (the same bytes as the tracked `reports/README.md`).
pub const README: &str = include_str!("../../reports/README.md");

/// A report being written.
pub struct Staging {
    out: PathBuf,
    /// `out` as the caller gave it (for messages).
    given: PathBuf,
    dir: PathBuf,
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |e| Error::io(path, e)
}

/// The staging or backup sibling of `out` for process `pid`.
fn sibling(out: &Path, tag: &str, pid: u32) -> PathBuf {
    out.with_file_name(format!(".{}.{tag}-{pid}", name(out)))
}

fn name(out: &Path) -> String {
    out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "reports".into())
}

/// Whether `out` may be replaced: it does not exist, or it is a folder that shotdamp wrote (and
/// holds nothing it did not write) or an empty one. Anything else is an error that says what
/// is there and what to do.
pub fn check(out: &Path) -> Result<()> {
    let out = &named(out)?;
    let meta = match std::fs::symlink_metadata(out) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(Error::io(out, e)),
    };
    let refuse =
        |what: String, rule: &str| Error::Destination { path: out.to_path_buf(), message: format!("{what}; {rule}") };
    const RULE: &str = "shotdamp replaces only a folder it wrote itself (with a .shotdamp-report file) or an empty one. Give --out a new folder, or move those files away first";
    if !meta.is_dir() {
        return Err(refuse(
            if meta.file_type().is_symlink() {
                "is a symbolic link, not a folder".into()
            } else {
                "is a file, not a folder".into()
            },
            RULE,
        ));
    }
    if out.join(MARKER).is_file() {
        let (foreign, listed) = foreign_entries(out)?;
        if foreign.is_empty() {
            return Ok(());
        }
        return Err(refuse(
            format!(
                "is a folder shotdamp wrote, but it holds {} that shotdamp did not write: {}{}",
                count(foreign.len()),
                shown(&foreign),
                if listed { "" } else { " (it has no list of what shotdamp wrote, .shotdamp-files: a report of an earlier version)" }
            ),
            "shotdamp never deletes what it did not write. Move them out of the folder (or the whole folder away), or give --out a new folder",
        ));
    }
    let mut entries: Vec<String> = std::fs::read_dir(out)
        .map_err(io(out))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    if entries.is_empty() {
        return Ok(());
    }
    entries.sort_unstable();
    Err(refuse(
        format!("is a folder that shotdamp did not write ({}: {})", count(entries.len()), shown(&entries)),
        RULE,
    ))
}

/// `out` without trailing `/` (so that a symbolic link is seen as one, not followed), refused
/// when it names no folder of its own: `.`, `..`, `/`, or a folder that holds the current
/// one (a report is renamed into place: the current folder cannot be).
fn named(out: &Path) -> Result<PathBuf> {
    let refuse = |what: &str| {
        Error::Destination {
        path: out.to_path_buf(),
        message: format!("{what}: a report is written beside its folder and renamed into place; give --out a folder of its own (a new name)"),
    }
    };
    match out.components().next_back() {
        None | Some(Component::CurDir | Component::ParentDir | Component::RootDir | Component::Prefix(_)) => {
            return Err(refuse("names the current folder, a parent or the root"))
        }
        Some(Component::Normal(_)) => {}
    }
    let trimmed: PathBuf = out.components().collect();
    let here = std::env::current_dir().ok().and_then(|d| std::fs::canonicalize(d).ok());
    if let (Some(here), Ok(there)) = (here, resolved(&trimmed)) {
        if here.starts_with(&there) {
            return Err(refuse("is or holds the current folder"));
        }
    }
    Ok(trimmed)
}

/// "1 entry" or "N entries".
fn count(n: usize) -> String {
    format!("{n} {}", if n == 1 { "entry" } else { "entries" })
}

/// The first three of `entries` (sorted), and how many more.
fn shown(entries: &[String]) -> String {
    let more = if entries.len() > 3 { format!(" and {} more", entries.len() - 3) } else { String::new() };
    format!("{}{more}", entries[..entries.len().min(3)].join(", "))
}

/// Every entry below `dir` (files, folders and links, not following links), as paths relative
/// to it with `/` between parts and a folder's path ending in `/`, sorted.
fn entries_below(dir: &Path) -> Result<Vec<String>> {
    let mut out = Vec::new();
    let mut stack = vec![(dir.to_path_buf(), String::new())];
    while let Some((path, rel)) = stack.pop() {
        for e in std::fs::read_dir(&path).map_err(io(&path))? {
            let e = e.map_err(io(&path))?;
            let name = e.file_name().to_string_lossy().into_owned();
            let is_dir = e.file_type().map_err(io(&e.path()))?.is_dir();
            let r = format!("{rel}{name}{}", if is_dir { "/" } else { "" });
            if is_dir {
                stack.push((e.path(), r.clone()));
            }
            out.push(r);
        }
    }
    out.sort_unstable();
    Ok(out)
}

/// The entries of the marked folder `dir` that shotdamp did not write: those its
/// [`MANIFEST`] does not list (without one: all but [`BARE_MARKED`]). Of a foreign folder
/// only the folder is named, not what it holds. The flag: whether the folder has a manifest.
fn foreign_entries(dir: &Path) -> Result<(Vec<String>, bool)> {
    let manifest = dir.join(MANIFEST);
    // Each entry, with its size and hash where the manifest records them (those of earlier
    // versions do not).
    let (written, listed): (std::collections::BTreeMap<String, Option<String>>, bool) =
        match std::fs::read_to_string(&manifest) {
            Ok(text) => (
                text.lines()
                    .map(|l| match l.split_once('\t') {
                        Some((p, f)) => (p.to_string(), Some(f.to_string())),
                        None => (l.to_string(), None),
                    })
                    .collect(),
                true,
            ),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                (BARE_MARKED.iter().map(|s| (s.to_string(), None)).collect(), false)
            }
            Err(e) => return Err(Error::io(&manifest, e)),
        };
    let mut foreign: Vec<String> = Vec::new();
    for e in entries_below(dir)? {
        if e == MARKER || e == MANIFEST {
            continue;
        }
        if let Some(recorded) = written.get(&e) {
            // A file shotdamp wrote and someone changed since is the user's now.
            if let Some(recorded) = recorded {
                if &fingerprint(&dir.join(&e))? != recorded {
                    foreign.push(format!("{e} (changed since shotdamp wrote it)"));
                }
            }
            continue;
        }
        // Inside a foreign folder: that folder is named already.
        if foreign.iter().any(|f| f.ends_with('/') && e.starts_with(f.as_str())) {
            continue;
        }
        foreign.push(e);
    }
    Ok((foreign, listed))
}

/// A file's size and content hash (64-bit FNV-1a, hex), as the [`MANIFEST`] records them:
/// an edit after shotdamp wrote the file is found on the next run into its folder.
fn fingerprint(path: &Path) -> Result<String> {
    use std::io::Read;
    let mut f = std::fs::File::open(path).map_err(io(path))?;
    let (mut hash, mut size, mut buf) = (0xcbf2_9ce4_8422_2325_u64, 0u64, vec![0u8; 1 << 16]);
    loop {
        let n = f.read(&mut buf).map_err(io(path))?;
        if n == 0 {
            break;
        }
        size += n as u64;
        for &b in &buf[..n] {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    Ok(format!("{size}\t{hash:016x}"))
}

/// Writes the [`MANIFEST`] of the staging folder `dir` (every entry in it, each file with its
/// size and hash after a tab).
fn write_manifest(dir: &Path) -> Result<()> {
    let mut text = String::new();
    for e in entries_below(dir)? {
        if e != MANIFEST {
            text.push_str(&e);
            if !e.ends_with('/') && std::fs::symlink_metadata(dir.join(&e)).is_ok_and(|m| m.is_file()) {
                text.push('\t');
                text.push_str(&fingerprint(&dir.join(&e))?);
            }
            text.push('\n');
        }
    }
    let path = dir.join(MANIFEST);
    std::fs::write(&path, text).map_err(io(&path))
}

/// Whether process `pid` is running (on systems without `/proc`: assumed running).
fn running(pid: u32) -> bool {
    !Path::new("/proc/self").exists() || Path::new(&format!("/proc/{pid}")).exists()
}

/// Removes the staging and backup folders beside `out` left by processes that no longer run.
/// Returns the folders removed.
pub fn remove_stale(out: &Path) -> Vec<PathBuf> {
    let Some(parent) = out.parent() else { return Vec::new() };
    let Ok(entries) = std::fs::read_dir(parent) else { return Vec::new() };
    let prefixes = [format!(".{}.tmp-", name(out)), format!(".{}.old-", name(out))];
    let mut removed = Vec::new();
    for e in entries.filter_map(|e| e.ok()) {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = prefixes.iter().find_map(|p| file.strip_prefix(p.as_str())).and_then(|s| s.parse::<u32>().ok())
        else {
            continue;
        };
        let path = e.path();
        // Only folders shotdamp wrote (a staging folder carries the marker from its start).
        if pid != std::process::id()
            && !running(pid)
            && path.join(MARKER).is_file()
            && std::fs::remove_dir_all(&path).is_ok()
        {
            removed.push(path);
        }
    }
    removed
}

impl Staging {
    /// Checks the destination and prepares a staging folder for it (with the marker and the
    /// README), before any long run.
    pub fn create(given: &Path) -> Result<Staging> {
        check(given)?;
        let out = absolute(&named(given)?)?;
        if let Some(parent) = out.parent() {
            std::fs::create_dir_all(parent).map_err(io(parent))?;
        }
        remove_stale(&out);
        let dir = sibling(&out, "tmp", std::process::id());
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(io(&dir))?;
        }
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        std::fs::write(dir.join(MARKER), MARKER_TEXT).map_err(io(&dir))?;
        std::fs::write(dir.join("README.md"), README).map_err(io(&dir))?;
        Ok(Staging { out, given: given.to_path_buf(), dir })
    }

    /// The staging folder (what an interrupt handler removes).
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Where the report will be.
    pub fn destination(&self) -> &Path {
        &self.out
    }

    /// Moves the report into place, with the list of what it holds ([`MANIFEST`]); the
    /// previous one (checked again: it may have changed during the run) is removed only after
    /// the new one is there.
    pub fn commit(self) -> Result<PathBuf> {
        // (`self` is dropped at the end: its staging folder is gone by then, or abandoned.)
        let mut committed = commit_lock();
        if !self.dir.is_dir() {
            // An interrupt removed it before the lock was taken: the process is ending.
            return Err(Error::Destination { path: self.dir.clone(), message: "removed by an interrupt".into() });
        }
        check(&self.given)?;
        write_manifest(&self.dir)?;
        let backup = sibling(&self.out, "old", std::process::id());
        let had_old = self.out.exists();
        if had_old {
            std::fs::rename(&self.out, &backup).map_err(io(&self.out))?;
            // Checked once more where no one else writes: anything added between the check
            // above and the rename is found here, and the folder is put back as it was.
            if let Err(e) = check(&backup) {
                let _ = std::fs::rename(&backup, &self.out);
                return Err(match check(&self.given) {
                    Err(named) => named,
                    Ok(()) => e,
                });
            }
        }
        if let Err(e) = std::fs::rename(&self.dir, &self.out) {
            if had_old {
                let _ = std::fs::rename(&backup, &self.out);
            }
            return Err(Error::io(&self.out, e));
        }
        *committed = true;
        if had_old {
            std::fs::remove_dir_all(&backup).map_err(io(&backup))?;
        }
        Ok(self.out.clone())
    }

    /// Removes the staging folder of an abandoned report (as dropping it does).
    pub fn abandon(self) {}
}

impl Drop for Staging {
    /// A report that was not committed leaves nothing behind (after a commit the staging
    /// folder no longer exists).
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
