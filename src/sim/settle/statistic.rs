//! The estimator of irregular motion (docs/simulator.md, "Irregular motion"): what a
//! measurement is asked ([`Measure`]), what it gives ([`Measured`], [`Motion`]) and the
//! statistics of a record, with no dynamics.
//!
//! The record's first [`ALIGN`] periods are cut, and then its start by the MSER-5 rule
//! (White 1997): the truncation that minimises the standard error of the rest of the
//! amplitude series, searched over the record's first half; a record whose best cut falls in
//! its second half is not stationary yet. The statistic of a mass is the 95th percentile of
//! its per-period amplitudes over the kept record, with a 95 % interval from [`BATCHES`]
//! batch percentiles (batch quantiles, Seila 1982; a t quantile on `BATCHES - 1` degrees of
//! freedom), fewer batches where a record is too short for 20 of [`MIN_BATCH`] periods
//! ([`batches_for`]); the exponent's interval comes from the same batches' means. No I/O.

/// Batches of the record for the intervals.
pub const BATCHES: usize = 20;

/// Shortest batch, forcing periods. Successive periods of an irregular motion are correlated:
/// batches of one to four periods make an interval narrower than it is. Measured (records cut
/// from 200,000-period runs of two chaotic points, `cargo run --release --example
/// interval_coverage`): 38 kept periods in 20 batches held the long run's value in 57-59 % of
/// records, in batches of at least 10 periods in 88-90 %; 99 kept, 74-79 % and 82-90 %.
pub const MIN_BATCH: usize = 10;

/// The batches a kept record of `len` periods is cut into: [`BATCHES`], or as many of at least
/// [`MIN_BATCH`] periods as it holds; 0 (no interval) when that is fewer than two.
pub fn batches_for(len: usize) -> usize {
    match (len / MIN_BATCH).min(BATCHES) {
        k if k >= 2 => k,
        _ => 0,
    }
}

/// The 0.975 quantile of Student's t on `BATCHES - 1` = 19 degrees of freedom.
pub const T_975_19: f64 = 2.093_024_054;

/// Shortest kept record judged, forcing periods (batches of 20 periods).
pub const MIN_PERIODS: usize = 400;

/// Periods always cut from a record's start (a quarter of a shorter record's): the tangent
/// vector turns towards the most stretched direction over them (its start direction is
/// arbitrary), and the motion leaves the orbit search's end.
pub const ALIGN: usize = 50;

/// The record grows by this many periods between judgements.
pub const STEP: usize = 100;

/// The percentile of the per-period amplitudes that is the compliance of an irregular point.
pub const PERCENTILE: f64 = 0.95;

/// How an irregular motion is measured ([`super::steady::SteadyOptions::measure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measure {
    /// Most forcing periods recorded; `None`: the steady state's own budget
    /// ([`super::steady::SteadyOptions::max_periods`], so a point costs at most twice it); `Some(0)`: no
    /// measurement (the point keeps the orbit search's short record). Handed over
    /// ([`Measure::hand_over`]): at most this many each time the point is measured, within
    /// the shared budget (a design's screen).
    pub max_periods: Option<usize>,
    /// Largest half-width of a statistic's 95 % interval, relative to the largest statistic.
    pub tol: f64,
    /// `Some(h)`: the orbit search hands a point with no orbit after `h` periods over to the
    /// measurement, which hands it back when the motion contracts ([`super::handed_over`]); the
    /// search and the measurement then share the steady state's one budget. `None`: the
    /// measurement starts where the whole search ended (the report's sweeps).
    pub hand_over: Option<usize>,
}

impl Default for Measure {
    fn default() -> Self {
        Measure { max_periods: None, tol: 0.01, hand_over: None }
    }
}

impl Measure {
    /// At most this many periods, whatever the steady state's budget.
    pub fn periods(max_periods: usize, tol: f64) -> Measure {
        Measure { max_periods: Some(max_periods), tol, hand_over: None }
    }

    /// Handed over after `hand_over` periods of the orbit search, to an interval of `tol`,
    /// within the steady state's one budget ([`super::handed_over`]).
    pub fn handed_over(hand_over: usize, tol: f64) -> Measure {
        Measure { max_periods: None, tol, hand_over: Some(hand_over) }
    }

    /// The budget under steady-state options of budget `steady_max`.
    pub fn budget(&self, steady_max: usize) -> usize {
        self.max_periods.unwrap_or(steady_max)
    }
}

