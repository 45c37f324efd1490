use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::bed::ImpactLaw;
use shotdamp::sim::soft::{amplitude, SoftOptions};
use shotdamp::sim::{steady_state, Dynamics, State, SteadyOptions, System};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let f: f64 = args[1].parse().unwrap();
    let grains: usize = args[2].parse().unwrap();
    let e: f64 = args[3].parse().unwrap();
    let m = [0.74, 0.71, 0.64];
    let structure = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let dampers: Vec<Damper> = [2].iter().map(|&h| Damper { host: h, mass: 0.1 * m[h], clearance: 0.35e-3 }).collect();
    let single = System::plastic(structure, dampers, 0, 2.6);
    let law = ImpactLaw { restitution: e, stick_speed: 1e-3 };
    let col = single.clone().with_law(law).with_grains(&[grains]);
    let w = 2.0 * std::f64::consts::PI * f;
    let d = Dynamics::new(&col, w).unwrap();
    let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
    println!(
        "ED  amp {:?} conv {} {:?} lifts {:?}",
        st.amplitude,
        st.converged,
        st.failure.map(|x| x.to_string()),
        st.liftoffs
    );
    for k in [1e6, 1e7, 1e8] {
        let t = std::time::Instant::now();
        let (a, steps) = amplitude(&col, w, &SoftOptions { stiffness: k, steps_per_contact: 40 }, 600, 100);
        let rel: Vec<f64> = a.iter().zip(&st.amplitude).map(|(x, y)| (x - y) / y).collect();
        println!("k {k:.0e} amp {a:?} rel {rel:.3?} steps {steps} {:.2}s", t.elapsed().as_secs_f64());
    }
}
