use shotdamp::model::{Damper, Damping, Structure};
use shotdamp::sim::{Dynamics, Engine, Event, Observer, State, System};
struct Log(Vec<(Event, Vec<shotdamp::sim::Bed>)>);
impl Observer for Log {
    fn event(&mut self, ev: &Event, a: &State) {
        self.0.push((*ev, a.beds.clone()));
    }
}
fn main() {
    let s = Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], Damping::ModalRatios(vec![0.01; 3]));
    let sys = System::plastic(s, vec![Damper { host: 0, mass: 0.074, clearance: f64::INFINITY }], 0, 2.6);
    let w = 2.0 * std::f64::consts::PI * 34.0;
    let d = Dynamics::new(&sys, w).unwrap();
    let mut st = State::at_rest(&d);
    let per = 2.0 * std::f64::consts::PI / w;
    let mut k = 1;
    loop {
        let mut log = Log(vec![]);
        let before = st.clone();
        let r = Engine::new(&d).advance(&mut st, k as f64 * per, &mut log);
        if r.is_err() {
            println!("{:?} from state {:?}", r, before);
            for (e, b) in log.0.iter().take(12) {
                println!("{:?} {:?}", e, b);
            }
            break;
        }
        k += 1;
    }
}
