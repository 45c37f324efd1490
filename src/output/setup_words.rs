//! The words of an experiment's setup: the report's parameter table and the assumptions a run
//! rests on, written from the experiment as validated (the analyses return numbers; the
//! sentences about what they were given are written here).

use crate::experiment::{Analysis, Experiment};
use crate::model::Damping;
use crate::number::{fmt_num, fmt_sig};

fn list(v: &[f64]) -> String {
    v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(", ")
}

/// Rows of a matrix the parameter table lists in full; a larger one (a reduced finite-element
/// model's) is given by its size and diagonal.
const LISTED_ROWS: usize = 12;

/// A matrix of the structure as the parameter table gives it: its rows, or above
/// [`LISTED_ROWS`] its size and diagonal.
fn matrix(m: &nalgebra::DMatrix<f64>) -> String {
    if m.nrows() > LISTED_ROWS {
        let diagonal: Vec<f64> = m.diagonal().iter().copied().collect();
        return format!("{0} x {0}, not listed; its diagonal: [{1}]", m.nrows(), list(&diagonal));
    }
    (0..m.nrows())
        .map(|i| format!("[{}]", list(&m.row(i).iter().copied().collect::<Vec<_>>())))
        .collect::<Vec<_>>()
        .join(" ")
}

/// ", rows" where [`matrix`] lists them.
fn rows_word(m: &nalgebra::DMatrix<f64>) -> &'static str {
    if m.nrows() > LISTED_ROWS {
        ""
    } else {
        ", rows"
    }
}

/// Modal damping ratios: listed, or above [`LISTED_ROWS`] modes with one ratio for all, that
/// ratio once.
fn ratios(z: &[f64]) -> String {
    match z.split_first() {
        Some((first, rest)) if z.len() > LISTED_ROWS && rest.iter().all(|x| x == first) => {
            format!("modal ratio zeta = {} for each of the {} modes", fmt_num(*first), z.len())
        }
        _ => format!("modal ratios zeta = [{}]", list(z)),
    }
}

/// The parameter table of the report.
pub fn parameters(exp: &Experiment) -> Vec<(String, String)> {
    let s = &exp.structure;
    let masses = match &s.coupled_mass {
        None => ("masses m_1..m_n (kg)".to_string(), list(&s.masses)),
        Some(m) => (format!("mass matrix M0 (kg){} (not diagonal: coordinates, not masses)", rows_word(m)), matrix(m)),
    };
    let mut p = vec![
        masses,
        (format!("stiffness K (N/m){}", rows_word(&s.stiffness)), matrix(&s.stiffness)),
        (
            "damping".to_string(),
            match &s.damping_spec {
                Damping::ModalRatios(z) => ratios(z),
                Damping::Rayleigh { alpha, beta } => {
                    format!("Rayleigh alpha = {} 1/s, beta = {} s", fmt_num(*alpha), fmt_num(*beta))
                }
            },
        ),
        ("excitation".to_string(), exp.excitation.describe()),
        ("analysis".to_string(), exp.analysis.kind().to_string()),
    ];
    if let Some(m) = &exp.model {
        p.insert(0, ("model".to_string(), format!("{} ({}): {}", m.label, m.id, m.description)));
    }
    if let Some(f) = &exp.fit {
        let worst = f.shape_residuals.iter().flatten().fold(0.0_f64, |a, r| a.max(r.abs()));
        let freq = f
            .frequency_residuals
            .iter()
            .zip(&f.omegas)
            .map(|(r, w)| format!("{:.1e}", r / (w - r)))
            .collect::<Vec<_>>()
            .join(", ");
        p.push((
            "stiffness fit".to_string(),
            format!(
                "Levenberg-Marquardt from {} starts, {} at the best fit ({}); condition of K {:.2}; relative frequency residuals [{freq}]; largest mode-shape residual {:.4}; measured shapes mass-orthogonal to {:.3}",
                f.starts,
                f.starts_at_best,
                if f.unique() { "unique" } else { "NOT unique" },
                f.condition,
                worst,
                f.orthogonality
            ),
        ));
    }
    if let Analysis::LinearFrf { freq_hz } = &exp.analysis {
        if let (Some(a), Some(b)) = (freq_hz.first(), freq_hz.last()) {
            p.push((
                "frequency grid (Hz)".into(),
                format!("{} to {}, {} points", fmt_num(*a), fmt_num(*b), freq_hz.len()),
            ));
        }
    }
    // A coupled mass matrix's diagonal is no mass at a point (a reduced model's): a shot is
    // stated against the lowest mode's modal mass there instead.
    let at_point = (!s.is_lumped()).then(|| crate::model::modal::symmetric_modes(&s.mass_matrix(), &s.stiffness));
    let mu = |d: &crate::model::Damper| match &at_point {
        None => format!("mu = {}", fmt_num(d.mass / s.masses[d.host])),
        Some(modes) => {
            let row = modes.mass_normalised.row(d.host);
            let largest = modes.mass_normalised.amax();
            match row.iter().position(|phi| phi.abs() > 1e-6 * largest) {
                // phi normalised to 1 at the point: its modal mass is 1 / phi_p^2.
                Some(i) => format!(
                    "mu = {} of mode {}'s modal mass at the point, {} kg",
                    fmt_sig(d.mass * row[i] * row[i], 3),
                    i + 1,
                    fmt_sig(1.0 / (row[i] * row[i]), 4)
                ),
                None => "no mode moves the point".to_string(),
            }
        }
    };
    for c in &exp.cases {
        let d = if c.beds.is_empty() {
            "no damper".to_string()
        } else {
            c.beds
                .iter()
                .map(|b| {
                    let (d, law, grains) = (&b.damper, b.law, b.grains);
                    let clr = d.clearance.to_string();
                    let sticks =
                        law.stick_speed().map_or(String::new(), |v| format!(" (sticks below {} m/s)", fmt_num(v)));
                    let bed = if grains > 1 {
                        format!(
                            ", a column of {grains} grains, restitution e = {}{}",
                            fmt_num(law.restitution()),
                            sticks
                        )
                    } else if !law.is_plastic() {
                        format!(", restitution e = {}{sticks}", fmt_num(law.restitution()))
                    } else {
                        String::new()
                    };
                    let along = match d.direction {
                        crate::model::Direction::Vertical => "",
                        crate::model::Direction::Horizontal => ", horizontal",
                    };
                    format!("m_{}: m_d = {} kg ({}), d = {clr}{bed}{along}", d.host + 1, fmt_num(d.mass), mu(d))
                })
                .collect::<Vec<_>>()
                .join("; ")
        };
        p.push((format!("case {} ({})", c.id, c.label), d));
    }
    p
}

