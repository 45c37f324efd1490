//! Pseudo-arclength continuation of periodic orbits in a parameter (the forcing frequency, or
//! any parameter a family of dynamics depends on), through folds, with the stability of every
//! point and the folds and period doublings located on the way. No I/O.
//!
//! The unknowns are the section coordinates `u` of [`super::periodic`] and the scaled
//! parameter `q = p / p_scale`. Each step predicts along the unit tangent of the branch and
//! corrects with Newton's method on `G(u, p) = 0` plus the arclength condition
//! `t . (y - y_pred) = 0`. When the parameter is the forcing frequency and the section's map
//! carries the derivative in it through the linearised flow ([`super::periodic::Return::d_omega`]),
//! the derivative of `G` in `p` is that exact column; otherwise a central difference.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::periodic::{finish, signature, NewtonOptions, Orbit, OrbitError, Section, FD_STEP};
use crate::sim::motion::system::{Dynamics, SetupError};

/// Steps across a change of the orbit's events are refined down to `ds_max / KINK_REFINEMENT`.
const KINK_REFINEMENT: f64 = 64.0;

/// Dynamics at a parameter value.
pub type Family<'a> = dyn Fn(f64) -> Result<Dynamics, SetupError> + Sync + 'a;

/// What the continuation parameter is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Parameter {
    /// The forcing frequency in Hz, and nothing else changes with it: the family is the same
    /// system forced at `omega = 2 pi p`, so `dG/dp` is `2 pi dP/domega` from the map.
    FrequencyHz,
    /// Anything else (a force, a clearance, a dimensionless acceleration): `dG/dp` by
    /// central differences.
    Other,
}

/// Settings of a continuation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuationOptions {
    /// The parameter range; the branch stops when it leaves it.
    pub p_min: f64,
    /// Upper end of the parameter range.
    pub p_max: f64,
    /// Unit of the parameter in the arclength (e.g. 1 Hz).
    pub p_scale: f64,
    /// First, smallest and largest arclength step.
    pub ds: f64,
    /// Smallest arclength step.
    pub ds_min: f64,
    /// Largest arclength step.
    pub ds_max: f64,
    /// Most points on the branch.
    pub max_points: usize,
    /// Newton's method at each corrector.
    pub newton: NewtonOptions,
    /// What `p` is.
    pub parameter: Parameter,
}

/// One point of a branch.
#[derive(Debug, Clone)]
pub struct BranchPoint {
    /// The parameter (forcing frequency, rad/s, or as the caller defines it).
    pub p: f64,
    /// The orbit at `p`.
    pub orbit: Orbit,
    /// The parameter component of the unit tangent (changes sign at a fold).
    pub dp_ds: f64,
    /// Arclength from the start.
    pub s: f64,
}

/// Why a branch ended.
#[derive(Debug, Clone, PartialEq)]
pub enum BranchEnd {
    /// It left the parameter range.
    Range,
    /// No orbit could be continued further: the last error.
    Failed(String),
    /// The point budget ran out.
    Budget,
}

/// A special point on a branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Special {
    /// A fold (saddle-node): the branch turns back in the parameter.
    Fold {
        /// The parameter where the branch turns.
        p: f64,
    },
    /// A real multiplier crosses -1.
    PeriodDoubling {
        /// The parameter of the crossing.
        p: f64,
    },
    /// The branch turns back where an impact appears or vanishes (a graze): a non-smooth
    /// turning point, somewhere between the two points around it; `p` is the outer one.
    Grazing {
        /// The parameter of the point after the change.
        p: f64,
    },
}

impl Special {
    /// Where it is on the parameter axis.
    pub fn p(&self) -> f64 {
        match *self {
            Special::Fold { p } | Special::PeriodDoubling { p } | Special::Grazing { p } => p,
        }
    }

