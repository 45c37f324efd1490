//! Design files: the designs `shotdamp report` shows (their stored answers evaluated again)
//! and `shotdamp design --store`, which writes the answers (docs/design.md, "In the report").

use std::path::{Path, PathBuf};

use crate::experiment::{self, Experiment};

/// The design files of `dir` marked `report = true` (none when the folder does not exist), set to evaluate the
/// answers their searches stored instead of searching (docs/design.md, "In the report").
pub fn report_designs(dir: &Path, reference: &Path) -> crate::Result<Vec<Experiment>> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut exps = experiment::load_all(&experiment::discover(dir)?, reference)?;
    for e in &mut exps {
        match &mut e.analysis {
            experiment::Analysis::Design { spec, .. } => spec.replay = true,
            other => {
                return Err(crate::Error::invalid(
                    &e.path,
                    "analysis.kind",
                    format!("\"{}\"", other.kind()),
                    "\"design\": the designs folder holds design files only",
                ))
            }
        }
    }
    exps.retain(|e| matches!(&e.analysis, experiment::Analysis::Design { spec, .. } if spec.report));
    Ok(exps)
}

/// `shotdamp design --store`: each model's answer, with how it was computed, as
/// `REFERENCE/designs/ID/MODEL.json` (written atomically); the files written.
pub fn store_designs(
    results: &[crate::analysis::ExperimentResult],
    reference: &Path,
    seconds: f64,
    threads: usize,
) -> crate::Result<Vec<PathBuf>> {
    let mut stored = Vec::new();
    for r in results {
        let Some(answer) = &r.design else { continue };
        let mut answer = answer.clone();
        answer.provenance = format!(
            "searched by `shotdamp design {} --store` (shotdamp {}) on {}; the command ({} design run(s)) took {:.0} s on {} threads",
            r.experiment.path.display(),
            env!("CARGO_PKG_VERSION"),
            crate::output::files::today_utc(),
            results.iter().filter(|r| r.design.is_some()).count(),
            seconds,
            threads
        );
        let path = crate::checks::reference::stored_design_path(reference, &r.experiment.key());
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| crate::Error::io(dir, e))?;
        }
        let text = serde_json::to_string_pretty(&answer)
            .map_err(|e| crate::Error::Render { what: path.display().to_string(), message: e.to_string() })?
            + "\n";
        crate::output::files::write_atomic(&path, text.as_bytes())?;
        stored.push(path);
    }
    Ok(stored)
}
