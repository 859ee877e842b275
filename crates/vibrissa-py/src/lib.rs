//! `vibrissa._core`: the native part of the `vibrissa` Python package (PyO3, built by
//! maturin; contract: `shared/spec/python.md`).
//!
//! The Python layer (`python/vibrissa/`) normalises the keyword arguments into a `spec` dict
//! and wraps the dicts returned here into result classes. Everything numerical goes through
//! the library the `vibrissa` command line prints (`vibrissa-io` on the model crates; no
//! command-line crate, no clap), so that a scene gives the same numbers and a bad input the
//! same one-line message:
//!
//! - [`params`]: a `spec` dict -> the library's typed values (floats as floats) and the
//!   scene that carries the units;
//! - [`errors`]: the library's errors -> `vibrissa.InvalidInput`, `SolverError`,
//!   `NoContact`, and the guard that keeps panics out of Python;
//! - [`convert`]: numpy arrays to and from Python, the library's serialisable records
//!   (summaries, scenes) as dicts;
//! - [`solve`], [`sweep`], [`reconstruct`], [`calibrate`], [`stream`], [`scene`]: the functions.
//!
//! Every computation runs with the GIL released (`Python::detach`), so threads run in
//! parallel.

use pyo3::prelude::*;

pub mod calibrate;
pub mod convert;
pub mod errors;
pub mod params;
pub mod reconstruct;
pub mod scene;
pub mod solve;
pub mod stream;
pub mod sweep;

/// The native part of `vibrissa`: `solve`, `sweep`, `reconstruct`, `load_scene` and
/// `Streamer` on normalised `spec` dicts (see the Python package for the documented API).
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct::reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate::calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_class::<stream::Streamer>()?;
    Ok(())
}
