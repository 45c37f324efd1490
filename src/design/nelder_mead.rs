//! Nelder-Mead's simplex method with the standard coefficients (reflection 1, expansion 2,
//! contraction 1/2, shrink 1/2), step for step as argmin 0.11 runs it (a test holds the two
//! together bit for bit), with one more way for a run to end: its simplex has shrunk below a
//! size in the search's coordinates. On an objective with noise (a design whose bands hold
//! points that never settle) the spread of the simplex's objectives may never fall below the
//! tolerance however small the simplex, and a run would spend all its iterations there.
//!
//! The objective is asked with the comparison its value feeds (`cost(x, cap)`): a reflected
//! point only against the worst vertex, an expanded or outside-contracted one against the
//! reflected point, an inside-contracted one against the worst. Above `cap` its value decides
//! nothing and is never kept, so the objective may return any number above `cap` there (a
//! design's evaluation ends its sweeps once a certified orbit shows it above): the same
//! steps, the same vertices, bit for bit.

/// When a run ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Iterations at most.
    pub max_iters: u64,
    /// The run ends when the standard deviation of the simplex's objectives is below this.
    pub sd_tolerance: f64,
    /// The run ends when every vertex lies within this of the best one in every coordinate
    /// (0: never).
    pub step_tolerance: f64,
}

/// A vertex of the simplex and its objective.
type Vertex = (Vec<f64>, f64);

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The simplex's objectives agree to the tolerance, or it shrank below its size.
    Converged,
    /// It spent its iterations.
    Iterations,
}

/// A run of the method that can be advanced a few iterations at a time: advanced in any
/// number of pieces it makes the same steps, evaluation for evaluation, as [`minimise`] (a
/// search advances all its runs in rounds, so that a time limit leaves none far behind).
#[derive(Debug, Clone)]
pub struct Simplex {
    p: Vec<Vertex>,
    iter: u64,
}

impl Simplex {
    /// The simplex of `vertices` (`d + 1` points of `d` coordinates), each evaluated.
    pub fn new<E>(mut cost: impl FnMut(&[f64], f64) -> Result<f64, E>, vertices: Vec<Vec<f64>>) -> Result<Self, E> {
        let mut p = Vec::with_capacity(vertices.len());
        for v in vertices {
            let c = cost(&v, f64::INFINITY)?;
            p.push((v, c));
        }
        sort(&mut p);
        Ok(Simplex { p, iter: 0 })
    }

    /// How the run has ended, if it has.
    pub fn ended(&self, s: &Settings) -> Option<End> {
        if self.p.len() <= 1 || spread(&self.p) < s.sd_tolerance || small(&self.p, s.step_tolerance) {
            Some(End::Converged)
        } else if self.iter >= s.max_iters {
            Some(End::Iterations)
        } else {
            None
        }
    }

    /// At most `iterations` more iterations, fewer when the run ends; the first error of
    /// `cost` ends the piece with it (the simplex keeps what it had).
    pub fn advance<E>(
        &mut self,
        mut cost: impl FnMut(&[f64], f64) -> Result<f64, E>,
        s: &Settings,
        iterations: u64,
    ) -> Result<Option<End>, E> {
        for _ in 0..iterations {
            if let Some(end) = self.ended(s) {
                return Ok(Some(end));
            }
            step(&mut self.p, &mut cost)?;
            self.iter += 1;
        }
        Ok(self.ended(s))
    }

    /// Iterations made.
    pub fn iterations(&self) -> u64 {
        self.iter
    }

    /// The best vertex and its objective.
    pub fn best(&self) -> &Vertex {
        &self.p[0]
    }
}

/// Minimises `cost` from the simplex `vertices` (`d + 1` points of `d` coordinates) and
/// returns the best vertex and its objective. The first error of `cost` ends the run with it.
/// `cost(x, cap)`: the objective at `x`, or any number above `cap` where it is above `cap`.
pub fn minimise<E>(
    mut cost: impl FnMut(&[f64], f64) -> Result<f64, E>,
    vertices: Vec<Vec<f64>>,
    s: &Settings,
) -> Result<Vertex, E> {
    let mut run = Simplex::new(&mut cost, vertices)?;
    run.advance(&mut cost, s, u64::MAX)?;
    Ok(run.p.swap_remove(0))
}

/// Sorts the vertices by objective (a stable sort: of equal ones the earlier stays first).
fn sort(p: &mut [Vertex]) {
    p.sort_by(|a, b| a.1.partial_cmp(&b.1).unwrap_or(std::cmp::Ordering::Equal));
}

/// The sample standard deviation of the objectives.
fn spread(p: &[Vertex]) -> f64 {
    let n = p.len() as f64;
    let c0 = p.iter().map(|v| v.1).sum::<f64>() / n;
    (1.0 / (n - 1.0) * p.iter().map(|v| (v.1 - c0).powi(2)).sum::<f64>()).sqrt()
}

