//! `vibrissa.calibrate`: the whisker's own parameters fitted to logs of sweeps past known
//! contours, as `vibrissa calibrate` computes them (same resolution, settings, result and
//! messages), the logs given as columns instead of CSV files.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use vibrissa_cli::cli::CalibrateArgs;
use vibrissa_cli::commands::calibrate::{fit_inputs, json_of, LogInput};
use vibrissa_cli::resolve::{resolve_model, ModelFlags};

use crate::convert::json;
use crate::errors::{compute, invalid};
use crate::params::{model_flags, number, string, units_scene, ProfileSpec};
use crate::reconstruct::{log_table, log_to_model_units, LOG_ORIGIN};

/// Calibrates the whisker of `spec` (start values `theta, a, b, k`, `units`; `fit` a
/// comma-separated list; `starts`; `q` with `alpha_deg` to hold the flow fixed) on `logs`, a
/// list of `(columns, profile)` pairs (a dict of 1-D arrays `x0, Ax, Ay, MA, phi0` in the
/// scene's units and a profile string or `(x, y)` arrays); returns the `--json` object of
/// `vibrissa calibrate` (`parameters`, `whisker`, `logs`, `rms_residual`, ...).
#[pyfunction]
pub fn calibrate<'py>(
    py: Python<'py>,
    logs: &Bound<'py, PyList>,
    spec: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let flags = model_flags(spec)?;
    let args = CalibrateArgs {
        logs: Vec::new(),
        scene: None,
        whisker: flags.whisker.clone(),
        profile: None,
        fit: string(spec, "fit")?,
        starts: number(spec, "starts")?,
        advise: Vec::new(),
        fluid: flags.fluid.clone(),
        noise: None,
        points: None,
        json: true,
        out: None,
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
        let model = ModelFlags {
            whisker: (&args.whisker).into(),
            fluid: (&args.fluid).into(),
            ..ModelFlags::default()
        };
        let r = resolve_model(&model, file)?;
        let units = r.units();
        let mut inputs = Vec::with_capacity(raw.len());
        for (i, (mut table, profile)) in raw.into_iter().enumerate() {
            let x0_given = log_to_model_units(&mut table, &units)?;
            let parsed = profile.parse(&units)?;
            inputs.push(LogInput {
                arg: format!("log {}", i + 1),
                path: PathBuf::from(LOG_ORIGIN),
                table,
                x0_given,
                profile: (profile.arg().spec, parsed),
            });
        }
        let (cal, _) = fit_inputs(&inputs, &r, &args)?;
        Ok(json_of(&cal, &inputs, &units, r.physical.as_ref(), None))
    })?;
    json(py, &value)
}
