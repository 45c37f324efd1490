//! `[structure.finite_element]`: a finite-element program's mass and stiffness matrices
//! (CalculiX, Matrix Market, Abaqus), read, checked and reduced by Craig-Bampton at the
//! points the experiment file names (docs/fe-models.md). Files are named relative to the
//! experiment file.

pub mod calculix;
pub mod made;
pub mod matrix_market;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::DMatrix;

use super::file::raw::RawFiniteElement;
use crate::error::{Error, Result};
use crate::model::fe::{DofLabel, FeStructure, FullModel, Point};
use crate::model::reduction::{craig_bampton_sparse, Keep, Matrix, Reduced, ReductionError};
use crate::model::sparse::SymSparse;
use crate::model::Direction;

/// The formats read.
pub const FORMATS: [&str; 3] = ["calculix", "matrix-market", "abaqus"];

/// The highest cutoff frequency, Hz (far above any structure's modes: every mode is kept
/// below it; its square in rad/s stays a finite number).
pub const MAX_CUTOFF_HZ: f64 = 1e12;

/// Interior factors costlier than this are announced before they are computed (operations:
/// a few seconds).
const ANNOUNCE_FLOPS: f64 = 5e9;

/// A finite-element structure: the reduced matrices and what they came from.
#[derive(Clone)]
pub struct FromFiles {
    /// How its coordinates follow moving supports.
    pub supports: crate::model::base::Supports,
    /// The reduced mass matrix, kg (points first, then modal coordinates).
    pub mass: DMatrix<f64>,
    /// The reduced stiffness matrix, N/m.
    pub stiffness: DMatrix<f64>,
    /// The full model, its points and the reduction.
    pub fe: FeStructure,
}

/// The line on which each position of a matrix file was given: finite-element programs
/// write each entry once, so a position given twice (a file written twice, two files joined)
/// is refused instead of summed.
#[derive(Default)]
pub struct Positions(std::collections::HashMap<(usize, usize), usize>);

impl Positions {
    /// Records `(row, col)` (0-based) given on `line`; the line it was given on before, if it
    /// was.
    pub fn repeated(&mut self, row: usize, col: usize, line: usize) -> Option<usize> {
        match self.0.entry((row, col)) {
            std::collections::hash_map::Entry::Occupied(o) => Some(*o.get()),
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(line);
                None
            }
        }
    }

    /// The message for a repeated position.
    pub fn message(row: usize, col: usize, before: usize) -> String {
        format!(
            "entry ({}, {}) is given again (first on line {before}): each entry once (is the file written twice, or two files joined?)",
            row + 1,
            col + 1
        )
    }
}

/// A file's first line without a byte-order mark (an editor's, on a Windows machine).
pub fn without_bom(line: String, number: usize) -> String {
    match line.strip_prefix('\u{feff}') {
        Some(rest) if number == 1 => rest.to_string(),
        _ => line,
    }
}

/// Entries of one matrix as read, and whether they hold one triangle.
struct Read {
    entries: Vec<(usize, usize, f64)>,
    one_triangle: bool,
}

/// Whether entries lie on one side of the diagonal only.
fn one_sided(e: &[(usize, usize, f64)]) -> bool {
    !(e.iter().any(|t| t.0 < t.1) && e.iter().any(|t| t.0 > t.1))
}

