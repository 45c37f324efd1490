//! The linearised flow's masses' rows carried in the real modal coordinates of the
//! configuration the motion is in (`sim::motion::modal`), above
//! [`LARGE_ABOVE`](crate::sim::motion::system::LARGE_ABOVE) degrees of freedom.
//!
//! With the derivative's masses' rows `D = B q` (`q` of `2L x k`), a segment of length `tau`
//! turns and decays each term's pair of rows (`c_r e^(lambda_r tau)`: `O(L k)`, no matrix
//! product); a change of configuration is one product with the transfer `T = P' B`; an impact
//! changes the masses' rows by two outer products (the momentum exchange moves the host's
//! velocity, and a coupled mass matrix every velocity with it, in proportion to one row; the
//! saltation's correction is a vector times the event function's gradient), each added to `q`
//! as `(P z) r^T` in `O(L (n + k))`; the rows an event reads (the host's position and
//! velocity, a resting bed's copy of them) are summed from `q` in `O(L k)` each. The physical
//! rows are formed once, when the run ends (`O(n L k)`). Against the transition matrix
//! formed and multiplied at every segment (three products of `2n`-square size), this is one
//! product an event that changes the configuration and none otherwise.

use nalgebra::{DMatrix, DMatrixView, DMatrixViewMut};
use num_complex::Complex64;

use crate::sim::motion::modal;
use crate::sim::motion::system::Dynamics;

/// The masses' rows of a derivative (`2n x k`) in the real modal coordinates of one
/// configuration.
#[derive(Debug, Clone)]
pub(super) struct Carried {
    /// The configuration's slot ([`Dynamics::slot`]).
    slot: usize,
    /// `2L x k`: the real parts of the terms' coefficients of each column, then their
    /// imaginary parts.
    q: DMatrix<f64>,
    /// The product's destination at a change of configuration (swapped with `q`).
    spare: DMatrix<f64>,
    /// A projected vector (`2L`) and the turn of each term over a segment (`L`).
    pz: Vec<f64>,
    turn: Vec<Complex64>,
    /// A row of `B` (`2L`).
    brow: Vec<f64>,
}

impl Carried {
    /// The masses' rows `top` (`2n x k`) seen from configuration `slot`: `q = P top`.
    pub fn enter(d: &Dynamics, slot: usize, top: DMatrixView<f64>) -> Carried {
        let modes = &d.configs[slot].modes;
        let len = modes.lambda.len();
        let [i_re, i_im] = &modes.inverse_parts;
        let mut q = DMatrix::zeros(2 * len, top.ncols());
        q.rows_mut(0, len).gemm(1.0, i_re, &top, 0.0);
        q.rows_mut(len, len).gemm(1.0, i_im, &top, 0.0);
        Carried { slot, q, spare: DMatrix::zeros(0, 0), pz: Vec::new(), turn: Vec::new(), brow: Vec::new() }
    }

    /// The same derivative seen from configuration `slot` (`q' = T q`, or through the
    /// physical rows where transfers are not kept).
    pub fn change(&mut self, d: &Dynamics, slot: usize) {
        if slot == self.slot {
            return;
        }
        let k = self.q.ncols();
        match d.transfer(self.slot, slot) {
            Some(t) => {
                if self.spare.shape() != (t.nrows(), k) {
                    self.spare = DMatrix::zeros(t.nrows(), k);
                }
                self.spare.gemm(1.0, t, &self.q, 0.0);
                std::mem::swap(&mut self.q, &mut self.spare);
                self.slot = slot;
            }
            None => {
                let mut top = DMatrix::zeros(2 * d.dof, k);
                self.physical_into(d, top.as_view_mut());
                *self = Carried::enter(d, slot, top.as_view());
            }
        }
    }

