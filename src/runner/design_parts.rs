//! Sharded design searches (docs/design.md, "Sharded searches"): `shotdamp design FILE
//! --shard I/N --parts DIR` searches the items shard `I` of `N` owns (item `k` of the
//! placements of every search, numbered search by search, belongs to shard `k mod N`) and writes
//! them as `DIR/design-part-I-of-N.json`; `shotdamp design FILE --merge DIR` gathers every part
//! and writes the report the unsharded search writes, byte for byte.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::analysis::design_shards::{self, Share};
use crate::design::search::Searched;
use crate::error::{Error, Result};
use crate::experiment::{self, Experiment};

/// The format of a part file, written into it.
const FORMAT: &str = "shotdamp design search part, version 1";

/// One shard's part: every design of the files searched for the items it owns.
#[derive(Debug, Serialize, Deserialize)]
struct Part {
    format: String,
    shard: usize,
    shards: usize,
    designs: Vec<PartDesign>,
}

/// One design (one model of a design file) in a part.
#[derive(Debug, Serialize, Deserialize)]
struct PartDesign {
    experiment: String,
    fingerprint: String,
    /// Per search, per placement: the item's end where this shard owns it.
    searches: Vec<Vec<Option<PartItem>>>,
}

/// One item's end; the coordinates as the bits of each number (hexadecimal), exact.
#[derive(Debug, Serialize, Deserialize)]
struct PartItem {
    x: Vec<String>,
    starts: usize,
    evaluations: u64,
    /// Whether the placement's search converged ("yes", or why not); absent in parts written
    /// before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    converged: Option<String>,
}

/// Which shard of how many.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DesignShard {
    /// 0-based index.
    pub index: usize,
    /// The number of shards.
    pub count: usize,
}

impl DesignShard {
    /// Whether this shard searches item `k`.
    pub fn owns(&self, k: usize) -> bool {
        k % self.count == self.index
    }
}

/// The part file of shard `shard` in `dir`.
pub fn part_path(dir: &Path, shard: DesignShard) -> PathBuf {
    dir.join(format!("design-part-{}-of-{}.json", shard.index, shard.count))
}

/// The design experiments of `files` (each model of each file), refusing any other kind.
fn designs(files: &[PathBuf], reference: &Path) -> Result<Vec<Experiment>> {
    let exps = experiment::loader::load_all(files, reference)?;
    if let Some(e) = exps.iter().find(|e| e.analysis.design().is_none()) {
        return Err(Error::invalid(
            &e.path,
            "analysis.kind",
            format!("\"{}\"", e.analysis.kind()),
            "`shotdamp design` runs design files (kind = \"design\"); run other experiments with `shotdamp run`",
        ));
    }
    Ok(exps)
}

/// Items of every design of `files` and how many of them `shard` owns.
pub fn items(files: &[PathBuf], reference: &Path, shard: DesignShard) -> Result<(usize, usize)> {
    let exps = designs(files, reference)?;
    let total: usize =
        exps.iter().map(|e| e.analysis.design().map_or(0, |(spec, _)| design_shards::items(e, spec))).sum();
    let mine = exps
        .iter()
        .map(|e| {
            e.analysis
                .design()
                .map_or(0, |(spec, _)| (0..design_shards::items(e, spec)).filter(|&k| shard.owns(k)).count())
        })
        .sum();
    Ok((total, mine))
}

/// Searches shard `shard`'s items of every design of `files` on `threads` threads (calling
/// `tick` at every layout evaluation) and writes its part into `dir` (created; written
/// atomically); the part's path.
pub fn search_shard(
    files: &[PathBuf],
    reference: &Path,
    dir: &Path,
    shard: DesignShard,
    jobs: Option<usize>,
    tick: &(dyn Fn() + Sync),
) -> Result<PathBuf> {
    let exps = designs(files, reference)?;
    let pool = super::pool(jobs)?;
    let mut designs = Vec::new();
    for e in &exps {
        let Some((spec, steady)) = e.analysis.design() else { continue };
        let share: Share = pool.install(|| design_shards::share(e, spec, steady, &|k| shard.owns(k), tick));
        designs.push(PartDesign {
            experiment: e.key(),
            fingerprint: share.fingerprint,
            searches: share
                .searches
                .into_iter()
                .map(|s| {
                    s.into_iter()
                        .map(|item| {
                            item.map(|i| PartItem {
                                x: i.x.iter().map(|v| format!("{:016x}", v.to_bits())).collect(),
                                starts: i.starts,
                                evaluations: i.evaluations,
                                converged: i.ended.map(|e| e.word().to_string()),
                            })
                        })
                        .collect()
                })
                .collect(),
        });
    }
    let part = Part { format: FORMAT.into(), shard: shard.index, shards: shard.count, designs };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let path = part_path(dir, shard);
    let text = serde_json::to_string_pretty(&part)
        .map_err(|e| Error::invalid(&path, "(part)", "(not written)", format!("cannot encode: {e}")))?;
    crate::output::files::write_atomic(&path, text.as_bytes())?;
    Ok(path)
}

