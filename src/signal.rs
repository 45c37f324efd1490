//! Measures of sampled signals, applied alike to computed histories and to reference data:
//! decay envelopes and decay times, the log decrement, and the spectrum. No physics here.

/// Peaks of `|y|`: samples larger than both neighbours (ties to the right count once),
/// refined by the parabola through the peak and its neighbours. Returns (time, value).
pub fn envelope(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    let mut out = Vec::new();
    for i in 1..n.saturating_sub(1) {
        let (a, b, c) = (y[i - 1].abs(), y[i].abs(), y[i + 1].abs());
        if b > a && b >= c {
            out.push(refine(t[i - 1], t[i], t[i + 1], a, b, c));
        }
    }
    out
}

/// The vertex of the parabola through three equally spaced points (the middle one highest).
fn refine(t0: f64, t1: f64, t2: f64, a: f64, b: f64, c: f64) -> (f64, f64) {
    let den = a - 2.0 * b + c;
    if den >= 0.0 {
        return (t1, b);
    }
    let p = 0.5 * (a - c) / den;
    let h = 0.5 * (t2 - t0);
    (t1 + p * h, b - 0.25 * (a - c) * p)
}

/// The envelope as it falls for good: at each peak, the largest of it and every later peak
/// (non-increasing; it crosses a level where [`decay_time`] says).
pub fn falling_envelope(peaks: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = peaks.to_vec();
    let mut running = 0.0_f64;
    for p in out.iter_mut().rev() {
        running = running.max(p.1);
        p.1 = running;
    }
    out
}

/// The time at which the envelope falls to `level` (e.g. 0.1) of its first peak for good:
/// between the last peak at or above the threshold and the next one, interpolated in the
/// logarithm. `None` when the last peak is still above it (not reached in the record).
pub fn decay_time(env: &[(f64, f64)], level: f64) -> Option<f64> {
    let first = env.first()?.1;
    let threshold = level * first;
    let last_above = env.iter().rposition(|p| p.1 >= threshold)?;
    let (t0, a0) = env[last_above];
    let (t1, a1) = *env.get(last_above + 1)?;
    let f = (a0.ln() - threshold.ln()) / (a0.ln() - a1.ln());
    Some(t0 + f * (t1 - t0))
}

/// A stretch of a decaying oscillation: its amplitude and the damping ratio from the log
/// decrement over it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decrement {
    /// Time between the two peaks, s.
    pub t: f64,
    /// Geometric mean of the two peak magnitudes.
    pub amplitude: f64,
    /// `delta / sqrt(pi^2 + delta^2)` with `delta = ln(A_k / A_k+s) / s` per half cycle.
    pub zeta: f64,
}

/// Log decrements of a (nearly) single-mode decaying signal: the signal is split at its sign
/// changes into half waves, each half wave's largest magnitude is refined by a parabola, and
/// peaks `span` half cycles apart give the damping ratio (a longer span averages out the
/// scatter of an impact damper). Exact for `e^{-zeta w t} sin(w_d t + p)` up to the
/// parabola's error.
pub fn log_decrements(t: &[f64], y: &[f64], span: usize) -> Vec<Decrement> {
    let n = t.len().min(y.len());
    let span = span.max(1);
    let mut peaks: Vec<(f64, f64)> = Vec::new();
    let mut start = None;
    for i in 1..n {
        if y[i - 1] == 0.0 || y[i - 1].signum() != y[i].signum() {
            if let Some(s) = start {
                // The largest magnitude of the closed half wave [s, i).
                if let Some(k) = (s..i).max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs())) {
                    if k > 0 && k + 1 < n {
                        peaks.push(refine(t[k - 1], t[k], t[k + 1], y[k - 1].abs(), y[k].abs(), y[k + 1].abs()));
                    }
                }
            }
            start = Some(i);
        }
    }
    peaks
        .windows(span + 1)
        .filter(|w| w[0].1 > 0.0 && w[span].1 > 0.0)
        .map(|w| {
            let delta = (w[0].1 / w[span].1).ln() / span as f64;
            Decrement {
                t: 0.5 * (w[0].0 + w[span].0),
                amplitude: (w[0].1 * w[span].1).sqrt(),
                zeta: delta / (std::f64::consts::PI.powi(2) + delta * delta).sqrt(),
            }
        })
        .collect()
}

/// Magnitude of the Fourier transform `|dt sum_k y_k e^{-i 2 pi f k dt}|` of samples taken
/// every `dt` from `t = 0`, at each frequency of `freqs` (Hz). At the bins `f = m / (N dt)`
/// this is `dt` times the magnitude of the discrete Fourier transform; between them it is the
/// zero-padded transform.
pub fn spectrum(dt: f64, y: &[f64], freqs: &[f64]) -> Vec<f64> {
    spectra(dt, &[y], freqs).pop().unwrap_or_default()
}

/// Frequencies advanced side by side in [`spectra`].
const LANES: usize = 4;

