//! The regression baseline: a small, reviewable sample of every experiment's results, stored
//! under `reference/baseline/` by `shotdamp report --bless` and compared with tight tolerances on
//! every other run, so that an unintended numerical change fails while an intended one is
//! blessed in the same commit.
//!
//! A sample is a long table `table, row, key, column, value`: from each result table, at most
//! [`ROWS_PER_TABLE`] evenly spaced rows (rows that did not settle or are not period-1, and
//! design rows with points that did not settle, are left out: their values depend on the
//! record, whose motion never settles and so carries the rounding of every step), every
//! numeric column. Tables whose values depend on
//! where an adaptive method put its points, or on the whole of a long impact history, are left
//! out too ([`SKIPPED`]).

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::{Error, Result};
use crate::table::{ColumnData, Table};

use super::{fmt_num, status, CheckOutcome, Source};

/// Most rows sampled from one table.
pub const ROWS_PER_TABLE: usize = 60;

/// Tables not sampled: continuation branches (adaptive points), the tables listing them,
/// impulse histories past their start and what is computed from the whole of them
/// (trajectories of an impact system part after many impacts under any change of rounding).
pub const SKIPPED: [&str; 10] = [
    "branches",
    "branch_special_points",
    "sdof_branch",
    "exact_branch",
    "special_points",
    "orbit_vs_simulation",
    "histories",
    "energy_history",
    "spectrum",
    "damping",
];

/// Columns not sampled: rounding-level numbers, which move with any change of the order of
/// operations: a fixed-point residual (whatever the last Newton step left, ~1e-13) and the
/// relative residual of an energy balance (~1e-15; its bound is asserted by the tests), and
/// what a time history's energy balance leaves over (`balance_j`, rounding and quadrature).
pub const SKIPPED_COLUMNS: [&str; 3] = ["orbit_residual", "residual", "balance_j"];

/// Relative tolerance of a baseline comparison, and the absolute floor as a fraction of the
/// column's largest magnitude (for values near zero).
pub const REL_TOL: f64 = 1e-6;
/// Absolute floor of a baseline comparison, as a fraction of the column's largest magnitude.
pub const ABS_FLOOR: f64 = 1e-9;

/// One sampled value.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    /// The table's name.
    pub table: String,
    /// The row, 0-based.
    pub row: i64,
    /// The row's text columns and its first numeric column, for people.
    pub key: String,
    /// The numeric column sampled.
    pub column: String,
    /// Its value.
    pub value: f64,
}

/// The sample of an experiment's tables.
pub fn sample(tables: &[Table]) -> Vec<Value> {
    let mut out = Vec::new();
    for t in tables.iter().filter(|t| !SKIPPED.contains(&t.name.as_str())) {
        let h = t.height();
        if h == 0 {
            continue;
        }
        let regular = |i: usize| {
            let ok = |name: &str, want: i64| match t.columns.iter().find(|(n, _)| n == name) {
                Some((_, ColumnData::I64(v))) => v[i] == want,
                _ => true,
            };
            ok("converged", 1) && ok("period", 1) && ok("unsettled_points", 0)
        };
        let rows: Vec<usize> = (0..h).filter(|&i| regular(i)).collect();
        let stride = rows.len().div_ceil(ROWS_PER_TABLE).max(1);
        for &i in rows.iter().step_by(stride) {
            let mut key: Vec<String> = t
                .columns
                .iter()
                .filter_map(|(_, c)| match c {
                    ColumnData::Str(v) => Some(v[i].clone()),
                    _ => None,
                })
                .collect();
            let mut first = true;
            for (name, c) in &t.columns {
                let v = match c {
                    ColumnData::F64(v) => v[i],
                    ColumnData::I64(v) => v[i] as f64,
                    ColumnData::Str(_) => continue,
                };
                if SKIPPED_COLUMNS.contains(&name.as_str()) {
                    continue;
                }
                if first {
                    key.push(format!("{name}={}", fmt_num(v)));
                    first = false;
                    continue;
                }
                out.push(Value {
                    table: t.name.clone(),
                    row: i as i64,
                    key: key.join(" "),
                    column: name.clone(),
                    value: v,
                });
            }
        }
    }
    out
}

/// The sample as a table (written as CSV by the report writer).
pub fn to_table(values: &[Value]) -> Table {
    Table::new("baseline", "Regression baseline: sampled results, blessed by shotdamp report --bless")
        .str("table", values.iter().map(|v| v.table.clone()).collect())
        .i64("row", values.iter().map(|v| v.row).collect())
        .str("key", values.iter().map(|v| v.key.clone()).collect())
        .str("column", values.iter().map(|v| v.column.clone()).collect())
        .f64("value", values.iter().map(|v| v.value).collect())
}

