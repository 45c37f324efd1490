//! One row per container's host of the state matrix's first three powers and of their
//! products with the input matrix, computed with each configuration's decomposition: what
//! the contact decisions of large structures read (`contact`, whose note derives them).

use nalgebra::DMatrix;

/// The rows of one host (`h_1..h_3`, length `2n`; `g_0..g_2`, length `n`).
#[derive(Debug, Clone)]
pub struct HostRow {
    /// The host's coordinate.
    pub host: usize,
    pub(super) h: [Vec<f64>; 3],
    pub(super) g: [Vec<f64>; 3],
}

/// The rows of every bed's host in a configuration of state matrix `a` and inverse mass
/// `m_inv` (of `n` coordinates), one per bed, in the beds' order.
pub fn host_rows(a: &DMatrix<f64>, m_inv: &DMatrix<f64>, hosts: impl Iterator<Item = usize>) -> Vec<HostRow> {
    let n = m_inv.nrows();
    hosts
        .map(|p| {
            let h1: Vec<f64> = a.row(n + p).iter().copied().collect();
            let times_a =
                |h: &[f64]| -> Vec<f64> { (0..2 * n).map(|j| (0..2 * n).map(|i| h[i] * a[(i, j)]).sum()).collect() };
            let h2 = times_a(&h1);
            let h3 = times_a(&h2);
            // `h B`: the velocity half of `h` times `M^-1`.
            let times_b =
                |h: &[f64]| -> Vec<f64> { (0..n).map(|j| (0..n).map(|i| h[n + i] * m_inv[(i, j)]).sum()).collect() };
            let g0: Vec<f64> = m_inv.row(p).iter().copied().collect();
            let (g1, g2) = (times_b(&h1), times_b(&h2));
            HostRow { host: p, h: [h1, h2, h3], g: [g0, g1, g2] }
        })
        .collect()
}