/// What a point's motion is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// A certified periodic orbit (its period in the steady state's `period`).
    Periodic,
    /// Quasi-periodic: recognised as a torus, or an exponent indistinguishable from 0.
    QuasiPeriodic,
    /// Chaotic: the largest Lyapunov exponent's interval lies above 0.
    Chaotic,
    /// Not over within the budget: the motion contracts (exponent below 0) or its amplitude
    /// series never became stationary; or it was not measured.
    Transient,
    /// Stopped by chatter (more events in a period than allowed).
    Chatter,
    /// A bed with restitution or a column of grains that never settled: measured by its long
    /// record ([`super::long_record`]).
    Aperiodic,
    /// Measured, but over a record too short to tell: fewer kept periods than two batches of
    /// [`MIN_BATCH`] (no interval for the exponent), or fewer than [`BATCHES`] batches whose
    /// interval contains 0 (too wide to tell a torus from chaos). A design's short budgets.
    Unclassified,
}

impl Motion {
    /// The class as tables write it.
    pub fn name(&self) -> &'static str {
        match self {
            Motion::Periodic => "periodic",
            Motion::QuasiPeriodic => "quasi-periodic",
            Motion::Chaotic => "chaotic",
            Motion::Transient => "transient",
            Motion::Chatter => "chatter",
            Motion::Aperiodic => "aperiodic",
            Motion::Unclassified => "unclassified",
        }
    }

    /// Its place in [`Motion::ALL`], and so in [`ClassCounts`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Every class, in the order pages count them (their order of declaration).
    pub const ALL: [Motion; 7] = [
        Motion::Periodic,
        Motion::QuasiPeriodic,
        Motion::Chaotic,
        Motion::Transient,
        Motion::Chatter,
        Motion::Aperiodic,
        Motion::Unclassified,
    ];
}

/// Steady states counted by class, in [`Motion::ALL`]'s order (index [`Motion::index`]).
pub type ClassCounts = [usize; Motion::ALL.len()];

/// The measurement of an irregular point.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// Per mass: the 95th percentile of the per-period amplitudes over the kept record, m
    /// (NaN for a mass not measured).
    pub statistic: Vec<f64>,
    /// Per mass: the half-width of its 95 % interval, m.
    pub half_width: Vec<f64>,
    /// Per mass: the largest per-period amplitude over the kept record, m.
    pub largest: Vec<f64>,
    /// The largest Lyapunov exponent, 1/s.
    pub lyapunov: f64,
    /// The half-width of its 95 % interval, 1/s.
    pub lyapunov_half_width: f64,
    /// Periods kept (after the cut).
    pub periods: usize,
    /// Periods cut from the record's start ([`ALIGN`], then the transient by MSER-5).
    pub discarded: usize,
    /// The record was stationary by the MSER-5 rule.
    pub stationary: bool,
    /// Every half-width met the tolerance.
    pub met: bool,
}

impl Measured {
    /// The class the exponent gives; none without its interval (a record too short for two
    /// batches: an unknown interval neither lies above 0 nor contains it), nor where an
    /// interval of fewer than [`BATCHES`] batches contains 0 (so wide that it cannot tell a
    /// torus from chaos: on the plate design's points, every one of nine such records was
    /// chaos or a periodic orbit once measured for 1500 periods, docs/design.md).
    pub fn class(&self) -> Motion {
        let (lo, hi) = (self.lyapunov - self.lyapunov_half_width, self.lyapunov + self.lyapunov_half_width);
        if !lo.is_finite() || !hi.is_finite() {
            Motion::Unclassified
        } else if lo > 0.0 {
            Motion::Chaotic
        } else if hi < 0.0 || !self.stationary {
            Motion::Transient
        } else if batches_for(self.periods) < BATCHES {
            Motion::Unclassified
        } else {
            Motion::QuasiPeriodic
        }
    }

    /// The largest half-width relative to the largest statistic.
    pub fn relative_half_width(&self) -> f64 {
        let top = self.statistic.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
        let hw = self.half_width.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
        if top > 0.0 {
            hw / top
        } else {
            f64::NAN
        }
    }
}

/// The `q` quantile of `v` (linear between order statistics, the "type 7" rule); NaN when
/// empty.
pub fn quantile(v: &[f64], q: f64) -> f64 {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
    if s.is_empty() {
        return f64::NAN;
    }
    s.sort_by(f64::total_cmp);
    let h = q * (s.len() - 1) as f64;
    let (i, f) = (h.floor() as usize, h - h.floor());
    if i + 1 < s.len() {
        s[i] + f * (s[i + 1] - s[i])
    } else {
        s[i]
    }
}

/// The MSER-5 cut of a series: the number of leading values to drop, or `None` when the best
/// cut lies in the second half (the series is not stationary yet).
pub fn mser5(y: &[f64]) -> Option<usize> {
    let z: Vec<f64> = y.chunks_exact(5).map(|c| c.iter().sum::<f64>() / 5.0).collect();
    let m = z.len();
    if m < 4 {
        return None;
    }
    // Suffix sums give each cut's mean and squared deviation in O(m).
    let (mut s1, mut s2) = (vec![0.0; m + 1], vec![0.0; m + 1]);
    for j in (0..m).rev() {
        s1[j] = s1[j + 1] + z[j];
        s2[j] = s2[j + 1] + z[j] * z[j];
    }
    let mut best = (0, f64::INFINITY);
    for d in 0..m - 1 {
        let k = (m - d) as f64;
        let ss = (s2[d] - s1[d] * s1[d] / k).max(0.0);
        let v = ss / (k * k);
        if v < best.1 {
            best = (d, v);
        }
    }
    (best.0 <= m / 2).then_some(5 * best.0)
}

