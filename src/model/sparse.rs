//! Sparse symmetric matrices of finite-element models and their `L D L^T` factor in envelope
//! (skyline) storage after a reverse Cuthill-McKee ordering: the solves of a Craig-Bampton
//! reduction, the shift-invert eigen solver ([`super::lanczos`]) and the full model's
//! compliance. The factor counts its negative pivots: Sylvester's inertia gives the number of
//! eigenvalues of `(K, M)` below a shift, which certifies that no mode was missed. Pure Rust,
//! no I/O. Work grows as `n b^2` and memory as `n b` for `n` degrees of freedom and an
//! envelope `b` wide (docs/fe-models.md gives the numbers).

use nalgebra::DMatrix;

/// A symmetric matrix by its lower triangle (diagonal included), row by row.
#[derive(Debug, Clone, PartialEq)]
pub struct SymSparse {
    n: usize,
    /// Row `i`'s entries are `cols[ptr[i]..ptr[i + 1]]`, ascending, the last `i` itself.
    ptr: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
}

/// A symmetric matrix given with an entry on both sides of the diagonal that differ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asymmetry {
    /// Row (0-based) of the entry below the diagonal.
    pub row: usize,
    /// Its column.
    pub col: usize,
    /// Its value.
    pub lower: f64,
    /// The value above the diagonal.
    pub upper: f64,
}

