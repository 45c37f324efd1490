use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::bed::ImpactLaw;
use shotdamp::sim::{steady_state, Dynamics, State, SteadyOptions, System};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let f: f64 = args[1].parse().unwrap();
    let grains: usize = args[2].parse().unwrap();
    let e: f64 = args[3].parse().unwrap();
    let m = [0.74, 0.71, 0.64];
    let structure = Structure::chain(&m, &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let dampers: Vec<Damper> =
        [0, 1, 2].iter().map(|&h| Damper { host: h, mass: 0.1 * m[h], clearance: 0.35e-3 }).collect();
    let single = System::plastic(structure, dampers, 0, 2.6);
    let law = ImpactLaw { restitution: e, stick_speed: 1e-3 };
    for sys in [single.clone(), single.clone().with_law(law), single.with_law(law).with_grains(&[grains; 3])] {
        let d = Dynamics::new(&sys, 2.0 * std::f64::consts::PI * f).unwrap();
        let st = steady_state(&d, State::at_rest(&d), &SteadyOptions::default());
        println!(
            "amp {:?} conv {} per {} bottom {:?} top {:?} lift {:?}",
            st.amplitude, st.converged, st.period, st.bottom_impacts, st.top_impacts, st.liftoffs
        );
    }
}
