//! A normalised `spec` dict (built by the Python layer from the keyword arguments) turned
//! into the library's typed values (`vibrissa_io`): the model's values over a scene
//! ([`ModelFlags`] of [`Value::Number`]s: each float reaches the model as is), the scene
//! that carries the units (a [`SceneFile`] built in memory), the profile.
//!
//! A value the model refuses is reported as the command line reports the same value typed
//! as a flag (`invalid value `-1.0` for `--theta`: ...`), the number written in Rust's
//! shortest round-trip form for the message only.

use std::path::PathBuf;

use beam_model::Preset;
use contact_sim::{ContactError, Profile};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use vibrissa_io::resolve::{LoadedScene, ModelFlags, ProfileArg, Value};
use vibrissa_io::scene_file::{LoadKind, SceneFile, Units, WhiskerSpec};
use vibrissa_io::units::{Quantity, UnitSystem};
use vibrissa_io::IoError;

use crate::errors::invalid;

/// The entry `key` of `spec`, `None` if absent or `None`.
pub fn item<'py>(spec: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    Ok(spec.get_item(key)?.filter(|v| !v.is_none()))
}

/// A number of `spec`, if given.
pub fn number(spec: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<Value>> {
    Ok(float(spec, key)?.map(Value::Number))
}

/// A float of `spec`, if given.
pub fn float(spec: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<f64>> {
    match item(spec, key)? {
        None => Ok(None),
        Some(v) => match v.extract::<f64>() {
            Ok(x) => Ok(Some(x)),
            Err(_) => Err(invalid(spec.py(), key, v.repr()?, "not a number")),
        },
    }
}

/// A string of `spec`, if given.
pub fn string(spec: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<String>> {
    match item(spec, key)? {
        None => Ok(None),
        Some(v) => match v.extract::<String>() {
            Ok(s) => Ok(Some(s)),
            Err(_) => Err(invalid(spec.py(), key, v.repr()?, "not a string")),
        },
    }
}

/// A count of `spec`, if given.
pub fn count(spec: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<Value>> {
    match item(spec, key)? {
        None => Ok(None),
        Some(v) => match v.extract::<i64>() {
            Ok(n) => Ok(Some(Value::Integer(n))),
            Err(_) => Err(invalid(
                spec.py(),
                key,
                v.repr()?,
                "not a non-negative integer",
            )),
        },
    }
}

/// The whisker, load and method values of `spec` (`theta, a, b, k, f, beta_deg, load, q,
/// alpha_deg, method, n, tol`); the method's name is checked where the model's methods
/// are named (`beam_model::Method::from_name`, one place for every front end).
pub fn model_flags(spec: &Bound<'_, PyDict>) -> PyResult<ModelFlags> {
    let mut flags = ModelFlags::default();
    flags.whisker.theta = number(spec, "theta")?;
    flags.whisker.a = number(spec, "a")?;
    flags.whisker.b = number(spec, "b")?;
    flags.whisker.k = number(spec, "k")?;
    flags.tip.f = number(spec, "f")?;
    flags.tip.beta_deg = number(spec, "beta_deg")?;
    flags.tip.load = match string(spec, "load")?.as_deref().map(str::trim) {
        None => None,
        Some(s) if s.eq_ignore_ascii_case("dp") => Some(LoadKind::Dp),
        Some(s) if s.eq_ignore_ascii_case("ap") => Some(LoadKind::Ap),
        Some(other) => {
            return Err(invalid(
                spec.py(),
                "--load",
                other,
                "expected dp (direction-preserving) or ap (angle-preserving)",
            ))
        }
    };
    flags.fluid.q = number(spec, "q")?;
    flags.fluid.alpha_deg = number(spec, "alpha_deg")?;
    flags.method.method = string(spec, "method")?;
    flags.method.n = count(spec, "n")?;
    flags.method.tol = number(spec, "tol")?;
    Ok(flags)
}

/// The scene file that carries `spec["units"]`: `None` for dimensionless values, else a
/// dict `{preset, length_mm, base_diameter_mm, youngs_modulus_gpa}` (a preset of Table 2.2
/// and/or explicit values), as a scene file's `units: Physical(...)` gives them.
pub fn units_scene(spec: &Bound<'_, PyDict>) -> PyResult<Option<LoadedScene>> {
    let py = spec.py();
    let Some(units) = item(spec, "units")? else {
        return Ok(None);
    };
    let Ok(units) = units.cast_into::<PyDict>() else {
        return Err(invalid(
            py,
            "units",
            "?",
            "expected None, a preset name (beta, gamma, A1, E2) or a dict",
        ));
    };
    let preset = string(&units, "preset")?;
    if let Some(name) = &preset {
        if Preset::from_name(name.trim()).is_none() {
            return Err(invalid(
                py,
                "units",
                name,
                "unknown whisker preset: expected beta, gamma, A1 or E2",
            ));
        }
    }
    let mut file = SceneFile::with_whisker(WhiskerSpec {
        theta: 1.0,
        a: 0.0,
        b: 0.0,
        k: None,
    });
    file.units = Units::Physical {
        preset,
        length_mm: float(&units, "length_mm")?,
        base_diameter_mm: float(&units, "base_diameter_mm")?,
        youngs_modulus_gpa: float(&units, "youngs_modulus_gpa")?,
    };
    // a scene built in memory: no text (a message names the field, at line 1)
    Ok(Some(LoadedScene {
        file,
        text: String::new(),
        path: PathBuf::from("<units>"),
    }))
}

/// The spec a tabulated profile given as arrays is named by in messages.
pub const ARRAY_PROFILE: &str = "points:(x, y) arrays";

/// An obstacle contour from `spec["profile"]`: a CLI profile string, or a pair of 1-D
/// arrays `(x, y)` in the scene's units.
pub enum ProfileSpec {
    /// A profile string (`g1`, `circle:0,1.5,0.6`, `points:FILE.csv`).
    Text(String),
    /// A tabulated contour in the scene's units.
    Table(Vec<f64>, Vec<f64>),
}

impl ProfileSpec {
    /// The profile of `spec[key]`, if given.
    pub fn from_spec(spec: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<Self>> {
        let py = spec.py();
        let Some(v) = item(spec, key)? else {
            return Ok(None);
        };
        if let Ok(s) = v.extract::<String>() {
            return Ok(Some(ProfileSpec::Text(s)));
        }
        let pair = v.cast_into::<PyTuple>().ok().filter(|t| t.len() == 2);
        let Some(pair) = pair else {
            return Err(invalid(
                py,
                "profile",
                "?",
                "expected a profile string (g1, circle:xc,yc,r, points:FILE.csv, ...) or a \
                 pair of 1-D arrays (x, y)",
            ));
        };
        let column = |i: usize| -> PyResult<Vec<f64>> {
            crate::convert::vector(&pair.get_item(i)?).ok_or_else(|| {
                invalid(
                    py,
                    "profile",
                    ARRAY_PROFILE,
                    "x and y must be 1-D sequences of numbers",
                )
            })
        };
        Ok(Some(ProfileSpec::Table(column(0)?, column(1)?)))
    }

    /// The profile argument the CLI's messages name.
    pub fn arg(&self) -> ProfileArg {
        let spec = match self {
            ProfileSpec::Text(s) => s.clone(),
            ProfileSpec::Table(..) => ARRAY_PROFILE.to_string(),
        };
        ProfileArg { spec, file: None }
    }

    /// The dimensionless contour in the unit system `units`.
    pub fn parse(&self, units: &UnitSystem) -> Result<Profile, IoError> {
        match self {
            ProfileSpec::Text(_) => self.arg().parse(units),
            ProfileSpec::Table(x, y) => {
                let l = 1.0 / units.scale(Quantity::Length);
                let (x, y) = (
                    x.iter().map(|v| v * l).collect(),
                    y.iter().map(|v| v * l).collect(),
                );
                Profile::points(x, y).map_err(|e| match e {
                    ContactError::ProfileSpec { reason, .. } => self.arg().error(reason),
                    other => self.arg().error(other.to_string()),
                })
            }
        }
    }
}
