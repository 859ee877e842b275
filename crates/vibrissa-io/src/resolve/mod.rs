//! Turning a scene file and command-line flags into the model's values.
//!
//! Every parameter remembers where it came from (a flag, the scene file, the default), so
//! that a value the model refuses is reported against its culprit: the flag with the value
//! as typed, or the scene file with the line of the field.
//!
//! Physical units (`units: Physical(...)` in a scene file) apply to the scene's values and to
//! the flags that override them: `f` in N, `q` in N/m, `k` in N m/rad, `a` in 1/m^2 and `b`
//! in 1/m (kappa0 in 1/m with s in m); `theta` and the angles are unit free. They are
//! converted with [3.16-3.19] (`beam_model::PhysicalWhisker`).
//!
//! The obstacle (`--profile`, the scene's `profile`, a points file) is resolved in
//! [`profile`].

use std::path::{Path, PathBuf};

use beam_model::{
    LoadKind, Loads, Method, ModelError, PhysicalWhisker, Preset, Scene, Support, TipForce, Whisker,
};
use contact_sim::ContactError;

use crate::error::IoError;
use crate::scene_file::{self, locate_field, SceneFile, Units};
use crate::units::UnitSystem;

pub mod flags;
pub mod motion;
pub mod profile;
pub mod sweep;

pub use flags::{FluidFlags, MethodFlags, ModelFlags, TipFlags, Value, WhiskerFlags};

pub use profile::{profile_arg, read_points_file, ProfileArg};

/// A scene file as read: its parsed value, its text (for line numbers) and its path.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// The parsed scene.
    pub file: SceneFile,
    /// The file's text.
    pub text: String,
    /// The file's path.
    pub path: PathBuf,
}

impl LoadedScene {
    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Self, IoError> {
        let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
        let file = SceneFile::parse(&text, path)?;
        Ok(LoadedScene {
            file,
            text,
            path: path.to_path_buf(),
        })
    }

    /// Reads the optional scene file.
    pub fn load_opt(path: Option<&Path>) -> Result<Option<Self>, IoError> {
        path.map(Self::load).transpose()
    }

    /// A [`IoError::Scene`] at the field `field` (dotted path) of this file.
    pub fn error_at(&self, field: &str, reason: String) -> IoError {
        let segments: Vec<&str> = field.split('.').collect();
        let (line, column) = (1..=segments.len())
            .rev()
            .find_map(|n| locate_field(&self.text, &segments[..n]))
            .unwrap_or((1, 1));
        IoError::Scene {
            path: self.path.clone(),
            line,
            column,
            field: Some(field.to_string()),
            reason,
        }
    }
}

/// Where a value came from.
#[derive(Debug, Clone, PartialEq)]
pub enum Origin {
    /// The built-in default.
    Default,
    /// A command-line flag, with the text as typed.
    Flag {
        /// The flag (`--theta`).
        flag: &'static str,
        /// The value as typed.
        raw: String,
    },
    /// The scene file, at the dotted field.
    Scene(&'static str),
}

/// A value as given (in the scene's units) with its origin.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// The value as given.
    pub value: f64,
    /// Where it came from.
    pub origin: Origin,
}

impl Param {
    fn default(value: f64) -> Self {
        Param {
            value,
            origin: Origin::Default,
        }
    }
}

/// Parses a number typed for `flag`.
pub fn parse_number(flag: &'static str, raw: &str) -> Result<f64, IoError> {
    raw.trim()
        .parse::<f64>()
        .map_err(|_| IoError::invalid_argument(flag, raw, "not a number"))
}

/// Parses a count typed for `flag`, at least `min`.
pub fn parse_count(flag: &'static str, raw: &str, min: usize) -> Result<usize, IoError> {
    let n = parse_count_unbounded(flag, raw, min)?;
    if n > MAX_COUNT {
        return Err(IoError::invalid_argument(
            flag,
            raw,
            format!("must be at most {MAX_COUNT} (the memory and time of one run are bounded)"),
        ));
    }
    Ok(n)
}

/// Largest count any flag accepts (grid intervals, contact points): bounds memory and run
/// time.
pub const MAX_COUNT: usize = 100_000;

