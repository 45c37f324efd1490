//! Values across the boundary: Python arguments to the TOML-shaped tables the library reads
//! (so that they get the experiment files' validation and messages), and results to numpy.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A Python value as the TOML value an experiment file would hold: bool, int, float, str,
/// sequences (lists, tuples, numpy arrays) and dicts with string keys. `key` names it in a
/// `TypeError`.
pub fn to_toml(key: &str, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return match v.extract::<i64>() {
            Ok(i) => Ok(toml::Value::Integer(i)),
            Err(_) => Ok(toml::Value::Float(v.extract::<f64>()?)),
        };
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        return Ok(toml::Value::Table(table(key, d)?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, x) in v.try_iter()?.enumerate() {
            out.push(to_toml(&format!("{key}[{i}]"), &x?)?);
        }
        return Ok(toml::Value::Array(out));
    }
    // numpy arrays and scalars (np.float64 is a float already; np.int64 is not an int).
    if v.hasattr("tolist")? && v.hasattr("dtype")? {
        return to_toml(key, &v.call_method0("tolist")?);
    }
    Err(PyTypeError::new_err(format!(
        "{key}: a number, a string, a bool, a sequence of them or a dict, not {}",
        v.get_type().name()?
    )))
}

/// A dict with string keys as a TOML table; `None` values are left out (not given).
pub fn table(key: &str, d: &Bound<'_, PyDict>) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let name: String = k.extract().map_err(|_| PyTypeError::new_err(format!("{key}: keys must be strings")))?;
        if v.is_none() {
            continue;
        }
        let value = to_toml(&format!("{key}.{name}"), &v)?;
        t.insert(name, value);
    }
    Ok(t)
}

/// Named optional arguments as a TOML table (those given).
pub fn named(pairs: &[(&str, Option<&Bound<'_, PyAny>>)]) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (name, v) in pairs {
        if let Some(v) = v.filter(|v| !v.is_none()) {
            t.insert((*name).to_string(), to_toml(name, v)?);
        }
    }
    Ok(t)
}

/// A one-dimensional sequence of floats (a numpy array of float64 without a copy of its
/// meaning, or any sequence of numbers).
pub fn floats(key: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    if let Ok(a) = v.extract::<PyReadonlyArray1<'_, f64>>() {
        return Ok(a.as_array().iter().copied().collect());
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(vec![x]);
    }
    v.extract::<Vec<f64>>().map_err(|_| {
        let shape = v.getattr("shape").map(|s| format!(" of shape {s}")).unwrap_or_default();
        PyValueError::new_err(format!("{key}: a one-dimensional sequence of numbers, not {}{shape}", type_name(v)))
    })
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into())
}

/// A vector as a numpy array.
pub fn array1<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// Rows of equal length as a two-dimensional numpy array (`cols` columns when there are no
/// rows).
pub fn array2<'py>(py: Python<'py>, rows: &[Vec<f64>], cols: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    if rows.is_empty() {
        return PyArray1::from_vec(py, Vec::<f64>::new()).reshape([0, cols]);
    }
    PyArray2::from_vec2(py, rows).map_err(|e| PyTypeError::new_err(e.to_string()))
}

/// A matrix as a two-dimensional numpy array.
pub fn matrix<'py>(py: Python<'py>, m: &nalgebra::DMatrix<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows: Vec<Vec<f64>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
    array2(py, &rows, m.ncols())
}

/// A table of the library as a `shotdamp.Table`: columns by name (numpy arrays; a list of str
/// for text), with the table's name and description.
pub fn columns<'py>(py: Python<'py>, t: &shotdamp::table::Table) -> PyResult<Bound<'py, PyAny>> {
    use shotdamp::table::ColumnData;
    let d = PyDict::new(py);
    for (name, col) in &t.columns {
        match col {
            ColumnData::F64(v) => d.set_item(name, PyArray1::from_slice(py, v))?,
            ColumnData::I64(v) => d.set_item(name, PyArray1::from_slice(py, v))?,
            ColumnData::Str(v) => d.set_item(name, PyList::new(py, v)?)?,
        }
    }
    py.import("shotdamp")?.getattr("Table")?.call1((d, &t.name, &t.description))
}

/// Most frequencies one call takes (as an experiment file's grid).
const MAX_FREQUENCIES: usize = 100_000;

/// Frequencies, Hz: positive and finite, at most [`MAX_FREQUENCIES`].
pub fn frequencies(origin: &str, f: &[f64]) -> PyResult<Vec<f64>> {
    if f.is_empty() {
        return Err(crate::compute::error(shotdamp::Error::invalid(
            origin,
            "freq_hz",
            "[]",
            "give at least one frequency (Hz)",
        )));
    }
    if f.len() > MAX_FREQUENCIES {
        return Err(crate::compute::error(shotdamp::Error::invalid(
            origin,
            "freq_hz",
            format!("{} frequencies", f.len()),
            format!("at most {MAX_FREQUENCIES} frequencies"),
        )));
    }
    if let Some((i, x)) = f.iter().enumerate().find(|(_, x)| !(x.is_finite() && **x > 0.0)) {
        return Err(crate::compute::error(shotdamp::Error::invalid(
            origin,
            format!("freq_hz[{i}]"),
            x,
            "frequencies must be positive and finite (Hz)",
        )));
    }
    Ok(f.to_vec())
}
