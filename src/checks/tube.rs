//! Curve comparisons that respect digitising error: a tube around a reference curve, and the
//! position of a resonance peak. Tolerances have an absolute and a relative part on each axis;
//! on a logarithmic axis distances are taken in the logarithm, so a relative tolerance is the
//! same fraction everywhere on it.

/// The tolerance along one axis: `abs + rel |value|` (on a log axis only `rel` applies, as
/// `ln(1 + rel)` in the logarithm).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisTol {
    /// Absolute tolerance, in the axis's unit.
    pub abs: f64,
    /// Relative tolerance.
    pub rel: f64,
    /// Logarithmic axis: tolerances apply to log10 of the values.
    pub log: bool,
}

impl AxisTol {
    /// The interval around `v` that the tolerance allows.
    pub fn interval(&self, v: f64) -> (f64, f64) {
        if self.log {
            let f = 1.0 + self.rel;
            (v / f, v * f)
        } else {
            let t = self.abs + self.rel * v.abs();
            (v - t, v + t)
        }
    }

    /// How far `v` is outside `[lo, hi]`, in units of the tolerance at `v` (0 inside).
    pub fn excess(&self, v: f64, lo: f64, hi: f64) -> f64 {
        if self.log {
            if !(v > 0.0 && lo > 0.0) {
                return f64::INFINITY;
            }
            let d = (lo.ln() - v.ln()).max(v.ln() - hi.ln()).max(0.0);
            let t = (1.0 + self.rel).ln();
            if d == 0.0 {
                0.0
            } else {
                d / t
            }
        } else {
            let d = (lo - v).max(v - hi).max(0.0);
            let t = self.abs + self.rel * v.abs();
            if d == 0.0 {
                0.0
            } else {
                d / t
            }
        }
    }
}

/// The worst reference point of a comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Worst {
    /// Its abscissa.
    pub x: f64,
    /// Its ordinate.
    pub y: f64,
    /// The computed values nearest to it within the x tolerance (lowest, highest).
    pub computed: (f64, f64),
    /// Distance outside the tube in units of the y tolerance (0 inside).
    pub excess: f64,
}

/// The outcome of a tube comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct TubeResult {
    /// Reference points compared.
    pub total: usize,
    /// Of those, points inside the tube.
    pub inside: usize,
    /// Reference points whose x window the computed curve does not reach.
    pub uncovered: usize,
    /// The point farthest outside (or nearest the edge).
    pub worst: Option<Worst>,
}

impl TubeResult {
    /// True when every covered reference point lies inside the tube.
    pub fn pass(&self) -> bool {
        self.total > 0 && self.inside == self.total
    }
}

/// Linear interpolation of a curve sorted by x (None outside it).
fn at(curve: &[(f64, f64)], x: f64) -> Option<f64> {
    let k = curve.partition_point(|p| p.0 < x);
    if k < curve.len() && curve[k].0 == x {
        return Some(curve[k].1);
    }
    if k == 0 || k == curve.len() {
        return None;
    }
    let (a, b) = (curve[k - 1], curve[k]);
    Some(a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0))
}

/// Every reference point must lie within the y tolerance of the computed curve somewhere within
/// its x tolerance: the computed curve (sorted by x, drawn straight between points) passes
/// through the box around each reference point.
pub fn tube(reference: &[(f64, f64)], computed: &[(f64, f64)], x: AxisTol, y: AxisTol) -> TubeResult {
    let mut out = TubeResult { total: reference.len(), inside: 0, uncovered: 0, worst: None };
    let (first, last) = match (computed.first(), computed.last()) {
        (Some(a), Some(b)) => (a.0, b.0),
        _ => {
            out.uncovered = reference.len();
            return out;
        }
    };
    for &(xr, yr) in reference {
        let (lo, hi) = x.interval(xr);
        let (lo, hi) = (lo.max(first), hi.min(last));
        if lo > hi {
            out.uncovered += 1;
            continue;
        }
        // The computed values over the window: its ends and the vertices inside.
        let mut ys: Vec<f64> = [at(computed, lo), at(computed, hi)].into_iter().flatten().collect();
        ys.extend(computed.iter().filter(|p| p.0 >= lo && p.0 <= hi).map(|p| p.1));
        let (ymin, ymax) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
        let excess = y.excess(yr, ymin, ymax);
        if excess <= 1.0 {
            out.inside += 1;
        }
        if out.worst.is_none_or(|w| excess > w.excess) {
            out.worst = Some(Worst { x: xr, y: yr, computed: (ymin, ymax), excess });
        }
    }
    out
}

