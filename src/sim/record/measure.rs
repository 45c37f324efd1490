//! What a run under a record measures on each smooth stretch of its closed form: the peaks
//! of every coordinate's displacement, every storey's drift and every coordinate's absolute
//! acceleration (at the stretch's ends and where the derivative vanishes inside, refined to
//! rounding), and the integrals of their squares, the ground's power and the damping's, by
//! five-point Gauss-Legendre quadrature (exact to degree 9 on a stretch of at most a
//! sixteenth of the shortest period).

use nalgebra::DMatrix;

use super::piece::{At, Factors, Particular, Piece};

/// Gauss-Legendre nodes on `[-1, 1]` and weights, five points.
const NODES: [f64; 5] =
    [-0.906_179_845_938_664, -0.538_469_310_105_683_1, 0.0, 0.538_469_310_105_683_1, 0.906_179_845_938_664];
const WEIGHTS: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];

/// Which quantity of a coordinate: its relative displacement, its storey's drift, or its
/// absolute acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Quantity {
    Displacement,
    Drift,
    Accel,
}

/// Running peaks, integrals of squares and energies.
#[derive(Debug, Clone)]
pub(super) struct Measure {
    n: usize,
    /// The coordinates measured: the first `shown` (a reduced model's points; every mass of
    /// a lumped structure).
    shown: usize,
    chain: bool,
    follow: Vec<f64>,
    c: DMatrix<f64>,
    pub peak: [Vec<f64>; 3],
    pub squares: [Vec<f64>; 3],
    pub time: f64,
    pub input: f64,
    pub viscous: f64,
}

impl Measure {
    /// Nothing measured yet on the first `shown` of `n` coordinates (`chain`: storeys'
    /// drifts too).
    pub fn new((n, shown): (usize, usize), chain: bool, follow: Vec<f64>, c: DMatrix<f64>) -> Measure {
        let storeys = if chain { shown } else { 0 };
        Measure {
            n,
            shown,
            chain,
            follow,
            c,
            peak: [vec![0.0; shown], vec![0.0; storeys], vec![0.0; shown]],
            squares: [vec![0.0; shown], vec![0.0; storeys], vec![0.0; shown]],
            time: 0.0,
            input: 0.0,
            viscous: 0.0,
        }
    }

    /// Value and rate of quantity `q` of coordinate `i` at `at`.
    fn value(&self, piece: &Piece, at: &At, q: Quantity, i: usize) -> (f64, f64) {
        match q {
            Quantity::Displacement => (piece.deriv(at, i, 0), piece.deriv(at, i, 1)),
            Quantity::Drift => {
                let below = |o| if i > 0 { piece.deriv(at, i - 1, o) } else { 0.0 };
                (piece.deriv(at, i, 0) - below(0), piece.deriv(at, i, 1) - below(1))
            }
            Quantity::Accel => {
                let r = self.follow[i];
                (piece.deriv(at, i, 2) + r * piece.ground(at.s), piece.deriv(at, i, 3) + r * piece.slope)
            }
        }
    }

    /// The factors that carry a stretch's start to its Gauss-Legendre nodes, for stretches of
    /// length `h` ([`Measure::stretch`]).
    pub fn nodes(piece: &Piece, h: f64) -> Vec<Factors> {
        NODES.iter().map(|x| piece.factors(0.5 * h * (1.0 + x))).collect()
    }