/// Reads the files of `raw` next to `path`: the labels (if any), stiffness, mass and size.
fn read(path: &Path, raw: &RawFiniteElement) -> Result<(Option<Vec<DofLabel>>, Read, Read, usize)> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let at = |name: &str| -> PathBuf { dir.join(name) };
    // A file that cannot be opened is named by its key, as given, and where it was looked for.
    for (key, name) in [("stiffness", Some(&raw.stiffness)), ("mass", Some(&raw.mass)), ("dofs", raw.dofs.as_ref())] {
        let Some(name) = name else { continue };
        // Not opened before it is known to be a regular file: opening a named pipe waits for
        // a writer for ever.
        if let Err(e) = crate::error::regular_file(&at(name))
            .map_err(|e| match e {
                Error::Io { error, .. } => error,
                other => std::io::Error::other(other.to_string()),
            })
            .and_then(|()| std::fs::File::open(at(name)))
        {
            return Err(Error::invalid(
                path,
                format!("structure.finite_element.{key}"),
                format!("\"{name}\""),
                format!(
                    "cannot be read ({e}; looked for {}): files are named relative to the experiment file",
                    at(name).display()
                ),
            ));
        }
    }
    let (k_path, m_path) = (at(&raw.stiffness), at(&raw.mass));
    match raw.format.as_str() {
        "calculix" => {
            let Some(dofs) = &raw.dofs else {
                return Err(Error::invalid(
                    path,
                    "structure.finite_element.dofs",
                    "(missing)",
                    "CalculiX's matrices need their .dof file (job.dof, written beside job.sti and job.mas)",
                ));
            };
            let labels = calculix::read_dofs(&at(dofs))?;
            let n = labels.len();
            let k = calculix::read_matrix(&k_path, n)?;
            let m = calculix::read_matrix(&m_path, n)?;
            let (ko, mo) = (one_sided(&k), one_sided(&m));
            Ok((Some(labels), Read { entries: k, one_triangle: ko }, Read { entries: m, one_triangle: mo }, n))
        }
        "matrix-market" => {
            let (k, m) = (matrix_market::read(&k_path)?, matrix_market::read(&m_path)?);
            for (t, p) in [(&k, &k_path), (&m, &m_path)] {
                if t.rows != t.cols {
                    return Err(Error::Parse {
                        file: p.display().to_string(),
                        message: format!("the matrix is {} x {}: a mass or stiffness matrix is square", t.rows, t.cols),
                    });
                }
            }
            if k.rows != m.rows {
                return Err(Error::Parse {
                    file: m_path.display().to_string(),
                    message: format!(
                        "the mass matrix is {0} x {0} but the stiffness matrix ({1}) is {2} x {2}",
                        m.rows,
                        k_path.display(),
                        k.rows
                    ),
                });
            }
            let n = k.rows;
            let labels = match &raw.dofs {
                Some(d) => {
                    let l = calculix::read_dofs(&at(d))?;
                    if l.len() != n {
                        return Err(Error::Parse {
                            file: at(d).display().to_string(),
                            message: format!("the file names {} degrees of freedom, the matrices have {n}", l.len()),
                        });
                    }
                    Some(l)
                }
                None => None,
            };
            // A `general` file holds the whole matrix: one holding one triangle is refused (it
            // would be read as half a matrix), not mirrored on a guess.
            for (t, p) in [(&k, &k_path), (&m, &m_path)] {
                if !t.symmetric && one_sided(&t.entries) && t.entries.iter().any(|e| e.0 != e.1) {
                    return Err(Error::Parse {
                        file: p.display().to_string(),
                        message: "the banner says general (the whole matrix) but the entries hold one triangle: give the banner symmetric if the file stores one triangle of a symmetric matrix".into(),
                    });
                }
            }
            let (ks, ms) = (k.symmetric, m.symmetric);
            Ok((
                labels,
                Read { entries: k.entries, one_triangle: ks },
                Read { entries: m.entries, one_triangle: ms },
                n,
            ))
        }
        "abaqus" => {
            let (labels, k) = calculix::read_abaqus(&k_path, Vec::new())?;
            let (labels, m) = calculix::read_abaqus(&m_path, labels)?;
            let n = labels.len();
            let (ko, mo) = (one_sided(&k), one_sided(&m));
            Ok((Some(labels), Read { entries: k, one_triangle: ko }, Read { entries: m, one_triangle: mo }, n))
        }
        other => Err(Error::invalid(
            path,
            "structure.finite_element.format",
            format!("\"{other}\""),
            format!("one of {}", FORMATS.map(|f| format!("\"{f}\"")).join(", ")),
        )),
    }
}