/// Reads every part of `dir` and hands each design of `exps` what its searches ended with
/// (`Spec::merged`): refused unless the parts are every shard of one split, of these very
/// designs (their fingerprints), each item searched by exactly one of them.
pub fn merge_into(exps: &mut [Experiment], dir: &Path) -> Result<()> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: String| Error::invalid(dir, key, value, msg);
    let parts = read_parts(dir)?;
    for e in exps.iter_mut() {
        let key = e.key();
        let Some((spec, steady)) = e.analysis.design() else { continue };
        let fingerprint = crate::design::stored::fingerprint(&crate::analysis::design::problem(e, spec, steady), spec);
        let spaces = design_shards::spaces(e, spec);
        let mut merged: Vec<Vec<Option<Searched>>> = spaces.iter().map(|s| vec![None; s.placements.len()]).collect();
        for (path, p) in &parts {
            let Some(d) = p.designs.iter().find(|d| d.experiment == key) else {
                return Err(Error::invalid(
                    path,
                    "designs",
                    &key,
                    "this part has no search of this design".to_string(),
                ));
            };
            if d.fingerprint != fingerprint {
                return Err(Error::invalid(
                    path,
                    "fingerprint",
                    &key,
                    "this part searched another version of the design (its file, structure or settings changed since): search the shards again",
                ));
            }
            let shape_ok =
                d.searches.len() == merged.len() && d.searches.iter().zip(&merged).all(|(a, b)| a.len() == b.len());
            if !shape_ok {
                return Err(Error::invalid(
                    path,
                    "searches",
                    &key,
                    "not this design's searches and placements".to_string(),
                ));
            }
            for (k, (got, into)) in d.searches.iter().zip(merged.iter_mut()).enumerate() {
                for (placement, (item, slot)) in got.iter().zip(into.iter_mut()).enumerate() {
                    let Some(item) = item else { continue };
                    if slot.is_some() {
                        return Err(Error::invalid(
                            path,
                            "searches",
                            format!("search {k}, placement {placement}"),
                            "searched by two parts",
                        ));
                    }
                    let x = item
                        .x
                        .iter()
                        .map(|h| u64::from_str_radix(h, 16).map(f64::from_bits))
                        .collect::<std::result::Result<Vec<f64>, _>>()
                        .map_err(|err| {
                            Error::invalid(
                                path,
                                "x",
                                format!("{:?}", item.x),
                                format!("not the bits of numbers: {err}"),
                            )
                        })?;
                    let ended = match &item.converged {
                        None => None,
                        Some(w) => Some(crate::design::search::Ended::from_word(w).ok_or_else(|| {
                            Error::invalid(path, "converged", w, "\"yes\", \"no: iterations spent\" or \"no: stopped\"")
                        })?),
                    };
                    *slot = Some(Searched {
                        x,
                        starts: item.starts,
                        evaluations: item.evaluations,
                        ended,
                        evaluation: None,
                    });
                }
            }
        }
        let complete: Option<Vec<Vec<Searched>>> =
            merged.into_iter().map(|s| s.into_iter().collect::<Option<Vec<Searched>>>()).collect();
        let Some(complete) = complete else {
            return Err(bad("searches", &key, "some placements were searched by no part".to_string()));
        };
        if let Some(spec) = e.analysis.design_mut() {
            spec.merged = Some(std::sync::Arc::new(complete));
        }
    }
    Ok(())
}

/// Every part in `dir` (`design-part-I-of-N.json`), in shard order: each of one split, each
/// shard exactly once.
fn read_parts(dir: &Path) -> Result<Vec<(PathBuf, Part)>> {
    let bad = |key: &str, value: &dyn std::fmt::Display, msg: String| Error::invalid(dir, key, value, msg);
    let mut parts = Vec::new();
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    for entry in entries {
        let path = entry.map_err(|e| Error::io(dir, e))?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        if !(name.starts_with("design-part-") && name.ends_with(".json")) {
            continue;
        }
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let part: Part = serde_json::from_str(&text)
            .map_err(|e| Error::invalid(&path, "(part)", "(unreadable)", format!("not a design search part: {e}")))?;
        if part.format != FORMAT {
            return Err(Error::invalid(&path, "format", &part.format, format!("\"{FORMAT}\"")));
        }
        parts.push((path, part));
    }
    let Some(count) = parts.first().map(|(_, p)| p.shards) else {
        return Err(bad(
            "design-part-I-of-N.json",
            &"(none)",
            "no part in this folder: run `shotdamp design FILE --shard I/N --parts DIR` for every I first".into(),
        ));
    };
    for (path, p) in &parts {
        if p.shards != count || p.shard >= count {
            return Err(Error::invalid(
                path,
                "shard",
                format!("{}/{}", p.shard, p.shards),
                format!("the folder holds parts of a split into {count}: give every shard's part of one split"),
            ));
        }
    }
    parts.sort_by_key(|(_, p)| p.shard);
    for i in 0..count {
        match parts.iter().filter(|(_, p)| p.shard == i).count() {
            1 => {}
            0 => {
                return Err(bad(
                    "shard",
                    &format!("{i}/{count}"),
                    format!("its part is missing: run `shotdamp design FILE --shard {i}/{count} --parts DIR`"),
                ))
            }
            _ => return Err(bad("shard", &format!("{i}/{count}"), "its part is there twice".to_string())),
        }
    }
    Ok(parts)
}
