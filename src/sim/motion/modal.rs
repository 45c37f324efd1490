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

/// What the coordinates of one configuration are made of (held by its decomposition,
/// `Modes::coordinates`): the weighted eigenvectors' displacement and velocity rows by term
/// (`by_term[order][part][r * n + p]`) and the real and imaginary parts of the terms' rows of
/// `V^-1` (`L x 2n`).
#[derive(Debug, Clone, Copy)]
pub struct Coordinates<'a> {
    /// Degrees of freedom.
    pub n: usize,
    /// Terms (`L`).
    pub terms: usize,
    /// The eigenvectors' rows by term.
    pub by_term: &'a [[Vec<f64>; 2]; 2],
    /// The parts of the terms' rows of `V^-1`.
    pub inverse_parts: &'a [DMatrix<f64>; 2],
}

/// Most configurations whose transfers are kept (`slots^2` entries, each formed when first
/// needed): 64 configurations (six beds) hold at most 4,096. Above, a change of
/// configuration goes through the physical coordinates (two products instead of one).
pub const MAX_TRANSFER_SLOTS: usize = 64;

/// `B = [Re(V_w) | -Im(V_w)]` of a configuration (`2n x 2L`): column `r` the real part of
/// term `r`'s weighted eigenvector (displacements, then velocities), column `L + r` minus its
/// imaginary part.
pub fn basis(c: Coordinates) -> DMatrix<f64> {
    let (n, len) = (c.n, c.terms);
    let mut b = DMatrix::zeros(2 * n, 2 * len);
    for r in 0..len {
        for order in 0..2 {
            let [re, im] = &c.by_term[order];
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
pub fn transfer(from: Coordinates, to: Coordinates) -> DMatrix<f64> {
    let b = basis(from);
    let [i_re, i_im] = to.inverse_parts;
    let len = to.terms;
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

    /// The transfer from configuration `from` to `to` (slots), formed from their coordinates
    /// when first asked for; `None` when transfers are not kept.
    pub fn get<'a>(&self, from: usize, to: usize, of: impl Fn(usize) -> Coordinates<'a>) -> Option<&DMatrix<f64>> {
        if from >= self.slots || to >= self.slots {
            return None;
        }
        Some(self.cells[from * self.slots + to].get_or_init(|| transfer(of(from), of(to))))
    }
}
