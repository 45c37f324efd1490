use super::*;

/// The response from the decomposition is the factorisation's, for a point force and a
/// complex load, in every configuration of a 12-mass chain with non-proportional damping
/// (Rayleigh plus a dashpot) and three beds, at frequencies below, between and above its
/// modes, with the frequency derivatives.
#[test]
fn the_modal_response_is_the_factorised_one() {
    use crate::model::{Clearance, Damper, Damping, Structure};
    let n = 12;
    let masses: Vec<f64> = (0..n).map(|i| 0.2 + 0.03 * i as f64).collect();
    let mut s = Structure::chain(&masses, &vec![8e4; n], Damping::Rayleigh { alpha: 3.0, beta: 2e-5 });
    s.damping[(4, 4)] += 7.0;
    let dampers = (n - 3..n).map(|h| Damper::new(h, 0.05, Clearance::from_m(5e-4))).collect();
    let d = Dynamics::unforced(&System::plastic(s, dampers, 0, 2.0)).unwrap();
    let load: Vec<Complex64> = (0..n).map(|i| Complex64::new((i as f64).sin(), 0.3 * (i as f64).cos())).collect();
    let d_load: Vec<Complex64> = load.iter().map(|z| z * 1e-3).collect();
    for cfg in &d.configs {
        for omega in [20.0, 333.0, 1500.0, 9000.0] {
            for drive in [Drive::Point(2, 2.6), Drive::Load(&load, &d_load)] {
                let mut by_lu = vec![Forced::default(); n];
                forced_into(&d.k, &d.c, &cfg.modes.mass, omega, drive, &mut by_lu).unwrap();
                let mut out = vec![Forced::default(); n];
                super::super::forced::forced_modal((&d.k, &d.c), &modal_parts(&cfg.modes), omega, drive, &mut out)
                    .unwrap();
                let sx = by_lu.iter().map(|f| f.amp).fold(0.0, f64::max);
                let sdx = by_lu.iter().map(|f| f.dp.hypot(f.dq)).fold(0.0, f64::max);
                for i in 0..n {
                    let Forced { p, q, dp, dq, .. } = by_lu[i];
                    assert!((out[i].p - p).abs().max((out[i].q - q).abs()) <= 1e-13 * sx, "omega {omega}: {i}");
                    assert!((out[i].dp - dp).abs().max((out[i].dq - dq).abs()) <= 1e-13 * sdx, "omega {omega}: d{i}");
                }
            }
        }
    }
}