/// How a row is named in messages.
fn row_name(labels: &Option<Vec<DofLabel>>, r: usize) -> String {
    match labels {
        Some(l) => format!("row {} ({})", r + 1, l[r]),
        None => format!("row {}", r + 1),
    }
}

/// A symmetric matrix of the entries, in SI units, with a positive diagonal.
fn matrix(file: &Path, what: &str, r: Read, n: usize, scale: f64, labels: &Option<Vec<DofLabel>>) -> Result<SymSparse> {
    let bad = |message: String| Error::Parse { file: file.display().to_string(), message };
    // Fewer entries than rows leave a diagonal empty: refused before anything of the rows'
    // size is allocated (a header's size is otherwise unbounded).
    if r.entries.len() < n {
        return Err(bad(format!(
            "the {what} matrix has {} entries for {n} degrees of freedom: every degree of freedom needs a positive diagonal entry (is the size its header gives right?)",
            r.entries.len()
        )));
    }
    let scaled = r.entries.into_iter().map(|(i, j, v)| (i, j, v * scale));
    let a = SymSparse::from_entries(n, scaled, r.one_triangle).map_err(|e| {
        bad(format!(
            "the {what} matrix is not symmetric: entry ({}, {}) is {} but ({}, {}) is {} ({})",
            e.row + 1,
            e.col + 1,
            e.lower / scale,
            e.col + 1,
            e.row + 1,
            e.upper / scale,
            row_name(labels, e.row)
        ))
    })?;
    if let Some((r, v)) = a.diagonal().into_iter().enumerate().find(|(_, v)| *v <= 0.0) {
        return Err(bad(format!(
            "the {what} matrix's diagonal at {} is {}: every degree of freedom needs a positive {what} (condense massless or unconnected ones out in the finite-element program)",
            row_name(labels, r),
            v / scale
        )));
    }
    Ok(a)
}

/// Reads, checks and reduces the model of `raw` (keys named `structure.finite_element.*`).
/// With `limit` (the most coordinates, and what runs them: e.g. `analysis kind "sweep"
/// runs`), a reduction that would keep more is refused once its modes are counted, before
/// they are computed.
///
/// A model already reduced in this process from the same files and settings is not reduced
/// again ([`made`]).
pub fn build(path: &Path, raw: RawFiniteElement, limit: Option<(usize, &str)>) -> Result<FromFiles> {
    let Some(key) = made::Key::of(path, &raw, limit.map(|l| l.0)) else {
        made::computed_without_key();
        return reduce(path, raw, limit);
    };
    if let Some(found) = made::find(&key) {
        return Ok(found);
    }
    let built = reduce(path, raw, limit)?;
    made::keep(key, &built);
    Ok(built)
}

