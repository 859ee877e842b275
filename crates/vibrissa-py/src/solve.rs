//! `vibrissa.solve`: one configuration, as `vibrissa solve` computes it.

use beam_model::solve as solve_scene;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vibrissa_io::resolve::resolve_model;
use vibrissa_io::summary::SolveSummary;
use vibrissa_io::units::Quantity;

use crate::convert::{record, with_columns};
use crate::errors::compute;
use crate::params::{model_flags, units_scene};

/// Solves the whisker of `spec` under its loads [3.27]; returns `{"columns": {s, x, y, phi,
/// kappa, m}, "tip", "base", "stats", "scene", "units"}` with lengths, forces and moments in
/// the scene's units (mm, N, N mm for a physical scene), as `elastica.csv` holds them, and
/// `"load_path"` (`{"folds": [{lambda, phi1, phi0}], "arrival", "other_equilibria",
/// "steps"}`) where the load path from zero folds; `stats`, `scene`, `load_path` are the
/// library's [`SolveSummary`] (that of `solve --json`).
#[pyfunction]
pub fn solve<'py>(py: Python<'py>, spec: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyDict>> {
    let flags = model_flags(spec)?;
    let file = units_scene(spec)?;
    let (r, sol) = compute(py, move || {
        let r = resolve_model(&flags, file)?;
        let sol = solve_scene(&r.scene, &r.method).map_err(|e| r.culprit(&e))?;
        Ok((r, sol))
    })?;
    let units = r.units();
    let (l, f, m, k) = (
        units.scale(Quantity::Length),
        units.scale(Quantity::Force),
        units.scale(Quantity::Moment),
        units.scale(Quantity::Curvature),
    );
    let summary = SolveSummary::of(&r, &sol);
    let e = sol.elastica;
    let scaled = |v: Vec<f64>, s: f64| v.into_iter().map(|x| x * s).collect::<Vec<_>>();
    let out = with_columns(
        py,
        vec![
            ("s", scaled(e.s, l)),
            ("x", scaled(e.x, l)),
            ("y", scaled(e.y, l)),
            ("phi", e.phi),
            ("kappa", scaled(e.kappa, k)),
            ("m", scaled(e.m, m)),
        ],
    )?;
    let tip = PyDict::new(py);
    tip.set_item("x", sol.tip.x * l)?;
    tip.set_item("y", sol.tip.y * l)?;
    tip.set_item("phi", sol.tip.phi)?;
    out.set_item("tip", tip)?;
    let base = PyDict::new(py);
    base.set_item("Ax", sol.base.ax * f)?;
    base.set_item("Ay", sol.base.ay * f)?;
    base.set_item("MA", sol.base.ma * m)?;
    base.set_item("phi0", sol.base.phi0)?;
    out.set_item("base", base)?;
    out.set_item("stats", record(py, &summary.stats)?)?;
    out.set_item("scene", record(py, &summary.scene)?)?;
    out.set_item("units", summary.units)?;
    out.set_item("method", summary.method)?;
    out.set_item("n", summary.n)?;
    // where the load path from zero folds: its folds and the other equilibria at full load
    if let Some(path) = &summary.load_path {
        out.set_item("load_path", record(py, path)?)?;
    }
    out.set_item("length_unit", units.unit(Quantity::Length))?;
    out.set_item("force_unit", units.unit(Quantity::Force))?;
    out.set_item("moment_unit", units.unit(Quantity::Moment))?;
    Ok(out)
}