impl SymSparse {
    /// The `n x n` matrix of `entries` `(row, col, value)`, 0-based, repeated entries summed.
    /// `one_triangle`: each off-diagonal pair is given once (either side); otherwise both
    /// sides are given and must agree to `1e-9` of the largest entry (or the first that does
    /// not is returned).
    pub fn from_entries(
        n: usize,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
        one_triangle: bool,
    ) -> Result<SymSparse, Asymmetry> {
        let mut lower: Vec<(usize, usize, f64)> = Vec::new();
        let mut upper: Vec<(usize, usize, f64)> = Vec::new();
        for (i, j, v) in entries {
            if i >= j || one_triangle {
                lower.push((i.max(j), i.min(j), v));
            } else {
                upper.push((j, i, v));
            }
        }
        let a = Self::assemble(n, lower);
        if one_triangle {
            return Ok(a);
        }
        let u = Self::assemble(n, upper);
        let scale = a.vals.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            let (mut p, mut q) = (a.ptr[i], u.ptr[i]);
            // Walk both rows below the diagonal in column order.
            loop {
                let ca = if p < a.ptr[i + 1] && a.cols[p] < i { Some(a.cols[p]) } else { None };
                let cu = if q < u.ptr[i + 1] { Some(u.cols[q]) } else { None };
                // The next column of either row; an entry on one side only meets zero.
                let next = match (ca, cu) {
                    (None, None) => break,
                    (Some(x), None) => x,
                    (None, Some(y)) => y,
                    (Some(x), Some(y)) => x.min(y),
                };
                let lo = if ca == Some(next) {
                    p += 1;
                    a.vals[p - 1]
                } else {
                    0.0
                };
                let up = if cu == Some(next) {
                    q += 1;
                    u.vals[q - 1]
                } else {
                    0.0
                };
                let col = next;
                if (lo - up).abs() > 1e-9 * scale {
                    return Err(Asymmetry { row: i, col, lower: lo, upper: up });
                }
            }
        }
        Ok(a)
    }

    /// Row-sorted lower-triangle storage of `(row >= col)` entries, repeats summed, every
    /// diagonal present (zero if not given).
    fn assemble(n: usize, mut e: Vec<(usize, usize, f64)>) -> SymSparse {
        e.extend((0..n).map(|i| (i, i, 0.0)));
        // Stable: repeated entries are summed in the order given.
        e.sort_by_key(|x| (x.0, x.1));
        let mut ptr = vec![0; n + 1];
        let (mut cols, mut vals) = (Vec::with_capacity(e.len()), Vec::with_capacity(e.len()));
        let mut last = None;
        for (i, j, v) in e {
            if last == Some((i, j)) {
                if let Some(x) = vals.last_mut() {
                    *x += v;
                }
                continue;
            }
            last = Some((i, j));
            cols.push(j);
            vals.push(v);
            ptr[i + 1] += 1;
        }
        for i in 0..n {
            ptr[i + 1] += ptr[i];
        }
        SymSparse { n, ptr, cols, vals }
    }

    /// Order.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Stored entries (the lower triangle).
    pub fn stored(&self) -> usize {
        self.vals.len()
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.vals[self.ptr[i + 1] - 1]).collect()
    }

    /// Row `i` below and on the diagonal: `(column, value)`.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let r = self.ptr[i]..self.ptr[i + 1];
        self.cols[r.clone()].iter().copied().zip(self.vals[r].iter().copied())
    }

    /// `y = A x`.
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for i in 0..self.n {
            let mut s = 0.0;
            for (j, v) in self.row(i) {
                s += v * x[j];
                if j != i {
                    y[j] += v * x[i];
                }
            }
            y[i] += s;
        }
    }

    /// `x^T A x` summed over every entry with `x` all ones: the sum of all entries.
    pub fn sum(&self) -> f64 {
        (0..self.n).flat_map(|i| self.row(i).map(move |(j, v)| if j == i { v } else { 2.0 * v })).sum()
    }

    /// The principal submatrix on `keep` (in that order).
    pub fn principal(&self, keep: &[usize]) -> SymSparse {
        let mut at = vec![usize::MAX; self.n];
        for (new, &old) in keep.iter().enumerate() {
            at[old] = new;
        }
        let mut e = Vec::new();
        for (new, &old) in keep.iter().enumerate() {
            for (j, v) in self.row(old) {
                if at[j] != usize::MAX {
                    e.push((new, at[j], v));
                }
            }
            // An entry above the diagonal of `old` is stored in a later row: met there.
        }
        Self::assemble(keep.len(), e.into_iter().map(|(i, j, v)| (i.max(j), i.min(j), v)).collect())
    }

    /// The rows `rows` and columns `cols` as a dense matrix.
    pub fn block(&self, rows: &[usize], cols: &[usize]) -> DMatrix<f64> {
        let (mut at_r, mut at_c) = (vec![usize::MAX; self.n], vec![usize::MAX; self.n]);
        rows.iter().enumerate().for_each(|(k, &r)| at_r[r] = k);
        cols.iter().enumerate().for_each(|(k, &c)| at_c[c] = k);
        let mut out = DMatrix::zeros(rows.len(), cols.len());
        for i in 0..self.n {
            for (j, v) in self.row(i) {
                if at_r[i] != usize::MAX && at_c[j] != usize::MAX {
                    out[(at_r[i], at_c[j])] += v;
                }
                if i != j && at_r[j] != usize::MAX && at_c[i] != usize::MAX {
                    out[(at_r[j], at_c[i])] += v;
                }
            }
        }
        out
    }

    /// The dense matrix.
    pub fn to_dense(&self) -> DMatrix<f64> {
        let all: Vec<usize> = (0..self.n).collect();
        self.block(&all, &all)
    }

    /// Neighbours of each row (the graph of the pattern).
    fn graph(&self) -> Vec<Vec<usize>> {
        let mut adj = vec![Vec::new(); self.n];
        for i in 0..self.n {
            for (j, _) in self.row(i) {
                if j != i {
                    adj[i].push(j);
                    adj[j].push(i);
                }
            }
        }
        adj
    }
}

