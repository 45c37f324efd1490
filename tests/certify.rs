//! The `certify` steady-state method (docs/simulator.md, "Certified transients"): the
//! transient method's settled motion certified as a periodic orbit. For the paper's single
//! plastic bed it must give the orbit method's certificate (the same exact Jacobian); for a
//! column of grains, whose Jacobian comes from central differences, a plastic column must give
//! the single plastic mass's multipliers (a second method for the differences), and every
//! certified orbit of a column with restitution must reproduce the transient record it
//! certifies.

use crate::common;

use std::f64::consts::PI;

use shotdamp::model::{Clearance, Damper};
use shotdamp::sim::motion::bed::ImpactLaw;
use shotdamp::sim::motion::observe::Extrema;
use shotdamp::sim::{steady_state, Dynamics, Engine, State, Steady, SteadyMethod, SteadyOptions, System};

/// Fig. 5's containers on the stated chain: mu = 0.1 on the masses given, d = 0.35 mm.
fn fig5(hosts: &[usize]) -> System {
    let structure = crate::common::paper();
    let m = [0.74, 0.71, 0.64];
    let dampers = hosts.iter().map(|&h| Damper::new(h, 0.1 * m[h], Clearance::from_mm(0.35))).collect();
    System::plastic(structure, dampers, 0, 2.6)
}

fn run(sys: &System, f: f64, method: SteadyMethod) -> Steady {
    let d = Dynamics::new(sys, 2.0 * PI * f).expect("dynamics");
    steady_state(&d, State::at_rest(&d), &SteadyOptions { method, ..SteadyOptions::default() })
}

/// Half the peak-to-peak displacement of each mass over one orbit from the certificate's
/// section state.
fn orbit_amplitudes(sys: &System, f: f64, st: &Steady) -> Vec<f64> {
    let d = Dynamics::new(sys, 2.0 * PI * f).expect("dynamics");
    let mut s = st.section_state().expect("certified").clone();
    let mut ext = Extrema::new(sys.dof(), sys.dampers.len());
    let t_end = s.t + st.period as f64 * 2.0 * PI / d.omega;
    Engine::new(&d).advance(&mut s, t_end, &mut ext).expect("one orbit");
    ext.amplitudes()
}

#[test]
fn certifying_the_single_plastic_bed_gives_the_orbit_methods_certificate() {
    let sys = fig5(&[1]);
    for f in [44.0, 47.0, 48.0, 52.0, 54.0] {
        let orbit = run(&sys, f, SteadyMethod::Orbit);
        let transient = run(&sys, f, SteadyMethod::Transient);
        let certified = run(&sys, f, SteadyMethod::Certify);
        // The record is the transient method's, bit for bit.
        assert_eq!(certified.amplitude, transient.amplitude, "{f} Hz");
        assert_eq!(certified.method, SteadyMethod::Certify);
        let (a, b) = (orbit.certificate.as_ref().expect("orbit"), certified.certificate.as_ref().expect("certified"));
        assert!(b.stable && b.smooth && b.residual < 1e-11, "{f} Hz: {b:?}");
        assert!(
            (a.spectral_radius() - b.spectral_radius()).abs() < 1e-9,
            "{f} Hz: {} vs {}",
            a.spectral_radius(),
            b.spectral_radius()
        );
    }
}