/// The points of `[structure.finite_element]` (`raw.points`) on the model's rows: each by its
/// node and direction or its row, distinct, named, and measured upward where `up` (the
/// global axis 1-3 and its sign) says which way is up.
fn points_of(
    path: &Path,
    raw: &RawFiniteElement,
    labels: &Option<Vec<DofLabel>>,
    n: usize,
    (up_axis, up_sign): (usize, f64),
) -> Result<Vec<Point>> {
    let key = |k: &str| format!("structure.finite_element.{k}");
    let invalid = |k: &str, v: &dyn std::fmt::Display, m: &str| Error::invalid(path, key(k), v, m);
    let mut points: Vec<Point> = Vec::with_capacity(raw.points.len());
    for (i, p) in raw.points.iter().enumerate() {
        let pk = format!("points[{i}]");
        let (row, label) = match (p.node, p.dof, p.row, labels) {
            (Some(node), Some(dof), None, Some(l)) => {
                if !(1..=3).contains(&dof) {
                    return Err(invalid(&format!("{pk}.dof"), &dof, "a translation: 1 (x), 2 (y) or 3 (z)"));
                }
                let want = DofLabel { node: node.max(0) as u64, dof: dof as u8 };
                match l.iter().position(|x| *x == want) {
                    Some(r) => (r, Some(want)),
                    None => {
                        let node_known = l.iter().any(|x| x.node == want.node);
                        return Err(invalid(
                            &pk,
                            &format!("{{ node = {node}, dof = {dof} }}"),
                            if node_known {
                                "this direction of the node is not a degree of freedom of the model (constrained?)"
                            } else {
                                "the node is not in the model's degrees of freedom (its .dof file or labels)"
                            },
                        ));
                    }
                }
            }
            (Some(_), Some(_), None, None) => {
                return Err(invalid(
                    &pk,
                    &"{ node, dof }",
                    "the model's files do not name nodes: give dofs = \"job.dof\" or a row = R",
                ))
            }
            (None, None, Some(r), _) if r >= 1 && (r as usize) <= n => {
                (r as usize - 1, labels.as_ref().map(|l| l[r as usize - 1]))
            }
            (None, None, Some(r), _) => {
                return Err(invalid(
                    &format!("{pk}.row"),
                    &r,
                    &format!("rows are numbered 1 to {n} (the model's degrees of freedom)"),
                ))
            }
            _ => return Err(invalid(&pk, &"(incomplete)", "give node and dof, or row")),
        };
        if let Some(j) = points.iter().position(|q| q.row == row) {
            return Err(invalid(&pk, &row_name(labels, row), &format!("the same degree of freedom as points[{j}]")));
        }
        // Without names every point is taken along the vertical (a chain's coordinates).
        let vertical = label.is_none_or(|l| usize::from(l.dof) == up_axis);
        let horizontal = label.is_none_or(|l| (1..=3).contains(&usize::from(l.dof)) && usize::from(l.dof) != up_axis);
        let name = p.name.clone().unwrap_or_else(|| match label {
            Some(l) => format!("node {} {}", l.node, ["x", "y", "z"][usize::from(l.dof) - 1]),
            None => format!("row {}", row + 1),
        });
        points.push(Point { name, row, label, vertical, horizontal, sign: if vertical { up_sign } else { 1.0 } });
    }
    Ok(points)
}

/// The settings of `[structure.finite_element]` other than its files and points, checked.
struct Settings {
    /// Stiffness and mass scales to N/m and kg.
    k_scale: f64,
    m_scale: f64,
    /// The global axis (1-3) that points up, and its sign.
    up: (usize, f64),
    /// The axis moving supports accelerate along, and its sign.
    base: (usize, f64),
    /// The fixed-interface modes kept.
    keep: Keep,
    /// The reduction check's tolerance.
    tolerance: f64,
}

