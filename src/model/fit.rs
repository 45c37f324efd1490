//! Model updating: a symmetric positive definite stiffness matrix fitted to measured natural
//! frequencies and mode shapes, the masses held fixed (docs/model.md section 1.3).
//!
//! Unknowns are the `n (n + 1) / 2` entries of `K` on and above the diagonal. Residuals are
//! the relative frequency errors (times `frequency_weight`) and, per mode, the differences of
//! the model's shape from the measured one, both normalised at the measured shape's largest
//! element (which is left out: it is 1 in both). Levenberg-Marquardt runs from several
//! starts (the symmetrised modal reconstruction `M Phi Omega^2 Phi^-1` and seeded
//! perturbations of it); the best fit is kept and the others tell whether it is unique.

use nalgebra::{DMatrix, DVector};

use super::least_squares::{levenberg_marquardt, LmOptions};
use super::modes::symmetric_modes;

/// Measured modal data.
#[derive(Debug, Clone)]
pub struct ModalData {
    /// Natural frequencies, rad/s, one per mode, ascending.
    pub omegas: Vec<f64>,
    /// Mode shapes, one row of `n` elements per mode.
    pub shapes: Vec<Vec<f64>>,
    /// Weight of a relative frequency error against a shape element's error.
    pub frequency_weight: f64,
    /// Weight of each shape element (0: not trusted), `shapes`' layout.
    pub shape_weights: Vec<Vec<f64>>,
}

/// Default weight of the frequencies: they are measured far more precisely than shapes.
pub const FREQUENCY_WEIGHT: f64 = 100.0;

/// Starts of the fit (the reconstruction and perturbations of it).
pub const STARTS: usize = 12;

/// Why measured modal data cannot be fitted.
#[derive(Debug, Clone, PartialEq)]
pub enum FitError {
    /// The number of modes or of shape elements does not match the masses.
    Shape {
        /// What does not match, in words.
        what: String,
    },
    /// A frequency is not positive and finite, or the frequencies are not increasing.
    Frequency {
        /// 1-based mode.
        mode: usize,
        /// The frequency given, rad/s.
        value: f64,
    },
    /// A shape element or weight is not finite (or a weight negative).
    Value {
        /// Which element or weight.
        what: String,
        /// The value given.
        value: f64,
    },
    /// The shapes are (nearly) linearly dependent: smallest over largest singular value.
    Dependent {
        /// Smallest over largest singular value of the shapes.
        ratio: f64,
    },
    /// No start reached a positive definite stiffness matrix.
    NotPositiveDefinite,
}

impl std::fmt::Display for FitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FitError::Shape { what } => write!(f, "{what}"),
            FitError::Frequency { mode, value } => write!(
                f,
                "natural frequency {} is {value}: frequencies must be positive, finite and strictly increasing",
                mode + 1
            ),
            FitError::Value { what, value } => write!(f, "{what} is {value}"),
            FitError::Dependent { ratio } => write!(
                f,
                "the mode shapes are not linearly independent (smallest/largest singular value {ratio:.1e} < 1e-6)"
            ),
            FitError::NotPositiveDefinite => {
                write!(f, "no start of the fit reached a positive definite stiffness matrix")
            }
        }
    }
}

impl std::error::Error for FitError {}

