//! Modal table and exact linear frequency response (bare and "stuck" structures).

use std::f64::consts::PI;

use crate::experiment::{Case, Experiment, PlotKind, Scale};
use crate::model::frf::compliance_curve;
use crate::model::modal::{modal_summary, ModeSummary};
use crate::model::structure::added_masses;
use crate::output::figure::{Dash, Figure, Panel, Series, VLine};
use crate::output::table::Table;

/// The modal table: frequencies, normalised shapes, modal mass/stiffness/damping, and the
/// mass ratio mu_i of Eq. 13 for each case with dampers.
pub fn modal_table(exp: &Experiment, modes: &[ModeSummary]) -> Table {
    let n = modes.len();
    let mut t = Table::new(
        "modal",
        "Modes of the bare structure: omega (rad/s), f (Hz), shape normalised to largest element +1, modal mass (kg), stiffness (N/m), damping (N s/m), damping ratio, and mu_i (Eq. 13) per case",
    )
    .i64("mode", modes.iter().map(|m| m.number as i64).collect())
    .f64("omega_rad_s", modes.iter().map(|m| m.omega).collect())
    .f64("freq_hz", modes.iter().map(|m| m.freq_hz).collect());
    for r in 0..n {
        t = t.f64(
            format!("phi_m{}", r + 1),
            modes.iter().map(|m| m.shape[r]).collect(),
        );
    }
    t = t
        .f64(
            "modal_mass_kg",
            modes.iter().map(|m| m.modal_mass).collect(),
        )
        .f64(
            "modal_stiffness_n_per_m",
            modes.iter().map(|m| m.modal_stiffness).collect(),
        )
        .f64(
            "modal_damping_ns_per_m",
            modes.iter().map(|m| m.modal_damping).collect(),
        )
        .f64(
            "damping_ratio",
            modes.iter().map(|m| m.damping_ratio).collect(),
        );
    for case in exp.cases.iter().filter(|c| !c.dampers.is_empty()) {
        let with = modal_summary(&exp.structure, &case.dampers);
        t = t.f64(
            format!("mu_{}", case.id),
            with.iter().map(|m| m.mass_ratio).collect(),
        );
    }
    t
}

/// The x values of a frequency grid in rad/s.
pub fn to_rad(freq_hz: &[f64]) -> Vec<f64> {
    freq_hz.iter().map(|f| 2.0 * PI * f).collect()
}

/// Linear compliance of every case (bare when it has no dampers, "stuck" otherwise).
pub fn frf(exp: &Experiment, modes: &[ModeSummary], freq_hz: &[f64]) -> (Table, Vec<Figure>) {
    let omegas = to_rad(freq_hz);
    let n = exp.structure.dof();
    let mut table = Table::new(
        "compliance",
        "Linear compliance |x_r / F| (m/N) of each mass r: the bare structure for cases without dampers, damper masses rigidly added (stuck) otherwise",
    )
    .f64("freq_hz", freq_hz.to_vec());
    let mut curves: Vec<(&Case, Vec<Vec<f64>>)> = Vec::new();
    for case in &exp.cases {
        let mass = exp.structure.mass_matrix_with(&added_masses(&case.dampers));
        let rows = compliance_curve(&exp.structure, &mass, exp.excitation.mass, &omegas);
        for r in 0..n {
            table = table.f64(
                format!("{}_c{}", case.id, r + 1),
                rows.iter().map(|row| row[r]).collect(),
            );
        }
        curves.push((case, rows));
    }
    let figures = exp
        .plots
        .iter()
        .filter(|p| p.kind == PlotKind::Compliance)
        .map(|p| {
            let mut series = Vec::new();
            for (ci, (case, rows)) in curves.iter().filter(|(c, _)| p.cases.contains(&c.id)).enumerate() {
                for &r in &p.masses {
                    let label = if exp.cases.len() > 1 { format!("m{} — {}", r + 1, case.label) } else { format!("m{}", r + 1) };
                    let dash = [Dash::Solid, Dash::Dashed, Dash::DashDot, Dash::Dotted][ci % 4];
                    series.push(Series::line(label, freq_hz.to_vec(), rows.iter().map(|row| row[r]).collect(), r).dashed(dash));
                }
            }
            let vlines = if p.mark_natural_frequencies {
                modes
                    .iter()
                    .map(|m| VLine { x: m.freq_hz, label: format!(" f{} = {:.2} Hz", m.number, m.freq_hz) })
                    .collect()
            } else {
                Vec::new()
            };
            let x_range = (freq_hz[0], freq_hz[freq_hz.len() - 1]);
            Figure {
                id: p.id.clone(),
                title: p.title.clone().unwrap_or_else(|| format!("{}: {}", exp.meta.figure, exp.meta.title)),
                caption: format!(
                    "Linear compliance, F on m{}; dashed vertical lines: natural frequencies of the model.",
                    exp.excitation.mass + 1
                ),
                panels: vec![Panel {
                    title: p.title.clone().unwrap_or_else(|| format!("{}: {}", exp.meta.figure, exp.meta.title)),
                    x_label: "frequency (Hz)".into(),
                    y_label: "compliance |x / F| (m/N)".into(),
                    x_range,
                    y_log: p.y_scale == Scale::Log,
                    series,
                    vlines,
                }],
            }
        })
        .collect();
    (table, figures)
}
