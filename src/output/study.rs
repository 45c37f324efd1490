//! A study's folder: its manifest, the Parquet part of each shard (written in atomic batches
//! so that a stopped shard resumes), and the merged table, summary and heat maps.
//!
//! ```text
//! DIR/study.json                        what the study is (every shard checks it matches)
//! DIR/parts/part-0002-of-0007.parquet   shard 2 of 7, complete
//! DIR/parts/shard-0003-of-0007/*.parquet batches of a shard still running (or stopped)
//! DIR/ID.csv, DIR/ID.parquet            the merged long table, sorted by sample and check
//! DIR/ID_summary.csv                    per model and claim: where it holds
//! DIR/figures/ID_check-K.png, .svg      heat maps
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use polars::prelude::*;

use crate::analysis::study::{ClaimRow, Verdict};
use crate::error::{Error, Result};
use crate::table::{self, Table};

use super::files::{sync_dir, temporary, write_synced};
pub use super::files::{write_atomic, ShardLock};
use super::manifest::{Manifest, Shard};

const MANIFEST: &str = "study.json";

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |e| Error::io(path, e)
}

fn table_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Table { path: path.to_path_buf(), message: e.to_string() }
}

/// Whether an entry of a study folder can be there before its `study.json` is: the parts
/// folder, the temporary manifests of shards that set the folder up at this moment, and the
/// `logs` folder a cluster job writes its logs into.
fn part_of_setup(name: &str) -> bool {
    name == "parts" || name == "logs" || name.starts_with(&format!(".{MANIFEST}.tmp-"))
}

/// Makes `dir` the folder of this study computed as `shards` shards, safe when any number of
/// shards on any number of hosts start at once: the first to arrive creates `study.json` (an
/// exclusive create, through a hard link of a complete file), every other reads it and checks
/// that it is this study (the same fingerprint) computed as as many shards. A folder of other
/// files is refused. Returns the folder's manifest.
pub fn prepare(dir: &Path, manifest: &Manifest, shards: usize) -> Result<Manifest> {
    let path = dir.join(MANIFEST);
    if !path.is_file() && dir.exists() {
        if !dir.is_dir() {
            return Err(Error::Destination {
                path: dir.to_path_buf(),
                message: "is a file, not a folder: give --out a new or empty folder".into(),
            });
        }
        let foreign: Vec<String> = std::fs::read_dir(dir)
            .map_err(io(dir))?
            .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
            .filter(|n| !part_of_setup(n) && n != MANIFEST)
            .collect();
        if !foreign.is_empty() && !path.is_file() {
            return Err(Error::Destination {
                path: dir.to_path_buf(),
                message: format!(
                    "is not empty and holds no study (no study.json; it has {}): give --out a new or empty folder",
                    foreign.iter().take(3).cloned().collect::<Vec<_>>().join(", ")
                ),
            });
        }
    }
    std::fs::create_dir_all(dir.join("parts")).map_err(io(dir))?;
    let mine = Manifest { shards, ..manifest.clone() };
    if !path.is_file() {
        let text = serde_json::to_string_pretty(&mine).map_err(|e| table_err(&path, e))?;
        let tmp = temporary(&path);
        write_synced(&tmp, text.as_bytes())?;
        // Exclusive: fails when another shard's manifest is there first.
        let linked = std::fs::hard_link(&tmp, &path);
        let _ = std::fs::remove_file(&tmp);
        match linked {
            Ok(()) => {
                sync_dir(dir);
                return Ok(mine);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(_) => {
                // A file system without hard links: an exclusive create of the manifest
                // itself (a reader that finds it half-written reads it again).
                if let Ok(mut f) = std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
                    use std::io::Write as _;
                    f.write_all(text.as_bytes()).and_then(|()| f.sync_all()).map_err(io(&path))?;
                    return Ok(mine);
                }
            }
        }
    }
    let theirs = read_manifest(dir)?;
    if theirs.fingerprint != manifest.fingerprint || theirs.study != manifest.study {
        return Err(Error::Destination {
            path: dir.to_path_buf(),
            message: format!(
                "holds parts of another study or of another version of it (study \"{}\", fingerprint {}; this one \"{}\", {}): give --out a new folder",
                theirs.study, theirs.fingerprint, manifest.study, manifest.fingerprint
            ),
        });
    }
    if theirs.shards != 0 && theirs.shards != shards {
        return Err(Error::Destination {
            path: dir.to_path_buf(),
            message: format!(
                "is computed as {} shard{} (recorded in {MANIFEST} by its first shard), not {shards}: run this study with --shard I/{} (or --shards {}), or give --out a new folder",
                theirs.shards,
                if theirs.shards == 1 { "" } else { "s" },
                theirs.shards,
                theirs.shards
            ),
        });
    }
    Ok(theirs)
}