/// [`Settings`] of `raw`, each refused with its key, value and what is allowed.
fn settings(path: &Path, raw: &RawFiniteElement) -> Result<Settings> {
    let key = |k: &str| format!("structure.finite_element.{k}");
    let invalid = |k: &str, v: &dyn std::fmt::Display, m: &str| Error::invalid(path, key(k), v, m);
    let (k_scale, m_scale) = match raw.units.as_deref() {
        None | Some("N-m-kg") => (1.0, 1.0),
        Some("N-mm-t") => (1e3, 1e3),
        Some(u) => {
            return Err(invalid("units", &format!("\"{u}\""), "\"N-m-kg\" (default) or \"N-mm-t\" (N/mm and tonnes)"))
        }
    };
    let axis = |k: &str, v: &str| match v {
        "x" | "+x" => Ok((1, 1.0)),
        "y" | "+y" => Ok((2, 1.0)),
        "z" | "+z" => Ok((3, 1.0)),
        "-x" => Ok((1, -1.0)),
        "-y" => Ok((2, -1.0)),
        "-z" => Ok((3, -1.0)),
        u => Err(invalid(
            k,
            &format!("\"{u}\""),
            &format!(
                "the global direction that {}: x, y, z, -x, -y or -z",
                if k == "up" { "points up" } else { "moving supports accelerate along" }
            ),
        )),
    };
    let up = axis("up", &raw.up)?;
    let base = axis("base_direction", raw.base_direction.as_deref().unwrap_or(&raw.up))?;
    let keep = match (raw.modes, raw.cutoff_hz) {
        (Some(m), None) if (0..=10_000).contains(&m) => Keep::Count(m as usize),
        (Some(m), None) => return Err(invalid("modes", &m, "the fixed-interface modes kept: a whole number from 0 to 10000")),
        (None, Some(f)) if f.is_finite() && f > 0.0 && f <= MAX_CUTOFF_HZ => Keep::Below(2.0 * std::f64::consts::PI * f),
        (None, Some(f)) => {
            return Err(invalid("cutoff_hz", &f, &format!("a positive frequency, Hz, at most {MAX_CUTOFF_HZ:e}")))
        }
        _ => {
            return Err(invalid(
                "modes / cutoff_hz",
                &"(both or neither)",
                "give at most one: modes = N (the lowest N fixed-interface modes) or cutoff_hz = F (every one below F); without either, every mode below twice the highest frequency the analysis simulates (a modal analysis has none: give one)",
            ))
        }
    };
    let tolerance = raw.tolerance.unwrap_or(1e-3);
    if !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(invalid("tolerance", &tolerance, "a relative difference between 0 and 1 (default 1e-3)"));
    }
    Ok(Settings { k_scale, m_scale, up, base, keep, tolerance })
}