    /// Measures the stretch `[a.s, b.s]` of `piece` (configuration parts `part`); `nodes`:
    /// [`Measure::nodes`] of its length, when known (else the nodes' terms are computed).
    pub fn stretch(&mut self, piece: &Piece, part: &Particular, (a, b): (&At, &At), nodes: Option<&[Factors]>) {
        let h = b.s - a.s;
        if h <= 0.0 {
            return;
        }
        for (qi, q) in [Quantity::Displacement, Quantity::Drift, Quantity::Accel].into_iter().enumerate() {
            for i in 0..self.peak[qi].len() {
                let ((ya, da), (yb, db)) = (self.value(piece, a, q, i), self.value(piece, b, q, i));
                let mut best = ya.abs().max(yb.abs());
                // An extreme inside, where the rate changes sign, unless even a generous
                // bound on it (the cubic through the ends, plus a hundredth of the stretch's
                // scale) stays below the peak so far.
                if da * db < 0.0 {
                    let scale = ya.abs() + yb.abs() + h * (da.abs() + db.abs());
                    let cubic = crate::model::ground_response::hermite_peak(ya, da, yb, db, h);
                    if cubic + 0.01 * scale > self.peak[qi][i] {
                        let s = rate_root(|s| self.value(piece, &piece.at(s), q, i).1, (a.s, da), (b.s, db));
                        best = best.max(self.value(piece, &piece.at(s), q, i).0.abs());
                    }
                }
                self.peak[qi][i] = self.peak[qi][i].max(best);
            }
        }
        let half = 0.5 * h;
        let mut at = At::default();
        for (k, (x, w)) in NODES.iter().zip(WEIGHTS).enumerate() {
            let s = a.s + half * (1.0 + x);
            match nodes {
                Some(f) => at = piece.shifted(a, &f[k]),
                None => piece.at_into(s, &mut at),
            }
            let weight = w * half;
            let v: Vec<f64> = (0..self.n).map(|p| piece.deriv(&at, p, 1)).collect();
            let mut momentum: f64 = v.iter().zip(part.load.iter()).map(|(v, l)| v * l).sum();
            for f in &piece.flights {
                momentum += f.mass * f.follow * piece.flight(f, s)[1];
            }
            self.input -= weight * piece.ground(s) * momentum;
            let mut dissipated = 0.0;
            for (i, vi) in v.iter().enumerate() {
                let row: f64 = (0..self.n).map(|j| self.c[(i, j)] * v[j]).sum();
                dissipated += vi * row;
            }
            self.viscous += weight * dissipated;
            for (qi, q) in [Quantity::Displacement, Quantity::Drift, Quantity::Accel].into_iter().enumerate() {
                if q == Quantity::Drift && !self.chain {
                    continue;
                }
                for i in 0..self.shown {
                    let y = self.value(piece, &at, q, i).0;
                    self.squares[qi][i] += weight * y * y;
                }
            }
        }
        self.time += h;
    }

    /// The root mean squares so far.
    pub fn rms(&self) -> [Vec<f64>; 3] {
        let t = self.time.max(f64::MIN_POSITIVE);
        self.squares.clone().map(|v| v.into_iter().map(|s| (s / t).sqrt()).collect())
    }
}

/// The root of a rate that changes sign between `(a, fa)` and `(b, fb)`, by the Illinois
/// variant of false position, to rounding (or 100 steps).
fn rate_root(f: impl Fn(f64) -> f64, (mut a, mut fa): (f64, f64), (mut b, mut fb): (f64, f64)) -> f64 {
    let mut side = 0;
    for _ in 0..100 {
        let s = (a * fb - b * fa) / (fb - fa);
        let s = if s > a && s < b { s } else { 0.5 * (a + b) };
        if s <= a || s >= b {
            return s;
        }
        let fs = f(s);
        if fs == 0.0 || (b - a) <= 4.0 * f64::EPSILON * b.abs().max(1e-300) {
            return s;
        }
        if (fs > 0.0) == (fa > 0.0) {
            (a, fa) = (s, fs);
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb) = (s, fs);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_root_is_found_to_rounding() {
        let s = rate_root(|x: f64| x.cos(), (1.0, 1f64.cos()), (2.0, 2f64.cos()));
        assert!((s - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn five_point_gauss_legendre_integrates_degree_nine_exactly() {
        let f = |x: f64| x.powi(9) + 3.0 * x.powi(8) - x.powi(3) + 2.0;
        let exact = 3.0 * 2.0 / 9.0 + 4.0;
        let sum: f64 = NODES.iter().zip(WEIGHTS).map(|(x, w)| w * f(*x)).sum();
        assert!((sum - exact).abs() < 1e-14, "{sum} {exact}");
    }
}
