//! Everything that leaves the program: tables, plots, pages. [`ReportWriter`] is the one
//! owner of destinations; exporters render to bytes or draw to a path it gives them.

mod axis;
pub mod bottom_line;
pub mod compare;
pub mod conclusion;
pub mod destination;
pub mod files;
pub mod heatmap;
pub mod index_page;
pub mod junit;
pub mod manifest;
pub mod models_page;
pub mod plot;
pub mod report;
pub mod robustness;
pub mod scan;
pub mod setup_words;
pub mod study;
pub mod study_words;
pub mod svg;
pub mod texts;
pub mod view;
pub mod weight;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::analysis::ExperimentResult;
use crate::checks::CheckOutcome;
use crate::error::{Error, Result};
use crate::table;

/// Writes a report into a fresh staging folder next to the destination and renames it into
/// place only when everything is written: a failed run leaves the previous report intact
/// ([`destination`]: what may be replaced).
pub struct ReportWriter {
    staging: destination::Staging,
    tera: tera::Tera,
    full_csv: bool,
    full_data: bool,
    svg: bool,
    complete: bool,
    smallest_png: bool,
    scans: Vec<scan::Scan>,
}

/// How a report is written.
#[derive(Debug, Clone, Default)]
pub struct ReportOptions {
    /// A folder of templates overriding the embedded ones.
    pub templates: Option<PathBuf>,
    /// Every row of every table in its CSV file (else a table longer than
    /// [`table::CSV_ROWS`] keeps a preview there: [`table::preview_stride`]; such tables are
    /// also written whole as Parquet up to [`table::LIGHT_ROWS`] rows).
    pub full_csv: bool,
    /// Every row of every table (`--full-data`): every table longer than [`table::CSV_ROWS`]
    /// is written whole as Parquet, its CSV every [`table::csv_stride`]-th row; else a table
    /// longer than [`table::LIGHT_ROWS`] has no Parquet file and its CSV holds the rows that
    /// keep every extreme ([`crate::table::Table::reduced`]).
    pub full_data: bool,
    /// Every figure as PNG and SVG (`--svg`); else each in the smaller of the two.
    pub svg: bool,
    /// Every experiment a text may quote runs (`shotdamp report`): a placeholder naming one
    /// that did not is an error, not a remark in the text.
    pub complete: bool,
    /// Scans of the paper's figures to draw our curves over ([`scan`]).
    pub scans: Vec<scan::Scan>,
    /// PNG files at the encoder's best compression (`shotdamp report`, whose folder must stay
    /// light: 11 % smaller, about 0.1 s more a figure; [`plot::to_png`]).
    pub smallest_png: bool,
}

/// How a table's data is written ([`ReportWriter::table_files`]).
#[derive(Debug, Clone, Copy, PartialEq)]
enum TableFiles {
    /// Every row in Parquet when the table is long; the CSV file every `stride`-th row.
    Whole { stride: usize },
    /// The CSV file holds the rows that keep every extreme; no Parquet file.
    Reduced,
}

/// Clears the links of a figure's files that were not written in `dir` (a figure is written
/// in one format unless both are asked for).
fn figure_links(dir: &Path, f: &mut view::FigureView) {
    for link in [&mut f.png, &mut f.svg] {
        if !link.is_empty() && !dir.join(link.as_str()).is_file() {
            link.clear();
        }
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).map_err(|e| Error::io(path, e))
}

/// Creates the folders of `rel` below `root`, never `root` itself: once an interrupted run
/// has removed its staging folder, a worker still writing cannot bring it back.
fn mkdir_below(root: &Path, rel: &Path) -> Result<()> {
    let mut path = root.to_path_buf();
    for part in rel.components() {
        path.push(part);
        match std::fs::create_dir(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && path.is_dir() => {}
            Err(e) => return Err(Error::io(&path, e)),
        }
    }
    Ok(())
}

fn mkdir(path: &Path) -> Result<()> {
    std::fs::create_dir_all(path).map_err(|e| Error::io(path, e))
}

impl ReportWriter {
    /// Prepares a staging folder for a report that will end up at `out`. Fails before any
    /// long run when the destination cannot be written.
    pub fn create(out: &Path, options: &ReportOptions) -> Result<ReportWriter> {
        let tera = report::templates(options.templates.as_deref())?;
        let staging = destination::Staging::create(out)?;
        Ok(ReportWriter {
            staging,
            tera,
            full_csv: options.full_csv,
            full_data: options.full_data,
            svg: options.svg,
            complete: options.complete,
            smallest_png: options.smallest_png,
            scans: options.scans.clone(),
        })
    }

