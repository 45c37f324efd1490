//! Newton's method on a periodic orbit's return map gives up early where it cannot converge:
//! when its iterates go round a cycle (docs/simulator.md, "Steady state and what is
//! measured"). On a scalar map whose Newton iterates are known in closed form.

use nalgebra::{DMatrix, DVector};
use shotdamp::model::{Damping, Structure};
use shotdamp::sim::orbits::periodic::{solve, NewtonOptions, OrbitError, Return, Section};
use shotdamp::sim::{Dynamics, State, System};

/// The return map `u -> u + f(u)` on R^1, with its exact Jacobian `1 + f'(u)`: Newton on its
/// fixed points is Newton on the roots of `f`, and counts its evaluations.
struct Roots<F: Fn(f64) -> (f64, f64)> {
    f: F,
    calls: std::cell::Cell<usize>,
}

impl<F: Fn(f64) -> (f64, f64)> Section for Roots<F> {
    fn shift(&self, dim: usize) -> DVector<f64> {
        DVector::zeros(dim)
    }
    fn state(&self, d: &Dynamics, _u: &DVector<f64>) -> State {
        State::at_rest(d)
    }
    fn map(&self, _d: &Dynamics, u: &DVector<f64>) -> Result<Return, OrbitError> {
        self.calls.set(self.calls.get() + 1);
        let (f, df) = (self.f)(u[0]);
        Ok(Return {
            image: DVector::from_element(1, u[0] + f),
            events: Vec::new(),
            jacobian: Some((DMatrix::from_element(1, 1, 1.0 + df), true)),
            d_omega: None,
        })
    }
}

fn dynamics() -> Dynamics {
    let structure = Structure::chain(&[1.0], &[1e4], Damping::ModalRatios(vec![0.01]));
    Dynamics::new(&System::plastic(structure, Vec::new(), 0, 1.0), 100.0).expect("one mass decomposes")
}

#[test]
fn newton_going_round_a_cycle_stops_at_the_first_repeat() {
    // f(x) = x^3 - 2x + 2 from x = 0: Newton goes 0, 1, 0, 1, ... for ever (the textbook
    // cycle). It stops before evaluating the second 1 again: three evaluations, not 13.
    let map = Roots { f: |x: f64| (x * x * x - 2.0 * x + 2.0, 3.0 * x * x - 2.0), calls: Default::default() };
    let opts = NewtonOptions { max_step: 10.0, ..NewtonOptions::default() };
    match solve(&map, &dynamics(), &DVector::from_element(1, 0.0), &opts) {
        Err(OrbitError::Cycling { residuals, to }) => {
            assert_eq!(residuals, vec![2.0, 1.0, 2.0]);
            assert_eq!(to, 1, "back to the iterate 1");
        }
        other => panic!("expected a cycle, got {other:?}"),
    }
    assert_eq!(map.calls.get(), 3);
    // The same root from a start that converges: no cycle is seen on the way.
    let map = Roots { f: |x: f64| (x * x * x - 2.0 * x + 2.0, 3.0 * x * x - 2.0), calls: Default::default() };
    let orbit = solve(&map, &dynamics(), &DVector::from_element(1, -2.0), &opts).expect("converges from -2");
    assert!((orbit.u[0] + 1.769_292_354_238_631).abs() < 1e-12, "{}", orbit.u[0]);
}