/// [`spectrum`] of several signals sampled at the same times: one result per signal, the
/// same numbers as `spectrum` of each (every frequency runs the same rotation recurrence,
/// renormalised every 256 steps; the signals share it and four frequencies advance side by
/// side, which only reorders independent operations).
pub fn spectra(dt: f64, ys: &[&[f64]], freqs: &[f64]) -> Vec<Vec<f64>> {
    let len = ys.iter().map(|y| y.len()).min().unwrap_or(0);
    let mut out = vec![Vec::with_capacity(freqs.len()); ys.len()];
    for chunk in freqs.chunks(LANES) {
        let mut c = [1.0_f64; LANES];
        let mut s = [0.0_f64; LANES];
        for (l, &f) in chunk.iter().enumerate() {
            (s[l], c[l]) = (-2.0 * std::f64::consts::PI * f * dt).sin_cos();
        }
        let (mut wr, mut wi) = ([1.0_f64; LANES], [0.0_f64; LANES]);
        let mut re = vec![[0.0_f64; LANES]; ys.len()];
        let mut im = vec![[0.0_f64; LANES]; ys.len()];
        for k in 0..len {
            for (j, y) in ys.iter().enumerate() {
                let v = y[k];
                for l in 0..LANES {
                    re[j][l] += v * wr[l];
                    im[j][l] += v * wi[l];
                }
            }
            for l in 0..LANES {
                let nr = wr[l] * c[l] - wi[l] * s[l];
                wi[l] = wr[l] * s[l] + wi[l] * c[l];
                wr[l] = nr;
            }
            if k % 256 == 255 {
                for l in 0..LANES {
                    let norm = wr[l].hypot(wi[l]);
                    wr[l] /= norm;
                    wi[l] /= norm;
                }
            }
        }
        for (j, o) in out.iter_mut().enumerate() {
            o.extend((0..chunk.len()).map(|l| dt * re[j][l].hypot(im[j][l])));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn damped(zeta: f64, w: f64, dt: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let wd = w * (1.0 - zeta * zeta).sqrt();
        let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
        let y = t.iter().map(|&t| (-zeta * w * t).exp() * (wd * t).sin()).collect();
        (t, y)
    }

    #[test]
    fn log_decrement_recovers_the_damping_ratio() {
        for zeta in [0.002, 0.01, 0.05] {
            let (t, y) = damped(zeta, 2.0 * PI * 20.0, 1e-4, 20_000);
            let d = log_decrements(&t, &y, 1 + (zeta * 1000.0) as usize % 4);
            assert!(d.len() > 20);
            for x in &d {
                assert!((x.zeta - zeta).abs() < 1e-3 * zeta, "{} vs {zeta}", x.zeta);
            }
        }
    }

    #[test]
    fn decay_time_of_an_exponential_envelope() {
        let zeta = 0.01;
        let w = 2.0 * PI * 50.0;
        let (t, y) = damped(zeta, w, 1e-4, 30_000);
        let env = envelope(&t, &y);
        let first = env[0];
        for level in [0.5, 0.1, 0.01] {
            let td = decay_time(&env, level).unwrap();
            // The envelope e^{-zeta w t} reaches level * (first peak) at t_first + ln(1/level) / (zeta w).
            let expected = first.0 + (1.0 / level).ln() / (zeta * w);
            assert!((td - expected).abs() < 2e-3 * expected, "{level}: {td} vs {expected}");
        }
        assert_eq!(decay_time(&env, 1e-9), None);
    }

    #[test]
    fn spectrum_peaks_at_the_frequency_and_matches_the_dft() {
        let dt = 1e-3;
        let n = 1000;
        let y: Vec<f64> = (0..n).map(|k| (2.0 * PI * 50.0 * k as f64 * dt).cos()).collect();
        let s = spectrum(dt, &y, &[49.0, 50.0, 51.0]);
        // A whole number of cycles: the 50 Hz bin holds N/2 * dt, the neighbours nothing.
        assert!((s[1] - 0.5 * n as f64 * dt).abs() < 1e-9, "{}", s[1]);
        assert!(s[0] < 1e-9 && s[2] < 1e-9, "{s:?}");
    }

    /// One frequency at a time, one signal at a time: the plain form of the recurrence.
    fn scalar_spectrum(dt: f64, y: &[f64], freqs: &[f64]) -> Vec<f64> {
        freqs
            .iter()
            .map(|&f| {
                let (s, c) = (-2.0 * PI * f * dt).sin_cos();
                let (mut wr, mut wi, mut re, mut im) = (1.0_f64, 0.0_f64, 0.0, 0.0);
                for (k, &v) in y.iter().enumerate() {
                    re += v * wr;
                    im += v * wi;
                    (wr, wi) = (wr * c - wi * s, wr * s + wi * c);
                    if k % 256 == 255 {
                        let norm = wr.hypot(wi);
                        (wr, wi) = (wr / norm, wi / norm);
                    }
                }
                dt * re.hypot(im)
            })
            .collect()
    }

    #[test]
    fn spectra_of_several_signals_equal_each_signal_s_own_bit_for_bit() {
        let dt = 1e-4;
        let (_, a) = damped(0.01, 2.0 * PI * 13.0, dt, 3001);
        let (_, b) = damped(0.03, 2.0 * PI * 41.0, dt, 3001);
        let c: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - 0.3 * y).collect();
        // Seven frequencies: one full group of four and a partial one.
        let freqs = [0.1, 5.0, 13.0, 13.05, 40.0, 41.0, 79.9];
        let all = spectra(dt, &[&a, &b, &c], &freqs);
        for (y, got) in [&a, &b, &c].into_iter().zip(&all) {
            let want = scalar_spectrum(dt, y, &freqs);
            assert_eq!(
                got.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                want.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
            );
        }
        assert!(spectra(dt, &[], &freqs).is_empty());
        assert_eq!(spectrum(dt, &a, &[]), Vec::<f64>::new());
    }
}
