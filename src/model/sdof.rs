//! The equivalent single-degree-of-freedom model of one mode (paper section 2.2, docs/model.md
//! section 4): modal mass, stiffness and damping of the mode shape normalised to a largest
//! element of +1, the force on the mode, and the mass ratio of Eq. 13.

use nalgebra::DMatrix;

use super::damper::{Damper, Direction};
use super::modal::{modal_summary, ModeSummary};
use super::structure::{Damping, Structure};
use super::Clearance;

/// One mode as a single mass with one damper on it.
#[derive(Debug, Clone)]
pub struct EquivalentSdof {
    /// The mode (with its normalised shape and the mass ratio for the dampers given).
    pub mode: ModeSummary,
    /// `phibar_k F`: the force on the mode, N (its sign only shifts the phase).
    pub force: f64,
    /// Damper mass on the modal mass, `mu_i M_i`, kg.
    pub damper_mass: f64,
    /// The clearance of the damper, m (that of the dampers mapped onto the mode).
    pub clearance: Clearance,
    /// The direction its bed moves in (that of the dampers mapped onto the mode).
    pub direction: Direction,
}

impl EquivalentSdof {
    /// The equivalent SDOF model of mode `mode` (0-based) with `dampers` and a force `force`
    /// on mass `driven`. The dampers must share one clearance (the SDOF has one damper).
    pub fn new(structure: &Structure, dampers: &[Damper], mode: usize, driven: usize, force: f64) -> EquivalentSdof {
        let m = modal_summary(structure, dampers).swap_remove(mode);
        let clearance = dampers.first().map_or(Clearance::NO_TOP, |d| d.clearance);
        let direction = dampers.first().map_or(Direction::Vertical, |d| d.direction);
        EquivalentSdof {
            force: m.shape[driven] * force,
            damper_mass: m.mass_ratio * m.modal_mass,
            clearance,
            direction,
            mode: m,
        }
    }

    /// The SDOF as a structure: one mass `M_i`, stiffness `K_i`, damping `C_i` (as the
    /// modal damping ratio `C_i / (2 sqrt(K_i M_i))` of its single mode, which gives `C_i`).
    pub fn structure(&self) -> Structure {
        let m = &self.mode;
        let zeta = m.modal_damping / (2.0 * (m.modal_stiffness * m.modal_mass).sqrt());
        Structure::from_matrices(
            &[m.modal_mass],
            DMatrix::from_element(1, 1, m.modal_stiffness),
            Damping::ModalRatios(vec![zeta]),
        )
    }

    /// The damper of the SDOF.
    pub fn damper(&self) -> Damper {
        Damper::new(0, self.damper_mass, self.clearance).along(self.direction)
    }

    /// The response of mass `r` per unit SDOF coordinate (`phibar_ir`).
    pub fn shape(&self, r: usize) -> f64 {
        self.mode.shape[r]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn third_mode_with_a_damper_on_m2() {
        let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
        let d = [Damper::new(1, 0.071, Clearance::from_mm(0.4))];
        let e = EquivalentSdof::new(&s, &d, 2, 0, 2.6);
        // Mode 3 peaks at m2: the SDOF coordinate is m2's displacement, the damper keeps its mass.
        assert_eq!(e.mode.reference_mass, 1);
        assert!((e.damper_mass - 0.071).abs() < 1e-15);
        assert!((e.force - e.mode.shape[0] * 2.6).abs() < 1e-15);
        let sdof = e.structure();
        assert!((sdof.damping[(0, 0)] - e.mode.modal_damping).abs() < 1e-12 * e.mode.modal_damping);
        let w = (sdof.stiffness[(0, 0)] / sdof.masses[0]).sqrt();
        assert!((w - e.mode.omega).abs() < 1e-9 * w);
    }
}