/// Reads a baseline file.
pub fn load(path: &Path) -> Result<Vec<Value>> {
    use polars::prelude::*;
    let err = |m: String| Error::Table { path: path.to_path_buf(), message: m };
    let df = crate::table::read_csv(path)?;
    let text = |name: &str| -> Result<Vec<String>> {
        let c = df.column(name).map_err(|e| err(e.to_string()))?;
        let c = c.cast(&DataType::String).map_err(|e| err(e.to_string()))?;
        let s = c.str().map_err(|e| err(e.to_string()))?;
        Ok(s.iter().map(|v| v.unwrap_or_default().to_string()).collect())
    };
    let num = |name: &str| -> Result<Vec<f64>> {
        let c = df.column(name).map_err(|e| err(e.to_string()))?;
        let c = c.cast(&DataType::Float64).map_err(|e| err(e.to_string()))?;
        let s = c.f64().map_err(|e| err(e.to_string()))?;
        Ok(s.iter().map(|v| v.unwrap_or(f64::NAN)).collect())
    };
    let (table, key, column) = (text("table")?, text("key")?, text("column")?);
    let (row, value) = (num("row")?, num("value")?);
    Ok((0..table.len())
        .map(|i| Value {
            table: table[i].clone(),
            row: row[i] as i64,
            key: key[i].clone(),
            column: column[i].clone(),
            value: value[i],
        })
        .collect())
}

/// Compares a run's sample with the blessed one. `figure` names the experiment's figure.
pub fn compare(experiment: &str, figure: &str, now: &[Value], blessed: &[Value]) -> CheckOutcome {
    let index = |v: &[Value]| -> BTreeMap<(String, i64, String), (String, f64)> {
        v.iter().map(|x| ((x.table.clone(), x.row, x.column.clone()), (x.key.clone(), x.value))).collect()
    };
    let (a, b) = (index(now), index(blessed));
    // Column scales for the absolute floor.
    let mut scale: BTreeMap<(String, String), f64> = BTreeMap::new();
    for x in blessed {
        let s = scale.entry((x.table.clone(), x.column.clone())).or_insert(0.0);
        if x.value.is_finite() {
            *s = s.max(x.value.abs());
        }
    }
    let mut moved: Vec<(f64, String)> = Vec::new();
    let mut missing = 0;
    for (k, (key, old)) in &b {
        let Some((_, new)) = a.get(k) else {
            missing += 1;
            continue;
        };
        let same_nan = old.is_nan() && new.is_nan();
        let floor = ABS_FLOOR * scale.get(&(k.0.clone(), k.2.clone())).copied().unwrap_or(0.0);
        let diff = (new - old).abs();
        // A NaN on one side only is a change too.
        let within = diff <= REL_TOL * old.abs() + floor;
        if !same_nan && !within {
            let rel = if *old != 0.0 { diff / old.abs() } else { f64::INFINITY };
            moved.push((
                if rel.is_nan() { f64::INFINITY } else { rel },
                format!(
                    "table {}, {key}, {}: {} now, {} blessed ({rel:.2e} relative)",
                    k.0,
                    k.2,
                    fmt_num(*new),
                    fmt_num(*old)
                ),
            ));
        }
    }
    let added = a.keys().filter(|k| !b.contains_key(*k)).count();
    moved.sort_by(|x, y| y.0.total_cmp(&x.0));
    let ok = moved.is_empty() && missing == 0 && added == 0;
    let worst = moved.first().map(|m| m.0).unwrap_or(0.0);
    let mut detail = format!("{} values compared", b.len());
    if let Some((_, w)) = moved.first() {
        detail += &format!("; {} moved, the worst: {w}", moved.len());
    }
    if missing + added > 0 {
        detail +=
            &format!("; {missing} blessed values no longer computed, {added} new ones (the tables changed shape)");
    }
    if !ok {
        detail += "; if the change is intended, bless it: shotdamp report --bless";
    }
    CheckOutcome {
        settled: None,
        id: None,
        values: Vec::new(),
        name: "baseline".into(),
        description: format!("{figure} ({experiment}): every sampled result against the blessed baseline"),
        computed: worst,
        expected: 0.0,
        unit: "(largest relative change)".into(),
        abs_diff: worst,
        rel_diff: worst,
        tolerance: format!("{} relative, floor {} of the column's largest value", fmt_num(REL_TOL), fmt_num(ABS_FLOOR)),
        status: status(ok, false),
        provenance: format!("reference/baseline/{experiment}.csv"),
        source: Source::Baseline,
        reason: None,
        detail: Some(detail),
    }
}

/// The outcome when an experiment has no blessed baseline yet.
pub fn missing(experiment: &str, figure: &str) -> CheckOutcome {
    CheckOutcome::unavailable(
        "baseline".into(),
        format!("{figure} ({experiment}): no blessed baseline"),
        format!("reference/baseline/{experiment}.csv (missing)"),
        Source::Baseline,
        Some("bless the current results with: shotdamp report --bless (and review the diff)".into()),
    )
}