/// The manifest of a study folder.
pub fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join(MANIFEST);
    if !path.is_file() {
        return Err(Error::Destination {
            path: dir.to_path_buf(),
            message: "is not a study folder (no study.json): give the --out folder of `shotdamp study`".into(),
        });
    }
    // A manifest written without hard links may be read half-written: read it again then.
    let mut last = None;
    for _ in 0..50 {
        let text = crate::error::read_to_string(&path)?;
        match serde_json::from_str(&text) {
            Ok(m) => return Ok(m),
            Err(e) => last = Some(e),
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    Err(Error::Parse { file: path.display().to_string(), message: last.map(|e| e.to_string()).unwrap_or_default() })
}

/// The key under which a part or batch records the fingerprint of the study version that
/// computed it (Parquet key-value metadata): a file renamed to another version's name is
/// still known for what it is.
const FINGERPRINT_KEY: &str = "shotdamp.study.fingerprint";

/// A part or batch of the study of `manifest`: its rows, once the fingerprint recorded
/// inside it is found to be the folder's (a part of another version, whatever its name, is
/// refused with the command that removes it).
fn read_parquet(path: &Path, manifest: &Manifest) -> Result<DataFrame> {
    let file = std::fs::File::open(path).map_err(io(path))?;
    let mut reader = ParquetReader::new(file);
    let recorded = reader
        .get_metadata()
        .map_err(|e| damaged(path, &e.to_string()))?
        .key_value_metadata
        .as_ref()
        .and_then(|kv| kv.iter().find(|k| k.key == FINGERPRINT_KEY).and_then(|k| k.value.clone()));
    if recorded.as_deref() != Some(manifest.fingerprint.as_str()) {
        return Err(Error::Destination {
            path: path.to_path_buf(),
            message: format!(
                "was computed by {} of study \"{}\", not by the version of the folder's study.json (fingerprint {}), whatever its name says: remove it (`rm '{}'`) and run its shard again",
                match &recorded {
                    Some(f) => format!("another version (fingerprint {f})"),
                    None => "a version that recorded no fingerprint".to_string(),
                },
                manifest.study,
                manifest.fingerprint,
                path.display()
            ),
        });
    }
    reader.finish().map_err(|e| damaged(path, &e.to_string()))
}

/// `df` as Parquet bytes recording `manifest`'s fingerprint ([`FINGERPRINT_KEY`]).
fn to_parquet(df: &mut DataFrame, manifest: &Manifest, path: &Path) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    let kv = KeyValueMetadata::from_static(vec![(FINGERPRINT_KEY.to_string(), manifest.fingerprint.clone())]);
    ParquetWriter::new(&mut buf).with_key_value_metadata(Some(kv)).finish(df).map_err(|e| table_err(path, e))?;
    Ok(buf)
}

/// A part or batch that cannot be read, named with the command that removes it.
fn damaged(path: &Path, why: &str) -> Error {
    let size = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    Error::Table {
        path: path.to_path_buf(),
        message: format!(
            "is damaged ({size} bytes: {why}), probably written by a shard that was stopped or crashed: remove it with `rm '{}'` and run its shard again (its samples are computed again)",
            path.display()
        ),
    }
}