    /// Its name in tables and legends.
    pub fn name(&self) -> &'static str {
        match self {
            Special::Fold { .. } => "fold",
            Special::PeriodDoubling { .. } => "period doubling",
            Special::Grazing { .. } => "turn at a graze",
        }
    }
}

/// A continued branch.
#[derive(Debug, Clone)]
pub struct Branch {
    /// The points in the order continued.
    pub points: Vec<BranchPoint>,
    /// Folds, period doublings and grazings found between them.
    pub special: Vec<Special>,
    /// Why the continuation stopped.
    pub end: BranchEnd,
}

struct Solver<'a, S: Section> {
    family: &'a Family<'a>,
    problem: S,
    opts: ContinuationOptions,
}

/// `y = (u, p / p_scale)`.
fn join(u: &DVector<f64>, q: f64) -> DVector<f64> {
    let m = u.len();
    DVector::from_fn(m + 1, |i, _| if i < m { u[i] } else { q })
}

impl<S: Section> Solver<'_, S> {
    fn dynamics(&self, q: f64) -> Result<Dynamics, OrbitError> {
        let d = (self.family)(q * self.opts.p_scale)?;
        debug_assert!(
            self.opts.parameter != Parameter::FrequencyHz
                || (d.omega - 2.0 * std::f64::consts::PI * q * self.opts.p_scale).abs() <= 1e-12 * d.omega,
            "a frequency family forces at omega = 2 pi p"
        );
        Ok(d)
    }

    /// `dG/dq`: exact from the map's `dP/domega` when the parameter is the forcing frequency
    /// and the map gives it, else by central differences.
    fn g_q_of(&self, d_omega: Option<&DVector<f64>>, u: &DVector<f64>, q: f64) -> Result<DVector<f64>, OrbitError> {
        match (self.opts.parameter, d_omega) {
            (Parameter::FrequencyHz, Some(dw)) => Ok(dw * (2.0 * std::f64::consts::PI * self.opts.p_scale)),
            _ => self.g_q(u, q),
        }
    }

    /// `dG/dq` by central differences.
    fn g_q(&self, u: &DVector<f64>, q: f64) -> Result<DVector<f64>, OrbitError> {
        let a = self.problem.residual_only(&self.dynamics(q + FD_STEP)?, u)?;
        let b = self.problem.residual_only(&self.dynamics(q - FD_STEP)?, u)?;
        Ok((a - b) / (2.0 * FD_STEP))
    }

    /// The augmented matrix `[[J - I, G_q], [t^T]]`.
    fn augmented(&self, j: &DMatrix<f64>, gq: &DVector<f64>, t: &DVector<f64>) -> DMatrix<f64> {
        let m = j.nrows();
        DMatrix::from_fn(m + 1, m + 1, |r, c| {
            if r == m {
                t[c]
            } else if c == m {
                gq[r]
            } else {
                j[(r, c)] - if r == c { 1.0 } else { 0.0 }
            }
        })
    }

    /// The unit tangent at a solution, oriented along `prev`.
    fn tangent(&self, j: &DMatrix<f64>, gq: &DVector<f64>, prev: &DVector<f64>) -> Option<DVector<f64>> {
        let m = j.nrows();
        let a = self.augmented(j, gq, prev);
        let mut rhs = DVector::zeros(m + 1);
        rhs[m] = 1.0;
        let t = a.lu().solve(&rhs)?;
        let t = t.normalize();
        Some(if t.dot(prev) < 0.0 { -t } else { t })
    }

    /// Corrects a predicted point onto the branch; returns the orbit, `q`, the Jacobian's
    /// parameter column and the iterations used.
    fn correct(
        &self,
        pred: &DVector<f64>,
        t: &DVector<f64>,
        ds: f64,
    ) -> Result<(Orbit, f64, DVector<f64>, usize), OrbitError> {
        let m = pred.len() - 1;
        let mut y = pred.clone();
        let mut residuals = Vec::new();
        for it in 0..=self.opts.newton.max_iter {
            let u = y.rows(0, m).into_owned();
            let q = y[m];
            let d = self.dynamics(q)?;
            let (g, ret) = self.problem.residual(&d, &u)?;
            let arc = t.dot(&(&y - pred));
            let norm = g.amax().max(arc.abs());
            // Newton's method near a solution shrinks the residual; one that has not shrunk
            // over two iterations (typically a 2-cycle across a kink of the map, where an
            // impact appears or vanishes between the iterate and the branch) will not
            // converge: refuse at once, so that the step is shortened.
            let stalled = residuals.len() >= 2 && norm >= residuals[residuals.len() - 2];
            residuals.push(norm);
            if stalled {
                return Err(OrbitError::NoConvergence(residuals));
            }
            let (j, smooth) = self.problem.jacobian(&d, &u, &ret)?;
            let gq = self.g_q_of(ret.d_omega.as_ref(), &u, q)?;
            if norm < self.opts.newton.tol {
                return Ok((finish(&self.problem, &d, u, ret, residuals, j, smooth)?, q, gq, it));
            }
            let a = self.augmented(&j, &gq, t);
            let mut rhs = join(&g, arc);
            rhs.neg_mut();
            let dy = a.lu().solve(&rhs).ok_or(OrbitError::Singular)?;
            y += dy;
            // A corrector that wanders off the predicted point by more than the step has
            // jumped to another part of the branch (across a kink of the return map, where
            // an impact appears or vanishes): refuse it, so that the step is shortened.
            if (&y - pred).amax() > self.opts.newton.max_step.min(2.0 * ds) {
                return Err(OrbitError::NoConvergence(residuals));
            }
        }
        Err(OrbitError::NoConvergence(residuals))
    }
}

