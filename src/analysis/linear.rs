//! Modal table and exact linear frequency response (bare and "stuck" structures).

use crate::checks::reference::ReferenceStore;
use crate::experiment::{CurveId, Experiment, PlotSpec};
use crate::figure::Figure;
use crate::model::modal::{modal_summary, ModeSummary};
use crate::table::Table;

use super::curves::{self, union_grid, Curve};
use super::figures::{self, Extras};
use super::kind::{Input, Kind, Output};

/// Modal analysis only (`kind = "modal"`): the modal table every experiment has.
pub struct Modal;

impl Kind for Modal {
    fn run(&self, _: &Input<'_>) -> Output {
        Output::default()
    }
}

/// The exact linear frequency response (`kind = "linear_frf"`) on a grid in Hz.
pub(crate) struct Frf<'a> {
    pub(crate) freq_hz: &'a [f64],
}

impl Kind for Frf<'_> {
    fn run(&self, i: &Input<'_>) -> Output {
        let (table, figures, curves) = frf(i.exp, i.modes, self.freq_hz, i.refs);
        Output { tables: vec![table], figures, curves, ..Output::default() }
    }
}

/// The modal table: frequencies, normalised shapes, modal mass/stiffness/damping, and the
/// mass ratio mu_i of Eq. 13 for each case with dampers.
pub fn modal_table(exp: &Experiment, modes: &[ModeSummary]) -> Table {
    let mut t = Table::new(
        "modal",
        "Modes of the bare structure: omega (rad/s), f (Hz), shape normalised to largest element +1 (a reduced model's at its points only), modal mass (kg), stiffness (N/m), damping (N s/m), damping ratio, for a reduced model whether the mode moves its points (1; 0: a node at every point, no modal quantities given), and mu_i (Eq. 13) per case",
    )
    .i64("mode", modes.iter().map(|m| m.number as i64).collect())
    .f64("omega_rad_s", modes.iter().map(|m| m.omega).collect())
    .f64("freq_hz", modes.iter().map(|m| m.freq_hz).collect());
    // A reduced model's shapes at its points only (its modal coordinates are no place to read
    // a mode at); a mode that does not move them has no modal mass there to state.
    let points = exp.structure.physical();
    for r in 0..points {
        t = t.f64(format!("phi_m{}", r + 1), modes.iter().map(|m| m.shape[r]).collect());
    }
    let at = |m: &ModeSummary, v: f64| if m.at_points { v } else { f64::NAN };
    t = t
        .f64("modal_mass_kg", modes.iter().map(|m| at(m, m.modal_mass)).collect())
        .f64("modal_stiffness_n_per_m", modes.iter().map(|m| at(m, m.modal_stiffness)).collect())
        .f64("modal_damping_ns_per_m", modes.iter().map(|m| at(m, m.modal_damping)).collect())
        .f64("damping_ratio", modes.iter().map(|m| m.damping_ratio).collect());
    if exp.structure.points.is_some() {
        // 1: the mode moves the points; 0: a node at every point (its modal quantities blank).
        t = t.i64("moves_the_points", modes.iter().map(|m| i64::from(m.at_points)).collect());
    }
    for case in exp.cases.iter().filter(|c| !c.beds.is_empty()) {
        let with = modal_summary(&exp.structure, &case.dampers());
        t = t.f64(format!("mu_{}", case.id), with.iter().map(|m| at(m, m.mass_ratio)).collect());
    }
    t
}

/// Linear compliance of every case (bare when it has no dampers, "stuck" otherwise) on the
/// grid and at the frequencies its curve checks need.
pub fn frf(
    exp: &Experiment,
    modes: &[ModeSummary],
    freq_hz: &[f64],
    refs: &ReferenceStore,
) -> (Table, Vec<Figure>, Vec<Curve>) {
    let n = exp.structure.dof();
    let curves: Vec<Curve> = exp
        .cases
        .iter()
        .map(|case| {
            let grid = union_grid(freq_hz, &super::sweep::check_frequencies(exp, refs, &CurveId::whole(&case.id)));
            curves::linear(exp, case, CurveId::whole(&case.id), &case.label, &grid, !case.beds.is_empty())
        })
        .collect();
    let shown: Vec<&Curve> = curves.iter().collect();
    let table = curves::table(
        "compliance",
        &format!("Linear compliance {} ({}) of each mass r (columns c1..cn): the bare structure for cases without dampers, damper masses rigidly added (stuck) otherwise", exp.excitation.ratio().replace(" /", "_r /"), exp.excitation.per_unit()),
        &shown,
        n,
        0,
    );
    let plots: Vec<&PlotSpec> = exp.plots.iter().collect();
    let figures = figures::compliance(
        exp,
        &plots,
        &shown,
        &Extras {
            overlays: super::overlays::overlays(exp, refs, &curves),
            linear: Vec::new(),
            marks: Vec::new(),
            branches: Vec::new(),
            range: (freq_hz[0], freq_hz[freq_hz.len() - 1]),
        },
        modes,
    );
    (table, figures, curves)
}
