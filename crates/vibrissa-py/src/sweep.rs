//! `vibrissa.sweep`: the whisker swept past an obstacle under the flow [ch. 5], as
//! `vibrissa sweep` computes it (same resolution, settings and messages), without files.

use contact_sim::{sweep as run_sweep, SweepSettings};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vibrissa_io::observables::ObservableRecord;
use vibrissa_io::outputs::output_scene;
use vibrissa_io::resolve::motion::{sweep_motion, MotionGiven, PathColumns};
use vibrissa_io::resolve::resolve_model;
use vibrissa_io::resolve::sweep::{
    check_sweep_loads, missing_profile, sweep_contact_law, sweep_points, sweep_settings_with,
    sweep_tol,
};
use vibrissa_io::resolve::Value;
use vibrissa_io::summary::SweepSummary;

use crate::convert::{record, record_dict, with_columns};
use crate::errors::compute;
use crate::params::{count, item, model_flags, number, string, units_scene, ProfileSpec};

/// Sweeps the whisker of `spec` past `spec["profile"]` (Coulomb friction `spec["mu"]`);
/// returns `{"columns": the `observables.csv` columns (numbers as arrays), "phase": [str],
/// "slip": [str], "summary": the library's
/// [`SweepSummary`] (that of `sweep --json`) with the profile, "scene": the `scene.ron` of
/// the sweep}`, in the scene's units.
#[pyfunction]
pub fn sweep<'py>(py: Python<'py>, spec: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyDict>> {
    let mut flags = model_flags(spec)?;
    // `tol` is the accuracy of the sweep's rows (`sweep --tol`), not a method's
    let tol_given = flags.method.tol.take();
    let file = units_scene(spec)?;
    let points_given = count(spec, "points")?;
    let mu_given = number(spec, "mu")?;
    let profile = ProfileSpec::from_spec(spec, "profile")?;
    let motion_given = motion_given(spec)?;
    let (r, res, points, law, arg, motion) = compute(py, move || {
        let profile = profile.ok_or_else(|| missing_profile(None))?;
        let points = sweep_points(points_given.as_ref(), None)?;
        let tol = sweep_tol(tol_given.as_ref(), None)?;
        let law = sweep_contact_law(mu_given.as_ref(), None)?;
        let r = resolve_model(&flags, file)?;
        check_sweep_loads(&r)?;
        let contour = profile.parse(&r.units())?;
        let arg = profile.arg();
        let motion = sweep_motion(&motion_given, None, &r.units())?;
        let settings = SweepSettings {
            motion: motion.motion.clone(),
            ..sweep_settings_with(points, tol, law)
        };
        let res = run_sweep(&r.scene.whisker, r.scene.loads.fluid, &contour, &settings)
            .map_err(|e| r.contact_culprit(e, &arg))?;
        Ok((r, res, points, law, arg, motion))
    })?;
    let units = r.units();
    let rows: Vec<ObservableRecord> = res
        .points
        .iter()
        .map(|p| ObservableRecord::of(p, &units))
        .collect();
    let col = |f: fn(&ObservableRecord) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
    let out = with_columns(
        py,
        vec![
            ("x0", col(|r| r.x0)),
            ("Ax", col(|r| r.ax)),
            ("Ay", col(|r| r.ay)),
            ("MA", col(|r| r.ma)),
            ("phi0", col(|r| r.phi0)),
            ("f", col(|r| r.f)),
            ("s1", col(|r| r.s1)),
            ("xc", col(|r| r.xc)),
            ("yc", col(|r| r.yc)),
            ("psi", col(|r| r.psi)),
            ("ft", col(|r| r.ft)),
            ("y0", col(|r| r.y0)),
            ("gamma", col(|r| r.gamma)),
        ],
    )?;
    let phases: Vec<&str> = rows.iter().map(|r| r.phase.label()).collect();
    out.set_item("phase", phases)?;
    let slips: Vec<&str> = rows.iter().map(|r| r.slip.label()).collect();
    out.set_item("slip", slips)?;
    if res.points.iter().any(|p| p.k.is_some()) {
        out.get_item("columns")?
            .ok_or_else(|| pyo3::exceptions::PyKeyError::new_err("columns"))?
            .set_item(
                "k",
                crate::convert::array(py, col(|r| r.k.unwrap_or(f64::NAN))),
            )?;
    }
    let summary = record_dict(
        py,
        &SweepSummary::of(&res, points, law, &units).with_motion(&motion.motion),
    )?;
    summary.set_item("profile", &arg.spec)?;
    out.set_item("summary", summary)?;
    let mut scene_file = output_scene(&r, Some(arg.spec), Some(points));
    scene_file.mu = law.mu();
    if motion.motion != contact_sim::BaseMotion::Translate {
        scene_file.motion = Some(motion.label.to_string());
    }
    if let Some((x0, y0, g0)) = motion.start {
        (scene_file.x0, scene_file.y0, scene_file.gamma_deg) = (Some(x0), Some(y0), Some(g0));
    }
    if let (Some(s), Some(acc)) = (scene_file.sweep.as_mut(), &res.accuracy) {
        s.tol = Some(acc.tol);
    }
    out.set_item("scene", record(py, &scene_file)?)?;
    Ok(out)
}

/// The base motion of `spec` (spec/python.md): `motion` (`"translate"`, `"rotate"`,
/// `"path"`), the start pose `x0`, `y0`, `gamma_deg` of a rotation, and `path`, a dict of the
/// columns `x0, y0, gamma_deg` and optionally `k` (1-D float sequences, the scene's units),
/// as the library's typed values (numbers as they are, no text in between).
fn motion_given(spec: &Bound<'_, PyDict>) -> PyResult<MotionGiven> {
    let path = match item(spec, "path")? {
        None => None,
        Some(v) => {
            let d = v.cast::<PyDict>().map_err(|_| {
                crate::errors::invalid(
                    spec.py(),
                    "path",
                    v.repr().map(|r| r.to_string()).unwrap_or_default(),
                    "a dict of the columns x0, y0, gamma_deg[, k]",
                )
            })?;
            let column = |name: &str| -> PyResult<Option<Vec<f64>>> {
                match item(d, name)? {
                    None => Ok(None),
                    Some(c) => crate::convert::vector(&c).map(Some).ok_or_else(|| {
                        crate::errors::invalid(
                            spec.py(),
                            "path",
                            name.to_string(),
                            "a column must be a 1-D sequence of numbers",
                        )
                    }),
                }
            };
            let need = |name: &str| -> PyResult<Vec<f64>> {
                column(name)?.ok_or_else(|| {
                    crate::errors::invalid(
                        spec.py(),
                        "path",
                        name.to_string(),
                        "missing column: a path has the columns x0, y0, gamma_deg[, k]",
                    )
                })
            };
            Some(PathColumns {
                x0: need("x0")?,
                y0: need("y0")?,
                gamma_deg: need("gamma_deg")?,
                k: column("k")?,
            })
        }
    };
    Ok(MotionGiven {
        motion: string(spec, "motion")?.map(Value::Text),
        x0: number(spec, "x0")?,
        y0: number(spec, "y0")?,
        gamma_deg: number(spec, "gamma_deg")?,
        path,
    })
}