    /// Carries the derivative over `tau` in its configuration: each term's coefficients times
    /// `e^(lambda tau)`.
    pub fn advance(&mut self, d: &Dynamics, tau: f64) {
        let lambda = &d.configs[self.slot].modes.lambda;
        let len = lambda.len();
        self.turn.clear();
        self.turn.extend(lambda.iter().map(|l| (l * tau).exp()));
        if len == 0 {
            return;
        }
        for column in self.q.as_mut_slice().chunks_exact_mut(2 * len) {
            let (re, im) = column.split_at_mut(len);
            for ((a, b), e) in re.iter_mut().zip(im.iter_mut()).zip(&self.turn) {
                let (x, y) = (*a, *b);
                *a = x * e.re - y * e.im;
                *b = x * e.im + y * e.re;
            }
        }
    }

    /// Row `i` (`< 2n`: a displacement, then the velocities) of the masses' rows, into `out`
    /// (one number per column).
    pub fn row(&mut self, d: &Dynamics, i: usize, out: &mut [f64]) {
        let modes = &d.configs[self.slot].modes;
        let (n, len) = (d.dof, modes.lambda.len());
        let [re, im] = &modes.by_term[i / n];
        let p = i % n;
        // Row `i` of `B`, gathered once, then one contiguous dot product per column.
        self.brow.clear();
        self.brow.extend((0..len).map(|r| re[r * n + p]));
        self.brow.extend((0..len).map(|r| -im[r * n + p]));
        for (o, column) in out.iter_mut().zip(self.q.as_slice().chunks_exact(2 * len.max(1))) {
            *o = dot(&self.brow, column);
        }
    }

    /// `P z` of a vector of the masses' rows (`2n`), into `self.pz`.
    fn project(&mut self, d: &Dynamics, z: &[f64]) {
        let modes = &d.configs[self.slot].modes;
        let len = modes.lambda.len();
        let [i_re, i_im] = &modes.inverse_parts;
        self.pz.clear();
        self.pz.resize(2 * len, 0.0);
        let (re, im) = self.pz.split_at_mut(len);
        // Column `j` of each part is contiguous (column-major).
        let columns = i_re.as_slice().chunks_exact(len.max(1)).zip(i_im.as_slice().chunks_exact(len.max(1)));
        for ((c_re, c_im), &zj) in columns.zip(z) {
            if zj == 0.0 {
                continue;
            }
            for (o, w) in re.iter_mut().zip(c_re) {
                *o += w * zj;
            }
            for (o, w) in im.iter_mut().zip(c_im) {
                *o += w * zj;
            }
        }
    }

    /// Adds `z r^T` to the masses' rows (`z` of `2n`, `r` one number per column).
    pub fn add_outer(&mut self, d: &Dynamics, z: &[f64], r: &[f64]) {
        self.project(d, z);
        let rows = self.pz.len().max(1);
        for (column, &rc) in self.q.as_mut_slice().chunks_exact_mut(rows).zip(r) {
            if rc == 0.0 {
                continue;
            }
            for (o, p) in column.iter_mut().zip(&self.pz) {
                *o += p * rc;
            }
        }
    }

    /// Adds `scale z` to column `c` of the masses' rows.
    pub fn add_to_column(&mut self, d: &Dynamics, c: usize, z: &[f64], scale: f64) {
        self.project(d, z);
        let rows = self.pz.len();
        let column = &mut self.q.as_mut_slice()[c * rows..(c + 1) * rows];
        for (o, p) in column.iter_mut().zip(&self.pz) {
            *o += scale * p;
        }
    }

    /// The masses' rows, `B q`, into `top` (`2n x k`).
    pub fn physical_into(&self, d: &Dynamics, mut top: DMatrixViewMut<f64>) {
        let b = modal::basis(d.configs[self.slot].modes.coordinates());
        top.gemm(1.0, &b, &self.q, 0.0);
    }
}

/// `a . b` summed in four interleaved partial sums (independent additions the processor
/// overlaps; the order is fixed, so the sum is the same on every run).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (a4.remainder(), b4.remainder());
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}