    /// Where the report will be.
    pub fn destination(&self) -> &Path {
        self.staging.destination()
    }

    /// The staging folder (removed when the run is interrupted).
    pub fn staging_dir(&self) -> &Path {
        self.staging.dir()
    }

    /// Writes one experiment's folder: figures (PNG, SVG) and tables (CSV, Parquet); its page
    /// is written by [`ReportWriter::finish`], once every text can be filled.
    pub fn write_experiment(&self, r: &ExperimentResult) -> Result<()> {
        let key = r.experiment.key();
        let dir = self.staging.dir().join(&key);
        mkdir_below(self.staging.dir(), &Path::new(&key).join("data"))?;
        let data = dir.join("data");
        for t in &r.tables {
            let csv = match self.table_files(t) {
                TableFiles::Reduced => table::to_csv(&t.reduced())?,
                TableFiles::Whole { stride: 1 } => table::to_csv(t)?,
                TableFiles::Whole { stride } => table::to_csv(&t.thinned(stride))?,
            };
            write(&data.join(format!("{}.csv", t.name)), &csv)?;
            if matches!(self.table_files(t), TableFiles::Whole { .. }) && table::has_parquet(t.height()) {
                write(&data.join(format!("{}.parquet", t.name)), &table::to_parquet(t)?)?;
            }
        }
        for f in &r.figures {
            self.write_figure(&dir, f)?;
        }
        Ok(())
    }

    /// How a table is written: whole (every row in Parquet when long, its CSV every
    /// `stride`-th row), or reduced to the rows that keep its extremes.
    fn table_files(&self, t: &table::Table) -> TableFiles {
        if self.full_data || self.full_csv {
            TableFiles::Whole { stride: table::csv_stride(t.height(), self.full_csv) }
        } else if t.height() <= table::LIGHT_ROWS {
            TableFiles::Whole { stride: table::preview_stride(t.height()) }
        } else {
            TableFiles::Reduced
        }
    }

    /// Writes a figure as `ID.png` and `ID.svg` when both are asked for (`--svg`), else in
    /// the smaller of the two (a curve of thousands of points is smaller as PNG; a few lines
    /// as SVG). The pages link the files that exist ([`figure_links`]).
    fn write_figure(&self, dir: &Path, f: &crate::figure::Figure) -> Result<()> {
        let png = plot::to_png(f, self.smallest_png)?;
        let svg = plot::to_svg(f)?;
        if self.svg || png.len() <= svg.len() {
            write(&dir.join(format!("{}.png", f.id)), &png)?;
        }
        if self.svg || svg.len() < png.len() {
            write(&dir.join(format!("{}.svg", f.id)), svg.as_bytes())?;
        }
        Ok(())
    }

    /// Copies the scans that go on `r`'s page into its folder (`scans/`) and draws our curves
    /// over each.
    fn write_scans(&self, r: &ExperimentResult) -> Result<Vec<report::ScanView>> {
        let model = r.experiment.model.as_ref().map(|m| m.id.as_str());
        let mine = self.scans.iter().filter(|s| {
            s.experiment == r.experiment.meta.id
                && (s.models.is_empty() || model.is_some_and(|m| s.models.iter().any(|x| x == m)))
        });
        let mut out = Vec::new();
        for s in mine {
            let Some(fig) = r.figures.iter().find(|f| f.id == s.plot) else {
                let ids: Vec<&str> = r.figures.iter().map(|f| f.id.as_str()).collect();
                return Err(Error::invalid(
                    &s.file,
                    "plot",
                    format!("\"{}\"", s.plot),
                    format!("the plots of {} are {ids:?}", r.experiment.key()),
                ));
            };
            let traces = scan::overlay(s, fig)?;
            let ext = s.image.extension().map(|e| e.to_string_lossy().to_string()).unwrap_or_default();
            let rel = format!("scans/{}.{ext}", s.name);
            mkdir_below(self.staging.dir(), &Path::new(&r.experiment.key()).join("scans"))?;
            let bytes = std::fs::read(&s.image).map_err(|e| Error::io(&s.image, e))?;
            write(&self.staging.dir().join(r.experiment.key()).join(&rel), &bytes)?;
            out.push(report::ScanView {
                title: s.title.clone(),
                image: rel,
                width: s.width,
                height: s.height,
                svg: scan::svg(s, &traces),
                calibrated_by: format!("{} ({})", s.calibrated_by, s.file.display()),
                plot: format!("{}.png", fig.id),
            });
        }
        Ok(out)
    }

