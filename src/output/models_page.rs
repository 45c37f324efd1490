//! The page of one experiment run on several models: the verdict on each, the checks side by
//! side, which conclusions depend on the model, and the figures overlaid or side by side.

use serde::Serialize;

use crate::analysis::ExperimentResult;
use crate::checks::fmt_num;
use crate::checks::verdict::verdict;
use crate::figure::Figure;

use super::view::{counts, dependence, status_class, FigureView};

/// One model's column.
#[derive(Debug, Serialize)]
pub struct ModelColumn {
    /// The model's id.
    pub id: String,
    /// Its label.
    pub label: String,
    /// What the model is.
    pub description: String,
    /// Link to the model's page.
    pub link: String,
    /// Against the paper only (as in the index).
    pub verdict: String,
    /// CSS class of the verdict.
    pub verdict_class: String,
    /// Every check, in words.
    pub counts: String,
    /// The main deviation on this model, in words.
    pub deviation: String,
}

/// One check across the models: (CSS class, text) per model, empty where it does not run.
#[derive(Debug, Serialize)]
pub struct MatrixRow {
    /// The check's name.
    pub name: String,
    /// What it compares.
    pub description: String,
    /// Where the expected value comes from.
    pub source: String,
    /// (CSS class, text) per model.
    pub cells: Vec<(String, String)>,
}

/// One figure of every model in a row.
#[derive(Debug, Serialize)]
pub struct SideBySide {
    /// The figure's title.
    pub title: String,
    /// (model label, PNG, SVG), links relative to the experiment's folder.
    pub cells: Vec<(String, String, String)>,
}

/// The context of `models.html`.
#[derive(Debug, Serialize)]
pub struct ModelsView {
    /// The experiment's id.
    pub id: String,
    /// Its title.
    pub title: String,
    /// The paper figure.
    pub figure: String,
    /// The caption (the paper's, or the experiment's own: [`crate::experiment::Meta::headings`]).
    pub caption: String,
    /// The claim tested (or the experiment's own question).
    pub claim: String,
    /// The headings of the caption and the claim.
    pub caption_heading: String,
    /// See `caption_heading`.
    pub claim_heading: String,
    /// The experiment file.
    pub source_file: String,
    /// One column per model.
    pub models: Vec<ModelColumn>,
    /// Figures that overlay the models.
    pub overlays: Vec<FigureView>,
    /// Each figure of the models side by side.
    pub side_by_side: Vec<SideBySide>,
    /// Every check across the models.
    pub matrix: Vec<MatrixRow>,
    /// Conclusions (checks against the paper) whose outcome differs between models.
    pub dependence: Vec<String>,
    /// The studies of this experiment: where its claims hold over unstated values.
    pub robustness: Vec<super::robustness::RobustnessView>,
    /// The studies of "Does the bed model matter?".
    pub bed: Vec<super::robustness::RobustnessView>,
}

/// Builds the page of `runs` (one experiment, one run per model) with the overlaid figures.
pub fn models_view(runs: &[&ExperimentResult], overlays: &[Figure]) -> ModelsView {
    let first = &runs[0].experiment;
    let models: Vec<ModelColumn> = runs
        .iter()
        .map(|r| {
            let m = r.experiment.model.clone().unwrap_or_else(|| crate::experiment::ModelInfo {
                id: String::new(),
                label: String::new(),
                description: String::new(),
            });
            let v = verdict(r.checks.iter());
            let (_, _, words) = counts(&r.checks);
            ModelColumn {
                link: format!("{}/index.html", m.id),
                id: m.id,
                label: m.label,
                description: m.description,
                verdict: v.label().to_string(),
                verdict_class: v.class().to_string(),
                counts: words,
                deviation: r.experiment.meta.deviation.clone().unwrap_or_default(),
            }
        })
        .collect();
    let mut names: Vec<(String, String, String)> = Vec::new();
    for r in runs {
        for c in &r.checks {
            if !names.iter().any(|(n, _, _)| *n == c.name) {
                names.push((c.name.clone(), c.description.clone(), c.source.label().to_string()));
            }
        }
    }
    let matrix = names
        .into_iter()
        .map(|(name, description, source)| MatrixRow {
            cells: runs
                .iter()
                .map(|r| match r.checks.iter().find(|c| c.name == name) {
                    Some(c) => (
                        status_class(c.status).to_string(),
                        format!("{}: {} {}", c.status.label(), fmt_num(c.computed), c.unit),
                    ),
                    None => (String::new(), "not run on this model".to_string()),
                })
                .collect(),
            name,
            description,
            source,
        })
        .collect();
    let side_by_side = runs[0]
        .figures
        .iter()
        .map(|f| SideBySide {
            title: f.title.clone(),
            cells: runs
                .iter()
                .filter(|r| r.figures.iter().any(|g| g.id == f.id))
                .filter_map(|r| {
                    let m = r.experiment.model.as_ref()?;
                    Some((m.label.clone(), format!("{}/{}.png", m.id, f.id), format!("{}/{}.svg", m.id, f.id)))
                })
                .collect(),
        })
        .collect();
    ModelsView {
        id: first.meta.id.clone(),
        title: first.meta.title.clone(),
        figure: first.meta.figure.clone(),
        caption: first.meta.caption.clone(),
        claim: first.meta.claim.clone(),
        caption_heading: first.meta.headings(first.analysis.answers()).0.to_string(),
        claim_heading: first.meta.headings(first.analysis.answers()).1.to_string(),
        source_file: first.path.display().to_string(),
        models,
        overlays: overlays
            .iter()
            .map(|f| FigureView {
                title: f.title.clone(),
                caption: f.caption.clone(),
                png: format!("{}.png", f.id),
                svg: format!("{}.svg", f.id),
            })
            .collect(),
        side_by_side,
        matrix,
        dependence: dependence(runs),
        robustness: Vec::new(),
        bed: Vec::new(),
    }
}
