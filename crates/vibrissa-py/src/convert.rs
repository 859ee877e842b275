//! Values to and from Python: columns as numpy arrays (one move of the vector, no copy per
//! element), the library's small records (summaries, scenes: serde `Serialize` types) as
//! Python dicts, lists and numbers (`pythonize`, no JSON text in between).

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Serialize;

/// A column as a 1-D numpy float64 array (the vector's buffer is handed to numpy).
pub fn array<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// A record of the library (a struct: a dict; `None` -> `None`; a non-finite number, which
/// the records write as `None`, stays `None`) as a Python object.
pub fn record<'py, T: Serialize + ?Sized>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, v).map_err(PyErr::from)
}

/// A record of the library that is a struct, as a Python dict (to add keys to).
pub fn record_dict<'py, T: Serialize + ?Sized>(
    py: Python<'py>,
    v: &T,
) -> PyResult<Bound<'py, PyDict>> {
    Ok(record(py, v)?.cast_into::<PyDict>()?)
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
