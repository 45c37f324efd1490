//! The "Robustness" section of a figure's page: each study of its experiment, with where
//! every claim holds on each model, the heat maps and the long table.

use std::path::Path;

use serde::Serialize;

use crate::analysis::study::{rows_table, summarise, summary_table};
use crate::error::Result;
use crate::number::fmt_num;
use crate::output::study_words::{claim_sentences, deviation_sentences};
use crate::table;

use super::heatmap;
use super::manifest::StudyRun;

/// One study on a figure's page.
#[derive(Debug, Serialize)]
pub struct RobustnessView {
    /// The study's id.
    pub id: String,
    /// Its title.
    pub title: String,
    /// What it varies and why.
    pub description: String,
    /// The study file.
    pub file: String,
    /// "27 samples, 3 claims each".
    pub size: String,
    /// One sentence per claim.
    pub claims: Vec<String>,
    /// "robustness" or "bed" (the page's section).
    pub section: String,
    /// A bed study: per claim, how far the bed models move it from the paper's bed.
    pub deviations: Vec<String>,
    /// Per model: the experiment's own values of the varied keys, e.g. "stated chain: damping
    /// 0.01, clearance_mm 0.3" (empty when not known).
    pub assumed: Vec<String>,
    /// (title, PNG, SVG), relative to the page.
    pub maps: Vec<(String, String, String)>,
    /// Links to the long table (CSV, Parquet) and the summary (CSV).
    pub tables: Vec<(String, String)>,
}

/// Writes a study's heat maps (into `dir/robustness/`) and tables (into `dir/data/`; both
/// folders exist) and returns its view. `write` writes a file of the report.
pub fn write(dir: &Path, run: &StudyRun, write: &dyn Fn(&Path, &[u8]) -> Result<()>) -> Result<RobustnessView> {
    let m = &run.manifest;
    let maps_dir = dir.join("robustness");
    let mut maps = Vec::new();
    for map in heatmap::maps(m, &run.rows, &run.assumed) {
        heatmap::write(&map, &maps_dir)?;
        maps.push((map.title.clone(), format!("robustness/{}.png", map.id), format!("robustness/{}.svg", map.id)));
    }
    let models: Vec<String> = m.models.iter().map(|x| x.0.clone()).collect();
    let names: Vec<String> = m.vary.iter().map(|a| a.name.clone()).collect();
    let summaries = summarise(&models, &run.rows);
    let long = rows_table(&m.study, &names, &run.rows);
    let summary = summary_table(&m.study, &names, &summaries);
    let data = dir.join("data");
    write(&data.join(format!("{}.csv", long.name)), &table::to_csv(&long)?)?;
    write(&data.join(format!("{}.parquet", long.name)), &table::to_parquet(&long)?)?;
    write(&data.join(format!("{}.csv", summary.name)), &table::to_csv(&summary)?)?;
    let n_claims = run.rows.iter().map(|r| r.check + 1).max().unwrap_or(0);
    Ok(RobustnessView {
        id: m.study.clone(),
        title: m.title.clone(),
        description: run.description.clone(),
        file: m.file.clone(),
        size: format!("{} samples, {n_claims} claims each", m.samples),
        claims: claim_sentences(&m.models, &names, &summaries),
        section: match m.section {
            crate::experiment::study::Section::Robustness => "robustness".into(),
            crate::experiment::study::Section::Bed => "bed".into(),
        },
        deviations: match m.section {
            crate::experiment::study::Section::Robustness => Vec::new(),
            crate::experiment::study::Section::Bed => deviation_sentences(&m.models, &names, &run.rows),
        },
        assumed: m
            .models
            .iter()
            .zip(&run.assumed)
            .map(|((_, label), own)| {
                let values: Vec<String> = names
                    .iter()
                    .zip(own)
                    .map(|(n, v)| {
                        format!("{n} {}", v.map_or_else(|| "(differs between elements)".to_string(), fmt_num))
                    })
                    .collect();
                format!("{label}: {}", values.join(", "))
            })
            .collect(),
        maps,
        tables: vec![
            (format!("{}.csv", long.name), format!("data/{}.csv", long.name)),
            (format!("{}.parquet", long.name), format!("data/{}.parquet", long.name)),
            (format!("{}.csv", summary.name), format!("data/{}.csv", summary.name)),
        ],
    })
}
