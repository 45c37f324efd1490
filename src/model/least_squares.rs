//! A small Levenberg-Marquardt solver for nonlinear least squares, `min 1/2 |r(x)|^2`, with
//! a central-difference Jacobian: enough for the handful of unknowns of model updating and
//! damping calibration (docs/model.md section 1).

use nalgebra::{DMatrix, DVector};

/// Stopping rules.
#[derive(Debug, Clone, Copy)]
pub struct LmOptions {
    /// Most iterations (accepted or rejected steps).
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the cost by less than this fraction.
    pub cost_rtol: f64,
    /// Stop when the step is smaller than this, relative to `1 + |x|`.
    pub step_rtol: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        LmOptions { max_iterations: 400, cost_rtol: 1e-15, step_rtol: 1e-14 }
    }
}

/// The minimiser found.
#[derive(Debug, Clone)]
pub struct LmResult {
    /// The parameters found.
    pub x: DVector<f64>,
    /// `1/2 |r(x)|^2`.
    pub cost: f64,
    /// The residuals at `x`.
    pub residuals: DVector<f64>,
    /// Iterations made.
    pub iterations: usize,
}

/// Central-difference Jacobian of `r` at `x`; `None` where `r` is undefined nearby.
fn jacobian<F>(r: &F, x: &DVector<f64>, m: usize) -> Option<DMatrix<f64>>
where
    F: Fn(&DVector<f64>) -> Option<DVector<f64>>,
{
    let n = x.len();
    let mut j = DMatrix::<f64>::zeros(m, n);
    for k in 0..n {
        let h = 1e-7 * x[k].abs().max(1e-3);
        let mut xp = x.clone();
        let mut xm = x.clone();
        xp[k] += h;
        xm[k] -= h;
        let d = (r(&xp)? - r(&xm)?) / (2.0 * h);
        j.set_column(k, &d);
    }
    Some(j)
}

/// Minimises `1/2 |r(x)|^2` from `x0`. `r` returns `None` where it is undefined (e.g. a
/// stiffness matrix that is not positive definite): such steps are rejected like uphill
/// ones. `None` when `r(x0)` is undefined.
pub fn levenberg_marquardt<F>(r: F, x0: DVector<f64>, options: LmOptions) -> Option<LmResult>
where
    F: Fn(&DVector<f64>) -> Option<DVector<f64>>,
{
    let mut x = x0;
    let mut res = r(&x)?;
    let mut cost = 0.5 * res.norm_squared();
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut jac = jacobian(&r, &x, res.len());
    while iterations < options.max_iterations && cost > 0.0 {
        let Some(j) = jac.as_ref() else { break };
        iterations += 1;
        let jtj = j.transpose() * j;
        let g = j.transpose() * &res;
        let mut a = jtj.clone();
        for k in 0..a.nrows() {
            a[(k, k)] += lambda * jtj[(k, k)].max(1e-30);
        }
        let Some(step) = a.cholesky().map(|c| c.solve(&(-&g))) else {
            lambda *= 10.0;
            continue;
        };
        let trial = &x + &step;
        match r(&trial) {
            Some(rt) if 0.5 * rt.norm_squared() < cost => {
                let new_cost = 0.5 * rt.norm_squared();
                let small_gain = cost - new_cost <= options.cost_rtol * cost;
                let small_step = step.norm() <= options.step_rtol * (1.0 + x.norm());
                x = trial;
                res = rt;
                cost = new_cost;
                lambda = (lambda / 3.0).max(1e-12);
                if small_gain || small_step {
                    break;
                }
                jac = jacobian(&r, &x, res.len());
            }
            _ => {
                lambda *= 4.0;
                if lambda > 1e16 {
                    break;
                }
            }
        }
    }
    Some(LmResult { x, cost, residuals: res, iterations })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rosenbrock_reaches_its_minimum() {
        // r = (10 (y - x^2), 1 - x): the minimum is (1, 1) with zero cost.
        let r = |p: &DVector<f64>| Some(DVector::from_vec(vec![10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]]));
        let out = levenberg_marquardt(r, DVector::from_vec(vec![-1.2, 1.0]), LmOptions::default()).unwrap();
        assert!((out.x[0] - 1.0).abs() < 1e-9 && (out.x[1] - 1.0).abs() < 1e-9, "{:?}", out.x);
    }

    #[test]
    fn linear_least_squares_matches_the_normal_equations() {
        // Fit y = a + b t to four points: the closed form is the normal equations.
        let t = [0.0, 1.0, 2.0, 3.0];
        let y = [1.0, 2.9, 5.2, 6.8];
        let r = |p: &DVector<f64>| Some(DVector::from_iterator(4, t.iter().zip(y).map(|(t, y)| p[0] + p[1] * t - y)));
        let out = levenberg_marquardt(r, DVector::from_vec(vec![0.0, 0.0]), LmOptions::default()).unwrap();
        let a = DMatrix::from_fn(4, 2, |i, j| if j == 0 { 1.0 } else { t[i] });
        let exact = (a.transpose() * &a).try_inverse().unwrap() * a.transpose() * DVector::from_column_slice(&y);
        assert!((out.x - exact).norm() < 1e-9);
    }
}
