//! Harmonic motion of a structure's supports (docs/model.md section 2.3): the supports
//! accelerate as `a_g(t) = A sin(omega t)` along the structure's direction of motion.
//!
//! The physics is written relative to the base (`u = x - r x_g`, `r` the influence vector:
//! ones for a chain): `M_S uddot + C udot + K u = -L a_g(t) + ...` with `L = M_S r`, and a
//! riding bed adds `-m_d r_p a_g` at its host. The simulator works in coordinates that follow
//! the supports at the hosts, `x = u + r x_g`: there the beds fly, land and ride exactly as
//! over a fixed floor (their own motion, impacts and contact forces are absolute), and the
//! load is the same in every configuration (a riding bed's inertia term cancels):
//! `f(t) = (M_S r - L) a_g + C r v_g + K r x_g`, harmonic at `omega` (`x_g = -A sin(omega t) /
//! omega^2`, `v_g = -A cos(omega t) / omega`). For a chain `M_S r - L` is zero and the load is
//! the springs' and dashpots' pull from the moving ground.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::Structure;

/// What drives a structure, for the words and units of its amplitude and its responses: a
/// force `F sin(omega t)` on one mass, or its supports accelerating as `A sin(omega t)`
/// (responses then relative to them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    /// A force on one mass, N.
    Force,
    /// The supports' acceleration, m/s^2.
    Supports,
}

impl Drive {
    /// The drive of a structure whose supports move (`true`) or that a force drives.
    pub fn of(supports: bool) -> Drive {
        if supports {
            Drive::Supports
        } else {
            Drive::Force
        }
    }

    /// The unit of the amplitude: "N" or "m/s^2".
    pub fn unit(self) -> &'static str {
        match self {
            Drive::Force => "N",
            Drive::Supports => "m/s^2",
        }
    }

    /// An amplitude in words, `value` already formatted: "2.6 N" or "3 m/s^2".
    pub fn amount(self, value: &str) -> String {
        format!("{value} {}", self.unit())
    }

    /// The unit of a response over the amplitude: "m/N", or "m/(m/s^2)" (displacement
    /// relative to the supports per unit of their acceleration).
    pub fn per_unit(self) -> &'static str {
        match self {
            Drive::Force => "m/N",
            Drive::Supports => "m/(m/s^2)",
        }
    }

    /// The amplitude's symbol: "F" or "A".
    pub fn symbol(self) -> &'static str {
        match self {
            Drive::Force => "F",
            Drive::Supports => "A",
        }
    }

    /// The response over the amplitude, in symbols: "|x / F|" or "|u / A|".
    pub fn ratio(self) -> &'static str {
        match self {
            Drive::Force => "|x / F|",
            Drive::Supports => "|u / A|",
        }
    }

    /// What drives, in words: "force" or "support acceleration".
    pub fn name(self) -> &'static str {
        match self {
            Drive::Force => "force",
            Drive::Supports => "support acceleration",
        }
    }
}

/// How a structure's coordinates follow a unit rigid motion of its supports: `r` and the
/// inertia load `L` per unit support acceleration. A chain's is `r = 1`, `L = M_S r`
/// ([`BaseMotion::rigid`]); a reduced finite-element model's is `r` at its physical points
/// (0 on its modal coordinates) and `L = T^T M r_full`, the full model's inertia load projected.
#[derive(Debug, Clone, PartialEq)]
pub struct Supports {
    /// `r` per coordinate.
    pub follow: Vec<f64>,
    /// `L` per coordinate, kg.
    pub load: Vec<f64>,
    /// The direction the supports move in, in words (e.g. "z").
    pub direction: String,
}

/// Harmonic support acceleration `A sin(omega t)` of one structure.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseMotion {
    /// Acceleration amplitude `A`, m/s^2.
    pub accel: f64,
    /// `r`: how far each coordinate moves with a unit rigid motion of the supports (ones for
    /// a chain: every mass translates along the supports' direction).
    pub follow: Vec<f64>,
    /// `L`: the inertia load per unit support acceleration, kg (`M_S r` for a chain).
    pub load: Vec<f64>,
}