/// The mean of `v` and the half-width of its 95 % interval from [`batches_for`] batch means
/// (NaN for fewer than `2 MIN_BATCH` values).
pub fn batch_mean(v: &[f64]) -> (f64, f64) {
    let batches = batches_for(v.len());
    let mean = if v.is_empty() { f64::NAN } else { v.iter().sum::<f64>() / v.len() as f64 };
    if batches == 0 {
        return (mean, f64::NAN);
    }
    let b = v.len() / batches;
    let means: Vec<f64> = v.chunks_exact(b).take(batches).map(|c| c.iter().sum::<f64>() / b as f64).collect();
    (mean, half_width(&means))
}

/// The `q` quantile of `v` over the whole and the half-width of its 95 % interval from
/// [`batches_for`] batch quantiles (NaN for fewer than `2 MIN_BATCH` values).
pub fn batch_quantile(v: &[f64], q: f64) -> (f64, f64) {
    batch_quantile_in(v, q, batches_for(v.len()))
}

/// [`batch_quantile`] from `batches` batches (2 to 30; NaN for fewer batches than 2 or fewer
/// values than batches).
pub fn batch_quantile_in(v: &[f64], q: f64, batches: usize) -> (f64, f64) {
    let b = if batches >= 2 { v.len() / batches } else { 0 };
    if b == 0 {
        return (quantile(v, q), f64::NAN);
    }
    let qs: Vec<f64> = v.chunks_exact(b).take(batches).map(|c| quantile(c, q)).collect();
    (quantile(v, q), half_width(&qs))
}

/// The 0.975 quantiles of Student's t on 1 to 29 degrees of freedom.
const T_975: [f64; 29] = [
    12.706_204_736,
    4.302_652_730,
    3.182_446_305,
    2.776_445_105,
    2.570_581_836,
    2.446_911_851,
    2.364_624_252,
    2.306_004_135,
    2.262_157_163,
    2.228_138_852,
    2.200_985_160,
    2.178_812_830,
    2.160_368_656,
    2.144_786_688,
    2.131_449_546,
    2.119_905_299,
    2.109_815_578,
    2.100_922_040,
    T_975_19,
    2.085_963_447,
    2.079_613_845,
    2.073_873_068,
    2.068_657_610,
    2.063_898_562,
    2.059_538_553,
    2.055_529_439,
    2.051_830_516,
    2.048_407_142,
    2.045_229_642,
];

