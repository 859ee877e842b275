//! `vibrissa.calibrate`: the whisker's own parameters fitted to logs of sweeps past known
//! contours, as `vibrissa calibrate` computes them (same resolution, settings, result and
//! messages), the logs given as columns instead of CSV files.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use vibrissa_io::calibration::{calib_model, fit_logs, CalibFlags, CalibrationReport, LogInput};

use crate::convert::record;
use crate::errors::{compute, invalid};
use crate::params::{model_flags, number, string, units_scene, ProfileSpec};
use crate::reconstruct::{log_table, log_to_model_units, LOG_ORIGIN};

/// Calibrates the whisker of `spec` (start values `theta, a, b, k`, `units`; `fit` a
/// comma-separated list; `starts`; `q` with `alpha_deg` to hold the flow fixed) on `logs`, a
/// list of `(columns, profile)` pairs (a dict of 1-D arrays `x0, Ax, Ay, MA, phi0` in the
/// scene's units and a profile string or `(x, y)` arrays); returns the library's
/// [`CalibrationReport`] (that of `vibrissa calibrate --json`: `parameters`, `whisker`,
/// `logs`, `rms_residual`, ...) as a dict.
#[pyfunction]
pub fn calibrate<'py>(
    py: Python<'py>,
    logs: &Bound<'py, PyList>,
    spec: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let model = model_flags(spec)?;
    let flags = CalibFlags {
        whisker: model.whisker,
        fluid: model.fluid,
        fit: string(spec, "fit")?,
        starts: number(spec, "starts")?,
    };
    let file = units_scene(spec)?;
    let mut raw = Vec::new();
    for (i, item) in logs.iter().enumerate() {
        let pair = item
            .cast_into::<PyTuple>()
            .ok()
            .filter(|t| t.len() == 2)
            .ok_or_else(|| invalid(py, "logs", i + 1, "each log must be a pair (log, profile)"))?;
        let columns = pair
            .get_item(0)?
            .cast_into::<PyDict>()
            .map_err(|_| invalid(py, "logs", i + 1, "a log must be a dict of columns"))?;
        let table = log_table(py, &columns)?;
        let holder = PyDict::new(py);
        holder.set_item("profile", pair.get_item(1)?)?;
        let profile = ProfileSpec::from_spec(&holder, "profile")?
            .ok_or_else(|| invalid(py, "profile", i + 1, "every log needs its known contour"))?;
        raw.push((table, profile));
    }
    let value = compute(py, move || {
        let r = calib_model(&flags, file)?;
        let units = r.units();
        let mut inputs = Vec::with_capacity(raw.len());
        for (i, (mut table, profile)) in raw.into_iter().enumerate() {
            let pose_given = vibrissa_io::recon_io::PoseColumns::of(&table);
            let x0_given = log_to_model_units(&mut table, &units)?;
            let parsed = profile.parse(&units)?;
            inputs.push(LogInput {
                arg: format!("log {}", i + 1),
                path: PathBuf::from(LOG_ORIGIN),
                table,
                x0_given,
                pose_given,
                profile: (profile.arg().spec, parsed),
            });
        }
        let (cal, _) = fit_logs(&inputs, &r, &flags, &|_| {})?;
        Ok(CalibrationReport::of(
            &cal,
            &inputs,
            &units,
            r.physical.as_ref(),
            None,
        ))
    })?;
    record(py, &value)
}
