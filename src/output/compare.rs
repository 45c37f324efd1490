//! `shotdamp compare A B`: a page that shows each figure of two reports side by side and
//! overlaid, and the checks whose status or value changed, for a reviewer looking at the
//! effect of a change. The page and copies of the figures go into a new folder renamed into
//! place at the end.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::checks::fmt_num;
use crate::error::{read_to_string, Error, Result};

/// One figure of both reports.
#[derive(Debug, Serialize)]
pub struct FigurePair {
    /// The experiment's key.
    pub experiment: String,
    /// The figure's file name.
    pub name: String,
    /// Relative paths in the comparison folder ("" when a report lacks it).
    pub a: String,
    /// The same in report B.
    pub b: String,
}

/// One check whose outcome differs.
#[derive(Debug, Serialize)]
pub struct CheckChange {
    /// The experiment's key.
    pub experiment: String,
    /// The check's name.
    pub name: String,
    /// Its status in report A ("" when absent).
    pub status_a: String,
    /// Its status in report B ("" when absent).
    pub status_b: String,
    /// Its computed value in report A.
    pub computed_a: String,
    /// Its computed value in report B.
    pub computed_b: String,
    /// What changed, in words.
    pub change: String,
}

/// The comparison page's context.
#[derive(Debug, Serialize)]
pub struct CompareView {
    /// Report A's folder.
    pub a: String,
    /// Report B's folder.
    pub b: String,
    /// Every figure of both reports.
    pub figures: Vec<FigurePair>,
    /// The checks that changed.
    pub changes: Vec<CheckChange>,
    /// Checks with the same status and value in both.
    pub unchanged: usize,
    /// Experiments that only one report has.
    pub only_a: Vec<String>,
    /// Experiments only report B has.
    pub only_b: Vec<String>,
}

type Checks = BTreeMap<(String, String), (String, f64)>;

fn checks(dir: &Path) -> Result<Checks> {
    let path = dir.join("checks.json");
    let v: serde_json::Value = serde_json::from_str(&read_to_string(&path)?)
        .map_err(|e| Error::Parse { file: path.display().to_string(), message: e.to_string() })?;
    let list = v.get("checks").and_then(|c| c.as_array()).cloned().unwrap_or_default();
    Ok(list
        .iter()
        .map(|c| {
            let s = |k: &str| c.get(k).and_then(|x| x.as_str()).unwrap_or_default().to_string();
            // A run on one of several models is `ID/MODEL`, as its folder.
            let run = match c.get("model").and_then(|m| m.as_str()) {
                Some(m) => format!("{}/{m}", s("experiment")),
                None => s("experiment"),
            };
            ((run, s("name")), (s("status"), c.get("computed").and_then(|x| x.as_f64()).unwrap_or(f64::NAN)))
        })
        .collect())
}

/// The PNG figures of a report, by experiment folder (`ID`, and `ID/MODEL` for the runs of an
/// experiment on several models).
fn figures(dir: &Path) -> Result<BTreeMap<String, Vec<String>>> {
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        if !entry.path().is_dir() {
            continue;
        }
        let id = entry.file_name().to_string_lossy().into_owned();
        out.insert(id.clone(), pngs(&entry.path())?);
        for sub in std::fs::read_dir(entry.path()).map_err(|e| Error::io(entry.path(), e))? {
            let sub = sub.map_err(|e| Error::io(entry.path(), e))?;
            let name = sub.file_name().to_string_lossy().into_owned();
            if sub.path().is_dir() && name != "data" {
                out.insert(format!("{id}/{name}"), pngs(&sub.path())?);
            }
        }
    }
    Ok(out)
}

/// The figures directly in `dir`, sorted: PNG files, and SVG files of figures written only
/// as SVG (a report writes each figure in the smaller format unless asked for both).
fn pngs(dir: &Path) -> Result<Vec<String>> {
    let names: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    let mut pngs: Vec<String> = names
        .iter()
        .filter(|n| {
            n.ends_with(".png")
                || n.strip_suffix(".svg").is_some_and(|stem| !names.iter().any(|m| *m == format!("{stem}.png")))
        })
        .cloned()
        .collect();
    pngs.sort();
    Ok(pngs)
}