    /// Writes one experiment's page.
    fn write_page(&self, r: &ExperimentResult) -> Result<()> {
        let mut view = report::experiment_view(r, &r.experiment.path.display().to_string(), &r.experiment.models);
        for (t, table) in view.tables.iter_mut().zip(&r.tables) {
            match self.table_files(table) {
                TableFiles::Whole { stride } => t.csv_stride = stride,
                TableFiles::Reduced => {
                    t.csv_stride = table::preview_stride(table.height());
                    t.reduced = true;
                    t.parquet = String::new();
                }
            }
        }
        let dir = self.staging.dir().join(r.experiment.key());
        for f in &mut view.figures {
            figure_links(&dir, f);
        }
        view.scans = self.write_scans(r)?;
        for s in &mut view.scans {
            let mut links =
                view::FigureView { png: s.plot.clone(), svg: s.plot.replace(".png", ".svg"), ..Default::default() };
            figure_links(&dir, &mut links);
            s.plot = links.image().to_string();
        }
        let html = report::render(&self.tera, "experiment.html", &view)?;
        write(&self.staging.dir().join(r.experiment.key()).join("index.html"), html.as_bytes())
    }

    /// Writes the index, the stylesheet and `checks.json`, then moves the report into place.
    /// `studies`: the studies run with the report, shown on their experiment's page.
    /// The texts of `results` are filled first ([`texts::fill`]).
    pub fn finish(self, results: &mut [ExperimentResult], studies: &[manifest::StudyRun]) -> Result<PathBuf> {
        texts::fill(results, if self.complete { texts::Missing::Error } else { texts::Missing::Say })?;
        if self.complete {
            for s in &self.scans {
                if !results.iter().any(|r| r.experiment.meta.id == s.experiment) {
                    return Err(Error::invalid(
                        &s.file,
                        "experiment",
                        format!("\"{}\"", s.experiment),
                        "no experiment of the report has this id",
                    ));
                }
            }
        }
        let results: &[ExperimentResult] = results;
        let dir = self.staging.dir();
        for r in results {
            self.write_page(r)?;
        }
        for runs in by_experiment(results) {
            self.write_models(&runs, studies)?;
        }
        write(&dir.join("style.css"), report::STYLE_CSS.as_bytes())?;
        let mut index_view = index_page::index_view(results);
        let bed = |s: &&manifest::StudyRun| {
            s.manifest.joint.is_empty() && s.manifest.section == crate::experiment::study::Section::Bed
        };
        for s in studies.iter().filter(bed) {
            let m = &s.manifest;
            let names: Vec<String> = m.vary.iter().map(|a| a.name.clone()).collect();
            index_view.bed.push(index_page::BedRow {
                figure: m.figure.clone(),
                link: format!("{}/index.html#{}", m.experiment, m.study),
                sentence: crate::output::study_words::deviation_summary(&m.models, &names, &s.rows),
            });
        }
        // Joint studies: their tables in `ID/`, their bottom line on the index (a stored
        // answer, the widest search, first).
        let mut joint_runs: Vec<&manifest::StudyRun> =
            studies.iter().filter(|s| !s.manifest.joint.is_empty()).collect();
        joint_runs.sort_by_key(|s| s.stored.is_none());
        for s in joint_runs {
            let m = &s.manifest;
            mkdir_below(dir, Path::new(&m.study))?;
            let names: Vec<String> = m.vary.iter().map(|a| a.name.clone()).collect();
            let long = crate::analysis::study::rows_table(&m.study, &names, &s.rows);
            let samples = crate::analysis::study_samples::per_sample(&s.rows);
            let per = crate::analysis::study_samples::table(&m.study, &names, &samples);
            for t in [&long, &per] {
                write(&dir.join(&m.study).join(format!("{}.csv", t.name)), &crate::table::to_csv(t)?)?;
            }
            index_view.bottom.push(bottom_line::of(s, &m.study));
        }
        let joint: Vec<bottom_line::AtJointSetup> =
            studies.iter().filter(|s| !s.manifest.joint.is_empty()).flat_map(bottom_line::at_joint_setup).collect();
        index_page::mark_joint(&mut index_view, &joint);
        // Thumbnails of figures written as SVG only.
        let shown = |rel: &mut String| {
            let mut links =
                view::FigureView { png: rel.clone(), svg: rel.replace(".png", ".svg"), ..Default::default() };
            figure_links(dir, &mut links);
            *rel = links.image().to_string();
        };
        index_view.rows.iter_mut().for_each(|r| shown(&mut r.thumbnail));
        index_view.figures.iter_mut().for_each(|f| shown(&mut f.thumbnail));
        index_view.examples.iter_mut().for_each(|f| shown(&mut f.thumbnail));
        let index = report::render(&self.tera, "index.html", &index_view)?;
        write(&dir.join("index.html"), index.as_bytes())?;
        write(&dir.join("checks.json"), &checks_json(results)?)?;
        write(&dir.join("junit.xml"), junit::render(results).as_bytes())?;
        self.staging.commit()
    }

