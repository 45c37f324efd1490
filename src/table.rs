//! Tables: a plain column store built by the analyses, written through polars (CSV, Parquet);
//! reference and baseline CSV files are read through it too.

use polars::prelude::*;

use crate::error::{Error, Result};

/// One column of a table.
#[derive(Debug, Clone, PartialEq)]
pub enum ColumnData {
    /// Floats.
    F64(Vec<f64>),
    /// Integers.
    I64(Vec<i64>),
    /// Text.
    Str(Vec<String>),
}

impl ColumnData {
    fn len(&self) -> usize {
        match self {
            ColumnData::F64(v) => v.len(),
            ColumnData::I64(v) => v.len(),
            ColumnData::Str(v) => v.len(),
        }
    }
}

/// Most rows a report writes to a table's CSV file unless every row is asked for: a longer
/// table's CSV keeps every `k`-th row ([`csv_stride`]) and its last, and the table is also
/// written whole as Parquet ([`has_parquet`]); a table of at most this many rows is whole in
/// its CSV file alone.
pub const CSV_ROWS: usize = 1_500;

/// Most rows of a light report's CSV file of a table longer than [`CSV_ROWS`] (evenly spaced,
/// the last included: [`preview_stride`]); the table is whole in its Parquet file, or, longer
/// than [`LIGHT_ROWS`], its extremes are kept ([`Table::reduced`]). `--full-data` writes the
/// [`CSV_ROWS`] thinning instead.
pub const PREVIEW_ROWS: usize = 300;

/// Longest table a report writes whole as Parquet unless the full data is asked for
/// (`--full-data`): a longer one (a history sampled at every step) is reduced in its CSV file
/// to [`Table::reduced`]'s rows, every extreme kept, and has no Parquet file.
pub const LIGHT_ROWS: usize = 10_000;

/// Whether a report writes the table of `rows` rows as Parquet too: when it is longer than
/// [`CSV_ROWS`] (whether or not its CSV is thinned).
pub fn has_parquet(rows: usize) -> bool {
    rows > CSV_ROWS
}

/// The stride of a table's CSV file in a report: 1 when `full` or the table has at most
/// [`CSV_ROWS`] rows, else the smallest `k` that keeps at most `CSV_ROWS` rows, the last
/// included.
pub fn csv_stride(rows: usize, full: bool) -> usize {
    if full || rows <= CSV_ROWS {
        1
    } else {
        (rows - 1).div_ceil(CSV_ROWS - 2)
    }
}

/// The stride of a light report's CSV file of a table of `rows` rows: 1 up to [`CSV_ROWS`]
/// rows, else the smallest `k` that keeps at most [`PREVIEW_ROWS`] rows, the last included.
pub fn preview_stride(rows: usize) -> usize {
    if rows <= CSV_ROWS {
        1
    } else {
        (rows - 1).div_ceil(PREVIEW_ROWS - 2)
    }
}

/// A named table of equal-length columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// File stem of the table (`NAME.csv`, `NAME.parquet`).
    pub name: String,
    /// One sentence on what it holds, with units.
    pub description: String,
    /// Columns by name, in order.
    pub columns: Vec<(String, ColumnData)>,
}

impl Table {
    /// An empty table.
    pub fn new(name: impl Into<String>, description: impl Into<String>) -> Table {
        Table { name: name.into(), description: description.into(), columns: Vec::new() }
    }

    /// Adds a column of floats.
    pub fn f64(mut self, name: impl Into<String>, values: Vec<f64>) -> Table {
        self.columns.push((name.into(), ColumnData::F64(values)));
        self
    }

    /// Adds a column of integers.
    pub fn i64(mut self, name: impl Into<String>, values: Vec<i64>) -> Table {
        self.columns.push((name.into(), ColumnData::I64(values)));
        self
    }

    /// Adds a column of strings.
    pub fn str(mut self, name: impl Into<String>, values: Vec<String>) -> Table {
        self.columns.push((name.into(), ColumnData::Str(values)));
        self
    }

    /// Every `stride`-th row from the first, and the last row (a thinned copy for a CSV file;
    /// `stride` 1 copies every row).
    pub fn thinned(&self, stride: usize) -> Table {
        let n = self.height();
        let keep = |i: usize| i % stride.max(1) == 0 || i + 1 == n;
        let pick = |c: &ColumnData| match c {
            ColumnData::F64(v) => {
                ColumnData::F64(v.iter().enumerate().filter(|(i, _)| keep(*i)).map(|x| *x.1).collect())
            }
            ColumnData::I64(v) => {
                ColumnData::I64(v.iter().enumerate().filter(|(i, _)| keep(*i)).map(|x| *x.1).collect())
            }
            ColumnData::Str(v) => {
                ColumnData::Str(v.iter().enumerate().filter(|(i, _)| keep(*i)).map(|x| x.1.clone()).collect())
            }
        };
        let columns = self.columns.iter().map(|(name, c)| (name.clone(), pick(c))).collect();
        Table { name: self.name.clone(), description: self.description.clone(), columns }
    }

