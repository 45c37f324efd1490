//! The reductions made in this process, kept by what they were computed from: a setup that
//! is validated again (each explorer request, each study sample, a design's budget, probe and
//! run) reads its matrix files again, finds them unchanged and takes the reduction already
//! made instead of reducing the model again (docs/extending.md, "One setup, built once").
//!
//! The key is everything a reduction depends on: the experiment file's folder, the
//! `[structure.finite_element]` table as given, the coordinate limit of the analysis, and
//! each matrix file's length and 64-bit hash of its bytes (a file edited between two
//! requests is reduced again). At most [`KEPT`] reductions are kept, the oldest dropped
//! first.

use std::hash::Hasher;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use super::FromFiles;
use crate::experiment::file::raw::RawFiniteElement;

/// Reductions kept at most.
pub const KEPT: usize = 8;

/// What a reduction is computed from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Key {
    folder: PathBuf,
    table: String,
    limit: Option<usize>,
    /// Each file read: its path, length and the hash of its bytes.
    files: Vec<(PathBuf, u64, u64)>,
}

impl Key {
    /// The key of `raw` read next to `path`, or `None` when a file cannot be read (the
    /// reduction then runs and says what is wrong).
    pub fn of(path: &Path, raw: &RawFiniteElement, limit: Option<usize>) -> Option<Key> {
        let folder = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let names = [Some(&raw.stiffness), Some(&raw.mass), raw.dofs.as_ref()];
        let mut files = Vec::new();
        for name in names.into_iter().flatten() {
            let at = folder.join(name);
            // Never opened before it is known to be a regular file (a named pipe would wait).
            crate::error::regular_file(&at).ok()?;
            let bytes = std::fs::read(&at).ok()?;
            let mut h = std::collections::hash_map::DefaultHasher::new();
            h.write(&bytes);
            files.push((at, bytes.len() as u64, h.finish()));
        }
        Some(Key { folder, table: format!("{raw:?}"), limit, files })
    }
}

/// The reductions kept, oldest first, with how often each was found.
static MADE: Mutex<Vec<(Key, FromFiles, usize)>> = Mutex::new(Vec::new());

/// Reductions computed in this process (not taken from [`MADE`]).
static COMPUTED: AtomicUsize = AtomicUsize::new(0);

/// The reduction made for `key`, if kept.
pub fn find(key: &Key) -> Option<FromFiles> {
    let mut made = MADE.lock().unwrap_or_else(|e| e.into_inner());
    made.iter_mut().find(|(k, _, _)| k == key).map(|(_, f, hits)| {
        *hits += 1;
        f.clone()
    })
}

/// Keeps `made`, reduced for `key` (counted as computed).
pub fn keep(key: Key, made: &FromFiles) {
    COMPUTED.fetch_add(1, Ordering::Relaxed);
    let mut kept = MADE.lock().unwrap_or_else(|e| e.into_inner());
    kept.retain(|(k, _, _)| *k != key);
    if kept.len() >= KEPT {
        kept.remove(0);
    }
    kept.push((key, made.clone(), 0));
}

/// Counts a reduction computed without a key (a file that could not be read for one).
pub fn computed_without_key() {
    COMPUTED.fetch_add(1, Ordering::Relaxed);
}

/// Finite-element reductions computed in this process so far: a setup validated again does
/// not add to it.
pub fn computed() -> usize {
    COMPUTED.load(Ordering::Relaxed)
}

/// For each reduction kept of a model in `folder` (the experiment file's), oldest first: how
/// often a validation found it instead of reducing again.
pub fn found_in(folder: &Path) -> Vec<usize> {
    let kept = MADE.lock().unwrap_or_else(|e| e.into_inner());
    kept.iter().filter(|(k, _, _)| k.folder == folder).map(|(_, _, hits)| *hits).collect()
}