fn parse_count_unbounded(flag: &'static str, raw: &str, min: usize) -> Result<usize, IoError> {
    let n = raw
        .trim()
        .parse::<usize>()
        .map_err(|_| IoError::invalid_argument(flag, raw, "not a non-negative integer"))?;
    if n < min {
        return Err(IoError::invalid_argument(
            flag,
            raw,
            format!("must be at least {min}"),
        ));
    }
    Ok(n)
}

/// A parameter from a flag, else the scene, else the default.
fn param(
    flag: &'static str,
    raw: &Option<Value>,
    scene: Option<(&'static str, f64)>,
    default: f64,
) -> Result<Param, IoError> {
    if let Some(raw) = raw {
        return Ok(Param {
            value: raw.number(flag)?,
            origin: Origin::Flag {
                flag,
                raw: raw.raw(),
            },
        });
    }
    Ok(match scene {
        Some((field, value)) => Param {
            value,
            origin: Origin::Scene(field),
        },
        None => Param::default(default),
    })
}

/// The whisker and load values as given, with their origins.
#[derive(Debug, Clone, PartialEq)]
pub struct Given {
    /// Conicity.
    pub theta: Param,
    /// Pre-curvature slope.
    pub a: Param,
    /// Pre-curvature offset.
    pub b: Param,
    /// Base stiffness (inf = rigid).
    pub k: Param,
    /// Tip force.
    pub f: Param,
    /// Tip force angle (degrees).
    pub beta_deg: Param,
    /// Tip force kind.
    pub load: LoadKind,
    /// Fluid load.
    pub q: Param,
    /// Fluid load angle (degrees).
    pub alpha_deg: Param,
    /// Method intervals.
    pub n: Option<Param>,
}

/// A resolved configuration: the dimensionless scene, the method and the unit system.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// The dimensionless scene (validated).
    pub scene: Scene,
    /// The method (validated name and intervals).
    pub method: Method,
    /// The physical whisker when the scene is in physical units.
    pub physical: Option<PhysicalWhisker>,
    /// The values as given.
    pub given: Given,
    /// The scene file, if any.
    pub file: Option<LoadedScene>,
}

/// The physical whisker of a scene file's units, if physical.
pub fn physical_whisker(file: &LoadedScene) -> Result<Option<PhysicalWhisker>, IoError> {
    let Units::Physical {
        preset,
        length_mm,
        base_diameter_mm,
        youngs_modulus_gpa,
    } = &file.file.units
    else {
        return Ok(None);
    };
    let base = match preset {
        Some(name) => Some(
            Preset::from_name(name.trim())
                .ok_or_else(|| {
                    file.error_at(
                        "units.preset",
                        format!("unknown whisker preset `{name}`: expected beta, gamma, A1 or E2"),
                    )
                })?
                .whisker(),
        ),
        None => None,
    };
    let pick = |v: &Option<f64>, scale: f64, from: Option<f64>| v.map(|x| x * scale).or(from);
    let length = pick(length_mm, 1e-3, base.map(|b| b.length));
    let diameter = pick(base_diameter_mm, 1e-3, base.map(|b| b.base_diameter));
    let modulus = pick(youngs_modulus_gpa, 1e9, base.map(|b| b.youngs_modulus));
    match (length, diameter, modulus) {
        (Some(l), Some(d), Some(e)) => {
            let given = [
                ("units.length_mm", *length_mm, "mm", 50.0),
                ("units.base_diameter_mm", *base_diameter_mm, "mm", 0.1),
                ("units.youngs_modulus_gpa", *youngs_modulus_gpa, "GPa", 3.0),
            ];
            let w = PhysicalWhisker::new(l, d, e)
                .map_err(|err| unusable_units(file, &given, err.to_string()))?;
            let ei = w.bending_stiffness();
            let scales = [
                ("E I", ei, "N m^2"),
                ("E I / L^2", ei / (l * l), "N"),
                ("E I / L^3", ei / (l * l * l), "N/m"),
                ("1 / L", 1.0 / l, "1/m"),
            ];
            if let Some((name, v, unit)) = scales
                .iter()
                .find(|(_, v, _)| !(v.is_finite() && *v > 0.0 && v.recip().is_finite()))
            {
                return Err(unusable_units(
                    file,
                    &given,
                    format!(
                        "the model's unit {name} = {v:e} {unit} is not a usable scale: forces, \
                         loads, moments and curvatures cannot be converted (a real whisker is \
                         10-100 mm long, 0.05-0.5 mm thick, E 1-10 GPa)"
                    ),
                ));
            }
            Ok(Some(w))
        }
        _ => Err(file.error_at(
            "units",
            "length_mm, base_diameter_mm and youngs_modulus_gpa are required without a preset"
                .to_string(),
        )),
    }
}