/// `t s / sqrt(k)` of `k` batch values (`t` on `k - 1` degrees of freedom).
fn half_width(batches: &[f64]) -> f64 {
    let k = batches.len() as f64;
    let mean = batches.iter().sum::<f64>() / k;
    let var = batches.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (k - 1.0);
    let t = T_975.get(batches.len().saturating_sub(2)).copied().unwrap_or(f64::NAN);
    t * (var / k).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_exponent(lyapunov: f64, half_width: f64, periods: usize) -> Measured {
        Measured {
            statistic: vec![1.0],
            half_width: vec![0.01],
            largest: vec![1.1],
            lyapunov,
            lyapunov_half_width: half_width,
            periods,
            discarded: 0,
            stationary: true,
            met: false,
        }
    }

    #[test]
    fn every_class_counts_at_its_place() {
        for (i, class) in Motion::ALL.iter().enumerate() {
            assert_eq!(class.index(), i, "{class:?}");
        }
    }

    #[test]
    fn a_class_needs_an_interval_and_a_torus_a_whole_one() {
        // Above 0 from any interval; below 0 a transient.
        assert_eq!(with_exponent(300.0, 100.0, 30).class(), Motion::Chaotic);
        assert_eq!(with_exponent(-50.0, 20.0, 30).class(), Motion::Transient);
        // No interval: no class.
        assert_eq!(with_exponent(300.0, f64::NAN, 15).class(), Motion::Unclassified);
        assert_eq!(with_exponent(f64::NAN, f64::NAN, 0).class(), Motion::Unclassified);
        // Containing 0: a torus only from the whole number of batches.
        assert_eq!(with_exponent(80.0, 120.0, 199).class(), Motion::Unclassified);
        assert_eq!(with_exponent(80.0, 120.0, 200).class(), Motion::QuasiPeriodic);
        assert_eq!(with_exponent(1.0, 3.0, 400).class(), Motion::QuasiPeriodic);
        // A record that is not stationary is a transient not over, whatever its exponent's sign.
        let drifting = Measured { stationary: false, ..with_exponent(1.0, 3.0, 400) };
        assert_eq!(drifting.class(), Motion::Transient);
    }

    #[test]
    fn quantiles_follow_the_type_7_rule() {
        let v = [3.0, 1.0, 2.0, 5.0, 4.0];
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert!((quantile(&v, 0.95) - 4.8).abs() < 1e-12);
    }

    /// MSER-5 cuts a decaying start and keeps a stationary series whole; a trend to the end
    /// is not stationary.
    #[test]
    fn mser5_cuts_the_transient() {
        let noise = |i: usize| ((i * 7919 % 101) as f64 / 101.0 - 0.5) * 0.1;
        let settled: Vec<f64> = (0..500).map(|i| 1.0 + noise(i)).collect();
        assert!(mser5(&settled).is_some_and(|d| d < 50), "{:?}", mser5(&settled));
        let decaying: Vec<f64> = (0..500).map(|i| 1.0 + 5.0 * (-(i as f64) / 30.0).exp() + noise(i)).collect();
        let cut = mser5(&decaying).unwrap();
        assert!((60..=250).contains(&cut), "{cut}");
        let trend: Vec<f64> = (0..500).map(|i| i as f64 + noise(i)).collect();
        assert_eq!(mser5(&trend), None);
    }

    /// Any batch count: 20 is the measurement's own, to the bit; 10 batches of the same values
    /// take t on 9 degrees of freedom.
    #[test]
    fn batch_quantiles_in_any_count() {
        let v: Vec<f64> = (0..400).map(|i| ((i * 7919 % 401) as f64).sqrt()).collect();
        assert_eq!(batch_quantile_in(&v, 0.95, BATCHES), batch_quantile(&v, 0.95));
        let (s, h) = batch_quantile_in(&v, 0.95, 10);
        let qs: Vec<f64> = v.chunks_exact(40).map(|c| quantile(c, 0.95)).collect();
        let mean = qs.iter().sum::<f64>() / 10.0;
        let sd = (qs.iter().map(|q| (q - mean).powi(2)).sum::<f64>() / 9.0).sqrt();
        assert_eq!(s, quantile(&v, 0.95));
        assert!((h - 2.262_157_163 * sd / 10f64.sqrt()).abs() < 1e-12 * h, "{h}");
        assert!(batch_quantile_in(&v[..5], 0.95, 10).1.is_nan());
        assert!(batch_quantile_in(&v, 0.95, 1).1.is_nan());
    }

    /// A short record is cut into batches of at least [`MIN_BATCH`] periods, never into
    /// batches of one or two: 38 values give 3 batches of 12 (t on 2 degrees of freedom), 19
    /// values no interval; 400 and more the measurement's 20.
    #[test]
    fn short_records_keep_their_batches_long() {
        assert_eq!([batches_for(19), batches_for(20), batches_for(38), batches_for(113)], [0, 2, 3, 11]);
        assert_eq!([batches_for(200), batches_for(400), batches_for(5000)], [BATCHES; 3]);
        let v: Vec<f64> = (0..38).map(|i| ((i * 7919 % 41) as f64).sqrt()).collect();
        let (s, h) = batch_quantile(&v, 0.95);
        let qs: Vec<f64> = v.chunks_exact(12).map(|c| quantile(c, 0.95)).collect();
        let mean = qs.iter().sum::<f64>() / 3.0;
        let sd = (qs.iter().map(|q| (q - mean).powi(2)).sum::<f64>() / 2.0).sqrt();
        assert_eq!(s, quantile(&v, 0.95));
        assert!((h - 4.302_652_730 * sd / 3f64.sqrt()).abs() < 1e-12 * h, "{h}");
        assert!(batch_quantile(&v[..19], 0.95).1.is_nan() && batch_mean(&v[..19]).1.is_nan());
        let (m, hm) = batch_mean(&v);
        assert_eq!(m, v.iter().sum::<f64>() / 38.0);
        assert!(hm.is_finite());
    }

    /// Independent normal-ish samples: the batch interval covers the true mean about 95 % of
    /// the time over many records (coverage, not a single draw).
    #[test]
    fn batch_means_cover_the_mean() {
        let mut state = 12345u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut covered = 0;
        for _ in 0..400 {
            // Sum of 12 uniforms minus 6: mean 0, variance 1.
            let v: Vec<f64> = (0..400).map(|_| (0..12).map(|_| uniform()).sum::<f64>() - 6.0).collect();
            let (m, h) = batch_mean(&v);
            covered += (m.abs() <= h) as usize;
        }
        assert!((360..=395).contains(&covered), "{covered} of 400");
    }
}