/// Continues the orbit found near `guess` at parameter `p0` in the direction `up` (increasing
/// parameter) or down, until the branch leaves the range, fails, or runs out of points.
pub fn continue_branch<S: Section>(
    family: &Family,
    problem: S,
    p0: f64,
    guess: &DVector<f64>,
    up: bool,
    opts: &ContinuationOptions,
) -> Result<Branch, OrbitError> {
    let solver = Solver { family, problem, opts: *opts };
    let q0 = p0 / opts.p_scale;
    let d0 = solver.dynamics(q0)?;
    let first = super::periodic::solve(&solver.problem, &d0, guess, &opts.newton)?;
    let gq = solver.g_q_of(first.d_omega.as_ref(), &first.u, q0)?;
    let m = first.u.len();
    let mut dir = DVector::zeros(m + 1);
    dir[m] = if up { 1.0 } else { -1.0 };
    let mut t = solver.tangent(&first.jacobian, &gq, &dir).ok_or(OrbitError::Singular)?;
    let mut points = vec![BranchPoint { p: p0, dp_ds: t[m], orbit: first, s: 0.0 }];
    let mut ds = opts.ds;
    let mut end = BranchEnd::Budget;
    // Set when the steps have shrunk to nothing at a kink: one step of full length across it
    // (a non-smooth turning point leaves in a direction the tangent does not predict).
    let mut leap_at: Option<usize> = None;
    while points.len() < opts.max_points {
        let last = &points[points.len() - 1];
        let y = join(&last.orbit.u, last.p / opts.p_scale);
        let pred = &y + &t * ds;
        match solver.correct(&pred, &t, ds) {
            Ok((orbit, q, gq, iters)) => {
                // Where an impact appears or vanishes the branch has a kink: step onto it in
                // small steps, so that both sides are resolved.
                let leaping = leap_at == Some(points.len());
                if !leaping
                    && ds > opts.ds_max / KINK_REFINEMENT
                    && signature(&orbit.events) != signature(&last.orbit.events)
                {
                    ds *= 0.5;
                    continue;
                }
                let p = q * opts.p_scale;
                if p < opts.p_min || p > opts.p_max {
                    end = BranchEnd::Range;
                    break;
                }
                let Some(nt) = solver.tangent(&orbit.jacobian, &gq, &t) else {
                    end = BranchEnd::Failed("singular tangent".into());
                    break;
                };
                t = nt;
                let s = last.s + ds;
                points.push(BranchPoint { p, dp_ds: t[m], orbit, s });
                if iters <= 2 {
                    ds = (ds * 1.5).min(opts.ds_max);
                }
            }
            Err(e) => {
                ds *= 0.5;
                if ds < opts.ds_min {
                    if leap_at != Some(points.len()) {
                        leap_at = Some(points.len());
                        ds = opts.ds_max;
                        continue;
                    }
                    end = BranchEnd::Failed(e.to_string());
                    break;
                }
            }
        }
    }
    let special = special_points(&points);
    Ok(Branch { points, special, end })
}

