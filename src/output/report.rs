//! The HTML report: contexts of pre-formatted strings, filled into tera templates.
//! Templates only fill in, loop and branch; every number is formatted here.

use std::path::Path;

use serde::Serialize;
use tera::{Context, Tera};

use crate::analysis::ExperimentResult;
use crate::checks::{fmt_num, CheckOutcome};
use crate::error::{read_to_string, Error, Result};
use crate::experiment::ModelInfo;

pub use super::view::{counts, status_class, FigureView};

/// Template names and their embedded defaults.
const TEMPLATES: [(&str, &str); 5] = [
    ("base.html", include_str!("../../templates/base.html")),
    ("index.html", include_str!("../../templates/index.html")),
    ("experiment.html", include_str!("../../templates/experiment.html")),
    ("models.html", include_str!("../../templates/models.html")),
    ("compare.html", include_str!("../../templates/compare.html")),
];

/// The report's stylesheet.
pub const STYLE_CSS: &str = include_str!("../../templates/style.css");

/// Loads the templates: embedded defaults, each replaced by `dir/NAME` where it exists.
pub fn templates(dir: Option<&Path>) -> Result<Tera> {
    let mut tera = Tera::new();
    for (name, default) in TEMPLATES {
        let text = match dir.map(|d| d.join(name)).filter(|p| p.is_file()) {
            Some(p) => read_to_string(&p)?,
            None => default.to_string(),
        };
        tera.add_raw_template(name, &text)
            .map_err(|e| Error::Render { what: format!("template {name}"), message: e.to_string() })?;
    }
    Ok(tera)
}

/// One check, formatted.
#[derive(Debug, Serialize)]
pub struct CheckRow {
    /// The experiment's key.
    pub experiment: String,
    /// The check's name.
    pub name: String,
    /// What it compares.
    pub description: String,
    /// The value computed, formatted.
    pub computed: String,
    /// The reference value, formatted.
    pub expected: String,
    /// Their difference, formatted.
    pub difference: String,
    /// The tolerance, in words.
    pub tolerance: String,
    /// Pass, fail or a known deviation.
    pub status: String,
    /// CSS class of the status.
    pub status_class: String,
    /// Where the expected value comes from.
    pub provenance: String,
    /// The kind of reference.
    pub source: String,
    /// Why a known deviation is expected.
    pub reason: String,
    /// Extra detail (e.g. the worst point of a curve).
    pub detail: String,
    /// "settled", "unsettled" (the value rests on a point that did not settle, or would change
    /// with one that was skipped) or "" (the check reads no steady state).
    pub settled: String,
}

impl CheckRow {
    pub(super) fn new(experiment: &str, c: &CheckOutcome) -> CheckRow {
        CheckRow {
            experiment: experiment.to_string(),
            name: c.name.clone(),
            description: c.description.clone(),
            computed: format!("{} {}", fmt_num(c.computed), c.unit),
            expected: format!("{} {}", fmt_num(c.expected), c.unit),
            difference: if c.rel_diff.is_finite() {
                format!("{} ({:.3} %)", fmt_num(c.abs_diff), c.rel_diff * 100.0)
            } else {
                fmt_num(c.abs_diff)
            },
            tolerance: c.tolerance.clone(),
            status: c.status.label().to_string(),
            status_class: status_class(c.status).to_string(),
            provenance: c.provenance.clone(),
            source: c.source.label().to_string(),
            reason: c.reason.clone().unwrap_or_default(),
            detail: c.detail.clone().unwrap_or_default(),
            settled: match c.settled {
                Some(true) => "settled",
                Some(false) => "unsettled",
                None => "",
            }
            .to_string(),
        }
    }
}

/// A scan of the paper's figure with our curves over it.
#[derive(Debug, Serialize)]
pub struct ScanView {
    /// Title of the paper's figure.
    pub title: String,
    /// The copy of the scan, relative to the page.
    pub image: String,
    /// Its width, pixels.
    pub width: u32,
    /// Its height, pixels.
    pub height: u32,
    /// Our curves in the scan's frame (an SVG element).
    pub svg: String,
    /// Where the calibration comes from, and the scan's file.
    pub calibrated_by: String,
    /// Our plot (PNG), relative to the page.
    pub plot: String,
}

/// A data table with its files.
#[derive(Debug, Serialize)]
pub struct TableView {
    /// File stem.
    pub name: String,
    /// What the table holds.
    pub description: String,
    /// Rows of the whole table.
    pub rows: usize,
    /// Link to its CSV file.
    pub csv: String,
    /// The CSV file holds every `csv_stride`-th row and the last (1: every row).
    pub csv_stride: usize,
    /// The CSV file holds the rows that keep every extreme ([`crate::table::Table::reduced`]):
    /// the table is too long for a light report; `--full-data` writes every row.
    pub reduced: bool,
    /// The Parquet file of a long table, every row ("" for a table whole in its CSV file).
    pub parquet: String,
}

