//! `vibrissa.reconstruct`: flow identification and contour reconstruction from a log of base
//! observables [ch. 6], as `vibrissa reconstruct` computes them (same resolution, settings
//! and messages), the log given as columns instead of a CSV file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use profile_recon::contour_error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vibrissa_io::csvio::Table;
use vibrissa_io::recon::{recon_model, reconstruct_log, ReconFlags, ReconOptions};
use vibrissa_io::recon_io::{recon_values, to_model_units_with, REQUIRED_COLUMNS};
use vibrissa_io::resolve::Value;
use vibrissa_io::summary::{ObstacleSummary, ReconSummary};
use vibrissa_io::units::{Quantity, UnitSystem};
use vibrissa_io::IoError;

use crate::convert::{record, with_columns};
use crate::errors::{compute, invalid};
use crate::params::{model_flags, number, string, units_scene, ProfileSpec};

/// Where the rows of a log given as columns are said to be in messages: `log row:N: ...`
/// names the 1-based row N.
pub const LOG_ORIGIN: &str = "log row";

/// A log given as columns (read by [`log_table`]) in the model's units, converted from the
/// scene's `units` (such a log has no units sidecar); returns its x0 column as given.
pub fn log_to_model_units(table: &mut Table, units: &UnitSystem) -> Result<Vec<f64>, IoError> {
    to_model_units_with(table, &BTreeMap::new(), units, Path::new(LOG_ORIGIN))
}

/// The library's values of a reconstruction from `spec` (`theta, a, b, k, q, alpha_deg,
/// noise, method, tolerance` (a number or `"none"`), `tol`).
pub fn recon_flags(spec: &Bound<'_, PyDict>) -> PyResult<ReconFlags> {
    let flags = model_flags(spec)?;
    Ok(ReconFlags {
        whisker: flags.whisker,
        q: flags.fluid.q,
        alpha_deg: flags.fluid.alpha_deg,
        noise: number(spec, "noise")?,
        method: string(spec, "method")?,
        tolerance: match string(spec, "tolerance") {
            Ok(t) => t.map(Value::Text),
            Err(_) => number(spec, "tolerance")?,
        },
        tol: number(spec, "tol")?,
    })
}

/// A log given as columns (`x0, Ax, Ay, MA, phi0` at least, in the scene's units) as the
/// table the CLI reads from a CSV file; row `i` (0-based) is "line" `i + 1`.
pub fn log_table(py: Python<'_>, log: &Bound<'_, PyDict>) -> PyResult<Table> {
    let mut numeric = BTreeMap::new();
    let mut rows = None;
    for name in REQUIRED_COLUMNS {
        let Some(col) = log.get_item(name)? else {
            return Err(invalid(
                py,
                "log",
                name,
                "missing required column (a log needs x0, Ax, Ay, MA and phi0)",
            ));
        };
        let v = crate::convert::vector(&col)
            .ok_or_else(|| invalid(py, "log", name, "the column must be a 1-D float64 array"))?;
        match rows {
            None => rows = Some(v.len()),
            Some(n) if n != v.len() => {
                return Err(invalid(
                    py,
                    "log",
                    name,
                    &format!(
                        "{} rows where x0 has {n}: the columns differ in length",
                        v.len()
                    ),
                ))
            }
            Some(_) => {}
        }
        numeric.insert(name.to_string(), v);
    }
    // the base pose of a log of any motion (issue 38), where the log has it
    for name in ["y0", "gamma", "k"] {
        let Some(col) = log.get_item(name)? else {
            continue;
        };
        let v = crate::convert::vector(&col)
            .ok_or_else(|| invalid(py, "log", name, "the column must be a 1-D float64 array"))?;
        if rows.is_some_and(|n| n != v.len()) {
            return Err(invalid(
                py,
                "log",
                name,
                &format!(
                    "{} rows where x0 has {}: the columns differ in length",
                    v.len(),
                    rows.unwrap_or(0)
                ),
            ));
        }
        numeric.insert(name.to_string(), v);
    }
    let n = rows.unwrap_or(0);
    if n < 2 {
        return Err(invalid(py, "log", n, "a log needs at least 2 rows"));
    }
    Ok(Table {
        path: PathBuf::from(LOG_ORIGIN),
        header: REQUIRED_COLUMNS.iter().map(|s| s.to_string()).collect(),
        numeric,
        text: BTreeMap::new(),
        lines: (1..=n).collect(),
        header_line: 0,
        delimiter: b',',
    })
}

/// Reconstructs the log `log` (a dict of columns) with the whisker of `spec`; returns
/// `{"columns": x0, x, y, s1, f, psi, sigma, residual, hypotheses (and error with a
/// profile), one entry per row of the log in its order (NaN before contact), "phase": [str],
/// "summary": the library's [`ReconSummary`] (q, alpha_deg, noise, ...)}` in the scene's
/// units.
#[pyfunction]
pub fn reconstruct<'py>(
    py: Python<'py>,
    log: &Bound<'py, PyDict>,
    spec: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let flags = recon_flags(spec)?;
    let file = units_scene(spec)?;
    let truth_spec = ProfileSpec::from_spec(spec, "profile")?;
    let mut table = log_table(py, log)?;
    // the pose columns as given (issue 38), appended to the result's columns
    let pose = vibrissa_io::recon_io::PoseColumns::of(&table);
    let (rec, units, x0_given, errors, method, obstacle) = compute(py, move || {
        let opts = ReconOptions::parse(&flags)?;
        let r = recon_model(&flags, file)?;
        let units = r.units();
        let truth = truth_spec.map(|p| p.parse(&units)).transpose()?;
        let x0_given = log_to_model_units(&mut table, &units)?;
        let rec = reconstruct_log(&flags, &opts, &r, &table)?;
        let errors = truth.as_ref().map(|p| contour_error(&rec.points, p));
        let obstacle = ObstacleSummary::of(&rec, truth.as_ref(), &units);
        Ok((rec, units, x0_given, errors, opts.method, obstacle))
    })?;
    let n = x0_given.len();
    let l = units.scale(Quantity::Length);
    let mut cols: Vec<Vec<f64>> = vec![vec![f64::NAN; n]; 10];
    cols[0].clone_from(&x0_given);
    let mut phase = vec!["none"; n];
    for (i, p) in rec.points.iter().enumerate() {
        let v = recon_values(p, &units, &x0_given);
        for (c, x) in v.iter().enumerate() {
            cols[c][p.row] = *x;
        }
        cols[6][p.row] = p.sigma * l;
        cols[7][p.row] = p.residual;
        cols[8][p.row] = p.alternatives as f64;
        if let Some(e) = &errors {
            cols[9][p.row] = e.get(i).copied().unwrap_or(f64::NAN) * l;
        }
        phase[p.row] = p.phase.label();
    }
    if errors.is_none() {
        cols.pop();
    }
    let names = [
        "x0",
        "x",
        "y",
        "s1",
        "f",
        "psi",
        "sigma",
        "residual",
        "hypotheses",
        "error",
    ];
    let mut columns: Vec<(&str, Vec<f64>)> = names.iter().copied().zip(cols).collect();
    columns.extend(pose.columns().iter().map(|(n, c)| (*n, c.clone())));
    let out = with_columns(py, columns)?;
    out.set_item("phase", phase)?;
    let summary = ReconSummary::of(&rec, method, n, &units);
    out.set_item("summary", record(py, &summary)?)?;
    if let Some(o) = obstacle {
        out.set_item("obstacle", record(py, &o)?)?;
    }
    Ok(out)
}
