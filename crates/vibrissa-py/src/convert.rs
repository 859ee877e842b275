//! Values to and from Python: columns as numpy arrays (one move of the vector, no copy per
//! element), JSON values (the CLI's summaries) as Python objects.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

/// A column as a 1-D numpy float64 array (the vector's buffer is handed to numpy).
pub fn array<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// A JSON value as a Python object (`null` -> `None`, numbers -> `int` or `float`).
pub fn json<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match n.as_i64() {
            Some(i) => i.into_pyobject(py)?.into_any(),
            None => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, item) in map {
                dict.set_item(k, json(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// A result dict holding named columns under `"columns"`, as a dict of numpy arrays (the
/// shape of every table the package returns: `solve`, `sweep`, `reconstruct`).
pub fn with_columns<'py>(
    py: Python<'py>,
    cols: Vec<(&str, Vec<f64>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (name, v) in cols {
        dict.set_item(name, array(py, v))?;
    }
    let out = PyDict::new(py);
    out.set_item("columns", dict)?;
    Ok(out)
}

/// A 1-D float64 numpy array (or anything numpy turns into one: the Python layer passes
/// contiguous float64 arrays) as a vector: one copy of the buffer, no Python object per
/// element. `None` if `obj` is not such an array.
pub fn vector(obj: &Bound<'_, PyAny>) -> Option<Vec<f64>> {
    let arr: PyReadonlyArray1<'_, f64> = obj.extract().ok()?;
    match arr.as_slice() {
        Ok(s) => Some(s.to_vec()),
        Err(_) => Some(arr.as_array().to_vec()),
    }
}
