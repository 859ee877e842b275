//! `vibrissa.reconstruct`: flow identification and contour reconstruction from a log of base
//! observables [ch. 6], as `vibrissa reconstruct` computes them (same resolution, settings
//! and messages), the log given as columns instead of a CSV file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use profile_recon::contour_error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vibrissa_io::csvio::Table;
use vibrissa_io::recon::{recon_model, ReconFlags, ReconOptions};
use vibrissa_io::recon_friction::{
    biased_warning, reconstruct_default_log, reconstruct_frictional_log, FrictionSummary, MuRequest,
};
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

/// `spec["mu"]` as `reconstruct --mu` reads it: None (absent: the CLI's default), the word
/// `"identify"`, or a number (written as the CLI would get it, parsed by [`MuRequest::parse`]
/// inside the computation so that a bad value raises the CLI's message).
fn mu_raw(spec: &Bound<'_, PyDict>) -> PyResult<Option<String>> {
    let Some(v) = crate::params::item(spec, "mu")? else {
        return Ok(None);
    };
    if let Ok(s) = v.extract::<String>() {
        return Ok(Some(s));
    }
    match v.extract::<f64>() {
        Ok(x) => Ok(Some(format!("{x}"))),
        Err(_) => Err(invalid(
            spec.py(),
            "mu",
            v.repr()?,
            "expected a number in [0, 10] or the word identify",
        )),
    }
}

/// The friction part of a reconstruction (issue 39), as `reconstruct --json` gives it:
/// `ft` and the slip state per point (by input row), `mu` and `friction` (JSON values), and
/// the warnings the CLI prints on stderr.
struct FrictionPart {
    ft: Vec<(usize, f64)>,
    slip: Vec<(usize, &'static str)>,
    friction: Result<FrictionSummary, String>,
    warnings: Vec<String>,
}

/// `friction` of a reconstruction that identified no mu (`--method thesis`, `--tol`, a
/// posed log, a failure), as the CLI's JSON has it.
#[derive(serde::Serialize)]
struct NotIdentified<'a> {
    identified: bool,
    reason: &'a str,
}

impl FrictionPart {
    /// The part of a frictional reconstruction `fr` (`ft` per point: `ft[i]` of point `i` of
    /// `rec`), rows numbered as the log's lines.
    fn of(
        fr: &profile_recon::FrictionalReconstruction,
        ft: Vec<(usize, f64)>,
        table: &Table,
        warnings: Vec<String>,
    ) -> Self {
        let s = FrictionSummary::of(fr, table);
        FrictionPart {
            ft,
            slip: fr
                .points
                .iter()
                .map(|p| {
                    let label = match p.slip {
                        contact_sim::SlipState::Slip => "slip",
                        contact_sim::SlipState::Stick => "stick",
                        _ => "none",
                    };
                    (p.row, label)
                })
                .collect(),
            friction: Ok(s),
            warnings,
        }
    }
}