/// An error of a physical unit system, at the given dimension whose value lies farthest (in
/// decades) from a real whisker's (`typical`, in its own unit), named with its value and
/// unit; at `units` if none was given (a preset's values).
fn unusable_units(
    file: &LoadedScene,
    given: &[(&str, Option<f64>, &str, f64); 3],
    reason: String,
) -> IoError {
    let culprit = given
        .iter()
        .filter_map(|(field, v, unit, typical)| {
            let v = (*v)?;
            let decades = if v > 0.0 && v.is_finite() {
                (v / typical).log10().abs()
            } else {
                f64::INFINITY
            };
            Some((decades, *field, v, *unit))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    match culprit {
        Some((_, field, v, unit)) => {
            let v = if (1e-4..1e6).contains(&v.abs()) {
                format!("{v}")
            } else {
                format!("{v:e}")
            };
            file.error_at(field, format!("{v} {unit}: {reason}"))
        }
        None => file.error_at("units", reason),
    }
}

/// Whisker values from flags over the scene file.
fn given_whisker(
    w: &WhiskerFlags,
    file: Option<&LoadedScene>,
) -> Result<(Param, Param, Param, Param), IoError> {
    let ws = file.map(|f| &f.file.whisker);
    let theta = param(
        "--theta",
        &w.theta,
        ws.map(|w| ("whisker.theta", w.theta)),
        1.0,
    )?;
    let a = param("--a", &w.a, ws.map(|w| ("whisker.a", w.a)), 0.0)?;
    let b = param("--b", &w.b, ws.map(|w| ("whisker.b", w.b)), 0.0)?;
    let k = param(
        "--k",
        &w.k,
        ws.and_then(|w| w.k).map(|k| ("whisker.k", k)),
        f64::INFINITY,
    )?;
    Ok((theta, a, b, k))
}

/// Resolves the whisker, loads and method of `solve` and `sweep`.
pub fn resolve_model(flags: &ModelFlags, file: Option<LoadedScene>) -> Result<Resolved, IoError> {
    let ModelFlags {
        whisker,
        tip,
        fluid,
        method,
    } = flags;
    resolve_parts(whisker, tip, fluid, method, file)
}

fn resolve_parts(
    w: &WhiskerFlags,
    tip: &TipFlags,
    fluid: &FluidFlags,
    m: &MethodFlags,
    file: Option<LoadedScene>,
) -> Result<Resolved, IoError> {
    let f_ref = file.as_ref();
    let physical = match f_ref {
        Some(f) => physical_whisker(f)?,
        None => None,
    };
    let (theta, a, b, k) = given_whisker(w, f_ref)?;
    let ls = f_ref.map(|f| &f.file.loads);
    let f = param("--f", &tip.f, ls.map(|l| ("loads.f", l.f)), 0.0)?;
    let beta_deg = param(
        "--beta-deg",
        &tip.beta_deg,
        ls.map(|l| ("loads.beta_deg", l.beta_deg)),
        0.0,
    )?;
    let q = param("--q", &fluid.q, ls.map(|l| ("loads.q", l.q)), 0.0)?;
    let alpha_deg = param(
        "--alpha-deg",
        &fluid.alpha_deg,
        ls.map(|l| ("loads.alpha_deg", l.alpha_deg)),
        0.0,
    )?;
    let load = match (tip.load, ls.map(|l| l.load)) {
        (Some(scene_file::LoadKind::Ap), _) | (None, Some(scene_file::LoadKind::Ap)) => {
            LoadKind::Ap
        }
        _ => LoadKind::Dp,
    };
    let n = given_n(m, f_ref)?;
    let given = Given {
        theta,
        a,
        b,
        k,
        f,
        beta_deg,
        load,
        q,
        alpha_deg,
        n,
    };
    let method = resolve_method(m, f_ref, &given)?;
    let mut resolved = Resolved {
        scene: Scene::default(),
        method,
        physical,
        given,
        file,
    };
    if method.intervals() < 4 {
        return Err(resolved.culprit(&ModelError::InvalidParameter {
            name: "n",
            value: method.intervals() as f64,
            reason: "at least 4 grid intervals are needed",
        }));
    }
    resolved.scene = resolved.build_scene()?;
    Ok(resolved)
}

/// The grid size: `--n` over the scene's `method.n`.
fn given_n(m: &MethodFlags, f_ref: Option<&LoadedScene>) -> Result<Option<Param>, IoError> {
    Ok(match (&m.n, f_ref.and_then(|f| f.file.method.n)) {
        (Some(raw), _) => Some(Param {
            value: raw.count("--n", 0)? as f64,
            origin: Origin::Flag {
                flag: "--n",
                raw: raw.raw(),
            },
        }),
        (None, Some(n)) => Some(Param {
            value: n as f64,
            origin: Origin::Scene("method.n"),
        }),
        (None, None) => None,
    })
}

/// The method: `--method` (or `auto` for `--tol`) over the scene's, with the grid size of
/// `given` and the accuracy asked for.
fn resolve_method(
    m: &MethodFlags,
    f_ref: Option<&LoadedScene>,
    given: &Given,
) -> Result<Method, IoError> {
    let (name, name_origin) = match (&m.method, f_ref, &m.tol) {
        (Some(name), _, _) => (name.clone(), Some("--method")),
        // --tol asks for the automatic choice.
        (None, _, Some(_)) => ("auto".to_string(), Some("--method")),
        (None, Some(f), None) => (f.file.method.name.clone(), None),
        (None, None, None) => ("accurate".to_string(), Some("--method")),
    };
    let n_value = given.n.as_ref().map(|p| p.value as usize);
    let mut method = Method::from_name(name.trim(), n_value).ok_or_else(|| {
        let reason =
            "unknown method: expected accurate, auto, rk4, fdm, fdm-richardson, multiple-shooting or collocation".to_string();
        match (name_origin, f_ref) {
            (None, Some(f)) => f.error_at("method.name", format!("{reason}, got `{name}`")),
            _ => IoError::invalid_argument("--method", name.clone(), reason),
        }
    })?;
    let tol = match (&m.tol, f_ref.and_then(|f| f.file.method.tol)) {
        (Some(raw), _) => Some((raw.number("--tol")?, "--tol")),
        (None, Some(t)) if name_origin.is_none() => Some((t, "method.tol")),
        _ => None,
    };
    if let Some((t, origin)) = tol {
        match &mut method {
            Method::Auto { tol, .. } | Method::Collocation { tol, .. } => {
                if !(1e-12..=1e-2).contains(&t) {
                    return Err(IoError::invalid_argument(
                        origin,
                        format!("{t:e}"),
                        "the accuracy asked for must be in [1e-12, 1e-2]".to_string(),
                    ));
                }
                *tol = t;
            }
            other => {
                return Err(IoError::invalid_argument(
                    origin,
                    format!("{t:e}"),
                    format!(
                        "--tol asks for the automatic choice (--method auto) or collocation, not {}",
                        other.name()
                    ),
                ));
            }
        }
    }
    Ok(method)
}

impl Resolved {
    /// The dimensionless scene from the given values, validated.
    fn build_scene(&self) -> Result<Scene, IoError> {
        let g = &self.given;
        let (mut a, mut b, mut f, mut q, mut k) =
            (g.a.value, g.b.value, g.f.value, g.q.value, g.k.value);
        if let Some(p) = &self.physical {
            (a, b) = p.dimensionless_curvature(a, b);
            f = p.dimensionless_force(f);
            q = p.dimensionless_line_load(q);
            k = p.dimensionless_stiffness(k);
        }
        let support = Support::from_stiffness(k).map_err(|e| self.culprit(&e))?;
        let whisker = Whisker {
            theta: g.theta.value,
            a,
            b,
            support,
        };
        let tip = TipForce {
            f,
            beta: degrees_to_radians(g.beta_deg.value),
            kind: g.load,
        };
        let scene = Scene::new(
            whisker,
            Loads::combined(tip, q, degrees_to_radians(g.alpha_deg.value)),
        );
        scene.validate().map_err(|e| self.culprit(&e))?;
        Ok(scene)
    }

    /// The given parameter the model calls `name`.
    fn param_named(&self, name: &str) -> Option<(&Param, &'static str)> {
        let g = &self.given;
        Some(match name {
            "theta" => (&g.theta, "whisker.theta"),
            "A" | "a" => (&g.a, "whisker.a"),
            "B" | "b" => (&g.b, "whisker.b"),
            "k" => (&g.k, "whisker.k"),
            "f" => (&g.f, "loads.f"),
            "beta" => (&g.beta_deg, "loads.beta_deg"),
            "q" => (&g.q, "loads.q"),
            "alpha" => (&g.alpha_deg, "loads.alpha_deg"),
            "n" => (g.n.as_ref()?, "method.n"),
            _ => return None,
        })
    }

    /// Maps a model error to the flag or scene field that caused it; solver failures are
    /// passed through (they name the method and the residual).
    pub fn culprit(&self, err: &ModelError) -> IoError {
        if let ModelError::InvalidParameter {
            name,
            value,
            reason,
        } = err
        {
            if let Some((p, field)) = self.param_named(name) {
                match &p.origin {
                    Origin::Flag { flag, raw } => {
                        return IoError::invalid_argument(*flag, raw.clone(), *reason)
                    }
                    Origin::Scene(_) => {
                        if let Some(file) = &self.file {
                            return file.error_at(field, format!("{reason}, got {}", p.value));
                        }
                    }
                    Origin::Default => {}
                }
            }
            return IoError::Solver {
                reason: format!("invalid parameter {name} = {value}: {reason}"),
                source: Some(Box::new(err.clone())),
            };
        }
        IoError::solver(err.clone())
    }

    /// Maps a contact-sweep error to its culprit (`--profile`, `--points`, a model
    /// parameter) or passes a solver failure through.
    pub fn contact_culprit(&self, err: ContactError, profile: &ProfileArg) -> IoError {
        match err {
            ContactError::Model(e) => self.culprit(&e),
            ContactError::ProfileSpec { reason, .. } => profile.error(reason),
            ContactError::NotConvex { .. } => profile.error(err.to_string()),
            ContactError::InvalidParameter {
                name: "points",
                value,
                reason,
            } => IoError::invalid_argument("--points", format!("{value}"), reason),
            ContactError::NoContact { reason } if self.physical.is_some() => {
                let l = self.units().length_mm().unwrap_or(f64::NAN);
                IoError::solver(ContactError::NoContact {
                    reason: format!(
                        "{reason} (the model's lengths: 1 = the whisker's length, {} mm; the \
                         contour `{}` as given)",
                        crate::units::round_sig(l),
                        profile.spec
                    ),
                })
            }
            other => IoError::solver(other),
        }
    }

    /// The unit system of the outputs.
    pub fn units(&self) -> UnitSystem {
        UnitSystem::new(self.physical)
    }

    /// Dimensionless fluid load q.
    pub fn q(&self) -> f64 {
        self.scene.loads.fluid.q
    }
}

/// An angle in degrees reduced exactly to `(-180, 180]` (`rem_euclid` is exact in floating
/// point, and so is the subtraction of 360 from a value in `(180, 360)`), then converted to
/// radians: `1e16` degrees is 280 = -80 degrees, not `1e16 * pi / 180` rounded.
pub fn degrees_to_radians(deg: f64) -> f64 {
    let mut r = deg.rem_euclid(360.0);
    if r > 180.0 {
        r -= 360.0;
    }
    r.to_radians()
}