fn samples_of(df: &DataFrame, path: &Path) -> Result<Vec<usize>> {
    let col = df.column("sample").and_then(|c| c.i64().cloned()).map_err(|e| damaged(path, &e.to_string()))?;
    Ok(col.iter().map(|v| v.unwrap_or(-1).max(0) as usize).collect())
}

/// Takes the shard's lock (one writer per shard at a time): `Ok(Err(holder))` when another
/// live process holds it.
pub fn lock(dir: &Path, shard: Shard) -> Result<std::result::Result<ShardLock, super::files::Holder>> {
    ShardLock::try_take(&dir.join("parts").join(shard.lock_name()))
}

/// The samples of `shard` already written (a complete part or batches). A complete part must
/// hold exactly the samples its shard owns; one that does not is named as damaged.
pub fn done(dir: &Path, manifest: &Manifest, shard: Shard) -> Result<(bool, Vec<usize>)> {
    let part = dir.join("parts").join(shard.part_name(&manifest.fingerprint));
    if part.is_file() {
        let mut got = samples_of(&read_parquet(&part, manifest)?, &part)?;
        got.dedup();
        let owned: Vec<usize> = (0..manifest.samples).filter(|&i| shard.owns(i)).collect();
        if got != owned {
            return Err(damaged(
                &part,
                &format!("it holds {} samples of the {} of shard {shard}", got.len(), owned.len()),
            ));
        }
        return Ok((true, got));
    }
    let mut out = Vec::new();
    for p in batches(dir, manifest, shard)? {
        out.extend(samples_of(&read_parquet(&p, manifest)?, &p)?);
    }
    out.sort_unstable();
    out.dedup();
    Ok((false, out))
}

fn batches(dir: &Path, manifest: &Manifest, shard: Shard) -> Result<Vec<PathBuf>> {
    let folder = dir.join("parts").join(shard.batch_dir(&manifest.fingerprint));
    if !folder.is_dir() {
        return Ok(Vec::new());
    }
    let mut out: Vec<PathBuf> = std::fs::read_dir(&folder)
        .map_err(io(&folder))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "parquet") && !is_temporary(p))
        .collect();
    out.sort();
    Ok(out)
}

fn is_temporary(p: &Path) -> bool {
    p.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.'))
}

/// Writes one batch of a shard's rows (atomically).
pub fn write_batch(dir: &Path, manifest: &Manifest, shard: Shard, first_sample: usize, rows: &Table) -> Result<()> {
    let folder = dir.join("parts").join(shard.batch_dir(&manifest.fingerprint));
    std::fs::create_dir_all(&folder).map_err(io(&folder))?;
    let path = folder.join(format!("batch-{first_sample:08}.parquet"));
    let mut df = rows.to_frame().map_err(|e| table_err(&path, e))?;
    write_atomic(&path, &to_parquet(&mut df, manifest, &path)?)
}

/// Joins a shard's batches into its part (sorted by sample and check) and removes them; a
/// shard without samples writes `empty` (the table's columns, no rows). The part must hold
/// every sample of the shard.
pub fn finish_shard(dir: &Path, manifest: &Manifest, shard: Shard, empty: &Table) -> Result<PathBuf> {
    let part = dir.join("parts").join(shard.part_name(&manifest.fingerprint));
    let mut frames = Vec::new();
    for p in batches(dir, manifest, shard)? {
        frames.push(read_parquet(&p, manifest)?);
    }
    if frames.is_empty() {
        frames.push(empty.to_frame().map_err(|e| table_err(&part, e))?);
    }
    let mut df = stack(frames, &part)?;
    let mut got = samples_of(&df, &part)?;
    got.dedup();
    let owned = shard.size(manifest.samples);
    if got.len() != owned {
        return Err(table_err(
            &part,
            format!("shard {shard} has {} of its {owned} samples written: run it again to compute the rest", got.len()),
        ));
    }
    write_atomic(&part, &to_parquet(&mut df, manifest, &part)?)?;
    let folder = dir.join("parts").join(shard.batch_dir(&manifest.fingerprint));
    if folder.exists() {
        std::fs::remove_dir_all(&folder).map_err(io(&folder))?;
    }
    Ok(part)
}

