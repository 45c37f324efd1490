//! Matrix Market coordinate files (the format ANSYS writes with `*EXPORT, MMF` and the
//! SuiteSparse collection uses): `real` or `integer` values, `general` or `symmetric`
//! storage, read line by line (a large file is never held as text). Every fault is an input
//! error naming the file, the line and what is wrong.

use std::io::BufRead;
use std::path::Path;

use nalgebra::DMatrix;

use crate::error::{Error, Result};

/// A sparse matrix as read: its size and its entries, 0-based, each position once (a
/// repeated one is refused). A symmetric file stores one triangle; `symmetric` says so.
#[derive(Debug, Clone, PartialEq)]
pub struct Triplets {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// `(row, column, value)`, 0-based, in the file's order.
    pub entries: Vec<(usize, usize, f64)>,
    /// The file stores the lower triangle of a symmetric matrix.
    pub symmetric: bool,
}

impl Triplets {
    /// The dense matrix (a symmetric file's triangle mirrored).
    pub fn to_dense(&self) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(self.rows, self.cols);
        for &(i, j, v) in &self.entries {
            m[(i, j)] += v;
            if self.symmetric && i != j {
                m[(j, i)] += v;
            }
        }
        m
    }
}

/// Reads the Matrix Market file at `path`.
pub fn read(path: &Path) -> Result<Triplets> {
    crate::error::regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    parse(std::io::BufReader::new(file), &path.display().to_string())
}

