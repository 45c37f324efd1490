//! A setup validated again with values set (an explorer request, a study sample) takes the
//! structure an earlier validation built where `[structure]` is unchanged
//! (`experiment::loader::vary`), and is the same experiment as one validated from scratch:
//! on every structure source (a chain, a stiffness matrix with springs to ground, a chain
//! fitted to measured modes, a reduced finite-element model), for a damping changed alone, a
//! value elsewhere, the structure changed, and an invalid value (the same message).

use crate::common::repo;

use std::path::Path;

use shotdamp::experiment::fe::made;
use shotdamp::experiment::loader::vary;
use shotdamp::experiment::read_models;
use shotdamp::experiment::study::KeyPath;
use shotdamp::reference::files::Files;

/// The changes tried on every table; those whose key a table lacks are skipped.
fn changes() -> Vec<(&'static str, toml::Value)> {
    vec![
        ("structure.damping.modal_ratios", toml::Value::Float(0.02)),
        ("structure.damping.modal_ratios", toml::Value::Float(-0.1)),
        ("excitation.force_n", toml::Value::Float(1.3)),
        ("cases[*].dampers[*].clearance_mm", toml::Value::Float(0.5)),
        ("cases[*].dampers[*].mass_ratio", toml::Value::Float(0.05)),
        ("cases[*].dampers[*].mass_kg", toml::Value::Float(0.03)),
        ("analysis.freq_hz.stop", toml::Value::Float(60.0)),
        ("structure.masses_kg", toml::Value::Float(0.8)),
        ("structure.ground_stiffness_n_per_m", toml::Value::Float(100.0)),
    ]
}

/// Every change of [`changes`] to `base` (a table of `path`), validated from scratch and with
/// what validating `base` built: the same experiment (its every number, as `Debug` prints
/// them) or the same error. Returns how many changes applied.
fn same_either_way(path: &Path, base: &toml::Table, files: &Files) -> usize {
    let (_, kept) = vary(path, base.clone(), files, None).unwrap();
    let mut applied = 0;
    for (key, value) in changes() {
        let mut table = base.clone();
        if KeyPath::parse(key).unwrap().set(&mut table, &value).is_err() {
            continue;
        }
        applied += 1;
        let fresh = vary(path, table.clone(), files, None);
        let again = vary(path, table, files, Some(&kept));
        match (fresh, again) {
            (Ok((a, _)), Ok((b, _))) => {
                assert_eq!(format!("{a:?}"), format!("{b:?}"), "{} {key} = {value}", path.display())
            }
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{} {key} = {value}", path.display()),
            (a, b) => panic!("{} {key} = {value}: from scratch {:?}, varied {:?}", path.display(), a.err(), b.err()),
        }
    }
    applied
}

#[test]
fn a_varied_setup_is_the_setup_validated_afresh_on_every_structure_source() {
    let files = Files::new(&repo().join("reference"));
    // The paper's structure on its three models: a chain, a stiffness matrix with springs to
    // ground (coil), a chain fitted to measured modes.
    let path = repo().join("experiments/fig05_third_mode.toml");
    let tables = read_models(&path).unwrap();
    assert_eq!(tables.len(), 3);
    for (_, table) in &tables {
        assert!(same_either_way(&path, table, &files) >= 6);
    }
    // The plate CalculiX meshed, reduced at its containers.
    let path = repo().join("examples/plate/plate.toml");
    let tables = read_models(&path).unwrap();
    assert!(same_either_way(&path, &tables[0].1, &files) >= 4);
}

/// The kept structure is used: a finite-element model varied in its clearance, force or
/// damping is not looked up (no matrix file read for the key, no reduction), where the same
/// table validated from scratch finds its reduction again.
#[test]
fn a_varied_setup_reads_no_matrix_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("k.mtx"),
        "%%MatrixMarket matrix coordinate real symmetric\n3 3 5\n1 1 46100\n2 1 -21800\n2 2 41600\n3 2 -19800\n3 3 19800\n",
    )
    .unwrap();
    std::fs::write(
        d.join("m.mtx"),
        "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 0.74\n2 2 0.71\n3 3 0.64\n",
    )
    .unwrap();
    let text = "[experiment]\nid = \"fe\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure.finite_element]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nup = \"x\"\npoints = [{ row = 1 }, { row = 3 }]\nmodes = 1\n[structure.damping]\nmodal_ratios = [0.01]\n[excitation]\nmass = 1\nforce_n = 2.6\n[analysis]\nkind = \"sweep\"\nfreq_hz = { start = 44.0, stop = 46.0, step = 1.0 }\n[[cases]]\nid = \"one\"\nlabel = \"one\"\ndampers = [{ mass = 2, mass_kg = 0.071, clearance_mm = 0.2 }]\n";
    let path = d.join("reduced.toml");
    std::fs::write(&path, text).unwrap();
    let files = Files::new(&repo().join("reference"));
    let table = read_models(&path).unwrap().remove(0).1;
    let (base, kept) = vary(&path, table.clone(), &files, None).unwrap();
    assert_eq!(made::found_in(d), vec![0], "reduced once");
    for (key, value) in [
        ("cases[0].dampers[0].clearance_mm", 0.5),
        ("excitation.force_n", 1.0),
        ("structure.damping.modal_ratios", 0.03),
    ] {
        let mut t = table.clone();
        KeyPath::parse(key).unwrap().set(&mut t, &toml::Value::Float(value)).unwrap();
        let (varied, _) = vary(&path, t, &files, Some(&kept)).unwrap();
        assert_eq!(made::found_in(d), vec![0], "{key}: the kept structure, no lookup");
        if key.starts_with("structure.damping") {
            assert_ne!(varied.structure.damping, base.structure.damping, "the new damping computed");
        }
    }
    // The same table from scratch looks its reduction up (found, not made again).
    let _ = vary(&path, table.clone(), &files, None).unwrap();
    assert_eq!(made::found_in(d), vec![1]);
    // A structure changed is built again: the mode count changed, another reduction.
    let mut t = table;
    KeyPath::parse("structure.finite_element.modes").unwrap().set(&mut t, &toml::Value::Integer(0)).unwrap();
    let (other, _) = vary(&path, t, &files, Some(&kept)).unwrap();
    assert_eq!(other.structure.dof(), 2);
    assert_eq!(made::found_in(d), vec![1, 0]);
}