#[test]
fn a_plastic_column_certified_by_differences_has_the_single_masss_multipliers() {
    // Five plastic grains per container move as the single plastic mass (tests/column.rs);
    // their orbit's Jacobian by central differences must have the exact Jacobian's leading
    // multiplier (the grains' extra coordinates collapse on impact: multipliers 0).
    for hosts in [vec![1], vec![0, 1, 2]] {
        let single = fig5(&hosts);
        let column = single.clone().with_grains(&vec![5; hosts.len()]);
        let mut certified = 0;
        for f in [44.0, 46.0, 48.0, 52.0, 54.0] {
            let exact = run(&single, f, SteadyMethod::Orbit);
            let differences = run(&column, f, SteadyMethod::Certify);
            let Some(c) = differences.certificate.as_ref() else { continue };
            certified += 1;
            let r = exact.certificate.as_ref().expect("the single mass's orbit").spectral_radius();
            println!("{hosts:?} {f} Hz: {r:.12} exact, {:.12} by differences", c.spectral_radius());
            assert!(c.stable && c.smooth && c.residual < 1e-11, "{hosts:?} {f} Hz: {c:?}");
            assert!((c.spectral_radius() - r).abs() < 1e-6, "{hosts:?} {f} Hz: {} vs {r}", c.spectral_radius());
        }
        assert!(certified >= 3, "{hosts:?}: {certified} of 5 points certified");
    }
}

#[test]
fn a_column_with_restitution_is_certified_where_its_motion_is_periodic() {
    // Three grains at e = 0.3 on m2 over Fig. 5's band: where the transient settles and the
    // map is smooth the orbit is certified, stable, and one orbit of it gives the transient
    // record's amplitudes (the record settled to 1e-7); where the central differences
    // straddle a change of the grains' collisions (a stack that lands in a different order)
    // the point keeps the transient record without a certificate.
    let law = ImpactLaw::with_restitution(0.3, 1e-3);
    let sys = fig5(&[1]).with_law(law).with_grains(&[3]);
    let (mut settled, mut certified) = (0, 0);
    for i in 0..13 {
        let f = 44.0 + i as f64;
        let transient = run(&sys, f, SteadyMethod::Transient);
        let st = run(&sys, f, SteadyMethod::Certify);
        assert_eq!(st.amplitude, transient.amplitude, "{f} Hz: the record is the transient's");
        settled += st.converged as usize;
        let Some(c) = st.certificate.as_ref() else { continue };
        certified += 1;
        assert!(c.stable && c.smooth && c.residual < 1e-11, "{f} Hz: {c:?}");
        let one = orbit_amplitudes(&sys, f, &st);
        let scale = st.amplitude.iter().copied().fold(0.0, f64::max);
        let apart = one.iter().zip(&st.amplitude).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        println!("{f} Hz: radius {:.6}, orbit vs record {:.1e}", c.spectral_radius(), apart / scale);
        assert!(apart <= 1e-6 * scale, "{f} Hz: {one:?} vs {:?}", st.amplitude);
    }
    println!("{certified} of {settled} settled points certified");
    assert!(certified * 2 >= settled, "{certified} of {settled} settled points certified");
}

#[test]
fn an_experiment_file_asks_for_certified_column_orbits_and_its_table_shows_them() {
    let dir = tempfile::tempdir().unwrap();
    let analysis =
        "kind = \"sweep\"\nfreq_hz = { start = 52.0, stop = 54.0, step = 1.0 }\nsteady = { method = \"certify\" }";
    let keys = r#", bed = "column", grains = 5, restitution = 0.0"#;
    let file = common::three_containers(dir.path(), "certified", analysis, "columns", [keys; 3]);
    let out =
        common::shotdamp().args(["run", file.to_str().unwrap(), "--out"]).arg(dir.path().join("o")).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(dir.path().join("o/certified/stated/data/compliance.csv")).unwrap();
    let rows = common::csv_rows(&csv);
    let col = |name: &str| rows[0].iter().position(|h| h == name).unwrap_or_else(|| panic!("{name} in {:?}", rows[0]));
    let (residual, radius, curve) = (col("orbit_residual"), col("max_multiplier"), col("curve"));
    let columns: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[curve] == "columns").collect();
    assert_eq!(columns.len(), 3);
    for r in columns {
        let (res, rad): (f64, f64) = (r[residual].parse().unwrap(), r[radius].parse().unwrap());
        assert!(res < 1e-11 && rad > 0.9 && rad < 1.0, "{r:?}");
    }
}
