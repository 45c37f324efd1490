//! Modal damping ratios calibrated against a measured (digitised) compliance of the bare
//! structure (docs/model.md section 1.4): least squares on the logarithm of the compliance at
//! the points near each resonance, with the half-power bandwidth as a second estimate.

use nalgebra::DVector;

use super::frf::receptance;
use super::least_squares::{levenberg_marquardt, LmOptions};
use super::modes::symmetric_modes;
use super::structure::{Damping, Structure};

/// Measured compliance of one mass, `|x / F|` (m/N) against frequency (Hz).
#[derive(Debug, Clone)]
pub struct Measured {
    /// 0-based mass.
    pub mass: usize,
    /// Measured frequencies, Hz.
    pub freq_hz: Vec<f64>,
    /// Measured compliance at each frequency, m/N.
    pub compliance: Vec<f64>,
}

/// The calibrated damping.
#[derive(Debug, Clone)]
pub struct DampingFit {
    /// One modal damping ratio per mode.
    pub ratios: Vec<f64>,
    /// Root mean square of `ln(model) - ln(measured)` over the points used.
    pub rms_log_residual: f64,
    /// Points used near each mode.
    pub points: Vec<usize>,
    /// The half-power bandwidth estimate of each mode, from the measured curve with the
    /// highest peak near it (`None` where the curve does not reach both half-power points).
    pub half_power: Vec<Option<f64>>,
}

/// Why the damping cannot be calibrated.
#[derive(Debug, Clone, PartialEq)]
pub enum DampingFitError {
    /// A point is not positive and finite, or a mass index is out of range.
    BadPoint {
        /// What is wrong, in words.
        what: String,
    },
    /// No measured point lies near this mode's natural frequency (0-based).
    NoPointsNear {
        /// 1-based mode.
        mode: usize,
        /// Its natural frequency, Hz.
        freq_hz: f64,
    },
}

impl std::fmt::Display for DampingFitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DampingFitError::BadPoint { what } => write!(f, "{what}"),
            DampingFitError::NoPointsNear { mode, freq_hz } => write!(
                f,
                "no measured point lies within the band of mode {} ({freq_hz:.2} Hz): its damping cannot be calibrated",
                mode + 1
            ),
        }
    }
}

impl std::error::Error for DampingFitError {}

/// Half width of the band around each natural frequency whose points are fitted, relative.
pub const BAND: f64 = 0.1;

/// Fits one modal damping ratio per mode of `structure` (its stiffness and masses; its own
/// damping is ignored) to `data`, the force on `driven`.
pub fn fit_modal_damping(
    structure: &Structure,
    driven: usize,
    data: &[Measured],
) -> Result<DampingFit, DampingFitError> {
    let n = structure.dof();
    let m0 = structure.mass_matrix();
    let modes = symmetric_modes(&m0, &structure.stiffness);
    let f_n: Vec<f64> = modes.omegas.iter().map(|w| w / (2.0 * std::f64::consts::PI)).collect();
    // Points within BAND of a natural frequency, by mode.
    let mut used: Vec<(usize, f64, f64)> = Vec::new();
    let mut per_mode = vec![0usize; n];
    for d in data {
        if d.mass >= n || d.freq_hz.len() != d.compliance.len() {
            return Err(DampingFitError::BadPoint {
                what: format!("a curve of mass {} (the structure has {n} masses) or of unequal lengths", d.mass + 1),
            });
        }
        for (&f, &c) in d.freq_hz.iter().zip(&d.compliance) {
            if !(f.is_finite() && c.is_finite() && f > 0.0 && c > 0.0) {
                return Err(DampingFitError::BadPoint {
                    what: format!(
                        "the point ({f} Hz, {c} m/N) of mass {}: both must be positive and finite",
                        d.mass + 1
                    ),
                });
            }
            if let Some(k) = (0..n).find(|&k| (f / f_n[k] - 1.0).abs() <= BAND) {
                per_mode[k] += 1;
                used.push((d.mass, f, c));
            }
        }
    }
    if let Some(k) = (0..n).find(|&k| per_mode[k] == 0) {
        return Err(DampingFitError::NoPointsNear { mode: k, freq_hz: f_n[k] });
    }
    let model = |x: &DVector<f64>| -> Option<DVector<f64>> {
        let ratios: Vec<f64> = x.iter().map(|v| v.exp()).collect();
        let s = structure.with_damping(Damping::ModalRatios(ratios));
        let r: Option<Vec<f64>> = used
            .iter()
            .map(|&(mass, f, c)| {
                let h = receptance(&s, &m0, driven, 2.0 * std::f64::consts::PI * f)?;
                Some(h[mass].norm().ln() - c.ln())
            })
            .collect();
        r.map(DVector::from_vec)
    };
    let x0 = DVector::from_element(n, 0.01f64.ln());
    let out = levenberg_marquardt(model, x0, LmOptions::default())
        .ok_or(DampingFitError::BadPoint { what: "the model's response is singular at a measured frequency".into() })?;
    let half_power = (0..n).map(|k| half_power(data, f_n[k])).collect();
    Ok(DampingFit {
        ratios: out.x.iter().map(|v| v.exp()).collect(),
        rms_log_residual: (out.residuals.norm_squared() / used.len() as f64).sqrt(),
        points: per_mode,
        half_power,
    })
}