    /// The rows that keep every extreme of a long table: every `stride`-th row and the last
    /// (as [`Table::thinned`]), and in each of `buckets` equal stretches of rows the row of
    /// the smallest and the largest value of every numeric column (NaN skipped, the first of
    /// equal values): MinMax reduction, so the largest and smallest value of each column,
    /// and of each stretch, are rows of the result.
    pub fn extreme_rows(&self, stride: usize, buckets: usize) -> Vec<usize> {
        let n = self.height();
        let mut keep: Vec<usize> = (0..n).filter(|i| i % stride.max(1) == 0 || i + 1 == n).collect();
        let buckets = buckets.clamp(1, n.max(1));
        for b in 0..buckets {
            let (lo, hi) = (b * n / buckets, (b + 1) * n / buckets);
            for (_, c) in &self.columns {
                let value = |i: usize| match c {
                    ColumnData::F64(v) => Some(v[i]),
                    ColumnData::I64(v) => Some(v[i] as f64),
                    ColumnData::Str(_) => None,
                };
                let mut low: Option<(usize, f64)> = None;
                let mut high: Option<(usize, f64)> = None;
                for i in lo..hi {
                    let Some(x) = value(i).filter(|x| !x.is_nan()) else { continue };
                    if low.is_none_or(|(_, l)| x < l) {
                        low = Some((i, x));
                    }
                    if high.is_none_or(|(_, h)| x > h) {
                        high = Some((i, x));
                    }
                }
                keep.extend(low.map(|l| l.0));
                keep.extend(high.map(|h| h.0));
            }
        }
        keep.sort_unstable();
        keep.dedup();
        keep
    }

    /// The table reduced for a light report ([`Table::extreme_rows`]): the preview's stride
    /// rows ([`preview_stride`]), and each numeric column's extremes in as many stretches as
    /// keep at most another [`PREVIEW_ROWS`] rows.
    pub fn reduced(&self) -> Table {
        let numeric = self.columns.iter().filter(|(_, c)| !matches!(c, ColumnData::Str(_))).count().max(1);
        self.rows(&self.extreme_rows(preview_stride(self.height()), PREVIEW_ROWS / (2 * numeric)))
    }

    /// The table of the given rows (ascending indices).
    pub fn rows(&self, rows: &[usize]) -> Table {
        let pick = |c: &ColumnData| match c {
            ColumnData::F64(v) => ColumnData::F64(rows.iter().map(|&i| v[i]).collect()),
            ColumnData::I64(v) => ColumnData::I64(rows.iter().map(|&i| v[i]).collect()),
            ColumnData::Str(v) => ColumnData::Str(rows.iter().map(|&i| v[i].clone()).collect()),
        };
        let columns = self.columns.iter().map(|(name, c)| (name.clone(), pick(c))).collect();
        Table { name: self.name.clone(), description: self.description.clone(), columns }
    }

    /// Number of rows.
    pub fn height(&self) -> usize {
        self.columns.first().map(|c| c.1.len()).unwrap_or(0)
    }

    /// A column of floats by name.
    pub fn column_f64(&self, name: &str) -> Option<&[f64]> {
        self.columns.iter().find_map(|(n, c)| match c {
            ColumnData::F64(v) if n == name => Some(v.as_slice()),
            _ => None,
        })
    }

    /// The polars frame of this table.
    pub fn to_frame(&self) -> PolarsResult<DataFrame> {
        let cols: Vec<Column> = self
            .columns
            .iter()
            .map(|(name, data)| match data {
                ColumnData::F64(v) => Column::new(name.as_str().into(), v.as_slice()),
                ColumnData::I64(v) => Column::new(name.as_str().into(), v.as_slice()),
                ColumnData::Str(v) => Column::new(name.as_str().into(), v.as_slice()),
            })
            .collect();
        DataFrame::new(self.height(), cols)
    }
}

/// CSV bytes of a table (floats in full precision).
pub fn to_csv(table: &Table) -> Result<Vec<u8>> {
    let mut df = table.to_frame().map_err(|e| table_err(&table.name, e))?;
    let mut buf = Vec::new();
    CsvWriter::new(&mut buf).include_header(true).finish(&mut df).map_err(|e| table_err(&table.name, e))?;
    Ok(buf)
}

/// Parquet bytes of a table.
pub fn to_parquet(table: &Table) -> Result<Vec<u8>> {
    let mut df = table.to_frame().map_err(|e| table_err(&table.name, e))?;
    let mut buf = Vec::new();
    ParquetWriter::new(&mut buf).finish(&mut df).map_err(|e| table_err(&table.name, e))?;
    Ok(buf)
}