/// Reverse Cuthill-McKee: a permutation `perm` (new position -> old index) that keeps the
/// pattern's entries near the diagonal. Each connected part starts from a pseudo-peripheral
/// row (the far end of repeated breadth-first searches). Deterministic.
pub fn rcm(a: &SymSparse) -> Vec<usize> {
    let adj = a.graph();
    let n = a.n;
    let degree: Vec<usize> = adj.iter().map(Vec::len).collect();
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let bfs_last = |start: usize, seen: &mut Vec<bool>| -> (usize, usize) {
        // Returns the last row reached (least degree in the last level) and the depth.
        let mut level = vec![start];
        seen[start] = true;
        let mut touched = vec![start];
        let mut depth = 0;
        let mut last = start;
        while !level.is_empty() {
            last = level.iter().copied().min_by_key(|&v| (degree[v], v)).unwrap_or(last);
            let mut next = Vec::new();
            for &v in &level {
                for &w in &adj[v] {
                    if !seen[w] {
                        seen[w] = true;
                        touched.push(w);
                        next.push(w);
                    }
                }
            }
            if !next.is_empty() {
                depth += 1;
            }
            level = next;
        }
        for v in touched {
            seen[v] = false;
        }
        (last, depth)
    };
    let mut scratch = vec![false; n];
    for s in 0..n {
        if placed[s] {
            continue;
        }
        // Pseudo-peripheral start.
        let (mut start, mut depth) = bfs_last(s, &mut scratch);
        for _ in 0..8 {
            let (far, d) = bfs_last(start, &mut scratch);
            if d <= depth {
                break;
            }
            (start, depth) = (far, d);
        }
        let first = order.len();
        placed[start] = true;
        order.push(start);
        let mut head = first;
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = adj[v].iter().copied().filter(|&w| !placed[w]).collect();
            next.sort_by_key(|&w| (degree[w], w));
            next.dedup();
            for w in next {
                if !placed[w] {
                    placed[w] = true;
                    order.push(w);
                }
            }
        }
    }
    order.reverse();
    order
}

/// `a . b` with eight partial sums (the products of a factorisation's rows; independent sums
/// let the processor overlap them).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    let mut acc = [0.0; 8];
    for (x, y) in ca.zip(cb) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7])) + tail
}

/// `P A P^T = L D L^T` in envelope storage (row `i` of `L` from its first stored column),
/// without pivoting: for positive definite matrices, and for `K - sigma M` whose negative
/// pivots count its eigenvalues below `sigma` (Sylvester).
#[derive(Debug, Clone)]
pub struct Skyline {
    n: usize,
    /// New position -> old index.
    perm: Vec<usize>,
    /// Row `i`'s first stored column.
    first: Vec<usize>,
    /// Row `i`'s entries `first[i]..i` start at `start[i]`.
    start: Vec<usize>,
    l: Vec<f64>,
    d: Vec<f64>,
}

/// A zero (or, for [`Skyline::positive`], non-positive) pivot: the matrix is singular at that
/// row (0-based, the original numbering).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Singular {
    /// The row.
    pub row: usize,
}

/// What a factor in envelope storage costs, known before it is allocated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// Stored entries of `L` below the diagonal (8 bytes each).
    pub entries: usize,
    /// Multiplications and additions of the factorisation, about `sum_i w_i^2` for row widths
    /// `w_i`.
    pub flops: f64,
}

/// Each row's first stored column of the envelope of `a + b` under `perm`.
fn first_columns(a: &SymSparse, b: Option<&SymSparse>, perm: &[usize]) -> Vec<usize> {
    let n = a.n;
    let mut inv = vec![0; n];
    perm.iter().enumerate().for_each(|(new, &old)| inv[old] = new);
    let mut first: Vec<usize> = (0..n).collect();
    for m in std::iter::once(a).chain(b) {
        for i in 0..n {
            for (j, _) in m.row(i) {
                let (p, q) = (inv[i].max(inv[j]), inv[i].min(inv[j]));
                first[p] = first[p].min(q);
            }
        }
    }
    first
}

impl Skyline {
    /// What the factor of `a - sigma b` under `perm` costs, without allocating it.
    pub fn cost(a: &SymSparse, b: Option<&SymSparse>, perm: &[usize]) -> Cost {
        let first = first_columns(a, b, perm);
        let widths = first.iter().enumerate().map(|(i, f)| i - f);
        Cost { entries: widths.clone().sum(), flops: widths.map(|w| (w as f64) * (w as f64)).sum() }
    }

