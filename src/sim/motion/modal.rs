//! A configuration's real modal coordinates, and the change of coordinates from one
//! configuration to another (above [`LARGE_ABOVE`] degrees of freedom).
//!
//! A state `z = (x, v)` of configuration `S` is `z = Re(sum_r w_r V_r c_r)` over its terms
//! (one eigenvalue of each conjugate pair, weight 2, and the real ones), `c = V^-1 z`. Its real
//! modal coordinates are `q = (Re c, Im c)` (`2L` numbers for `L` terms), so that
//! `z = B q` with `B = [Re(V_w) | -Im(V_w)]` (`2n x 2L`) and `q = P z` with
//! `P = [Re(V^-1); Im(V^-1)]` (`2L x 2n`, the terms' rows). Between events each term's
//! coefficient only turns and decays (`c_r e^(lambda_r tau)`); the same state seen from
//! configuration `S'` is `q' = P' B q`: the transfer `T = P' B` (`2L' x 2L`), formed once per
//! pair of configurations and shared by every forcing frequency ([`Transfers`]). The
//! linearised flow carries its derivative so (`sim::orbits::tangent`).
//!
//! [`LARGE_ABOVE`]: super::system::LARGE_ABOVE

use std::sync::OnceLock;

use nalgebra::DMatrix;

use super::system::Modes;

/// Most configurations whose transfers are kept (`slots^2` entries, each formed when first
/// needed): 64 configurations (six beds) hold at most 4,096. Above, a change of
/// configuration goes through the physical coordinates (two products instead of one).
pub const MAX_TRANSFER_SLOTS: usize = 64;

/// `B = [Re(V_w) | -Im(V_w)]` of a configuration (`2n x 2L`): column `r` the real part of
/// term `r`'s weighted eigenvector (displacements, then velocities), column `L + r` minus its
/// imaginary part.
pub fn basis(modes: &Modes) -> DMatrix<f64> {
    let n = modes.vl.len();
    let len = modes.lambda.len();
    let mut b = DMatrix::zeros(2 * n, 2 * len);
    for r in 0..len {
        for order in 0..2 {
            let [re, im] = &modes.by_term[order];
            for p in 0..n {
                b[(order * n + p, r)] = re[r * n + p];
                b[(order * n + p, len + r)] = -im[r * n + p];
            }
        }
    }
    b
}

/// `T = P' B` (`2L' x 2L`): the real modal coordinates in configuration `to` of a state given
/// by its coordinates in `from`. Needs the parts of `to`'s inverse (held above
/// [`LARGE_ABOVE`](super::system::LARGE_ABOVE) degrees of freedom).
pub fn transfer(from: &Modes, to: &Modes) -> DMatrix<f64> {
    let b = basis(from);
    let [i_re, i_im] = &to.inverse_parts;
    let len = to.lambda.len();
    let mut t = DMatrix::zeros(2 * len, b.ncols());
    t.rows_mut(0, len).gemm(1.0, i_re, &b, 0.0);
    t.rows_mut(len, len).gemm(1.0, i_im, &b, 0.0);
    t
}

/// The transfers between every pair of configurations of a structure, formed when first
/// needed and shared by the dynamics at every forcing frequency; none (`slots() == 0`) up to
/// [`LARGE_ABOVE`](super::system::LARGE_ABOVE) degrees of freedom or above
/// [`MAX_TRANSFER_SLOTS`] configurations.
#[derive(Debug, Clone, Default)]
pub struct Transfers {
    slots: usize,
    cells: Vec<OnceLock<DMatrix<f64>>>,
}

impl Transfers {
    /// Room for `slots` configurations (none when `keep` is false or there are too many).
    pub fn new(slots: usize, keep: bool) -> Transfers {
        let slots = if keep && slots <= MAX_TRANSFER_SLOTS { slots } else { 0 };
        Transfers { slots, cells: (0..slots * slots).map(|_| OnceLock::new()).collect() }
    }

    /// The transfer from configuration `from` to `to` (slots), formed from `modes` when first
    /// asked for; `None` when transfers are not kept.
    pub fn get<'a>(&'a self, from: usize, to: usize, modes: impl Fn(usize) -> &'a Modes) -> Option<&'a DMatrix<f64>> {
        if from >= self.slots || to >= self.slots {
            return None;
        }
        Some(self.cells[from * self.slots + to].get_or_init(|| transfer(modes(from), modes(to))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::system::{Dynamics, System};

    /// A configuration's coordinates are a change of basis (`P B = I`, so `T` from a
    /// configuration to itself is the identity), and a transfer carries a state as its
    /// physical form does (`B' T q = B q`), on a chain with a resting bed's mass.
    #[test]
    fn transfers_are_changes_of_basis() {
        let n = 12;
        let s = Structure::chain(&vec![0.2; n], &vec![8e4; n], Damping::Rayleigh { alpha: 3.0, beta: 2e-5 });
        let dampers = (n - 2..n).map(|h| Damper::new(h, 0.05, Clearance::from_m(5e-4))).collect();
        let d = Dynamics::new(&System::plastic(s, dampers, 0, 2.0), 100.0).unwrap();
        let same = d.transfer(1, 1).unwrap();
        let identity = DMatrix::<f64>::identity(same.nrows(), same.ncols());
        assert!((same - &identity).amax() < 1e-11, "{:e}", (same - &identity).amax());
        let q = DMatrix::from_fn(same.ncols(), 3, |r, c| 1.0 / (1.0 + r as f64 + 2.0 * c as f64));
        for (from, to) in [(0, 3), (3, 1), (2, 0)] {
            let t = d.transfer(from, to).unwrap();
            let want = basis(&d.configs[from].modes) * &q;
            let got = basis(&d.configs[to].modes) * (t * &q);
            assert!((&got - &want).amax() <= 1e-11 * want.amax(), "{from} -> {to}: {:e}", (&got - &want).amax());
        }
        // Not kept up to LARGE_ABOVE degrees of freedom.
        let small = Structure::chain(&[0.2; 3], &[8e4; 3], Damping::ModalRatios(vec![0.02; 3]));
        let d =
            Dynamics::new(&System::plastic(small, vec![Damper::new(2, 0.02, Clearance::from_m(5e-4))], 0, 2.0), 100.0);
        assert!(d.unwrap().transfer(0, 1).is_none());
    }
}
