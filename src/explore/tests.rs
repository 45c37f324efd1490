use super::keys::generalise;
use super::*;

fn req(start: f64, stop: f64, step: f64) -> Request {
    Request { model: 0, set: Vec::new(), band: Band { start, stop, step }, start: "rest".into(), seq: 0 }
}

#[test]
fn a_selector_is_read_as_any_element() {
    assert_eq!(generalise("cases[single].dampers[0].clearance_mm"), "cases[*].dampers[*].clearance_mm");
    assert_eq!(generalise("structure.damping.modal_ratios[2]"), "structure.damping.modal_ratios[*]");
    assert!(allowed("cases[triple].dampers[2].clearance_mm", &json!(0.4)).is_ok());
    assert!(allowed("structure.damping.modal_ratios[1]", &json!(0.02)).is_ok());
    assert!(allowed("cases[*].dampers[*].bed", &json!("restitution")).is_ok());
    assert!(allowed("cases[*].dampers[*].bed", &json!("column")).is_err());
    assert!(allowed("structure.finite_element.mass", &json!("/etc/passwd")).is_err());
    assert!(allowed("cases[*].dampers[*].clearance_mm", &json!("inf")).is_err());
    assert!(allowed("cases[*].dampers[*].clearance_mm", &json!(null)).is_err());
}

#[test]
fn a_band_has_at_most_max_points() {
    assert_eq!(band(&req(44.0, 56.0, 0.1)).unwrap().len(), 121);
    assert_eq!(band(&req(1.0, 21.0, 0.01)).unwrap().len(), MAX_POINTS);
    assert!(band(&req(1.0, 21.01, 0.01)).is_err());
    assert!(band(&req(50.0, 44.0, 0.1)).is_err());
    assert!(band(&req(44.0, 56.0, 0.0)).is_err());
    assert!(band(&req(f64::NAN, 56.0, 0.1)).is_err());
}

/// On a reduced finite-element model the page has a chart per point (the plate example's
/// four, not its 20 coordinates), and each sweep's curve has the points' compliance.
#[test]
fn a_reduced_model_is_drawn_at_its_points() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let session = Session::open(&root.join("examples/plate/plate.toml"), &root.join("reference")).unwrap();
    assert_eq!(session.setup()["masses"], 4);
    let request = Request { start: "continuation".into(), ..req(34.0, 34.5, 0.5) };
    let answer = session.run(&request, &|| {}).unwrap();
    assert_eq!(answer["masses"], 4);
    let sweep = answer["curves"].as_array().unwrap().iter().find(|c| c["kind"] == "sweep").unwrap();
    let compliance = sweep["compliance"].as_array().unwrap();
    assert!(compliance.len() >= 4);
    for point in &compliance[..4] {
        assert!(point.as_array().unwrap().iter().all(|c| c.as_f64().is_some_and(|c| c > 0.0)), "{point}");
    }
}
