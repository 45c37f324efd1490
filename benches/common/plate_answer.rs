// The plate design's stored answer (examples/plate/modes.toml: three containers on the
// design's five points) on a reduction of the plate CalculiX meshed, given as the line that
// replaces the file's `modes = 20` (`modes = 41`, `cutoff_hz = 8000.0`), and its system: one
// definition for benches/fe.rs, examples/scaling.rs and examples/irregular_cost.rs, each of
// which `include!`s this file.

/// The answer's experiment on the reduction `reduction`.
fn plate_answer(reduction: &str) -> shotdamp::experiment::Experiment {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("examples/plate/modes.toml")).expect("examples/plate/modes.toml");
    let data = root.join("examples/plate/data");
    let text = text.replace("\"data/", &format!("\"{}/", data.display()));
    let file: String = text
        .lines()
        .map(|l| if l.starts_with("modes = ") { reduction.to_string() } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("answer.toml");
    std::fs::write(&path, file).expect("written");
    shotdamp::experiment::loader::load(&path, &root.join("reference")).expect("the answer loads").remove(0)
}

/// The system of the answer's case on an experiment [`plate_answer`] loaded.
fn answer_system(exp: &shotdamp::experiment::Experiment) -> shotdamp::sim::System {
    let case = &exp.cases[0];
    shotdamp::sim::System::plastic(exp.structure.clone(), case.dampers(), exp.excitation.mass, exp.excitation.force)
}