/// Reads a CSV file with a header into a polars frame.
pub fn read_csv(path: &std::path::Path) -> Result<DataFrame> {
    CsvReadOptions::default()
        .with_has_header(true)
        .try_into_reader_with_file_path(Some(path.to_path_buf()))
        .and_then(|r| r.finish())
        .map_err(|e| Error::Table { path: path.to_path_buf(), message: e.to_string() })
}

fn table_err(name: &str, e: PolarsError) -> Error {
    Error::Table { path: format!("{name} (table)").into(), message: e.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trip_keeps_full_precision() {
        let t =
            Table::new("t", "test").f64("x", vec![0.1, 1.0 / 3.0, 1e-5 * std::f64::consts::PI]).i64("k", vec![1, 2, 3]);
        let csv = to_csv(&t).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.csv");
        std::fs::write(&p, csv).unwrap();
        let curve = crate::checks::reference::Curve::load(&p).unwrap();
        assert_eq!(curve.column("x").unwrap(), &[0.1, 1.0 / 3.0, 1e-5 * std::f64::consts::PI]);
        assert_eq!(curve.column("k").unwrap(), &[1.0, 2.0, 3.0]);
        assert!(!to_parquet(&t).unwrap().is_empty());
    }

    #[test]
    fn the_reduction_keeps_every_extreme_of_every_stretch() {
        let n = 25_001;
        let wave: Vec<f64> = (0..n).map(|i| (i as f64 * 0.0251).sin() * (1.0 + (i % 97) as f64 * 1e-3)).collect();
        let mut spikes = vec![0.0; n];
        spikes[12_345] = 7.0;
        spikes[20_001] = -3.0;
        let t = Table::new("h", "")
            .f64("t", (0..n).map(|i| i as f64 * 1e-4).collect())
            .f64("x", wave.clone())
            .f64("s", spikes)
            .i64("k", (0..n as i64).map(|i| (i * 7919) % 1000).collect())
            .str("label", vec!["a".into(); n]);
        let small = t.reduced();
        assert!(small.height() <= 2 * CSV_ROWS, "{}", small.height());
        // Every row of the result is a row of the table, in order.
        let ColumnData::F64(ts) = &small.columns[0].1 else { panic!("column type") };
        assert!(ts.windows(2).all(|w| w[0] < w[1]));
        // The largest and smallest value of every numeric column is kept, the spikes too.
        for c in 1..4 {
            let (whole, kept) = (t.columns[c].1.clone(), small.columns[c].1.clone());
            let values = |d: &ColumnData| match d {
                ColumnData::F64(v) => v.clone(),
                ColumnData::I64(v) => v.iter().map(|&x| x as f64).collect(),
                ColumnData::Str(_) => Vec::new(),
            };
            let (w, k) = (values(&whole), values(&kept));
            let max = |v: &[f64]| v.iter().copied().fold(f64::MIN, f64::max);
            let min = |v: &[f64]| v.iter().copied().fold(f64::MAX, f64::min);
            assert_eq!((max(&w), min(&w)), (max(&k), min(&k)), "column {c}");
        }
        // Each stretch's extremes of the wave: the rows chosen for 44 stretches.
        let rows = t.extreme_rows(17, 44);
        for b in 0..44 {
            let (lo, hi) = (b * n / 44, (b + 1) * n / 44);
            let top = (lo..hi).max_by(|&a, &c| wave[a].total_cmp(&wave[c]).then(c.cmp(&a))).unwrap();
            assert!(rows.binary_search(&top).is_ok(), "stretch {b}: row {top}");
        }
    }

    #[test]
    fn thinned_csv_keeps_at_most_the_limit_first_and_last_rows() {
        for n in [0, 1, CSV_ROWS, CSV_ROWS + 1, 2 * CSV_ROWS - 1, 2 * CSV_ROWS + 7, 100_003] {
            let t =
                Table::new("t", "").i64("i", (0..n as i64).collect()).str("s", (0..n).map(|i| i.to_string()).collect());
            let k = csv_stride(n, false);
            let thin = t.thinned(k);
            assert!(thin.height() <= CSV_ROWS, "{n} rows, stride {k}: {}", thin.height());
            let ColumnData::I64(kept) = &thin.columns[0].1 else { panic!("column type") };
            if n > 0 {
                assert_eq!((kept[0], *kept.last().unwrap()), (0, n as i64 - 1));
            }
            // Every k-th row, then the last.
            assert!(kept.windows(2).all(|w| w[1] - w[0] == k as i64 || w[1] == n as i64 - 1));
            assert_eq!(csv_stride(n, true), 1);
        }
        assert_eq!(csv_stride(CSV_ROWS, false), 1);
    }
}
