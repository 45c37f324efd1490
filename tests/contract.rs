//! docs/reliability.md's table of bad inputs, row by row through the binary: each row's input
//! (one change to a copy of the repository's inputs), its exit code and its whole message.
//! The table in the document is generated here; the test fails when the document differs
//! from what the binary says, so the contract cannot drift. After a deliberate change of a
//! message, write the table anew with
//!
//!     SHOTDAMP_WRITE_CONTRACT=1 cargo test --release --locked --test all -- contract::
//!
//! and review the diff of docs/reliability.md.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::repo;

mod hostile;

/// What a row changes in the copy before the command runs (undone after it).
enum Edit {
    /// Nothing.
    None,
    /// `file`: the first `from` becomes `to`.
    Replace(&'static str, &'static str, &'static str),
    /// `file` gets `bytes` at its end.
    Append(&'static str, &'static [u8]),
    /// `file` is replaced by `bytes`.
    Write(&'static str, &'static [u8]),
    /// `file` is followed by a second copy of itself.
    Twice(&'static str),
    /// Anything else, in the copy's folder (what it creates is removed after the row).
    Setup(fn(&Path)),
}

/// One row: the area, the input as the table names it, the change, the command line and the
/// environment, and the exit code the contract promises.
struct Row {
    area: &'static str,
    input: &'static str,
    edit: Edit,
    args: &'static [&'static str],
    env: &'static [(&'static str, &'static str)],
    exit: i32,
}

const RUN_04: &[&str] = &["run", "experiments/fig04b_no_damper.toml", "--out", "out"];
const RUN_08: &[&str] = &["run", "experiments/fig08_number_of_dampers.toml", "--out", "out"];
const RUN_10: &[&str] = &["run", "experiments/fig10b_impulse.toml", "--out", "out"];
const STUDY: &[&str] = &["study", "fig05_report.toml", "--out", "s", "--dry-run"];
const F04: &str = "experiments/fig04b_no_damper.toml";
const F08: &str = "experiments/fig08_number_of_dampers.toml";
const STATED: &str = "experiments/shared/models/stated.toml";
const FITTED: &str = "experiments/shared/models/fitted.toml";
const SHARED: &str = "experiments/shared/paper_structure.toml";
const CURVE: &str = "reference/independent-solver/P_dinf_N3.csv";
const PAPER: &str = "reference/paper-text.toml";
const FIVE: &str = "designs/five_storey.toml";
const PLATE: &str = "examples/plate/plate.toml";
const PLATE_STI: &str = "examples/plate/data/plate.sti";
const RUN_PLATE: &[&str] = &["run", PLATE, "--out", "out"];

fn row(area: &'static str, input: &'static str, edit: Edit, args: &'static [&'static str], exit: i32) -> Row {
    Row { area, input, edit, args, env: &[], exit }
}

/// `fig05_report.toml` beside the inputs (its experiment path made relative to it), with
/// `from` replaced by `to`.
fn study_with(dir: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(repo().join("studies/fig05_report.toml")).unwrap();
    let text = text.replace("../experiments/", "experiments/");
    assert!(text.contains(from), "{from}");
    std::fs::write(dir.join("fig05_report.toml"), text.replacen(from, to, 1)).unwrap();
}

/// The reference curve with its lines edited.
fn curve_with(dir: &Path, edit: fn(&mut Vec<String>)) {
    let path = dir.join(CURVE);
    let mut lines: Vec<String> = std::fs::read_to_string(&path).unwrap().lines().map(String::from).collect();
    edit(&mut lines);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
}

/// Cell `col` of data line `line` (1-based, the header is line 1) set to `value`.
fn cell(lines: &mut [String], line: usize, col: usize, value: &str) {
    let mut cells: Vec<String> = lines[line - 1].split(',').map(String::from).collect();
    cells[col] = value.to_string();
    lines[line - 1] = cells.join(",");
}

