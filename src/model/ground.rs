//! A recorded ground motion: the ground's acceleration sampled at a fixed step, taken as linear
//! between samples (as the event-driven simulator is to take it: a forcing whose particular
//! solution on each interval has a closed form). No I/O: `experiment::ground` reads the
//! record files.

use super::GRAVITY;

/// A ground acceleration record.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundMotion {
    /// What the record is (its file's title lines, or its file name).
    pub name: String,
    /// The sampling step, s.
    pub dt_s: f64,
    /// The acceleration at `t = k dt_s`, m/s^2, from `k = 0`.
    pub accel_m_s2: Vec<f64>,
}

/// One recorded ground motion as a file names it, read and scaled (`experiment::ground` reads
/// it; a time history and a design against records run it).
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// A short key for figure and table names: the file's stem in lower case, letters,
    /// digits and `_` only.
    pub key: String,
    /// Its name on the page.
    pub name: String,
    /// The file as the experiment names it.
    pub file: String,
    /// How it was scaled, in words (e.g. "scaled to a peak of 0.4 g (x 1.255)").
    pub scaling: String,
    /// The scaled record.
    pub motion: GroundMotion,
    /// The direction the file states for it (checked against the structure's supports by
    /// `experiment::ground::directions_fit`); `None`: the structure's own.
    pub direction: Option<String>,
}

impl GroundMotion {
    /// The record's length, s (the last sample's time).
    pub fn duration_s(&self) -> f64 {
        self.dt_s * self.accel_m_s2.len().saturating_sub(1) as f64
    }

    /// The largest absolute acceleration, m/s^2, and the time of its first sample, s.
    pub fn peak(&self) -> (f64, f64) {
        let (k, a) =
            self.accel_m_s2
                .iter()
                .enumerate()
                .fold((0, 0.0f64), |(bk, ba), (k, a)| if a.abs() > ba { (k, a.abs()) } else { (bk, ba) });
        (a, k as f64 * self.dt_s)
    }

    /// The record times `factor`.
    pub fn scaled(&self, factor: f64) -> GroundMotion {
        GroundMotion { accel_m_s2: self.accel_m_s2.iter().map(|a| a * factor).collect(), ..self.clone() }
    }

    /// The record scaled to a peak of `peak_g` times g (unchanged when it is all zero).
    pub fn scaled_to_peak_g(&self, peak_g: f64) -> GroundMotion {
        let (peak, _) = self.peak();
        if peak > 0.0 {
            self.scaled(peak_g * GRAVITY / peak)
        } else {
            self.clone()
        }
    }

    /// The acceleration at `t`, s: linear between samples, 0 before the first and after the
    /// last (the ground at rest).
    pub fn at(&self, t: f64) -> f64 {
        if t.is_nan() || t < 0.0 || self.accel_m_s2.is_empty() {
            return 0.0;
        }
        let x = t / self.dt_s;
        let k = x.floor() as usize;
        match (self.accel_m_s2.get(k), self.accel_m_s2.get(k + 1)) {
            (Some(a), Some(b)) => a + (b - a) * (x - k as f64),
            (Some(a), None) if x == k as f64 => *a,
            _ => 0.0,
        }
    }

    /// The ground's velocity change over the record, m/s: the trapezoidal integral of the
    /// piecewise-linear acceleration (exact for it).
    pub fn velocity_change(&self) -> f64 {
        self.accel_m_s2.windows(2).map(|w| 0.5 * (w[0] + w[1]) * self.dt_s).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> GroundMotion {
        GroundMotion { name: "r".into(), dt_s: 0.5, accel_m_s2: vec![0.0, 2.0, -4.0, 1.0] }
    }

    #[test]
    fn linear_between_samples_and_at_rest_outside() {
        let r = record();
        assert_eq!(r.at(0.25), 1.0);
        assert_eq!(r.at(0.75), -1.0);
        assert_eq!(r.at(1.5), 1.0);
        assert_eq!((r.at(-0.1), r.at(1.6)), (0.0, 0.0));
        assert_eq!(r.duration_s(), 1.5);
        assert_eq!(r.peak(), (4.0, 1.0));
        // The integral of a piecewise-linear function is its trapezoidal sum: 0.5 - 0.5 - 0.75.
        assert_eq!(r.velocity_change(), 0.25 * (2.0 - 2.0 - 3.0));
    }

    #[test]
    fn scaled_to_a_peak_in_g() {
        let s = record().scaled_to_peak_g(0.5);
        assert!((s.peak().0 - 0.5 * GRAVITY).abs() < 1e-12);
        assert_eq!(s.at(1.0) / s.at(0.5), -2.0, "the shape is kept");
        let zero = GroundMotion { accel_m_s2: vec![0.0; 3], ..record() };
        assert_eq!(zero.scaled_to_peak_g(1.0), zero);
    }
}
