//! What a report folder holds: long tables thinned in CSV and whole in Parquet (README,
//! "Reading the report"), `--full-csv` for every row.

use crate::common;

use polars::prelude::*;

fn parquet_height(path: &std::path::Path) -> usize {
    ParquetReader::new(std::fs::File::open(path).unwrap()).finish().unwrap().height()
}

#[test]
fn long_histories_are_thinned_in_csv_and_whole_in_parquet() {
    let dir = tempfile::tempdir().unwrap();
    let exps = common::experiments(dir.path(), &["fig10b_impulse.toml"]);
    let (thin, full) = (dir.path().join("thin"), dir.path().join("full"));
    for (out, extra) in [(&thin, None), (&full, Some("--full-csv"))] {
        let mut cmd = common::shotdamp();
        cmd.arg("run").arg(exps.join("fig10b_impulse.toml")).arg("--out").arg(out);
        if let Some(flag) = extra {
            cmd.arg(flag);
        }
        let status = cmd.output().unwrap().status;
        assert!(status.code().is_some_and(|c| c <= 1), "{status:?}");
    }
    let data = |root: &std::path::Path| root.join("fig10b_impulse/stated/data");
    let rows = parquet_height(&data(&thin).join("histories.parquet"));
    assert!(rows > shotdamp::table::CSV_ROWS, "the histories are long: {rows} rows");
    assert_eq!(parquet_height(&data(&full).join("histories.parquet")), rows);
    let whole = common::csv_rows(&std::fs::read_to_string(data(&full).join("histories.csv")).unwrap());
    let thinned = common::csv_rows(&std::fs::read_to_string(data(&thin).join("histories.csv")).unwrap());
    assert_eq!(whole.len() - 1, rows, "--full-csv: every row");
    let k = shotdamp::table::csv_stride(rows, false);
    assert!(k > 1 && thinned.len() - 1 <= shotdamp::table::CSV_ROWS);
    // Every k-th row of the whole table, and its last, byte for byte.
    let expected: Vec<&Vec<String>> =
        whole[1..].iter().enumerate().filter(|(i, _)| i % k == 0 || i + 1 == rows).map(|(_, r)| r).collect();
    assert_eq!(thinned[0], whole[0], "same header");
    assert_eq!(thinned[1..].iter().collect::<Vec<_>>(), expected);
    // The page says so; the other page does not.
    let page = |root: &std::path::Path| std::fs::read_to_string(root.join("fig10b_impulse/stated/index.html")).unwrap();
    assert!(page(&thin).contains(&format!("one row in {k} and the last")), "the page states the stride");
    assert!(!page(&full).contains("and the last; <code>--full-csv"));
}