/// The fitted stiffness and how well it reproduces the data.
#[derive(Debug, Clone)]
pub struct StiffnessFit {
    /// Symmetric positive definite, N/m.
    pub stiffness: DMatrix<f64>,
    /// The model's natural frequencies, rad/s.
    pub omegas: Vec<f64>,
    /// Model minus measured frequency, rad/s.
    pub frequency_residuals: Vec<f64>,
    /// The model's shapes, normalised like the measured ones.
    pub shapes: Vec<Vec<f64>>,
    /// Model minus measured shape element.
    pub shape_residuals: Vec<Vec<f64>>,
    /// Condition number of `K` (largest over smallest eigenvalue).
    pub condition: f64,
    /// Starts tried, and how many reached the best cost (to 1e-8 relative).
    pub starts: usize,
    /// Index of the start that gave the best fit.
    pub starts_at_best: usize,
    /// Largest difference between the stiffness matrices of the starts at the best cost,
    /// relative to the largest entry of the best one.
    pub spread: f64,
    /// Largest off-diagonal of the measured shapes' `phi^T M phi`, normalised by the diagonal
    /// (0 for exactly mass-orthogonal data).
    pub orthogonality: f64,
    /// Weighted cost `1/2 |r|^2` of the best fit.
    pub cost: f64,
}

impl StiffnessFit {
    /// True when every start that reached the best cost found the same matrix.
    pub fn unique(&self) -> bool {
        self.spread < 1e-6
    }
}

/// Index of the largest-magnitude element.
fn reference_index(v: &[f64]) -> usize {
    (0..v.len()).fold(0, |best, j| if v[j].abs() > v[best].abs() { j } else { best })
}

fn unpack(x: &DVector<f64>, n: usize, scale: f64) -> DMatrix<f64> {
    let mut k = DMatrix::<f64>::zeros(n, n);
    let mut p = 0;
    for i in 0..n {
        for j in i..n {
            k[(i, j)] = x[p] * scale;
            k[(j, i)] = x[p] * scale;
            p += 1;
        }
    }
    k
}

fn pack(k: &DMatrix<f64>, scale: f64) -> DVector<f64> {
    let n = k.nrows();
    let mut v = Vec::with_capacity(n * (n + 1) / 2);
    for i in 0..n {
        for j in i..n {
            v.push(0.5 * (k[(i, j)] + k[(j, i)]) / scale);
        }
    }
    DVector::from_vec(v)
}

/// The model's frequencies and shapes normalised at the measured reference elements; `None`
/// when `k` is not positive definite.
fn model_modes(m: &DMatrix<f64>, k: &DMatrix<f64>, refs: &[usize]) -> Option<(Vec<f64>, Vec<Vec<f64>>)> {
    k.clone().cholesky()?;
    let modes = symmetric_modes(m, k);
    let shapes = refs
        .iter()
        .enumerate()
        .map(|(i, &r)| {
            let col = modes.mass_normalised.column(i);
            col.iter().map(|v| v / col[r]).collect()
        })
        .collect();
    Some((modes.omegas, shapes))
}

/// Checks the data's shape and values.
fn validate(masses: &[f64], data: &ModalData) -> Result<(), FitError> {
    let n = masses.len();
    if data.omegas.len() != n || data.shapes.len() != n || data.shape_weights.len() != n {
        return Err(FitError::Shape {
            what: format!(
                "{} masses need {n} frequencies, {n} shapes and {n} rows of shape weights (got {}, {}, {})",
                n,
                data.omegas.len(),
                data.shapes.len(),
                data.shape_weights.len()
            ),
        });
    }
    for (i, &w) in data.omegas.iter().enumerate() {
        if !(w.is_finite() && w > 0.0) || (i > 0 && w <= data.omegas[i - 1]) {
            return Err(FitError::Frequency { mode: i, value: w });
        }
    }
    if !(data.frequency_weight.is_finite() && data.frequency_weight > 0.0) {
        return Err(FitError::Value { what: "the frequency weight".into(), value: data.frequency_weight });
    }
    for i in 0..n {
        if data.shapes[i].len() != n || data.shape_weights[i].len() != n {
            return Err(FitError::Shape { what: format!("mode {} needs {n} shape elements and {n} weights", i + 1) });
        }
        for j in 0..n {
            let (v, w) = (data.shapes[i][j], data.shape_weights[i][j]);
            if !v.is_finite() {
                return Err(FitError::Value { what: format!("element {} of mode shape {}", j + 1, i + 1), value: v });
            }
            if !(w.is_finite() && w >= 0.0) {
                return Err(FitError::Value {
                    what: format!("the weight of element {} of mode shape {} (must be >= 0)", j + 1, i + 1),
                    value: w,
                });
            }
        }
    }
    let phi = DMatrix::from_fn(n, n, |r, c| data.shapes[c][r]);
    let sv = phi.singular_values();
    let (lo, hi) = (sv.min(), sv.max());
    if hi.is_nan() || hi <= 0.0 || lo / hi < 1e-6 {
        return Err(FitError::Dependent { ratio: if hi > 0.0 { lo / hi } else { 0.0 } });
    }
    Ok(())
}