/// Frames stacked and sorted by sample, then check.
fn stack(frames: Vec<DataFrame>, path: &Path) -> Result<DataFrame> {
    let mut it = frames.into_iter();
    let Some(mut df) = it.next() else {
        return Err(table_err(path, "no rows to write"));
    };
    for f in it {
        df.vstack_mut(&f).map_err(|e| table_err(path, e))?;
    }
    df.sort(["sample", "check"], SortMultipleOptions::default()).map_err(|e| table_err(path, e))
}

/// The merged table of a study folder, sorted by sample and check: every sample exactly once,
/// or an error that names the shards still missing.
pub fn merge(dir: &Path, manifest: &Manifest) -> Result<DataFrame> {
    let parts_dir = dir.join("parts");
    let mut parts: Vec<PathBuf> = std::fs::read_dir(&parts_dir)
        .map_err(io(&parts_dir))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "parquet") && !is_temporary(p))
        .collect();
    parts.sort();
    let mut owner: BTreeMap<usize, PathBuf> = BTreeMap::new();
    let mut counts: Vec<usize> = Vec::new();
    let mut frames = Vec::new();
    for p in &parts {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        // part-IIII-of-NNNN-FINGERPRINT.parquet
        let Some((n, print)) = name
            .strip_suffix(".parquet")
            .and_then(|s| s.rsplit_once("-of-"))
            .and_then(|(_, rest)| rest.split_once('-'))
            .and_then(|(n, f)| Some((n.parse::<usize>().ok()?, f.to_string())))
        else {
            return Err(Error::Destination {
                path: p.clone(),
                message: "is not a part of a study (parts are named part-I-of-N-FINGERPRINT.parquet): move it out of the parts folder".into(),
            });
        };
        if print != manifest.fingerprint {
            return Err(Error::Destination {
                path: dir.to_path_buf(),
                message: format!(
                    "holds parts of two versions of study \"{}\": {} has fingerprint {print}, the folder's study.json {}: remove the parts of the version you do not want (`rm {}/parts/*-{print}.parquet`), then run its shards again",
                    manifest.study,
                    p.display(),
                    manifest.fingerprint,
                    dir.display()
                ),
            });
        }
        if !counts.contains(&n) {
            counts.push(n);
        }
        let df = read_parquet(p, manifest)?;
        let names: Vec<String> = df.get_column_names().iter().map(|c| c.to_string()).collect();
        if names != manifest.columns {
            return Err(table_err(p, format!("columns {names:?}, expected {:?}", manifest.columns)));
        }
        for s in samples_of(&df, p)? {
            if s >= manifest.samples {
                return Err(table_err(p, format!("sample {s}: the study has {} samples", manifest.samples)));
            }
            if let Some(other) = owner.get(&s).filter(|o| *o != p) {
                return Err(Error::Destination {
                    path: dir.to_path_buf(),
                    message: format!(
                        "sample {s} is in two parts, {} and {}: parts of two different shardings are mixed; remove one set",
                        other.display(),
                        p.display()
                    ),
                });
            }
            owner.insert(s, p.clone());
        }
        frames.push(df);
    }
    let missing: Vec<usize> = (0..manifest.samples).filter(|s| !owner.contains_key(s)).collect();
    if !missing.is_empty() {
        let shards = match counts.as_slice() {
            [n] => {
                let mut idx: Vec<usize> = missing.iter().map(|s| s % n).collect();
                idx.sort_unstable();
                idx.dedup();
                let list: Vec<String> = idx.iter().map(|i| format!("{i}/{n}")).collect();
                format!(
                    "shards {} have not finished (run `shotdamp study {} --shard I/{n} --out {}` for each)",
                    list.join(", "),
                    manifest.file,
                    dir.display()
                )
            }
            [] => format!(
                "no shard has finished (run `shotdamp study {} --shard I/N --out {}`)",
                manifest.file,
                dir.display()
            ),
            _ => format!("parts of several shardings are mixed ({counts:?} shards)"),
        };
        let first: Vec<String> = missing.iter().take(10).map(|s| s.to_string()).collect();
        return Err(Error::Destination {
            path: dir.to_path_buf(),
            message: format!(
                "{} of {} samples are missing (samples {}{}): {shards}",
                missing.len(),
                manifest.samples,
                first.join(", "),
                if missing.len() > 10 { ", ..." } else { "" }
            ),
        });
    }
    stack(frames, &parts_dir)
}

