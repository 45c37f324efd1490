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

/// A configuration's coordinates are a change of basis (`P B = I`, so `T` from a
/// configuration to itself is the identity), and a transfer carries a state as its
/// physical form does (`B' T q = B q`), on a chain with a resting bed's mass.
#[test]
fn transfers_are_changes_of_basis() {
    use crate::model::{Clearance, Damper, Damping, Structure};
    use crate::sim::motion::modal::basis;
    let n = 12;
    let s = Structure::chain(&vec![0.2; n], &vec![8e4; n], Damping::Rayleigh { alpha: 3.0, beta: 2e-5 });
    let dampers = (n - 2..n).map(|h| Damper::new(h, 0.05, Clearance::from_m(5e-4))).collect();
    let d = Dynamics::new(&System::plastic(s, dampers, 0, 2.0), 100.0).unwrap();
    let same = d.transfer(1, 1).unwrap();
    let identity = DMatrix::<f64>::identity(same.nrows(), same.ncols());
    assert!((same - &identity).amax() < 1e-11, "{:e}", (same - &identity).amax());
    let q = DMatrix::from_fn(same.ncols(), 3, |r, c| 1.0 / (1.0 + r as f64 + 2.0 * c as f64));
    for (from, to) in [(0, 3), (3, 1), (2, 0)] {
        let t = d.transfer(from, to).unwrap();
        let want = basis(d.configs[from].modes.coordinates()) * &q;
        let got = basis(d.configs[to].modes.coordinates()) * (t * &q);
        assert!((&got - &want).amax() <= 1e-11 * want.amax(), "{from} -> {to}: {:e}", (&got - &want).amax());
    }
    // Not kept up to LARGE_ABOVE degrees of freedom.
    let small = Structure::chain(&[0.2; 3], &[8e4; 3], Damping::ModalRatios(vec![0.02; 3]));
    let d = Dynamics::new(&System::plastic(small, vec![Damper::new(2, 0.02, Clearance::from_m(5e-4))], 0, 2.0), 100.0);
    assert!(d.unwrap().transfer(0, 1).is_none());
}