/// A report of the linear experiment in `dir/a` (for `compare`).
fn report_a(dir: &Path) {
    let out = Command::new(assert_cmd::cargo::cargo_bin("shotdamp"))
        .current_dir(dir)
        .args(["run", F04, "--out", "a"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
}

fn rows() -> Vec<Row> {
    use Edit::*;
    let mut v = vec![
        row("experiment", "file does not exist", None, &["run", "experiments/none.toml", "--out", "out"], 2),
        row("experiment", "empty file", Write(F04, b""), RUN_04, 2),
        row("experiment", "not TOML (a line without \"=\")", Append(F04, b"this is not toml\n"), RUN_04, 2),
        row("experiment", "invalid UTF-8", Append(F04, b"# \xff\xfe\n"), RUN_04, 2),
        row(
            "experiment",
            "unknown key in [experiment]",
            Replace(F04, "[experiment]\n", "[experiment]\ncolour = \"red\"\n"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "a number where text is expected",
            Replace(F04, "id = \"fig04b_no_damper\"", "id = 4"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "a tiny number where text is expected",
            Replace(F04, "figure = \"Fig. 4(b)\"", "figure = 1e-320"),
            RUN_04,
            2,
        ),
        row("experiment", "id with a space", Replace(F04, "id = \"fig04b_no_damper\"", "id = \"fig 4b\""), RUN_04, 2),
        row(
            "experiment",
            "id with a tab and an escape character",
            Replace(F04, "id = \"fig04b_no_damper\"", "id = \"fig\\t4b\\u001B\""),
            RUN_04,
            2,
        ),
        row("experiment (model file stated.toml)", "mass 0 kg", Replace(STATED, "[0.74,", "[0.0,"), RUN_04, 2),
        row("experiment (model file stated.toml)", "mass nan", Replace(STATED, "[0.74,", "[nan,"), RUN_04, 2),
        row(
            "experiment (model file stated.toml)",
            "negative stiffness",
            Replace(STATED, "[24.3e3,", "[-24.3e3,"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "two stiffnesses for three masses",
            Replace(STATED, "[24.3e3, 21.8e3, 19.8e3]", "[24.3e3, 21.8e3]"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "masses and a mass matrix both",
            Replace(STATED, "masses_kg = [0.74, 0.71, 0.64]", "masses_kg = [0.74, 0.71, 0.64]\nmass_matrix_kg = [[0.74, 0.0, 0.0], [0.0, 0.71, 0.0], [0.0, 0.0, 0.64]]"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "mass matrix not symmetric",
            Replace(STATED, "masses_kg = [0.74, 0.71, 0.64]", "mass_matrix_kg = [[0.74, 0.1, 0.0], [0.0, 0.71, 0.0], [0.0, 0.0, 0.64]]"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "mass matrix not positive definite",
            Replace(STATED, "masses_kg = [0.74, 0.71, 0.64]", "mass_matrix_kg = [[0.74, 0.8, 0.0], [0.8, 0.71, 0.0], [0.0, 0.0, 0.64]]"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "mass matrix of two rows for three stiffnesses",
            Replace(STATED, "masses_kg = [0.74, 0.71, 0.64]", "mass_matrix_kg = [[0.74, 0.0], [0.0, 0.71]]"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "damping ratio -0.01",
            Replace(STATED, "[0.01, 0.01, 0.01]", "[-0.01, 0.01, 0.01]"),
            RUN_04,
            2,
        ),
        row(
            "experiment (model file stated.toml)",
            "damping ratio 1.5",
            Replace(STATED, "[0.01, 0.01, 0.01]", "[1.5, 0.01, 0.01]"),
            RUN_04,
            2,
        ),
        row("experiment", "force on mass 4 of 3", Replace(SHARED, "mass = 1", "mass = 4"), RUN_04, 2),
        row("experiment", "force 1e6 N (1.4e5 g on m1)", Replace(SHARED, "force_n = 2.6", "force_n = 1e6"), RUN_04, 2),
        row("finite element (plate.toml)", "its .dof file missing", Replace(PLATE, "data/plate.dof", "data/none.dof"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "a node not in the model", Replace(PLATE, "node = 224", "node = 99999"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "a point named twice", Replace(PLATE, "node = 290", "node = 224"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "a rotation as a point", Replace(PLATE, "node = 257, dof = 3", "node = 257, dof = 5"), RUN_PLATE, 2),
        row(
            "experiment",
            "a horizontal container without a top",
            Replace(F08, "dampers = [{ mass = 1, mass_ratio = 0.1, clearance_mm = \"inf\" }]", "dampers = [{ mass = 1, mass_ratio = 0.1, clearance_mm = \"inf\", direction = \"horizontal\" }]"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "an unknown container direction",
            Replace(F08, "dampers = [{ mass = 1, mass_ratio = 0.1, clearance_mm = \"inf\" }]", "dampers = [{ mass = 1, mass_ratio = 0.1, clearance_mm = \"inf\", direction = \"sideways\" }]"),
            RUN_08,
            2,
        ),
        row(
            "finite element (plate.toml)",
            "a container on a point that moves sideways",
            Replace(PLATE, "node = 224, dof = 3", "node = 224, dof = 1"),
            RUN_PLATE,
            2,
        ),
        row(
            "finite element (plate.toml)",
            "a horizontal container on a vertical point",
            Replace(PLATE, "{ mass = 1, mass_kg = 0.0471, clearance_mm = 2.0 }", "{ mass = 1, mass_kg = 0.0471, clearance_mm = 2.0, direction = \"horizontal\" }"),
            RUN_PLATE,
            2,
        ),
        row("finite element (plate.toml)", "a container on a modal coordinate", Replace(PLATE, "{ mass = 1, mass_kg", "{ mass = 7, mass_kg"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "the force on a modal coordinate", Replace(PLATE, "mass = 3\nforce_n", "mass = 9\nforce_n"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "an unknown format", Replace(PLATE, "format = \"calculix\"", "format = \"nastran\""), RUN_PLATE, 2),
        row("finite element (plate.toml)", "a truncated last line of the stiffness file", Append(PLATE_STI, b"7 7\n"), RUN_PLATE, 2),
        row("finite element (plate.toml)", "a NaN in the stiffness file", Append(PLATE_STI, b"7 7 nan\n"), RUN_PLATE, 2),
        row(
            "experiment",
            "force 1e400 (overflows to inf)",
            Replace(SHARED, "force_n = 2.6", "force_n = 1e400"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "extends a missing file",
            Replace(F04, "shared/paper_structure.toml", "shared/none.toml"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "extends itself (a cycle)",
            Replace(F04, "shared/paper_structure.toml", "fig04b_no_damper.toml"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "extends = 3",
            Replace(F04, "extends = \"shared/paper_structure.toml\"", "extends = 3"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "frequency grid stop below start",
            Replace(F08, "start = 8.0, stop = 60.0", "start = 60.0, stop = 8.0"),
            RUN_08,
            2,
        ),
        row("experiment", "frequency grid step 0", Replace(F08, "step = 0.1 }", "step = 0 }"), RUN_08, 2),
        row("experiment", "negative frequency", Replace(F08, "start = 8.0", "start = -8.0"), RUN_08, 2),
        row(
            "experiment",
            "damper on mass 5",
            Replace(F08, "[{ mass = 1, mass_ratio", "[{ mass = 5, mass_ratio"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "mass ratio -0.1",
            Replace(F08, "[{ mass = 1, mass_ratio = 0.1", "[{ mass = 1, mass_ratio = -0.1"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "mass ratio and mass in kg both",
            Replace(F08, "[{ mass = 1, mass_ratio = 0.1", "[{ mass = 1, mass_kg = 0.07, mass_ratio = 0.1"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "clearance \"wide\"",
            Replace(F08, "mass_ratio = 0.1, clearance_mm = \"inf\" }]", "mass_ratio = 0.1, clearance_mm = \"wide\" }]"),
            RUN_08,
            2,
        ),
        row("experiment", "two cases with one id", Replace(F08, "id = \"C\"", "id = \"B\""), RUN_08, 2),
        row(
            "experiment",
            "steady.method = \"magic\"",
            Replace(F08, "start = \"rest\"", "start = \"rest\"\nsteady = { method = \"magic\" }"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "steady.orbit_tol = 0.5",
            Replace(F08, "start = \"rest\"", "start = \"rest\"\nsteady = { orbit_tol = 0.5 }"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "steady.max_periods = 0",
            Replace(F08, "start = \"rest\"", "start = \"rest\"\nsteady = { max_periods = 0 }"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "steady.max_periods = 1e9",
            Replace(F08, "start = \"rest\"", "start = \"rest\"\nsteady = { max_periods = 1e9 }"),
            RUN_08,
            2,
        ),
        row(
            "model file fitted.toml",
            "a negative measured frequency",
            Replace(FITTED, "[81.9, 243.9,", "[81.9, -243.9,"),
            RUN_04,
            2,
        ),
        row(
            "model file fitted.toml",
            "two equal mode shapes",
            Replace(FITTED, "[1.0, 0.57, -0.91]", "[0.37, 0.77, 1.0]"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "a model file that does not exist in `models`",
            Replace(SHARED, "models/fitted.toml", "models/none.toml"),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "a check for an unknown model",
            Replace(
                F04,
                "models = [\"stated\"]\nreference = \"paper-text.toml\"\n",
                "models = [\"chain\"]\nreference = \"paper-text.toml\"\n",
            ),
            RUN_04,
            2,
        ),
        row(
            "experiment",
            "a check against a missing reference file",
            Replace(F08, "independent-solver/P_bare.csv", "independent-solver/none.csv"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "a check against an unknown quantity id",
            Replace(F04, "paper-text.toml#omega_1", "paper-text.toml#no_such_id"),
            RUN_04,
            2,
        ),
        row(
            "check",
            "`rel_tol = 1e300` (to \"disable\" a check)",
            Replace(F08, "rel_tol = 1e-6", "rel_tol = 1e300"),
            RUN_08,
            2,
        ),
        row(
            "experiment",
            "a check's clearance that the scan does not run",
            Replace("experiments/fig05_clearance_scan.toml", "clearance_mm = 0.1\n", "clearance_mm = 0.12\n"),
            &["run", "experiments/fig05_clearance_scan.toml", "--out", "out"],
            2,
        ),
        row(
            "experiment",
            "a continuation check without its direction",
            Replace("experiments/fig05_hysteresis.toml", "direction = \"up\"\n", ""),
            &["run", "experiments/fig05_hysteresis.toml", "--out", "out"],
            2,
        ),
        row(
            "experiment",
            "257 masses in a sweep (the simulator takes 256)",
            Setup(|d| {
                let list = |v: &str| [v; 257].join(", ");
                std::fs::write(d.join("m12.toml"), format!(
                "[experiment]\nid = \"m257\"\ntitle = \"t\"\nfigure = \"none\"\ncaption = \"c\"\nclaim = \"c\"\n[structure]\nmasses_kg = [{}]\nchain_stiffness_n_per_m = [{}]\n[structure.damping]\nmodal_ratios = [{}]\n[excitation]\nmass = 1\nforce_n = 2.0\n[analysis]\nkind = \"sweep\"\nfreq_hz = {{ start = 5.0, stop = 6.0, step = 0.5 }}\n[[cases]]\nid = \"a\"\nlabel = \"a\"\ndampers = [{{ mass = 257, mass_ratio = 0.1, clearance_mm = 1.0 }}]\n",
                list("1.0"), list("2e4"), list("0.02"))).unwrap();
            }),
            &["run", "m12.toml", "--out", "out"],
            2,
        ),
        row(
            "impulse",
            "initial_velocity_m_s = 1e200",
            Replace("experiments/fig10b_impulse.toml", "initial_velocity_m_s = 0.5", "initial_velocity_m_s = 1e200"),
            RUN_10,
            2,
        ),
        row(
            "impulse",
            "impulse_n_s = 1e160",
            Replace("experiments/fig10b_impulse.toml", "initial_velocity_m_s = 0.5", "impulse_n_s = 1e160"),
            RUN_10,
            2,
        ),
        row("reference curve", "a word in a cell", Setup(|d| curve_with(d, |l| cell(l, 11, 2, "abc"))), RUN_08, 2),
        row("reference curve", "nan in a cell", Setup(|d| curve_with(d, |l| cell(l, 21, 1, "nan"))), RUN_08, 2),
        row("reference curve", "an empty cell", Setup(|d| curve_with(d, |l| cell(l, 8, 1, ""))), RUN_08, 2),
        row(
            "reference curve",
            "columns c2, c3 deleted",
            Setup(|d| {
                curve_with(d, |l| {
                    for line in l.iter_mut() {
                        let cells: Vec<&str> = line.split(',').collect();
                        *line = [&cells[..2], &cells[4..]].concat().join(",");
                    }
                })
            }),
            RUN_08,
            2,
        ),
        row(
            "reference curve",
            "a duplicated row",
            Setup(|d| {
                curve_with(d, |l| {
                    let again = l[29].clone();
                    l.insert(30, again);
                })
            }),
            RUN_08,
            2,
        ),
        row("reference curve", "rows out of order", Setup(|d| curve_with(d, |l| l.swap(30, 31))), RUN_08, 2),
        row("reference curve", "converged = 2", Setup(|d| curve_with(d, |l| cell(l, 41, 4, "2"))), RUN_08, 2),
        row("reference curve", "period = 1.5", Setup(|d| curve_with(d, |l| cell(l, 41, 5, "1.5"))), RUN_08, 2),
        row("reference curve", "header only", Setup(|d| curve_with(d, |l| l.truncate(1))), RUN_08, 2),
        row("paper values", "value = nan", Replace(PAPER, "value = 81.9", "value = nan"), RUN_04, 2),
        row("paper values", "a duplicated id", Replace(PAPER, "id = \"omega_2\"", "id = \"omega_1\""), RUN_04, 2),
        row(
            "paper values",
            "value and values both",
            Replace(PAPER, "value = 81.9", "value = 81.9\nvalues = [1.0]"),
            RUN_04,
            2,
        ),
        row("paper values", "unknown key", Replace(PAPER, "value = 81.9", "value = 81.9\nweight = 2"), RUN_04, 2),
        row(
            "output",
            "--out names a folder of the user's files",
            Setup(|d| {
                std::fs::create_dir(d.join("mine")).unwrap();
                std::fs::write(d.join("mine/notes.txt"), "x").unwrap();
            }),
            &["run", F04, "--out", "mine"],
            2,
        ),
        row(
            "output",
            "--out names a file",
            Setup(|d| std::fs::write(d.join("notes.txt"), "x").unwrap()),
            &["run", F04, "--out", "notes.txt"],
            2,
        ),
        row(
            "output",
            "--out names a folder shotdamp wrote, with a user's file added",
            Setup(|d| {
                report_a(d);
                std::fs::write(d.join("a/mynotes.txt"), "precious").unwrap();
            }),
            &["run", F04, "--out", "a"],
            2,
        ),
        row(
            "output",
            "--out names an empty folder",
            Setup(|d| std::fs::create_dir(d.join("empty")).unwrap()),
            &["run", F04, "--out", "empty"],
            0,
        ),
        row("output", "`run FILE --out experiments/shared/x`", None, &["run", F04, "--out", "experiments/shared/x"], 2),
        row("output", "`design FILE --out designs/x`", None, &["design", FIVE, "--out", "designs/x"], 2),
        row(
            "output",
            "`study FILE --out experiments/z`",
            Setup(|d| study_with(d, "report = true", "report = true")),
            &["study", "fig05_report.toml", "--out", "experiments/z"],
            2,
        ),
        row("output", "`report --out reference/x`", None, &["report", "--out", "reference/x"], 2),
        row("output", "`compare a a --out a`", Setup(report_a), &["compare", "a", "a", "--out", "a"], 2),
        row("output", "`compare a a --out a/sub`", Setup(report_a), &["compare", "a", "a", "--out", "a/sub"], 2),
        row("command line", "unknown command", None, &["frobnicate"], 2),
        row("command line", "--jobs 0", None, &["run", F04, "--jobs", "0"], 2),
        row("command line", "--jobs 100000", None, &["run", F04, "--jobs", "100000"], 2),
        row(
            "command line",
            "compare a folder that is not a report",
            Setup(|d| std::fs::create_dir(d.join("a")).unwrap()),
            &["compare", "a", "a"],
            2,
        ),
        row(
            "design",
            "a band of 100,000 frequencies",
            Replace(FIVE, "start = 5.0, stop = 8.0, step = 0.1", "start = 5.0, stop = 8.0, points = 100000"),
            &["design", FIVE, "--dry-run"],
            2,
        ),
        row(
            "design",
            "a repeated Pareto ratio",
            Replace(FIVE, "max_beds = 2", "max_beds = 2\npareto_mass_ratios = [0.02, 0.05, 0.02]"),
            &["design", FIVE, "--dry-run"],
            2,
        ),
        row(
            "design",
            "max_iters = 1e9",
            Replace(FIVE, "max_beds = 2", "max_beds = 2\nmax_iters = 1e9"),
            &["design", FIVE, "--dry-run"],
            2,
        ),
        row(
            "design",
            "a force scenario of 1e9 N on a 1 kg floor",
            Replace(FIVE, "max_beds = 2", "max_beds = 2\nscenarios = { force_n = [2.0, 1e9] }"),
            &["design", FIVE, "--dry-run"],
            2,
        ),
        row(
            "design",
            "the SDOF technique with horizontal containers",
            Replace(FIVE, "max_beds = 2", "max_beds = 2\ndirection = \"horizontal\"\nsdof = { mode = 1, clearances_mm = [1.0, 2.0] }"),
            &["design", FIVE, "--dry-run"],
            2,
        ),
        row(
            "design",
            "eleven force scenarios",
            Replace(
                FIVE,
                "max_beds = 2",
                "max_beds = 2\nscenarios = { force_n = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0] }",
            ),
            &["design", FIVE, "--dry-run"],
            2,
        ),
        row(
            "study",
            "unknown key path",
            Setup(|d| study_with(d, "structure.damping.modal_ratios", "structure.dampin.modal_ratios")),
            STUDY,
            2,
        ),
        row(
            "study",
            "a case id that does not exist",
            Setup(|d| study_with(d, "cases[*].dampers[*]", "cases[two].dampers[*]")),
            STUDY,
            2,
        ),
        row(
            "study",
            "damping value -0.5 (not allowed by the experiment)",
            Setup(|d| study_with(d, "[0.003, 0.005, 0.01]", "[0.003, 0.005, -0.5]")),
            STUDY,
            2,
        ),
        row("study", "no values and no range", Setup(|d| study_with(d, "values = [0.2, 0.3, 0.4]", "")), STUDY, 2),
        row(
            "study",
            "a model the experiment does not run on",
            Setup(|d| study_with(d, "report = true", "report = true\nmodels = [\"measured\"]")),
            STUDY,
            2,
        ),
        row(
            "study",
            "sobol without samples",
            Setup(|d| study_with(d, "report = true", "report = true\ndesign = \"sobol\"")),
            STUDY,
            2,
        ),
        row(
            "study",
            "map naming an unknown key",
            Setup(|d| study_with(d, "map = [\"clearance_mm\", \"damping\"]", "map = [\"clearance\", \"damping\"]")),
            STUDY,
            2,
        ),
        row(
            "study",
            "experiment file missing",
            Setup(|d| study_with(d, "experiments/fig05_third_mode.toml", "none.toml")),
            STUDY,
            2,
        ),
        row(
            "study",
            "--shard 7/7",
            Setup(|d| study_with(d, "report = true", "report = true")),
            &["study", "fig05_report.toml", "--shard", "7/7", "--out", "s"],
            2,
        ),
        row(
            "study",
            "--out a folder of other files",
            Setup(|d| {
                study_with(d, "report = true", "report = true");
                std::fs::create_dir(d.join("other")).unwrap();
                std::fs::write(d.join("other/notes.txt"), "x").unwrap();
            }),
            &["study", "fig05_report.toml", "--out", "other"],
            2,
        ),
        row(
            "study",
            "merge of a folder that is not a study",
            Setup(|d| std::fs::create_dir(d.join("DIR")).unwrap()),
            &["study", "merge", "DIR"],
            2,
        ),
    ];
    v.push(Row {
        area: "study",
        input: "JOB_COMPLETION_INDEX set, no --shards",
        edit: Setup(|d| study_with(d, "report = true", "report = true")),
        args: &["study", "fig05_report.toml", "--out", "s"],
        env: &[("JOB_COMPLETION_INDEX", "0")],
        exit: 2,
    });
    v.push(Row {
        area: "study",
        input: "a stepped Slurm array (`--array=0-6:2`) into a new folder, no `--shards`",
        edit: Setup(|d| study_with(d, "report = true", "report = true")),
        args: &["study", "fig05_report.toml", "--out", "s"],
        env: &[
            ("SLURM_ARRAY_TASK_ID", "2"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "6"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ],
        exit: 2,
    });
    v.extend(hostile::rows());
    v
}

/// The names in `dir` (top level).
fn names(dir: &Path) -> Vec<std::ffi::OsString> {
    let mut v: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    v.sort();
    v
}

/// Runs a row in `dir` (a copy of the inputs) and undoes its change: exit code and message
/// (stderr on one line, `|` escaped for the table; "(runs; ...)" for a run that succeeds).
fn run(dir: &Path, r: &Row) -> (i32, String) {
    let before = names(dir);
    let mut saved: Option<(std::path::PathBuf, Vec<u8>)> = None;
    let mut keep = |file: &str| {
        let path = dir.join(file);
        saved = Some((path.clone(), std::fs::read(&path).unwrap()));
        path
    };
    match &r.edit {
        Edit::None => {}
        Edit::Replace(file, from, to) => {
            let path = keep(file);
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(text.contains(from), "{}: {file} has no {from:?}", r.input);
            std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        }
        Edit::Append(file, bytes) => {
            let path = keep(file);
            let mut all = std::fs::read(&path).unwrap();
            all.extend_from_slice(bytes);
            std::fs::write(&path, all).unwrap();
        }
        Edit::Write(file, bytes) => {
            let path = keep(file);
            std::fs::write(&path, bytes).unwrap();
        }
        Edit::Twice(file) => {
            let path = keep(file);
            let once = std::fs::read(&path).unwrap();
            std::fs::write(&path, [once.as_slice(), once.as_slice()].concat()).unwrap();
        }
        Edit::Setup(f) => {
            keep(CURVE);
            f(dir);
        }
    }
    let mut cmd = Command::new(assert_cmd::cargo::cargo_bin("shotdamp"));
    cmd.current_dir(dir).args(r.args).env_remove("SLURM_ARRAY_TASK_ID").env_remove("JOB_COMPLETION_INDEX");
    for (k, v) in r.env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    if let Some((path, bytes)) = saved {
        std::fs::write(path, bytes).unwrap();
    }
    for name in names(dir) {
        if !before.contains(&name) {
            let p = dir.join(&name);
            if p.is_dir() {
                std::fs::remove_dir_all(&p).unwrap();
            } else {
                std::fs::remove_file(&p).unwrap();
            }
        }
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    let text: Vec<&str> = stderr.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    let message = if out.status.success() { "(runs)".to_string() } else { text.join(" ") };
    // The one message that depends on the machine: its number of cores.
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let most = shotdamp::runner::max_jobs();
    let message = message
        .replace(&format!("give 1 to {most} worker threads"), "give 1 to MAX worker threads")
        .replace(&format!("here {cores} cores"), "here CORES cores");
    (out.status.code().unwrap_or(-1), message.replace('|', "\\|"))
}

const BEGIN: &str = "<!-- the rows below are written by tests/contract.rs -->";
const END: &str = "<!-- end of the rows written by tests/contract.rs -->";

#[test]
fn every_row_of_the_contract_is_what_the_binary_does() {
    let dir = tempfile::tempdir().unwrap();
    for sub in ["experiments", "reference", "studies", "designs", "examples"] {
        common::copy_tree(&repo().join(sub), &dir.path().join(sub));
    }
    let mut table = String::from("| area | input | exit | message |\n|---|---|---|---|\n");
    let mut wrong = Vec::new();
    for r in rows() {
        let (exit, message) = run(dir.path(), &r);
        if exit != r.exit {
            wrong.push(format!("{} / {}: exit {exit}, the contract says {}: {message}", r.area, r.input, r.exit));
        }
        table.push_str(&format!("| {} | {} | {exit} | {message} |\n", r.area, r.input));
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    let doc_path = repo().join("docs/reliability.md");
    let doc = std::fs::read_to_string(&doc_path).unwrap();
    let (Some(b), Some(e)) = (doc.find(BEGIN), doc.find(END)) else {
        panic!("docs/reliability.md has no markers {BEGIN} ... {END}");
    };
    let current = &doc[b + BEGIN.len() + 1..e];
    if current != table {
        if std::env::var_os("SHOTDAMP_WRITE_CONTRACT").is_some() {
            let new = format!("{}{BEGIN}\n{table}{}", &doc[..b], &doc[e..]);
            std::fs::write(&doc_path, new).unwrap();
            return;
        }
        let first = current.lines().zip(table.lines()).find(|(a, b)| a != b);
        panic!(
            "docs/reliability.md differs from what the binary does (first difference: {first:?}; rows {} vs {}). If the change is meant, run SHOTDAMP_WRITE_CONTRACT=1 cargo test --release --locked --test all -- contract:: and review the diff",
            current.lines().count(),
            table.lines().count()
        );
    }
}
