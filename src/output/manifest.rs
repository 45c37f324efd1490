//! What a study folder is: its manifest (`study.json`, which every shard checks it matches:
//! the study, its samples, its fingerprint), a shard of it, and a study's run as the report
//! shows it.

use serde::{Deserialize, Serialize};

use crate::analysis::study::ClaimRow;
use crate::experiment::study::{Design, Study};

/// A shard: `index` of `count` (0-based); sample `i` belongs to shard `i % count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// 0-based index of the shard.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The whole study in one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Whether sample `i` is this shard's.
    pub fn owns(self, i: usize) -> bool {
        i % self.count == self.index
    }

    /// The name of the shard's complete part: it carries the study's fingerprint, so that a
    /// part of another version of the study is never merged.
    pub(super) fn part_name(self, fingerprint: &str) -> String {
        format!("part-{:04}-of-{:04}-{fingerprint}.parquet", self.index, self.count)
    }

    pub(super) fn batch_dir(self, fingerprint: &str) -> String {
        format!("shard-{:04}-of-{:04}-{fingerprint}", self.index, self.count)
    }

    pub(super) fn lock_name(self) -> String {
        format!("shard-{:04}-of-{:04}.lock", self.index, self.count)
    }

    /// How many of a study's `samples` belong to this shard.
    pub fn size(self, samples: usize) -> usize {
        (0..samples).filter(|&i| self.owns(i)).count()
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// A study run whole (as `shotdamp report` runs it): what it is and its rows, in sample order.
#[derive(Debug, Clone)]
pub struct StudyRun {
    /// What the study folder holds.
    pub manifest: Manifest,
    /// What the study varies and why.
    pub description: String,
    /// A row per sample and claim.
    pub rows: Vec<ClaimRow>,
    /// Per model of the manifest: the experiment's own value of each varied key, as the report
    /// ran it (`None`: no single value; empty: not known, as in `shotdamp study`).
    pub assumed: Vec<Vec<Option<f64>>>,
    /// A study marked `stored = true`: its stored answer, whose best sample per model `rows`
    /// ran again; `fresh` says whether the answer is of this version of the study.
    pub stored: Option<StoredRun>,
}

/// The stored answer of a study the report ran again.
#[derive(Debug, Clone)]
pub struct StoredRun {
    /// The answer as stored.
    pub answer: crate::experiment::study::stored::StoredStudy,
    /// Whether it was computed by this version of the study (the same fingerprint).
    pub fresh: bool,
}

/// A varied key as the merged outputs need it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// The varied key's name.
    pub name: String,
    /// Axis label, with its unit.
    pub label: String,
    /// Logarithmic axis.
    pub log: bool,
}

/// What a study folder holds: written by the first shard, checked by every other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The study's id.
    pub study: String,
    /// Its title.
    pub title: String,
    /// The study file, as given on the command line.
    pub file: String,
    /// The experiment whose claims are studied.
    pub experiment: String,
    /// The paper figure.
    pub figure: String,
    /// Changes whenever the samples or what is set in them change.
    pub fingerprint: String,
    /// Number of samples.
    pub samples: usize,
    /// Columns of the long table, in order.
    pub columns: Vec<String>,
    /// The varied keys.
    pub vary: Vec<Axis>,
    /// Indices into `vary` of the heat maps' axes.
    pub map: Option<(usize, usize)>,
    /// Model ids and labels, in order.
    pub models: Vec<(String, String)>,
    /// Whether the samples form a full grid (heat maps of cells; otherwise scatter maps).
    pub grid: bool,
    /// The number of shards the folder is computed as, recorded by its first shard (0: not
    /// recorded, as for a study run by the report).
    #[serde(default)]
    pub shards: usize,
    /// An adaptive study's rounds, once its last has ended and they are merged (0 otherwise).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rounds: usize,
    /// A joint study's experiments (ids, in order; empty for a study of one experiment).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joint: Vec<String>,
    /// Where the report shows it.
    #[serde(default)]
    pub section: crate::experiment::study::Section,
}

impl Manifest {
    /// The manifest of `study`, read from `file`. Its fingerprint depends on what the study
    /// computes (its id, the experiment's content on every model, what it varies and sets,
    /// every sample's values), never on how the study's path is spelled.
    pub fn of(study: &Study, file: &str) -> Manifest {
        let mut text = format!("{}\n{}\n{}", study.id, study.base[0].meta.id, study.content());
        for v in &study.vary {
            text.push_str(&format!("vary {} {}\n", v.name, v.key.as_str()));
            if !v.experiments.is_empty() {
                text.push_str(&format!("vary {} in {}\n", v.name, v.experiments.join(" ")));
            }
        }
        for (k, v) in &study.set {
            text.push_str(&format!("set {} = {v}\n", k.as_str()));
        }
        if let Design::Adaptive { levels, refine } = study.design {
            // Its samples after round 0 follow from these and from the answers.
            text.push_str(&format!("adaptive {levels} {}\n", refine.name()));
        }
        for s in &study.samples {
            let bits: Vec<String> = s.values.iter().map(|x| format!("{:016x}", x.to_bits())).collect();
            text.push_str(&format!("{} {} {}\n", s.index, s.model, bits.join(" ")));
        }
        Manifest {
            study: study.id.clone(),
            title: study.title.clone(),
            file: file.to_string(),
            experiment: study.base[0].meta.id.clone(),
            // A joint study's claims come from several figures: all of them, in order.
            figure: study.parts().map(|p| p.base[0].meta.figure.clone()).collect::<Vec<_>>().join(", "),
            fingerprint: fingerprint(&text),
            samples: study.samples.len(),
            columns: crate::analysis::study::columns(study),
            vary: study
                .vary
                .iter()
                .map(|v| Axis { name: v.name.clone(), label: v.label.clone(), log: v.log() })
                .collect(),
            map: study.map,
            models: study
                .base
                .iter()
                .map(|e| e.model.as_ref().map(|m| (m.id.clone(), m.label.clone())).unwrap_or_default())
                .collect(),
            grid: study.design == Design::Grid,
            shards: 0,
            rounds: 0,
            joint: if study.joint.is_empty() {
                Vec::new()
            } else {
                study.parts().map(|p| p.base[0].meta.id.clone()).collect()
            },
            section: study.section,
        }
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// FNV-1a, 64 bits: a fingerprint that is the same on every machine and version.
pub fn fingerprint(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}