/// Whether every vertex is within `tol` of the best in every coordinate.
fn small(p: &[Vertex], tol: f64) -> bool {
    p[1..].iter().all(|v| v.0.iter().zip(&p[0].0).all(|(a, b)| (a - b).abs() < tol))
}

/// `a + (b - a) * f`, coordinate by coordinate.
fn toward(a: &[f64], b: &[f64], f: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a + (b - a) * f).collect()
}

/// One iteration: reflect the worst vertex through the centroid of the others, then expand,
/// contract or shrink.
fn step<E>(p: &mut [Vertex], cost: &mut impl FnMut(&[f64], f64) -> Result<f64, E>) -> Result<(), E> {
    let n = p.len();
    let others = n - 1;
    let mut x0 = p[0].0.clone();
    for v in &p[1..others] {
        x0.iter_mut().zip(&v.0).for_each(|(a, b)| *a += b);
    }
    let scale = 1.0 / others as f64;
    x0.iter_mut().for_each(|a| *a *= scale);
    let (best, worst, second) = (p[0].1, p[n - 1].1, p[n - 2].1);
    // x0 + (x0 - worst) * 1
    let xr: Vec<f64> = x0.iter().zip(&p[n - 1].0).map(|(c, w)| c + (c - w) * 1.0).collect();
    // At or above the worst only the inside contraction follows, which does not read it.
    let cr = cost(&xr, worst)?;
    if cr < second && cr >= best {
        p[n - 1] = (xr, cr);
    } else if cr < best {
        let xe = toward(&x0, &xr, 2.0);
        let ce = cost(&xe, cr)?;
        p[n - 1] = if ce < cr { (xe, ce) } else { (xr, cr) };
    } else {
        let outside = cr < worst;
        let xc = if outside { toward(&x0, &xr, 0.5) } else { toward(&x0, &p[n - 1].0, 0.5) };
        let cc = cost(&xc, if outside { cr } else { worst })?;
        if (outside && cc <= cr) || (!outside && cc < worst) {
            p[n - 1] = (xc, cc);
        } else {
            let first = p[0].0.clone();
            for v in &mut p[1..] {
                v.0 = toward(&first, &v.0, 0.5);
                v.1 = cost(&v.0, f64::INFINITY)?;
            }
        }
    }
    sort(p);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use argmin::core::{CostFunction, Executor, State};
    use argmin::solver::neldermead::NelderMead;

    /// Rosenbrock's valley, and a bumpy bowl whose bumps (a hash of the point's bits) are the
    /// noise of a design's unsettled points.
    fn rosenbrock(x: &[f64]) -> f64 {
        x.windows(2).map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2)).sum()
    }
    fn bumpy(x: &[f64]) -> f64 {
        let h = x.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| (h ^ v.to_bits()).wrapping_mul(0x0100_0000_01b3));
        x.iter().map(|v| (v - 0.3) * (v - 0.3)).sum::<f64>() + 1e-3 * (h >> 11) as f64 / (1u64 << 53) as f64
    }

    struct F(fn(&[f64]) -> f64, std::cell::Cell<u64>);
    impl CostFunction for F {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
            self.1.set(self.1.get() + 1);
            Ok((self.0)(x))
        }
    }

    fn simplex(x0: &[f64]) -> Vec<Vec<f64>> {
        let mut s = vec![x0.to_vec()];
        for i in 0..x0.len() {
            let mut v = x0.to_vec();
            v[i] += 1.0;
            s.push(v);
        }
        s
    }

    #[test]
    fn the_same_steps_as_argmin_bit_for_bit() {
        for (f, x0, tol, iters) in [
            (rosenbrock as fn(&[f64]) -> f64, vec![-1.2, 1.0], 1e-9, 400),
            (rosenbrock, vec![0.5, -0.5, 2.0], 1e-6, 100),
            (bumpy, vec![2.0, -1.0, 0.0], 1e-6, 100),
            (bumpy, vec![1.0], 1e-3, 50),
        ] {
            let ours = std::cell::Cell::new(0u64);
            let (x, c) = minimise(
                |x, _| {
                    ours.set(ours.get() + 1);
                    Ok::<_, ()>(f(x))
                },
                simplex(&x0),
                &Settings { max_iters: iters, sd_tolerance: tol, step_tolerance: 0.0 },
            )
            .unwrap();
            let solver = NelderMead::new(simplex(&x0)).with_sd_tolerance(tol).unwrap();
            let problem = F(f, std::cell::Cell::new(0));
            let res = Executor::new(problem, solver).configure(|s| s.max_iters(iters)).run().unwrap();
            let theirs = res.problem.problem.as_ref().unwrap().1.get();
            let st = res.state();
            assert_eq!(st.get_best_param().unwrap(), &x, "{x0:?}");
            assert_eq!(st.get_best_cost().to_bits(), c.to_bits());
            assert_eq!(theirs, ours.get(), "evaluations from {x0:?}");
        }
    }

    #[test]
    fn a_small_simplex_ends_a_run_on_a_noisy_objective() {
        // The bumps keep the objectives' spread near 3e-4 however small the simplex: the
        // spread never ends the run; the simplex's size does, near the bowl's bottom, sooner.
        let run = |step| {
            let mut n = 0;
            let (x, _) = minimise(
                |x, _| {
                    n += 1;
                    Ok::<_, ()>(bumpy(x))
                },
                simplex(&[2.0, -1.0, 0.0]),
                &Settings { max_iters: 300, sd_tolerance: 1e-9, step_tolerance: step },
            )
            .unwrap();
            (x, n)
        };
        let (all, n_all) = run(0.0);
        let (small, n_small) = run(1e-2);
        assert!(n_small * 2 < n_all, "{n_small} against {n_all} evaluations");
        for x in [&all, &small] {
            assert!(x.iter().all(|v| (v - 0.3).abs() < 0.05), "{x:?}");
        }
    }

    #[test]
    fn a_run_advanced_in_pieces_makes_the_same_steps() {
        let settings = Settings { max_iters: 150, sd_tolerance: 1e-9, step_tolerance: 0.0 };
        fn count(f: fn(&[f64]) -> f64, n: &std::cell::Cell<u64>) -> impl FnMut(&[f64], f64) -> Result<f64, ()> + '_ {
            move |x, _| {
                n.set(n.get() + 1);
                Ok(f(x))
            }
        }
        for f in [rosenbrock as fn(&[f64]) -> f64, bumpy] {
            let (whole, pieces) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
            let (x, c) = minimise(count(f, &whole), simplex(&[0.5, -0.5, 2.0]), &settings).unwrap();
            let mut run = Simplex::new(count(f, &pieces), simplex(&[0.5, -0.5, 2.0])).unwrap();
            let mut rounds = 0;
            while run.advance(count(f, &pieces), &settings, 7).unwrap().is_none() {
                rounds += 1;
            }
            assert!(rounds > 3, "{rounds} rounds");
            assert_eq!((&run.best().0, run.best().1.to_bits()), (&x, c.to_bits()));
            assert_eq!(whole.get(), pieces.get());
        }
        let mut run = Simplex::new(|x, _| Ok::<_, ()>(rosenbrock(x)), simplex(&[-1.2, 1.0])).unwrap();
        assert_eq!(
            run.advance(|x, _| Ok::<_, ()>(rosenbrock(x)), &Settings { max_iters: 5, ..settings }, 100),
            Ok(Some(End::Iterations))
        );
    }

    #[test]
    fn an_objective_that_stops_above_its_cap_makes_the_same_steps() {
        // Above the comparison it feeds the objective answers infinity (a design's evaluation
        // ends its sweeps there): every vertex, objective and evaluation count is the same,
        // and a good share of the evaluations needed no value.
        let settings = Settings { max_iters: 200, sd_tolerance: 1e-9, step_tolerance: 0.0 };
        for (f, x0) in [
            (rosenbrock as fn(&[f64]) -> f64, vec![-1.2, 1.0]),
            (rosenbrock, vec![0.5, -0.5, 2.0]),
            (bumpy, vec![2.0, -1.0, 0.0]),
        ] {
            let (mut exact, mut lazy, mut capped) = (0u64, 0u64, 0u64);
            let whole = minimise(
                |x, _| {
                    exact += 1;
                    Ok::<_, ()>(f(x))
                },
                simplex(&x0),
                &settings,
            )
            .unwrap();
            let stopped = minimise(
                |x, cap| {
                    lazy += 1;
                    let v = f(x);
                    if v > cap {
                        capped += 1;
                        Ok::<_, ()>(f64::INFINITY)
                    } else {
                        Ok(v)
                    }
                },
                simplex(&x0),
                &settings,
            )
            .unwrap();
            assert_eq!((&whole.0, whole.1.to_bits()), (&stopped.0, stopped.1.to_bits()), "{x0:?}");
            assert_eq!(exact, lazy, "{x0:?}");
            assert!(capped * 5 > lazy, "{capped} of {lazy} evaluations above their cap from {x0:?}");
        }
    }

    #[test]
    fn an_error_of_the_objective_ends_the_run_with_it() {
        let mut n = 0;
        let r = minimise(
            |x, _| {
                n += 1;
                if n > 5 {
                    Err("stop")
                } else {
                    Ok(rosenbrock(x))
                }
            },
            simplex(&[0.0, 0.0]),
            &Settings { max_iters: 100, sd_tolerance: 0.0, step_tolerance: 0.0 },
        );
        assert_eq!(r, Err("stop"));
    }
}