/// The highest point of a curve within `[lo, hi]`.
pub fn peak(curve: &[(f64, f64)], lo: f64, hi: f64) -> Option<(f64, f64)> {
    curve.iter().copied().filter(|p| p.0 >= lo && p.0 <= hi && p.1.is_finite()).max_by(|a, b| a.1.total_cmp(&b.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A resonance-like curve.
    fn curve(shift_x: f64, scale_y: f64) -> Vec<(f64, f64)> {
        (0..=400)
            .map(|i| {
                let f = 40.0 + 0.05 * i as f64;
                (f + shift_x, scale_y * 1e-4 / (1.0 + ((f - 50.0) / 1.5).powi(2)))
            })
            .collect()
    }

    #[test]
    fn linear_axes_pass_within_and_fail_beyond_in_x_and_y() {
        let reference: Vec<(f64, f64)> = curve(0.0, 1.0).into_iter().step_by(20).collect();
        let x = AxisTol { abs: 0.2, rel: 0.0, log: false };
        let y = AxisTol { abs: 2e-6, rel: 0.0, log: false };
        assert!(tube(&reference, &curve(0.0, 1.0), x, y).pass());
        // Shifted in x within 0.2 Hz: passes; by 0.6 Hz: the flanks leave the tube.
        assert!(tube(&reference, &curve(0.15, 1.0), x, y).pass());
        assert!(!tube(&reference, &curve(0.6, 1.0), x, y).pass());
        // Shifted in y: 1e-6 inside, 5e-6 outside (the peak is 1e-4).
        let up = |d: f64| curve(0.0, 1.0).into_iter().map(|(f, c)| (f, c + d)).collect::<Vec<_>>();
        assert!(tube(&reference, &up(1e-6), x, y).pass());
        let r = tube(&reference, &up(5e-6), x, y);
        assert!(!r.pass());
        let w = r.worst.unwrap();
        // 5e-6 away with a tolerance of 2e-6: 2.5 tolerances out (where the curve is flat).
        assert!((w.excess - 2.5).abs() < 0.05, "{w:?}");
    }

    #[test]
    fn log_axes_take_relative_distances() {
        let reference: Vec<(f64, f64)> = curve(0.0, 1.0).into_iter().step_by(20).collect();
        let x = AxisTol { abs: 0.0, rel: 0.004, log: true };
        let y = AxisTol { abs: 0.0, rel: 0.05, log: true };
        // 3 % higher everywhere (tails included): inside; 8 %: outside.
        assert!(tube(&reference, &curve(0.0, 1.03), x, y).pass());
        assert!(!tube(&reference, &curve(0.0, 1.08), x, y).pass());
        // A shift of 0.1 Hz at 50 Hz is 0.2 %: inside 0.4 %; 0.5 Hz is 1 %: outside.
        assert!(tube(&reference, &curve(0.1, 1.0), x, y).pass());
        assert!(!tube(&reference, &curve(0.5, 1.0), x, y).pass());
    }

    #[test]
    fn peaks_are_found_in_their_window() {
        let c = curve(0.3, 2.0);
        let (f, v) = peak(&c, 45.0, 55.0).unwrap();
        assert!((f - 50.3).abs() < 1e-9 && (v - 2e-4).abs() < 1e-15);
    }
}