/// The page of one experiment.
#[derive(Debug, Serialize)]
pub struct ExperimentView {
    /// The experiment's id.
    pub id: String,
    /// The way up to the report's root ("../", or "../../" for a model's page).
    pub root: String,
    /// The model run on ("" when the experiment has one structure of its own), what it is,
    /// and every model of the experiment: (label, link from this page, is this one).
    pub model: String,
    /// What the model is.
    pub model_description: String,
    /// Every model of the experiment: (label, link from this page, is this one).
    pub siblings: Vec<(String, String, bool)>,
    /// The experiment's title.
    pub title: String,
    /// The paper figure.
    pub figure: String,
    /// The caption (the paper's, or the experiment's own: [`crate::experiment::Meta::headings`]).
    pub caption: String,
    /// The claim tested (or the experiment's own question).
    pub claim: String,
    /// What the reader must know before the answer (ExperimentResult::warnings).
    pub warnings: Vec<String>,
    /// The answer in one paragraph ("" when the analysis gives none).
    pub answer: String,
    /// The headings of the caption and the claim.
    pub caption_heading: String,
    /// See `caption_heading`.
    pub claim_heading: String,
    /// The experiment file.
    pub source_file: String,
    /// Named parameters of the run.
    pub parameters: Vec<(String, String)>,
    /// Every assumption the run rests on.
    pub assumptions: Vec<String>,
    /// Notes of the experiment file.
    pub notes: Vec<String>,
    /// The run's figures.
    pub figures: Vec<FigureView>,
    /// The paper's figures under ours (none without scans: [`super::scan`]).
    pub scans: Vec<ScanView>,
    /// The run's tables.
    pub tables: Vec<TableView>,
    /// The run's checks.
    pub checks: Vec<CheckRow>,
    /// The modes table's rows.
    pub modes: Vec<Vec<String>>,
    /// The modes table's header.
    pub mode_header: Vec<String>,
    /// The verdict on the figure, in words.
    pub verdict: String,
    /// CSS class of the verdict.
    pub verdict_class: String,
    /// Checks passed, failed and known deviations, in words.
    pub counts: String,
}

/// Builds the view of one experiment; `source_file` is how the report names its input.
pub fn experiment_view(r: &ExperimentResult, source_file: &str, models: &[ModelInfo]) -> ExperimentView {
    let id = &r.experiment.key();
    let current = r.experiment.model.as_ref();
    let (verdict, class, words) = counts(&r.checks);
    let headings = r.experiment.meta.headings(r.experiment.analysis.answers());
    let n = r.modes.len();
    let mut mode_header = vec!["mode".to_string(), "omega (rad/s)".into(), "f (Hz)".into()];
    mode_header.extend((0..n).map(|i| format!("phibar m{}", i + 1)));
    mode_header.extend(["M_i (kg)".to_string(), "K_i (N/m)".into(), "C_i (N s/m)".into(), "zeta_i".into()]);
    let modes = r
        .modes
        .iter()
        .map(|m| {
            let mut row = vec![m.number.to_string(), format!("{:.2}", m.omega), format!("{:.3}", m.freq_hz)];
            row.extend(m.shape.iter().map(|v| format!("{v:.3}")));
            row.extend([
                format!("{:.4}", m.modal_mass),
                format!("{:.1}", m.modal_stiffness),
                format!("{:.4}", m.modal_damping),
                format!("{:.4}", m.damping_ratio),
            ]);
            row
        })
        .collect();
    ExperimentView {
        id: id.clone(),
        root: if current.is_some() { "../../".into() } else { "../".into() },
        model: current.map(|m| m.label.clone()).unwrap_or_default(),
        model_description: current.map(|m| m.description.clone()).unwrap_or_default(),
        siblings: if current.is_some() {
            models.iter().map(|m| (m.label.clone(), format!("../{}/index.html", m.id), Some(m) == current)).collect()
        } else {
            Vec::new()
        },
        title: r.experiment.meta.title.clone(),
        figure: r.experiment.meta.figure.clone(),
        caption: r.experiment.meta.caption.clone(),
        claim: r.experiment.meta.claim.clone(),
        warnings: r.warnings.clone(),
        answer: r.answer.clone().unwrap_or_default(),
        caption_heading: headings.0.to_string(),
        claim_heading: headings.1.to_string(),
        source_file: source_file.to_string(),
        parameters: super::setup_words::parameters(&r.experiment),
        assumptions: super::setup_words::assumptions(&r.experiment),
        notes: r.experiment.meta.notes.clone(),
        figures: r
            .figures
            .iter()
            .map(|f| FigureView {
                title: f.title.clone(),
                caption: f.caption.clone(),
                png: format!("{}.png", f.id),
                svg: format!("{}.svg", f.id),
            })
            .collect(),
        scans: Vec::new(),
        tables: r
            .tables
            .iter()
            .map(|t| TableView {
                name: t.name.clone(),
                description: t.description.clone(),
                rows: t.height(),
                csv: format!("data/{}.csv", t.name),
                csv_stride: 1,
                reduced: false,
                parquet: if crate::table::has_parquet(t.height()) {
                    format!("data/{}.parquet", t.name)
                } else {
                    String::new()
                },
            })
            .collect(),
        checks: r.checks.iter().map(|c| CheckRow::new(id, c)).collect(),
        modes,
        mode_header,
        verdict,
        verdict_class: class.to_string(),
        counts: words,
    }
}

/// Renders a page from a serialisable view.
pub fn render<T: Serialize>(tera: &Tera, template: &str, view: &T) -> Result<String> {
    let ctx =
        Context::from_serialize(view).map_err(|e| Error::Render { what: template.into(), message: e.to_string() })?;
    tera.render(template, &ctx).map_err(|e| Error::Render { what: template.into(), message: format!("{e:#}") })
}
