//! Reference files read once: validation parses each value file and digitised file it checks
//! an experiment against through one [`Files`] (one per load of a set of experiments), keeps
//! what it parsed in the checks ([`Loaded`]), and the checks' store takes it from there: no
//! file is parsed twice.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use super::digitised::{self, DigitisedFile};
use super::values::ValueFile;
use crate::error::Result;

/// A reference file as validation parsed it, kept by the check that names it.
#[derive(Debug, Clone)]
pub enum Loaded {
    /// A file of values stated in a source.
    Values(Arc<ValueFile>),
    /// Curves digitised from a figure.
    Digitised(Arc<DigitisedFile>),
}

/// The reference folder and the files of it parsed so far, each parsed once.
#[derive(Debug)]
pub struct Files {
    dir: PathBuf,
    values: Mutex<BTreeMap<String, Arc<ValueFile>>>,
    digitised: Mutex<BTreeMap<String, Arc<DigitisedFile>>>,
    reads: AtomicUsize,
}

/// `map[name]`, parsed by `parse` the first time it is asked for.
fn memo<T>(map: &Mutex<BTreeMap<String, Arc<T>>>, name: &str, parse: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
    // A panic elsewhere while the map was held leaves it whole (inserts are single calls).
    let mut map = map.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(v) = map.get(name) {
        return Ok(Arc::clone(v));
    }
    let v = Arc::new(parse()?);
    map.insert(name.to_string(), Arc::clone(&v));
    Ok(v)
}

impl Files {
    /// Files under the reference folder `dir`, none parsed yet.
    pub fn new(dir: &Path) -> Files {
        Files {
            dir: dir.to_path_buf(),
            values: Mutex::default(),
            digitised: Mutex::default(),
            reads: AtomicUsize::new(0),
        }
    }

    /// The reference folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The value file `name` (a path below the folder), parsed the first time.
    pub fn values(&self, name: &str) -> Result<Arc<ValueFile>> {
        memo(&self.values, name, || {
            self.reads.fetch_add(1, Ordering::Relaxed);
            ValueFile::load(&self.dir.join(name))
        })
    }

    /// The digitised file `name` (a path below the folder), parsed the first time.
    pub fn digitised(&self, name: &str) -> Result<Arc<DigitisedFile>> {
        memo(&self.digitised, name, || {
            self.reads.fetch_add(1, Ordering::Relaxed);
            digitised::load(&self.dir.join(name))
        })
    }

    /// How many files were parsed (each once).
    pub fn reads(&self) -> usize {
        self.reads.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_file_is_parsed_once() {
        let dir = std::env::temp_dir().join(format!("shotdamp-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = "[meta]\nprovenance = \"paper text\"\nsource = \"x\"\n\n[[quantity]]\nid = \"f1\"\nvalue = 14.6\nunit = \"Hz\"\nsection = \"1\"\nquote = \"q\"\n";
        std::fs::write(dir.join("v.toml"), text).unwrap();
        let files = Files::new(&dir);
        let (a, b) = (files.values("v.toml"), files.values("v.toml"));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!(Arc::ptr_eq(&a, &b));
        assert_eq!(files.reads(), 1);
        assert!(files.values("none.toml").is_err());
        assert!(files.digitised("none.json").is_err());
        assert_eq!(files.reads(), 3, "a failed read is tried again, not kept");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