/// [`build`] without looking for a reduction already made.
fn reduce(path: &Path, raw: RawFiniteElement, limit: Option<(usize, &str)>) -> Result<FromFiles> {
    let key = |k: &str| format!("structure.finite_element.{k}");
    let invalid = |k: &str, v: &dyn std::fmt::Display, m: &str| Error::invalid(path, key(k), v, m);
    let Settings { k_scale, m_scale, up: (up_axis, up_sign), base, keep, tolerance } = settings(path, &raw)?;
    let (labels, k_read, m_read, n) = read(path, &raw)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let stiffness = matrix(&dir.join(&raw.stiffness), "stiffness", k_read, n, k_scale, &labels)?;
    let mass = matrix(&dir.join(&raw.mass), "mass", m_read, n, m_scale, &labels)?;
    if raw.points.is_empty() {
        return Err(invalid(
            "points",
            &"[]",
            "name at least one point: { node = N, dof = D } (container hosts, the force, responses)",
        ));
    }
    let points = points_of(path, &raw, &labels, n, (up_axis, up_sign))?;
    let boundary: Vec<usize> = points.iter().map(|p| p.row).collect();
    // The key that sets how many modes are kept, as given.
    let (keep_key, keep_value) = match (raw.modes, raw.cutoff_hz) {
        (Some(m), _) => ("modes", m.to_string()),
        (None, f) => ("cutoff_hz", f.map_or_else(|| "(none)".into(), |f| f.to_string())),
    };
    announce(path, &mass, &stiffness, &boundary);
    let file_of = |matrix: Matrix| dir.join(if matrix == Matrix::Mass { &raw.mass } else { &raw.stiffness });
    let mut reduced = craig_bampton_sparse(&mass, &stiffness, &boundary, keep, limit.map(|l| l.0)).map_err(|e| match e {
        ReductionError::NotPositive { matrix, row } => Error::Parse {
            file: file_of(matrix).display().to_string(),
            message: format!(
                "the {matrix} matrix is not positive definite: the factor of the degrees of freedom other than the points has a zero or negative pivot at {}: {}",
                row_name(&labels, row),
                if matrix == Matrix::Mass {
                    "a negative or indefinite mass entry"
                } else {
                    "a part of the model not held by its supports or points (a free-floating piece, a mechanism, a zero-energy mode of reduced integration) or an indefinite stiffness entry"
                }
            ),
        },
        ReductionError::ReducedNotPositive { matrix, coordinate } => Error::Parse {
            file: file_of(matrix).display().to_string(),
            message: format!(
                "the {matrix} matrix is not positive definite at point \"{}\" ({}, points[{coordinate}]): {}",
                points[coordinate].name,
                row_name(&labels, points[coordinate].row),
                if matrix == Matrix::Mass {
                    "a negative or indefinite mass entry there"
                } else {
                    "the point with what hangs on it floats free (held by no support), or an indefinite stiffness entry there"
                }
            ),
        },
        e @ ReductionError::TooLarge { .. } => Error::refused_in(
            path,
            "structure.finite_element",
            format!("{n} degrees of freedom"),
            "is too large to reduce here: ",
            e,
            " (docs/fe-models.md, section 3: condense the model in the finite-element program, or coarsen its mesh)",
        ),
        ReductionError::TooMany { boundary, modes, most } => invalid(
            keep_key,
            &keep_value,
            &format!(
                "it keeps {modes} fixed-interface modes, with the {boundary} points {} coordinates: {} the exact simulator, which takes at most {most} (modes = {} at most, or a lower cutoff_hz)",
                boundary + modes,
                limit.map_or("", |l| l.1),
                most.saturating_sub(boundary),
            ),
        ),
        e @ ReductionError::Missed { .. } => {
            Error::refused_in(path, key(keep_key), &keep_value, format!("the model ({n} degrees of freedom) cannot be reduced so: "), e, "")
        }
        e => Error::refused_in(path, "structure.finite_element", format!("{n} degrees of freedom"), "cannot be reduced: ", e, ""),
    })?;
    // A point whose direction points down is measured upward: its coordinate changes sign.
    for (c, p) in points.iter().enumerate() {
        if p.sign < 0.0 {
            reduced.transform.column_mut(c).neg_mut();
            for a in [&mut reduced.mass, &mut reduced.stiffness] {
                a.row_mut(c).neg_mut();
                a.column_mut(c).neg_mut();
            }
        }
    }
    let files = [Some(&raw.stiffness), Some(&raw.mass), raw.dofs.as_ref()]
        .into_iter()
        .flatten()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    let supports = supports(&mass, &labels, &points, &reduced, base, raw.base_direction.as_deref().unwrap_or(&raw.up));
    let moving_up = along(&mass, &labels, up_axis);
    // A stated mass holds the mass the model moves (the supports' share aside).
    let mass_stated = match raw.mass_kg {
        None => None,
        Some(m) if m.is_finite() && m >= moving_up * (1.0 - 1e-6) => Some(m),
        Some(m) => {
            return Err(invalid(
                "mass_kg",
                &m,
                &format!(
                    "the physical structure's whole mass in kg, at least the {} kg its matrices move vertically",
                    crate::number::fmt_sig(moving_up, 6)
                ),
            ))
        }
    };
    let full = FullModel { stiffness, mass, labels, files: format!("{} ({})", files, raw.format) };
    Ok(FromFiles {
        supports,
        mass: reduced.mass.clone(),
        stiffness: reduced.stiffness.clone(),
        fe: FeStructure {
            full: Arc::new(full),
            points,
            reduced,
            up: raw.up,
            tolerance,
            mass_along_up: moving_up,
            mass_stated,
        },
    })
}

/// The mass that moves when the whole model translates along global `axis` (1-3), kg:
/// `r^T M r`, `r` one on every translation along the axis (every row when the files name no
/// degrees of freedom).
fn along(mass: &SymSparse, labels: &Option<Vec<DofLabel>>, axis: usize) -> f64 {
    let r: Vec<f64> = match labels {
        Some(l) => l.iter().map(|d| if usize::from(d.dof) == axis { 1.0 } else { 0.0 }).collect(),
        None => vec![1.0; mass.n()],
    };
    let mut mr = vec![0.0; r.len()];
    mass.mul(&r, &mut mr);
    r.iter().zip(&mr).map(|(a, b)| a * b).sum()
}

