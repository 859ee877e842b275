//! `vibrissa.load_scene`: a scene RON file read and checked as the CLI reads it.

use std::path::PathBuf;

use pyo3::prelude::*;
use vibrissa_io::resolve::{profile_arg, LoadedScene};

use crate::convert::record;
use crate::errors::compute;

/// Reads the scene file `path` (checked as the CLI checks it); returns the library's
/// `SceneFile` as Python values (`units`, `whisker`, `loads`, `profile`, `sweep`,
/// `method`), a `points:FILE.csv` profile with its path made relative to the working
/// directory.
#[pyfunction]
pub fn load_scene(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyAny>> {
    let file = compute(py, move || {
        let loaded = LoadedScene::load(&path)?;
        let points = profile_arg(&None, Some(&loaded)).and_then(|p| p.points_path());
        let mut file = loaded.file;
        if let Some(p) = points {
            file.profile = Some(format!("points:{}", p.display()));
        }
        Ok(file)
    })?;
    record(py, &file)
}
