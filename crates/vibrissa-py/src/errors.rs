//! The library's errors as Python exceptions, and the guard that keeps panics out of Python.
//!
//! The classes live in `vibrissa._errors` (pure Python, so that `InvalidInput` can also be a
//! `ValueError` and `SolverError` a `RuntimeError`); the message is the one line of
//! [`IoError`], the same the command line prints.

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::prelude::*;
use pyo3::types::PyType;
use vibrissa_io::IoError;

/// The Python class of an error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `vibrissa.InvalidInput` (also a `ValueError`): parameters, profiles, logs, files.
    InvalidInput,
    /// `vibrissa.SolverError` (also a `RuntimeError`): no solution meets the accuracy.
    SolverError,
    /// `vibrissa.NoContact` (a `SolverError`): the whisker never touches the obstacle.
    NoContact,
}

impl Kind {
    /// The class name in `vibrissa._errors`.
    pub fn class_name(self) -> &'static str {
        match self {
            Kind::InvalidInput => "InvalidInput",
            Kind::SolverError => "SolverError",
            Kind::NoContact => "NoContact",
        }
    }

    /// The class of an error (the command line's exit codes 2, 3, 1): its input variants
    /// are `InvalidInput`, a sweep that never touches is `NoContact`, every other solver
    /// failure `SolverError`.
    pub fn of(err: &IoError) -> Kind {
        match err {
            IoError::Io { .. }
            | IoError::Csv { .. }
            | IoError::Scene { .. }
            | IoError::InvalidArgument { .. }
            | IoError::Usage { .. }
            | IoError::Locked { .. }
            | IoError::ForeignFile { .. } => Kind::InvalidInput,
            _ if err.is_no_contact() => Kind::NoContact,
            IoError::Solver { .. } => Kind::SolverError,
        }
    }
}

/// A Python exception of class `kind` with `message`.
pub fn py_error(py: Python<'_>, kind: Kind, message: String) -> PyErr {
    let class = py
        .import("vibrissa._errors")
        .and_then(|m| m.getattr(kind.class_name()))
        .and_then(|c| c.cast_into::<PyType>().map_err(PyErr::from));
    match class {
        Ok(ty) => PyErr::from_type(ty, message),
        Err(e) => e,
    }
}

/// A library error as its Python exception.
pub fn to_py(py: Python<'_>, err: IoError) -> PyErr {
    py_error(py, Kind::of(&err), err.to_string())
}

/// A bad input named by its keyword (`invalid value `V` for `name`: reason`).
pub fn invalid(py: Python<'_>, name: &str, value: impl std::fmt::Display, reason: &str) -> PyErr {
    to_py(
        py,
        IoError::invalid_argument(name, value.to_string(), reason.to_string()),
    )
}

/// Runs `f` with the GIL released and turns both its error and a panic into a Python
/// exception (a panic is an internal error: `SolverError` with its message; it never
/// crosses into Python as a `PanicException`).
pub fn compute<T, F>(py: Python<'_>, f: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> Result<T, IoError> + Send,
{
    let outcome = py.detach(move || catch_unwind(AssertUnwindSafe(f)));
    match outcome {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(to_py(py, e)),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".to_string());
            Err(py_error(
                py,
                Kind::SolverError,
                format!("internal error (please report): {what}"),
            ))
        }
    }
}