/// Reconstructs the log `log` (a dict of columns) with the whisker of `spec`; returns
/// `{"columns": x0, x, y, s1, f, psi, sigma, residual, hypotheses, ft (and error with a
/// profile), one entry per row of the log in its order (NaN before contact), "phase": [str],
/// "slip": [str], "summary": the library's [`ReconSummary`] (q, alpha_deg, noise, ...),
/// "mu", "friction", "warnings"}` in the scene's units. `spec["mu"]` is `reconstruct --mu`
/// (None: its default, the frictionless points with mu identified beside them; `"identify"`
/// or a number: the frictional points), bit for bit the CLI's numbers.
#[pyfunction]
pub fn reconstruct<'py>(
    py: Python<'py>,
    log: &Bound<'py, PyDict>,
    spec: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let flags = recon_flags(spec)?;
    let file = units_scene(spec)?;
    let truth_spec = ProfileSpec::from_spec(spec, "profile")?;
    let mu = mu_raw(spec)?;
    let mut table = log_table(py, log)?;
    // the pose columns as given (issue 38), appended to the result's columns
    let pose = vibrissa_io::recon_io::PoseColumns::of(&table);
    let (rec, units, x0_given, errors, method, obstacle, fric) = compute(py, move || {
        let mu = mu.as_deref().map(MuRequest::parse).transpose()?;
        let opts = ReconOptions::parse(&flags)?;
        let r = recon_model(&flags, file)?;
        let units = r.units();
        let truth = truth_spec.map(|p| p.parse(&units)).transpose()?;
        let x0_given = log_to_model_units(&mut table, &units)?;
        let line = |row: usize| table.line_of(row).unwrap_or(row + 1);
        let (rec, fric) = match mu {
            Some(mu) => {
                let ans = reconstruct_frictional_log(&flags, &opts, &r, &table, mu)?;
                let mut warnings: Vec<String> = ans
                    .biased
                    .iter()
                    .map(|ev| biased_warning(ev, line(ev.row)))
                    .collect();
                if ans.frictional.violations > 0 {
                    warnings.push(format!(
                        "warning: {} rows break the given mu (their |ft| / fn beyond the cone, or sliding rows off its edge)",
                        ans.frictional.violations
                    ));
                }
                let ft = ans.rec.points.iter().map(|p| p.row).zip(ans.ft).collect();
                let part = FrictionPart::of(&ans.frictional, ft, &table, warnings);
                (ans.rec, part)
            }
            None => {
                let ans = reconstruct_default_log(&flags, &opts, &r, &table)?;
                let warnings: Vec<String> = ans
                    .biased
                    .iter()
                    .map(|ev| biased_warning(ev, line(ev.row)))
                    .collect();
                let part = match &ans.frictional {
                    Ok(fr) => {
                        let ft = fr.points.iter().map(|p| (p.row, p.ft)).collect();
                        FrictionPart::of(fr, ft, &table, warnings)
                    }
                    Err(reason) => FrictionPart {
                        ft: Vec::new(),
                        slip: Vec::new(),
                        friction: Err(reason.clone()),
                        warnings,
                    },
                };
                (ans.rec, part)
            }
        };
        let errors = truth.as_ref().map(|p| contour_error(&rec.points, p));
        let obstacle = ObstacleSummary::of(&rec, truth.as_ref(), &units);
        Ok((rec, units, x0_given, errors, opts.method, obstacle, fric))
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
    let mut ft = vec![f64::NAN; n];
    let fs = units.scale(Quantity::Force);
    for &(row, v) in &fric.ft {
        if let Some(c) = ft.get_mut(row) {
            *c = v * fs;
        }
    }
    let mut slip = vec!["none"; n];
    for &(row, s) in &fric.slip {
        if let Some(c) = slip.get_mut(row) {
            *c = s;
        }
    }
    let mut named: Vec<(&str, Vec<f64>)> = names.iter().copied().zip(cols).collect();
    named.push(("ft", ft));
    named.extend(pose.columns().iter().map(|(n, c)| (*n, c.clone())));
    let out = with_columns(py, named)?;
    out.set_item("phase", phase)?;
    out.set_item("slip", slip)?;
    match &fric.friction {
        Ok(s) => {
            out.set_item("mu", record(py, &s.mu)?)?;
            out.set_item("friction", record(py, s)?)?;
        }
        Err(reason) => {
            out.set_item("mu", py.None())?;
            let ni = NotIdentified {
                identified: false,
                reason,
            };
            out.set_item("friction", record(py, &ni)?)?;
        }
    }
    out.set_item("warnings", fric.warnings)?;
    let summary = ReconSummary::of(&rec, method, n, &units);
    out.set_item("summary", record(py, &summary)?)?;
    if let Some(o) = obstacle {
        out.set_item("obstacle", record(py, &o)?)?;
    }
    Ok(out)
}