/// The half-power estimate `zeta = (f_2 - f_1) / (2 f_peak)` near `f_n`, from the curve with
/// the highest peak within the band.
fn half_power(data: &[Measured], f_n: f64) -> Option<f64> {
    let mut best: Option<(f64, f64)> = None; // (peak, zeta)
    for d in data {
        let idx: Vec<usize> = (0..d.freq_hz.len()).filter(|&i| (d.freq_hz[i] / f_n - 1.0).abs() <= BAND).collect();
        let &ip = idx.iter().max_by(|&&a, &&b| d.compliance[a].total_cmp(&d.compliance[b]))?;
        let peak = d.compliance[ip];
        let level = peak / std::f64::consts::SQRT_2;
        let crossing = |range: &mut dyn Iterator<Item = usize>| -> Option<f64> {
            let mut prev = ip;
            for i in range {
                if d.compliance[i] <= level {
                    let (fa, fb, ca, cb) = (d.freq_hz[prev], d.freq_hz[i], d.compliance[prev], d.compliance[i]);
                    return Some(fa + (level - ca) * (fb - fa) / (cb - ca));
                }
                prev = i;
            }
            None
        };
        let f1 = crossing(&mut (0..ip).rev());
        let f2 = crossing(&mut (ip + 1..d.freq_hz.len()));
        if let (Some(f1), Some(f2)) = (f1, f2) {
            if best.is_none_or(|(p, _)| peak > p) {
                best = Some((peak, (f2 - f1) / (2.0 * d.freq_hz[ip])));
            }
        }
    }
    best.map(|(_, z)| z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::frf::compliance_curve;

    #[test]
    fn recovers_known_damping_from_its_own_response() {
        let zetas = vec![0.008, 0.012, 0.02];
        let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(zetas.clone()));
        let freq: Vec<f64> = (0..2900).map(|i| 2.0 + 0.02 * i as f64).collect();
        let omegas: Vec<f64> = freq.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
        let c = compliance_curve(&s, &s.mass_matrix(), 0, &omegas);
        let data: Vec<Measured> = (0..3)
            .map(|m| Measured { mass: m, freq_hz: freq.clone(), compliance: c.iter().map(|r| r[m]).collect() })
            .collect();
        let fit = fit_modal_damping(&s, 0, &data).unwrap();
        for (k, z) in zetas.iter().enumerate() {
            assert!((fit.ratios[k] / z - 1.0).abs() < 1e-6, "mode {k}: {:?}", fit.ratios);
            // The half-power estimate is the second method: close, not exact.
            let hp = fit.half_power[k].unwrap();
            assert!((hp / z - 1.0).abs() < 0.15, "mode {k}: half power {hp}");
        }
        assert!(fit.rms_log_residual < 1e-9);
    }

    #[test]
    fn a_mode_without_points_is_refused() {
        let s = Structure::chain(&[1.0, 1.0], &[1e4, 1e4], Damping::ModalRatios(vec![0.01, 0.01]));
        let data = [Measured { mass: 0, freq_hz: vec![9.5, 9.8], compliance: vec![1e-3, 2e-3] }];
        assert!(matches!(fit_modal_damping(&s, 0, &data), Err(DampingFitError::NoPointsNear { .. })));
    }
}
