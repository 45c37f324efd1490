//! CalculiX's matrices, written by `*FREQUENCY, SOLVER=MATRIXSTORAGE`: `job.sti` and
//! `job.mas` hold one triangle of the stiffness and mass matrices, a line `row column value`
//! each (1-based, the constrained degrees of freedom left out), and `job.dof` names each row
//! `node.direction` (directions 1-3 translations x, y, z). Abaqus' `*MATRIX GENERATE` output
//! (`*MATRIX OUTPUT, STIFFNESS, MASS, FORMAT=LABELS`) names rows by `node, dof` on every line
//! instead: [`read_abaqus`]. Files are read line by line; every fault is an input error
//! naming the file, the line and what is wrong.

use std::io::BufRead;
use std::path::Path;

use super::{without_bom, Positions};
use crate::error::{Error, Result};
use crate::model::fe::DofLabel;

fn open(path: &Path) -> Result<impl BufRead> {
    crate::error::regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    Ok(std::io::BufReader::new(file))
}

fn bad(origin: &str, line: usize, message: String) -> Error {
    Error::Parse { file: origin.to_string(), message: format!("line {line}: {message}") }
}

fn number(origin: &str, line: usize, s: &str, what: &str) -> Result<f64> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(bad(origin, line, format!("{what} \"{}\" is not a finite number", s.trim()))),
    }
}

/// Reads a `.dof` file: one `node.direction` a line.
pub fn read_dofs(path: &Path) -> Result<Vec<DofLabel>> {
    parse_dofs(open(path)?, &path.display().to_string())
}

/// Parses `.dof` text; errors name `origin`.
pub fn parse_dofs(reader: impl BufRead, origin: &str) -> Result<Vec<DofLabel>> {
    let mut labels = Vec::new();
    let mut first_on: std::collections::HashMap<DofLabel, usize> = std::collections::HashMap::new();
    for (i, line) in reader.lines().enumerate() {
        let n = i + 1;
        let line = without_bom(line.map_err(|e| bad(origin, n, format!("cannot be read ({e})")))?, n);
        let t = line.trim();
        if t.is_empty() {
            continue;
        }
        let parsed = t.split_once('.').and_then(|(a, b)| Some((a.parse::<u64>().ok()?, b.parse::<u8>().ok()?)));
        match parsed {
            Some((node, dof)) if (1..=6).contains(&dof) => {
                let label = DofLabel { node, dof };
                if let Some(before) = first_on.insert(label, n) {
                    return Err(bad(
                        origin,
                        n,
                        format!("\"{t}\" names node {node} direction {dof} again (first on line {before}): each degree of freedom once, one a row"),
                    ));
                }
                labels.push(label);
            }
            _ => {
                return Err(bad(
                    origin,
                    n,
                    format!("\"{t}\" is not node.direction (a node number, a dot, a direction 1 to 6)"),
                ))
            }
        }
    }
    if labels.is_empty() {
        return Err(bad(origin, 1, "the file names no degree of freedom".into()));
    }
    Ok(labels)
}

/// Reads a `.sti` or `.mas` file of a model of `n` degrees of freedom: its entries, 0-based,
/// one triangle.
pub fn read_matrix(path: &Path, n: usize) -> Result<Vec<(usize, usize, f64)>> {
    parse_matrix(open(path)?, &path.display().to_string(), n)
}