    /// Writes the page of one experiment run on several models (`ID/index.html`) with the
    /// figures that overlay them.
    fn write_models(&self, runs: &[&ExperimentResult], studies: &[manifest::StudyRun]) -> Result<()> {
        let id = &runs[0].experiment.meta.id;
        let dir = self.staging.dir().join(id);
        mkdir_below(self.staging.dir(), Path::new(id))?;
        let overlays = crate::analysis::models::overlay(runs);
        for f in &overlays {
            self.write_figure(&dir, f)?;
        }
        let mut view = models_page::models_view(runs, &overlays);
        for f in &mut view.overlays {
            figure_links(&dir, f);
        }
        for cell in view.side_by_side.iter_mut().flat_map(|s| s.cells.iter_mut()) {
            let mut links = view::FigureView { png: cell.1.clone(), svg: cell.2.clone(), ..Default::default() };
            figure_links(&dir, &mut links);
            (cell.1, cell.2) = (links.image().to_string(), links.link().to_string());
        }
        for s in studies.iter().filter(|s| s.manifest.joint.is_empty() && &s.manifest.experiment == id) {
            mkdir_below(self.staging.dir(), &Path::new(id).join("robustness"))?;
            mkdir_below(self.staging.dir(), &Path::new(id).join("data"))?;
            let written = robustness::write(&dir, s, &write)?;
            match s.manifest.section {
                crate::experiment::study::Section::Robustness => view.robustness.push(written),
                crate::experiment::study::Section::Bed => view.bed.push(written),
            }
        }
        let html = report::render(&self.tera, "models.html", &view)?;
        write(&dir.join("index.html"), html.as_bytes())
    }

    /// Removes the staging folder of an abandoned report.
    pub fn abandon(self) {
        self.staging.abandon();
    }
}

/// The runs of each experiment that runs on several models, grouped, in first-seen order.
pub fn by_experiment(results: &[ExperimentResult]) -> Vec<Vec<&ExperimentResult>> {
    let mut groups: Vec<Vec<&ExperimentResult>> = Vec::new();
    for r in results.iter().filter(|r| r.experiment.model.is_some()) {
        match groups.iter_mut().find(|g| g[0].experiment.meta.id == r.experiment.meta.id) {
            Some(g) => g.push(r),
            None => groups.push(vec![r]),
        }
    }
    groups
}

/// Writes an experiment's regression baseline sample to `dir/ID.csv`.
pub fn write_baseline(dir: &Path, id: &str, values: &[crate::checks::baseline::Value]) -> Result<()> {
    let path = dir.join(format!("{id}.csv"));
    mkdir(path.parent().unwrap_or(dir))?;
    write(&path, &table::to_csv(&crate::checks::baseline::to_table(values))?)
}

#[derive(Serialize)]
struct CheckRecord<'a> {
    experiment: &'a str,
    /// The model the run used (absent when the experiment has one structure of its own).
    #[serde(skip_serializing_if = "Option::is_none")]
    model: Option<&'a str>,
    figure: &'a str,
    #[serde(flatten)]
    check: &'a CheckOutcome,
}

#[derive(Serialize)]
struct ChecksFile<'a> {
    shotdamp_version: &'a str,
    passed: bool,
    checks: Vec<CheckRecord<'a>>,
}

/// Every check of every experiment as JSON.
pub fn checks_json(results: &[ExperimentResult]) -> Result<Vec<u8>> {
    let file = ChecksFile {
        shotdamp_version: env!("CARGO_PKG_VERSION"),
        passed: results.iter().all(|r| r.passed()),
        checks: results
            .iter()
            .flat_map(|r| {
                r.checks.iter().map(move |c| CheckRecord {
                    experiment: &r.experiment.meta.id,
                    model: r.experiment.model.as_ref().map(|m| m.id.as_str()),
                    figure: &r.experiment.meta.figure,
                    check: c,
                })
            })
            .collect(),
    };
    serde_json::to_vec_pretty(&file).map_err(|e| Error::Render { what: "checks.json".into(), message: e.to_string() })
}