    /// The envelope of `a + b` under `perm` (for factors of `a - sigma b`).
    pub fn pattern(a: &SymSparse, b: Option<&SymSparse>, perm: Vec<usize>) -> Skyline {
        let n = a.n;
        let first = first_columns(a, b, &perm);
        let mut start = vec![0; n + 1];
        for i in 0..n {
            start[i + 1] = start[i] + (i - first[i]);
        }
        let size = start[n];
        Skyline { n, perm, first, start, l: vec![0.0; size], d: vec![0.0; n] }
    }

    /// The ordering: new position -> original index.
    pub fn order(&self) -> &[usize] {
        &self.perm
    }

    /// Stored entries of `L` below the diagonal.
    pub fn envelope(&self) -> usize {
        self.l.len()
    }

    /// Factors `a - sigma b` (`b` absent: `a`) into this pattern; the number of negative
    /// pivots, or the first zero pivot.
    pub fn factor(&mut self, a: &SymSparse, b: Option<(&SymSparse, f64)>) -> Result<usize, Singular> {
        let n = self.n;
        let mut inv = vec![0; n];
        self.perm.iter().enumerate().for_each(|(new, &old)| inv[old] = new);
        self.l.iter_mut().for_each(|v| *v = 0.0);
        self.d.iter_mut().for_each(|v| *v = 0.0);
        let scatter = |m: &SymSparse, scale: f64, l: &mut [f64], d: &mut [f64]| {
            for i in 0..n {
                for (j, v) in m.row(i) {
                    let (p, q) = (inv[i].max(inv[j]), inv[i].min(inv[j]));
                    if p == q {
                        d[p] += scale * v;
                    } else {
                        l[self.start[p] + q - self.first[p]] += scale * v;
                    }
                }
            }
        };
        scatter(a, 1.0, &mut self.l, &mut self.d);
        if let Some((b, sigma)) = b {
            scatter(b, -sigma, &mut self.l, &mut self.d);
        }
        // Row by row: u_ij = a_ij - sum_k u_ik L_jk, then L_ij = u_ij / d_j, d_i -= u_ij L_ij.
        let scale = self.d.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut negative = 0;
        for i in 0..n {
            let fi = self.first[i];
            let si = self.start[i];
            for j in fi..i {
                let fj = self.first[j].max(fi);
                let sj = self.start[j];
                let (row_i, row_j) =
                    (&self.l[si + fj - fi..si + j - fi], &self.l[sj + fj - self.first[j]..sj + j - self.first[j]]);
                let d = dot(row_i, row_j);
                self.l[si + j - fi] -= d;
            }
            let mut di = self.d[i];
            for j in fi..i {
                let u = self.l[si + j - fi];
                let lij = u / self.d[j];
                di -= u * lij;
                self.l[si + j - fi] = lij;
            }
            // Entries of row i hold u_ij until converted above; rows after i read L values.
            if di == 0.0 || !di.is_finite() || di.abs() <= 1e-300 * scale {
                return Err(Singular { row: self.perm[i] });
            }
            if di < 0.0 {
                negative += 1;
            }
            self.d[i] = di;
        }
        Ok(negative)
    }

    /// Whether every pivot is positive (after a successful [`Skyline::factor`]).
    pub fn positive(&self) -> Result<(), Singular> {
        match self.d.iter().position(|&v| v <= 0.0) {
            Some(i) => Err(Singular { row: self.perm[i] }),
            None => Ok(()),
        }
    }