/// Parses `.sti` / `.mas` text; errors name `origin`.
pub fn parse_matrix(reader: impl BufRead, origin: &str, n: usize) -> Result<Vec<(usize, usize, f64)>> {
    let mut entries = Vec::new();
    let mut positions = Positions::default();
    for (i, line) in reader.lines().enumerate() {
        let no = i + 1;
        let line = without_bom(line.map_err(|e| bad(origin, no, format!("cannot be read ({e})")))?, no);
        let parts: Vec<&str> = line.split_whitespace().collect();
        if parts.is_empty() {
            continue;
        }
        let [r, c, v] = parts.as_slice() else {
            return Err(bad(origin, no, format!("\"{}\" is not an entry: row column value (truncated?)", line.trim())));
        };
        let index = |s: &str, what: &str| match s.parse::<usize>() {
            Ok(k) if (1..=n).contains(&k) => Ok(k - 1),
            _ => Err(bad(
                origin,
                no,
                format!(
                    "{what} \"{s}\" is not a whole number from 1 to {n} (the .dof file names {n} degrees of freedom)"
                ),
            )),
        };
        let (r, c, v) = (index(r, "row")?, index(c, "column")?, number(origin, no, v, "value")?);
        if let Some(before) = positions.repeated(r, c, no) {
            return Err(bad(origin, no, Positions::message(r, c, before)));
        }
        entries.push((r, c, v));
    }
    if entries.is_empty() {
        return Err(bad(origin, 1, "the file holds no entry".into()));
    }
    Ok(entries)
}

/// An Abaqus matrix: the degrees of freedom in order of first appearance and the entries
/// (0-based in that order, one triangle).
pub type Labelled = (Vec<DofLabel>, Vec<(usize, usize, f64)>);

/// Reads an Abaqus `.mtx` file (`node, dof, node, dof, value` a line; lines starting `*`
/// are comments). `labels` continues the numbering of another file of the same model (its
/// stiffness, for its mass): a degree of freedom met first here is appended.
pub fn read_abaqus(path: &Path, labels: Vec<DofLabel>) -> Result<Labelled> {
    parse_abaqus(open(path)?, &path.display().to_string(), labels)
}

