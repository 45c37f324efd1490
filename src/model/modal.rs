//! Modal analysis of the bare structure (docs/model.md sections 1 and 4).

use nalgebra::DVector;

use super::damper::Damper;
pub use super::modes::{symmetric_modes, Modes};
use super::structure::Structure;

/// One mode with the numbers the paper's equivalent SDOF analysis needs.
#[derive(Debug, Clone)]
pub struct ModeSummary {
    /// 1-based mode number.
    pub number: usize,
    /// Natural frequency, rad/s.
    pub omega: f64,
    /// Natural frequency, Hz.
    pub freq_hz: f64,
    /// Mode shape normalised so that its largest-magnitude element is +1 (phibar).
    pub shape: Vec<f64>,
    /// Index (0-based) of the mass with the largest modal amplitude.
    pub reference_mass: usize,
    /// The mode moves the structure's points (a reduced model's physical coordinates; every
    /// mass of a lumped one) by more than [`AT_POINTS`] of its largest coordinate. A mode that
    /// does not (a node at every point) is normalised by rounding at the points: its shape and
    /// modal quantities say nothing a damper at a point would feel.
    pub at_points: bool,
    /// Modal mass `phibar^T M0 phibar`, kg.
    pub modal_mass: f64,
    /// Modal stiffness `phibar^T K phibar`, N/m.
    pub modal_stiffness: f64,
    /// Modal damping `phibar^T C phibar`, N s/m.
    pub modal_damping: f64,
    /// Modal damping ratio `C_i / (2 M_i omega_i)`.
    pub damping_ratio: f64,
    /// Mass ratio `mu_i` of Eq. 13 for the damper set analysed (0 without dampers).
    pub mass_ratio: f64,
}

/// The least motion of the points, relative to the mode's largest coordinate, of a mode that
/// moves them ([`ModeSummary::at_points`]).
pub const AT_POINTS: f64 = 1e-6;

/// Modal analysis of a structure, with the mass ratios of Eq. 13 for `dampers`. Each shape
/// is scaled to 1 at its largest component among the masses (a reduced model's points: its
/// modal coordinates are no place to read a mode at), or among every coordinate when the mode
/// does not move the points at all.
pub fn modal_summary(structure: &Structure, dampers: &[Damper]) -> Vec<ModeSummary> {
    let m0 = structure.mass_matrix();
    let modes = symmetric_modes(&m0, &structure.stiffness);
    let n = structure.dof();
    let physical = structure.physical();
    (0..n)
        .map(|i| {
            let col = modes.mass_normalised.column(i);
            let moves = col.iter().take(physical).any(|v| *v != 0.0);
            // The points move by more than rounding of the mode's largest motion.
            let largest = |k: usize| col.iter().take(k).fold(0.0_f64, |a, v| a.max(v.abs()));
            let at_points = largest(physical) > AT_POINTS * largest(n);
            let among = if moves { physical } else { n };
            let (imax, _) =
                col.iter().take(among).enumerate().fold(
                    (0, 0.0_f64),
                    |acc, (j, v)| {
                        if v.abs() > acc.1 {
                            (j, v.abs())
                        } else {
                            acc
                        }
                    },
                );
            let scale = col[imax];
            let shape: DVector<f64> = col / scale;
            let modal_mass = (shape.transpose() * &m0 * &shape)[(0, 0)];
            let modal_stiffness = (shape.transpose() * &structure.stiffness * &shape)[(0, 0)];
            let modal_damping = (shape.transpose() * &structure.damping * &shape)[(0, 0)];
            let omega = modes.omegas[i];
            let mass_ratio = dampers.iter().map(|d| shape[d.host].abs() * d.mass).sum::<f64>() / modal_mass;
            ModeSummary {
                number: i + 1,
                omega,
                freq_hz: omega / (2.0 * std::f64::consts::PI),
                shape: shape.iter().copied().collect(),
                reference_mass: imax,
                at_points,
                modal_mass,
                modal_stiffness,
                modal_damping,
                damping_ratio: modal_damping / (2.0 * modal_mass * omega),
                mass_ratio,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::structure::Damping;

    fn paper() -> Structure {
        Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]))
    }

    #[test]
    fn eigen_residuals_are_tiny() {
        let s = paper();
        let m = s.mass_matrix();
        let modes = symmetric_modes(&m, &s.stiffness);
        for i in 0..3 {
            let phi = modes.mass_normalised.column(i);
            let w2 = modes.omegas[i].powi(2);
            let r = (&s.stiffness * phi - &m * phi * w2).norm();
            assert!(r < 1e-9 * (&s.stiffness * phi).norm(), "mode {i}: residual {r}");
            let mm = (phi.transpose() * &m * phi)[(0, 0)];
            assert!((mm - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn paper_chain_frequencies_match_model_md() {
        let modes = modal_summary(&paper(), &[]);
        let expected = [81.91, 218.51, 312.04];
        for (m, e) in modes.iter().zip(expected) {
            // 4 significant digits.
            assert!((m.omega - e).abs() / e < 5e-5 * 2.0, "{} vs {e}", m.omega);
        }
        let shapes = [[0.415, 0.783, 1.0], [1.0, 0.494, -0.909], [-0.840, 1.0, -0.466]];
        for (m, s) in modes.iter().zip(shapes) {
            for (a, b) in m.shape.iter().zip(s) {
                assert!((a - b).abs() < 6e-4, "{a} vs {b}");
            }
        }
        for m in &modes {
            assert!((m.damping_ratio - 0.01).abs() < 1e-12);
            assert!((m.modal_stiffness / m.modal_mass - m.omega.powi(2)).abs() < 1e-6 * m.omega.powi(2));
        }
    }

    #[test]
    fn mass_ratio_follows_eq13() {
        let s = paper();
        let dampers = [Damper::new(1, 0.071, crate::model::Clearance::NO_TOP)];
        let modes = modal_summary(&s, &dampers);
        for m in &modes {
            let expected = m.shape[1].abs() * 0.071 / m.modal_mass;
            assert!((m.mass_ratio - expected).abs() < 1e-15);
        }
        // Mode 3 peaks at m2, so mu_3 = m_d / M_3.
        assert!((modes[2].mass_ratio - 0.071 / modes[2].modal_mass).abs() < 1e-15);
    }
}