fn copy(from: &Path, to: &Path) -> Result<()> {
    if let Some(p) = to.parent() {
        std::fs::create_dir_all(p).map_err(|e| Error::io(p, e))?;
    }
    std::fs::copy(from, to).map(|_| ()).map_err(|e| Error::io(from, e))
}

/// Builds the comparison of reports `a` and `b` in `out`.
pub fn write(a: &Path, b: &Path, out: &Path) -> Result<PathBuf> {
    for d in [a, b] {
        if !d.join("index.html").is_file() {
            return Err(Error::invalid(
                d,
                "(report folder)",
                d.display(),
                "not a shotdamp report: it has no index.html",
            ));
        }
    }
    let (ca, cb) = (checks(a)?, checks(b)?);
    let (fa, fb) = (figures(a)?, figures(b)?);
    let stage = super::destination::Staging::create(out)?;
    let staging = stage.dir().to_path_buf();
    let mut pairs = Vec::new();
    let ids: std::collections::BTreeSet<&String> = fa.keys().chain(fb.keys()).collect();
    for id in ids {
        let mut names: Vec<&String> =
            fa.get(id).into_iter().flatten().chain(fb.get(id).into_iter().flatten()).collect();
        names.sort();
        names.dedup();
        for name in names {
            let mut pair =
                FigurePair { experiment: id.clone(), name: name.clone(), a: String::new(), b: String::new() };
            for (side, root, list, slot) in [("a", a, &fa, &mut pair.a), ("b", b, &fb, &mut pair.b)] {
                if list.get(id).is_some_and(|l| l.contains(name)) {
                    let rel = format!("{side}/{id}/{name}");
                    copy(&root.join(id).join(name), &staging.join(&rel))?;
                    *slot = rel;
                }
            }
            pairs.push(pair);
        }
    }
    let experiments = |c: &Checks| c.keys().map(|k| k.0.clone()).collect::<std::collections::BTreeSet<String>>();
    let (ea, eb) = (experiments(&ca), experiments(&cb));
    let only_a: Vec<String> = ea.difference(&eb).cloned().collect();
    let only_b: Vec<String> = eb.difference(&ea).cloned().collect();
    let keys: std::collections::BTreeSet<&(String, String)> =
        ca.keys().chain(cb.keys()).filter(|k| ea.contains(&k.0) && eb.contains(&k.0)).collect();
    let mut changes = Vec::new();
    let mut unchanged = 0;
    for k in keys {
        let (x, y) = (ca.get(k), cb.get(k));
        let change = match (x, y) {
            (Some(x), Some(y)) if x.0 != y.0 => "status changed".to_string(),
            (Some(x), Some(y)) => {
                let same = (x.1.is_nan() && y.1.is_nan()) || (x.1 - y.1).abs() <= 1e-12 * x.1.abs().max(y.1.abs());
                if same {
                    unchanged += 1;
                    continue;
                }
                format!("value moved by {:.2e} relative", (y.1 - x.1).abs() / x.1.abs().max(f64::MIN_POSITIVE))
            }
            (Some(_), None) => "only in A".into(),
            (None, Some(_)) => "only in B".into(),
            (None, None) => continue,
        };
        let v = |c: Option<&(String, f64)>| c.map(|c| (c.0.clone(), fmt_num(c.1))).unwrap_or_default();
        let ((sa, va), (sb, vb)) = (v(x), v(y));
        changes.push(CheckChange {
            experiment: k.0.clone(),
            name: k.1.clone(),
            status_a: sa,
            status_b: sb,
            computed_a: va,
            computed_b: vb,
            change,
        });
    }
    let view = CompareView {
        a: a.display().to_string(),
        b: b.display().to_string(),
        figures: pairs,
        changes,
        unchanged,
        only_a,
        only_b,
    };
    let tera = super::report::templates(None)?;
    let html = super::report::render(&tera, "compare.html", &view)?;
    std::fs::write(staging.join("index.html"), html).map_err(|e| Error::io(&staging, e))?;
    std::fs::write(staging.join("style.css"), super::report::STYLE_CSS).map_err(|e| Error::io(&staging, e))?;
    Ok(stage.commit()?.join("index.html"))
}
