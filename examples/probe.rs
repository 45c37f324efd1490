use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::{steady_state, Dynamics, State, SteadyOptions, System};

fn main() {
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let args: Vec<String> = std::env::args().collect();
    let f: f64 = args.get(1).map(|a| a.parse().unwrap()).unwrap_or(49.5);
    let nd: usize = args.get(2).map(|a| a.parse().unwrap()).unwrap_or(3);
    let clr: f64 = args.get(3).map(|a| a.parse().unwrap()).unwrap_or(f64::INFINITY);
    let masses = [0.74, 0.71, 0.64];
    let dampers: Vec<Damper> = (0..nd).map(|j| Damper { host: j, mass: 0.1 * masses[j], clearance: clr }).collect();
    let sys = System::plastic(s, dampers, 0, 2.6);
    let t = std::time::Instant::now();
    let d = Dynamics::new(&sys, 2.0 * std::f64::consts::PI * f).unwrap();
    let r = steady_state(&d, State::at_rest(&d), &SteadyOptions { energy: true, ..Default::default() });
    println!("{:?}", t.elapsed());
    println!(
        "conv {} trans {} period {} amp/F {:?}",
        r.converged,
        r.transient_periods,
        r.period,
        r.amplitude.iter().map(|a| a / 2.6).collect::<Vec<_>>()
    );
    println!("bottom {:?} top {:?} lift {:?} flight {:?}", r.bottom_impacts, r.top_impacts, r.liftoffs, r.max_flight);
    println!("energy {:?} resid {:e}", r.energy, r.energy.unwrap().relative_residual());
    println!("stop {:?} evals {}", r.stop, shotdamp::sim::segment::EVALS.load(std::sync::atomic::Ordering::Relaxed));
}