/// The assumptions a run rests on: derived from the model settings, then the file's own.
pub fn assumptions(exp: &Experiment) -> Vec<String> {
    let mut a = Vec::new();
    let damping = match &exp.structure.damping_spec {
        Damping::ModalRatios(z) => format!("Damping of the bare structure: modal damping ratios [{}]", list(z)),
        Damping::Rayleigh { alpha, beta } => {
            format!("Damping of the bare structure: Rayleigh alpha = {}, beta = {}", fmt_num(*alpha), fmt_num(*beta))
        }
    };
    a.push(match &exp.damping_assumption {
        Some(why) => format!("{damping} ({why})."),
        None => format!("{damping}."),
    });
    if let Some(src) = &exp.structure_source {
        a.push(format!("Structure: {src}."));
    }
    for c in &exp.cases {
        for (d, law, n) in c.beds.iter().filter(|b| b.grains > 1).map(|b| (&b.damper, b.law, b.grains)) {
            a.push(format!(
                "Case {}: the bed on m_{} is a column of {n} equal grains (total mass unchanged) with restitution e = {} between grains and against the ends{}; grains resting on an end move with it, grains in free flight meet in binary collisions resolved in sequence (docs/model.md, \"Bed models\"); the paper's bed is one plastic mass.",
                c.id,
                d.host + 1,
                fmt_num(law.restitution()),
                law.stick_speed().map_or(String::new(), |v| format!(", sticking below {} m/s", fmt_num(v)))
            ));
        }
        for (d, law) in c.beds.iter().filter(|b| !b.law.is_plastic() && b.grains <= 1).map(|b| (&b.damper, b.law)) {
            a.push(format!(
                "Case {}: the bed on m_{} bounces off its container's ends with restitution e = {} and sticks below {} m/s (the paper's bed is plastic, e = 0).",
                c.id,
                d.host + 1,
                fmt_num(law.restitution()),
                fmt_num(law.stick_speed().unwrap_or(0.0))
            ));
        }
    }
    for c in &exp.cases {
        for d in c.beds.iter().map(|b| &b.damper).filter(|d| d.direction == crate::model::Direction::Horizontal) {
            a.push(format!(
                "Case {}: the container on m_{} is horizontal: no gravity along its bed's motion, which flies at constant velocity between two walls {} apart and hits either; friction with the container's floor is neglected (docs/model.md section 5; the paper's containers are vertical).",
                c.id,
                d.host + 1,
                d.clearance
            ));
        }
    }
    a.extend(exp.meta.assumptions.iter().cloned());
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    #[test]
    fn a_large_matrix_is_given_by_its_size_and_diagonal() {
        let small = DMatrix::<f64>::identity(3, 3);
        assert_eq!(matrix(&small), "[1, 0, 0] [0, 1, 0] [0, 0, 1]");
        assert_eq!(rows_word(&small), ", rows");
        let large = DMatrix::from_fn(13, 13, |i, j| if i == j { i as f64 + 1.0 } else { 0.5 });
        let words = matrix(&large);
        assert!(words.starts_with("13 x 13, not listed; its diagonal: [1, 2, 3,"), "{words}");
        assert!(words.ends_with(", 13]") && !words.contains("0.5"), "{words}");
        assert_eq!(rows_word(&large), "");
    }

    #[test]
    fn many_equal_damping_ratios_are_given_once() {
        assert_eq!(ratios(&[0.01; 3]), "modal ratios zeta = [0.01, 0.01, 0.01]");
        assert_eq!(ratios(&[0.01; 25]), "modal ratio zeta = 0.01 for each of the 25 modes");
        let mut mixed = vec![0.01; 25];
        mixed[7] = 0.02;
        assert!(ratios(&mixed).starts_with("modal ratios zeta = [0.01,"));
    }
}
