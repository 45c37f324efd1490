//! docs/extending.md lists, for each kind of addition, the files it touches and the names in
//! them: every file it names exists, and every name it puts beside files is in one of them.

use std::collections::BTreeSet;
use std::path::Path;

use crate::common::repo;

/// The text between backticks of `s`.
fn quoted(s: &str) -> Vec<String> {
    s.split('`').skip(1).step_by(2).map(str::to_string).collect()
}

/// A quoted path of the project (a source file or folder, a test, a doc).
fn is_path(q: &str) -> bool {
    ["src/", "tests/", "docs/", "python/", "benches/", "examples/"].iter().any(|p| q.starts_with(p))
}

/// The identifiers a quoted text names: `Kind::run`, `kind_of`, `runs_columns`,
/// `bounces(rel)` give their last path segment without arguments; paths, keys in quotes and
/// prose are not names.
fn name_of(q: &str) -> Option<String> {
    let head = q.split('(').next().unwrap_or(q);
    let last = head.rsplit("::").next().unwrap_or(head);
    let ok = !last.is_empty()
        && last.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && last.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    // A lower-case word of one letter or a TOML table (`[design]`) is not a code name.
    (ok && last.len() > 1 && !is_path(q)).then(|| last.to_string())
}

/// The list items and paragraphs of the page: one block each.
fn blocks(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    for line in text.lines() {
        let starts_item = line.trim_start().chars().next().is_some_and(|c| c.is_ascii_digit())
            && line.trim_start().split_once(". ").is_some_and(|(n, _)| n.chars().all(|c| c.is_ascii_digit()));
        if line.trim().is_empty() || line.starts_with('#') || starts_item {
            if !cur.trim().is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            cur.clear();
        }
        if !line.starts_with('#') {
            cur.push_str(line);
            cur.push('\n');
        }
    }
    if !cur.trim().is_empty() {
        out.push(cur);
    }
    out
}

#[test]
fn every_file_the_extension_guide_lists_exists_and_holds_the_names_it_gives() {
    let root = repo();
    let text = std::fs::read_to_string(root.join("docs/extending.md")).unwrap();
    let mut missing_files = BTreeSet::new();
    let mut missing_names = Vec::new();
    let mut named = 0;
    for block in blocks(&text) {
        let quotes = quoted(&block);
        // `src/cli/NAME.rs`: a placeholder for the new file, not a file.
        let files: Vec<&String> = quotes.iter().filter(|q| is_path(q) && !q.contains("NAME")).collect();
        let mut sources = String::new();
        for f in &files {
            // `src/analysis/checks/` (a folder) or `src/x.rs::function`.
            let path = f.split("::").next().unwrap_or(f).trim_end_matches('/');
            let p = root.join(path);
            if !p.exists() {
                missing_files.insert(path.to_string());
            } else if p.is_file() {
                sources.push_str(&std::fs::read_to_string(&p).unwrap_or_default());
            } else {
                for e in std::fs::read_dir(&p).unwrap().flatten() {
                    if e.path().extension().is_some_and(|x| x == "rs") {
                        sources.push_str(&std::fs::read_to_string(e.path()).unwrap_or_default());
                    }
                }
            }
        }
        if sources.is_empty() {
            continue;
        }
        for q in &quotes {
            // `src/x.rs::name` names a function of that file.
            let q = match q.split_once(".rs::") {
                Some((_, name)) => name,
                None => q.as_str(),
            };
            if let Some(name) = name_of(q) {
                named += 1;
                if !sources.contains(&name) {
                    missing_names.push(format!("{name} (in {:?})", files));
                }
            }
        }
    }
    assert!(missing_files.is_empty(), "docs/extending.md names files that do not exist: {missing_files:?}");
    assert!(missing_names.is_empty(), "docs/extending.md names what its files do not hold: {missing_names:#?}");
    assert!(named > 40, "only {named} names checked: the page's shape changed");
    assert!(Path::new(&root.join("docs/extending.md")).exists());
}