/// Says on standard error, before it starts, that a reduction will take a while (a factor of
/// more than [`ANNOUNCE_FLOPS`] operations): the only output of this layer, so that a large
/// model's wait is never silent.
fn announce(path: &Path, mass: &SymSparse, stiffness: &SymSparse, boundary: &[usize]) {
    let interior: Vec<usize> = (0..mass.n()).filter(|i| !boundary.contains(i)).collect();
    let (k, m) = (stiffness.principal(&interior), mass.principal(&interior));
    let cost = crate::model::sparse::Skyline::cost(&k, Some(&m), &crate::model::sparse::rcm(&k));
    if cost.flops > ANNOUNCE_FLOPS && cost.flops <= crate::model::reduction::MAX_FACTOR.flops {
        eprintln!(
            "{}: reducing a finite-element model of {} degrees of freedom (a factor of {} entries, {:.1e} operations; each factor takes seconds to a minute)",
            path.display(),
            mass.n(),
            cost.entries,
            cost.flops
        );
    }
}

/// How a reduced model's coordinates follow its supports moving along global `axis` (1-3)
/// with `sign`: `r_full` is `sign` on every translation along the axis (every row when the
/// files name none), the load `L = T^T M r_full`, and `r` the points' share of it (0 on the
/// modal coordinates; a point measured the other way round changes sign).
fn supports(
    mass: &SymSparse,
    labels: &Option<Vec<DofLabel>>,
    points: &[Point],
    reduced: &Reduced,
    (axis, sign): (usize, f64),
    direction: &str,
) -> crate::model::base::Supports {
    let n = mass.n();
    let r: Vec<f64> = match labels {
        Some(l) => l.iter().map(|d| if usize::from(d.dof) == axis { sign } else { 0.0 }).collect(),
        None => vec![1.0; n],
    };
    let mut mr = vec![0.0; n];
    mass.mul(&r, &mut mr);
    let t = &reduced.transform;
    let load = (0..t.ncols()).map(|c| t.column(c).iter().zip(&mr).map(|(a, b)| a * b).sum()).collect();
    let follow = (0..t.ncols()).map(|c| points.get(c).map_or(0.0, |p| r[p.row] * p.sign)).collect();
    crate::model::base::Supports { follow, load, direction: direction.to_string() }
}

/// Checks that `host` (0-based coordinate, named `key`) is a point a container moving along
/// `direction` may sit on: a translation along the vertical for a vertical container, at a
/// right angle to it for a horizontal one.
pub fn host_fits(path: &Path, fe: &FeStructure, key: &str, host: usize, direction: Direction) -> Result<()> {
    let p = fe.points.len();
    match fe.points.get(host) {
        None => Err(Error::invalid(
            path,
            key,
            host + 1,
            format!("a container sits on one of the finite-element points, numbered 1 to {p} (coordinates above {p} are modal)"),
        )),
        Some(pt) if direction == Direction::Vertical && !pt.vertical => Err(Error::invalid(
            path,
            key,
            host + 1,
            format!(
                "point \"{}\" does not move along the vertical (structure.finite_element.up = \"{}\"): a vertical container moves along gravity; give the container direction = \"horizontal\" if this point is a horizontal translation",
                pt.name, fe.up
            ),
        )),
        Some(pt) if direction == Direction::Horizontal && !pt.horizontal => Err(Error::invalid(
            path,
            key,
            host + 1,
            format!(
                "point \"{}\" is not a horizontal translation (structure.finite_element.up = \"{}\"): a horizontal container moves at a right angle to gravity; give it direction = \"vertical\" on a vertical point",
                pt.name, fe.up
            ),
        )),
        Some(_) => Ok(()),
    }
}
