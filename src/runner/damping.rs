//! `shotdamp damping`: the modal damping ratios that fit a digitised compliance curve of the
//! bare structure (docs/model.md), for each model of an experiment file.

use std::path::Path;

use crate::error::{Error, Result};
use crate::experiment::{self, Experiment};
use crate::model::damping_fit::{fit_modal_damping, DampingFit, Measured};
use crate::reference::digitised;

/// The fit of one model.
#[derive(Debug)]
pub struct Calibration {
    /// The model's label (the experiment's id without models).
    pub label: String,
    /// Its damping ratios and how well they fit.
    pub fit: DampingFit,
}

/// What was fitted.
#[derive(Debug)]
pub struct Calibrated {
    /// Curves of the digitised file mapped to a mass.
    pub curves: usize,
    /// Their points.
    pub points: usize,
    /// One fit per model chosen.
    pub models: Vec<Calibration>,
}

/// Fits the modal damping ratios of each model of `file` (or the one with id `model`) to the
/// curves of the digitised file `curve` mapped to masses (`DATASET=bare:MASS` at import).
pub fn calibrate(file: &Path, curve: &Path, model: Option<&str>, reference: &Path) -> Result<Calibrated> {
    let digitised = digitised::load(curve)?;
    let data: Vec<Measured> = digitised
        .curve
        .iter()
        .filter_map(|c| {
            let m = usize::try_from(c.mass?).ok()?.checked_sub(1)?;
            Some(Measured { mass: m, freq_hz: c.x.clone(), compliance: c.y.clone() })
        })
        .collect();
    if data.is_empty() {
        return Err(Error::invalid(
            curve,
            "curve[].mass",
            "(none)",
            "no curve is mapped to a mass: import it with --map \"DATASET=bare:1\" (one per mass)",
        ));
    }
    let exps = experiment::loader::load(file, reference)?;
    let ids: Vec<String> = exps.iter().filter_map(|e| e.model.as_ref().map(|m| m.id.clone())).collect();
    let chosen: Vec<&Experiment> =
        exps.iter().filter(|e| model.is_none_or(|id| e.model.as_ref().is_some_and(|m| m.id == id))).collect();
    if chosen.is_empty() {
        return Err(Error::invalid("--model", "model", model.unwrap_or(""), format!("one of {ids:?}")));
    }
    let mut models = Vec::new();
    for exp in chosen {
        if exp.excitation.supports {
            return Err(Error::invalid(
                file,
                "excitation.base_acceleration_m_s2",
                "(moving supports)",
                "measured compliances are fitted under a force on one mass: use an experiment file driven by a force",
            ));
        }
        let fit = fit_modal_damping(&exp.structure, exp.excitation.mass, &data)
            .map_err(|e| Error::refused(curve, "curve", exp.meta.id.clone(), e))?;
        let label = exp.model.as_ref().map(|m| m.label.clone()).unwrap_or_else(|| exp.meta.id.clone());
        models.push(Calibration { label, fit });
    }
    let points = data.iter().map(|d| d.freq_hz.len()).sum();
    Ok(Calibrated { curves: data.len(), points, models })
}
