//! What a report folder holds (README, "Reading the report"): a history too long for a light
//! report in a CSV file that keeps every extreme and no Parquet file; `--full-data` writes
//! it whole in Parquet and thinned in CSV, `--full-csv` every row in CSV; each figure in the
//! smaller of PNG and SVG, `--svg` both.

use crate::common;

use polars::prelude::*;

fn parquet_height(path: &std::path::Path) -> usize {
    ParquetReader::new(std::fs::File::open(path).unwrap()).finish().unwrap().height()
}

#[test]
fn long_histories_are_reduced_to_their_extremes_and_whole_with_full_data() {
    let dir = tempfile::tempdir().unwrap();
    let exps = common::experiments(dir.path(), &["fig10b_impulse.toml"]);
    let (light, data_full, thin, svg) =
        (dir.path().join("light"), dir.path().join("data"), dir.path().join("full"), dir.path().join("svg"));
    let mut checks = Vec::new();
    for (out, extra) in
        [(&light, None), (&data_full, Some("--full-data")), (&thin, Some("--full-csv")), (&svg, Some("--svg"))]
    {
        let mut cmd = common::shotdamp();
        cmd.arg("run").arg(exps.join("fig10b_impulse.toml")).arg("--out").arg(out);
        if let Some(flag) = extra {
            cmd.arg(flag);
        }
        let status = cmd.output().unwrap().status;
        assert!(status.code().is_some_and(|c| c <= 1), "{status:?}");
        checks.push(std::fs::read_to_string(out.join("checks.json")).unwrap());
    }
    // The checks read the whole tables before any reduction: the same values every way.
    assert!(checks.iter().all(|c| *c == checks[0]), "checks.json differs between the ways of writing");
    let data = |root: &std::path::Path| root.join("fig10b_impulse/stated/data");
    // --full-data: every row in Parquet, the CSV every k-th row and the last.
    let rows = parquet_height(&data(&data_full).join("histories.parquet"));
    assert!(rows > shotdamp::table::LIGHT_ROWS, "the histories are long: {rows} rows");
    let whole = common::csv_rows(&std::fs::read_to_string(data(&thin).join("histories.csv")).unwrap());
    assert_eq!(whole.len() - 1, rows, "--full-csv: every row");
    let k = shotdamp::table::csv_stride(rows, false);
    let thinned = common::csv_rows(&std::fs::read_to_string(data(&data_full).join("histories.csv")).unwrap());
    let expected: Vec<&Vec<String>> =
        whole[1..].iter().enumerate().filter(|(i, _)| i % k == 0 || i + 1 == rows).map(|(_, r)| r).collect();
    assert_eq!(thinned[0], whole[0], "same header");
    assert_eq!(thinned[1..].iter().collect::<Vec<_>>(), expected);
    // The light report: no Parquet file; the CSV's rows are rows of the whole table, the
    // thinned ones among them, and each column's largest and smallest value is there.
    assert!(!data(&light).join("histories.parquet").exists());
    let reduced = common::csv_rows(&std::fs::read_to_string(data(&light).join("histories.csv")).unwrap());
    assert_eq!(reduced[0], whole[0]);
    assert!(reduced.len() - 1 <= 2 * shotdamp::table::PREVIEW_ROWS, "{} rows", reduced.len() - 1);
    let set: std::collections::HashSet<&Vec<String>> = whole[1..].iter().collect();
    assert!(reduced[1..].iter().all(|r| set.contains(r)), "a reduced row is a row of the table");
    let p = shotdamp::table::preview_stride(rows);
    let previewed = whole[1..].iter().enumerate().filter(|(i, _)| i % p == 0 || i + 1 == rows).map(|(_, r)| r);
    let kept: std::collections::HashSet<&Vec<String>> = reduced[1..].iter().collect();
    for r in previewed {
        assert!(kept.contains(r), "the preview's rows are kept");
    }
    assert!(reduced.len() > rows / p, "extremes added to the preview");
    for c in 0..whole[0].len() {
        let column = |rows: &[Vec<String>]| rows.iter().filter_map(|r| r[c].parse::<f64>().ok()).collect::<Vec<f64>>();
        let (w, s) = (column(&whole[1..]), column(&reduced[1..]));
        let top = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let bottom = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!((top(&w), bottom(&w)), (top(&s), bottom(&s)), "column {}", whole[0][c]);
    }
    // The pages say so.
    let page = |root: &std::path::Path| std::fs::read_to_string(root.join("fig10b_impulse/stated/index.html")).unwrap();
    assert!(page(&light).contains("every row: <code>--full-data</code>"), "the light page names the flag");
    assert!(page(&data_full).contains(&format!("one row in {k} and the last")), "the page states the stride");
    assert!(!page(&thin).contains("and the last; <code>--full-csv"));
    // Figures: one file each, the smaller; both with --svg; the page links what exists.
    let folder = |root: &std::path::Path| root.join("fig10b_impulse/stated");
    for f in ["decay", "spectrum"] {
        let (png, svgf) = (folder(&svg).join(format!("{f}.png")), folder(&svg).join(format!("{f}.svg")));
        assert!(png.is_file() && svgf.is_file(), "--svg: both of {f}");
        let smaller = if std::fs::metadata(&png).unwrap().len() <= std::fs::metadata(&svgf).unwrap().len() {
            "png"
        } else {
            "svg"
        };
        let other = if smaller == "png" { "svg" } else { "png" };
        assert!(folder(&light).join(format!("{f}.{smaller}")).is_file(), "{f}: the smaller file");
        assert!(!folder(&light).join(format!("{f}.{other}")).exists(), "{f}: only the smaller file");
        assert!(page(&light).contains(&format!("src=\"{f}.{smaller}\"")), "{f}: the page shows it");
        assert!(!page(&light).contains(&format!("\"{f}.{other}\"")), "{f}: no link to a file not written");
    }
}
