//! A figure's axes: the range a panel's values span (finite, positive on a logarithmic axis,
//! clamped to what plotters can draw) and how its ticks are written.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::prelude::{IntoLogRange, LogCoord};

use crate::figure::Panel;

/// A logarithmic axis from `lo` to `hi` whose key points are each drawn once: plotters'
/// `LogCoord` gives each decade's end twice (the last multiple of one decade and the first
/// value of the next are the same number), and its grid line and label were drawn twice at
/// one place.
pub(super) struct LogOnce(LogCoord<f64>);

impl LogOnce {
    pub(super) fn new(lo: f64, hi: f64) -> LogOnce {
        LogOnce((lo..hi).log_scale().into())
    }
}

impl Ranged for LogOnce {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.0.map(value, limit)
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let mut points = self.0.key_points(hint);
        points.dedup();
        points
    }

    fn range(&self) -> Range<f64> {
        self.0.range()
    }

    fn axis_pixel_range(&self, limit: (i32, i32)) -> Range<i32> {
        self.0.axis_pixel_range(limit)
    }
}

/// Finite y values of all series (positive ones for log axes).
pub(super) fn y_extent(panel: &Panel) -> (f64, f64) {
    if let Some(r) = panel.y_range {
        return r;
    }
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for s in &panel.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if y.is_finite() && x >= panel.x_range.0 && x <= panel.x_range.1 && (!panel.y_log || y > 0.0) {
                lo = lo.min(y);
                hi = hi.max(y);
            }
        }
    }
    if !lo.is_finite() {
        return if panel.y_log { (1e-6, 1e-3) } else { (0.0, 1.0) };
    }
    if panel.y_log {
        (lo / 1.5, hi * 1.5)
    } else {
        let pad = ((hi - lo) * 0.06).max(1e-12 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    }
}

/// The largest magnitude an axis end may have (beyond it a tick's arithmetic overflows).
pub(super) const AXIS_MAX: f64 = 1e300;

/// The most decades a logarithmic axis spans (its key points are computed per decade).
pub(super) const AXIS_DECADES: f64 = 30.0;

/// An axis range that plotters can draw whatever the data: finite ends inside
/// +-[`AXIS_MAX`], `lo < hi` with a width tick labels can resolve, and on a logarithmic axis
/// positive ends at most [`AXIS_DECADES`] apart (the upper end kept: the largest values
/// matter). Every axis of every plot passes here.
pub(crate) fn axis_range(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    if log {
        let (mut lo, mut hi) = (lo.clamp(1.0 / AXIS_MAX, AXIS_MAX), hi.clamp(1.0 / AXIS_MAX, AXIS_MAX));
        if lo.is_nan() || hi.is_nan() || lo <= 0.0 {
            return (1e-6, 1e-3);
        }
        if lo > hi {
            std::mem::swap(&mut lo, &mut hi);
        }
        if hi / lo < 1.0 + 1e-9 {
            // One value: a decade around it.
            let (a, b) = (lo / 10f64.sqrt(), hi * 10f64.sqrt());
            return (a.max(1.0 / AXIS_MAX), b.min(AXIS_MAX));
        }
        if (hi / lo).log10() > AXIS_DECADES {
            lo = hi / 10f64.powf(AXIS_DECADES);
        }
        (lo, hi)
    } else {
        if lo.is_nan() || hi.is_nan() {
            return (0.0, 1.0);
        }
        let (mut lo, mut hi) = (lo.clamp(-AXIS_MAX, AXIS_MAX), hi.clamp(-AXIS_MAX, AXIS_MAX));
        if lo > hi {
            std::mem::swap(&mut lo, &mut hi);
        }
        // Tick labels resolve about 1e-9 of the ends' magnitude; a narrower range is widened
        // around its middle (or to +-1 around 0).
        let scale = lo.abs().max(hi.abs());
        let least = if scale > 0.0 { (scale * 1e-9).max(1e-300) } else { 1.0 };
        if hi - lo < least {
            let mid = 0.5 * (lo + hi);
            (mid - least, mid + least)
        } else {
            (lo, hi)
        }
    }
}

/// Whether a logarithmic axis labels its tick at `v`: 1, 2 and 5 times a power of ten (an axis
/// within a decade or two has a tick at every integer multiple, whose labels would run into
/// each other above 5).
fn labelled(v: f64) -> bool {
    if !(v.is_finite() && v > 0.0) {
        return false;
    }
    let m = v / 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().any(|&k| (m - k).abs() < 1e-6 * k)
}

/// Tick labels of a value axis: scientific notation for small or large values; on a
/// logarithmic axis only at 1, 2 and 5 times a power of ten ([`labelled`]).
pub(super) fn tick_format(lo: f64, hi: f64, log: bool) -> Box<dyn Fn(&f64) -> String> {
    let big = lo.abs().max(hi.abs());
    let plain = |v: f64| {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    if log && lo >= 1e-2 && hi < 1e5 {
        // A log axis over everyday values (mm, N, Hz): 0.5, 2, 40 read better than 5e-1.
        Box::new(move |v: &f64| if labelled(*v) { plain(*v) } else { String::new() })
    } else if log {
        Box::new(|v: &f64| if labelled(*v) { format!("{v:.0e}") } else { String::new() })
    } else if !(1e-2..1e5).contains(&big) {
        // Enough mantissa digits to tell ticks about a tenth of the range apart.
        let step = ((hi - lo).abs() / 10.0).max(f64::MIN_POSITIVE);
        let digits = ((big / step).log10().ceil() as i32).clamp(1, 4) as usize;
        Box::new(move |v: &f64| if v.abs() < 1e-9 * big { "0".into() } else { format!("{v:.digits$e}") })
    } else {
        Box::new(move |v: &f64| plain(if v.abs() < 1e-12 * big { 0.0 } else { *v }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_axis_gives_each_key_point_once() {
        let raw: Vec<f64> = LogCoord::from((2e-4..2.4e-2).log_scale()).key_points(40usize);
        let once = LogOnce::new(2e-4, 2.4e-2).key_points(40usize);
        // plotters' own gives the decade's end twice, the same number.
        assert!(raw.windows(2).any(|w| w[0] == w[1]), "{raw:?}");
        assert!(once.windows(2).all(|w| w[0] < w[1]), "{once:?}");
        assert_eq!(once.iter().filter(|&&v| (v / 1e-2 - 1.0).abs() < 1e-12).count(), 1, "{once:?}");
        let mut dedup = raw.clone();
        dedup.dedup();
        assert_eq!(once, dedup);
    }

    #[test]
    fn a_log_axis_labels_one_two_and_five_times_its_decades_once() {
        let f = tick_format(1e-4, 2.4e-3, true);
        let shown: Vec<String> = [1e-4, 2e-4, 3e-4, 5e-4, 9e-4, 1e-3, 1e-3 * (1.0 + 1e-12), 2e-3]
            .iter()
            .map(&f)
            .filter(|s| !s.is_empty())
            .collect();
        assert_eq!(shown, ["1e-4", "2e-4", "5e-4", "1e-3", "1e-3", "2e-3"]);
        let f = tick_format(0.4, 60.0, true);
        let shown: Vec<String> =
            [0.5, 0.7, 1.0, 3.0, 10.0, 20.0, 50.0].iter().map(&f).filter(|s| !s.is_empty()).collect();
        assert_eq!(shown, ["0.5", "1", "10", "20", "50"]);
        assert!(!labelled(0.0) && !labelled(f64::NAN) && !labelled(-2.0));
    }
}