/// Writes the merged table as CSV and Parquet (atomically each).
pub fn write_merged(dir: &Path, manifest: &Manifest, df: &mut DataFrame) -> Result<()> {
    let csv = dir.join(format!("{}.csv", manifest.study));
    let mut buf = Vec::new();
    CsvWriter::new(&mut buf).include_header(true).finish(df).map_err(|e| table_err(&csv, e))?;
    write_atomic(&csv, &buf)?;
    let pq = dir.join(format!("{}.parquet", manifest.study));
    let mut buf = Vec::new();
    ParquetWriter::new(&mut buf).finish(df).map_err(|e| table_err(&pq, e))?;
    write_atomic(&pq, &buf)
}

/// Writes a table as CSV beside the study (atomically).
pub fn write_table(dir: &Path, t: &Table) -> Result<()> {
    write_atomic(&dir.join(format!("{}.csv", t.name)), &table::to_csv(t)?)
}

/// The rows of a merged frame.
pub fn rows(df: &DataFrame, manifest: &Manifest, path: &Path) -> Result<Vec<ClaimRow>> {
    let e = |x: PolarsError| table_err(path, x);
    let int = |name: &str| -> Result<Vec<i64>> {
        Ok(df.column(name).and_then(|c| c.i64().cloned()).map_err(e)?.iter().map(|v| v.unwrap_or(0)).collect())
    };
    let float = |name: &str| -> Result<Vec<f64>> {
        Ok(df.column(name).and_then(|c| c.f64().cloned()).map_err(e)?.iter().map(|v| v.unwrap_or(f64::NAN)).collect())
    };
    let text = |name: &str| -> Result<Vec<String>> {
        Ok(df
            .column(name)
            .and_then(|c| c.str().cloned())
            .map_err(e)?
            .iter()
            .map(|v| v.unwrap_or("").to_string())
            .collect())
    };
    let (sample, model, check, claim, reading, value, settled, bound, outcome, reason) = (
        int("sample")?,
        text("model")?,
        int("check")?,
        text("claim")?,
        text("reading")?,
        float("value")?,
        int("settled")?,
        text("bound")?,
        text("outcome")?,
        text("reason")?,
    );
    let verdicts = outcome
        .iter()
        .map(|w| {
            Verdict::from_word(w).ok_or_else(|| {
                table_err(path, format!("outcome = \"{w}\": one of \"holds\", \"fails\", \"not evaluable\""))
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let values: Vec<Vec<f64>> = manifest.vary.iter().map(|a| float(&a.name)).collect::<Result<_>>()?;
    Ok((0..df.height())
        .map(|i| ClaimRow {
            sample: sample[i] as usize,
            model: model[i].clone(),
            values: values.iter().map(|v| v[i]).collect(),
            check: check[i] as usize,
            claim: claim[i].clone(),
            reading: reading[i].clone(),
            value: value[i],
            bound: bound[i].clone(),
            outcome: verdicts[i],
            reason: reason[i].clone(),
            settled: settled[i] != 0,
        })
        .collect())
}
