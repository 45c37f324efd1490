//! The contract's rows of the hostile retest's inputs (docs/reliability.md).

use super::{row, Edit, Row, F04, PLATE, PLATE_STI, RUN_04, RUN_PLATE};

const PLATE_MAS: &str = "examples/plate/data/plate.mas";
const PLATE_DOF: &str = "examples/plate/data/plate.dof";
const F09: &str = "experiments/fig09_third_mode.toml";

/// A text made once for the whole run (rows hold `&'static str`).
fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// The rows of the hostile retest's inputs: lists without bounds, finite-element files that
/// are not a structure, output paths.
pub(super) fn rows() -> Vec<Row> {
    use Edit::{Replace, Setup, Twice};
    let long_id = leak(format!("id = \"{}\"", "a".repeat(256)));
    let many_masses = leak(format!("masses = [{}]", vec!["1"; 200_000].join(", ")));
    let many_clearances = leak(format!("clearances_mm = [{}]", vec!["0.2"; 1000].join(", ")));
    let twice_clearances = leak("clearances_mm = [0.1, 0.15, 0.1]".to_string());
    vec![
        row("experiment", "an id of 256 characters", Replace(F04, "id = \"fig04b_no_damper\"", long_id), RUN_04, 2),
        row("experiment", "a plot of 200,000 masses", Replace(F04, "masses = [1, 2, 3]", many_masses), RUN_04, 2),
        row("experiment", "a plot naming a mass twice", Replace(F04, "masses = [1, 2, 3]", "masses = [1, 2, 1]"), RUN_04, 2),
        row(
            "experiment",
            "1,000 candidate clearances of an SDOF analysis",
            Replace(F09, "clearances_mm = [0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.42, 0.45, 0.48, 0.5, 0.52, 0.55, 0.6, 0.7, 0.8, 1.0]", many_clearances),
            &["run", F09, "--out", "out"],
            2,
        ),
        row(
            "experiment",
            "a clearance listed twice",
            Replace(F09, "clearances_mm = [0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.42, 0.45, 0.48, 0.5, 0.52, 0.55, 0.6, 0.7, 0.8, 1.0]", twice_clearances),
            &["run", F09, "--out", "out"],
            2,
        ),
        row("finite element (plate.toml)", "a .dof file naming a direction of a node twice", Replace(PLATE_DOF, "2.1\n2.2\n", "2.1\n2.1\n"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "the whole stiffness file twice", Twice(PLATE_STI), RUN_PLATE, 2),
        row(
            "finite element (plate.toml)",
            "an indefinite stiffness entry",
            Replace(PLATE_STI, "1 2  3.7252902984619e-08", "1 2  1e12"),
            RUN_PLATE,
            2,
        ),
        row(
            "finite element (plate.toml)",
            "an indefinite mass entry",
            Replace(PLATE_MAS, "1 2  0.0000000000000e+00", "1 2  1.0"),
            RUN_PLATE,
            2,
        ),
        row("finite element (plate.toml)", "cutoff_hz = 1e308", Replace(PLATE, "cutoff_hz = 2500.0", "cutoff_hz = 1e308"), RUN_PLATE, 2),
        row("output", "`--out .`", Edit::None, &["run", F04, "--out", "."], 2),
        row(
            "output",
            "`--out LINK/` (a symbolic link to a folder, with a slash)",
            Setup(|d| {
                std::fs::create_dir(d.join("elsewhere")).unwrap();
                std::os::unix::fs::symlink(d.join("elsewhere"), d.join("link")).unwrap();
            }),
            &["run", F04, "--out", "link/"],
            2,
        ),
    ]
}