    /// Solves the factored system for `b`, in place (the original numbering).
    pub fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        let mut y: Vec<f64> = self.perm.iter().map(|&old| b[old]).collect();
        for i in 0..n {
            let fi = self.first[i];
            let row = &self.l[self.start[i]..self.start[i] + i - fi];
            let s = dot(row, &y[fi..i]);
            y[i] -= s;
        }
        for (v, d) in y.iter_mut().zip(&self.d) {
            *v /= d;
        }
        for i in (0..n).rev() {
            let fi = self.first[i];
            let yi = y[i];
            let row = &self.l[self.start[i]..self.start[i] + i - fi];
            for (v, l) in y[fi..i].iter_mut().zip(row) {
                *v -= l * yi;
            }
        }
        for (new, &old) in self.perm.iter().enumerate() {
            b[old] = y[new];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2-D grid Laplacian plus a diagonal shift: a sparse positive definite matrix whose
    /// natural order has a wide envelope.
    fn grid(w: usize, h: usize, shift: f64) -> SymSparse {
        let id = |x: usize, y: usize| x * h + y;
        let mut e = Vec::new();
        for x in 0..w {
            for y in 0..h {
                e.push((id(x, y), id(x, y), 4.0 + shift + 0.01 * ((x * 7 + y * 3) % 5) as f64));
                if x + 1 < w {
                    e.push((id(x + 1, y), id(x, y), -1.0));
                }
                if y + 1 < h {
                    e.push((id(x, y), id(x, y + 1), -1.0));
                }
            }
        }
        SymSparse::from_entries(w * h, e, true).unwrap()
    }

    #[test]
    fn products_blocks_and_sums_match_the_dense_matrix() {
        let a = grid(5, 4, 0.3);
        let d = a.to_dense();
        assert_eq!(d, d.transpose());
        let x: Vec<f64> = (0..20).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut y = vec![0.0; 20];
        a.mul(&x, &mut y);
        let yd = &d * nalgebra::DVector::from_vec(x.clone());
        for (p, q) in y.iter().zip(yd.iter()) {
            assert!((p - q).abs() < 1e-14);
        }
        assert!((a.sum() - d.sum()).abs() < 1e-12);
        let keep = [3, 17, 0, 9];
        assert_eq!(a.principal(&keep).to_dense(), a.block(&keep, &keep));
        assert_eq!(a.block(&keep, &[1, 2])[(2, 0)], d[(0, 1)]);
    }

    #[test]
    fn both_triangles_must_agree() {
        let ok = [(0, 0, 2.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 2.0)];
        let a = SymSparse::from_entries(2, ok, false).unwrap();
        assert_eq!(
            a.to_dense(),
            SymSparse::from_entries(2, [(0, 0, 2.0), (1, 0, -1.0), (1, 1, 2.0)], true).unwrap().to_dense()
        );
        let bad = [(0, 0, 2.0), (0, 1, -1.0), (1, 0, -1.5), (1, 1, 2.0)];
        let e = SymSparse::from_entries(2, bad, false).unwrap_err();
        assert_eq!((e.row, e.col, e.lower, e.upper), (1, 0, -1.5, -1.0));
        let missing = [(0, 0, 2.0), (1, 0, -1.0), (1, 1, 2.0)];
        assert_eq!(SymSparse::from_entries(2, missing, false).unwrap_err().upper, 0.0);
    }

    #[test]
    fn the_factor_solves_and_rcm_narrows_the_envelope() {
        let a = grid(12, 9, 0.1);
        let natural = Skyline::pattern(&a, None, (0..a.n()).collect());
        let mut f = Skyline::pattern(&a, None, rcm(&a));
        assert!(f.envelope() <= natural.envelope(), "{} > {}", f.envelope(), natural.envelope());
        assert_eq!(f.factor(&a, None), Ok(0));
        let x: Vec<f64> = (0..a.n()).map(|i| 1.0 + (i as f64).cos()).collect();
        let mut b = vec![0.0; a.n()];
        a.mul(&x, &mut b);
        f.solve(&mut b);
        for (p, q) in b.iter().zip(&x) {
            assert!((p - q).abs() < 1e-12, "{p} vs {q}");
        }
    }

    #[test]
    fn negative_pivots_count_the_eigenvalues_below_the_shift() {
        let a = grid(6, 5, 0.0);
        let eig = a.to_dense().symmetric_eigenvalues();
        let mut ident = Vec::new();
        (0..a.n()).for_each(|i| ident.push((i, i, 1.0)));
        let m = SymSparse::from_entries(a.n(), ident, true).unwrap();
        let mut f = Skyline::pattern(&a, Some(&m), rcm(&a));
        for sigma in [0.5, 2.0, 3.3, 5.1, 7.9] {
            let below = eig.iter().filter(|&&l| l < sigma).count();
            assert_eq!(f.factor(&a, Some((&m, sigma))), Ok(below), "sigma {sigma}");
        }
    }
}
