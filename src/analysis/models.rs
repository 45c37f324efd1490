//! One experiment on several models of the structure: compliance curves overlaid across
//! models (docs/model.md section 1.2). Nothing here runs a solver: it reads finished results.

use crate::experiment::{Analysis, PlotKind, Scale};
use crate::figure::{Corner, Dash, Figure, Panel, Series};

use super::result::ExperimentResult;

/// Dash patterns in case order.
const DASHES: [Dash; 4] = [Dash::Solid, Dash::Dashed, Dash::DashDot, Dash::Dotted];

/// Most cases a plot may have for its models to be overlaid (more reads badly: the report
/// shows those side by side only).
const MAX_CASES: usize = 2;

/// The compliance plots of the first run with every run's curves overlaid: one panel per
/// mass, colour by model, dash by case, over the analysis's frequency range. Empty when the
/// experiment draws no compliance plot of at most `MAX_CASES` (2) cases or the runs are not of
/// one experiment on several models.
pub fn overlay(runs: &[&ExperimentResult]) -> Vec<Figure> {
    let Some(first) = runs.first() else { return Vec::new() };
    if runs.len() < 2 || runs.iter().any(|r| r.experiment.model.is_none()) {
        return Vec::new();
    }
    let exp = &first.experiment;
    exp.plots
        .iter()
        .filter(|p| matches!(p.kind, PlotKind::Compliance | PlotKind::CompliancePanels) && p.cases.len() <= MAX_CASES)
        .filter_map(|p| {
            let grid = match &exp.analysis {
                Analysis::LinearFrf { freq_hz } | Analysis::Sweep { freq_hz, .. } => freq_hz,
                Analysis::ClearanceStudy { freq_hz, .. } => freq_hz,
                _ => return None,
            };
            let grid_range = (grid.first().copied()?, grid.last().copied()?);
            let mut panels = Vec::new();
            let mut range = (f64::INFINITY, f64::NEG_INFINITY);
            for &mass in &p.masses {
                let mut series = Vec::new();
                for (mi, r) in runs.iter().enumerate() {
                    let label = r.experiment.model.as_ref().map(|m| m.label.clone()).unwrap_or_default();
                    let cases: Vec<_> = r
                        .curves
                        .iter()
                        .filter(|c| p.cases.iter().any(|id| c.id.drawn_for(id)))
                        .collect();
                    for (ci, c) in cases.iter().enumerate() {
                        if c.freq_hz.is_empty() {
                            continue;
                        }
                        range.0 = range.0.min(c.freq_hz[0]);
                        range.1 = range.1.max(c.freq_hz[c.freq_hz.len() - 1]);
                        let name = if cases.len() > 1 { format!("{label} — {}", c.label) } else { label.clone() };
                        let y = c.compliance.iter().map(|row| row[mass]).collect();
                        series.push(Series::line(name, c.freq_hz.clone(), y, mi).dashed(DASHES[ci % 4]));
                    }
                }
                if series.is_empty() {
                    continue;
                }
                let mut panel = Panel::new(
                    format!("{}: m{} on each model", exp.meta.figure, mass + 1),
                    "frequency (Hz)",
                    format!("compliance {} ({})", exp.excitation.ratio(), exp.excitation.per_unit()),
                    (0.0, 1.0),
                );
                panel.y_log = p.y_scale == Scale::Log;
                panel.legend = Corner::UpperRight;
                panel.series = series;
                panels.push(panel);
            }
            if panels.is_empty() || range.0.partial_cmp(&range.1) != Some(std::cmp::Ordering::Less) {
                return None;
            }
            let range = p.x_range.unwrap_or(grid_range);
            for panel in &mut panels {
                panel.x_range = range;
            }
            Some(Figure {
                id: format!("models_{}", p.id),
                title: format!("{}: the models overlaid", p.title.clone().unwrap_or_else(|| exp.meta.title.clone())),
                caption: format!(
                    "The same experiment on each model of the structure, one colour per model{}; {}. Points that did not settle are drawn like the others here: see each model's page for them.",
                    if p.cases.len() > 1 { ", one dash pattern per case" } else { "" },
                    exp.excitation.at(),
                ),
                panels,
            })
        })
        .collect()
}