/// Parses Matrix Market text from `reader`; errors name `origin`.
pub fn parse(reader: impl BufRead, origin: &str) -> Result<Triplets> {
    let bad = |line: usize, message: String| Error::Parse {
        file: origin.to_string(),
        message: format!("line {line}: {message}"),
    };
    let mut lines = reader.lines().enumerate().map(|(i, l)| (i + 1, l));
    let mut next = |what: &str| -> Result<Option<(usize, String)>> {
        match lines.next() {
            Some((n, l)) => {
                let l = l.map_err(|e| bad(n, format!("cannot be read ({e}) while reading {what}")))?;
                Ok(Some((n, super::without_bom(l, n))))
            }
            None => Ok(None),
        }
    };
    // The banner: %%MatrixMarket matrix coordinate real|integer general|symmetric.
    let Some((n, banner)) = next("the banner")? else {
        return Err(bad(1, "the file is empty: a Matrix Market file starts with %%MatrixMarket".into()));
    };
    let words: Vec<String> = banner.split_whitespace().map(str::to_ascii_lowercase).collect();
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    let symmetric = match words.as_slice() {
        ["%%matrixmarket", "matrix", "coordinate", "real" | "integer" | "double", sym] => match *sym {
            "general" => false,
            "symmetric" => true,
            other => return Err(bad(n, format!("storage \"{other}\" is not read: give general or symmetric"))),
        },
        ["%%matrixmarket", "matrix", "coordinate", field, _] => {
            return Err(bad(n, format!("values of type \"{field}\" are not read: give real or integer")))
        }
        ["%%matrixmarket", "matrix", "array", ..] => {
            return Err(bad(n, "a dense (array) file is not read: give the coordinate format".into()))
        }
        _ => {
            return Err(bad(
                n,
                format!("\"{banner}\" is not a Matrix Market banner (%%MatrixMarket matrix coordinate real general)"),
            ))
        }
    };
    // Comments, then the size line: rows, columns, entries.
    let mut seen = n;
    let (n, size) = loop {
        match next("the size line")? {
            None => return Err(bad(seen + 1, "the file ends before its size line (rows columns entries)".into())),
            Some((n, l)) if l.trim().is_empty() || l.trim_start().starts_with('%') => seen = n,
            Some(found) => break found,
        }
    };
    let numbers: Vec<std::result::Result<usize, _>> = size.split_whitespace().map(str::parse::<usize>).collect();
    let (rows, cols, count) = match numbers.as_slice() {
        [Ok(r), Ok(c), Ok(e)] if *r > 0 && *c > 0 => (*r, *c, *e),
        _ => return Err(bad(n, format!("\"{size}\" is not a size line: three whole numbers, rows columns entries"))),
    };
    if symmetric && rows != cols {
        return Err(bad(n, format!("a symmetric matrix must be square, not {rows} x {cols}")));
    }
    // Reserved up to a modest size: a header may claim any count (the file then ends early).
    let mut entries = Vec::with_capacity(count.min(1 << 16));
    let mut positions = super::Positions::default();
    let mut last = n;
    while entries.len() < count {
        let Some((n, l)) = next("an entry")? else {
            return Err(bad(
                last + 1,
                format!("the file ends after {} of its {count} entries (truncated?)", entries.len()),
            ));
        };
        last = n;
        if l.trim().is_empty() || l.trim_start().starts_with('%') {
            continue;
        }
        let parts: Vec<&str> = l.split_whitespace().collect();
        let [i, j, v] = parts.as_slice() else {
            return Err(bad(n, format!("\"{l}\" is not an entry: row column value")));
        };
        let index = |s: &str, size: usize, what: &str| match s.parse::<usize>() {
            Ok(k) if (1..=size).contains(&k) => Ok(k - 1),
            _ => Err(bad(n, format!("{what} \"{s}\" is not a whole number from 1 to {size}"))),
        };
        let (i, j) = (index(i, rows, "row")?, index(j, cols, "column")?);
        let v: f64 = match v.parse::<f64>() {
            Ok(v) if v.is_finite() => v,
            _ => return Err(bad(n, format!("value \"{v}\" is not a finite number"))),
        };
        if symmetric && j > i {
            return Err(bad(
                n,
                format!(
                    "entry ({}, {}) lies above the diagonal: a symmetric file stores the lower triangle",
                    i + 1,
                    j + 1
                ),
            ));
        }
        if let Some(before) = positions.repeated(i, j, n) {
            return Err(bad(n, super::Positions::message(i, j, before)));
        }
        entries.push((i, j, v));
    }
    // Nothing but comments and blank lines may follow.
    while let Some((n, l)) = next("the end")? {
        if !(l.trim().is_empty() || l.trim_start().starts_with('%')) {
            return Err(bad(n, format!("more entries than the {count} the size line gives")));
        }
    }
    Ok(Triplets { rows, cols, entries, symmetric })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(text: &str) -> Result<Triplets> {
        parse(std::io::Cursor::new(text), "k.mtx")
    }

    fn message(text: &str) -> String {
        parsed(text).unwrap_err().to_string()
    }

    #[test]
    fn a_symmetric_file_is_mirrored_and_a_general_one_kept() {
        let sym = "%%MatrixMarket matrix coordinate real symmetric\n% a comment\n\n3 3 4\n1 1 2.0\n2 1 -1\n2 2 2e0\n3 3 1.5\n";
        let m = parsed(sym).unwrap().to_dense();
        assert_eq!(m, DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, 0.0, 0.0, 0.0, 1.5]));
        let gen = "%%MatrixMarket matrix coordinate integer general\n2 2 2\n1 2 4\n2 1 3\n";
        let m = parsed(gen).unwrap().to_dense();
        assert_eq!(m, DMatrix::from_row_slice(2, 2, &[0.0, 4.0, 3.0, 0.0]));
        let twice = "%%MatrixMarket matrix coordinate integer general\n2 2 3\n1 2 4\n2 1 3\n1 2 1\n";
        assert!(message(twice).contains("line 5: entry (1, 2) is given again (first on line 3)"));
        let bom = "\u{feff}%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 0.25\n";
        assert_eq!(parsed(bom).unwrap().to_dense()[(0, 0)], 0.25);
    }

    #[test]
    fn every_fault_names_its_line() {
        let head = "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n";
        for (text, says) in [
            ("", "k.mtx: line 1: the file is empty"),
            ("%%MatrixMarket matrix array real general\n2 2\n", "line 1: a dense (array) file is not read"),
            ("%%MatrixMarket matrix coordinate complex general\n", "line 1: values of type \"complex\" are not read"),
            ("%%MatrixMarket matrix coordinate real hermitian\n", "line 1: storage \"hermitian\" is not read"),
            (
                "%%MatrixMarket matrix coordinate real general\n% only a comment\n",
                "line 3: the file ends before its size line",
            ),
            ("%%MatrixMarket matrix coordinate real general\n2 x 3\n", "line 2: \"2 x 3\" is not a size line"),
            ("%%MatrixMarket matrix coordinate real symmetric\n2 3 1\n", "line 2: a symmetric matrix must be square"),
            (&format!("{head}1 1 1.0\n"), "line 4: the file ends after 1 of its 2 entries (truncated?)"),
            (&format!("{head}1 1 1.0\n3 1 1.0\n"), "line 4: row \"3\" is not a whole number from 1 to 2"),
            (&format!("{head}1 1 nan\n2 2 1\n"), "line 3: value \"nan\" is not a finite number"),
            (&format!("{head}1 2 1.0\n2 2 1\n"), "line 3: entry (1, 2) lies above the diagonal"),
            (&format!("{head}1 1 1.0\n2 2\n"), "line 4: \"2 2\" is not an entry"),
            (&format!("{head}1 1 1.0\n2 2 1\n2 1 1\n"), "line 5: more entries than the 2 the size line gives"),
        ] {
            let m = message(text);
            assert!(m.contains(says), "{text:?}: {m}");
        }
    }

    #[test]
    fn the_paper_s_chain_as_matrix_market_files_is_the_paper_s_structure() {
        use crate::model::{Damping, Structure};
        let m = "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 0.74\n2 2 0.71\n3 3 0.64\n";
        let k = "%%MatrixMarket matrix coordinate real symmetric\n3 3 5\n1 1 46100\n2 1 -21800\n2 2 41600\n3 2 -19800\n3 3 19800\n";
        let damping = Damping::ModalRatios(vec![0.01; 3]);
        let read =
            Structure::from_mass_matrix(parsed(m).unwrap().to_dense(), parsed(k).unwrap().to_dense(), damping.clone());
        assert_eq!(read, Structure::chain(&[0.74, 0.71, 0.64], &[24.3e3, 21.8e3, 19.8e3], damping));
    }

    #[test]
    fn a_file_on_disk_is_read_and_a_missing_one_is_an_io_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.mtx");
        std::fs::write(&path, "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 0.25\n").unwrap();
        assert_eq!(read(&path).unwrap().to_dense()[(0, 0)], 0.25);
        assert!(matches!(read(&dir.path().join("none.mtx")), Err(Error::Io { .. })));
    }
}
