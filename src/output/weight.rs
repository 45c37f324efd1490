//! What a report weighs, page by page (docs/reviewing.md, "Mailing the report"): every
//! folder that holds a page (`index.html`) is measured apart from its `data/` folder, and
//! each against its budget, so that a figure or table that grows is named with its page.
//! Reads the folder; writes nothing.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Most bytes of a page with its figures (not its data folder).
pub const PAGE_BUDGET: u64 = 1_000_000;

/// Most bytes of a page's data folder (its tables).
pub const DATA_BUDGET: u64 = 2_000_000;

/// Most bytes of the whole report (`shotdamp report`'s folder): small enough to mail; `.ci/run`
/// refuses a folder over 20 MB outright.
pub const REPORT_BUDGET: u64 = 15_000_000;

/// One folder's weight.
#[derive(Debug, Clone, PartialEq)]
pub struct Weight {
    /// The folder, relative to the report.
    pub folder: PathBuf,
    /// Bytes of its own files (a page and its figures, or a data folder's tables).
    pub bytes: u64,
    /// Its largest file and that file's bytes.
    pub largest: Option<(String, u64)>,
    /// Its budget.
    pub budget: u64,
}

impl Weight {
    /// The sentence for a folder over its budget: the page, its weight, the largest file.
    pub fn over(&self) -> Option<String> {
        (self.bytes > self.budget).then(|| {
            format!(
                "{}: {} bytes, over its budget of {}{}",
                self.folder.display(),
                self.bytes,
                self.budget,
                self.largest.as_ref().map_or(String::new(), |(f, b)| format!(" (largest file {f}: {b} bytes)"))
            )
        })
    }
}

fn files(dir: &Path) -> Result<Vec<(String, u64)>> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let e = e.map_err(|e| Error::io(dir, e))?;
        let meta = e.metadata().map_err(|err| Error::io(e.path(), err))?;
        if meta.is_file() {
            out.push((e.file_name().to_string_lossy().into_owned(), meta.len()));
        }
    }
    Ok(out)
}

fn weigh(report: &Path, dir: &Path, budget: u64) -> Result<Weight> {
    let f = files(dir)?;
    let largest = f.iter().max_by_key(|x| x.1).cloned();
    Ok(Weight {
        folder: dir.strip_prefix(report).unwrap_or(dir).to_path_buf(),
        bytes: f.iter().map(|x| x.1).sum(),
        largest,
        budget,
    })
}

/// The weight of every page folder of `report` and of every data folder, in path order.
pub fn pages(report: &Path) -> Result<Vec<Weight>> {
    let mut out = Vec::new();
    let mut stack = vec![report.to_path_buf()];
    while let Some(dir) = stack.pop() {
        if dir.join("index.html").is_file() {
            out.push(weigh(report, &dir, PAGE_BUDGET)?);
        }
        if dir.file_name().is_some_and(|n| n == "data") {
            out.push(weigh(report, &dir, DATA_BUDGET)?);
        }
        for e in std::fs::read_dir(&dir).map_err(|e| Error::io(&dir, e))? {
            let e = e.map_err(|e| Error::io(&dir, e))?;
            if e.file_type().map_err(|err| Error::io(e.path(), err))?.is_dir() {
                stack.push(e.path());
            }
        }
    }
    out.sort_by(|a, b| a.folder.cmp(&b.folder));
    Ok(out)
}

/// Bytes of every file under `report`, the sentence for a report over [`REPORT_BUDGET`] with
/// its three heaviest folders.
pub fn total(report: &Path) -> Result<(u64, Option<String>)> {
    let bytes = bytes_under(report)?;
    let mut heaviest = pages(report)?;
    heaviest.sort_by_key(|w| std::cmp::Reverse(w.bytes));
    let named: Vec<String> =
        heaviest.iter().take(3).map(|w| format!("{} ({} bytes)", w.folder.display(), w.bytes)).collect();
    let over = (bytes > REPORT_BUDGET).then(|| {
        format!("the report is {bytes} bytes, over its budget of {REPORT_BUDGET}; heaviest: {}", named.join(", "))
    });
    Ok((bytes, over))
}

/// Bytes of every file under `dir`, at any depth.
fn bytes_under(dir: &Path) -> Result<u64> {
    let mut bytes = 0;
    for e in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let e = e.map_err(|e| Error::io(dir, e))?;
        let meta = e.metadata().map_err(|err| Error::io(e.path(), err))?;
        bytes += if meta.is_dir() { bytes_under(&e.path())? } else { meta.len() };
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A page over its budget is named with its largest file; the data folder is weighed
    /// apart from its page.
    #[test]
    fn a_page_over_its_budget_is_named_with_its_largest_file() {
        let dir = tempfile::tempdir().unwrap();
        let page = dir.path().join("fig99/stated");
        std::fs::create_dir_all(page.join("data")).unwrap();
        std::fs::write(page.join("index.html"), vec![b'x'; 1000]).unwrap();
        std::fs::write(page.join("big.png"), vec![0u8; PAGE_BUDGET as usize]).unwrap();
        std::fs::write(page.join("data/t.csv"), vec![b'1'; 10]).unwrap();
        std::fs::write(dir.path().join("index.html"), b"top").unwrap();
        let w = pages(dir.path()).unwrap();
        let names: Vec<String> = w.iter().map(|x| x.folder.display().to_string()).collect();
        assert_eq!(names, ["", "fig99/stated", "fig99/stated/data"]);
        let over: Vec<String> = w.iter().filter_map(Weight::over).collect();
        assert_eq!(over.len(), 1, "{over:?}");
        assert!(
            over[0].starts_with("fig99/stated: 1001000 bytes") && over[0].contains("largest file big.png"),
            "{}",
            over[0]
        );
        assert_eq!(w[2].bytes, 10);
        // Every file counts once in the whole: the pages, their data, and the folders that are
        // neither (a page's scans).
        std::fs::create_dir_all(page.join("scans")).unwrap();
        std::fs::write(page.join("scans/s.png"), vec![0u8; 7]).unwrap();
        let (bytes, over) = total(dir.path()).unwrap();
        assert_eq!(bytes, 3 + 1000 + PAGE_BUDGET + 10 + 7);
        assert!(over.is_none());
    }
}