/// Folds (sign changes of `dp/ds`, located at the vertex of the parabola `p(s)` through the
/// three points around them) and period doublings (a real multiplier crossing -1: a sign
/// change of [`pd_measure`], located by linear interpolation).
fn special_points(points: &[BranchPoint]) -> Vec<Special> {
    let mut out = Vec::new();
    for w in points.windows(2) {
        if w[0].dp_ds * w[1].dp_ds < 0.0 && signature(&w[0].orbit.events) != signature(&w[1].orbit.events) {
            let p = if w[0].dp_ds > 0.0 { w[0].p.max(w[1].p) } else { w[0].p.min(w[1].p) };
            out.push(Special::Grazing { p });
        } else if w[0].dp_ds * w[1].dp_ds < 0.0 {
            // Take the neighbour triple (s, p) and the vertex of its parabola.
            let k = points.iter().position(|x| std::ptr::eq(x, &w[0])).unwrap_or(0);
            let (a, b) = if k + 2 < points.len() { (k, k + 2) } else { (k.saturating_sub(1), k + 1) };
            let tri = &points[a..=b];
            let p = if tri.len() == 3 { vertex(tri) } else { 0.5 * (w[0].p + w[1].p) };
            out.push(Special::Fold { p });
        }
        let (f0, f1) = (pd_measure(&w[0].orbit), pd_measure(&w[1].orbit));
        if let (Some(f0), Some(f1)) = (f0, f1) {
            if f0 * f1 < 0.0 {
                out.push(Special::PeriodDoubling { p: w[0].p + (w[1].p - w[0].p) * f0 / (f0 - f1) });
            }
        }
    }
    out
}

/// The vertex of the parabola through three points (s, p).
fn vertex(tri: &[BranchPoint]) -> f64 {
    let (s0, s1, s2) = (tri[0].s, tri[1].s, tri[2].s);
    let (p0, p1, p2) = (tri[0].p, tri[1].p, tri[2].p);
    let d01 = (p1 - p0) / (s1 - s0);
    let d12 = (p2 - p1) / (s2 - s1);
    let a = (d12 - d01) / (s2 - s0);
    if a == 0.0 {
        return p1;
    }
    let b = d01 - a * (s0 + s1);
    let sv = -b / (2.0 * a);
    p0 + d01 * (sv - s0) + a * (sv - s0) * (sv - s1)
}

/// `det(I + J) = prod (1 + lambda)` over the multipliers: its sign changes exactly where an
/// odd number of real multipliers cross -1 (a complex pair contributes `|1 + lambda|^2 > 0`,
/// a multiplier near +1 a positive factor), whatever the others do, so a period doubling is
/// seen even when the multiplier that crosses was one of a complex pair at the previous point
/// (a pair meets on the negative axis, splits, and one of the two crosses -1 within a step).
/// `None` without multipliers.
pub fn pd_measure(o: &Orbit) -> Option<f64> {
    if o.multipliers.is_empty() {
        return None;
    }
    Some(o.multipliers.iter().fold(Complex64::new(1.0, 0.0), |acc, z| acc * (z + 1.0)).re)
}