/// A deterministic pseudo-random sequence in [-1, 1) (xorshift64*), for the perturbed starts.
struct Jitter(u64);

impl Jitter {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Fits a symmetric positive definite `K` to `data` with the masses fixed.
pub fn fit_stiffness(masses: &[f64], data: &ModalData) -> Result<StiffnessFit, FitError> {
    validate(masses, data)?;
    let n = masses.len();
    let m = DMatrix::from_diagonal(&DVector::from_column_slice(masses));
    let refs: Vec<usize> = data.shapes.iter().map(|s| reference_index(s)).collect();
    let measured: Vec<Vec<f64>> =
        data.shapes.iter().zip(&refs).map(|(s, &r)| s.iter().map(|v| v / s[r]).collect()).collect();

    let residuals = |k: &DMatrix<f64>| -> Option<DVector<f64>> {
        let (omegas, shapes) = model_modes(&m, k, &refs)?;
        let mut r = Vec::with_capacity(n * n);
        for i in 0..n {
            r.push(data.frequency_weight * (omegas[i] / data.omegas[i] - 1.0));
            for j in (0..n).filter(|&j| j != refs[i]) {
                r.push(data.shape_weights[i][j] * (shapes[i][j] - measured[i][j]));
            }
        }
        Some(DVector::from_vec(r))
    };

    // The modal reconstruction K = M Phi Omega^2 Phi^-1 (exact for mass-orthogonal data),
    // symmetrised; the scale keeps the unknowns near 1.
    let phi = DMatrix::from_fn(n, n, |r, c| measured[c][r]);
    let omega2 = DMatrix::from_diagonal(&DVector::from_iterator(n, data.omegas.iter().map(|w| w * w)));
    let phi_inv = phi.clone().try_inverse().ok_or(FitError::Dependent { ratio: 0.0 })?;
    let recon = &m * &phi * omega2 * phi_inv;
    let recon = (&recon + recon.transpose()) * 0.5;
    let scale = recon.diagonal().iter().map(|v| v.abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let base = pack(&recon, scale);
    // The fallback start: a diagonal K giving each mass the mean measured omega^2.
    let mean_w2 = data.omegas.iter().map(|w| w * w).sum::<f64>() / n as f64;
    let diag = pack(&DMatrix::from_diagonal(&DVector::from_iterator(n, masses.iter().map(|mi| mi * mean_w2))), scale);

    let mut jitter = Jitter(0x5eed_5407_da3b);
    let mut fits: Vec<(f64, DMatrix<f64>)> = Vec::new();
    for s in 0..STARTS {
        let x0 = match s {
            0 => base.clone(),
            1 => diag.clone(),
            _ => base.map(|v| v + 0.3 * jitter.next() * v.abs().max(0.05)),
        };
        let r = |x: &DVector<f64>| residuals(&unpack(x, n, scale));
        if let Some(out) = levenberg_marquardt(r, x0, LmOptions::default()) {
            fits.push((out.cost, unpack(&out.x, n, scale)));
        }
    }
    let best = fits.iter().min_by(|a, b| a.0.total_cmp(&b.0)).cloned().ok_or(FitError::NotPositiveDefinite)?;
    let (cost, k) = best;
    let at_best: Vec<&DMatrix<f64>> =
        fits.iter().filter(|(c, _)| *c <= cost * (1.0 + 1e-8) + 1e-24).map(|(_, k)| k).collect();
    let kmax = k.amax();
    let spread = at_best.iter().map(|other| (*other - &k).amax() / kmax).fold(0.0, f64::max);

    let (omegas, shapes) = model_modes(&m, &k, &refs).ok_or(FitError::NotPositiveDefinite)?;
    let eig = k.clone().symmetric_eigen().eigenvalues;
    let condition = eig.max() / eig.min();
    let mut orthogonality: f64 = 0.0;
    for i in 0..n {
        for j in 0..n {
            if i != j {
                let (a, b) = (phi.column(i), phi.column(j));
                let mij = (a.transpose() * &m * b)[(0, 0)];
                let mii = (a.transpose() * &m * a)[(0, 0)];
                let mjj = (b.transpose() * &m * b)[(0, 0)];
                orthogonality = orthogonality.max(mij.abs() / (mii * mjj).sqrt());
            }
        }
    }
    Ok(StiffnessFit {
        frequency_residuals: omegas.iter().zip(&data.omegas).map(|(a, b)| a - b).collect(),
        shape_residuals: shapes
            .iter()
            .zip(&measured)
            .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x - y).collect())
            .collect(),
        omegas,
        shapes,
        condition,
        starts: STARTS,
        starts_at_best: at_best.len(),
        spread,
        orthogonality,
        cost,
        stiffness: k,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::structure::chain_stiffness;

    fn data_of(m: &[f64], k: &DMatrix<f64>) -> ModalData {
        let mm = DMatrix::from_diagonal(&DVector::from_column_slice(m));
        let modes = symmetric_modes(&mm, k);
        let n = m.len();
        let shapes = (0..n)
            .map(|i| {
                let c = modes.mass_normalised.column(i);
                let r = reference_index(c.as_slice());
                c.iter().map(|v| v / c[r]).collect()
            })
            .collect();
        ModalData {
            omegas: modes.omegas,
            shapes,
            frequency_weight: FREQUENCY_WEIGHT,
            shape_weights: vec![vec![1.0; n]; n],
        }
    }

    #[test]
    fn recovers_a_known_stiffness_from_its_own_modes() {
        let m = [0.74, 0.71, 0.64];
        let mut k = chain_stiffness(&[24.3e3, 21.8e3, 19.8e3]);
        k[(0, 0)] += 6.6e3;
        k[(0, 2)] = 1.5e3;
        k[(2, 0)] = 1.5e3;
        let fit = fit_stiffness(&m, &data_of(&m, &k)).unwrap();
        let err = (&fit.stiffness - &k).amax() / k.amax();
        assert!(err < 1e-8, "relative error {err:e}\n{}", fit.stiffness);
        assert!(fit.unique(), "spread {}", fit.spread);
        assert!(fit.orthogonality < 1e-12);
    }

    #[test]
    fn dependent_shapes_and_bad_frequencies_are_refused() {
        let m = [1.0, 1.0];
        let ok = ModalData {
            omegas: vec![10.0, 20.0],
            shapes: vec![vec![1.0, 0.5], vec![1.0, 0.5]],
            frequency_weight: FREQUENCY_WEIGHT,
            shape_weights: vec![vec![1.0; 2]; 2],
        };
        assert!(matches!(fit_stiffness(&m, &ok), Err(FitError::Dependent { .. })));
        let bad = ModalData { omegas: vec![20.0, 10.0], shapes: vec![vec![1.0, 0.5], vec![-0.5, 1.0]], ..ok.clone() };
        assert!(matches!(fit_stiffness(&m, &bad), Err(FitError::Frequency { mode: 1, .. })));
        let bad = ModalData { omegas: vec![0.0, 10.0], ..bad };
        assert!(matches!(fit_stiffness(&m, &bad), Err(FitError::Frequency { mode: 0, .. })));
    }
}