/// Parses Abaqus `.mtx` text; errors name `origin`.
pub fn parse_abaqus(reader: impl BufRead, origin: &str, mut labels: Vec<DofLabel>) -> Result<Labelled> {
    let mut at: std::collections::HashMap<DofLabel, usize> = labels.iter().enumerate().map(|(i, l)| (*l, i)).collect();
    let mut entries = Vec::new();
    let mut positions = Positions::default();
    for (i, line) in reader.lines().enumerate() {
        let no = i + 1;
        let line = without_bom(line.map_err(|e| bad(origin, no, format!("cannot be read ({e})")))?, no);
        let t = line.trim();
        if t.is_empty() || t.starts_with('*') {
            continue;
        }
        let parts: Vec<&str> = t.split(',').map(str::trim).collect();
        let [n1, d1, n2, d2, v] = parts.as_slice() else {
            return Err(bad(origin, no, format!("\"{t}\" is not an entry: node, dof, node, dof, value (truncated?)")));
        };
        let mut label = |n: &str, d: &str| -> Result<usize> {
            let parsed = n.parse::<u64>().ok().zip(d.parse::<u8>().ok().filter(|d| (1..=6).contains(d)));
            let Some((node, dof)) = parsed else {
                return Err(bad(origin, no, format!("\"{n}, {d}\" is not a node number and a direction 1 to 6")));
            };
            let l = DofLabel { node, dof };
            let next = at.len();
            Ok(*at.entry(l).or_insert_with(|| {
                labels.push(l);
                next
            }))
        };
        let (r, c, v) = (label(n1, d1)?, label(n2, d2)?, number(origin, no, v, "value")?);
        if let Some(before) = positions.repeated(r, c, no) {
            return Err(bad(origin, no, Positions::message(r, c, before)));
        }
        entries.push((r, c, v));
    }
    if entries.is_empty() {
        return Err(bad(origin, 1, "the file holds no entry".into()));
    }
    Ok((labels, entries))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn msg(e: Error) -> String {
        e.to_string()
    }

    #[test]
    fn a_small_model_is_read() {
        let dofs = parse_dofs("2.1\n2.3\n\n7.3\n".as_bytes(), "m.dof").unwrap();
        assert_eq!(
            dofs,
            vec![DofLabel { node: 2, dof: 1 }, DofLabel { node: 2, dof: 3 }, DofLabel { node: 7, dof: 3 }]
        );
        let k = parse_matrix("1 1 4.0e+03\n1 2 -1.5E3\n2 2 3e3\n3 3 1\n".as_bytes(), "m.sti", 3).unwrap();
        assert_eq!(k, vec![(0, 0, 4e3), (0, 1, -1.5e3), (1, 1, 3e3), (2, 2, 1.0)]);
        let (labels, e) = parse_abaqus(
            "** stiffness\n1,1, 1,1, 2.0\n1,3, 1,1, -1.0\n 4, 2, 4, 2, 5.0\n".as_bytes(),
            "k.mtx",
            Vec::new(),
        )
        .unwrap();
        assert_eq!(labels.len(), 3);
        assert_eq!(labels[2], DofLabel { node: 4, dof: 2 });
        assert_eq!(e, vec![(0, 0, 2.0), (1, 0, -1.0), (2, 2, 5.0)]);
        // The mass file continues the stiffness file's numbering.
        let (more, m) = parse_abaqus("4,2,4,2,0.5\n9,1,9,1,0.25\n".as_bytes(), "m.mtx", labels).unwrap();
        assert_eq!((more.len(), m[0].0, m[1].0), (4, 2, 3));
    }

    #[test]
    fn each_bad_file_names_its_line_and_fault() {
        let e = msg(parse_dofs("2.1\n2.x\n".as_bytes(), "m.dof").unwrap_err());
        assert!(e.contains("m.dof") && e.contains("line 2") && e.contains("node.direction"), "{e}");
        let e = msg(parse_dofs("".as_bytes(), "m.dof").unwrap_err());
        assert!(e.contains("no degree of freedom"), "{e}");
        let e = msg(parse_matrix("1 1 1.0\n2 1\n".as_bytes(), "m.sti", 2).unwrap_err());
        assert!(e.contains("m.sti") && e.contains("line 2") && e.contains("truncated"), "{e}");
        let e = msg(parse_matrix("1 1 NaN\n".as_bytes(), "m.sti", 2).unwrap_err());
        assert!(e.contains("line 1") && e.contains("finite"), "{e}");
        let e = msg(parse_matrix("1 3 1.0\n".as_bytes(), "m.mas", 2).unwrap_err());
        assert!(e.contains("column \"3\"") && e.contains("names 2 degrees"), "{e}");
        let e = msg(parse_abaqus("1,1,1,1\n".as_bytes(), "k.mtx", Vec::new()).unwrap_err());
        assert!(e.contains("k.mtx") && e.contains("line 1") && e.contains("node, dof, node, dof, value"), "{e}");
        let e = msg(parse_abaqus("1,7,1,1,2.0\n".as_bytes(), "k.mtx", Vec::new()).unwrap_err());
        assert!(e.contains("direction 1 to 6"), "{e}");
    }

    #[test]
    fn a_repeated_degree_of_freedom_or_entry_is_refused_and_a_byte_order_mark_is_read() {
        let e = msg(parse_dofs("2.1\n2.3\n2.1\n".as_bytes(), "m.dof").unwrap_err());
        assert!(e.contains("line 3") && e.contains("node 2 direction 1 again (first on line 1)"), "{e}");
        let e = msg(parse_matrix("1 1 1.0\n2 2 1.0\n1 1 1.0\n".as_bytes(), "m.sti", 2).unwrap_err());
        assert!(e.contains("m.sti: line 3: entry (1, 1) is given again (first on line 1)"), "{e}");
        let e = msg(parse_abaqus("1,1,1,1,2.0\n1,1,1,1,2.0\n".as_bytes(), "k.mtx", Vec::new()).unwrap_err());
        assert!(e.contains("line 2: entry (1, 1) is given again"), "{e}");
        let dofs = parse_dofs("\u{feff}2.1\n2.3\n".as_bytes(), "m.dof").unwrap();
        assert_eq!(dofs[0], DofLabel { node: 2, dof: 1 });
        assert_eq!(parse_matrix("\u{feff}1 1 4.0\n".as_bytes(), "m.sti", 1).unwrap(), vec![(0, 0, 4.0)]);
    }
}