impl BaseMotion {
    /// The supports of `structure` accelerating at `accel`: along its own [`Supports`] when it
    /// has them (a reduced finite-element model), else [`BaseMotion::rigid`].
    pub fn of(structure: &Structure, accel: f64) -> BaseMotion {
        match &structure.supports {
            Some(s) => BaseMotion { accel, follow: s.follow.clone(), load: s.load.clone() },
            None => BaseMotion::rigid(structure, accel),
        }
    }

    /// The supports of a structure whose every coordinate translates along their direction
    /// (a chain, a shear building, any lumped structure): `r = 1`, `L = M_S r`.
    pub fn rigid(structure: &Structure, accel: f64) -> BaseMotion {
        let n = structure.dof();
        let follow = vec![1.0; n];
        let load = (structure.mass_matrix() * DVector::from_element(n, 1.0)).iter().copied().collect();
        BaseMotion { accel, follow, load }
    }

    /// The support displacement's amplitude `X_g = -A / omega^2`: `x_g(t) = X_g sin(omega t)`.
    pub fn displacement(&self, omega: f64) -> f64 {
        -self.accel / (omega * omega)
    }

    /// The load's phasor `F` (`f(t) = Im(F e^{i omega t})`) in the simulator's coordinates and
    /// its derivative in `omega`, for a structure of stiffness `k`, damping `c` and bare mass
    /// matrix `m`.
    pub fn load_phasor(
        &self,
        k: &DMatrix<f64>,
        c: &DMatrix<f64>,
        m: &DMatrix<f64>,
        omega: f64,
    ) -> (Vec<Complex64>, Vec<Complex64>) {
        let a = self.accel;
        let r = DVector::from_column_slice(&self.follow);
        let (kr, cr, mr) = (k * &r, c * &r, m * &r);
        // a_g: A; v_g: -i A / omega; x_g: -A / omega^2.
        let f = (0..r.len())
            .map(|i| Complex64::new((mr[i] - self.load[i]) * a - kr[i] * a / (omega * omega), -cr[i] * a / omega))
            .collect();
        let df = (0..r.len())
            .map(|i| Complex64::new(2.0 * kr[i] * a / (omega * omega * omega), cr[i] * a / (omega * omega)))
            .collect();
        (f, df)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Damping;

    #[test]
    fn a_chain_is_pulled_only_through_its_ground_spring_and_dashpot() {
        // Stiffness-proportional damping: C r = beta K r = beta k1 e_1.
        let s = Structure::chain(&[2.0, 3.0, 1.5], &[4e4, 2e4, 1e4], Damping::Rayleigh { alpha: 0.0, beta: 1e-4 });
        let b = BaseMotion::rigid(&s, 2.0);
        let omega = 60.0;
        let (f, df) = b.load_phasor(&s.stiffness, &s.damping, &s.mass_matrix(), omega);
        let xg = b.displacement(omega);
        assert!((f[0].re - 4e4 * xg).abs() < 1e-12 * 4e4 * xg.abs());
        assert!((f[0].im - 1e-4 * 4e4 * omega * xg).abs() < 1e-12 * 4e4 * xg.abs());
        for z in &f[1..] {
            assert!(z.norm() < 1e-12 * 4e4 * xg.abs(), "{z}");
        }
        // The derivative in omega against a central difference.
        let h = 1e-5 * omega;
        let (fp, _) = b.load_phasor(&s.stiffness, &s.damping, &s.mass_matrix(), omega + h);
        let (fm, _) = b.load_phasor(&s.stiffness, &s.damping, &s.mass_matrix(), omega - h);
        let fd = (fp[0] - fm[0]) / (2.0 * h);
        assert!((fd - df[0]).norm() < 1e-7 * df[0].norm(), "{fd} vs {}", df[0]);
    }
}
