//! What the command line prints of a structure: its modes (`shotdamp modal`), a stiffness
//! fitted to measured modes, and a damping calibrated to measured curves.

use crate::experiment::Experiment;
use crate::model::modal::modal_summary;
use crate::model::sdof::EquivalentSdof;
use crate::runner;
use anyhow::Context as _;
use std::path::Path;

/// `shotdamp modal`: the bare structure's modes and, per case, its equivalent SDOF models.
pub(super) fn print_modal(exp: &Experiment, case: Option<&str>) -> anyhow::Result<()> {
    let cases: Vec<_> = match case {
        Some(id) => {
            let c = exp.cases.iter().find(|c| c.id == id).with_context(|| {
                format!(
                    "{}: no case \"{id}\"; the cases are {:?}",
                    exp.path.display(),
                    exp.cases.iter().map(|c| &c.id).collect::<Vec<_>>()
                )
            })?;
            vec![c]
        }
        None => exp.cases.iter().filter(|c| !c.beds.is_empty()).collect(),
    };
    let modes = modal_summary(&exp.structure, &[]);
    let n = modes.len();
    let on = exp.model.as_ref().map(|m| format!(", model \"{}\" ({})", m.id, m.label)).unwrap_or_default();
    say!("{} ({}{on}): modes of the bare structure", exp.meta.id, exp.path.display());
    if let Some(fe) = &exp.finite_element {
        say!(
            "finite-element model: {} degrees of freedom ({}), reduced to {} coordinates; the mass moving along the vertical ({}) is {:.6} kg{}",
            fe.full.mass.n(),
            fe.full.files,
            fe.reduced.mass.nrows(),
            fe.up,
            fe.mass_along_up,
            fe.mass_stated.map_or(String::new(), |m| format!(" (the whole structure's, as stated: {m} kg)"))
        );
    }
    if let Some(fit) = &exp.fit {
        print_fit(fit);
    }
    // A reduced model's shapes at its points only; a mode with a node at every point says so.
    let points = exp.structure.physical();
    if points < n {
        say!("shapes at the {points} point{} (the modal coordinates left out)", if points == 1 { "" } else { "s" });
    }
    say_part!("{:>4} {:>12} {:>10}", "mode", "omega rad/s", "f Hz");
    for r in 0..points {
        say_part!(" {:>9}", format!("phi_m{}", r + 1));
    }
    say!(" {:>10} {:>12} {:>11} {:>8}", "M_i kg", "K_i N/m", "C_i N s/m", "zeta_i");
    for m in &modes {
        say_part!("{:>4} {:>12.3} {:>10.4}", m.number, m.omega, m.freq_hz);
        if !m.at_points {
            say!(
                "  does not move the points (a node at every point): no shape or modal mass there; zeta {:.5}",
                m.damping_ratio
            );
            continue;
        }
        for v in &m.shape[..points] {
            say_part!(" {v:>9.4}");
        }
        say!(" {:>10.5} {:>12.2} {:>11.5} {:>8.5}", m.modal_mass, m.modal_stiffness, m.modal_damping, m.damping_ratio);
    }
    if exp.excitation.supports && !cases.is_empty() {
        say!();
        say!("no equivalent SDOF models: they take a force on one mass (paper Eq. 12-13), and the supports move");
    }
    for c in cases.iter().filter(|_| !exp.excitation.supports) {
        say!();
        say!("case {} ({}): equivalent SDOF model of each mode (paper section 2.2, Eq. 12-13)", c.id, c.label);
        say!(
            "{:>4} {:>8} {:>10} {:>12} {:>11} {:>10} {:>9} {:>10} {:>8}",
            "mode",
            "q at",
            "M_i kg",
            "K_i N/m",
            "C_i N s/m",
            "F_i N",
            "mu_i",
            "m_d,i kg",
            "d mm"
        );
        for i in 0..n {
            let e = EquivalentSdof::new(&exp.structure, &c.dampers(), i, exp.excitation.mass, exp.excitation.force);
            let m = &e.mode;
            let d = if e.clearance.is_bounded() { format!("{:.3}", e.clearance.mm()) } else { "inf".into() };
            say!(
                "{:>4} {:>8} {:>10.5} {:>12.2} {:>11.5} {:>10.4} {:>9.5} {:>10.5} {:>8}",
                m.number,
                format!("m{}", m.reference_mass + 1),
                m.modal_mass,
                m.modal_stiffness,
                m.modal_damping,
                e.force,
                m.mass_ratio,
                e.damper_mass,
                d
            );
        }
    }
    Ok(())
}

/// `shotdamp damping`: the modal damping ratios that fit a digitised bare-structure curve.
pub(super) fn calibrate_damping(
    file: &Path,
    curve: &Path,
    model: Option<&str>,
    reference: &Path,
) -> anyhow::Result<()> {
    let done = runner::damping::calibrate(file, curve, model, reference)?;
    say!(
        "{}: {} curves, {} points; fitted: ln|x/F| at the points within {:.0} % of each natural frequency",
        curve.display(),
        done.curves,
        done.points,
        crate::model::damping_fit::BAND * 100.0
    );
    for m in &done.models {
        let fit = &m.fit;
        say!("{}: rms residual of ln(compliance) {:.4}", m.label, fit.rms_log_residual);
        say!("{:>4} {:>10} {:>8} {:>12}", "mode", "zeta", "points", "half-power");
        for (k, z) in fit.ratios.iter().enumerate() {
            let hp = fit.half_power[k].map(|v| format!("{v:.5}")).unwrap_or_else(|| "-".into());
            say!("{:>4} {:>10.5} {:>8} {:>12}", k + 1, z, fit.points[k], hp);
        }
        let list: Vec<String> = fit.ratios.iter().map(|z| format!("{z:.5}")).collect();
        say!("  in a model file: [structure.damping] modal_ratios = [{}]", list.join(", "));
    }
    Ok(())
}

/// The stiffness fitted to measured modes: the matrix, its condition, the residuals.
fn print_fit(fit: &crate::model::fit::StiffnessFit) {
    let n = fit.omegas.len();
    say!("stiffness fitted to the measured modes (N/m):");
    for i in 0..n {
        let row: Vec<String> = (0..n).map(|j| format!("{:>12.1}", fit.stiffness[(i, j)])).collect();
        say!("  [{}]", row.join(" "));
    }
    say!(
        "  condition {:.2}; {} of {} starts reached the best fit{}; measured shapes mass-orthogonal to {:.3}",
        fit.condition,
        fit.starts_at_best,
        fit.starts,
        if fit.unique() {
            " (the same matrix: unique)".to_string()
        } else {
            format!(" (NOT unique: their matrices differ by {:.1e} relative)", fit.spread)
        },
        fit.orthogonality
    );
    say!(
        "{:>4} {:>14} {:>14} {:>12}   shape (model), residual per element",
        "mode",
        "omega rad/s",
        "residual",
        "relative"
    );
    for i in 0..n {
        let measured = fit.omegas[i] - fit.frequency_residuals[i];
        let shape: Vec<String> =
            fit.shapes[i].iter().zip(&fit.shape_residuals[i]).map(|(v, r)| format!("{v:.4} ({r:+.4})")).collect();
        say!(
            "{:>4} {:>14.6} {:>14.3e} {:>12.3e}   {}",
            i + 1,
            fit.omegas[i],
            fit.frequency_residuals[i],
            fit.frequency_residuals[i] / measured,
            shape.join(", ")
        );
    }
    let worst = fit.shape_residuals.iter().flatten().fold(0.0_f64, |a, r| a.max(r.abs()));
    say!("  largest shape residual {worst:.4}");
}
